// Office corridor: the walls, floor and ceiling of the plain corridor plus what real buildings
// have along them, so that the scene also constrains motion along the corridor axis: recessed
// doors (some open into furnished rooms), wall recesses and niches, side corridors, pillars at
// irregular spacing with ceiling beams, radiators and cabinets. Nothing below the beams comes
// closer than kClearance to the route; rooms and side corridors only occupy ground that no other
// stretch of the route is nearer to (zigzag corners, loops).
#include <algorithm>
#include <cmath>
#include <utility>
#include <vector>

#include "scene_builders.hpp"
#include "socc/sim/path_proximity.hpp"
#include "socc/sim/semantic_ids.hpp"

namespace socc::sim {

namespace {

class OfficeBuilder {
 public:
  OfficeBuilder(const Path& route, double sensor_height, Random& rng)
      : route_(route),
        near_(route, 2.0),
        rng_(rng),
        floor_z_(route.points().front().position.z() - sensor_height) {}

  std::vector<Primitive> build() {
    columnGrid();
    for (const double side : {1.0, -1.0}) layoutSide(side);
    for (const Run& r : runs_) {
      wallRun(r);
      wallFurniture(r);
    }
    pillars();
    return std::move(out_);
  }

  double floorZ() const { return floor_z_; }
  static constexpr double kCeiling = 2.8;  // [m] above the floor

 private:
  static constexpr double kHalfWidth = 1.5;       // [m] as the plain corridor
  static constexpr double kWall = 0.4;            // [m] thick: door and recess reveals
  static constexpr double kClearance = 1.2;       // [m] route to anything below the beams
  static constexpr double kTile = 1.0;            // [m] wall tiles follow curved routes
  static constexpr double kDoorHeight = 2.1;      // [m]
  static constexpr double kBeamDepth = 0.35;      // [m] below the ceiling
  static constexpr double kMaxTurn = 0.15;        // [rad] features sit on straight stretches
  static constexpr double kColumnGap = 0.5;       // [m] features keep off the column grid
  static constexpr double kMinWallRun = 0.4;      // [m] of wall between features (reveals)
  static constexpr double kTop = kCeiling + 0.1;  // walls reach into the ceiling: no gaps

  // Wall frame: origin on the floor at the corridor-facing wall surface, x along the route, y
  // away from the corridor, z up. Mirrored on the right side so that x grows with arc length.
  struct Frame {
    Eigen::Vector3d origin;
    Eigen::Vector2d t;
    Eigen::Vector2d n;
    double s;
    Eigen::Vector3d at(double x, double y, double z = 0.0) const {
      const Eigen::Vector2d xy = origin.head<2>() + x * t + y * n;
      return {xy.x(), xy.y(), origin.z() + z};
    }
    double yaw() const { return std::atan2(t.y(), t.x()); }
  };
  struct Extent {  // axis-aligned in a wall frame
    double x0, x1, y0, y1, z0, z1;
  };
  struct Run {  // plain wall over arc length [s0, s1]
    double side, s0, s1;
  };
  struct Placed {  // a feature's arc length end and how far its rooms reach
    double end, reach;
  };

  Frame frameAt(double s, double side) const {
    const PathPoint p = route_.at(s);
    const Eigen::Vector2d t(std::cos(p.heading), std::sin(p.heading));
    Eigen::Vector3d o = p.offset(side * kHalfWidth);
    o.z() = floor_z_;
    return {o, t, side * Eigen::Vector2d(-t.y(), t.x()), s};
  }

  void box(const Frame& f, const Extent& e, std::uint16_t label) {
    const Eigen::Vector3d c = f.at((e.x0 + e.x1) / 2, (e.y0 + e.y1) / 2, (e.z0 + e.z1) / 2);
    out_.push_back({makeBox(c, {e.x1 - e.x0, e.y1 - e.y0, e.z1 - e.z0}, f.yaw()), label});
  }

  // Heading within kMaxTurn of the middle one over [s0, s1].
  bool straight(double s0, double s1) const {
    const double mid = route_.at((s0 + s1) / 2).heading;
    for (double s = s0; s < s1 + 0.125; s += 0.25)
      if (std::abs(std::remainder(route_.at(std::min(s, s1)).heading - mid, 2 * M_PI)) > kMaxTurn)
        return false;
    return true;
  }

