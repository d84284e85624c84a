// The consistency service's durability (docs/consistency.md, "Durability"): every keyframe,
// accepted closure and rebuild goes to the store as the worker makes it, and a service started
// from the store's contents holds the same keyframes, graph and grid poses as the one that
// wrote it.
#include "consistency_restore.hpp"

#include <algorithm>
#include <map>
#include <stdexcept>

#include "consistency_service.hpp"

namespace socc::consistency {

std::vector<const StoredWaiting*> waitingKeyframes(const StoreContents& contents) {
  std::map<std::string, int> next;  // robot: its keyframes held so far
  for (const StoredKeyframe& k : contents.keyframes)
    next[k.robot] = std::max(next[k.robot], k.keyframe.robot_kf + 1);
  std::vector<const StoredWaiting*> out;
  for (const StoredWaiting& w : contents.waiting) {
    int& held = next[w.robot];
    if (w.keyframe.robot_kf < held) continue;  // processed since, or written at two marks
    held = w.keyframe.robot_kf + 1;
    out.push_back(&w);
  }
  return out;
}

const StoredCheckpoint* coveringMark(const StoreContents& contents, std::int64_t journal_sequence,
                                     std::int64_t map_version, std::string& problem) {
  const auto mark = std::find_if(
      contents.checkpoints.rbegin(), contents.checkpoints.rend(), [&](const StoredCheckpoint& c) {
        return c.journal_sequence == journal_sequence && c.map_version == map_version;
      });
  if (mark == contents.checkpoints.rend()) {
    problem = "it has no mark of the snapshot at journal sequence " +
              std::to_string(journal_sequence) + ", map version " + std::to_string(map_version);
    return nullptr;
  }
  const std::size_t held = contents.keyframes.size() + waitingKeyframes(contents).size();
  if (static_cast<std::int64_t>(held) < mark->observed) {
    problem = "it holds " + std::to_string(held) + " of the " + std::to_string(mark->observed) +
              " keyframes in the snapshot";
    return nullptr;
  }
  const bool rebuilt =
      std::any_of(contents.rebuilds.begin(), contents.rebuilds.end(),
                  [&](const StoredRebuild& r) { return r.serial == mark->grid_serial; });
  if (mark->grid_serial > 0 && !rebuilt) {
    problem = "it lacks rebuild " + std::to_string(mark->grid_serial) + ", the snapshot's grid";
    return nullptr;
  }
  return &*mark;
}

void ConsistencyService::checkpoint(std::int64_t journal_sequence, std::int64_t map_version) {
  if (!store_) return;
  // The waiting keyframes before the mark (a mark's keyframes are all in the store), written
  // with it in one synced append.
  std::vector<std::pair<RecordType, std::string>> records = waitingRecords();
  StoredCheckpoint mark;
  mark.journal_sequence = journal_sequence;
  mark.map_version = map_version;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    for (const auto& [name, track] : robots_) mark.observed += track.keyframes;
    mark.grid_serial = grid_serial_;
  }
  records.emplace_back(RecordType::kCheckpoint, encodeCheckpoint(mark));
  store_->add(records);
}

std::vector<std::pair<RecordType, std::string>> ConsistencyService::waitingRecords() {
  // The map's thread (as observe): no keyframe is observed meanwhile. The worker may store the
  // one it is processing at the same time; a restart keeps the first of the two.
  std::vector<Pending> waiting;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    if (in_flight_ && !in_flight_->stored) waiting.push_back(*in_flight_);
    if (in_flight_) in_flight_->stored = true;
    for (Pending& p : queue_) {
      if (!p.stored) waiting.push_back(p);
      p.stored = true;
    }
  }
  std::vector<std::pair<RecordType, std::string>> records;
  for (const Pending& p : waiting) {
    StoredWaiting record;
    record.robot = p.robot;
    record.keyframe = p.keyframe;
    if (p.cloud) {
      record.form = WaitingForm::kCloud;
      record.cloud.points = p.cloud->points;
      record.cloud.labels = p.cloud->labels;
    } else if (p.reduced) {
      record.form = WaitingForm::kReduced;
      record.keyframe.points = p.reduced->points;
      record.keyframe.scan = p.reduced->scan;
    }
    records.emplace_back(RecordType::kWaiting, encodeWaiting(record));
  }
  return records;
}

