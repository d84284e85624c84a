// Each robot in 3D: an arrow (cone) at its pose coloured by tracking state (healthy green,
// degraded amber, lost red), drawn over the map at a constant size on screen; its trajectory as
// a line and its latest scan as small white points.
import * as THREE from 'three';
import { STATE_COLOURS } from './colours.js';

class RobotObjects {
  constructor(scene) {
    this.group = new THREE.Group();
    this.marker = new THREE.Mesh(new THREE.ConeGeometry(0.5, 1.6, 16),
                                 new THREE.MeshBasicMaterial({ color: STATE_COLOURS[0], depthTest: false }));
    this.marker.rotation.z = -Math.PI / 2;  // the cone points along the robot's x axis
    this.marker.renderOrder = 10;  // over the voxels
    this.body = new THREE.Group();
    this.body.add(this.marker);
    this.trajectory = new Float32Array(3 * 1024);
    this.trajectoryLength = 0;
    this.lineGeometry = new THREE.BufferGeometry();
    this.lineGeometry.setAttribute('position', new THREE.BufferAttribute(this.trajectory, 3));
    this.line = new THREE.Line(this.lineGeometry,
                               new THREE.LineBasicMaterial({ color: 0xffffff, depthTest: false }));
    this.line.frustumCulled = false;
    this.line.renderOrder = 9;
    this.scanGeometry = new THREE.BufferGeometry();
    this.scan = new THREE.Points(this.scanGeometry,
                                 new THREE.PointsMaterial({ color: 0xffffff, size: 1.5, sizeAttenuation: false }));
    this.scan.frustumCulled = false;
    this.group.add(this.body, this.line, this.scan);
    scene.add(this.group);
  }

  appendTrajectory(from, points) {
    if (from === 0) this.trajectoryLength = 0;
    const need = 3 * (this.trajectoryLength + points.length);
    if (need > this.trajectory.length) {
      const grown = new Float32Array(Math.max(need, 2 * this.trajectory.length));
      grown.set(this.trajectory.subarray(0, 3 * this.trajectoryLength));
      this.trajectory = grown;
      this.lineGeometry.setAttribute('position', new THREE.BufferAttribute(grown, 3));
    }
    for (const p of points) this.trajectory.set(p, 3 * this.trajectoryLength++);
    this.lineGeometry.attributes.position.needsUpdate = true;
    this.lineGeometry.setDrawRange(0, this.trajectoryLength);
  }

  setPose(t, q, state) {
    this.body.position.set(t[0], t[1], t[2]);
    this.body.quaternion.set(q[1], q[2], q[3], q[0]);
    const colour = STATE_COLOURS[state] ?? STATE_COLOURS[2];
    this.marker.material.color.setHex(colour);
    this.line.material.color.setHex(colour);
  }

  setScan(points) {
    this.scanGeometry.setAttribute('position', new THREE.BufferAttribute(points, 3));
    this.scanGeometry.computeBoundingSphere();
  }

  // About `pixels` tall on screen whatever the zoom.
  fitScreen(camera, viewportHeight, pixels) {
    const distance = camera.position.distanceTo(this.body.position);
    const metresPerPixel = (2 * distance * Math.tan((camera.fov * Math.PI) / 360)) / viewportHeight;
    this.body.scale.setScalar(Math.max(0.5, (pixels * metresPerPixel) / 1.6));
  }

  dispose(scene) { scene.remove(this.group); }
}

export class RobotsLayer {
  constructor(scene) {
    this.scene = scene;
    this.robots = new Map();  // id -> {objects, info}
  }

  clear() {
    for (const r of this.robots.values()) r.objects.dispose(this.scene);
    this.robots.clear();
  }

  entry(id) {
    if (!this.robots.has(id)) this.robots.set(id, { objects: new RobotObjects(this.scene), info: null, trajectory: [] });
    return this.robots.get(id);
  }

  update(list) {
    for (const r of list) {
      const e = this.entry(r.id);
      if (r.trajectory_from === 0) e.trajectory = [];
      e.trajectory.push(...r.trajectory);
      e.objects.appendTrajectory(r.trajectory_from, r.trajectory);
      e.objects.setPose(r.pose.t, r.pose.q, r.tracking_state);
      e.info = r;
    }
  }

  // Each robot's position on screen (CSS pixels) and marker colour, for tests.
  screenPositions(camera, width, height) {
    const out = {};
    for (const [id, r] of this.robots) {
      if (!r.info) continue;
      const p = r.objects.body.position.clone().project(camera);
      const hex = r.objects.marker.material.color.getHex();
      out[id] = { x: ((p.x + 1) / 2) * width, y: ((1 - p.y) / 2) * height,
                  rgb: [hex >> 16, (hex >> 8) & 255, hex & 255] };
    }
    return out;
  }

  fitScreen(camera, viewportHeight) {
    for (const r of this.robots.values()) r.objects.fitScreen(camera, viewportHeight, 28);
  }

  setScan(id, points) {
    const e = this.entry(id);
    e.objects.setScan(points);
    e.scanPoints = points.length / 3;
  }
}