  bool columnIn(double s0, double s1) const {
    return std::any_of(columns_.begin(), columns_.end(),
                       [&](double c) { return c > s0 && c < s1; });
  }

  // No other stretch of the route is nearer than the own corridor to the footprint x0..x1,
  // 0..y1: it then lies behind every corridor wall and never overlaps another room. Route
  // points within 2 m of arc length of the foot of each footprint point are its own stretch.
  bool ownGround(const Frame& f, double x0, double x1, double y1) const {
    const int nx = static_cast<int>(std::ceil((x1 - x0) / 0.5));
    const int ny = static_cast<int>(std::ceil(y1 / 0.5));
    for (int i = 0; i <= nx; ++i) {
      for (int j = 0; j <= ny; ++j) {
        const double y = y1 * j / ny;
        const double x = x0 + (x1 - x0) * i / nx;
        if (near_.nearOtherPart(f.at(x, y).head<2>(), kHalfWidth + y + 0.1, f.s + x, 2.0))
          return false;
      }
    }
    return true;
  }

  // The face `depth` in front of the wall over x0..x1 keeps kClearance from the whole route.
  bool keepsClear(const Frame& f, double x0, double x1, double depth) const {
    const int n = std::max(1, static_cast<int>(std::ceil((x1 - x0) / 0.25)));
    for (int i = 0; i <= n; ++i)
      if (near_.near(f.at(x0 + (x1 - x0) * i / n, -depth).head<2>(), kClearance - 0.01))
        return false;
    return true;
  }

  // Some corner or middle of a wall tile over -half..half is within kClearance of another
  // stretch (where the lobes of a figure eight run side by side).
  bool crowdsOtherPart(const Frame& f, double half) const {
    for (const double x : {-half, 0.0, half})
      for (const double y : {0.0, kWall})
        if (near_.nearOtherPart(f.at(x, y).head<2>(), kClearance, f.s + x, 4 * kHalfWidth))
          return true;
    return false;
  }

  // A feature over arc length [s, s + width], reaching `x_extra` beyond its ends and y1 deep.
  bool fits(const Frame& f, double s, double width, double x_extra, double y1) const {
    if (s - x_extra < 0.5 || s + width + x_extra > route_.length() - 0.5) return false;
    if (columnIn(s - kColumnGap, s + width + kColumnGap)) return false;
    return straight(s - x_extra - 0.5, s + width + x_extra + 0.5) &&
           ownGround(f, -width / 2 - x_extra, width / 2 + x_extra, y1);
  }

  // The largest of depth, 0.75 depth, ... down to min_depth (0 if none) at which a room or side
  // corridor `walls` thicker than that fits: zigzags leave little ground beside each leg.
  double deepestFit(const Frame& f, double s, double width, double x_extra, double depth,
                    double min_depth, double walls) const {
    for (;; depth = std::max(min_depth, depth * 0.75)) {
      if (fits(f, s, width, x_extra, depth + walls)) return depth;
      if (depth <= min_depth) return 0.0;
    }
  }

  // Structural grid at irregular spacing: pillars on the walls, some with a ceiling beam.
  void columnGrid() {
    for (double s = rng_.uniform(1.0, 6.0); s < route_.length(); s += rng_.uniform(3.0, 10.0)) {
      if (!straight(s - 0.5, s + 0.5)) continue;
      columns_.push_back(s);
      if (!rng_.chance(0.5)) continue;
      const Frame f = frameAt(s, 1.0);
      box(f, {-0.15, 0.15, -2 * kHalfWidth - 0.2, 0.2, kCeiling - kBeamDepth, kTop},
          raw::kOtherStructure);
    }
  }

