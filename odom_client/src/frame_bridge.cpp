#include "socc/odom/frame_bridge.hpp"

#include <algorithm>
#include <stdexcept>

#include "socc/pose_interpolation.hpp"

namespace socc::odom {

FrameBridge::FrameBridge(const Eigen::Isometry3d& shared_T_own)
    : from_(shared_T_own), to_(shared_T_own) {}

FrameBridge::FrameBridge(const std::vector<std::int64_t>& seqs,
                         const std::vector<Eigen::Vector3d>& positions, std::int64_t from_seq,
                         const Eigen::Isometry3d& from, std::int64_t to_seq,
                         const Eigen::Isometry3d& to)
    : seqs_(seqs), from_(from), to_(to), to_seq_(to_seq) {
  if (seqs.size() != positions.size() || seqs.empty() || from_seq > to_seq)
    throw std::invalid_argument("FrameBridge: one position per seq, from_seq <= to_seq");
  path_.assign(seqs.size(), 0.0);
  for (std::size_t i = 1; i < seqs.size(); ++i)
    path_[i] = path_[i - 1] + (positions[i] - positions[i - 1]).norm();
  from_path_ = pathAt(from_seq);
  to_path_ = pathAt(to_seq);
  const auto at_to = std::lower_bound(seqs_.begin(), seqs_.end(), to_seq);
  to_position_ = positions[static_cast<std::size_t>(
      std::min(at_to - seqs_.begin(), static_cast<std::ptrdiff_t>(seqs_.size()) - 1))];
}

double FrameBridge::pathAt(std::int64_t seq) const {
  // The scan at seq, or the last before it (a seq between rows: the path so far).
  const auto after = std::upper_bound(seqs_.begin(), seqs_.end(), seq);
  return after == seqs_.begin() ? 0.0 : path_[static_cast<std::size_t>(after - seqs_.begin()) - 1];
}

Eigen::Isometry3d FrameBridge::at(std::int64_t seq) const {
  if (seqs_.empty() || to_path_ <= from_path_) return seq < to_seq_ ? from_ : to_;
  const double s = std::clamp((pathAt(seq) - from_path_) / (to_path_ - from_path_), 0.0, 1.0);
  return interpolatePose(from_, to_, s);
}

double FrameBridge::bridgedDrift() const {
  return ((from_ * to_position_) - (to_ * to_position_)).norm();
}

}  // namespace socc::odom
