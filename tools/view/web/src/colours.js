// Voxel colours: by class (the palette the server sends in its hello, socc/labels.hpp) or by
// occupancy probability (a blue -> yellow -> red ramp over [0.5, 1]).
export const STATE_COLOURS = [0x33cc4d, 0xffb31a, 0xe62626, 0xe62626];  // tracking .. relocalizing

export class Palette {
  constructor() { this.classes = []; }
  setClasses(classes) {
    this.classes = classes.map((c) => (c.id === 0 ? [128, 128, 128] : c.color));
  }
  classRgb(label) { return this.classes[label] || [200, 200, 200]; }
  occupancyRgb(byte) {
    const t = Math.min(1, Math.max(0, (byte / 255 - 0.5) * 2));
    if (t < 0.5) return [40 + 430 * t, 90 + 300 * t, 230 - 300 * t];
    return [255, 240 - 400 * (t - 0.5), 80 - 160 * (t - 0.5)];
  }
  rgb(mode, occupancy, label) {
    return mode === 'occupancy' ? this.occupancyRgb(occupancy) : this.classRgb(label);
  }
}
