// socc-eval: scores an estimated trajectory against ground truth (KITTI metrics, ATE, RPE).
#include <CLI/CLI.hpp>
#include <fstream>
#include <iostream>
#include <nlohmann/json.hpp>
#include <optional>

#include "socc/eval/evaluation.hpp"
#include "socc/eval/plot_writer.hpp"
#include "socc/eval/trajectory.hpp"
#include "socc/version.hpp"

namespace {

namespace fs = std::filesystem;
using namespace socc::eval;

// Installed, the gnuplot scripts are in <prefix>/share/socc/scripts next to bin/ (any prefix);
// a build-tree binary uses the source tree's scripts/.
fs::path defaultPlotScripts() {
  std::error_code ec;
  const fs::path exe = fs::read_symlink("/proc/self/exe", ec);
  const fs::path installed = exe.parent_path().parent_path() / "share/socc/scripts";
  if (!ec && fs::is_directory(installed, ec)) return installed;
  return SOCC_SCRIPTS_DIR;
}

struct Arguments {
  fs::path gt;
  fs::path est;
  std::string gt_format = "auto";
  std::string est_format = "auto";
  std::optional<fs::path> calib;
  std::vector<double> lengths = kittiDefaultLengths();
  std::size_t step = 10;
  bool truncate = false;
  std::optional<fs::path> json;
  std::optional<fs::path> plot_dir;
  fs::path plot_scripts = defaultPlotScripts();
};

int run(const Arguments& a) {
  Trajectory gt = loadTrajectory(a.gt, parseTrajectoryFormat(a.gt_format), a.calib);
  Trajectory est = loadTrajectory(a.est, parseTrajectoryFormat(a.est_format));
  if (gt.poses.size() != est.poses.size()) {
    if (!a.truncate) {
      std::cerr << "error: " << a.est << " has " << est.poses.size() << " poses but " << a.gt
                << " has " << gt.poses.size() << " (use --truncate to score the common prefix)\n";
      return 2;
    }
    const std::size_t n = std::min(gt.poses.size(), est.poses.size());
    std::cerr << "note: scoring the first " << n << " poses only (--truncate)\n";
    gt.poses.resize(n);
    est.poses.resize(n);
  }
  if (gt.poses.size() < 2) {
    std::cerr << "error: at least 2 poses are needed\n";
    return 2;
  }

  const Evaluation e = evaluate(gt.poses, est.poses, {a.lengths, a.step});
  printTable(std::cout, e);
  if (a.json) {
    std::ofstream out(*a.json);
    out << toJson(e).dump(2) << '\n';
    if (!out) throw std::runtime_error(a.json->string() + ": cannot write");
  }
  if (a.plot_dir) {
    writePlotData(*a.plot_dir, gt.poses, est.poses, e);
    renderPlots(*a.plot_dir, a.plot_scripts, e);
    std::cout << "\nplots written to " << a.plot_dir->string() << '\n';
  }
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{
      "socc-eval: scores an estimated trajectory against ground truth.\n"
      "Prints the KITTI odometry metrics (t_err %, r_err deg/100m over sub-sequences of\n"
      "--lengths metres, first frames every --step frames), the ATE after SE(3) alignment\n"
      "(as evo_ape -a) and the frame-to-frame RPE (as evo_rpe, delta 1 frame).\n"
      "Poses are matched by index: both files must hold the same number of poses."};
  app.set_version_flag("--version", socc::versionLine("socc-eval"));
  Arguments a;
  app.add_option("--gt", a.gt, "Ground-truth trajectory (KITTI 3x4 or TUM)")
      ->required()
      ->check(CLI::ExistingFile);
  app.add_option("--est", a.est, "Estimated trajectory (KITTI 3x4 or TUM)")
      ->required()
      ->check(CLI::ExistingFile);
  app.add_option("--gt-format", a.gt_format, "Ground-truth format")
      ->check(CLI::IsMember({"auto", "kitti", "tum"}))
      ->capture_default_str();
  app.add_option("--est-format", a.est_format, "Estimate format")
      ->check(CLI::IsMember({"auto", "kitti", "tum"}))
      ->capture_default_str();
  app.add_option("--calib", a.calib,
                 "KITTI calib.txt: the ground truth is in the camera frame; move it to the LiDAR "
                 "frame with Tr (T_lidar = Tr^-1 T_cam Tr)")
      ->check(CLI::ExistingFile);
  app.add_option("--lengths", a.lengths, "KITTI sub-sequence lengths [m], comma separated")
      ->delimiter(',')
      ->check(CLI::PositiveNumber)
      ->capture_default_str();
  app.add_option("--step", a.step, "KITTI first-frame step [frames]")
      ->check(CLI::PositiveNumber)
      ->capture_default_str();
  app.add_flag("--truncate", a.truncate,
               "Score the common prefix when the files have different numbers of poses");
  app.add_option("--json", a.json, "Also write the results as JSON to this file");
  app.add_option("--plot-dir", a.plot_dir,
                 "Write data files and PNG plots (trajectory, errors, KITTI per length) here");
  app.add_option("--plot-scripts", a.plot_scripts, "Directory of the plot_*.gp gnuplot scripts")
      ->capture_default_str();
  CLI11_PARSE(app, argc, argv);
  try {
    return run(a);
  } catch (const std::exception& ex) {
    std::cerr << "error: " << ex.what() << '\n';
    return 1;
  }
}
