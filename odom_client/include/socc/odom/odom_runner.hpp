#pragma once
// The client pipeline against the map service, per scan:
//   prepare -> registration target (map_pipeline.hpp) -> register (deskew iterated, health
//   judged) -> Integrate (in a worker thread, which then fetches the next chunk).
// Only healthy frames are integrated; after max_unhealthy_frames in a row the robot is lost and
// integrates nothing (the shared map is never fed a pose the robot does not trust) until it has
// found itself in the map again: it relocalizes (relocalization.hpp) near its last good pose
// first, anywhere after half of relocalize_timeout, and resumes there; a search that outlasts
// relocalize_timeout ends the run LOST. With --own-frame a robot without a pose maps in its own
// frame (OwnFrameMap, odom_runner_own_frame.cpp), integrating nothing, until its search finds
// the shared map; then its kept scans are integrated there and it goes on as any robot.
// Stateless between frames apart from the odometry state: no map is kept beyond one chunk and
// the voxels of the last frame.
#include <Eigen/Geometry>
#include <atomic>
#include <chrono>
#include <cstdint>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "socc/kitti_io.hpp"
#include "socc/odom/frame_log.hpp"
#include "socc/odom/kept_place_sweep.hpp"
#include "socc/odom/map_pipeline.hpp"
#include "socc/odom/odom_config.hpp"
#include "socc/odom/odometry.hpp"
#include "socc/odom/own_frame_map.hpp"
#include "socc/odom/relocalization.hpp"
#include "socc/odom/relocalizer.hpp"
#include "socc/odom/scan_source.hpp"
#include "socc/odom/shared_map_search.hpp"
#include "socc/odom/tracking_state.hpp"
#include "socc/rpc/map_client.hpp"
#include "socc/trajectory_revision.hpp"

namespace socc::odom {

struct RunOptions {
  Eigen::Isometry3d initial_pose = Eigen::Isometry3d::Identity();  // map frame, first scan
  bool initial_pose_known = false;   // given by the user (--initial-pose): see Odometry
  std::int64_t skip_until_seq = -1;  // scans with seq <= this were integrated before (--resume)
  // --relocalize: the first pose is searched in the map (relocalization.hpp), narrowed by hint.
  // (A robot that gets lost searches again in any case.)
  bool relocalize = false;
  std::optional<PoseHint> hint;
  // --own-frame (without an initial pose): maps in its own frame from the first scan and keeps
  // searching the shared map; merged into it when found (docs/relocalization.md "Own frame").
  bool own_frame = false;
  // --found-map (with own_frame): on an empty server the robot founds the map, its own frame the
  // map frame (docs/relocalization.md "Founding an empty map").
  bool found_map = false;
  bool progress = true;
  const std::atomic<bool>* stop = nullptr;  // set (e.g. by SIGINT) to end after the current frame
};

using socc::Trajectory;  // poses: map_T_sensor per processed scan, with its stamp and seq

/// The robot found no pose in the map within relocalize_timeout (odom_client exits 4).
class RelocalizationFailed : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// A frame's registration numbers and health into its row.
void addHealth(const FrameEstimate& e, FrameStats& stats);

class OdomRunner {
 public:
  OdomRunner(const OdomConfig& config, rpc::MapClient& client, RunOptions options);

  /// Processes scans until the source ends (or stop is set). Throws std::runtime_error when the
  /// map service fails (after MapClient's retries) or returns a malformed chunk, and
  /// RelocalizationFailed when a search outlasts relocalize_timeout; the trajectory up to that
  /// point stays available through trajectory().
  void run(ScanSource& source, FrameLog& log);

