#pragma once
// The registration target of each frame and the frames' way into the map (odom_client/README.md
// "Pipeline").
//
// Serial, each frame waits for the server: Integrate of frame k-1, then the chunk around frame
// k (query, encode, send, decode, search tree). Pipelined, frame k registers against the last
// chunk the worker fetched plus the own voxels of the frames integrated since (frame k-1 back to
// at most chunk_interval frames) that the chunk lacks (with the first points the server keeps for
// them), while the worker sends frame k-1's Integrate and, with every chunk_interval-th one,
// fetches the chunk after it and builds its tree. The server and the client work at the same time.
// Voxels of few points come with their moments (FIELD_MOMENTS), and the frames' points are merged
// into them as the server merges them: a sparse sensor's voxels get and refine their normals when
// they would in the serial target. The target differs from the serial one only in the features of
// voxels of many points that those frames hit again, and in occupancies and labels. Soft state:
// dropping it loses nothing, the next frame then fetches its chunk itself (the first frame, after a
// jump).
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <atomic>
#include <cstdint>
#include <future>
#include <memory>
#include <optional>
#include <vector>

#include "socc/odom/chunk_cache.hpp"
#include "socc/odom/chunk_frame_gate.hpp"
#include "socc/odom/frame_log.hpp"
#include "socc/odom/local_map.hpp"
#include "socc/odom/odom_config.hpp"
#include "socc/odom/odometry.hpp"
#include "socc/rpc/map_client.hpp"

namespace socc::odom {

/// The server refused a frame's Integrate as implausible (FAILED_PRECONDITION: a pose no robot
/// can reach from its last accepted one in the time between the scans, plausibility.hpp): the
/// robot has lost track although its registration looked good.
class IntegrateRefused : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

class MapPipeline {
 public:
  /// Rows of integrated frames go to log once the server has answered their Integrate.
  MapPipeline(rpc::MapClient& client, const OdomConfig& config, FrameLog& log);
  ~MapPipeline();
  MapPipeline(const MapPipeline&) = delete;
  MapPipeline& operator=(const MapPipeline&) = delete;

  /// The registration target of a frame at center. Throws std::runtime_error when the service
  /// fails (after MapClient's retries), std::invalid_argument on a malformed chunk.
  LocalMap target(const Eigen::Vector3d& center, FrameStats& stats);

  /// Sends a healthy frame's Integrate (in the worker); ahead is where the frame that will use
  /// the chunk fetched after it is expected (two frames on).
  void integrate(FrameEstimate estimate, const FrameStats& stats, const Eigen::Vector3d& ahead);

  /// Waits for the Integrate in flight and logs its frame; returns the map version it produced
  /// (-1 when none was in flight). Throws IntegrateRefused when the server refused it as
  /// implausible, std::runtime_error when it failed otherwise (target() and integrate() call
  /// it too).
  std::int64_t finish();

  /// finish() at the end of the run: a chunk the worker has not asked for yet is not fetched
  /// (no frame would register against it).
  void close();

  /// The map correction an Integrate reply brought (docs/consistency.md), once: the caller
  /// applies it to its odometry. Until then every frame integrate() sends is moved by it (it
  /// was registered in the old frame), and the cached chunks were dropped when it arrived.
  std::optional<Eigen::Isometry3d> takeCorrection();

  /// Chunks fetched twice because the first one predated the previous frame's Integrate.
  std::int64_t refetchedChunks() const { return refetched_chunks_; }
  /// Chunks of a grid swapped in by another robot's Integrate, held until this robot's next
  /// Integrate reply (ChunkFrameGate).
  std::int64_t heldChunks() const { return held_chunks_; }

 private:
  struct Exchange {  // what the worker brings back
    rpc::Result<integrate_reply_t> integrate;
    double integrate_ms = 0.0;
    std::int64_t bytes_sent = 0;
    std::optional<LocalMap> chunk;  // none: not asked for, or the service failed (soft state)
    std::int64_t chunk_version = 0;
    Eigen::Vector3d center = Eigen::Vector3d::Zero();
    std::int64_t chunk_bytes = 0;
    double chunk_ms = 0.0;
  };
  struct InFlight {
    std::future<Exchange> reply;
    FrameStats stats;
  };
  struct Overlaid {  // a chunk's overlay and updated voxels, and the chunk with them
    std::vector<MapVoxel> overlay;
    VoxelUpdates updated;
    LocalMap map;
  };
  struct Target {  // the last chunk, with the voxels of the integrated frames after it
    LocalMap chunk;
    LocalMap map;  // chunk with overlay: the next frame's target
    Eigen::Vector3d center;
    std::int64_t bytes = 0;  // of the chunk, until a frame reported them
    double chunk_ms = 0.0;
    std::vector<MapVoxel> overlay;
    VoxelUpdates updated;           // chunk voxels of few points that the frames hit again
    std::future<Overlaid> pending;  // with the last frame's voxels; not valid: none
  };

  LocalMap fetchNow(const Eigen::Vector3d& center, FrameStats& stats);
  void startOverlay(std::shared_ptr<const FrameEstimate> frame);  // target_->pending
  /// The next target after an Integrate reply: a chunk held since the last one, else none;
  /// the exchange's own chunk when it is in the robot's frame, else held in turn.
  std::optional<Target> nextTarget(Exchange& x);
  /// In the worker: the frame's Integrate (its pose in the frame of map instance epoch), then
  /// (when fetch_at) the chunk around fetch_at.
  Exchange exchange(const FrameEstimate& frame, std::int64_t epoch,
                    const std::optional<Eigen::Vector3d>& fetch_at);
  rpc::Result<chunk_reply_t> fetchChunk(const Eigen::Vector3d& center);
  bool covers(const Target& target, const Eigen::Vector3d& center) const;

  rpc::MapClient& client_;
  const OdomConfig& config_;
  FrameLog& log_;
  std::optional<InFlight> in_flight_;
  std::atomic<bool> closing_{false};  // set by close(), read by the worker
  std::optional<Target> target_;
  std::optional<Target> held_;  // a chunk of a grid the robot may not be in yet (ChunkFrameGate)
  ChunkFrameGate frame_gate_;
  std::int64_t integrates_ = 0;
  ChunkCache cache_;  // the worker's (delta_chunks)
  std::int64_t refetched_chunks_ = 0;
  std::int64_t held_chunks_ = 0;
  std::optional<Eigen::Isometry3d> correction_;  // received, not taken yet
  // The map instance whose frame the next frame's pose is in (integrate_request_t::map_epoch):
  // of the target it registered against, or of the reply whose correction moved it.
  std::int64_t pose_epoch_ = 0;
};

}  // namespace socc::odom
