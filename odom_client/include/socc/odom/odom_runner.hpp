#pragma once
// The client pipeline against the map service, per scan:
//   preprocess -> GET_CHUNK around the prediction -> (previous Integrate ack) -> LocalMap ->
//   register -> Integrate (asynchronous, in a worker thread).
// The next scan is preprocessed while the previous Integrate is in flight, and its GET_CHUNK is
// queued behind that Integrate on the single-threaded server without waiting for the ack; a
// chunk whose map version predates the Integrate's is fetched again.
// Stateless between frames apart from the odometry state: no map is kept beyond one chunk.
#include <Eigen/Geometry>
#include <atomic>
#include <cstdint>
#include <string>
#include <vector>

#include "socc/odom/frame_log.hpp"
#include "socc/odom/odom_config.hpp"
#include "socc/odom/scan_source.hpp"
#include "socc/rpc/map_client.hpp"

namespace socc::odom {

struct RunOptions {
  Eigen::Isometry3d initial_pose = Eigen::Isometry3d::Identity();  // map frame, first scan
  bool initial_pose_known = false;   // given by the user (--initial-pose): see Odometry
  std::int64_t skip_until_seq = -1;  // scans with seq <= this were integrated before (--resume)
  bool progress = true;
  const std::atomic<bool>* stop = nullptr;  // set (e.g. by SIGINT) to end after the current frame
};

struct Trajectory {
  std::vector<std::int64_t> seqs;
  std::vector<double> stamps;            // [s]
  std::vector<Eigen::Isometry3d> poses;  // map_T_sensor
};

class OdomRunner {
 public:
  OdomRunner(const OdomConfig& config, rpc::MapClient& client, RunOptions options);

  /// Processes scans until the source ends (or stop is set). Throws std::runtime_error when the
  /// map service fails (after MapClient's retries) or returns a malformed chunk; the trajectory
  /// up to that point stays available through trajectory().
  void run(ScanSource& source, FrameLog& log);

  const Trajectory& trajectory() const { return trajectory_; }
  double wallSeconds() const { return wall_seconds_; }
  /// Chunks fetched twice because the first one predated the previous frame's Integrate.
  std::int64_t refetchedChunks() const { return refetched_chunks_; }

 private:
  OdomConfig config_;
  rpc::MapClient& client_;
  RunOptions options_;
  Trajectory trajectory_;
  double wall_seconds_ = 0.0;
  std::int64_t refetched_chunks_ = 0;
};

}  // namespace socc::odom
