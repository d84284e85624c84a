// The consistency service on a simulated loop: a VLP-32 drives 1.2 laps of socc-sim's circular
// street with an odometry whose heading drifts; the service must close the loop, correct the
// keyframes, and never accept a wrong closure (also not between two robots in two worlds).
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>

#include "../temp_dir.hpp"
#include "consistency_restore.hpp"
#include "consistency_service.hpp"
#include "service/map_service.hpp"
#include "socc/pose_conversion.hpp"
#include "socc/rpc/map_client.hpp"
#include "socc/sim/lidar_model.hpp"
#include "socc/sim/scan_simulator.hpp"
#include "socc/sim/scene.hpp"
#include "socc/trajectory_revision.hpp"

namespace socc::consistency {
namespace {

constexpr double kSpeed = 18.0;  // [m/s] on a 50 m circle: 175 frames a lap
constexpr int kFrames = 210;
constexpr int kStep = 4;            // every 4th frame is sent (7.2 m apart: each one a keyframe)
constexpr double kYawDrift = 0.02;  // the odometry turns 2 % too much

struct Drive {
  sim::Scene scene;
  std::vector<Eigen::Isometry3d> truth, odometry;
  std::vector<LabeledCloud> scans;
};

Drive drive(std::uint64_t world_seed, int frames, const std::string& lidar_name = "vlp32") {
  sim::SceneOptions options;
  options.type = sim::SceneType::kStreet;
  options.route = "circle";
  options.frames = static_cast<std::size_t>(frames);
  options.seed = world_seed;
  options.speed = kSpeed;
  Drive d{sim::buildScene(options), {}, {}, {}};
  const sim::LidarModel lidar = sim::lidarPreset(lidar_name);
  for (int k = 0; k < frames; k += kStep) {
    const double t = k * 0.1;
    d.truth.push_back(d.scene.trajectory.poseAt(t));
    const sim::SimulatedScan s =
        sim::simulateScan(d.scene, lidar, t, static_cast<std::uint64_t>(k), sim::ScanOptions{});
    LabeledCloud cloud;
    cloud.points = s.points;
    d.scans.push_back(std::move(cloud));
  }
  d.odometry.push_back(d.truth[0]);
  for (std::size_t i = 1; i < d.truth.size(); ++i) {
    Eigen::Isometry3d rel = d.truth[i - 1].inverse() * d.truth[i];
    const double yaw = std::atan2(rel.linear()(1, 0), rel.linear()(0, 0));
    rel.linear() = Eigen::AngleAxisd(yaw * (1.0 + kYawDrift), Eigen::Vector3d::UnitZ()) *
                   rel.linear() * Eigen::AngleAxisd(-yaw, Eigen::Vector3d::UnitZ());
    d.odometry.push_back(d.odometry.back() * rel);
  }
  return d;
}

ConsistencyParams params() {
  ConsistencyParams p;
  p.keyframe_distance = 6.0;
  return p;
}

// The map correction tests (each a process of its own, at most 60 s under ASan): a VLP-16
// over 1.1 laps (the revisit's first keyframes close the loop) with a closure every 20 m
// instead of every keyframe (fewer verifications and rebuilds, the same correction), and the
// integrated odometry edges (this odometry drifts but never snaps: OdometryEdge.* checks the
// scan-to-scan ones).
constexpr int kCorrectionFrames = 196;
Drive correctionDrive() {
  return drive(1, kCorrectionFrames, "vlp16");
}
ConsistencyParams correctionParams() {
  ConsistencyParams p = params();
  p.closure_spacing = 20.0;
  p.scan_to_scan_edges = false;
  return p;
}

double rms(const std::vector<double>& e) {
  double s = 0.0;
  for (double v : e) s += v * v;
  return e.empty() ? 0.0 : std::sqrt(s / static_cast<double>(e.size()));
}

TEST(PlaceRecognition, ClosesASimulatedLoopWithoutWrongClosures) {
  const Drive d = drive(1, kFrames);
  ConsistencyService service(params(), map::MapConfig{});
  for (std::size_t i = 0; i < d.scans.size(); ++i)
    service.observe("car", static_cast<std::int64_t>(i) * kStep,
                    static_cast<std::int64_t>(i) * kStep * 100000, d.odometry[i], d.scans[i]);
  service.flush();
  const ConsistencyStats stats = service.stats();
  EXPECT_EQ(stats.keyframes, static_cast<int>(d.scans.size()));
  ASSERT_GE(stats.recognition.verified, 1);
  for (const Closure& c : service.closures()) {
    const Eigen::Isometry3d truth = d.truth[static_cast<std::size_t>(c.from)].inverse() *
                                    d.truth[static_cast<std::size_t>(c.to)];
    const Eigen::Isometry3d error = truth.inverse() * c.relative;
    EXPECT_LT(error.translation().norm(), 0.3) << c.from << " -> " << c.to;
    EXPECT_LT(Eigen::AngleAxisd(error.linear()).angle(), 0.02) << c.from << " -> " << c.to;
  }
  std::vector<double> before, after;
  for (const auto& k : service.keyframePoses()) {
    const std::size_t i = static_cast<std::size_t>(k.seq / kStep);
    before.push_back((k.odom_pose.translation() - d.truth[i].translation()).norm());
    after.push_back((k.optimized.translation() - d.truth[i].translation()).norm());
  }
  EXPECT_LT(rms(after), rms(before) / 5.0) << rms(before) << " -> " << rms(after);
  // corrected() moves an integration between keyframes with them.
  const Eigen::Isometry3d last =
      service.corrected("car", (kFrames / kStep - 1) * kStep, d.odometry.back());
  EXPECT_LT((last.translation() - d.truth.back().translation()).norm(), before.back() / 3.0);
  std::cerr << "keyframes " << stats.keyframes << ", closures " << stats.recognition.verified
            << " of " << stats.recognition.attempts << " attempts, ATE " << rms(before) << " -> "
            << rms(after) << " m, " << stats.keyframe_bytes / stats.keyframes << " B/keyframe, "
            << stats.recognition.seconds / stats.recognition.attempts << " s/attempt\n";
}

TEST(PlaceRecognition, TwoRobotsInTwoWorldsNeverMeet) {
  // Same route, same coordinates, different streets: nothing of one is the other.
  const Drive a = drive(1, 32), b = drive(7, 32);
  ConsistencyService service(params(), map::MapConfig{});
  for (std::size_t i = 0; i < a.scans.size(); ++i) {
    service.observe("a", static_cast<std::int64_t>(i), 0, a.truth[i], a.scans[i]);
    service.observe("b", static_cast<std::int64_t>(i), 0, b.truth[i], b.scans[i]);
  }
  service.flush();
  const RecognitionTally tally = service.stats().recognition;
  EXPECT_GT(tally.attempts, 0);
  EXPECT_EQ(tally.verified, 0);
  // Every attempt's candidates were refused, each counted by why (stats.txt).
  int refused = 0;
  for (std::size_t i = 0; i < tally.candidates_refused.size(); ++i) {
    std::cerr << odom::refusalName(static_cast<odom::Refusal>(i)) << ' '
              << tally.candidates_refused[i] << '\n';
    refused += tally.candidates_refused[i];
  }
  EXPECT_EQ(tally.candidates_refused[0], 0);  // kNone: only refusals are counted
  EXPECT_GE(refused, tally.attempts);
  std::cerr << tally.attempts << " attempts, " << tally.seconds << " s\n";
}

// Share of map's occupied voxels that truth saw as free space: surfaces where there are none
// (a second copy of a wall beside the first).
double misplaced(const map::SemanticOccupancyMap& map, const map::SemanticOccupancyMap& truth) {
  map::ChunkQuery query;
  query.radius = 500.0;
  query.fields = map::ChunkQuery::kIndex;
  const map::ChunkVoxels voxels = map.queryChunk(query);
  const double size = map.config().voxel_size;
  int wrong = 0;
  for (std::size_t i = 0; i < voxels.index[0].size(); ++i) {
    const Eigen::Vector3d centre(voxels.index[0][i] + 0.5, voxels.index[1][i] + 0.5,
                                 voxels.index[2][i] + 0.5);
    const double p = truth.occupancyAt(centre * size);
    wrong += p >= 0.0 && p < 0.5 ? 1 : 0;
  }
  return voxels.index[0].empty() ? 0.0 : static_cast<double>(wrong) / voxels.index[0].size();
}

// Occupied voxels of map within radius of centre.
std::size_t occupiedNear(const map::SemanticOccupancyMap& map, const Eigen::Vector3d& centre,
                         double radius) {
  map::ChunkQuery query;
  query.center = centre;
  query.radius = radius;
  query.fields = map::ChunkQuery::kIndex;
  return map.queryChunk(query).index[0].size();
}

TEST(MapCorrection, AWorkerFarBehindKeepsEveryKeyframeScanButBoundsTheQueuedClouds) {
  // The whole drive arrives while the worker is held, with room for one queued cloud: every
  // later keyframe's cloud is reduced on arrival to what the worker keeps of it. Each is still
  // matched (the loop closes between reduced keyframes) and in every rebuild; the closures of
  // the backlog share one rebuild.
  const Drive d = correctionDrive();
  const int n = static_cast<int>(d.scans.size());
  ConsistencyParams p = correctionParams();
  p.max_pending_scans = 1;
  p.closure_spacing = 3.0;     // several closures in the backlog
  p.rebuild_max_wait = 1.0e6;  // however slow the machine: the backlog drains first
  ConsistencyService service(p, map::MapConfig{});
  service.hold(true);
  for (std::size_t i = 0; i < d.scans.size(); ++i)
    service.observe("car", static_cast<std::int64_t>(i) * kStep, 0, d.odometry[i], d.scans[i]);
  ConsistencyStats stats = service.stats();
  EXPECT_EQ(stats.pending, n);
  EXPECT_EQ(stats.pending_clouds, 1);
  EXPECT_EQ(stats.scans_reduced_on_arrival, n - 1);
  service.hold(false);
  service.flush();
  stats = service.stats();
  EXPECT_EQ(stats.keyframes, n);
  EXPECT_GE(stats.recognition.verified, 2);
  // Every closure of the backlog made a rebuild due; it waited for the queue to drain.
  EXPECT_EQ(stats.rebuilds, 1);
  // Two more keyframes, far from the drive, while the rebuilt grid waits to be taken (its
  // tail): a cloud and, behind it, one reduced on arrival. The swap integrates both.
  const auto far = [&](double x) {
    Eigen::Isometry3d pose = d.odometry.back();
    pose.pretranslate(Eigen::Vector3d(x, 0.0, 0.0));
    return pose;
  };
  service.hold(true);
  service.observe("car", static_cast<std::int64_t>(n) * kStep, 0, far(300.0), d.scans[0]);
  service.observe("car", static_cast<std::int64_t>(n + 1) * kStep, 0, far(600.0), d.scans[1]);
  EXPECT_EQ(service.stats().pending_clouds, 1);
  EXPECT_EQ(service.stats().scans_reduced_on_arrival, n);
  const std::unique_ptr<RebuiltGrid> grid = service.takeRebuild();
  ASSERT_TRUE(grid);
  EXPECT_EQ(grid->keyframes, n);  // each with its scan (a pose only would not count)
  const Eigen::Isometry3d& correction = grid->corrections.at("car");
  EXPECT_GT(occupiedNear(grid->map, (correction * far(300.0)).translation(), 40.0), 0u);
  EXPECT_GT(occupiedNear(grid->map, (correction * far(600.0)).translation(), 40.0), 0u);
  service.hold(false);
  service.flush();
  std::cerr << n - 1 << " of " << n << " clouds reduced on arrival, " << stats.recognition.verified
            << " closures, " << stats.rebuilds << " rebuild(s), last " << grid->keyframes
            << " scans\n";
}

TEST(MapCorrection, AClosureRebuildsTheGridFromTheKeyframeScansAtTheOptimizedPoses) {
  const Drive d = correctionDrive();
  ConsistencyService service(correctionParams(), map::MapConfig{});
  // The same keyframe scans at the odometry's poses and at the truth.
  map::SemanticOccupancyMap drifted{map::MapConfig{}}, truth{map::MapConfig{}};
  for (std::size_t i = 0; i < d.scans.size(); ++i) {
    service.observe("car", static_cast<std::int64_t>(i) * kStep, 0, d.odometry[i], d.scans[i]);
    const KeyframeScan scan = compactScan(d.scans[i], correctionParams().rebuild_voxel);
    integrateScan(drifted, d.odometry[i], scan);
    integrateScan(truth, d.truth[i], scan);
  }
  service.flush();
  std::unique_ptr<RebuiltGrid> grid = service.takeRebuild();
  ASSERT_TRUE(grid);
  EXPECT_FALSE(service.takeRebuild());  // handed over once
  EXPECT_EQ(grid->keyframes, static_cast<int>(d.scans.size()));
  EXPECT_GT(grid->max_shift, correctionParams().rebuild_min_shift);
  ASSERT_EQ(grid->corrections.count("car"), 1u);
  const Eigen::Isometry3d corrected = grid->corrections.at("car") * d.odometry.back();
  EXPECT_LT((corrected.translation() - d.truth.back().translation()).norm(),
            (d.odometry.back().translation() - d.truth.back().translation()).norm() / 3.0);
  // The graph's frame is the first keyframe's, the truth's: the drifted grid has walls where
  // the truth saw free space (the loop's second copy), the rebuilt one hardly any.
  const double before = misplaced(drifted, truth), after = misplaced(grid->map, truth);
  EXPECT_LT(after, 0.6 * before);  // 43 % -> 22 % (VLP-16, 49 keyframes, 1 rebuild)
  const ConsistencyStats stats = service.stats();
  EXPECT_GE(stats.rebuilds, 1);
  std::cerr << "last rebuild: " << grid->keyframes << " scans in " << grid->seconds << " s ("
            << stats.rebuilds << " rebuilds), " << stats.scan_bytes / stats.keyframes
            << " B/keyframe scan; occupied voxels in the truth's free space " << before * 100
            << " % (drifted) -> " << after * 100 << " % (rebuilt)\n";
}

TEST(MapCorrection, LaterRebuildsOfTheMovedRegionGiveTheMapOfAWholeRebuild) {
  // Every closure rebuilds at once (rebuild_min_shift and rebuild_max_wait 0): the first of the
  // whole map, the later ones of the region whose keyframes moved (grid_rebuild.hpp,
  // updateGrid). The last grid is as good as one rebuilt whole at the final optimized poses.
  const Drive d = correctionDrive();
  ConsistencyParams p = correctionParams();
  p.rebuild_min_shift = 0.0;
  p.rebuild_max_wait = 0.0;
  p.rebuild_region_max_share = 1.0;  // region rebuilds even where they reach every keyframe
  ConsistencyService service(p, map::MapConfig{});
  map::SemanticOccupancyMap truth{map::MapConfig{}}, whole{map::MapConfig{}};
  for (std::size_t i = 0; i < d.scans.size(); ++i) {
    service.observe("car", static_cast<std::int64_t>(i) * kStep, 0, d.odometry[i], d.scans[i]);
    integrateScan(truth, d.truth[i], compactScan(d.scans[i], p.rebuild_voxel));
  }
  service.flush();
  for (const auto& k : service.keyframePoses())
    integrateScan(whole, k.optimized,
                  compactScan(d.scans[static_cast<std::size_t>(k.seq / kStep)], p.rebuild_voxel));
  std::unique_ptr<RebuiltGrid> grid = service.takeRebuild();
  ASSERT_TRUE(grid);
  const ConsistencyStats stats = service.stats();
  EXPECT_GE(stats.rebuilds, 2);
  EXPECT_GT(stats.base_bytes, 0u);
  const double region = misplaced(grid->map, truth), reference = misplaced(whole, truth);
  EXPECT_LT(region, reference + 0.01);
  std::cerr << stats.rebuilds << " rebuilds, " << stats.rebuild_scans << " scans integrated ("
            << grid->keyframes << " in the last) of " << stats.keyframes
            << " keyframes; occupied voxels in the truth's free space " << region * 100
            << " % (region rebuilds), " << reference * 100 << " % (whole, at the final poses)\n";
}

// The largest angle between a keyframe's up direction in the graph (its rotation applied to the
// world's +z, the map frame's up: the first keyframe is level) and the truth's.
double maxTilt(const std::vector<ConsistencyService::KeyframePose>& keyframes, const Drive& d,
               bool optimized) {
  double worst = 0.0;
  for (const auto& k : keyframes) {
    const Eigen::Matrix3d r = (optimized ? k.optimized : k.odom_pose).linear();
    const Eigen::Vector3d seen = r.transpose() * Eigen::Vector3d::UnitZ();
    const Eigen::Vector3d truth =
        d.truth[static_cast<std::size_t>(k.seq / kStep)].linear().transpose() *
        Eigen::Vector3d::UnitZ();
    worst = std::max(worst, std::acos(std::clamp(seen.dot(truth), -1.0, 1.0)));
  }
  return worst;
}

TEST(MapCorrection, GravityReferencesTakeTheTiltOutOfTheCorrectedKeyframes) {
  // The drive's odometry also pitches 0.0002 rad too much per keyframe (on the circle the tilt
  // turns with the heading: 0.16 deg at most); each keyframe carries its true up direction
  // (sigma 0.001 rad). The loop closes either way; with the references the optimized keyframes
  // are level with the truth, without them they stay tilted (a little more than integrated).
  Drive d = correctionDrive();
  std::vector<Eigen::Isometry3d> tilted{d.odometry.front()};
  for (std::size_t i = 1; i < d.odometry.size(); ++i) {
    Eigen::Isometry3d rel = d.odometry[i - 1].inverse() * d.odometry[i];
    rel.linear() = rel.linear() * Eigen::AngleAxisd(0.0002, Eigen::Vector3d::UnitY());
    tilted.push_back(tilted.back() * rel);
  }
  d.odometry = tilted;
  ConsistencyParams p = correctionParams();
  p.correct_grid = false;  // the graph is what is tested here
  const auto run = [&](bool references) {
    ConsistencyService service(p, map::MapConfig{});
    for (std::size_t i = 0; i < d.scans.size(); ++i) {
      const Eigen::Vector3d up = d.truth[i].linear().transpose() * Eigen::Vector3d::UnitZ();
      service.observe("car", static_cast<std::int64_t>(i) * kStep, 0, d.odometry[i], d.scans[i],
                      references ? gravityReference(up, 0.001) : std::nullopt);
    }
    service.flush();
    EXPECT_GE(service.stats().recognition.verified, 1) << references;
    EXPECT_EQ(service.stats().gravity_keyframes, references ? static_cast<int>(d.scans.size()) : 0);
    return service.keyframePoses();
  };
  const auto with = run(true), without = run(false);
  const double raw = maxTilt(with, d, false);
  const double closures_only = maxTilt(without, d, true), gravity = maxTilt(with, d, true);
  std::cerr << "tilt of the keyframes, max: integrated " << raw << " rad, optimized without "
            << "references " << closures_only << " rad, with " << gravity << " rad\n";
  EXPECT_GT(raw, 0.002);
  EXPECT_LT(gravity, 0.3 * closures_only);
  EXPECT_LT(gravity, 0.003);
}

// GET_KEYFRAMES after the correction: the keyframes' optimized poses in the map frame (the
// graph's, not moved again by the robot's correction), and the robot's output (seq 0..last-1 in
// its first frame, last-1 registered against the old grid, last in the corrected frame) revised
// by them (socc/trajectory_revision.hpp): every pose near the truth.
void expectTheRevisedTrajectoryFollowsTheGraph(const service::MapService& server, const Drive& d,
                                               std::int64_t last,
                                               const Eigen::Isometry3d& correction) {
  keyframes_request_t request{};
  request.robot_id = "car";
  request.max_keyframes = 1000;
  const keyframes_reply_t reply = server.getKeyframes(request);
  ASSERT_EQ(reply.header.status, +reply_header_t::OK) << reply.header.message;
  EXPECT_GE(reply.optimizations, 1);
  const pose_history_t& h = reply.keyframes;
  ASSERT_EQ(h.num_poses, static_cast<int>(d.scans.size()));  // every scan 7.2 m on: a keyframe
  std::vector<KeyframeEstimate> keyframes;
  std::vector<double> odometry_error, keyframe_error;
  for (std::size_t i = 0; i < h.seq.size(); ++i) {
    const Eigen::Vector3d at(h.translation[0][i], h.translation[1][i], h.translation[2][i]);
    const Eigen::Quaterniond q(h.quaternion[0][i], h.quaternion[1][i], h.quaternion[2][i],
                               h.quaternion[3][i]);
    Eigen::Isometry3d pose(q.normalized());
    pose.translation() = at;
    keyframes.push_back({h.seq[i], pose});
    const std::size_t k = static_cast<std::size_t>(h.seq[i]);
    odometry_error.push_back((d.odometry[k].translation() - d.truth[k].translation()).norm());
    keyframe_error.push_back((at - d.truth[k].translation()).norm());
  }
  EXPECT_LT(rms(keyframe_error), rms(odometry_error) / 3.0)
      << rms(odometry_error) << " -> " << rms(keyframe_error);
  std::vector<std::int64_t> seqs;
  Poses output;
  for (std::int64_t s = 0; s < last; ++s) {
    seqs.push_back(s);
    output.push_back(d.odometry[static_cast<std::size_t>(s)]);
  }
  seqs.push_back(last);
  output.push_back(d.odometry.back());  // registered against the old grid
  seqs.push_back(last + 1);
  output.push_back(correction * d.odometry.back());  // in the corrected frame
  const RevisedTrajectory revised =
      reviseTrajectory(seqs, output, keyframes, {{last + 1, correction}});
  std::vector<double> raw_error, revised_error;
  for (std::size_t i = 0; i < output.size(); ++i) {
    const Eigen::Vector3d truth = d.truth[std::min(i, d.truth.size() - 1)].translation();
    raw_error.push_back((output[i].translation() - truth).norm());
    revised_error.push_back((revised.poses[i].translation() - truth).norm());
  }
  EXPECT_LT(rms(revised_error), rms(raw_error) / 3.0)
      << rms(raw_error) << " -> " << rms(revised_error);
  // The last two frames are the same place in two frames: revised to the same pose.
  EXPECT_LT(
      (revised.poses.back().translation() - revised.poses[output.size() - 2].translation()).norm(),
      1e-6);
  std::cerr << "revised output: ATE " << rms(raw_error) << " -> " << rms(revised_error)
            << " m (keyframes " << rms(odometry_error) << " -> " << rms(keyframe_error) << ")\n";
}

TEST(MapCorrection, TheServiceSwapsTheGridInAndTellsTheRobotItsCorrectionOnce) {
  const Drive d = correctionDrive();
  service::ServerConfig config;
  config.consistency = correctionParams();
  config.consistency.enabled = true;
  service::MapService server(config);
  const auto send = [&](std::int64_t seq, const Eigen::Isometry3d& pose, const LabeledCloud& s,
                        std::int64_t epoch = 0) {
    integrate_request_t request = rpc::makeIntegrateRequest(seq, seq * 400000, pose, s);
    request.header.client_id = "car";
    request.map_epoch = epoch;  // the grid the pose is in (0: the frame last told)
    return server.integrate(request);
  };
  std::int64_t seq = 0;
  for (std::size_t i = 0; i < d.scans.size(); ++i, ++seq) {
    const integrate_reply_t r = send(seq, d.odometry[i], d.scans[i]);
    ASSERT_EQ(r.header.status, +reply_header_t::OK) << r.header.message;
  }
  server.consistency()->flush();
  const std::int64_t version = server.map().version();
  const std::int64_t epoch = server.map().epoch();
  // The robot's next scan, registered against the old grid: moved into the new one, and told.
  const Eigen::Isometry3d next = d.odometry.back();
  const integrate_reply_t told = send(seq, next, d.scans.back(), epoch);
  ASSERT_EQ(told.header.status, +reply_header_t::OK) << told.header.message;
  ASSERT_TRUE(told.corrected);
  EXPECT_EQ(server.mapCorrections(), 1);
  EXPECT_GT(told.map_version, version);
  EXPECT_NE(server.map().epoch(), epoch);           // cached chunks and deltas are stale
  EXPECT_EQ(told.map_epoch, server.map().epoch());  // the frame the robot is moved into
  const Eigen::Isometry3d correction = fromLcm(told.correction);
  EXPECT_LT(((correction * next).translation() - d.truth.back().translation()).norm(),
            (next.translation() - d.truth.back().translation()).norm() / 3.0);
  EXPECT_TRUE(fromLcm(server.robots().find("car")->last_pose).isApprox(correction * next, 1e-6));
  // A retry of that request is told again; the next request is in the corrected frame.
  const integrate_reply_t again = send(seq, next, d.scans.back(), epoch);
  EXPECT_TRUE(again.duplicate);
  EXPECT_TRUE(again.corrected);
  const integrate_reply_t after = send(seq + 1, correction * next, d.scans.back(), told.map_epoch);
  ASSERT_EQ(after.header.status, +reply_header_t::OK) << after.header.message;
  EXPECT_FALSE(after.corrected);
  EXPECT_TRUE(fromLcm(server.robots().find("car")->last_pose).isApprox(correction * next, 1e-6));
  expectTheRevisedTrajectoryFollowsTheGraph(server, d, seq, correction);
  // The frame is the one the request names: a pose of the old grid is moved (and told) even
  // after the robot was told once; one of the corrected grid never is.
  const integrate_reply_t stale = send(seq + 2, next, d.scans.back(), epoch);
  ASSERT_EQ(stale.header.status, +reply_header_t::OK) << stale.header.message;
  EXPECT_TRUE(stale.corrected);
  EXPECT_TRUE(fromLcm(server.robots().find("car")->last_pose).isApprox(correction * next, 1e-6));
}

TEST(MapCorrection, AServiceRestartedFromItsStoreRebuildsWithTheKeyframesFromBeforeTheRestart) {
  const Drive d = correctionDrive();
  const socc::testing::TempDir dir;
  const std::filesystem::path file = dir / "store";
  constexpr std::size_t kBeforeRestart = 40;  // most of the first lap: no closure yet
  {
    ConsistencyService live(correctionParams(), map::MapConfig{}, {},
                            KeyframeStore::create(file, false, true));
    for (std::size_t i = 0; i < kBeforeRestart; ++i)
      live.observe("car", static_cast<std::int64_t>(i) * kStep, 0, d.odometry[i], d.scans[i]);
    live.flush();
    live.checkpoint(static_cast<std::int64_t>(kBeforeRestart), 1);
    EXPECT_EQ(live.stats().recognition.verified, 0);
  }
  const StoreContents contents = KeyframeStore::read(file);
  std::string why;
  const StoredCheckpoint* mark = coveringMark(contents, kBeforeRestart, 1, why);
  ASSERT_NE(mark, nullptr) << why;
  ConsistencyService service(correctionParams(), map::MapConfig{}, {},
                             KeyframeStore::resume(file, contents, true), &contents,
                             mark->grid_serial);
  for (std::size_t i = kBeforeRestart; i < d.scans.size(); ++i)
    service.observe("car", static_cast<std::int64_t>(i) * kStep, 0, d.odometry[i], d.scans[i]);
  service.flush();
  EXPECT_GE(service.stats().recognition.verified, 1);
  std::unique_ptr<RebuiltGrid> grid = service.takeRebuild();
  ASSERT_TRUE(grid);
  EXPECT_EQ(grid->keyframes, static_cast<int>(d.scans.size()));  // the first lap included
  const Eigen::Isometry3d corrected = grid->corrections.at("car") * d.odometry.back();
  EXPECT_LT((corrected.translation() - d.truth.back().translation()).norm(),
            (d.odometry.back().translation() - d.truth.back().translation()).norm() / 3.0);
  // Its closures and rebuild are in the store too: a second restart has them.
  const StoreContents again = KeyframeStore::read(file);
  EXPECT_EQ(again.keyframes.size(), d.scans.size());
  EXPECT_EQ(again.closures.size(), service.closures().size());
  EXPECT_GE(again.rebuilds.size(), 1u);
  std::cerr << "store: " << again.valid_bytes << " B for " << again.keyframes.size()
            << " keyframes, " << again.closures.size() << " closures, " << again.rebuilds.size()
            << " rebuilds (" << again.valid_bytes / again.keyframes.size() << " B/keyframe)\n";
  // The swapped grid is checkpointed; a second restart from that mark has the same graph and
  // nothing to rebuild. From the mark before the swap (kill -9 before its checkpoint) the
  // restarted service makes the interrupted correction again, from all keyframes.
  service.checkpoint(60, 2);
  const auto poses = service.keyframePoses();
  const auto read_start = std::chrono::steady_clock::now();
  const StoreContents last = KeyframeStore::read(file);
  const auto read_end = std::chrono::steady_clock::now();
  const StoredCheckpoint* swapped = coveringMark(last, 60, 2, why);
  ASSERT_NE(swapped, nullptr) << why;
  EXPECT_EQ(swapped->grid_serial, grid->serial);
  {
    ConsistencyService again_service(correctionParams(), map::MapConfig{}, {}, nullptr, &last,
                                     swapped->grid_serial);
    again_service.flush();
    std::cerr << "restart: store read in "
              << std::chrono::duration<double>(read_end - read_start).count()
              << " s, service restored in "
              << std::chrono::duration<double>(std::chrono::steady_clock::now() - read_end).count()
              << " s\n";
    EXPECT_FALSE(again_service.takeRebuild());
    const auto restored = again_service.keyframePoses();
    ASSERT_EQ(restored.size(), poses.size());
    double worst = 0.0;
    for (std::size_t i = 0; i < poses.size(); ++i)
      worst = std::max(
          worst, (restored[i].optimized.translation() - poses[i].optimized.translation()).norm());
    EXPECT_LT(worst, 0.01) << "optimized poses after the restart";
    EXPECT_EQ(again_service.closures().size(), service.closures().size());
  }
  ConsistencyService interrupted(correctionParams(), map::MapConfig{}, {}, nullptr, &last, 0);
  interrupted.flush();
  const std::unique_ptr<RebuiltGrid> resumed = interrupted.takeRebuild();
  ASSERT_TRUE(resumed);
  EXPECT_EQ(resumed->keyframes, static_cast<int>(d.scans.size()));
}

}  // namespace
}  // namespace socc::consistency
