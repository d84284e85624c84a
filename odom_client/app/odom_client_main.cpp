// odom_client: SOCC-ICP odometry against the shared map server (see odom_client/README.md).
#include <CLI/CLI.hpp>
#include <Eigen/Geometry>
#include <algorithm>
#include <atomic>
#include <cmath>
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
#include "socc/odom/revised_trajectory.hpp"
#include "socc/pose_conversion.hpp"
#include "socc/sensors/sensor_config.hpp"
#include "socc/version.hpp"

namespace fs = std::filesystem;
using namespace socc::odom;

namespace {

// The only process-wide state: async-signal-safe stop request (Ctrl-C ends after the frame).
std::atomic<bool> g_stop{false};
void onSignal(int) {
  g_stop = true;
}

// The command line as parsed.
struct Args {
  std::string input, pcd_dir, out_dir, initial_pose, key_file, pose_hint;
  std::string robot_id = "robot1";
  std::string lcm_url{socc::channels::kDefaultLcmUrl};
  std::string scan_lcm_url;               // --live: where scans arrive; empty = lcm_url
  std::vector<std::string> config_files;  // --config, layered in order
  bool live = false, no_semantics = false, no_gravity = false, resume = false, quiet = false,
       relocalize = false, own_frame = false, found_map = false, no_revised = false;
  double revised_wait_s = 30.0;  // --revised-wait
  double hint_radius = 0.0, hint_yaw_tolerance_deg = 180.0;
  double frame_period = 0.0;  // --frame-period; 0: the config's frame_period
  std::int64_t first = 0, last = -1;
  double idle_timeout_s = 5.0;
  double rate = 0.0;  // --rate; 0: files as fast as the odometry reads them
  // --pcap / --bag: a recording read through socc_sensors (docs/sensors.md).
  std::string pcap, bag, topic, imu_topic, sensor, calibration, sensor_address;
  std::uint16_t port = 0;
};

// Recordings of a real sensor: the inputs beside --kitti / --pcd-dir / --live.
std::vector<CLI::Option*> addRecordingOptions(CLI::App& app, Args& a) {
  auto* pcap = app.add_option("--pcap", a.pcap, "pcap capture of LiDAR packets (docs/sensors.md)")
                   ->check(CLI::ExistingFile);
  auto* bag = app.add_option("--bag", a.bag,
                             "ROS 1 .bag, ROS 2 .db3 (or its folder) or .mcap: PointCloud2 or "
                             "packet topics (docs/sensors.md)")
                  ->check(CLI::ExistingPath);
  app.add_option("--topic", a.topic, "--bag: the topic to read (default: the only LiDAR topic)")
      ->needs(bag);
  app.add_option("--imu-topic", a.imu_topic,
                 "--bag: a sensor_msgs/Imu topic whose attitude (orientation) is the gravity "
                 "reference of the scans; its mounting: imu_roll_deg / imu_pitch_deg / "
                 "imu_yaw_deg in --config, else the bag's /tf_static (odom_client/README.md "
                 "\"Gravity reference\")")
      ->needs(bag);
  std::string models;
  for (const std::string& m : socc::sensors::supportedModels())
    models += (models.empty() ? "" : ", ") + m;
  app.add_option("--sensor", a.sensor,
                 "--pcap / packet topics: the sensor model (" + models +
                     "); default: detected from the packets");
  app.add_option("--calibration", a.calibration,
                 "the sensor's calibration: VeloView .xml or ROS velodyne .yaml, Ouster metadata "
                 ".json, Hesai angle-correction .csv; default: the model's nominal angles")
      ->check(CLI::ExistingFile);
  app.add_option("--port", a.port, "--pcap: UDP destination port of the LiDAR data (0: any)")
      ->capture_default_str()
      ->needs(pcap);
  app.add_option("--sensor-address", a.sensor_address,
                 "--pcap: decode the packets of the sensor at this IPv4 address only (several "
                 "sensors on one port); default: the first sender, others are dropped and "
                 "reported")
      ->needs(pcap);
  return {pcap, bag};
}

void addOptions(CLI::App& app, Args& a) {
  auto* in_opt = app.add_option(
      "--kitti", a.input,
      "KITTI-layout directory (velodyne/*.bin, optional labels/, times.txt, point_times/)");
  auto* pcd_opt =
      app.add_option("--pcd-dir", a.pcd_dir, "directory of .pcd/.ply scans (sorted by name)");
  auto* live_opt =
      app.add_flag("--live", a.live,
                   "read socc::scan_t from SOCC/SCAN/<robot-id> over LCM (e.g. lcm-logplayer)");
  in_opt->excludes(pcd_opt, live_opt);
  pcd_opt->excludes(live_opt);
  app.add_option("--rate", a.rate,
                 "replay a directory or recording at this many times the pace of its scans' "
                 "time stamps, as the sensor delivered them (1: real time; scans the loop "
                 "takes late are counted, not dropped); default: as fast as the odometry goes")
      ->check(CLI::Range(0.001, 1000.0))
      ->excludes(live_opt);
  const std::vector<CLI::Option*> recording = addRecordingOptions(app, a);
  for (CLI::Option* r : recording) r->excludes(in_opt)->excludes(pcd_opt)->excludes(live_opt);
  recording[0]->excludes(recording[1]);
  app.add_option("--robot-id", a.robot_id, "robot / client id (several robots share one map)")
      ->capture_default_str();
  app.add_option("--lcm-url", a.lcm_url,
                 "LCM URL: udpm://239.x.y.z:port?ttl=0; ttl=1 (LAN, docs/fleet.md) only with "
                 "--key-file")
      ->capture_default_str();
  app.add_option("--scan-lcm-url", a.scan_lcm_url,
                 "--live: read scans from this URL (default: --lcm-url); scans are not signed, "
                 "so it must be ttl=0 (this machine) when --lcm-url is a LAN (ttl=1)");
  app.add_option("--config", a.config_files,
                 "YAML parameters (odom_client/config/default.yaml documents each); may be given "
                 "several times: a later file's keys override an earlier one's (e.g. "
                 "config/kitti.yaml for the sensor, then config/baseline.yaml for the method)")
      ->allow_extra_args(false);
  app.add_option(
      "--out-dir", a.out_dir,
      "write poses_kitti.txt, poses_tum.txt and frames.csv here, and at the end "
      "range_calibration.txt (each laser's range correction, when range_calibration "
      "is on) and poses_revised_kitti.txt / poses_revised_tum.txt when the server runs the "
      "consistency service: the poses revised by its pose graph (GET_KEYFRAMES, "
      "docs/consistency.md \"The revised trajectory\")");
  app.add_flag("--no-revised", a.no_revised,
               "do not ask the server for the revised trajectory at the end of the run");
  app.add_option("--revised-wait", a.revised_wait_s,
                 "seconds to wait at the end for the server's consistency service to place its "
                 "last keyframes into its graph before the revised trajectory is written (not "
                 "after Ctrl-C)")
      ->capture_default_str()
      ->check(CLI::Range(0.0, 86400.0));
  app.add_option("--initial-pose", a.initial_pose,
                 "pose of the first scan in the map frame: \"x y z roll pitch yaw\" [m, rad]; "
                 "taken as exact unless refine_initial_pose is set in --config");
  auto* reloc_opt = app.add_flag(
      "--relocalize", a.relocalize,
      "find the first scan's pose in the server's map (LOCALIZE + verification, "
      "docs/relocalization.md) unless --initial-pose gives it; a robot that gets lost searches "
      "again");
  auto* own_frame_opt =
      app.add_flag(
             "--own-frame", a.own_frame,
             "a robot with no pose in the server's map yet (e.g. switched on where nobody has "
             "mapped): maps in its own frame (identity at its first scan) and integrates "
             "nothing while it searches the shared map (every scan for relocalize_timeout, then "
             "every own_frame_search_period); once a place is verified and confirmed it is merged: "
             "its kept scans go into the shared map and it goes on there. Exits 5 when the input "
             "ends before the merge (poses_own_frame_*.txt instead of poses_*.txt; "
             "docs/relocalization.md \"Own frame\")")
          ->excludes(reloc_opt);
  app.add_flag("--found-map", a.found_map,
               "--own-frame on a server whose map is empty: this robot founds the map, its own "
               "frame (its first scan) the map frame, and goes on tracking in it; a map that is "
               "not empty (another robot founded it first) is searched as without the flag. For "
               "fleets in which no robot has a pose; a robot started with --initial-pose would "
               "not share the founder's frame (docs/relocalization.md \"Founding an empty map\")")
      ->needs(own_frame_opt);
  app.add_option("--pose-hint", a.pose_hint,
                 "--relocalize: search near \"x y z yaw\" [m, rad] (map frame) only; needs "
                 "--hint-radius")
      ->needs(reloc_opt);
  app.add_option("--hint-radius", a.hint_radius, "--pose-hint: search radius [m]")
      ->needs(reloc_opt);
  app.add_option("--hint-yaw-tolerance", a.hint_yaw_tolerance_deg,
                 "--pose-hint: accepted heading difference [deg]; 180 = any")
      ->capture_default_str()
      ->needs(reloc_opt);
  app.add_option("--frame-period", a.frame_period,
                 "seconds between scans of an input without time stamps (a KITTI directory "
                 "without times.txt, PCD/PLY files without stamps in their names); overrides "
                 "frame_period of --config")
      ->check(CLI::PositiveNumber);
  app.add_option("--first-frame", a.first, "first frame index of a directory or recording input")
      ->capture_default_str();
  app.add_option("--last-frame", a.last, "last frame index (inclusive); -1 = all")
      ->capture_default_str();
  app.add_flag("--resume", a.resume,
               "continue from the pose/seq the server holds for --robot-id (GET_ROBOT_POSE)");
  app.add_flag("--no-semantics", a.no_semantics, "ignore labels (all points unlabeled)");
  app.add_flag("--no-gravity", a.no_gravity,
               "do not send the input's gravity reference (a KITTI directory's gravity.txt) "
               "with the INTEGRATE requests");
  app.add_option("--idle-timeout", a.idle_timeout_s,
                 "--live: stop after this many seconds without scans")
      ->capture_default_str();
  app.add_option("--key-file", a.key_file,
                 "shared key for signed requests (if the server requires it)");
  app.add_flag("--quiet", a.quiet, "no progress bar");
}

// --pose-hint "x y z yaw" with --hint-radius.
PoseHint parseHint(const Args& a) {
  std::istringstream in(a.pose_hint);
  double v[4];
  for (double& x : v)
    if (!(in >> x) || !std::isfinite(x))
      throw std::runtime_error("--pose-hint needs 4 finite numbers \"x y z yaw\"");
  if (!(a.hint_radius > 0.0)) throw std::runtime_error("--pose-hint needs --hint-radius > 0");
  PoseHint hint;
  hint.position = {v[0], v[1], v[2]};
  hint.yaw = v[3];
  hint.radius = a.hint_radius;
  hint.yaw_tolerance = std::clamp(a.hint_yaw_tolerance_deg, 0.0, 180.0) * M_PI / 180.0;
  return hint;
}

void checkArgs(const Args& a) {
  if (a.input.empty() && a.pcd_dir.empty() && !a.live && a.pcap.empty() && a.bag.empty())
    throw std::runtime_error(
        "no input: give --kitti <dir>, --pcd-dir <dir>, --pcap <file>, --bag <file> or --live");
  if (const std::string why = socc::checkLcmUrl(a.lcm_url, socc::lcmAuthFor(a.key_file));
      !why.empty())
    throw std::runtime_error("--lcm-url " + a.lcm_url + ": " + why);
  if (a.robot_id.empty()) throw std::runtime_error("--robot-id must not be empty");
  if (a.own_frame && (!a.initial_pose.empty() || a.resume))
    throw std::runtime_error(
        "--own-frame is for a robot without a pose: not with --initial-pose or --resume");
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

socc::rpc::ClientOptions clientOptions(const Args& a, const OdomConfig& config) {
  socc::rpc::ClientOptions client_options;
  client_options.lcm_url = a.lcm_url;
  client_options.client_id = a.robot_id;
  client_options.timeout = std::chrono::milliseconds(config.timeout_ms);
  client_options.max_attempts = config.max_attempts;
  client_options.key_file = a.key_file;
  return client_options;
}

// --resume: starts after the last scan the server integrated for this robot (advances
// a.first); a robot the server does not know starts fresh.
void resumeFromServer(socc::rpc::MapClient& client, Args& a, const OdomConfig& config,
                      RunOptions& options) {
  const auto reply = client.getRobotPose(a.robot_id);
  if (reply.ok()) {
    const socc::robot_state_t& state = reply.reply->state;
    options.initial_pose = socc::fromLcm(state.last_pose);
    if (options.relocalize && !options.hint) {
      // After an outage the robot may have moved: searched near where it was last.
      PoseHint near;
      near.position = options.initial_pose.translation();
      near.radius = config.relocalize_hint_radius;
      options.hint = near;
    }
    options.initial_pose_known = false;  // the pose of the last scan, not of the next one
    options.skip_until_seq = state.last_seq;
    a.first = std::max<std::int64_t>(a.first, state.last_seq + 1);
    std::cerr << "odom_client: resuming " << a.robot_id << " after seq " << state.last_seq << "\n";
  } else if (reply.error.status == socc::reply_header_t::NOT_FOUND) {
    std::cerr << "odom_client: the server does not know " << a.robot_id << " yet: starting fresh\n";
  } else {
    throw std::runtime_error("GET_ROBOT_POSE failed: " + reply.error.message);
  }
}

ImuAttitude imuAttitude(const fs::path& bag, const std::string& topic, const OdomConfig& config) {
  constexpr double kDeg = M_PI / 180.0;
  const bool stated = !std::isnan(config.imu_roll_deg);  // validate(): all three or none
  ImuAttitude imu;
  imu.stream = socc::sensors::openImuTopic(bag, topic);
  if (stated)
    imu.sensor_R_imu = (Eigen::AngleAxisd(config.imu_yaw_deg * kDeg, Eigen::Vector3d::UnitZ()) *
                        Eigen::AngleAxisd(config.imu_pitch_deg * kDeg, Eigen::Vector3d::UnitY()) *
                        Eigen::AngleAxisd(config.imu_roll_deg * kDeg, Eigen::Vector3d::UnitX()))
                           .toRotationMatrix();
  else
    imu.mounts = socc::sensors::StaticTransforms::fromBag(bag);
  imu.sigma = config.imu_attitude_sigma_deg * kDeg;
  return imu;
}

std::unique_ptr<ScanSource> openFiles(const Args& a, const OdomConfig& config) {
  if (!a.input.empty())
    return readAhead(openKittiDirectory(a.input, {a.first, a.last}, config.frame_period));
  if (!a.pcap.empty() || !a.bag.empty()) {
    socc::sensors::RecordingOptions options;
    options.sensor.model = a.sensor;
    options.sensor.calibration = a.calibration;
    options.sensor.sensor_address = a.sensor_address;
    options.topic = a.topic;
    options.port = a.port;
    std::unique_ptr<ScanSource> scans =
        openRecordingScans(a.pcap.empty() ? a.bag : a.pcap, options, {a.first, a.last});
    if (!a.imu_topic.empty())
      scans = withImuAttitude(std::move(scans), imuAttitude(a.bag, a.imu_topic, config));
    return readAhead(std::move(scans));
  }
  return readAhead(openPointCloudDirectory(a.pcd_dir, {a.first, a.last}, config.frame_period));
}

std::unique_ptr<ScanSource> openSource(const Args& a, const OdomConfig& config) {
  if (!a.live) {
    std::unique_ptr<ScanSource> files = openFiles(a, config);
    return a.rate > 0.0 ? atRecordedPace(std::move(files), a.rate) : std::move(files);
  }
  auto source = openLcmScans(a.scan_lcm_url.empty() ? a.lcm_url : a.scan_lcm_url, a.robot_id,
                             std::chrono::milliseconds(static_cast<int>(a.idle_timeout_s * 1000)));
  // Scans published before this line are not received: start lcm-logplayer after it.
  std::cerr << "odom_client: listening for scans on " << socc::channels::scan(a.robot_id)
            << std::endl;
  return source;
}

// Map-frame poses go to poses_kitti.txt / poses_tum.txt; a robot never merged into the shared
// map (--own-frame) has own-frame poses only, written as poses_own_frame_*.txt so that nothing
// takes them for map-frame poses.
void writeOutputs(const fs::path& out_dir, const Trajectory& t, bool own_frame) {
  if (out_dir.empty()) return;
  const std::string prefix = own_frame ? "poses_own_frame_" : "poses_";
  socc::writeKittiPoses(out_dir / (prefix + "kitti.txt"), t.poses);
  socc::writeTumPoses(out_dir / (prefix + "tum.txt"), t.poses, t.stamps);
}

void removeRevised(const fs::path& out_dir) {
  if (out_dir.empty()) return;
  std::error_code ec;
  for (const char* name : {"poses_revised_kitti.txt", "poses_revised_tum.txt"})
    fs::remove(out_dir / name, ec);
}

// Registers every scan of the source; the outputs are written even when a frame fails.
// Returns the exit code: 0, 1 (error), 3 (the run ended LOST), 4 (--relocalize found no pose) or
// 5 (--own-frame: the input ended before the robot was merged into the shared map).
int runOdometry(const Args& a, const OdomConfig& config, socc::rpc::MapClient& client,
                const RunOptions& options, ScanSource& source) {
  std::signal(SIGINT, onSignal);
  std::signal(SIGTERM, onSignal);
  FrameLog log(a.out_dir.empty() ? fs::path{} : fs::path(a.out_dir) / "frames.csv");
  OdomRunner runner(config, client, options);
  int rc = 0;
  try {
    runner.run(source, log);
  } catch (const RelocalizationFailed& e) {
    std::cerr << "odom_client: error: " << e.what() << "\n";
    rc = 4;
  } catch (const std::exception& e) {
    std::cerr << "odom_client: error: " << e.what() << "\n";
    rc = 1;
  }
  writeOutputs(a.out_dir, runner.trajectory(), runner.endedInOwnFrame());
  if (!a.out_dir.empty() && config.range_calibration)
    writeRangeCalibration((fs::path(a.out_dir) / "range_calibration.txt").string(),
                          runner.rangeCalibration());
  removeRevised(a.out_dir);  // an earlier run's must not pass for this one's
  if (!a.out_dir.empty() && !a.no_revised && rc != 1 && !runner.endedInOwnFrame()) {
    // Stopped by a signal: the keyframes the service holds now, without waiting for more.
    const double wait_s = g_stop ? 0.0 : a.revised_wait_s;
    std::cerr << "odom_client: "
              << writeRevisedTrajectory(client, a.robot_id, runner.trajectory(),
                                        runner.appliedCorrections(), a.out_dir,
                                        std::chrono::milliseconds(std::llround(wait_s * 1000.0)))
              << "\n";
  }
  std::cout << log.summary(runner.wallSeconds());
  std::cout << "map: " << runner.corrections() << " corrections applied, "
            << runner.relocalizations() << " relocalizations, " << runner.heldChunks()
            << " chunks held for the next Integrate reply (another robot's correction), "
            << runner.refetchedChunks() << " refetched\n";
  if (rc == 0 && runner.trackingState() == TrackingState::kLost) {
    std::cerr << "odom_client: error: the run ended LOST: frames after the robot lost track "
                 "were not integrated (frames.csv status column)\n";
    rc = 3;
  }
  if (rc == 0 && runner.endedInOwnFrame()) {
    std::cerr << "odom_client: error: not merged into the shared map by the end of the input "
                 "(--own-frame): nothing was integrated; own-frame poses in "
                 "poses_own_frame_kitti.txt / poses_own_frame_tum.txt\n";
    rc = 5;
  }
  return rc;
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
  Args args;
  addOptions(app, args);
  CLI11_PARSE(app, argc, argv);

  try {
    checkArgs(args);
    OdomConfig config =
        loadOdomConfig(std::vector<fs::path>(args.config_files.begin(), args.config_files.end()));
    if (args.no_semantics) config.use_semantics = false;
    if (args.no_gravity) config.use_gravity = false;
    if (args.frame_period > 0.0) config.frame_period = args.frame_period;
    if (!args.out_dir.empty()) fs::create_directories(args.out_dir);
    socc::rpc::MapClient client(clientOptions(args, config));

    RunOptions options{};  // value-initialized: GCC 12 took the empty hint for uninitialized
    options.progress = !args.quiet;
    options.stop = &g_stop;
    if (!args.initial_pose.empty()) {
      options.initial_pose = parsePose(args.initial_pose);
      options.initial_pose_known = true;
    }
    options.relocalize = args.relocalize;
    options.own_frame = args.own_frame;
    options.found_map = args.found_map;
    if (!args.pose_hint.empty()) options.hint = parseHint(args);
    if (args.resume) resumeFromServer(client, args, config, options);
    if (args.resume && !args.input.empty() &&
        args.first >= static_cast<std::int64_t>(socc::listKittiSequence(args.input).scans.size())) {
      std::cout << "odom_client: every frame of " << args.input << " was integrated already\n";
      return 0;
    }
    const std::unique_ptr<ScanSource> source = openSource(args, config);
    std::cerr << "odom_client: scan times: " << source->timing() << "\n";
    return runOdometry(args, config, client, options, *source);
  } catch (const std::exception& e) {
    std::cerr << "odom_client: error: " << e.what() << "\n";
    return 1;
  }
}
