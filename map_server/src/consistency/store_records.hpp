#pragma once
// The records of the consistency store (keyframe_store.hpp, docs/consistency.md "Durability"):
// what the consistency service must keep to come back after a restart with the same keyframes
// and pose graph, and their byte encodings. A keyframe record carries the keyframe as the
// worker processed it (matching points, rebuild scan, its pose as integrated) with the graph
// elements added for it; a closure record an accepted closure edge; a rebuild record the poses
// a rebuilt grid put the scans at; a checkpoint record what the map's snapshot covered.
#include <Eigen/Geometry>
#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "keyframe.hpp"
#include "place_recognition.hpp"
#include "pose_graph.hpp"

namespace socc::consistency {

enum class RecordType : std::uint8_t {
  kKeyframe = 1,
  kClosure = 2,
  kRebuild = 3,
  kCheckpoint = 4,
  kWaiting = 5,
};

struct StoredKeyframe {
  std::string robot;
  Keyframe keyframe;  // without its descriptor (recomputed from the points); with gravity
  Eigen::Isometry3d estimate = Eigen::Isometry3d::Identity();  // the node's pose when added
  std::vector<PoseEdge> edges;    // the graph's edges added with the node
  std::vector<PosePrior> priors;  // and its priors
};

/// What a waiting keyframe's record holds of its scan (one byte; 0 and 1 are those of the
/// stores written before reduction on arrival, which read as they did).
enum class WaitingForm : std::uint8_t {
  kPoseOnly = 0,  // no scan (stores before reduction on arrival: the worker was far behind)
  kCloud = 1,     // the cloud as observed
  kReduced = 2,   // reduced on arrival (keyframe_reduction.hpp): the keyframe's points and scan
};

/// A keyframe observed but not yet processed (written with a checkpoint mark, before the
/// snapshot cuts the journal that holds its integration).
struct StoredWaiting {
  std::string robot;
  // robot, robot_kf, seq, utime, odom_pose, travelled, gravity; points and scan when kReduced.
  Keyframe keyframe;
  WaitingForm form = WaitingForm::kPoseOnly;
  LabeledCloud cloud;  // kCloud: points and labels as observed (no times)
};

struct StoredClosure {
  Closure closure;
  PoseEdge edge;  // as added to the graph
};

struct StoredRebuild {
  int serial = 0;                        // 1 for the service's first rebuild
  std::vector<Eigen::Isometry3d> poses;  // keyframe id -> its scan's pose in the grid
  std::map<std::string, Eigen::Isometry3d> corrections;  // RebuiltGrid::corrections
};

/// Written when the map checkpoints: the snapshot at (journal_sequence, map_version) holds the
/// integrations of `observed` keyframes and the rebuilt grid grid_serial (0: none).
struct StoredCheckpoint {
  std::int64_t journal_sequence = 0;
  std::int64_t map_version = 0;
  std::int64_t observed = 0;
  int grid_serial = 0;
};

std::string encodeKeyframe(const StoredKeyframe& record);
std::string encodeClosure(const StoredClosure& record);
std::string encodeRebuild(const StoredRebuild& record);
std::string encodeCheckpoint(const StoredCheckpoint& record);
std::string encodeWaiting(const StoredWaiting& record);

/// Each throws std::runtime_error when payload is not exactly one such record.
StoredKeyframe decodeKeyframe(const std::string& payload);
StoredClosure decodeClosure(const std::string& payload);
StoredRebuild decodeRebuild(const std::string& payload);
StoredCheckpoint decodeCheckpoint(const std::string& payload);
StoredWaiting decodeWaiting(const std::string& payload);

}  // namespace socc::consistency
