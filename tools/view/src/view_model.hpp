#pragma once
// socc-view's picture of the shared map and its robots, fed by the LCM side (LcmFeed) and read
// by the client sessions. Holds the map's occupied voxels block by block (as map_delta_t
// delivers them), each robot's pose, trajectory, latest scan and tracking state, and the
// server's latest stats. Thread-safe; listeners hear which parts changed (under the model's
// lock: they only note it and return).
#include <array>
#include <cstdint>
#include <functional>
#include <map>
#include <mutex>
#include <optional>
#include <string>
#include <unordered_map>
#include <vector>

#include "socc/integrate_request_t.hpp"
#include "socc/map_delta_t.hpp"
#include "socc/map_stats_t.hpp"

namespace socc::view {

using BlockKey = std::array<std::int32_t, 3>;

struct BlockKeyHash {
  std::size_t operator()(const BlockKey& k) const {
    return (static_cast<std::size_t>(static_cast<std::uint32_t>(k[0])) * 73856093u) ^
           (static_cast<std::size_t>(static_cast<std::uint32_t>(k[1])) * 19349663u) ^
           (static_cast<std::size_t>(static_cast<std::uint32_t>(k[2])) * 83492791u);
  }
};

/// One block's occupied voxels (map_delta_t's columns for that block).
struct BlockContent {
  std::vector<std::int16_t> local;
  std::vector<std::uint8_t> occupancy;
  std::vector<std::uint8_t> label;
};

struct RobotView {
  std::string id;
  std::array<double, 3> translation{};
  std::array<double, 4> quaternion{1, 0, 0, 0};  // w x y z
  std::int64_t last_seq = 0;
  std::int64_t integrations = 0;
  std::int64_t refused = 0;
  std::int8_t tracking_state = 0;
  std::string tracking_reason;
  std::vector<std::array<float, 3>> trajectory;  // map frame, one point per >= kTrajectoryStep
  std::vector<float> scan;                       // latest scan, map frame, x y z interleaved
  std::int64_t scan_seq = -1;
};

/// What changed, told to listeners.
struct ModelListener {
  virtual ~ModelListener() = default;
  virtual void mapReset() = 0;  // new epoch: forget every block and robot
  virtual void blocksChanged(const std::vector<BlockKey>& keys) = 0;
  virtual void robotsChanged() = 0;
  virtual void statsChanged() = 0;
};

class ViewModel {
 public:
  static constexpr double kTrajectoryStep = 0.25;        // [m] between kept trajectory points
  static constexpr std::size_t kMaxTrajectory = 200000;  // points per robot
  static constexpr std::size_t kMaxScanPoints = 4000;    // kept of each robot's latest scan
  static constexpr std::size_t kMaxRobots = 256;         // more ids (hostile senders) ignored

  /// Empty when applied, else why the message was refused (inconsistent counts).
  std::string applyDelta(const map_delta_t& delta);
  void applyStats(const map_stats_t& stats);
  /// A robot's INTEGRATE as sent (its pose and points): trajectory and latest scan.
  void applyIntegrate(const integrate_request_t& request);

  void addListener(ModelListener* listener);
  void removeListener(ModelListener* listener);

  // Readers: run f under the model's lock.
  template <typename F>
  auto read(F&& f) const {
    const std::lock_guard<std::mutex> lock(mutex_);
    return f(*this);
  }

  // Valid under read().
  std::int64_t epoch() const { return epoch_; }
  double voxelSize() const { return voxel_size_; }
  int blockDim() const { return block_dim_; }
  std::int64_t voxelCount() const { return voxel_count_; }
  const std::unordered_map<BlockKey, BlockContent, BlockKeyHash>& blocks() const { return blocks_; }
  const std::map<std::string, RobotView>& robots() const { return robots_; }
  const std::optional<map_stats_t>& stats() const { return stats_; }
  std::int64_t deltasReceived() const { return deltas_received_; }

 private:
  /// The robot's entry, created if there is room (nullptr when kMaxRobots are known).
  RobotView* robot(const std::string& id);
  static void extendTrajectory(RobotView& robot);

  mutable std::mutex mutex_;
  std::vector<ModelListener*> listeners_;
  std::int64_t epoch_ = 0;
  double voxel_size_ = 0.0;
  int block_dim_ = 8;
  std::int64_t voxel_count_ = 0;
  std::int64_t deltas_received_ = 0;
  std::unordered_map<BlockKey, BlockContent, BlockKeyHash> blocks_;
  std::map<std::string, RobotView> robots_;
  std::optional<map_stats_t> stats_;
};

}  // namespace socc::view
