#pragma once
// The consistency service of map_server (docs/consistency.md): keyframes of every robot's
// integrations, place recognition between them (revisits and encounters, each verified), and a
// pose graph over all keyframes optimized after each verified closure. It runs beside the map
// on its own thread: observe() only decides whether an integration is a keyframe and copies its
// points (or, while the worker is max_pending_scans behind, reduces them to what the worker
// keeps); downsampling, descriptors, verification and optimization happen in the background.
//
// It corrects the estimate of every keyframe (and, through them, of every integration:
// corrected()) and, after a closure that moves keyframes, rebuilds the grid from the keyframe
// scans at their optimized poses on its thread; the map service swaps it in (takeRebuild).
// With a store (keyframe_store.hpp) every keyframe, accepted closure and rebuild is recorded
// as the worker makes it, and a service started from the store's contents goes on with the
// same keyframes and graph (consistency_restore.cpp).
#include <Eigen/Geometry>
#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <deque>
#include <filesystem>
#include <limits>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <thread>
#include <utility>
#include <vector>

#include "consistency_params.hpp"
#include "grid_rebuild.hpp"
#include "keyframe.hpp"
#include "keyframe_reduction.hpp"
#include "keyframe_store.hpp"
#include "odometry_edge.hpp"
#include "place_recognition.hpp"
#include "pose_graph.hpp"
#include "socc/map/map_config.hpp"
#include "socc/odom/odom_config.hpp"
#include "socc/point_cloud.hpp"

namespace socc::consistency {

struct ConsistencyStats {
  int robots = 0;
  int keyframes = 0;
  int pending = 0;         // keyframes waiting for the worker
  int pending_clouds = 0;  // of them, with their full cloud (at most max_pending_scans)
  // Keyframes whose cloud the map's thread reduced on arrival (keyframe_reduction.hpp): the
  // worker was max_pending_scans behind.
  int scans_reduced_on_arrival = 0;
  int gravity_keyframes = 0;  // keyframes whose INTEGRATE carried a gravity reference
  RecognitionTally recognition;
  OdometryEdgeTally odometry_edges;  // scan-to-scan checks of the odometry edges
  int optimizations = 0;
  double last_optimization_s = 0.0;
  double max_correction_s = 0.0;  // keyframe arrival to its closure's optimized poses
  std::size_t keyframe_bytes = 0;
  std::size_t scan_bytes = 0;  // of that, the scans kept to rebuild the grid
  int rebuilds = 0;            // grids rebuilt (each swapped in unless a newer one replaced it)
  double max_rebuild_s = 0.0;  // the worker's longest rebuild
  int rebuild_keyframes = 0;   // scans in the longest rebuild
  double rebuild_s = 0.0;      // the worker's time in rebuilds, summed
  long rebuild_scans = 0;      // scans integrated by rebuilds, summed
  // What the worker keeps for region rebuilds: the keyframes' part of the last rebuild (its
  // grid's memory_bytes) and their footprints, on top of the map's own grid.
  std::size_t base_bytes = 0;
  double travelled = 0.0;  // [m] sum over robots
};

class ConsistencyService {
 public:
  /// store: where every keyframe, closure and rebuild is recorded (null: nowhere). restored:
  /// the state to start from (a store's contents read back), with grid_serial the rebuild whose
  /// grid the map holds (0: none); docs/consistency.md, "Durability".
  ConsistencyService(const ConsistencyParams& params, const map::MapConfig& map_config,
                     const odom::OdomConfig& odom_config = {},
                     std::unique_ptr<KeyframeStore> store = nullptr,
                     const StoreContents* restored = nullptr, int grid_serial = 0);
  ~ConsistencyService();
  ConsistencyService(const ConsistencyService&) = delete;
  ConsistencyService& operator=(const ConsistencyService&) = delete;

  /// An applied integration of robot: a keyframe when it moved far enough since its last one.
  /// gravity: the up direction the integration carried (gravity_reference.hpp), if any.
  /// One thread observes (the map's; also checkpoint() and takeRebuild()).
  void observe(const std::string& robot, std::int64_t seq, std::int64_t utime,
               const Eigen::Isometry3d& pose, const LabeledCloud& cloud,
               const std::optional<GravityReference>& gravity = std::nullopt);

  /// Blocks until every observed keyframe is processed (tests, the benchmark, shutdown).
  void flush();

  /// pose (robot's integration at seq) moved by the correction of the robot's keyframes around
  /// seq; pose unchanged before the robot's first keyframe or for unknown robots.
  Eigen::Isometry3d corrected(const std::string& robot, std::int64_t seq,
                              const Eigen::Isometry3d& pose) const;