  const Trajectory& trajectory() const { return trajectory_; }
  double wallSeconds() const { return wall_seconds_; }
  /// Chunks fetched twice because the first one predated the previous frame's Integrate.
  std::int64_t refetchedChunks() const { return pipeline_ ? pipeline_->refetchedChunks() : 0; }
  /// Chunks held for the robot's next Integrate reply (MapPipeline::heldChunks).
  std::int64_t heldChunks() const { return pipeline_ ? pipeline_->heldChunks() : 0; }
  TrackingState trackingState() const { return tracking_.state(); }
  /// Scans localized in the map by relocalization (the first, and each recovery).
  int relocalizations() const { return relocalizations_; }
  /// Map corrections applied (docs/consistency.md): the pose output jumps at each.
  int corrections() const { return static_cast<int>(applied_.size()); }
  /// Those corrections, each with the first trajectory() seq it moved (reviseTrajectory).
  const std::vector<FrameCorrection>& appliedCorrections() const { return applied_; }
  /// --own-frame: the run ended before the robot was merged into the shared map; trajectory()
  /// then holds own-frame poses (identity at its first scan) and nothing was integrated.
  bool endedInOwnFrame() const { return own_.has_value(); }
  /// The lasers the per-laser range calibration corrected, as it stood at the end of run()
  /// (empty when off, or when run() threw).
  const std::vector<RangeCalibration::Laser>& rangeCalibration() const { return range_lasers_; }

 private:
  /// One prepared scan through the pipeline; its stats.
  FrameStats processScan(Odometry& odometry, const PreparedScan& scan,
                         std::chrono::steady_clock::time_point start);
  /// Searches the scan's pose in the map; on success restarts odometry there. False while the
  /// robot is still unlocalized (the scan is logged, not integrated).
  bool relocalize(Odometry& odometry, const PreparedScan& scan);
  void startRelocalizing(std::int64_t utime);
  /// Odometry's SurpriseCheck: the map service's free-space check of the frame (LOCALIZE check
  /// mode); more than relocalize_max_free of its points where the map saw free space contradicts
  /// it.
  void watch(Odometry& odometry);
  std::string contradictsMap(const FrameEstimate& frame);
  /// The server refused a frame as implausible: lost, recovery from the next scan.
  void refused(const PreparedScan& scan, const std::string& why);
  /// A lost robot starts searching from the next scan, near its last good pose first.
  void startRecovery(const FrameEstimate& frame);
  /// The search outlasted relocalize_timeout: a first search throws RelocalizationFailed, a
  /// recovery ends the run LOST.
  void giveUp(const PreparedScan& scan, double searched, const std::string& problem);
  /// Judges, records and (when healthy and not lost) integrates one finished frame; ahead: see
  /// MapPipeline::integrate.
  void submit(Odometry& odometry, FrameEstimate estimate, FrameStats stats,
              const Eigen::Vector3d& ahead);
  /// Applies a map correction the pipeline received to the odometry and the last good pose and
  /// returns it; the next submitted frame's row says how far the pose output jumped.
  std::optional<Eigen::Isometry3d> applyCorrection(Odometry& odometry);
  void reportTracking(TrackingState state, const FrameEstimate& frame);
  // --own-frame (odom_runner_own_frame.cpp).
  void startOwnFrame(Odometry& odometry, const PreparedScan& scan);
  /// Registers a scan against the own-frame map, keeps it, searches the shared map when due.
  void ownFrameScan(Odometry& odometry, const PreparedScan& scan,
                    std::chrono::steady_clock::time_point start);
  /// Adds a registered own-frame frame to the trajectory and, when healthy, to the own map.
  bool keepOwnFrame(const FrameEstimate& frame, FrameStats& stats);
  bool ownSearchDue(std::int64_t utime) const;
  /// The shared-map search at frame newest: merges when a finished search found the map, else
  /// starts the next one when due; only at a kept (trusted) frame. The search's verdict.
  std::string followSearch(Odometry& odometry, const FrameEstimate& newest, bool kept);
  /// The next search: every other one (after relocalize_timeout) looks back at a kept place.
  void launchSearch(const FrameEstimate& newest);
  void launchForward(const FrameEstimate& newest, const std::optional<PoseHint>& hint);
  /// A kept place was found looking back: the next searches look for the newest place near
  /// where it puts it (kept_place_checks_ of them at most); the row's verdict.
  std::string holdKeptPlace(const SearchOutcome& found);
  PoseHint nearKeptPlace(const FrameEstimate& newest) const;
  /// Own-frame path travelled since the scan seq [m].
  double ownPathSince(std::int64_t seq) const;
  /// A finished search's verdict for the frame's row.
  std::string verdictText(const SearchOutcome& done) const;
  /// Starts the sweep's next search of a kept place; false when there is none.
  bool launchLookBack();
  void startLookBack(KeptPlaceSearch search);
  bool ownSearchRunning() const;
  /// The finished search (forward or look back), waiting for it when wait is set.
  std::optional<SearchOutcome> ownSearchOutcome(bool wait);
  /// At the end of the input: waits for a running search, then looks back over the whole kept
  /// path once; merges on the first success.
  void finishOwnSearch(Odometry& odometry);
  std::optional<SearchOutcome> lookBackOnce();
  /// Integrates the kept scans (newest last) where the search placed them, bridged from the kept
  /// place found looking back if there is one (FrameBridge); shared from here on.
  void mergeOwnFrame(Odometry& odometry, const OwnKeyframe& newest, const SearchOutcome& search,
                     const std::optional<SearchOutcome>& kept_place);
  /// --found-map: the first kept scan founds the map (integrate_request_t::FOUND_MAP) and the
  /// robot goes on in it, its own frame the map frame; false when the map was not empty.
  bool foundSharedMap(Odometry& odometry, const FrameEstimate& newest);
  /// The kept scans (newest last) integrated in the shared frame through bridge (map instance
  /// epoch), the own-frame rows and the odometry moved by shared_T_own: tracking from here on.
  void joinSharedMap(Odometry& odometry, const OwnKeyframe& newest, const FrameBridge& bridge,
                     const Eigen::Isometry3d& shared_T_own, std::int64_t epoch);
  /// The own frame's move from the kept place's placement to shared_T_own at seq.
  FrameBridge bridgeTo(const SearchOutcome& kept_place, std::int64_t seq,
                       const Eigen::Isometry3d& shared_T_own) const;
  /// A kept scan at its merged pose, in the frame of map instance epoch (the place found).
  void integrateKept(const OwnKeyframe& keyframe, std::int64_t epoch);
  void sendStatus(std::int8_t wire, const std::string& reason, std::int64_t seq,
                  std::int64_t utime);

