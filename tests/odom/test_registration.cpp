#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <random>

#include "../kitti_pairs.hpp"
#include "socc/kitti_io.hpp"
#include "socc/odom/odom_config.hpp"
#include "socc/odom/point_cloud_file.hpp"
#include "socc/odom/preprocessing.hpp"
#include "socc/odom/registration.hpp"
#include "socc/odom/scan_map.hpp"
#include "socc/odom/se3.hpp"
#include "socc/odom/voxel_downsampling.hpp"

namespace fs = std::filesystem;
using namespace socc::odom;

namespace {

const fs::path kData = SOCC_SHARED_DATA_DIR;

double translationError(const Eigen::Isometry3d& a, const Eigen::Isometry3d& b) {
  return (a.inverse() * b).translation().norm();
}
double rotationErrorDeg(const Eigen::Isometry3d& a, const Eigen::Isometry3d& b) {
  return Eigen::AngleAxisd((a.inverse() * b).linear()).angle() * 180.0 / M_PI;
}

// The source scan as the odometry registers it: range-filtered, downsampled to ~2500 points.
socc::LabeledCloud registrationCloud(const socc::LabeledCloud& scan, double min_range) {
  const OdomConfig cfg;
  const socc::LabeledCloud filtered = rangeFilter(scan, min_range, cfg.max_range);
  AdaptiveVoxelSize v(cfg.initial_voxel_size, cfg.min_voxel_size, cfg.max_voxel_size,
                      cfg.target_points);
  socc::LabeledCloud out;
  for (int i = 0; i < 4; ++i) {
    out = semanticVoxelDownsample(filtered, v.size(), classFactors(cfg));
    v.update(out.size());
  }
  return out;
}

// The paper's registration: every voxel paired, also those of fewer than 5 points (the maps
// here are built from one scan; the pipeline's own pairs are tested in test_grid_registration).
RegistrationParams paperParams() {
  const OdomConfig cfg;
  return {cfg.planarity_threshold,
          cfg.gamma,
          cfg.w_lower,
          cfg.max_iterations,
          cfg.convergence,
          cfg.point_to_plane,
          true,
          true,
          {},
          0.0};
}

// A box-shaped room (planes) plus scattered clutter.
socc::LabeledCloud syntheticRoom() {
  std::mt19937 rng(3);
  std::uniform_real_distribution<float> u(-10.f, 10.f);
  socc::LabeledCloud world;
  for (int i = 0; i < 20000; ++i) {
    const float a = u(rng), b = u(rng);
    switch (i % 5) {
      case 0:
        world.points.push_back({a, b, -2.f});
        break;
      case 1:
        world.points.push_back({10.f, a, b * 0.3f});
        break;
      case 2:
        world.points.push_back({a, 10.f, b * 0.3f});
        break;
      case 3:
        world.points.push_back({-10.f, a, b * 0.3f});
        break;
      default:
        world.points.push_back({a * 0.5f, b * 0.5f, std::abs(u(rng)) * 0.2f});
        break;
    }
  }
  return world;
}

}  // namespace

TEST(Registration, RecoversAKnownTransformOnSyntheticStructure) {
  const socc::LabeledCloud world = syntheticRoom();
  const LocalMap map = buildScanMap(world, 0.5);
  const Eigen::Isometry3d truth =
      expSe3((Vector6d() << 0.4, -0.3, 0.05, 0.01, -0.02, 0.08).finished());
  const socc::LabeledCloud scan = transformed(world, truth.inverse());
  const socc::LabeledCloud down = semanticVoxelDownsample(scan, 0.6, classFactors(OdomConfig{}));
  const RegistrationResult r =
      registerScan(down, map, Eigen::Isometry3d::Identity(), 1.0, paperParams());
  EXPECT_TRUE(r.converged);
  EXPECT_GT(r.planar, 0);
  EXPECT_GT(r.non_planar, 0);
  EXPECT_NEAR(r.alpha, double(r.planar) / (r.planar + r.non_planar), 1e-12);
  EXPECT_LT(translationError(r.pose, truth), 0.02);
  EXPECT_LT(rotationErrorDeg(r.pose, truth), 0.05);
}

