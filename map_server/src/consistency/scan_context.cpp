#include "scan_context.hpp"

#include <cmath>

namespace socc::consistency {

ScanContext::ScanContext(const std::vector<Eigen::Vector3f>& points,
                         const ScanContextParams& params)
    : bins_(Eigen::MatrixXf::Zero(params.rings, params.sectors)),
      ring_key_(Eigen::VectorXf::Zero(params.rings)) {
  const double ring_width = params.max_range / params.rings;
  const double sector_width = 2.0 * M_PI / params.sectors;
  for (const Eigen::Vector3f& p : points) {
    const double range = std::hypot(p.x(), p.y());
    if (!(range < params.max_range) || range < 1e-3) continue;
    const int ring = std::min(params.rings - 1, static_cast<int>(range / ring_width));
    const double azimuth = std::atan2(p.y(), p.x()) + M_PI;  // [0, 2 pi]
    const int sector = std::min(params.sectors - 1, static_cast<int>(azimuth / sector_width));
    // Negative heights (a pit below the offset) count as the lowest non-empty value.
    const float height = std::max(1e-3f, p.z() + static_cast<float>(params.height_offset));
    bins_(ring, sector) = std::max(bins_(ring, sector), height);
  }
  for (int r = 0; r < params.rings; ++r)
    ring_key_(r) = static_cast<float>((bins_.row(r).array() > 0.0f).count()) / params.sectors;
}

ScanContext::Match ScanContext::compare(const ScanContext& other) const {
  Match best;
  if (empty() || other.empty() || bins_.rows() != other.bins_.rows() ||
      bins_.cols() != other.bins_.cols())
    return best;
  const Eigen::Index sectors = bins_.cols();
  const Eigen::RowVectorXf norms = bins_.colwise().norm();
  const Eigen::RowVectorXf other_norms = other.bins_.colwise().norm();
  for (Eigen::Index shift = 0; shift < sectors; ++shift) {
    double sum = 0.0;
    int compared = 0;
    for (Eigen::Index s = 0; s < sectors; ++s) {
      const Eigen::Index o = (s + shift) % sectors;
      if (norms(s) <= 0.0f || other_norms(o) <= 0.0f) continue;  // an empty sector says nothing
      sum += bins_.col(s).dot(other.bins_.col(o)) / (norms(s) * other_norms(o));
      ++compared;
    }
    if (compared == 0) continue;
    const double distance = 1.0 - sum / compared;
    if (distance < best.distance) {
      best.distance = distance;
      // Sector s here sees what sector s + shift sees there: this sensor is turned by shift.
      best.yaw = std::remainder(2.0 * M_PI * static_cast<double>(shift) / sectors, 2.0 * M_PI);
    }
  }
  return best;
}

std::size_t ScanContext::bytes() const {
  return static_cast<std::size_t>(bins_.size() + ring_key_.size()) * sizeof(float);
}

}  // namespace socc::consistency
