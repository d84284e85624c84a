// socc-view's page: connects to the bridge's WebSocket (/ws, same host, same ?token=) and
// shows the shared map (voxel_layer.js), the robots (robots_layer.js), the server's stats and
// the top-down layer (topdown.js). window.soccView exposes the page's state (tests read it).
import * as THREE from 'three';
import { OrbitControls } from 'three/examples/jsm/controls/OrbitControls.js';
import { Palette } from './colours.js';
import { KIND_BLOCKS, KIND_SCAN, decodeBlocks, decodeScan } from './protocol.js';
import { RobotsLayer } from './robots_layer.js';
import { TopDown } from './topdown.js';
import { VoxelLayer } from './voxel_layer.js';

const state = { connected: false, hello: null, stats: null, messages: 0, bytes: 0, frames: 0,
                webgl: false, colourMode: 'class', voxels: 0, blocks: 0, robots: {}, tilesBuilt: 0, scaleBarMetres: 0 };
window.soccView = state;

const palette = new Palette();
const scene = new THREE.Scene();
scene.background = new THREE.Color(0x15181d);
const camera = new THREE.PerspectiveCamera(60, window.innerWidth / window.innerHeight, 0.5, 5000);
camera.up.set(0, 0, 1);  // the map's z is up
camera.position.set(-40, -40, 60);
let renderer = null;
try {
  renderer = new THREE.WebGLRenderer({ antialias: false, preserveDrawingBuffer: true });
  renderer.setPixelRatio(Math.min(window.devicePixelRatio, 2));
  renderer.setSize(window.innerWidth, window.innerHeight);
  document.getElementById('scene').appendChild(renderer.domElement);
  state.webgl = true;
} catch (e) {
  document.getElementById('scene').textContent = 'WebGL unavailable: ' + e.message;
}
const controls = renderer ? new OrbitControls(camera, renderer.domElement) : null;
// For the console and tests (not part of the page's state): the scene's objects.
Object.defineProperty(state, 'three', { value: { scene, camera, controls, renderer }, enumerable: false });
scene.add(new THREE.AxesHelper(5));

const voxels = new VoxelLayer(scene, palette);
const robots = new RobotsLayer(scene);
const topdown = new TopDown(document.getElementById('topdown'), voxels, robots, palette);
let framed = false;  // the camera was placed on the first map data

function resetAll() {
  voxels.clear();
  robots.clear();
  topdown.clear();
  framed = false;
}

function fmt(n) { return typeof n === 'number' ? n.toLocaleString('en-US', { maximumFractionDigits: 1 }) : n; }

function showStats(s) {
  const rows = [['server', s.server_version], ['voxels (occupied)', fmt(s.num_occupied)],
    ['voxels (observed)', fmt(s.num_voxels)], ['blocks', fmt(s.num_blocks)],
    ['memory', (s.memory_bytes / 1048576).toFixed(1) + ' MiB'], ['map version', fmt(s.map_version)],
    ['integrations', fmt(s.integrations) + ` (${s.integrations_per_s.toFixed(1)}/s)`],
    ['requests / rejected', `${fmt(s.requests)} / ${fmt(s.rejected_requests)}`],
    ['shown voxels', fmt(s.view_voxels)]];
  const table = document.getElementById('stats');
  table.replaceChildren(...rows.map(([k, v]) => {
    const tr = document.createElement('tr');
    const a = document.createElement('td'); a.textContent = k;
    const b = document.createElement('td'); b.className = 'n'; b.textContent = v;
    tr.append(a, b);
    return tr;
  }));
}

function showRobots() {
  const table = document.getElementById('robots');
  table.replaceChildren(...[...robots.robots.values()].filter((r) => r.info).map(({ info }) => {
    const tr = document.createElement('tr');
    const id = document.createElement('td'); id.textContent = info.id;
    const st = document.createElement('td');
    const badge = document.createElement('span');
    badge.className = 'badge ' + info.tracking_name;
    badge.textContent = info.tracking_name;
    badge.title = info.reason;
    st.append(badge);
    const seq = document.createElement('td'); seq.className = 'n'; seq.textContent = 'seq ' + info.seq;
    tr.append(id, st, seq);
    return tr;
  }));
  state.robots = Object.fromEntries([...robots.robots.entries()].filter(([, r]) => r.info).map(([id, r]) => [id, {
    state: r.info.tracking_name, seq: r.info.seq, pose: r.info.pose.t, trajectory: r.trajectory.length,
    scanPoints: r.scanPoints || 0 }]));
}

