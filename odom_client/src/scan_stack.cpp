#include "socc/odom/scan_stack.hpp"

#include <utility>

namespace socc::odom {

ScanStack::ScanStack(const OdomConfig& config, std::size_t max_scans)
    : config_(config), frames_(max_scans) {}

void ScanStack::restart() {
  odometry_.emplace(config_, Eigen::Isometry3d::Identity());
  frames_.clear();
}

bool ScanStack::add(const PreparedScan& scan) {
  restarted_ = false;
  if (!odometry_) restart();
  FrameEstimate estimate = odometry_->registerFrame(scan, frames_.target());
  if (std::optional<FrameEstimate> first = odometry_->takeReleasedFrame()) frames_.push(*first);
  if (estimate.held) return true;
  if (!estimate.health.healthy()) {
    restart();
    restarted_ = true;
    FrameEstimate fresh = odometry_->registerFrame(scan, LocalMap());
    if (!fresh.held) frames_.push(fresh);
    return false;
  }
  frames_.push(estimate);
  return true;
}

PreparedScan ScanStack::cloud() const {
  return frames_.stacked(frames_.size(), config_.deskew_reference_time);
}

}  // namespace socc::odom
