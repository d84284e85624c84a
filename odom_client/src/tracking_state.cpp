#include "socc/odom/tracking_state.hpp"

namespace socc::odom {

const char* trackingStateName(TrackingState state) {
  switch (state) {
    case TrackingState::kTracking:
      return "tracking";
    case TrackingState::kDegraded:
      return "degraded";
    case TrackingState::kLost:
      return "lost";
  }
  return "unknown";
}

TrackingState TrackingMonitor::update(bool healthy) {
  if (state_ == TrackingState::kLost) return state_;
  in_a_row_ = healthy ? 0 : in_a_row_ + 1;
  if (in_a_row_ >= max_unhealthy_)
    state_ = TrackingState::kLost;
  else
    state_ = in_a_row_ > 0 ? TrackingState::kDegraded : TrackingState::kTracking;
  return state_;
}

}  // namespace socc::odom