TEST(Registration, ARunThatReachesAnEarlierRunsPathJoinsIt) {
  const socc::LabeledCloud world = syntheticRoom();
  const LocalMap map = buildScanMap(world, 0.5);
  const Eigen::Isometry3d truth =
      expSe3((Vector6d() << 0.4, -0.3, 0.05, 0.01, -0.02, 0.08).finished());
  const socc::LabeledCloud down =
      semanticVoxelDownsample(transformed(world, truth.inverse()), 0.6, classFactors(OdomConfig{}));
  RegistrationParams params = paperParams();
  params.join_distance = 0.02;
  const RegistrationResult first =
      registerScan(down, map, Eigen::Isometry3d::Identity(), 1.0, params);
  ASSERT_TRUE(first.converged);
  ASSERT_EQ(first.path.size(), static_cast<std::size_t>(first.iterations - 1));  // not the last
  EXPECT_TRUE(
      registerScan(down, map, Eigen::Isometry3d::Identity(), 1.0, paperParams()).path.empty());
  params.join_path = first.path;
  params.join_path.push_back(first.pose);
  // Started on the earlier run's path: it joins at once, where that run went on.
  const RegistrationResult on_path = registerScan(down, map, first.path.front(), 1.0, params);
  EXPECT_TRUE(on_path.joined);
  EXPECT_EQ(on_path.iterations, 1);
  const Eigen::Isometry3d other_guess = expSe3((Vector6d() << 0.8, 0, 0, 0, 0, 0).finished());
  const RegistrationResult alone = registerScan(down, map, other_guess, 1.0, paperParams());
  const RegistrationResult joined = registerScan(down, map, other_guess, 1.0, params);
  EXPECT_TRUE(joined.joined);
  EXPECT_FALSE(alone.joined);
  EXPECT_LT(joined.iterations, alone.iterations);
  EXPECT_LT(logSe3(first.pose.inverse() * alone.pose).norm(), 0.02);  // the same basin
}

TEST(Registration, ContinuousTimeRecoversTheSweepsTwist) {
  // A 0.1 s sweep of the room taken while turning at 0.6 rad/s and moving at 2 m/s, deskewed
  // with a twist that misses the turn: the registration measures the missing part.
  const socc::LabeledCloud world = syntheticRoom();
  const Eigen::Isometry3d mid = expSe3((Vector6d() << 0.4, -0.3, 0.05, 0.0, 0.0, 0.3).finished());
  const Vector6d truth = (Vector6d() << 2.0, 0.0, 0.0, 0.0, 0.0, 0.6).finished();
  const Vector6d used = (Vector6d() << 2.0, 0.0, 0.0, 0.0, 0.0, 0.0).finished();
  socc::LabeledCloud scan;
  for (const Eigen::Vector3f& w : world.points) {
    const Eigen::Vector3d local = mid.inverse() * w.cast<double>();
    const double s = 0.05 * std::atan2(local.y(), local.x()) / M_PI;  // [-0.05, 0.05] s
    const Eigen::Vector3d taken = (mid * expSe3(s * truth)).inverse() * w.cast<double>();
    scan.points.push_back((expSe3(s * used) * taken).cast<float>());  // deskewed with `used`
    scan.times.push_back(static_cast<float>(s));
  }
  const socc::LabeledCloud down = semanticVoxelDownsample(scan, 0.6, classFactors(OdomConfig{}));
  ASSERT_TRUE(down.hasTimes());
  SweepTwistPrior prior;  // centred on `used`, loose: the scan decides
  prior.sigma.setConstant(10.0);
  const LocalMap map = buildScanMap(world, 0.5);
  const Eigen::Isometry3d guess =
      mid * expSe3((Vector6d() << 0.1, -0.1, 0.0, 0.0, 0.0, 0.02).finished());
  const RegistrationResult r = registerScan(down, map, guess, 1.0, paperParams(), &prior);
  EXPECT_TRUE(r.converged);
  EXPECT_NEAR(r.twist_correction[5], 0.6, 0.03);
  EXPECT_LT((r.twist_correction - (truth - used)).head<3>().norm(), 0.5);  // m/s
  EXPECT_LT(translationError(r.pose, mid), 0.03);
  EXPECT_LT(rotationErrorDeg(r.pose, mid), 0.15);

  // A tight prior holds the twist where it was measured.
  prior.sigma.setConstant(1e-6);
  const RegistrationResult held = registerScan(down, map, guess, 1.0, paperParams(), &prior);
  EXPECT_LT(held.twist_correction.norm(), 1e-3);
}

TEST(Registration, EmptyInputsKeepTheInitialGuess) {
  const Eigen::Isometry3d guess = expSe3((Vector6d() << 1, 2, 3, 0, 0, 0.1).finished());
  socc::LabeledCloud scan;
  scan.points = {{1, 2, 3}};
  const RegistrationResult r = registerScan(scan, LocalMap(), guess, 1.0, paperParams());
  EXPECT_TRUE(r.pose.isApprox(guess));
  EXPECT_EQ(r.planar + r.non_planar, 0);
}

// KITTI seq 00 pairs: map from the first scan (its LiDAR frame = map frame), register the second
// from identity; compare with the KITTI GT relative motion (ICP agrees with it to 5 / 18 mm).
class KittiPair : public ::testing::TestWithParam<std::pair<int, int>> {};

