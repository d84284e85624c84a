#include "socc/sim/scene.hpp"

#include <stdexcept>

#include "scene_builders.hpp"

namespace socc::sim {

namespace {

struct SceneDefaults {
  double sensor_height;  // [m] above the ground
  double speed;          // [m/s]
  double radius;         // [m] of circle / figure-eight lobes
  double zigzag_period;  // [m]
  double margin;         // [m] of world before and after an open route
  const char* route;
};

SceneDefaults defaultsFor(SceneType type) {
  switch (type) {
    case SceneType::kStreet:
      return {1.73, 9.0, 50.0, 60.0, 80.0, "straight"};  // KITTI-like car
    case SceneType::kCorridor:
      return {1.2, 1.5, 15.0, 16.0, 40.0, "straight"};
    case SceneType::kZigzag:
      return {1.2, 1.5, 15.0, 16.0, 40.0, "zigzag"};
    case SceneType::kOffice:
      return {1.2, 1.5, 15.0, 16.0, 40.0, "straight"};
    case SceneType::kIndoor:
      return {1.2, 0.8, 3.0, 6.0, 2.0, "circle"};
  }
  throw std::invalid_argument("unknown scene");
}

std::shared_ptr<const Path> makeRoute(const std::string& route, const SceneDefaults& d,
                                      double travel) {
  const double open_length = travel + 2 * d.margin;
  if (route == "straight")
    return std::make_shared<Path>(straightPath(open_length, d.sensor_height));
  if (route == "circle") return std::make_shared<Path>(circlePath(d.radius, d.sensor_height));
  if (route == "figure8") return std::make_shared<Path>(figureEightPath(d.radius, d.sensor_height));
  if (route == "zigzag")
    return std::make_shared<Path>(zigzagPath(open_length, d.zigzag_period, d.sensor_height));
  throw std::invalid_argument("unknown trajectory '" + route +
                              "' (straight, circle, figure8, zigzag)");
}

}  // namespace

SceneType parseSceneType(const std::string& name) {
  if (name == "street") return SceneType::kStreet;
  if (name == "corridor") return SceneType::kCorridor;
  if (name == "zigzag") return SceneType::kZigzag;
  if (name == "office") return SceneType::kOffice;
  if (name == "indoor") return SceneType::kIndoor;
  throw std::invalid_argument("unknown scene '" + name +
                              "' (street, corridor, zigzag, office, indoor)");
}

Scene buildScene(const SceneOptions& o) {
  if (o.frames == 0) throw std::invalid_argument("frames must be > 0");
  if (!(o.frame_period > 0.0)) throw std::invalid_argument("frame period must be > 0");
  const SceneDefaults d = defaultsFor(o.type);
  const double speed = o.speed.value_or(d.speed);
  if (!(speed >= 0.0)) throw std::invalid_argument("speed must be >= 0");
  const double duration = o.frame_period * static_cast<double>(o.frames);

  std::shared_ptr<const Path> route;
  std::optional<Trajectory> trajectory;
  if (o.poses) {
    if (o.poses->size() < 2) throw std::invalid_argument("need at least 2 poses to follow");
    route = std::make_shared<Path>(posePath(*o.poses, d.margin));
    trajectory.emplace(*o.poses, o.frame_period);
  } else {
    const std::string name = o.route == "auto" ? d.route : o.route;
    route = makeRoute(name, d, speed * duration);
    // Open routes start `margin` metres in, so the world also extends behind the sensor.
    const double s0 = route->closed() ? 0.0 : d.margin;
    trajectory.emplace(followPath(*route, speed, s0, duration + o.frame_period));
  }

  const MotionErrors& m = o.body_motion;
  if (m.pitch_per_acceleration_deg > 0 || m.roll_per_lateral_deg > 0 || m.bump_pitch_deg > 0 ||
      m.bump_roll_deg > 0 || m.bump_heave > 0 || m.vibration_deg > 0)
    trajectory->setBodyMotion(BodyMotion(m, o.seed));

  Random rng(o.seed);
  switch (o.type) {
    case SceneType::kStreet:
      return {buildStreetWorld(route, d.sensor_height, rng), *trajectory, true};
    case SceneType::kCorridor:
    case SceneType::kZigzag:
      return {buildCorridorWorld(*route, d.sensor_height), *trajectory};
    case SceneType::kOffice:
      return {buildOfficeWorld(*route, d.sensor_height, rng), *trajectory};
    case SceneType::kIndoor:
      return {buildIndoorWorld(*route, d.sensor_height, rng), *trajectory};
  }
  throw std::invalid_argument("unknown scene");
}

}  // namespace socc::sim