  /// The grid rebuilt after the last correcting closure, once, with the keyframes observed
  /// while it was built integrated into it (on the caller's thread: a few at most); null when
  /// none is ready. The caller swaps it in and tells each robot its correction.
  std::unique_ptr<RebuiltGrid> takeRebuild();

  /// Records in the store that the map's snapshot at (journal_sequence, map_version) holds
  /// every keyframe observed so far and the last grid taken (call before writing it). The
  /// keyframes the worker has not stored yet are written first, as observed: once the snapshot
  /// cuts the journal they are nowhere else.
  void checkpoint(std::int64_t journal_sequence, std::int64_t map_version);

  /// Holds the worker before its next keyframe (on) or lets it go on (tests: a kill while
  /// keyframes wait for it).
  void hold(bool on);

  ConsistencyStats stats() const;
  std::vector<Closure> closures() const;

  struct KeyframePose {
    std::string robot;
    std::int64_t seq = 0;
    Eigen::Isometry3d odom_pose = Eigen::Isometry3d::Identity();
    Eigen::Isometry3d optimized = Eigen::Isometry3d::Identity();
    std::int64_t utime = 0;
  };
  std::vector<KeyframePose> keyframePoses() const;
  /// robot's keyframes in the graph with seq >= from_seq, in seq order, at most max of them
  /// (truncated: more follow); empty for an unknown robot. optimized is in the graph's frame:
  /// the frame the first robot's first keyframe holds, in which the grid is rebuilt.
  std::vector<KeyframePose> robotKeyframes(const std::string& robot, std::int64_t from_seq,
                                           std::size_t max, bool* truncated) const;
  /// Keyframes of any robot observed but not yet processed: queued, or the one the worker is on
  /// (its search, optimization and rebuild).
  int unprocessed() const;
  /// The robot whose first keyframe is fixed in the graph (empty before the first keyframe).
  std::string anchorRobot() const;

  /// Writes keyframes.txt (robot seq odom[12] optimized[12]), closures.txt (robot seq robot seq
  /// relative[12] fitness free), odometry_edges.txt (robot seq registered snap jump_t jump_r
  /// seconds, and when registered the scan-to-scan relative pose[12]: the check of the edge to
  /// that keyframe) and stats.txt into dir.
  void write(const std::filesystem::path& dir) const;

 private:
  struct Pending {
    Keyframe keyframe;
    // What the worker makes the keyframe's points and scan from: its full cloud or, when
    // max_pending_scans clouds waited on arrival, the cloud reduced then. Neither: a pose only
    // (a waiting keyframe of a store written before reduction on arrival).
    std::shared_ptr<const LabeledCloud> cloud;
    std::shared_ptr<const ReducedScan> reduced;
    std::string robot;
    std::chrono::steady_clock::time_point arrived;
    bool stored = false;  // written to the store as waiting (checkpoint)
  };
  struct RobotTrack {
    int index = 0;
    std::optional<Eigen::Isometry3d> last_keyframe_pose;
    std::optional<Eigen::Isometry3d> last_pose;
    double travelled = 0.0;
    int keyframes = 0;
    double next_attempt_travel = 0.0;  // closure_spacing after the last closure
    std::vector<int> keyframe_ids;     // filled by the worker
    std::vector<std::int64_t> keyframe_seqs;
    // The relative pose of the odometry edge into the last keyframe, as the graph measures it
    // (none before the second keyframe): the motion the next edge's check continues.
    std::optional<Eigen::Isometry3d> last_motion;
    // Restored from the store: integrations up to this seq are in it (a journal replay shows
    // them again).
    std::int64_t restored_seq = std::numeric_limits<std::int64_t>::min();
  };