  void pillars() {
    for (const double s : columns_) {
      for (const double side : {1.0, -1.0}) {
        const bool present = rng_.chance(0.85);
        const bool round = rng_.chance(0.3);
        const double width = rng_.uniform(0.4, 0.6);
        const double depth = round ? width / 2 : rng_.uniform(0.15, 0.3);
        const Frame f = frameAt(s, side);
        if (!present || !keepsClear(f, -width / 2, width / 2, depth)) continue;
        if (round)
          out_.push_back({Cylinder{f.at(0, 0).head<2>(), floor_z_ - 0.1, floor_z_ + kTop, depth},
                          raw::kBuilding});
        else
          box(f, {-width / 2, width / 2, -depth, kWall / 2, -0.1, kTop}, raw::kBuilding);
      }
    }
  }

  // Plain wall runs alternating with features along one side.
  void layoutSide(double side) {
    double run_start = 0.0;  // of the wall run being laid
    double free_from = 0.0;  // rooms may reach back to here
    double s = rng_.uniform(0.5, 3.0);
    while (s < route_.length()) {
      const Placed p = feature(side, s, free_from);
      if (p.end <= s) {
        s += rng_.uniform(0.5, 2.0);
        continue;
      }
      runs_.push_back({side, run_start, s});
      run_start = p.end;
      free_from = p.reach;
      s = p.reach + kMinWallRun + rng_.uniform(0.0, 4.0);
    }
    runs_.push_back({side, run_start, route_.length()});
  }

  Placed feature(double side, double s, double free_from) {
    const double u = rng_.uniform();
    if (u < 0.35) return door(side, s, free_from);
    if (u < 0.6) return recess(side, s);
    if (u < 0.8) return sideCorridor(side, s);
    return {s, s};  // more plain wall
  }

  // The wall tile over [a, b] of a run: along the chord of the wall (longer than the route on
  // the outside of a turn), lengthened by 0.15 m where it meets another tile (no gaps on the
  // outside of curves) but not at the run's ends (the reveals of the features).
  std::pair<Frame, double> tile(const Run& r, double a, double b) const {
    const double lo = a > r.s0 || a <= 0 ? 0.15 : 0.0;
    const double hi = b < r.s1 || b >= route_.length() ? 0.15 : 0.0;
    Frame f = frameAt((a + b) / 2, r.side);
    const Eigen::Vector3d p0 = frameAt(a, r.side).origin;
    const Eigen::Vector3d p1 = frameAt(b, r.side).origin;
    const Eigen::Vector2d chord = (p1 - p0).head<2>();
    // Inside a turn tighter than the corridor the wall folds back: keep the route's heading.
    if (chord.dot(f.t) < 0.7 * chord.norm() || chord.norm() < 1e-3)
      return {frameAt((a - lo + b + hi) / 2, r.side), (b - a + lo + hi) / 2};
    f.t = chord.normalized();
    f.n = r.side * Eigen::Vector2d(-f.t.y(), f.t.x());
    f.origin = (p0 + p1) / 2;
    f.origin.head<2>() += (hi - lo) / 2 * f.t;
    return {f, (chord.norm() + lo + hi) / 2};
  }

  // Tiles of at most kTile, halved where they would come closer than kClearance to the route
  // (long straight tiles cut into the inside of tight zigzag corners).
  void wallRun(const Run& r) {
    for (double a = r.s0; a < r.s1;) {
      double b = std::min(r.s1, a + kTile);
      const auto crowded = [&](double end) {
        const auto [f, half] = tile(r, a, end);
        return !keepsClear(f, -half, half, 0.0);
      };
      while (b - a > 0.2 && crowded(b)) b = (a + b) / 2;
      if (r.s1 - b < 0.1) b = r.s1;  // no sliver at the end
      const auto [f, half] = tile(r, a, b);
      a = b;
      // Skip walls that would cut through or crowd another stretch of a looping route.
      if (near_.nearOtherPart(f.at(0, kWall / 2).head<2>(), kHalfWidth, f.s, 4 * kHalfWidth) ||
          crowdsOtherPart(f, half))
        continue;
      box(f, {-half, half, 0, kWall, -0.1, kTop}, raw::kBuilding);
    }
  }

