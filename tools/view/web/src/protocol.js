// Decoding of socc-view's binary messages (tools/view/src/page_protocol.hpp, little-endian).
export const KIND_BLOCKS = 1;
export const KIND_SCAN = 2;

// Calls onBlock(key [x,y,z], local Uint16Array, occupancy Uint8Array, label Uint8Array).
export function decodeBlocks(buffer, onBlock) {
  const view = new DataView(buffer);
  const n = view.getUint32(4, true);
  let at = 8;
  for (let b = 0; b < n; ++b) {
    const key = [view.getInt32(at, true), view.getInt32(at + 4, true), view.getInt32(at + 8, true)];
    const count = view.getUint16(at + 12, true);
    at += 14;
    const local = new Uint16Array(count);
    const occupancy = new Uint8Array(count);
    const label = new Uint8Array(count);
    for (let v = 0; v < count; ++v, at += 4) {
      local[v] = view.getUint16(at, true);
      occupancy[v] = view.getUint8(at + 2);
      label[v] = view.getUint8(at + 3);
    }
    onBlock(key, local, occupancy, label);
  }
}

const SCAN_STEP = 0.02;  // [m] per unit of a scan point's int16 offsets

export function decodeScan(buffer) {
  const view = new DataView(buffer);
  const idLength = view.getUint8(1);
  const id = new TextDecoder().decode(new Uint8Array(buffer, 2, idLength));
  let at = 2 + idLength;
  const n = view.getUint32(at, true);
  const origin = [0, 1, 2].map((a) => view.getFloat32(at + 4 + 4 * a, true));
  at += 16;
  const points = new Float32Array(3 * n);
  for (let i = 0; i < 3 * n; ++i, at += 2) points[i] = origin[i % 3] + SCAN_STEP * view.getInt16(at, true);
  return { id, points };
}
