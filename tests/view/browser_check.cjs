// Loads socc-view's page in headless Chromium (playwright-core, Debian's /usr/bin/chromium) and
// waits until the page shows map voxels and both robots, from the page's own state
// (window.soccView) and from the pixels of a screenshot, which it keeps.
// Usage: node browser_check.cjs URL SCREENSHOT.png ROBOT_ID... [--timeout S]
const { chromium } = require('playwright-core');
const fs = require('fs');
const os = require('os');
const path = require('path');

const args = process.argv.slice(2);
let timeout = 60;
const t = args.indexOf('--timeout');
if (t >= 0) { timeout = Number(args[t + 1]); args.splice(t, 2); }
const [url, screenshot, ...robotIds] = args;
if (!url || !screenshot || robotIds.length === 0) {
  console.error('usage: node browser_check.cjs URL SCREENSHOT.png ROBOT_ID... [--timeout S]');
  process.exit(2);
}
const fail = (why) => { console.log(`FAIL: ${why}`); process.exitCode = 1; };

// Counts, in the screenshot (decoded by the page itself), the non-background pixels of the 3D
// view outside the panels, and around each robot's dot in the top-down layer the pixels of its
// tracking colour.
async function screenshotPixels(page, png) {
  return page.evaluate(async (b64) => {
    const img = new Image();
    img.src = 'data:image/png;base64,' + b64;
    await img.decode();
    const c = document.createElement('canvas');
    c.width = img.width; c.height = img.height;
    const ctx = c.getContext('2d');
    ctx.drawImage(img, 0, 0);
    const data = ctx.getImageData(0, 0, c.width, c.height).data;
    const at = (x, y) => { const i = 4 * (Math.round(y) * c.width + Math.round(x)); return [data[i], data[i + 1], data[i + 2]]; };
    const near = (p, q, tol) => Math.abs(p[0] - q[0]) + Math.abs(p[1] - q[1]) + Math.abs(p[2] - q[2]) <= tol;
    const boxes = ['panel', 'topdown-box'].map((id) => document.getElementById(id).getBoundingClientRect());
    const inBox = (x, y) => boxes.some((r) => x >= r.left && x <= r.right && y >= r.top && y <= r.bottom);
    const background = [0x15, 0x18, 0x1d];
    let scenePixels = 0;
    for (let y = 0; y < c.height; y += 2)
      for (let x = 0; x < c.width; x += 2)
        if (!inBox(x, y) && !near(at(x, y), background, 24)) ++scenePixels;
    const td = document.getElementById('topdown').getBoundingClientRect();
    const robots = {};
    for (const [id, r] of Object.entries(window.soccView.robotPixels || {})) {
      let hits = 0;
      for (let dy = -4; dy <= 4; ++dy)
        for (let dx = -4; dx <= 4; ++dx)
          if (near(at(td.left + r.x + dx, td.top + r.y + dy), r.rgb, 30)) ++hits;
      robots[id] = hits;
    }
    const robots3d = {};
    for (const [id, r] of Object.entries(window.soccView.robotScreen || {})) {
      let hits = 0;
      for (let dy = -6; dy <= 6; ++dy)
        for (let dx = -6; dx <= 6; ++dx)
          if (near(at(r.x + dx, r.y + dy), r.rgb, 30)) ++hits;
      robots3d[id] = hits;
    }
    let topdownPixels = 0;
    for (let y = td.top; y < td.bottom; y += 2)
      for (let x = td.left; x < td.right; x += 2)
        if (!near(at(x, y), [0x0b, 0x0d, 0x10], 24)) ++topdownPixels;
    return { scenePixels, topdownPixels, robots, robots3d };
  }, png.toString('base64'));
}

(async () => {
  const userDataDir = fs.mkdtempSync(path.join(os.tmpdir(), 'socc-view-chromium-'));
  const browser = await chromium.launchPersistentContext(userDataDir, {
    executablePath: process.env.SOCC_CHROMIUM || '/usr/bin/chromium',
    headless: true,
    viewport: { width: 1024, height: 700 },
    args: ['--no-sandbox', '--disable-gpu', '--disable-quic', '--no-first-run',
           '--disable-background-networking', '--disable-component-update', '--disable-sync',
           '--use-angle=swiftshader', '--enable-unsafe-swiftshader'],
  });
  try {
    const page = browser.pages()[0] || await browser.newPage();
    page.on('pageerror', (e) => console.log(`page error: ${e.message}`));
    await page.goto(url);
    const deadline = Date.now() + timeout * 1000;
    let s = null;
    const ready = (st) => st && st.connected && st.voxels > 0 && st.pendingTiles === 0 &&
      robotIds.every((id) => st.robots[id] && st.robots[id].trajectory > 1 && st.robots[id].scanPoints > 0);
    while (Date.now() < deadline) {
      s = await page.evaluate(() => JSON.parse(JSON.stringify(window.soccView)));
      if (ready(s)) break;
      await page.waitForTimeout(500);
    }
    console.log(`page state: connected=${s.connected} webgl=${s.webgl} voxels=${s.voxels} blocks=${s.blocks} ` +
                `tiles=${s.tilesBuilt} frames=${s.frames} messages=${s.messages} bytes=${s.bytes} ` +
                `scale bar=${s.scaleBarMetres} m robots=${JSON.stringify(s.robots)}`);
    if (!ready(s)) fail(`the page did not show voxels and robots ${robotIds.join(', ')} within ${timeout} s`);
    await page.waitForTimeout(700);  // one more top-down redraw with the final state
    const png = await page.screenshot({ path: screenshot });
    const pixels = await screenshotPixels(page, png);
    console.log(`screenshot ${screenshot}: ${JSON.stringify(pixels)}`);
    if (s.webgl && pixels.scenePixels < 500) fail(`3D view: only ${pixels.scenePixels} map pixels`);
    if (pixels.topdownPixels < 200) fail(`top-down layer: only ${pixels.topdownPixels} map pixels`);
    for (const id of robotIds) {
      if (!(pixels.robots[id] >= 5)) fail(`robot ${id}: not drawn in the top-down layer (${pixels.robots[id]} pixels)`);
      if (s.webgl && !(pixels.robots3d[id] >= 5)) fail(`robot ${id}: not drawn in 3D (${pixels.robots3d[id]} pixels)`);
    }
    if (!s.webgl) console.log('NOTE: WebGL unavailable in this Chromium: 3D pixels not checked');
    // Colour by occupancy: every tile is rebuilt, the top-down layer redrawn.
    const builtBefore = s.tilesBuilt;
    await page.check('input[name=colour][value=occupancy]');
    await page.waitForFunction((n) => window.soccView.colourMode === 'occupancy' &&
      window.soccView.pendingTiles === 0 && window.soccView.tilesBuilt > n, builtBefore, { timeout: 20000 });
    console.log('colour by occupancy: tiles rebuilt');
  } finally {
    await browser.close();
    fs.rmSync(userDataDir, { recursive: true, force: true });
  }
  if (!process.exitCode) console.log('browser check passed');
})().catch((e) => { console.log(`FAIL: ${e.stack || e}`); process.exit(1); });
