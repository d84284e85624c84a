// odom_client: SOCC-ICP odometry against the shared map server (see odom_client/README.md).
#include <CLI/CLI.hpp>
#include <atomic>
#include <csignal>
#include <filesystem>
#include <iostream>
#include <sstream>

#include "socc/channels.hpp"
#include "socc/kitti_io.hpp"
#include "socc/large_message_heap.hpp"
#include "socc/lcm_url.hpp"
#include "socc/odom/odom_config.hpp"
#include "socc/odom/odom_runner.hpp"
#include "socc/pose_conversion.hpp"
#include "socc/version.hpp"

namespace fs = std::filesystem;
using namespace socc::odom;

namespace {

// The only process-wide state: async-signal-safe stop request (Ctrl-C ends after the frame).
std::atomic<bool> g_stop{false};
void onSignal(int) {
  g_stop = true;
}

Eigen::Isometry3d parsePose(const std::string& text) {
  std::istringstream in(text);
  double v[6];
  for (double& x : v)
    if (!(in >> x) || !std::isfinite(x))
      throw std::runtime_error("--initial-pose needs 6 finite numbers \"x y z roll pitch yaw\"");
  std::string rest;
  if (in >> rest) throw std::runtime_error("--initial-pose has more than 6 numbers");
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.linear() = (Eigen::AngleAxisd(v[5], Eigen::Vector3d::UnitZ()) *
                   Eigen::AngleAxisd(v[4], Eigen::Vector3d::UnitY()) *
                   Eigen::AngleAxisd(v[3], Eigen::Vector3d::UnitX()))
                      .toRotationMatrix();
  pose.translation() = Eigen::Vector3d(v[0], v[1], v[2]);
  return pose;
}

void writeOutputs(const fs::path& out_dir, const Trajectory& t) {
  if (out_dir.empty()) return;
  socc::writeKittiPoses(out_dir / "poses_kitti.txt", t.poses);
  socc::writeTumPoses(out_dir / "poses_tum.txt", t.poses, t.stamps);
}

}  // namespace