  // Now and then a radiator or a cabinet against a plain wall, clear of the pillars.
  void wallFurniture(const Run& r) {
    if (r.s1 - r.s0 < 1.6 || !rng_.chance(0.35)) return;
    const bool radiator = rng_.chance(0.6);
    const double len = rng_.uniform(0.8, std::min(1.6, r.s1 - r.s0 - 0.6));
    const double s = rng_.uniform(r.s0 + 0.3, r.s1 - 0.3 - len);
    const double depth = radiator ? 0.1 : rng_.uniform(0.25, 0.3);
    const double height = radiator ? 0.75 : rng_.uniform(0.9, 2.0);
    const Frame f = frameAt(s + len / 2, r.side);
    if (columnIn(s - 0.35, s + len + 0.35) || !straight(s, s + len) ||
        !keepsClear(f, -len / 2, len / 2, depth))
      return;
    box(f, {-len / 2, len / 2, -depth, 0, radiator ? 0.15 : 0.0, height}, raw::kOtherObject);
  }

  Placed door(double side, double s, double free_from) {
    const double w = rng_.uniform(0.85, 1.1);
    const double leaf_depth = rng_.uniform(0.08, 0.25);  // set back in the reveal
    const bool open = rng_.chance(0.5);
    const double back = rng_.uniform(0.2, 2.0);  // room beyond the door's ends
    const double fwd = rng_.uniform(0.2, 2.0);
    const double depth = rng_.uniform(2.5, 4.5);
    const Frame f = frameAt(s + w / 2, side);
    if (!fits(f, s, w, 0.0, kWall + 0.5)) return {s, s};
    box(f, {-w / 2, w / 2, 0, kWall, kDoorHeight, kTop}, raw::kBuilding);  // lintel
    const double x0 = -w / 2 - back;
    const double x1 = w / 2 + fwd;
    const double room_depth =
        open && s - back - kWall > free_from + 0.2
            ? deepestFit(f, s, w, std::max(back, fwd) + kWall, depth, 2.5, 2 * kWall)
            : 0.0;
    const double y1 = kWall + room_depth;
    if (room_depth <= 0.0) {
      box(f, {-w / 2, w / 2, leaf_depth, leaf_depth + 0.05, -0.1, kDoorHeight + 0.05},
          raw::kBuilding);
      return {s + w, s + w};
    }
    box(f, {x0 - kWall, x1 + kWall, y1, y1 + kWall, -0.1, kTop}, raw::kBuilding);
    box(f, {x0 - kWall, x0, 0, y1, -0.1, kTop}, raw::kBuilding);
    box(f, {x1, x1 + kWall, 0, y1, -0.1, kTop}, raw::kBuilding);
    openLeaf(f, w);
    furnishRoom(f, x0, x1, y1);
    return {s + w, s + w + fwd + kWall};
  }

  // The leaf swung 50-86 deg into the room about a hinge on either jamb.
  void openLeaf(const Frame& f, double w) {
    const double hinge = rng_.sign() * w / 2;
    const double angle = rng_.uniform(0.87, 1.5);
    const double dx = -std::copysign(std::cos(angle), hinge);
    const double dy = std::sin(angle);
    const Eigen::Vector3d c =
        f.at(hinge + dx * (w / 2 - 0.01), kWall + dy * (w / 2 - 0.01), kDoorHeight / 2);
    const Eigen::Vector2d d = dx * f.t + dy * f.n;
    out_.push_back({makeBox(c, {w - 0.02, 0.04, kDoorHeight - 0.02}, std::atan2(d.y(), d.x())),
                    raw::kBuilding});
  }

  // A desk against the back wall and a cabinet against a side wall, both beyond the leaf's swing.
  void furnishRoom(const Frame& f, double x0, double x1, double y1) {
    const double cabinet_y = rng_.uniform(kWall + 1.7, y1 - 0.6);
    const double cabinet_h = rng_.uniform(1.0, 2.0);
    const bool cabinet_left = rng_.chance(0.5);
    if (cabinet_left)
      box(f, {x0, x0 + 0.45, cabinet_y - 0.5, cabinet_y + 0.5, 0, cabinet_h}, raw::kOtherObject);
    else
      box(f, {x1 - 0.45, x1, cabinet_y - 0.5, cabinet_y + 0.5, 0, cabinet_h}, raw::kOtherObject);
    const double lo = x0 + (cabinet_left ? 0.5 : 0.05) + 0.7;
    const double hi = x1 - (cabinet_left ? 0.05 : 0.5) - 0.7;
    if (lo > hi) return;
    const double xc = rng_.uniform(lo, hi);
    box(f, {xc - 0.7, xc + 0.7, y1 - 0.75, y1 - 0.05, 0.72, 0.76}, raw::kOtherObject);
    box(f, {xc - 0.7, xc - 0.66, y1 - 0.75, y1 - 0.05, 0, 0.72}, raw::kOtherObject);
    box(f, {xc + 0.66, xc + 0.7, y1 - 0.75, y1 - 0.05, 0, 0.72}, raw::kOtherObject);
  }

