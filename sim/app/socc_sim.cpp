// socc-sim: synthetic LiDAR sequences with exact ground truth, in the KITTI layout.
#include <CLI/CLI.hpp>
#include <chrono>
#include <cmath>
#include <iomanip>
#include <iostream>
#include <optional>

#include "socc/kitti_io.hpp"
#include "socc/sim/realism.hpp"
#include "socc/sim/road_heights.hpp"
#include "socc/sim/road_report.hpp"
#include "socc/sim/scene.hpp"
#include "socc/sim/sequence_writer.hpp"
#include "socc/version.hpp"

namespace {

namespace fs = std::filesystem;
using namespace socc::sim;

struct Arguments {
  std::string scene = "street";
  std::string sensor = "hdl64";
  std::size_t frames = 100;
  std::size_t every = 1;
  std::uint64_t seed = 1;
  std::optional<std::uint64_t> sensor_seed;
  fs::path out;
  std::string trajectory = "auto";
  std::optional<fs::path> kitti_poses;
  std::optional<fs::path> calib;
  bool recorded_heights = false;
  bool road_report = false;
  std::optional<double> speed;
  double noise = 0.02;
  double dropout = 0.0;
  bool distortion = false;
  double max_range = 100.0;
  std::string realism = "none";
  std::vector<std::string> realism_off;
  double realism_scale = 1.0;
  std::optional<std::string> imu;  // default: ins with --realism kitti, none without
  bool quiet = false;
};

// The route at the heights of the road it drove (unless --recorded-heights): the recorded
// attitude's grade, one height at each revisit (road_heights.hpp). Returns each pose's change.
std::vector<double> roadHeights(socc::Poses& poses, const Arguments& a) {
  if (a.recorded_heights) return {};
  RoadHeights road = fuseRoadHeights(poses);
  if (!a.quiet)
    std::cerr << "heights fused with the recorded attitude (" << road.revisit_pairs
              << " poses tied to a street driven before): changed by up to "
              << std::round(road.max_change * 100.0) / 100.0 << " m; the sensor pitched "
              << std::round(road.sensor_pitch * 180.0 / M_PI * 100.0) / 100.0
              << " deg against the road\n";
  poses = std::move(road.poses);
  return std::move(road.change);
}

socc::Poses routePoses(const Arguments& a) {
  socc::Poses poses = socc::readKittiPoses(*a.kitti_poses);
  if (a.calib) poses = socc::cameraToLidarPoses(poses, socc::readKittiCalibTr(*a.calib));
  if (poses.size() < 2) throw std::runtime_error(a.kitti_poses->string() + ": need >= 2 poses");
  return poses;
}

// --road-report: the route's heights against its attitude, recorded and as fused (the table of
// docs/simulator.md "Road heights").
int printRoadReport(const Arguments& a) {
  const RoadReport report = roadReport(routePoses(a));
  const auto degrees = [](double rad) { return rad * 180.0 / M_PI; };
  const auto row = [](const char* name, double recorded, double road) {
    std::cout << std::left << std::setw(36) << name << std::right << std::setw(10) << recorded
              << std::setw(10) << road << '\n';
  };
  std::cout << std::fixed << std::setprecision(3) << a.kitti_poses->string() << ": "
            << report.heights.poses.size() << " poses, the sensor pitched "
            << degrees(report.heights.sensor_pitch) << " deg against the road, "
            << report.heights.revisit_pairs << " poses tied to a street driven before, heights "
            << "changed by up to " << report.heights.max_change << " m\n"
            << std::setw(56) << "recorded      road\n";
  row("grade vs attitude, 10 m [deg RMS]", degrees(report.recorded.grade_rms),
      degrees(report.road.grade_rms));
  row("steepest 10 m [%]", 100.0 * report.recorded.steepest, 100.0 * report.road.steepest);
  row("worst revisit difference [m]", report.recorded.worst_revisit, report.road.worst_revisit);
  return 0;
}

int run(const Arguments& a) {
  if (a.road_report) return printRoadReport(a);
  if (a.out.empty()) throw std::runtime_error("--out is required");
  SceneOptions scene_options;
  scene_options.type = parseSceneType(a.scene);
  scene_options.route = a.trajectory;
  SequenceOptions options;
  options.frames = a.frames;
  options.every = a.every;
  scene_options.frames = sweepsSpanned(options);
  if (scene_options.frames > 100000)
    throw std::runtime_error("--frames x --every spans more than 100000 sweeps");
  scene_options.speed = a.speed;
  scene_options.seed = a.seed;
  Realism realism = realismPreset(a.realism);
  disableRealism(realism, a.realism_off);
  scaleRealism(realism, a.realism_scale);
  scene_options.body_motion = realism.motion;
  std::vector<double> height_change;
  if (a.kitti_poses) {
    socc::Poses poses = routePoses(a);
    if (scene_options.frames > poses.size()) {
      options.frames = (poses.size() - 1) / options.every + 1;
      scene_options.frames = sweepsSpanned(options);
      std::cerr << "note: " << a.kitti_poses->string() << " has " << poses.size()
                << " poses; generating " << options.frames << " frames\n";
    }
    height_change = roadHeights(poses, a);
    scene_options.poses = std::move(poses);
  }
  LidarModel model = lidarPreset(a.sensor);
  model.range_noise = a.noise;
  model.dropout = a.dropout;
  model.max_range = a.max_range;

  const auto start = std::chrono::steady_clock::now();
  const Scene scene = buildScene(scene_options);
  options.frame_period = scene_options.frame_period;
  options.write_point_times = a.distortion;
  options.show_progress = !a.quiet;
  options.scan = {a.distortion, a.seed, &realism, a.sensor_seed};
  const std::string imu = a.imu.value_or(a.realism == "kitti" ? "ins" : "none");
  options.imu = imuPreset(imu);
  options.recorded_height_change = std::move(height_change);
  const SequenceSummary summary = writeSequence(a.out, scene, model, options);
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  std::cout << "wrote " << options.frames << " frames"
            << (options.every > 1 ? " (one sweep in " + std::to_string(options.every) + ")" : "")
            << " (" << a.scene << ", " << a.sensor << ") to " << a.out.string() << " in " << seconds
            << " s (realism " << a.realism << ", imu " << imu << ")\n";
  if (summary.label_classes > 0)
    std::cout << "labels: mIoU " << 100.0 * summary.label_miou << " % against the exact labels ("
              << summary.label_classes << " classes)\n";
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{
      "socc-sim: ray-casts a procedurally generated, seeded world into a synthetic LiDAR\n"
      "sequence with exact ground truth, written in the KITTI layout (velodyne/, labels/ with\n"
      "raw SemanticKITTI ids, poses.txt in the LiDAR frame, calib.txt, times.txt, with\n"
      "--distortion point_times/, with an --imu gravity.txt, with --kitti-poses\n"
      "poses_recorded_heights.txt). Same seed -> identical files.\n"
      "Default: 100 frames of an urban street (HDL-64, 9 m/s, moving cars and pedestrians)."};
  app.set_version_flag("--version", socc::versionLine("socc-sim"));
  Arguments a;
  app.add_option("--out", a.out, "Output directory (created); required unless --road-report");
  app.add_option("--scene", a.scene, "World to build around the trajectory")
      ->check(CLI::IsMember({"street", "corridor", "zigzag", "office", "indoor"}))
      ->capture_default_str();
  app.add_option("--sensor", a.sensor, "LiDAR model")
      ->check(CLI::IsMember({"hdl64", "vlp32", "vlp16"}))
      ->capture_default_str();
  app.add_option("--frames", a.frames, "Number of frames (10 Hz)")
      ->check(CLI::Range(std::size_t{1}, std::size_t{100000}))
      ->capture_default_str();
  app.add_option("--every", a.every,
                 "Write every Nth sweep only: a recording of the 10 Hz sensor at 1/N of its rate "
                 "(e.g. 5: 2 Hz); its frames are sweeps 0, N, 2N, ... of the 10 Hz sequence, "
                 "byte for byte, and --frames counts the frames written")
      ->check(CLI::Range(std::size_t{1}, std::size_t{1000}))
      ->capture_default_str();
  app.add_option("--seed", a.seed, "Seed of the world, noise and dropouts")->capture_default_str();
  app.add_option("--sensor-seed", a.sensor_seed,
                 "Seed of the sensor instance: its per-laser calibration errors (--realism); "
                 "default: --seed");
  auto* traj = app.add_option("--trajectory", a.trajectory,
                              "Route (auto: the scene's default: street/corridor/office "
                              "straight, zigzag zigzag, indoor circle)")
                   ->check(CLI::IsMember({"auto", "straight", "circle", "figure8", "zigzag"}))
                   ->capture_default_str();
  auto* kitti = app.add_option("--kitti-poses", a.kitti_poses,
                               "Follow a real KITTI GT trajectory (3x4 per line, 10 Hz); the "
                               "world is built along it. Without --calib the poses must "
                               "already be LiDAR-frame poses (x forward, z up)")
                    ->check(CLI::ExistingFile)
                    ->excludes(traj);
  app.add_option("--calib", a.calib,
                 "KITTI calib.txt whose Tr moves --kitti-poses from the camera to the LiDAR "
                 "frame")
      ->check(CLI::ExistingFile)
      ->needs(kitti);
  app.add_flag("--recorded-heights", a.recorded_heights,
               "Keep --kitti-poses' heights as recorded. By default the world is built at the "
               "heights of the road the recorded attitude drove (KITTI's GPS heights climb 16 m "
               "under a level car on 08 and do not close at revisits, up to 6 m), tied to one "
               "height at every revisit; poses_recorded_heights.txt then holds the ground truth "
               "at the recorded heights (docs/simulator.md \"Road heights\")")
      ->needs(kitti);
  app.add_flag("--road-report", a.road_report,
               "Print how --kitti-poses' recorded heights and the fused road's fit the recorded "
               "attitude (grade against attitude, steepest 10 m, worst revisit difference, the "
               "sensor's pitch against the road) and exit; no sequence is written")
      ->needs(kitti);
  app.add_option("--speed", a.speed, "Speed along the route [m/s] (default per scene)")
      ->check(CLI::NonNegativeNumber)
      ->excludes(kitti);
  app.add_option("--noise", a.noise, "Gaussian range noise sigma [m]")
      ->check(CLI::Range(0.0, 1.0))
      ->capture_default_str();
  app.add_option("--dropout", a.dropout, "Probability that a return is lost")
      ->check(CLI::Range(0.0, 1.0))
      ->capture_default_str();
  app.add_flag("--distortion", a.distortion,
               "Move the sensor during each 0.1 s sweep and write per-point times "
               "(point_times/); see sim/README.md for the convention");
  app.add_option("--max-range", a.max_range, "Maximum range [m]")
      ->check(CLI::Range(1.0, 1000.0))
      ->capture_default_str();
  app.add_option("--realism", a.realism,
                 "Error models of real LiDAR data (sim/README.md \"Realism\"): none = exact "
                 "(unit tests), kitti = a KITTI-like HDL-64 on a car (the benchmarks' default)")
      ->check(CLI::IsMember({"none", "kitti"}))
      ->capture_default_str();
  app.add_option(
         "--realism-off", a.realism_off,
         std::string("Switch groups (or single models) of the preset off: ") + kRealismSwitches)
      ->delimiter(',');
  app.add_option("--realism-scale", a.realism_scale,
                 "Multiply every magnitude of the preset (probabilities saturate at 1)")
      ->check(CLI::Range(0.0, 10.0))
      ->capture_default_str();
  app.add_option("--imu", a.imu,
                 "Attitude sensor writing gravity.txt (the up direction in the sensor frame per "
                 "frame, sim/README.md \"Attitude sensor\"): none, ins (an OxTS RT3003-class "
                 "INS, 0.035 deg), mems (a MEMS IMU with an attitude filter, 0.24 deg); "
                 "default: ins with --realism kitti, none otherwise")
      ->check(CLI::IsMember({"none", "ins", "mems"}));
  app.add_flag("--quiet", a.quiet, "No progress bar");
  CLI11_PARSE(app, argc, argv);
  try {
    return run(a);
  } catch (const std::exception& ex) {
    std::cerr << "error: " << ex.what() << '\n';
    return 1;
  }
}