TEST_P(KittiPair, MatchesGroundTruthWithin5cmAnd0p1deg) {
  const fs::path dir = socc::test::kittiPairsDir("00");
  if (!fs::exists(dir)) GTEST_SKIP() << "shared data folder absent: " << dir;
  const auto [a, b] = GetParam();
  const socc::Poses lidar = socc::test::kittiGt(0, {a, b});
  const Eigen::Isometry3d truth = lidar[0].inverse() * lidar[1];

  const socc::LabeledCloud target = socc::test::kittiPairScan("00", a);
  const socc::LabeledCloud source = socc::test::kittiPairScan("00", b);
  const LocalMap map = buildScanMap(rangeFilter(target, 5.0, 100.0), 0.5);
  const socc::LabeledCloud down = registrationCloud(source, 5.0);
  const RegistrationResult r =
      registerScan(down, map, Eigen::Isometry3d::Identity(), 2.0, paperParams());
  const double et = translationError(r.pose, truth), er = rotationErrorDeg(r.pose, truth);
  std::cout << a << "->" << b << ": " << down.size() << " points, " << r.iterations
            << " iterations, alpha " << r.alpha << ", error " << et * 100 << " cm " << er
            << " deg (motion " << truth.translation().norm() << " m)\n";
  EXPECT_LT(et, 0.05);
  EXPECT_LT(er, 0.1);
}

INSTANTIATE_TEST_SUITE_P(Seq00, KittiPair,
                         ::testing::Values(std::make_pair(94, 95), std::make_pair(198, 199)));

// small_gicp's outdoor pair: its T_target_source agrees with ICP to 14 mm / 0.16 deg.
TEST(Registration, SmallGicpPairMatchesGivenTransform) {
  const fs::path dir = kData / "small_gicp_pair";
  if (!fs::exists(dir)) GTEST_SKIP() << "shared data folder absent: " << dir;
  Eigen::Matrix4d m;
  std::ifstream in(dir / "T_target_source.txt");
  for (int i = 0; i < 16; ++i) ASSERT_TRUE(in >> m(i / 4, i % 4));
  const Eigen::Isometry3d truth(m);

  const socc::LabeledCloud target = loadPointCloudFile(dir / "target.ply");
  const socc::LabeledCloud source = loadPointCloudFile(dir / "source.ply");
  ASSERT_GT(target.size(), 1000u);
  const LocalMap map = buildScanMap(rangeFilter(target, 1.0, 100.0), 0.5);
  const socc::LabeledCloud down = registrationCloud(source, 1.0);
  const RegistrationResult r =
      registerScan(down, map, Eigen::Isometry3d::Identity(), 2.0, paperParams());
  const double et = translationError(r.pose, truth), er = rotationErrorDeg(r.pose, truth);
  std::cout << "small_gicp: " << down.size() << " points, " << r.iterations << " iterations, error "
            << et * 100 << " cm " << er << " deg\n";
  EXPECT_LT(et, 0.05);
  EXPECT_LT(er, 0.3);
}

TEST(PointCloudFile, MissingAndWrongFilesGiveClearErrors) {
  EXPECT_THROW(loadPointCloudFile("/nonexistent/scan.pcd"), std::runtime_error);
  const fs::path p =
      fs::temp_directory_path() / ("socc_odom_bad_" + std::to_string(::getpid()) + ".pcd");
  std::ofstream(p) << "this is not a pcd file\n";
  EXPECT_THROW(loadPointCloudFile(p), std::runtime_error);
  fs::remove(p);
  EXPECT_TRUE(isPointCloudFile("a/b.PLY"));
  EXPECT_FALSE(isPointCloudFile("a/b.bin"));
}

// A map tilted by 0.5 deg about x, a level sensor and a reference that says so: the registration
// alone follows the map, with the reference's gain it moves that share of the way back to level,
// and the heading stays the scan's.
TEST(Registration, AGravityReferenceMovesTheTiltByItsGain) {
  const socc::LabeledCloud world = syntheticRoom();
  const double tilt = 0.5 * M_PI / 180.0;
  const Eigen::Isometry3d map_tilt(Eigen::AngleAxisd(tilt, Eigen::Vector3d::UnitX()));
  const LocalMap map = buildScanMap(transformed(world, map_tilt), 0.5);
  const socc::LabeledCloud down = semanticVoxelDownsample(world, 0.6, classFactors(OdomConfig{}));
  const auto registeredTilt = [&](double gain) {
    RegistrationParams params = paperParams();
    if (gain > 0.0)
      params.tilt = TiltPrior{Eigen::Vector3d::UnitZ(), Eigen::Vector3d::UnitZ(), gain};
    const RegistrationResult r =
        registerScan(down, map, Eigen::Isometry3d::Identity(), 1.0, params);
    EXPECT_TRUE(r.converged);
    const Eigen::Vector3d up = r.pose.linear() * Eigen::Vector3d::UnitZ();
    EXPECT_NEAR(std::atan2(r.pose.linear()(1, 0), r.pose.linear()(0, 0)), 0.0, 1e-3);  // heading
    return std::acos(std::clamp(up.z(), -1.0, 1.0));
  };
  const double alone = registeredTilt(0.0);  // the map's tilt, to the grid's precision
  EXPECT_NEAR(alone, tilt, 0.15 * tilt);
  // The kernel flattens the data's cost away from its minimum: the reference gets a little more
  // than its gain there.
  EXPECT_NEAR(registeredTilt(0.5), 0.5 * alone, 0.15 * alone);
  EXPECT_NEAR(registeredTilt(0.9), 0.1 * alone, 0.05 * alone);
}