  /// Whether robot's integration at (seq, pose) is a keyframe (its fields but the scan's into
  /// keyframe); counts its path either way. Under the lock.
  bool isKeyframe(const std::string& robot, std::int64_t seq, const Eigen::Isometry3d& pose,
                  Keyframe& keyframe);
  void run();
  void process(Pending pending);
  /// odometry: the edge from the robot's previous keyframe (none for its first).
  void addToGraph(const Keyframe& keyframe, RobotTrack& track,
                  const std::optional<PoseEdge>& odometry);
  /// kf's gravity prior, when it has a reference and the priors are on; true when added.
  bool addGravityPrior(const Keyframe& kf);
  /// The odometry edge from the robot's previous keyframe to kf (scan to scan where it snapped;
  /// snap: whether it did).
  std::optional<PoseEdge> measureOdometry(const Keyframe& kf, const std::string& robot, bool& snap);
  /// The closure attempt of a snapped keyframe (query, its odometry edge at edge_index measured
  /// scan to scan), made at once: when it does not close, the edge goes back to the integrated
  /// relative pose of its two keyframes.
  std::optional<std::pair<Closure, PoseEdge>> closeSnap(
      int query, std::size_t edge_index, const std::string& robot, double travelled,
      std::chrono::steady_clock::time_point arrived);
  /// A verified closure of keyframe query, added to the graph (the estimates updated, the
  /// robot's next attempt spaced) when it is consistent with it; counted either way.
  std::optional<std::pair<Closure, PoseEdge>> attemptClosure(
      int query, const std::string& robot, double travelled,
      std::chrono::steady_clock::time_point arrived);
  /// After a correcting closure: rebuilds the grid when a keyframe moved far enough.
  void maybeRebuild();
  /// The rebuild a closure made due, once no keyframe waits or it waited rebuild_max_wait.
  void rebuildWhenDue();
  void rebuild(double max_shift);
  /// The correction a rebuild tells the robot: fitted to its last correction_window metres of
  /// keyframes (correction_fit.hpp). Worker thread.
  Eigen::Isometry3d robotCorrection(const RobotTrack& track) const;
  struct TailScan {
    std::string robot;
    Eigen::Isometry3d raw_pose = Eigen::Isometry3d::Identity();
    std::shared_ptr<const LabeledCloud> cloud;   // compacted as the keyframe's scan is
    std::shared_ptr<const ReducedScan> reduced;  // or its scan already
  };
  /// A waiting keyframe's scan for the rebuild's tail (none for a pose only).
  static std::optional<TailScan> tailScan(const Pending& pending);
  /// tail's scans into grid at their robots' corrections.
  void integrateTail(RebuiltGrid& grid, const std::vector<TailScan>& tail) const;
  // Durability (consistency_restore.cpp): writing the store, and starting from its contents.
  /// The last keyframe with graph edges [first_edge, end_edge) and the priors from first_prior.
  void storeKeyframe(const std::string& robot, std::size_t first_edge, std::size_t end_edge,
                     std::size_t first_prior);
  void storeClosure(const Closure& closure, const PoseEdge& edge);
  void storeRebuild(const RebuiltGrid& grid);
  void restore(const StoreContents& contents, int grid_serial);
  void restoreKeyframe(const StoredKeyframe& stored);
  void restoreClosure(const StoredClosure& stored);
  void restoreGridPoses(const StoreContents& contents, int grid_serial);
  void restoreWaiting(const StoredWaiting& stored);
  /// The records of the keyframes observed but not yet stored by the worker (a checkpoint
  /// writes them); marks them stored.
  std::vector<std::pair<RecordType, std::string>> waitingRecords();

  ConsistencyParams params_;
  map::MapConfig map_config_;
  odom::OdomConfig odom_config_;

  mutable std::mutex mutex_;  // everything below
  std::condition_variable wake_;
  std::condition_variable idle_;
  std::deque<Pending> queue_;
  std::optional<Pending> in_flight_;  // taken by the worker, not yet in the store
  bool held_ = false;
  int pending_clouds_ = 0;  // entries of queue_ with their full cloud
  bool busy_ = false;
  bool stopping_ = false;
  std::map<std::string, RobotTrack> robots_;
  std::vector<std::string> robot_names_;
  std::vector<Keyframe> keyframes_;
  std::vector<Eigen::Isometry3d> estimates_;  // optimized keyframe poses
  PoseGraph graph_;  // the worker's alone (nodes added under the lock, optimized without)
  std::vector<Closure> closures_;
  std::vector<std::pair<int, OdometryEdgeCheck>> edge_checks_;  // keyframe: its edge's check
  ConsistencyStats stats_;
  // Map correction. While a rebuild runs or waits for takeRebuild, every keyframe observed
  // since it started (with those still queued then) is kept in tail_ for it.
  bool rebuilding_ = false;
  std::vector<TailScan> tail_;
  std::size_t tail_done_ = 0;  // tail_ entries the worker already integrated into ready_
  std::unique_ptr<RebuiltGrid> ready_;
  std::map<std::string, Eigen::Isometry3d> applied_;  // robot: raw -> grid of the last rebuild
  int grid_serial_ = 0;                   // the rebuild whose grid was last taken (0: none)
  std::unique_ptr<KeyframeStore> store_;  // null: not durable
  bool resume_rebuild_ = false;  // restored: the worker first rebuilds if the grid is behind
  // The worker's alone: since when a closure's rebuild waits (none: no rebuild due).
  std::optional<std::chrono::steady_clock::time_point> rebuild_due_;
  // The worker's alone: the keyframes' part of its last rebuild (none: the next one is whole).
  std::optional<KeyframeGrid> base_;

  std::thread worker_;  // last: started after everything it uses
};

}  // namespace socc::consistency