  // A recess the full wall height, sometimes with a cabinet in it, or a niche with a sill.
  Placed recess(double side, double s) {
    const double len = rng_.uniform(0.8, 2.5);
    const double depth = rng_.uniform(0.15, 0.35);
    const Frame f = frameAt(s + len / 2, side);
    if (!fits(f, s, len, 0.0, depth + kWall)) return {s, s};
    box(f, {-len / 2 - 0.2, len / 2 + 0.2, depth, depth + kWall, -0.1, kTop}, raw::kBuilding);
    if (rng_.chance(0.4)) {
      box(f, {-len / 2, len / 2, 0, kWall, -0.1, rng_.uniform(0.6, 1.0)}, raw::kBuilding);
      box(f, {-len / 2, len / 2, 0, kWall, rng_.uniform(1.8, 2.3), kTop}, raw::kBuilding);
    } else if (rng_.chance(0.5)) {
      const double l = std::min(len - 0.1, rng_.uniform(0.8, 1.2));
      const double front = depth - std::min(depth + 0.3, rng_.uniform(0.4, 0.6));
      const double h = rng_.uniform(0.9, 2.0);
      if (keepsClear(f, -l / 2, l / 2, -front))
        box(f, {-l / 2, l / 2, front, depth, 0, h}, raw::kOtherObject);
    }
    return {s + len, s + len};
  }

  // A short dead-end side corridor, sometimes under a bulkhead, with a cabinet at its end.
  Placed sideCorridor(double side, double s) {
    const double w = rng_.uniform(1.5, 2.5);
    const Frame f = frameAt(s + w / 2, side);
    const double len = deepestFit(f, s, w, kWall, rng_.uniform(3.0, 7.0), 2.0, kWall);
    if (len <= 0.0) return {s, s};
    box(f, {-w / 2 - kWall, -w / 2, 0, len, -0.1, kTop}, raw::kBuilding);
    box(f, {w / 2, w / 2 + kWall, 0, len, -0.1, kTop}, raw::kBuilding);
    box(f, {-w / 2 - kWall, w / 2 + kWall, len, len + kWall, -0.1, kTop}, raw::kBuilding);
    if (rng_.chance(0.5))
      box(f, {-w / 2, w / 2, 0, kWall, rng_.uniform(2.2, 2.5), kTop}, raw::kBuilding);
    if (rng_.chance(0.8)) {
      const double l = rng_.uniform(0.8, std::min(1.4, w - 0.2));
      const double xc = rng_.uniform(-w / 2 + l / 2, w / 2 - l / 2);
      box(f, {xc - l / 2, xc + l / 2, len - 0.5, len, 0, rng_.uniform(1.0, 1.9)},
          raw::kOtherObject);
    }
    return {s + w, s + w + kWall};
  }

  const Path& route_;
  PathProximity near_;
  Random& rng_;
  double floor_z_;
  std::vector<double> columns_;  // arc lengths of the structural grid
  std::vector<Run> runs_;
  std::vector<Primitive> out_;
};

}  // namespace

World buildOfficeWorld(const Path& route, double sensor_height, Random& rng) {
  OfficeBuilder builder(route, sensor_height, rng);
  std::vector<Primitive> statics = builder.build();
  std::vector<Plane> planes = {
      {Eigen::Vector3d::UnitZ(), builder.floorZ(), raw::kOtherGround},
      {Eigen::Vector3d::UnitZ(), builder.floorZ() + OfficeBuilder::kCeiling, raw::kOtherStructure}};
  return World(std::move(statics), std::move(planes), nullptr, {}, sensor_height);
}

}  // namespace socc::sim
