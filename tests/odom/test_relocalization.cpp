// Relocalization (docs/relocalization.md) against an in-process map: the server's candidate
// search (GlobalLocalizer) and the client's verification, without LCM. Robot A maps part of a
// socc-sim world from its known start; a robot B dropped inside that part finds its pose in A's
// map frame, and a scan from a place A never mapped is not localized.
#include <gtest/gtest.h>

#include "closed_loop_harness.hpp"
#include "global_localizer.hpp"
#include "socc/odom/relocalization.hpp"

namespace {

using namespace socc::odom;
using harness::ClosedLoop;
using harness::simulated;

// MapAccess over the in-process grid: what map_server answers to LOCALIZE and GET_CHUNK.
class InProcessMap : public MapAccess {
 public:
  InProcessMap(const socc::map::SemanticOccupancyMap& map, const OdomConfig& cfg)
      : map_(map), cfg_(cfg) {}
  std::vector<Eigen::Isometry3d> candidates(const std::vector<Eigen::Vector3f>& scan,
                                            const std::optional<PoseHint>& hint, int max) override {
    std::optional<socc::localization::LocalizeHint> h;
    if (hint)
      h = socc::localization::LocalizeHint{hint->position, hint->yaw, hint->radius,
                                           hint->yaw_tolerance};
    std::vector<Eigen::Isometry3d> out;
    for (const auto& c : localizer_.localize(map_, scan, h, max).candidates) out.push_back(c.pose);
    return out;
  }
  LocalMap chunk(const Eigen::Vector3d& center) override {
    return harness::chunkAround(map_, center, cfg_);
  }

 private:
  const socc::map::SemanticOccupancyMap& map_;
  OdomConfig cfg_;
  socc::localization::GlobalLocalizer localizer_;
};

double degrees(const Eigen::Isometry3d& d) {
  return Eigen::AngleAxisd(d.linear()).angle() * 180.0 / M_PI;
}

struct MappedWorld {
  socc::sim::Scene scene;
  socc::sim::LidarModel lidar = socc::sim::lidarPreset("vlp32");
  ClosedLoop loop;

  // Robot A maps frames [0, frames) of the scene from its exact start pose.
  MappedWorld(const socc::sim::SceneOptions& options, int frames)
      : scene(socc::sim::buildScene(options)), loop(scene.trajectory.poseAt(0.0)) {
    for (int k = 0; k < frames; ++k) {
      socc::LabeledCloud scan = simulated(scene, lidar, k, false);
      scan.times.clear();  // taken at one instant: nothing to deskew
      loop.step(scan, k);
    }
  }
  // A's estimated pose at time t (its map frame), interpolated between its frames.
  Eigen::Isometry3d mappedPoseAt(double t) const {
    const auto k = static_cast<std::size_t>(t / 0.1);
    const Eigen::Isometry3d& a = loop.poses.at(k);
    const Vector6d step = logSe3(a.inverse() * loop.poses.at(k + 1));
    return a * expSe3(step * (t / 0.1 - static_cast<double>(k)));
  }
  PreparedScan scanAt(double t, const socc::sim::Scene& from) const {
    Odometry odom(loop.cfg, Eigen::Isometry3d::Identity());
    const socc::sim::SimulatedScan s = socc::sim::simulateScan(from, lidar, t, 1000, {false, 11});
    socc::LabeledCloud c;
    c.points = s.points;
    return odom.prepare(c, 1000, static_cast<std::int64_t>(t * 1e6));
  }
};

class RelocalizeInMappedPart : public ::testing::TestWithParam<socc::sim::SceneType> {};

TEST_P(RelocalizeInMappedPart, LandsInTheMapFrameWithin10cmAnd1deg) {
  socc::sim::SceneOptions options;
  options.type = GetParam();
  options.frames = 60;
  MappedWorld world(options, 40);
  InProcessMap access(world.loop.map, world.loop.cfg);
  // Between A's frames, on its path: a pose A's scans never had exactly.
  for (const double t : {0.75, 2.05, 3.35}) {
    const Relocalization r = relocalize(world.loop.cfg, world.scanAt(t, world.scene), access, {});
    ASSERT_TRUE(r.pose) << "t = " << t << ": " << r.problem;
    const Eigen::Isometry3d d = world.mappedPoseAt(t).inverse() * *r.pose;
    std::printf("t %.2f: %d candidates, fitness %.2f (runner-up %.2f), error %.3f m %.3f deg\n", t,
                r.candidates, r.fitness, r.runner_up, d.translation().norm(), degrees(d));
    EXPECT_LT(d.translation().norm(), 0.1);
    EXPECT_LT(degrees(d), 1.0);
  }
}

INSTANTIATE_TEST_SUITE_P(Scenes, RelocalizeInMappedPart,
                         ::testing::Values(socc::sim::SceneType::kStreet,
                                           socc::sim::SceneType::kIndoor));

// No false positive: a scan of a world A never mapped must not be given a pose.
TEST(Relocalize, AnUnmappedPlaceIsNotLocalized) {
  socc::sim::SceneOptions street;
  street.frames = 40;
  MappedWorld world(street, 30);
  InProcessMap access(world.loop.map, world.loop.cfg);
  for (const socc::sim::SceneType type :
       {socc::sim::SceneType::kIndoor, socc::sim::SceneType::kStreet}) {
    socc::sim::SceneOptions other;
    other.type = type;
    other.frames = 40;
    other.seed = 99;  // another street: same kind of place, other buildings
    const socc::sim::Scene elsewhere = socc::sim::buildScene(other);
    for (const double t : {0.5, 2.0}) {
      const Relocalization r = relocalize(world.loop.cfg, world.scanAt(t, elsewhere), access, {});
      std::printf("unmapped place: %d candidates, fitness %.2f, runner-up %.2f: %s\n", r.candidates,
                  r.fitness, r.runner_up, r.problem.c_str());
      EXPECT_FALSE(r.pose) << "a place that is not in the map was localized";
    }
  }
}

}  // namespace
