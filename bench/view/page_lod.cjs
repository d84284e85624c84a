// The page's level of detail on a large map, without a map server: a stand-in bridge (node,
// the page protocol of tools/view/src/page_protocol.hpp) serves the built page and a synthetic
// map of N voxels (a gently rolling 0.5 m ground surface with 8 m walls every 40 m), headless
// Chromium loads it, and the page reports how long it took to hold and draw everything and what
// a frame draws from the overview camera: points (with LOD vs every voxel) and draw calls, and
// the median frame time (software WebGL here: SwiftShader, so times are upper bounds).
// Usage: node page_lod.cjs WEB_ROOT [--voxels N] [--max-points N] [--max-frame-ms MS]
// Exits 1 when the drawn points exceed --max-points (default 1.5 M) or the median frame time
// --max-frame-ms (default: not judged).
const fs = require('fs');
const http = require('http');
const os = require('os');
const path = require('path');
const { WebSocketServer } = require('ws');
const { chromium } = require('playwright-core');

const args = process.argv.slice(2);
const opt = (name, def) => { const i = args.indexOf(name); return i >= 0 ? Number(args[i + 1]) : def; };
const webRoot = args[0];
const target = opt('--voxels', 3000000);
const maxPoints = opt('--max-points', 1500000);
const maxFrameMs = opt('--max-frame-ms', Infinity);
if (!webRoot || !fs.existsSync(path.join(webRoot, 'index.html'))) {
  console.error('usage: node page_lod.cjs WEB_ROOT [--voxels N] [--max-points N] [--max-frame-ms MS]');
  process.exit(2);
}

// The synthetic map as page-protocol block messages (blocks of 8^3 voxels of 0.5 m).
function mapMessages() {
  const side = Math.ceil(Math.sqrt(target * 0.9));  // ground columns per side (walls add ~10 %)
  const blocks = new Map();
  const add = (x, y, z, label) => {
    const k = `${x >> 3},${y >> 3},${z >> 3}`;
    if (!blocks.has(k)) blocks.set(k, { key: [x >> 3, y >> 3, z >> 3], voxels: [] });
    blocks.get(k).voxels.push([((x & 7) << 6) | ((y & 7) << 3) | (z & 7), 230, label]);
  };
  let n = 0;
  for (let x = 0; x < side && n < target; ++x)
    for (let y = 0; y < side && n < target; ++y) {
      const z = Math.round(4 * Math.sin(x / 90) * Math.cos(y / 70));
      add(x, y, z, 9); ++n;
      if (x % 80 === 0) for (let h = 1; h <= 16 && n < target; ++h) { add(x, y, z + h, 13); ++n; }
    }
  const messages = [];
  let parts = [], size = 0, count = 0;
  const flush = () => {
    const head = Buffer.alloc(8); head[0] = 1; head.writeUInt32LE(count, 4);
    messages.push(Buffer.concat([head, ...parts])); parts = []; size = 0; count = 0;
  };
  for (const b of blocks.values()) {
    const buf = Buffer.alloc(14 + 4 * b.voxels.length);
    b.key.forEach((k, i) => buf.writeInt32LE(k, 4 * i));
    buf.writeUInt16LE(b.voxels.length, 12);
    b.voxels.forEach(([l, o, c], i) => { buf.writeUInt16LE(l, 14 + 4 * i); buf[16 + 4 * i] = o; buf[17 + 4 * i] = c; });
    parts.push(buf); size += buf.length; ++count;
    if (size > 256 * 1024) flush();
  }
  if (count) flush();
  return { messages, voxels: n, blocks: blocks.size };
}

const map = mapMessages();
const classes = Array.from({ length: 20 }, (_, id) => ({ id, name: `class${id}`, color: [(id * 53) % 256, (id * 97) % 256, (id * 151) % 256] }));
const server = http.createServer((req, res) => {
  const file = path.join(webRoot, req.url === '/' ? 'index.html' : path.basename(req.url.split('?')[0]));
  if (!fs.existsSync(file)) { res.writeHead(404); res.end(); return; }
  res.writeHead(200, { 'Content-Type': file.endsWith('.js') ? 'text/javascript' : file.endsWith('.css') ? 'text/css' : 'text/html' });
  fs.createReadStream(file).pipe(res);
});
const wss = new WebSocketServer({ server, path: '/ws' });
wss.on('connection', (ws) => {
  ws.send(JSON.stringify({ type: 'hello', voxel_size: 0.5, block_dim: 8, classes, tracking_states: ['TRACKING'] }));
  for (const m of map.messages) ws.send(m);
});

server.listen(0, '127.0.0.1', async () => {
  const url = `http://127.0.0.1:${server.address().port}/`;
  const userDataDir = fs.mkdtempSync(path.join(os.tmpdir(), 'socc-view-lod-'));
  const browser = await chromium.launchPersistentContext(userDataDir, {
    executablePath: process.env.SOCC_CHROMIUM || '/usr/bin/chromium', headless: true,
    viewport: { width: 1280, height: 800 },
    args: ['--no-sandbox', '--disable-gpu', '--disable-quic', '--no-first-run', '--disable-background-networking',
           '--disable-component-update', '--disable-sync', '--use-angle=swiftshader', '--enable-unsafe-swiftshader'],
  });
  let ok = true;
  try {
    const page = browser.pages()[0] || await browser.newPage();
    const start = Date.now();
    await page.goto(url);
    await page.waitForFunction((n) => window.soccView.voxels >= n && window.soccView.pendingTiles === 0,
                               map.voxels, { timeout: 600000, polling: 500 });
    const loadS = (Date.now() - start) / 1000;
    await page.waitForTimeout(1000);
    const r = await page.evaluate(async () => {
      const { renderer, scene, camera } = window.soccView.three;
      const times = [];
      for (let i = 0; i < 15; ++i) {
        const t0 = performance.now();
        renderer.render(scene, camera);
        renderer.getContext().finish();
        times.push(performance.now() - t0);
      }
      times.sort((a, b) => a - b);
      return { points: renderer.info.render.points, calls: renderer.info.render.calls, frameMs: times[7] };
    });
    console.log('| voxels | blocks | load and build s | points drawn (LOD) | of all voxels | draw calls | frame ms (median, SwiftShader) |');
    console.log('|---|---|---|---|---|---|---|');
    console.log(`| ${map.voxels} | ${map.blocks} | ${loadS.toFixed(1)} | ${r.points} | ${(100 * r.points / map.voxels).toFixed(0)} % | ${r.calls} | ${r.frameMs.toFixed(1)} |`);
    if (r.points > maxPoints) { console.log(`MISSED: ${r.points} points drawn > ${maxPoints}`); ok = false; }
    if (r.frameMs > maxFrameMs) { console.log(`MISSED: frame ${r.frameMs.toFixed(0)} ms > ${maxFrameMs}`); ok = false; }
  } finally {
    await browser.close();
    fs.rmSync(userDataDir, { recursive: true, force: true });
    server.close();
  }
  process.exit(ok ? 0 : 1);
});
