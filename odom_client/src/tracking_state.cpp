#include "socc/odom/tracking_state.hpp"

#include <algorithm>
#include <cctype>

#include "socc/robot_status_request_t.hpp"
#include "socc/rpc/status_names.hpp"

namespace socc::odom {

std::int8_t toWire(TrackingState state) {
  switch (state) {
    case TrackingState::kDegraded:
      return robot_status_request_t::DEGRADED;
    case TrackingState::kLost:
      return robot_status_request_t::LOST;
    case TrackingState::kTracking:
      break;
  }
  return robot_status_request_t::TRACKING;
}

std::string trackingStateName(TrackingState state) {
  std::string name = rpc::trackingStateName(toWire(state));
  std::transform(name.begin(), name.end(), name.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return name;
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
