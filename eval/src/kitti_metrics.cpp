#include "socc/eval/kitti_metrics.hpp"

#include <algorithm>
#include <cmath>
#include <optional>
#include <stdexcept>

namespace socc::eval {

namespace {

constexpr double kRadToDeg = 180.0 / M_PI;

// First frame after `first` whose distance exceeds dist[first] + length (devkit semantics).
std::optional<std::size_t> lastFrameOfSegment(const std::vector<double>& dist, std::size_t first,
                                              double length) {
  const double target = dist[first] + length;
  const auto it =
      std::upper_bound(dist.begin() + static_cast<std::ptrdiff_t>(first), dist.end(), target);
  if (it == dist.end()) return std::nullopt;
  return static_cast<std::size_t>(it - dist.begin());
}

}  // namespace

std::vector<double> kittiDefaultLengths() {
  return {100, 200, 300, 400, 500, 600, 700, 800};
}

std::vector<double> trajectoryDistances(const Poses& poses) {
  std::vector<double> dist(poses.size(), 0.0);
  for (std::size_t i = 1; i < poses.size(); ++i)
    dist[i] = dist[i - 1] + (poses[i].translation() - poses[i - 1].translation()).norm();
  return dist;
}

double rotationAngle(const Eigen::Isometry3d& pose) {
  const Eigen::Matrix3d& r = pose.linear();
  const double c = 0.5 * (r.trace() - 1.0);
  const double s =
      0.5 * Eigen::Vector3d(r(2, 1) - r(1, 2), r(0, 2) - r(2, 0), r(1, 0) - r(0, 1)).norm();
  return std::atan2(s, c);
}

KittiMetrics computeKittiMetrics(const Poses& gt, const Poses& est,
                                 const std::vector<double>& lengths, std::size_t step) {
  if (gt.size() != est.size())
    throw std::invalid_argument("KITTI metrics need as many estimated poses (" +
                                std::to_string(est.size()) + ") as ground-truth poses (" +
                                std::to_string(gt.size()) + ")");
  if (step == 0) throw std::invalid_argument("KITTI metrics: step must be > 0");
  for (const double l : lengths)
    if (!(l > 0.0)) throw std::invalid_argument("KITTI metrics: lengths must be > 0");

  KittiMetrics m;
  const std::vector<double> dist = trajectoryDistances(gt);
  // The distance is non-decreasing, so the devkit's linear search equals an upper_bound.
  for (std::size_t first = 0; first < gt.size(); first += step) {
    for (const double length : lengths) {
      const auto last = lastFrameOfSegment(dist, first, length);
      if (!last) continue;
      const Eigen::Isometry3d delta_gt = gt[first].inverse() * gt[*last];
      const Eigen::Isometry3d delta_est = est[first].inverse() * est[*last];
      const Eigen::Isometry3d error = delta_est.inverse() * delta_gt;
      m.segments.push_back({first, *last, length, error.translation().norm() / length,
                            rotationAngle(error) / length});
    }
  }

  for (const double length : lengths) {
    KittiLengthError le;
    le.length = length;
    for (const auto& s : m.segments) {
      if (s.length != length) continue;
      ++le.segments;
      le.t_err_percent += s.t_err;
      le.r_err_deg_per_100m += s.r_err;
    }
    if (le.segments > 0) {
      le.t_err_percent *= 100.0 / static_cast<double>(le.segments);
      le.r_err_deg_per_100m *= 100.0 * kRadToDeg / static_cast<double>(le.segments);
    }
    m.per_length.push_back(le);
  }

  if (m.valid()) {
    double t = 0.0;
    double r = 0.0;
    for (const auto& s : m.segments) {
      t += s.t_err;
      r += s.r_err;
    }
    const double n = static_cast<double>(m.segments.size());
    m.t_err_percent = 100.0 * t / n;
    m.r_err_deg_per_100m = 100.0 * kRadToDeg * r / n;
  }
  return m;
}

std::vector<KittiSpeedError> kittiErrorsBySpeed(const KittiMetrics& metrics, double frame_period) {
  if (!(frame_period > 0.0)) throw std::invalid_argument("KITTI speeds: frame period must be > 0");
  std::vector<KittiSpeedError> out;
  for (int centre = 2; centre < 25; centre += 2) {
    KittiSpeedError bin;
    bin.speed = centre;
    for (const auto& s : metrics.segments) {
      const double frames = static_cast<double>(s.last_frame - s.first_frame + 1);
      if (std::abs(s.length / (frame_period * frames) - centre) >= 2.0) continue;
      ++bin.segments;
      bin.t_err_percent += s.t_err;
      bin.r_err_deg_per_100m += s.r_err;
    }
    if (bin.segments == 0) continue;
    bin.t_err_percent *= 100.0 / static_cast<double>(bin.segments);
    bin.r_err_deg_per_100m *= 100.0 * kRadToDeg / static_cast<double>(bin.segments);
    out.push_back(bin);
  }
  return out;
}

}  // namespace socc::eval