function showLegend(classes) {
  const legend = document.getElementById('legend');
  legend.replaceChildren(...classes.map((c) => {
    const span = document.createElement('span');
    const swatch = document.createElement('i');
    const rgb = palette.classRgb(c.id);
    swatch.style.background = `rgb(${rgb[0]},${rgb[1]},${rgb[2]})`;
    span.append(swatch, c.name);
    return span;
  }));
}

function onText(message) {
  if (message.type === 'hello') {
    resetAll();
    state.hello = message;
    palette.setClasses(message.classes);
    voxels.configure(message.voxel_size, message.block_dim);
    showLegend(message.classes);
  } else if (message.type === 'reset') {  // a new map (epoch): robots are sent again
    resetAll();
  } else if (message.type === 'stats') {
    state.stats = message;
    showStats(message);
  } else if (message.type === 'robots') {
    robots.update(message.robots);
    showRobots();
  }
}

function onBinary(buffer) {
  const kind = new Uint8Array(buffer, 0, 1)[0];
  if (kind === KIND_BLOCKS) {
    decodeBlocks(buffer, (key, local, occupancy, label) => {
      voxels.setBlock(key, local, occupancy, label);
      topdown.blockChanged(key);
    });
  } else if (kind === KIND_SCAN) {
    const scan = decodeScan(buffer);
    robots.setScan(scan.id, scan.points);
    showRobots();
  }
}

function connect() {
  const link = document.getElementById('link');
  const url = `${location.protocol === 'https:' ? 'wss' : 'ws'}://${location.host}/ws${location.search}`;
  const ws = new WebSocket(url);
  ws.binaryType = 'arraybuffer';
  ws.onopen = () => { state.connected = true; link.textContent = 'live'; link.className = 'badge TRACKING'; };
  ws.onclose = () => {
    state.connected = false;
    link.textContent = 'disconnected';
    link.className = 'badge LOST';
    setTimeout(connect, 1000);
  };
  ws.onmessage = (event) => {
    ++state.messages;
    if (typeof event.data === 'string') {
      state.bytes += event.data.length;
      onText(JSON.parse(event.data));
    } else {
      state.bytes += event.data.byteLength;
      onBinary(event.data);
    }
  };
}

for (const input of document.querySelectorAll('input[name=colour]'))
  input.addEventListener('change', () => {
    voxels.setMode(input.value);
    state.colourMode = input.value;
    topdown.clear();
    for (const b of voxels.blocks.values()) topdown.blockChanged(b.key);
  });

function frameCamera() {
  const b = voxels.bounds;
  if (!b || framed || !controls) return;
  const centre = [(b.min[0] + b.max[0]) / 2, (b.min[1] + b.max[1]) / 2];
  const span = Math.max(b.max[0] - b.min[0], b.max[1] - b.min[1], 20);
  controls.target.set(centre[0], centre[1], 0);
  camera.position.set(centre[0] - 0.6 * span, centre[1] - 0.6 * span, 0.7 * span);
  controls.update();
  framed = true;
}

let lastTopDown = 0;
function animate(now) {
  requestAnimationFrame(animate);
  voxels.update(8);
  state.voxels = voxels.voxelCount;
  state.blocks = voxels.blocks.size;
  state.tilesBuilt = voxels.tilesBuilt;
  state.pendingTiles = voxels.dirty.size;
  if (voxels.voxelCount > 0 && voxels.dirty.size === 0) frameCamera();
  if (now - lastTopDown > 500) {
    topdown.draw();
    state.scaleBarMetres = topdown.scaleBarMetres;
    state.robotPixels = topdown.robotPixels;
    lastTopDown = now;
  }
  if (renderer) {
    controls.update();
    robots.fitScreen(camera, window.innerHeight);
    state.robotScreen = robots.screenPositions(camera, window.innerWidth, window.innerHeight);
    renderer.render(scene, camera);
  }
  ++state.frames;
}

window.addEventListener('resize', () => {
  camera.aspect = window.innerWidth / window.innerHeight;
  camera.updateProjectionMatrix();
  if (renderer) renderer.setSize(window.innerWidth, window.innerHeight);
});

connect();
requestAnimationFrame(animate);
