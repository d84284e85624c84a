// The top-down 2D layer: every voxel column seen from above (colour of its highest occupied
// voxel), the robots' trajectories and positions, and a scale bar. Columns are cached per tile
// of TILE x TILE blocks in small canvases (one pixel per voxel), redrawn when a block changes.
import { STATE_COLOURS } from './colours.js';

const TILE = 4;

function niceLength(metres) {  // 1, 2 or 5 x 10^k, at most metres
  const p = Math.pow(10, Math.floor(Math.log10(metres)));
  return [5, 2, 1].map((m) => m * p).find((l) => l <= metres) || p;
}

export class TopDown {
  constructor(canvas, voxels, robots, palette) {
    this.canvas = canvas;
    this.ctx = canvas.getContext('2d');
    this.voxels = voxels;
    this.robots = robots;
    this.palette = palette;
    this.columns = new Map();  // "tx,ty" -> {canvas, dirty}
    this.drawn = 0;
    this.scaleBarMetres = 0;
    this.robotPixels = {};  // id -> {x, y, rgb} of its dot (tests look for it)
  }

  clear() { this.columns.clear(); }

  blockChanged(key) {
    const k = `${Math.floor(key[0] / TILE)},${Math.floor(key[1] / TILE)}`;
    if (!this.columns.has(k)) this.columns.set(k, { canvas: null, dirty: true, members: new Set() });
    const c = this.columns.get(k);
    c.dirty = true;
    c.members.add(`${key[0]},${key[1]},${key[2]}`);
  }

  rebuildColumn(k, c) {
    const [tx, ty] = k.split(',').map(Number);
    const d = this.voxels.blockDim;
    const size = TILE * d;
    if (!c.canvas) {
      c.canvas = document.createElement('canvas');
      c.canvas.width = size;
      c.canvas.height = size;
    }
    const image = c.canvas.getContext('2d').createImageData(size, size);
    const top = new Int32Array(size * size).fill(-2147483648);
    for (const member of c.members) {
      const b = this.voxels.blocks.get(member);
      if (!b) {
        c.members.delete(member);
        continue;
      }
      for (let v = 0; v < b.local.length; ++v) {
        const l = b.local[v];
        const x = (b.key[0] - tx * TILE) * d + Math.floor(l / (d * d));
        const y = (b.key[1] - ty * TILE) * d + (Math.floor(l / d) % d);
        const z = b.key[2] * d + (l % d);
        const px = x + (size - 1 - y) * size;  // +y up
        if (z <= top[px]) continue;
        top[px] = z;
        const rgb = this.palette.rgb(this.voxels.mode, b.occupancy[v], b.label[v]);
        image.data.set([rgb[0], rgb[1], rgb[2], 255], 4 * px);
      }
    }
    c.canvas.getContext('2d').putImageData(image, 0, 0);
    c.dirty = false;
  }

  draw() {
    const { ctx, canvas } = this;
    ctx.fillStyle = '#0b0d10';
    ctx.fillRect(0, 0, canvas.width, canvas.height);
    const b = this.voxels.bounds;
    let min = b ? [...b.min] : null, max = b ? [...b.max] : null;
    for (const r of this.robots.robots.values())
      for (const p of r.trajectory) {
        if (!min) { min = [p[0], p[1]]; max = [p[0], p[1]]; }
        min = [Math.min(min[0], p[0]), Math.min(min[1], p[1])];
        max = [Math.max(max[0], p[0]), Math.max(max[1], p[1])];
      }
    if (!min) return;
    const margin = 10;
    const span = Math.max(max[0] - min[0], max[1] - min[1], 1);
    const scale = (canvas.width - 2 * margin) / span;  // pixels per metre
    const toPx = (x, y) => [margin + (x - min[0]) * scale, canvas.height - margin - (y - min[1]) * scale];
    const s = this.voxels.voxelSize;
    const tileMetres = TILE * this.voxels.blockDim * s;
    ctx.imageSmoothingEnabled = false;
    for (const [k, c] of this.columns) {
      if (c.dirty) this.rebuildColumn(k, c);
      const [tx, ty] = k.split(',').map(Number);
      const [px, py] = toPx(tx * tileMetres, (ty + 1) * tileMetres);
      ctx.drawImage(c.canvas, px, py, tileMetres * scale, tileMetres * scale);
    }
    for (const r of this.robots.robots.values()) {
      if (!r.info) continue;
      const hex = STATE_COLOURS[r.info.tracking_state] ?? STATE_COLOURS[2];
      const colour = '#' + hex.toString(16).padStart(6, '0');
      ctx.strokeStyle = colour;
      ctx.lineWidth = 1.5;
      ctx.beginPath();
      r.trajectory.forEach((p, i) => { const [x, y] = toPx(p[0], p[1]); if (i) ctx.lineTo(x, y); else ctx.moveTo(x, y); });
      ctx.stroke();
      const [x, y] = toPx(r.info.pose.t[0], r.info.pose.t[1]);
      ctx.fillStyle = colour;
      ctx.beginPath();
      ctx.arc(x, y, 5, 0, 2 * Math.PI);
      ctx.fill();
      this.robotPixels[r.info.id] = { x, y, rgb: [hex >> 16, (hex >> 8) & 255, hex & 255] };
      ctx.fillStyle = '#fff';
      ctx.font = '11px sans-serif';
      ctx.fillText(r.info.id, x + 7, y - 5);
    }
    // Scale bar: a round length of about a quarter of the width.
    const metres = niceLength((canvas.width / 4) / scale);
    this.scaleBarMetres = metres;
    const x0 = margin, y0 = canvas.height - 8, w = metres * scale;
    ctx.fillStyle = '#fff';
    ctx.fillRect(x0, y0 - 3, w, 3);
    ctx.fillRect(x0, y0 - 8, 1.5, 8);
    ctx.fillRect(x0 + w - 1.5, y0 - 8, 1.5, 8);
    ctx.font = '11px sans-serif';
    ctx.fillText(`${metres} m`, x0 + w + 5, y0);
    ++this.drawn;
  }
}
