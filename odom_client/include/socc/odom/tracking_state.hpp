#pragma once
// Whether a robot still knows where it is: a run of unhealthy frames makes it lost, and a lost
// robot never writes into the shared map again in this run (only relocalization could bring it
// back: its odometry may have drifted anywhere while the frames were unhealthy).
#include <cstdint>
#include <string>

namespace socc::odom {

enum class TrackingState { kTracking, kDegraded, kLost };

/// The robot_status_request_t code of a state (DEGRADED: unhealthy frames, not lost yet).
std::int8_t toWire(TrackingState state);
/// socc::rpc::trackingStateName of the wire code in lower case, for logs: "tracking", "lost".
std::string trackingStateName(TrackingState state);

class TrackingMonitor {
 public:
  explicit TrackingMonitor(int max_unhealthy_frames) : max_unhealthy_(max_unhealthy_frames) {}

  /// Feeds one frame's verdict and returns the new state.
  TrackingState update(bool healthy);
  /// Lost on other evidence (the server refused a frame as implausible).
  void lose() { state_ = TrackingState::kLost; }
  TrackingState state() const { return state_; }
  int unhealthyInARow() const { return in_a_row_; }

 private:
  int max_unhealthy_;
  int in_a_row_ = 0;
  TrackingState state_ = TrackingState::kTracking;
};

}  // namespace socc::odom
