#pragma once
// What map_server --consistency-dir writes (keyframes.txt, closures.txt), read back for the
// consistency benchmarks (bench_consistency_eval, bench_gravity_graph), and the tilt fit of a
// vertical error; docs/consistency.md describes the files.
#include <Eigen/Dense>
#include <cmath>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

namespace socc::bench {

/// 12 values of a KITTI-layout pose (3x4, row-major).
inline Eigen::Isometry3d readPose(std::istream& in) {
  Eigen::Matrix4d m = Eigen::Matrix4d::Identity();
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 4; ++c) in >> m(r, c);
  return Eigen::Isometry3d(m);
}

struct KeyframeRow {
  std::string robot;
  long seq = 0;
  Eigen::Isometry3d odom = Eigen::Isometry3d::Identity();       // as integrated
  Eigen::Isometry3d optimized = Eigen::Isometry3d::Identity();  // the graph's estimate
};

/// keyframes.txt: `robot seq` and the two poses per line. Throws when the file cannot be read.
inline std::vector<KeyframeRow> readKeyframes(const std::string& file) {
  std::ifstream in(file);
  if (!in) throw std::runtime_error("cannot read " + file);
  std::vector<KeyframeRow> rows;
  std::string line;
  while (std::getline(in, line)) {
    std::istringstream s(line);
    KeyframeRow row;
    if (!(s >> row.robot >> row.seq)) continue;
    row.odom = readPose(s);
    row.optimized = readPose(s);
    if (s) rows.push_back(row);
  }
  return rows;
}

struct ClosureRow {
  std::string robot_a, robot_b;
  long seq_a = 0, seq_b = 0;
  Eigen::Isometry3d relative = Eigen::Isometry3d::Identity();
};

/// closures.txt: `robot_a seq_a robot_b seq_b` and the relative pose per line (none: empty).
inline std::vector<ClosureRow> readClosures(const std::string& file) {
  std::ifstream in(file);
  std::vector<ClosureRow> rows;
  std::string line;
  while (std::getline(in, line)) {
    std::istringstream s(line);
    ClosureRow row;
    if (!(s >> row.robot_a >> row.seq_a >> row.robot_b >> row.seq_b)) continue;
    row.relative = readPose(s);
    if (s) rows.push_back(row);
  }
  return rows;
}

// The vertical error as a tilted map frame: z error = a x + b y + c over the truth's positions
// (least squares). A tilt is consistent everywhere: no loop closure can observe it.
struct TiltFit {
  double degrees = 0.0;   // tilt of the fitted plane
  double residual = 0.0;  // RMS of the vertical error the plane leaves [m]
};

inline TiltFit fitTilt(const std::vector<Eigen::Vector3d>& truth,
                       const std::vector<double>& z_error) {
  TiltFit out;
  if (truth.size() < 3) return out;
  Eigen::MatrixXd a(truth.size(), 3);
  Eigen::VectorXd z(truth.size());
  for (std::size_t i = 0; i < truth.size(); ++i) {
    a.row(static_cast<Eigen::Index>(i)) << truth[i].x(), truth[i].y(), 1.0;
    z(static_cast<Eigen::Index>(i)) = z_error[i];
  }
  const Eigen::Vector3d p = a.colPivHouseholderQr().solve(z);
  out.degrees = std::atan(std::hypot(p.x(), p.y())) * 180.0 / M_PI;
  out.residual = std::sqrt((a * p - z).squaredNorm() / static_cast<double>(truth.size()));
  return out;
}

}  // namespace socc::bench