  OdomConfig config_;
  rpc::MapClient& client_;
  RunOptions options_;
  FrameLog* log_ = nullptr;
  TrackingMonitor tracking_;
  std::optional<MapPipeline> pipeline_;  // during run()
  Trajectory trajectory_;
  double wall_seconds_ = 0.0;
  bool localized_ = true;
  bool recovering_ = false;  // the current search follows LOST (else: --relocalize's first)
  bool gave_up_ = false;     // a recovery outlasted relocalize_timeout: the run ends LOST
  std::int64_t search_since_utime_ = -1;        // scan time the current search began; -1: not yet
  std::optional<Relocalizer> search_;           // the current search's scans and places
  std::optional<PoseHint> hint_;                // for the next search only
  std::optional<Eigen::Isometry3d> last_good_;  // pose of the last integrated frame
  int relocalizations_ = 0;
  std::vector<FrameCorrection> applied_;
  std::vector<RangeCalibration::Laser> range_lasers_;  // rangeCalibration()
  std::string jump_;  // the last correction, for the next frame's row
  // --own-frame, until the merge.
  std::optional<OwnFrameMap> own_;
  std::optional<SharedMapSearch> own_search_;     // the newest scans'
  std::optional<SharedMapSearch> own_look_back_;  // the kept scans' (a new one per sweep)
  std::optional<KeptPlaceSweep> own_sweep_;       // none: own_frame_look_back off
  bool found_tried_ = false;                      // --found-map: the founding INTEGRATE was sent
  bool look_back_next_ = false;
  bool look_back_in_map_ = false;  // the last look back's best place explained enough of it
  std::optional<SearchOutcome> kept_place_;  // found looking back, the newest place not yet
  int kept_place_checks_ = 0;                // searches near it that did not find the newest
  bool live_input_ = false;  // searches beside the scan loop; file input waits for each answer
  std::size_t own_rows_begin_ = 0;        // first trajectory row in the own frame
  std::int64_t own_since_utime_ = -1;     // scan time it began mapping in its own frame
  std::int64_t own_searched_utime_ = -1;  // scan time of the last search
  Eigen::Isometry3d own_searched_pose_ = Eigen::Isometry3d::Identity();  // own pose then
};

}  // namespace socc::odom