void ConsistencyService::storeKeyframe(const std::string& robot, std::size_t first_edge,
                                       std::size_t end_edge, std::size_t first_prior) {
  if (!store_) return;
  // Only the worker changes keyframes_, estimates_ and graph_: read unlocked.
  StoredKeyframe record;
  record.robot = robot;
  record.keyframe = keyframes_.back();
  record.keyframe.descriptor = ScanContext();  // recomputed from the points
  record.estimate = estimates_.back();
  const std::vector<PoseEdge>& edges = graph_.edges();
  record.edges.assign(edges.begin() + static_cast<std::ptrdiff_t>(first_edge),
                      edges.begin() + static_cast<std::ptrdiff_t>(end_edge));
  const std::vector<PosePrior>& priors = graph_.priors();
  record.priors.assign(priors.begin() + static_cast<std::ptrdiff_t>(first_prior), priors.end());
  store_->add(RecordType::kKeyframe, encodeKeyframe(record));
}

void ConsistencyService::storeClosure(const Closure& closure, const PoseEdge& edge) {
  if (store_) store_->add(RecordType::kClosure, encodeClosure({closure, edge}));
}

void ConsistencyService::storeRebuild(const RebuiltGrid& grid) {
  if (!store_) return;
  StoredRebuild record;
  record.serial = grid.serial;
  for (const Keyframe& k : keyframes_) record.poses.push_back(k.grid_pose);
  record.corrections = grid.corrections;
  store_->add(RecordType::kRebuild, encodeRebuild(record));
}

void ConsistencyService::restore(const StoreContents& contents, int grid_serial) {
  for (const StoredKeyframe& k : contents.keyframes) restoreKeyframe(k);
  for (const StoredClosure& c : contents.closures) restoreClosure(c);
  // The graph with every closure: what the last optimization before the restart gave (the
  // nodes after the last closure continue from it by their odometry, as they were added).
  if (!closures_.empty()) graph_.optimize();
  for (std::size_t i = 0; i < graph_.size(); ++i) estimates_[i] = graph_.pose(static_cast<int>(i));
  restoreGridPoses(contents, grid_serial);
  // Observed before the snapshot but not processed: queued again, the worker makes them as it
  // would have (their grid poses as integrated at their robots' last correction).
  for (const StoredWaiting* w : waitingKeyframes(contents)) restoreWaiting(*w);
  stats_.recognition.verified = static_cast<int>(closures_.size());
  resume_rebuild_ = params_.correct_grid && !closures_.empty();
  busy_ = resume_rebuild_;
}

void ConsistencyService::restoreKeyframe(const StoredKeyframe& stored) {
  Keyframe kf = stored.keyframe;
  const int id = static_cast<int>(keyframes_.size());
  auto [it, added] = robots_.try_emplace(stored.robot);
  RobotTrack& track = it->second;
  if (added) {
    track.index = static_cast<int>(robot_names_.size());
    robot_names_.push_back(stored.robot);
  }
  if (kf.id != id || kf.robot != track.index || kf.robot_kf < track.keyframes)
    throw std::runtime_error("keyframe record " + std::to_string(id) + " is out of order");
  for (const PoseEdge& e : stored.edges)
    if (e.to != id || e.from < 0 || e.from >= id)
      throw std::runtime_error("keyframe record " + std::to_string(id) + " has a bad edge");
  for (const PosePrior& p : stored.priors)
    if (p.node != id)
      throw std::runtime_error("keyframe record " + std::to_string(id) + " has a bad prior");
  if (!kf.points.empty()) kf.descriptor = ScanContext(kf.points, params_.descriptor);
  graph_.addNode(stored.estimate);
  for (const PoseEdge& e : stored.edges) graph_.addEdge(e);
  for (const PosePrior& p : stored.priors) graph_.addPrior(p);
  addGravityPrior(kf);  // from the keyframe's reference and the params of this run
  estimates_.push_back(stored.estimate);
  track.last_keyframe_pose = kf.odom_pose;
  track.last_pose = kf.odom_pose;
  track.travelled = kf.travelled;
  track.keyframes = kf.robot_kf + 1;
  track.keyframe_ids.push_back(id);
  track.keyframe_seqs.push_back(kf.seq);
  track.restored_seq = kf.seq;
  // Its record's edges are the odometry edge from the robot's previous keyframe (if any).
  track.last_motion.reset();
  if (!stored.edges.empty()) track.last_motion = stored.edges.front().relative;
  keyframes_.push_back(std::move(kf));
  stats_.keyframe_bytes += keyframes_.back().bytes();
  stats_.scan_bytes += keyframes_.back().scan.bytes();
}

