#include "socc/eval/trajectory.hpp"

#include <Eigen/SVD>
#include <cmath>
#include <fstream>
#include <sstream>
#include <stdexcept>

namespace socc::eval {
namespace fs = std::filesystem;

namespace {

// Number of whitespace-separated fields on the first non-blank, non-comment line.
std::size_t firstLineFieldCount(const fs::path& file) {
  std::ifstream in(file);
  if (!in) throw std::runtime_error(file.string() + ": cannot open");
  std::string line;
  while (std::getline(in, line)) {
    const auto p = line.find_first_not_of(" \t\r");
    if (p == std::string::npos || line[p] == '#') continue;
    std::istringstream ss(line);
    std::size_t n = 0;
    for (std::string field; ss >> field;) ++n;
    return n;
  }
  throw std::runtime_error(file.string() + ": no poses");
}

TrajectoryFormat detectFormat(const fs::path& file) {
  const std::size_t fields = firstLineFieldCount(file);
  if (fields == 12) return TrajectoryFormat::kKitti;
  if (fields == 8) return TrajectoryFormat::kTum;
  throw std::runtime_error(file.string() + ": cannot detect the format (" + std::to_string(fields) +
                           " numbers per line; KITTI has 12, TUM has 8)");
}

// KITTI files hold ~7 significant digits, so their rotations are orthonormal only to ~1e-6;
// project to the nearest rotation so that chained relative poses stay rigid.
Eigen::Isometry3d orthonormalized(const Eigen::Isometry3d& pose) {
  Eigen::Isometry3d out = pose;
  const Eigen::JacobiSVD<Eigen::Matrix3d> svd(pose.linear(),
                                              Eigen::ComputeFullU | Eigen::ComputeFullV);
  Eigen::Matrix3d r = svd.matrixU() * svd.matrixV().transpose();
  out.linear() = r;
  return out;
}

}  // namespace

TrajectoryFormat parseTrajectoryFormat(const std::string& name) {
  if (name == "auto") return TrajectoryFormat::kAuto;
  if (name == "kitti") return TrajectoryFormat::kKitti;
  if (name == "tum") return TrajectoryFormat::kTum;
  throw std::invalid_argument("unknown trajectory format '" + name + "' (auto, kitti, tum)");
}

Trajectory loadTrajectory(const fs::path& file, TrajectoryFormat format,
                          const std::optional<fs::path>& calib) {
  if (format == TrajectoryFormat::kAuto) format = detectFormat(file);
  Trajectory t;
  t.poses =
      format == TrajectoryFormat::kKitti ? readKittiPoses(file) : readTumPoses(file, &t.stamps);
  if (t.poses.empty()) throw std::runtime_error(file.string() + ": no poses");
  if (calib) t.poses = cameraToLidarPoses(t.poses, orthonormalized(readKittiCalibTr(*calib)));
  for (std::size_t i = 0; i < t.poses.size(); ++i) {
    const double det = t.poses[i].linear().determinant();
    if (!(std::abs(det - 1.0) < 1e-2))
      throw std::runtime_error(file.string() + ": pose " + std::to_string(i) +
                               " is not a rotation (determinant " + std::to_string(det) + ")");
    t.poses[i] = orthonormalized(t.poses[i]);
  }
  return t;
}

}  // namespace socc::eval
