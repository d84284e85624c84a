// The map's occupied voxels in 3D, with level of detail. Blocks (8^3 voxels) are grouped into
// tiles of TILE^3 blocks (32 m at 0.5 m voxels: few draw calls); each tile is a THREE.LOD of
// point clouds at full, half and quarter resolution (a coarse point stands for the occupied
// voxels of its 2^3 or 4^3 cell), shown from LEVEL_DISTANCE voxel sizes away, so far tiles draw
// 4-16x fewer points and a map of millions of voxels stays fluid. Changed tiles are rebuilt
// within a time budget per frame.
import * as THREE from 'three';

const TILE = 8;
const LEVELS = [1, 2, 4];            // voxel merge factor per level
const LEVEL_DISTANCE = [0, 120, 320];  // from the tile's centre, in voxel sizes (60 m, 160 m)

function keyOf(x, y, z) { return `${x},${y},${z}`; }

export class VoxelLayer {
  constructor(scene, palette) {
    this.scene = scene;
    this.palette = palette;
    this.group = new THREE.Group();
    scene.add(this.group);
    this.blocks = new Map();  // "x,y,z" -> {key, local, occupancy, label}
    this.tiles = new Map();   // "tx,ty,tz" -> {lod, blocks: Set}
    this.dirty = new Set();
    this.voxelSize = 0.5;
    this.blockDim = 8;
    this.mode = 'class';
    this.voxelCount = 0;
    this.tilesBuilt = 0;
    this.bounds = null;  // {min:[x,y], max:[x,y]} of blocks, metres
  }

  configure(voxelSize, blockDim) {
    this.voxelSize = voxelSize;
    this.blockDim = blockDim;
  }

  clear() {
    for (const tile of this.tiles.values()) this.disposeTile(tile);
    this.tiles.clear();
    this.blocks.clear();
    this.dirty.clear();
    this.voxelCount = 0;
    this.bounds = null;
  }

  setMode(mode) {
    this.mode = mode;
    for (const k of this.tiles.keys()) this.dirty.add(k);
  }

  tileKeyOf(key) {
    return keyOf(Math.floor(key[0] / TILE), Math.floor(key[1] / TILE), Math.floor(key[2] / TILE));
  }

  setBlock(key, local, occupancy, label) {
    const k = keyOf(key[0], key[1], key[2]);
    const old = this.blocks.get(k);
    if (old) this.voxelCount -= old.local.length;
    const tk = this.tileKeyOf(key);
    let tile = this.tiles.get(tk);
    if (local.length === 0) {
      this.blocks.delete(k);
      if (tile) tile.blocks.delete(k);
    } else {
      this.blocks.set(k, { key, local, occupancy, label });
      this.voxelCount += local.length;
      if (!tile) {
        tile = { lod: null, blocks: new Set() };
        this.tiles.set(tk, tile);
      }
      tile.blocks.add(k);
      this.extendBounds(key);
    }
    this.dirty.add(tk);
  }

  extendBounds(key) {
    const edge = this.voxelSize * this.blockDim;
    const lo = [key[0] * edge, key[1] * edge];
    const hi = [lo[0] + edge, lo[1] + edge];
    if (!this.bounds) this.bounds = { min: lo, max: hi };
    const b = this.bounds;
    b.min = [Math.min(b.min[0], lo[0]), Math.min(b.min[1], lo[1])];
    b.max = [Math.max(b.max[0], hi[0]), Math.max(b.max[1], hi[1])];
  }

  // Rebuilds dirty tiles for at most budgetMs; returns how many remain.
  update(budgetMs) {
    const start = performance.now();
    for (const tk of this.dirty) {
      this.dirty.delete(tk);
      this.buildTile(tk);
      if (performance.now() - start > budgetMs) break;
    }
    return this.dirty.size;
  }

  disposeTile(tile) {
    if (!tile.lod) return;
    this.group.remove(tile.lod);
    for (const level of tile.lod.levels) {
      level.object.geometry.dispose();
      level.object.material.dispose();
    }
    tile.lod = null;
  }

  buildTile(tk) {
    const tile = this.tiles.get(tk);
    if (!tile) return;
    this.disposeTile(tile);
    if (tile.blocks.size === 0) {
      this.tiles.delete(tk);
      return;
    }
    const d = this.blockDim;
    const s = this.voxelSize;
    const tileEdge = TILE * d * s;
    const lod = new THREE.LOD();
    LEVELS.forEach((factor, level) => {
      const cells = new Map();  // merged cell -> [x, y, z, r, g, b]
      for (const k of tile.blocks) {
        const b = this.blocks.get(k);
        for (let v = 0; v < b.local.length; ++v) {
          const l = b.local[v];
          const x = b.key[0] * d + Math.floor(l / (d * d));
          const y = b.key[1] * d + (Math.floor(l / d) % d);
          const z = b.key[2] * d + (l % d);
          const cx = Math.floor(x / factor), cy = Math.floor(y / factor), cz = Math.floor(z / factor);
          const ck = factor === 1 ? cells.size : keyOf(cx, cy, cz);  // full level: every voxel
          if (!cells.has(ck)) {
            const rgb = this.palette.rgb(this.mode, b.occupancy[v], b.label[v]);
            cells.set(ck, [(cx + 0.5) * factor * s, (cy + 0.5) * factor * s, (cz + 0.5) * factor * s,
                           rgb[0] / 255, rgb[1] / 255, rgb[2] / 255]);
          }
        }
      }
      const positions = new Float32Array(3 * cells.size);
      const colours = new Float32Array(3 * cells.size);
      let i = 0;
      for (const c of cells.values()) {
        positions.set(c.slice(0, 3), 3 * i);
        colours.set(c.slice(3), 3 * i);
        ++i;
      }
      const geometry = new THREE.BufferGeometry();
      geometry.setAttribute('position', new THREE.BufferAttribute(positions, 3));
      geometry.setAttribute('color', new THREE.BufferAttribute(colours, 3));
      geometry.computeBoundingSphere();
      const material = new THREE.PointsMaterial({ size: 0.9 * factor * s, sizeAttenuation: true,
                                                  vertexColors: true });
      lod.addLevel(new THREE.Points(geometry, material), LEVEL_DISTANCE[level] * s);
    });
    const [tx, ty, tz] = tk.split(',').map(Number);
    // LOD distances are measured to the object's origin: the tile's centre.
    const centre = [(tx + 0.5) * tileEdge, (ty + 0.5) * tileEdge, (tz + 0.5) * tileEdge];
    for (const level of lod.levels) level.object.geometry.translate(-centre[0], -centre[1], -centre[2]);
    lod.position.set(centre[0], centre[1], centre[2]);
    lod.autoUpdate = true;
    this.group.add(lod);
    tile.lod = lod;
    ++this.tilesBuilt;
  }
}