void ConsistencyService::restoreClosure(const StoredClosure& stored) {
  const Closure& c = stored.closure;
  const int n = static_cast<int>(keyframes_.size());
  if (c.from < 0 || c.from >= n || c.to < 0 || c.to >= n || stored.edge.from != c.from ||
      stored.edge.to != c.to)
    throw std::runtime_error("closure record " + std::to_string(closures_.size()) +
                             " names keyframes the store does not hold");
  graph_.addEdge(stored.edge);
  closures_.push_back(c);
  const Keyframe& query = keyframes_[static_cast<std::size_t>(c.to)];
  RobotTrack& track = robots_.at(robot_names_[static_cast<std::size_t>(query.robot)]);
  track.next_attempt_travel =
      std::max(track.next_attempt_travel, query.travelled + params_.closure_spacing);
}

void ConsistencyService::restoreGridPoses(const StoreContents& contents, int grid_serial) {
  const StoredRebuild* grid = nullptr;
  for (const StoredRebuild& r : contents.rebuilds) {
    stats_.rebuilds = std::max(stats_.rebuilds, r.serial);  // new rebuilds number on
    if (r.serial == grid_serial) grid = &r;
  }
  if (grid_serial > 0 && grid == nullptr)
    throw std::runtime_error("the store lacks rebuild " + std::to_string(grid_serial));
  if (grid != nullptr) applied_ = grid->corrections;
  grid_serial_ = grid_serial;
  // Where each scan is in the map's grid: at the rebuild's pose, or (integrated later) at its
  // robot's correction of that rebuild, or as integrated.
  for (Keyframe& k : keyframes_) {
    const auto id = static_cast<std::size_t>(k.id);
    const auto applied = applied_.find(robot_names_[static_cast<std::size_t>(k.robot)]);
    if (grid != nullptr && id < grid->poses.size())
      k.grid_pose = grid->poses[id];
    else
      k.grid_pose = applied == applied_.end() ? k.odom_pose : applied->second * k.odom_pose;
  }
}

void ConsistencyService::restoreWaiting(const StoredWaiting& stored) {
  auto [it, added] = robots_.try_emplace(stored.robot);
  RobotTrack& track = it->second;
  if (added) {
    track.index = static_cast<int>(robot_names_.size());
    robot_names_.push_back(stored.robot);
  }
  const Keyframe& kf = stored.keyframe;
  if (kf.robot != track.index || kf.robot_kf != track.keyframes)
    throw std::runtime_error("waiting keyframe " + std::to_string(kf.robot_kf) + " of " +
                             stored.robot + " is out of order");
  track.last_keyframe_pose = kf.odom_pose;
  track.last_pose = kf.odom_pose;
  track.travelled = kf.travelled;
  track.keyframes = kf.robot_kf + 1;
  track.restored_seq = kf.seq;
  Pending pending;
  pending.keyframe.robot = kf.robot;
  pending.keyframe.robot_kf = kf.robot_kf;
  pending.keyframe.seq = kf.seq;
  pending.keyframe.utime = kf.utime;
  pending.keyframe.odom_pose = kf.odom_pose;
  pending.keyframe.travelled = kf.travelled;
  pending.keyframe.gravity = kf.gravity;
  switch (stored.form) {
    case WaitingForm::kCloud:
      pending.cloud = std::make_shared<const LabeledCloud>(stored.cloud);
      ++pending_clouds_;
      break;
    case WaitingForm::kReduced:
      pending.reduced = std::make_shared<const ReducedScan>(ReducedScan{kf.points, kf.scan});
      break;
    case WaitingForm::kPoseOnly:
      break;
  }
  pending.robot = stored.robot;
  pending.arrived = std::chrono::steady_clock::now();
  pending.stored = true;  // already in the store
  queue_.push_back(std::move(pending));
}

}  // namespace socc::consistency
