// A Foxglove WebSocket client (@foxglove/ws-protocol, the library Foxglove's own apps use)
// against socc-view's /foxglove: it must get serverInfo and the advertised channels with
// Foxglove schemas, subscribe to all of them, and decode messages of each: a voxel point cloud,
// robot scans, a scene update and a frame transform for every robot, the map stats.
// Usage: node foxglove_check.cjs WS_URL ROBOT_ID... [--timeout S]
const { FoxgloveClient } = require('@foxglove/ws-protocol');
const WebSocket = require('ws');

const args = process.argv.slice(2);
let timeout = 30;
const t = args.indexOf('--timeout');
if (t >= 0) { timeout = Number(args[t + 1]); args.splice(t, 2); }
const [url, ...robotIds] = args;
if (!url || robotIds.length === 0) {
  console.error('usage: node foxglove_check.cjs WS_URL ROBOT_ID... [--timeout S]');
  process.exit(2);
}

const client = new FoxgloveClient({ ws: new WebSocket(url, [FoxgloveClient.SUPPORTED_SUBPROTOCOL]) });
const channels = new Map();  // subscription id -> channel
const seen = { serverInfo: null, voxels: 0, scans: 0, entities: new Set(), frames: new Set(), stats: null };
const decoder = new TextDecoder();
let bytes = 0;

function pointCount(cloud) {
  const data = Buffer.from(cloud.data, 'base64');
  if (cloud.point_stride <= 0 || data.length % cloud.point_stride !== 0) throw new Error('PointCloud data is not whole points');
  for (const f of ['x', 'y', 'z']) if (!cloud.fields.some((x) => x.name === f)) throw new Error(`PointCloud lacks field ${f}`);
  return data.length / cloud.point_stride;
}

function done() {
  return seen.serverInfo && seen.voxels > 0 && seen.scans > 0 && seen.stats &&
    robotIds.every((id) => seen.entities.has(`robot/${id}`) && seen.frames.has(id));
}

function finish(ok) {
  console.log(`foxglove: server=${seen.serverInfo && seen.serverInfo.name} channels=${[...channels.values()].map((c) => `${c.topic}:${c.schemaName}`).join(',')} ` +
              `voxel points=${seen.voxels} scan points=${seen.scans} entities=${[...seen.entities].join(',')} ` +
              `frames=${[...seen.frames].join(',')} bytes=${bytes}`);
  console.log(ok ? 'foxglove check passed' : `FAIL: incomplete after ${timeout} s`);
  client.close();
  process.exit(ok ? 0 : 1);
}

client.on('serverInfo', (info) => { seen.serverInfo = info; });
client.on('error', (e) => { console.log(`FAIL: ${e.message || e}`); process.exit(1); });
client.on('advertise', (advertised) => {
  for (const c of advertised) {
    if (c.encoding !== 'json' || !c.schemaName) { console.log(`FAIL: channel ${c.topic} not json/schema`); process.exit(1); }
    channels.set(client.subscribe(c.id), c);
  }
});
client.on('message', ({ subscriptionId, data }) => {
  bytes += data.byteLength;
  const c = channels.get(subscriptionId);
  if (!c) return;
  const m = JSON.parse(decoder.decode(data));
  if (c.schemaName === 'foxglove.PointCloud' && c.topic === '/map/voxels') seen.voxels = pointCount(m);
  else if (c.schemaName === 'foxglove.PointCloud') seen.scans = pointCount(m);
  else if (c.schemaName === 'foxglove.SceneUpdate') for (const e of m.entities) seen.entities.add(e.id);
  else if (c.schemaName === 'foxglove.FrameTransform') {
    if (m.parent_frame_id !== 'map' || typeof m.translation.x !== 'number') throw new Error('bad FrameTransform');
    seen.frames.add(m.child_frame_id);
  } else seen.stats = m;
  if (done()) finish(true);
});
setTimeout(() => finish(false), timeout * 1000);