int main(int argc, char** argv) {
  socc::keepHeapForLargeMessages();
  CLI::App app{
      "odom_client: SOCC-ICP LiDAR odometry against the shared semantic occupancy map.\n"
      "Per scan: range filter, deskew, semantic adaptive downsampling, GET_CHUNK around the\n"
      "predicted pose, point-to-plane/point-to-point ICP with occupancy and semantic weights,\n"
      "then INTEGRATE of the full scan at the estimated pose. Needs a running map_server."};
  app.set_version_flag("--version", socc::versionLine("odom_client"));
  std::string input, pcd_dir, config_file, out_dir, initial_pose, key_file;
  std::string robot_id = "robot1";
  std::string lcm_url(socc::channels::kDefaultLcmUrl);
  bool live = false, no_semantics = false, resume = false, quiet = false;
  std::int64_t first = 0, last = -1;
  double idle_timeout_s = 5.0;
  auto* in_opt = app.add_option(
      "--kitti", input,
      "KITTI-layout directory (velodyne/*.bin, optional labels/, times.txt, point_times/)");
  auto* pcd_opt =
      app.add_option("--pcd-dir", pcd_dir, "directory of .pcd/.ply scans (sorted by name)");
  auto* live_opt = app.add_flag(
      "--live", live, "read socc::scan_t from SOCC/SCAN/<robot-id> over LCM (e.g. lcm-logplayer)");
  in_opt->excludes(pcd_opt, live_opt);
  pcd_opt->excludes(live_opt);
  app.add_option("--robot-id", robot_id, "robot / client id (several robots share one map)")
      ->capture_default_str();
  app.add_option("--lcm-url", lcm_url, "LCM URL: udpm://239.x.y.z:port?ttl=0 only")
      ->capture_default_str();
  app.add_option("--config", config_file,
                 "YAML parameters (odom_client/config/default.yaml documents each)");
  app.add_option("--out-dir", out_dir, "write poses_kitti.txt, poses_tum.txt and frames.csv here");
  app.add_option("--initial-pose", initial_pose,
                 "pose of the first scan in the map frame: \"x y z roll pitch yaw\" [m, rad]; "
                 "taken as exact unless refine_initial_pose is set in --config");
  app.add_option("--first-frame", first, "first frame index of a directory input")
      ->capture_default_str();
  app.add_option("--last-frame", last, "last frame index (inclusive); -1 = all")
      ->capture_default_str();
  app.add_flag("--resume", resume,
               "continue from the pose/seq the server holds for --robot-id (GET_ROBOT_POSE)");
  app.add_flag("--no-semantics", no_semantics, "ignore labels (all points unlabeled)");
  app.add_option("--idle-timeout", idle_timeout_s,
                 "--live: stop after this many seconds without scans")
      ->capture_default_str();
  app.add_option("--key-file", key_file,
                 "shared key for signed requests (if the server requires it)");
  app.add_flag("--quiet", quiet, "no progress bar");
  CLI11_PARSE(app, argc, argv);

  try {
    if (input.empty() && pcd_dir.empty() && !live)
      throw std::runtime_error("no input: give --kitti <dir>, --pcd-dir <dir> or --live");
    if (const std::string why = socc::checkLcmUrl(lcm_url); !why.empty())
      throw std::runtime_error("--lcm-url " + lcm_url + ": " + why);
    if (robot_id.empty()) throw std::runtime_error("--robot-id must not be empty");
    OdomConfig config = config_file.empty() ? OdomConfig{} : loadOdomConfig(config_file);
    if (no_semantics) config.use_semantics = false;
    if (!out_dir.empty()) fs::create_directories(out_dir);

    socc::rpc::ClientOptions client_options;
    client_options.lcm_url = lcm_url;
    client_options.client_id = robot_id;
    client_options.timeout = std::chrono::milliseconds(config.timeout_ms);
    client_options.max_attempts = config.max_attempts;
    client_options.key_file = key_file;
    socc::rpc::MapClient client(client_options);

    RunOptions options;
    options.progress = !quiet;
    options.stop = &g_stop;
    if (!initial_pose.empty()) {
      options.initial_pose = parsePose(initial_pose);
      options.initial_pose_known = true;
    }
    if (resume) {
      const auto reply = client.getRobotPose(robot_id);
      if (reply.ok()) {
        const socc::robot_state_t& state = reply.reply->state;
        options.initial_pose = socc::fromLcm(state.last_pose);
        options.initial_pose_known = false;  // the pose of the last scan, not of the next one
        options.skip_until_seq = state.last_seq;
        first = std::max<std::int64_t>(first, state.last_seq + 1);
        std::cerr << "odom_client: resuming " << robot_id << " after seq " << state.last_seq
                  << "\n";
      } else if (reply.error.status == socc::reply_header_t::NOT_FOUND) {
        std::cerr << "odom_client: the server does not know " << robot_id
                  << " yet: starting fresh\n";
      } else {
        throw std::runtime_error("GET_ROBOT_POSE failed: " + reply.error.message);
      }
    }

    if (resume && !input.empty() &&
        first >= static_cast<std::int64_t>(socc::listKittiSequence(input).scans.size())) {
      std::cout << "odom_client: every frame of " << input << " was integrated already\n";
      return 0;
    }
    std::unique_ptr<ScanSource> source;
    if (!input.empty())
      source = openKittiDirectory(input, {first, last});
    else if (!pcd_dir.empty())
      source = openPointCloudDirectory(pcd_dir, {first, last}, config.frame_period);
    else {
      source = openLcmScans(lcm_url, robot_id,
                            std::chrono::milliseconds(static_cast<int>(idle_timeout_s * 1000)));
      // Scans published before this line are not received: start lcm-logplayer after it.
      std::cerr << "odom_client: listening for scans on " << socc::channels::scan(robot_id)
                << std::endl;
    }

    std::signal(SIGINT, onSignal);
    std::signal(SIGTERM, onSignal);
    FrameLog log(out_dir.empty() ? fs::path{} : fs::path(out_dir) / "frames.csv");
    OdomRunner runner(config, client, options);
    int rc = 0;
    try {
      runner.run(*source, log);
    } catch (const std::exception& e) {
      std::cerr << "odom_client: error: " << e.what() << "\n";
      rc = 1;
    }
    writeOutputs(out_dir, runner.trajectory());
    std::cout << log.summary(runner.wallSeconds());
    if (rc == 0 && runner.trackingState() == TrackingState::kLost) {
      std::cerr << "odom_client: error: the run ended LOST: frames after the robot lost track "
                   "were not integrated (frames.csv status column)\n";
      rc = 3;
    }
    return rc;
  } catch (const std::exception& e) {
    std::cerr << "odom_client: error: " << e.what() << "\n";
    return 1;
  }
}
