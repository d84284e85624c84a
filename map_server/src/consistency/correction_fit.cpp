#include "correction_fit.hpp"

namespace socc::consistency {

Eigen::Isometry3d fitCorrection(const std::vector<CorrectionSample>& samples) {
  Eigen::Isometry3d out = Eigen::Isometry3d::Identity();
  if (samples.empty()) return out;
  // Mean of unit quaternions on one hemisphere: exact enough for corrections degrees apart.
  Eigen::Vector4d sum = Eigen::Vector4d::Zero();
  Eigen::Vector3d raw_centroid = Eigen::Vector3d::Zero();
  Eigen::Vector3d optimized_centroid = Eigen::Vector3d::Zero();
  const Eigen::Quaterniond first(samples.front().optimized.linear() *
                                 samples.front().raw.linear().transpose());
  for (const CorrectionSample& s : samples) {
    Eigen::Quaterniond q(s.optimized.linear() * s.raw.linear().transpose());
    if (q.dot(first) < 0.0) q.coeffs() = -q.coeffs();
    sum += q.coeffs();
    raw_centroid += s.raw.translation();
    optimized_centroid += s.optimized.translation();
  }
  const double n = static_cast<double>(samples.size());
  out.linear() = Eigen::Quaterniond(sum.normalized()).toRotationMatrix();
  out.translation() = optimized_centroid / n - out.linear() * (raw_centroid / n);
  return out;
}

}  // namespace socc::consistency
