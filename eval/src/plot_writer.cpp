#include "socc/eval/plot_writer.hpp"

#include <spawn.h>
#include <sys/wait.h>

#include <fstream>
#include <stdexcept>
#include <string>
#include <vector>

extern char** environ;

namespace socc::eval {
namespace fs = std::filesystem;

namespace {

std::ofstream openData(const fs::path& file) {
  std::ofstream out(file);
  if (!out) throw std::runtime_error(file.string() + ": cannot open for writing");
  out.precision(9);
  return out;
}

// The two axes of the top view: drop the axis along which the ground truth varies least
// (z in the LiDAR frame, y for KITTI camera-frame poses).
std::pair<int, int> topViewAxes(const Poses& gt) {
  Eigen::Vector3d lo = Eigen::Vector3d::Constant(1e300);
  Eigen::Vector3d hi = -lo;
  for (const auto& p : gt) {
    lo = lo.cwiseMin(p.translation());
    hi = hi.cwiseMax(p.translation());
  }
  Eigen::Index up = 2;
  (hi - lo).minCoeff(&up);
  if (up == 0) return {1, 2};
  if (up == 1) return {0, 2};
  return {0, 1};
}

// Runs gnuplot without a shell (paths may contain any character).
void runGnuplot(const fs::path& script, const fs::path& dir) {
  if (!fs::is_regular_file(script))
    throw std::runtime_error(script.string() + ": plot script not found (see --plot-scripts)");
  const std::string vars = "dir='" + dir.string() + "'";
  if (dir.string().find('\'') != std::string::npos)
    throw std::runtime_error(dir.string() + ": plot directory must not contain a quote");
  std::vector<std::string> args = {"gnuplot", "-e", vars, script.string()};
  std::vector<char*> argv;
  for (auto& a : args) argv.push_back(a.data());
  argv.push_back(nullptr);
  pid_t pid = 0;
  if (posix_spawnp(&pid, "gnuplot", nullptr, nullptr, argv.data(), environ) != 0)
    throw std::runtime_error("cannot start gnuplot (is gnuplot installed?)");
  int status = 0;
  if (waitpid(pid, &status, 0) < 0 || !WIFEXITED(status) || WEXITSTATUS(status) != 0)
    throw std::runtime_error("gnuplot failed on " + script.string());
}

void writeTrajectoryData(const fs::path& file, const Poses& gt, const Poses& est,
                         const Evaluation& e) {
  const auto [a, b] = topViewAxes(gt);
  std::ofstream out = openData(file);
  out << "# frame gt_a gt_b est_a est_b aligned_a aligned_b (top-view axes " << a << ", " << b
      << ")\n";
  for (std::size_t i = 0; i < gt.size(); ++i) {
    const auto& g = gt[i].translation();
    const auto& s = est[i].translation();
    const auto& t = e.ate.aligned_estimate[i].translation();
    out << i << ' ' << g[a] << ' ' << g[b] << ' ' << s[a] << ' ' << s[b] << ' ' << t[a] << ' '
        << t[b] << '\n';
  }
}

void writeErrorData(const fs::path& file, std::size_t frames, const Evaluation& e) {
  std::ofstream out = openData(file);
  out << "# frame ate_m rpe_trans_m rpe_rot_deg (RPE of the pair frame-1 -> frame)\n";
  for (std::size_t i = 0; i < frames; ++i) {
    out << i << ' ' << e.ate.errors[i];
    if (i > 0)
      out << ' ' << e.rpe.translation_errors[i - 1] << ' ' << e.rpe.rotation_errors[i - 1];
    else
      out << " NaN NaN";
    out << '\n';
  }
}

void writeKittiData(const fs::path& dir, const KittiMetrics& kitti) {
  std::ofstream lengths = openData(dir / "kitti_lengths.dat");
  lengths << "# length_m segments t_err_percent r_err_deg_per_100m\n";
  for (const auto& l : kitti.per_length)
    if (l.segments > 0)
      lengths << l.length << ' ' << l.segments << ' ' << l.t_err_percent << ' '
              << l.r_err_deg_per_100m << '\n';
  std::ofstream speeds = openData(dir / "kitti_speeds.dat");
  speeds << "# speed_m_per_s segments t_err_percent r_err_deg_per_100m (devkit: 0.1 s/frame, "
            "+-2 m/s)\n";
  for (const auto& v : kittiErrorsBySpeed(kitti))
    speeds << v.speed << ' ' << v.segments << ' ' << v.t_err_percent << ' ' << v.r_err_deg_per_100m
           << '\n';
}

}  // namespace

void writePlotData(const fs::path& dir, const Poses& gt, const Poses& est, const Evaluation& e) {
  fs::create_directories(dir);
  writeTrajectoryData(dir / "trajectory.dat", gt, est, e);
  writeErrorData(dir / "errors.dat", gt.size(), e);
  writeKittiData(dir, e.kitti);
}

void renderPlots(const fs::path& dir, const fs::path& script_dir, const Evaluation& e) {
  runGnuplot(script_dir / "plot_trajectory.gp", dir);
  runGnuplot(script_dir / "plot_errors.gp", dir);
  if (!e.kitti.valid()) return;
  runGnuplot(script_dir / "plot_kitti_lengths.gp", dir);
  runGnuplot(script_dir / "plot_kitti_speeds.gp", dir);
}

}  // namespace socc::eval
