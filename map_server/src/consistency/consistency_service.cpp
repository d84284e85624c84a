#include "consistency_service.hpp"

#include <algorithm>
#include <fstream>
#include <stdexcept>
#include <utility>

#include "correction_fit.hpp"
#include "socc/pose_interpolation.hpp"

namespace socc::consistency {
namespace {

double angleBetween(const Eigen::Isometry3d& a, const Eigen::Isometry3d& b) {
  return Eigen::AngleAxisd(a.linear().transpose() * b.linear()).angle();
}

void writePose(std::ostream& out, const Eigen::Isometry3d& pose) {
  const Eigen::Matrix<double, 3, 4> m = pose.matrix().topRows<3>();
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 4; ++c) out << ' ' << m(r, c);
}

}  // namespace

ConsistencyService::ConsistencyService(const ConsistencyParams& params,
                                       const map::MapConfig& map_config,
                                       const odom::OdomConfig& odom_config,
                                       std::unique_ptr<KeyframeStore> store,
                                       const StoreContents* restored, int grid_serial)
    : params_(params), map_config_(map_config), odom_config_(odom_config) {
  if (restored != nullptr) restore(*restored, grid_serial);
  store_ = std::move(store);  // after restore: nothing restored is written again
  worker_ = std::thread([this] { run(); });
}

ConsistencyService::~ConsistencyService() {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    stopping_ = true;
  }
  wake_.notify_all();
  worker_.join();
}

void ConsistencyService::observe(const std::string& robot, std::int64_t seq, std::int64_t utime,
                                 const Eigen::Isometry3d& pose, const LabeledCloud& cloud,
                                 const std::optional<GravityReference>& gravity) {
  Pending pending;
  bool full_cloud = false;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    if (!isKeyframe(robot, seq, pose, pending.keyframe)) return;
    // Its place in the queue is taken now; the cloud is copied or reduced off the lock (the
    // worker goes on meanwhile; only this thread observes).
    full_cloud = pending_clouds_ < params_.max_pending_scans;
    if (full_cloud)
      ++pending_clouds_;
    else
      ++stats_.scans_reduced_on_arrival;
  }
  pending.keyframe.utime = utime;
  pending.keyframe.gravity = gravity;
  if (full_cloud) {
    auto copy = std::make_shared<LabeledCloud>();
    copy->points = cloud.points;
    if (params_.correct_grid) copy->labels = cloud.labels;  // times play no part
    pending.cloud = std::move(copy);
  } else {
    // The worker is max_pending_scans behind: what it would keep of the cloud, made here.
    pending.reduced = std::make_shared<const ReducedScan>(reduceScan(cloud, params_));
  }
  pending.robot = robot;
  pending.arrived = std::chrono::steady_clock::now();
  std::lock_guard<std::mutex> lock(mutex_);
  if (rebuilding_) tail_.push_back(*tailScan(pending));
  queue_.push_back(std::move(pending));
  wake_.notify_one();
}

bool ConsistencyService::isKeyframe(const std::string& robot, std::int64_t seq,
                                    const Eigen::Isometry3d& pose, Keyframe& keyframe) {
  auto [it, added] = robots_.try_emplace(robot);
  RobotTrack& track = it->second;
  if (added) {
    track.index = static_cast<int>(robot_names_.size());
    robot_names_.push_back(robot);
  }
  if (seq <= track.restored_seq) return false;  // a journal replay of what the store holds
  if (track.last_pose)
    track.travelled += (pose.translation() - track.last_pose->translation()).norm();
  track.last_pose = pose;
  if (track.last_keyframe_pose &&
      (track.last_keyframe_pose->translation() - pose.translation()).norm() <
          params_.keyframe_distance &&
      angleBetween(*track.last_keyframe_pose, pose) < params_.keyframe_angle)
    return false;
  track.last_keyframe_pose = pose;
  keyframe.robot = track.index;
  keyframe.robot_kf = track.keyframes++;
  keyframe.seq = seq;
  keyframe.odom_pose = pose;
  keyframe.travelled = track.travelled;
  return true;
}

std::optional<ConsistencyService::TailScan> ConsistencyService::tailScan(const Pending& pending) {
  if (!pending.cloud && !pending.reduced) return std::nullopt;
  return TailScan{pending.robot, pending.keyframe.odom_pose, pending.cloud, pending.reduced};
}

void ConsistencyService::flush() {
  std::unique_lock<std::mutex> lock(mutex_);
  idle_.wait(lock, [this] { return queue_.empty() && !busy_; });
}

void ConsistencyService::run() {
  if (resume_rebuild_) {  // a correction the restart interrupted (busy_ set by restore)
    try {
      maybeRebuild();
    } catch (const std::exception&) {
      // As a failed keyframe: the grid stays as it is until the next closure.
    }
    std::lock_guard<std::mutex> lock(mutex_);
    busy_ = false;
  }
  idle_.notify_all();
  for (;;) {
    Pending next;
    {
      std::unique_lock<std::mutex> lock(mutex_);
      wake_.wait(lock, [this] { return stopping_ || (!held_ && !queue_.empty()); });
      if (stopping_) return;
      next = std::move(queue_.front());
      queue_.pop_front();
      if (next.cloud) --pending_clouds_;
      in_flight_ = next;  // waiting (for a checkpoint) until its keyframe record is written
      busy_ = true;
    }
    try {
      process(std::move(next));
    } catch (const std::exception&) {
      // A keyframe that cannot be processed is dropped; the map and the graph stay as they were.
    }
    try {
      rebuildWhenDue();
    } catch (const std::exception&) {
      // As a failed keyframe: the grid stays as it is until the next closure.
    }
    {
      std::lock_guard<std::mutex> lock(mutex_);
      in_flight_.reset();
      busy_ = false;
    }
    idle_.notify_all();
  }
}

void ConsistencyService::hold(bool on) {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    held_ = on;
  }
  wake_.notify_all();
}

void ConsistencyService::process(Pending pending) {
  Keyframe& kf = pending.keyframe;
  if (pending.cloud) {
    ReducedScan reduced = reduceScan(*pending.cloud, params_);
    kf.points = std::move(reduced.points);
    kf.scan = std::move(reduced.scan);
  } else if (pending.reduced) {  // reduced on arrival
    kf.points = pending.reduced->points;
    kf.scan = pending.reduced->scan;
  }
  pending.cloud.reset();
  pending.reduced.reset();
  const bool matchable = !kf.points.empty();  // not a pose only (an old store's waiting one)
  if (matchable) kf.descriptor = ScanContext(kf.points, params_.descriptor);
  kf.id = static_cast<int>(keyframes_.size());  // only this thread adds keyframes
  bool snap = false;
  const std::optional<PoseEdge> odometry = measureOdometry(kf, pending.robot, snap);
  int query = 0;
  double travelled = 0.0;
  double next_attempt = 0.0;
  const std::size_t first_edge = graph_.edges().size();
  const std::size_t first_prior = graph_.priors().size();
  {
    std::lock_guard<std::mutex> lock(mutex_);
    RobotTrack& track = robots_.at(pending.robot);
    // In the grid at its robot's correction of the last rebuild (as integrated before any).
    const auto applied = applied_.find(pending.robot);
    kf.grid_pose = applied == applied_.end() ? kf.odom_pose : applied->second * kf.odom_pose;
    addToGraph(kf, track, odometry);
    track.keyframe_ids.push_back(kf.id);
    track.keyframe_seqs.push_back(kf.seq);
    keyframes_.push_back(std::move(kf));
    stats_.keyframe_bytes += keyframes_.back().bytes();
    stats_.scan_bytes += keyframes_.back().scan.bytes();
    query = keyframes_.back().id;
    travelled = keyframes_.back().travelled;
    next_attempt = track.next_attempt_travel;
  }
  const std::size_t end_edge = graph_.edges().size();
  std::optional<std::pair<Closure, PoseEdge>> closed;
  if (snap && matchable)
    closed = closeSnap(query, first_edge, pending.robot, travelled, pending.arrived);
  storeKeyframe(pending.robot, first_edge, end_edge, first_prior);
  {
    std::lock_guard<std::mutex> lock(mutex_);
    in_flight_.reset();  // durable: a checkpoint need not write it
  }
  // Only this thread changes keyframes_ and estimates_: reading them unlocked is safe here.
  if (!closed && !snap && matchable && travelled >= next_attempt)
    closed = attemptClosure(query, pending.robot, travelled, pending.arrived);
  if (!closed) return;
  storeClosure(closed->first, closed->second);
  if (params_.correct_grid && !rebuild_due_) rebuild_due_ = std::chrono::steady_clock::now();
}

std::optional<std::pair<Closure, PoseEdge>> ConsistencyService::closeSnap(
    int query, std::size_t edge_index, const std::string& robot, double travelled,
    std::chrono::steady_clock::time_point arrived) {
  // A snap (the client pulled onto walls it mapped before) is measured scan to scan so that a
  // closure of the revisit spreads the loop's error; a snap no closure ties would lose the
  // revisit, which the integrated edge keeps (the client's own closure against the map).
  auto closed = attemptClosure(query, robot, travelled, arrived);
  if (closed) return closed;
  PoseEdge edge = graph_.edges()[edge_index];
  edge.relative = keyframes_[static_cast<std::size_t>(edge.from)].odom_pose.inverse() *
                  keyframes_[static_cast<std::size_t>(edge.to)].odom_pose;
  graph_.replaceEdge(edge_index, edge);
  std::lock_guard<std::mutex> lock(mutex_);
  robots_.at(robot).last_motion = edge.relative;
  ++stats_.odometry_edges.snaps_unclosed;
  return std::nullopt;
}

std::optional<std::pair<Closure, PoseEdge>> ConsistencyService::attemptClosure(
    int query, const std::string& robot, double travelled,
    std::chrono::steady_clock::time_point arrived) {
  const std::vector<Candidate> candidates = findCandidates(keyframes_, query, estimates_, params_);
  if (candidates.empty()) return std::nullopt;
  const auto verify_start = std::chrono::steady_clock::now();
  RefusalCounts refused{};
  const std::optional<Closure> closure =
      verifyCandidate(keyframes_, query, candidates, estimates_, params_, map_config_, odom_config_,
                      nullptr, &refused);
  const double verify_seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - verify_start).count();
  PoseEdge edge;
  bool consistent = false;
  OptimizationSummary summary;
  if (closure) {
    edge.from = closure->from;
    edge.to = closure->to;
    edge.relative = closure->relative;
    edge.information = isotropicInformation(params_.loop_sigma_t, params_.loop_sigma_r);
    // graph_ is the worker's alone: optimized without holding the lock.
    consistent = graph_.addConsistentEdge(edge, params_.max_closure_chi2, nullptr, &summary);
  }
  std::lock_guard<std::mutex> lock(mutex_);
  ++stats_.recognition.attempts;
  stats_.recognition.seconds += verify_seconds;
  for (std::size_t i = 0; i < refused.size(); ++i)
    stats_.recognition.candidates_refused[i] += refused[i];
  if (!closure) {
    ++stats_.recognition.refused;
    return std::nullopt;
  }
  if (!consistent) {
    ++stats_.recognition.inconsistent;
    return std::nullopt;
  }
  ++stats_.recognition.verified;
  closures_.push_back(*closure);
  robots_.at(robot).next_attempt_travel = travelled + params_.closure_spacing;
  for (std::size_t i = 0; i < graph_.size(); ++i) estimates_[i] = graph_.pose(static_cast<int>(i));
  ++stats_.optimizations;
  stats_.last_optimization_s = summary.seconds;
  stats_.max_correction_s =
      std::max(stats_.max_correction_s,
               std::chrono::duration<double>(std::chrono::steady_clock::now() - arrived).count());
  return std::make_pair(*closure, edge);
}

void ConsistencyService::rebuildWhenDue() {
  if (!rebuild_due_) return;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    const double waited =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - *rebuild_due_).count();
    if (!queue_.empty() && waited < params_.rebuild_max_wait) return;
  }
  rebuild_due_.reset();  // a rebuild that fails waits for the next closure
  maybeRebuild();
}

void ConsistencyService::maybeRebuild() {
  // Only this thread changes keyframes_ and estimates_ (and grid_pose): read unlocked.
  double max_shift = 0.0;
  for (const Keyframe& k : keyframes_)
    if (!k.scan.empty())
      max_shift =
          std::max(max_shift, poseShift(k.grid_pose, estimates_[static_cast<std::size_t>(k.id)],
                                        params_.rebuild_lever));
  if (max_shift > params_.rebuild_min_shift) rebuild(max_shift);
}

void ConsistencyService::rebuild(double max_shift) {
  const auto start = std::chrono::steady_clock::now();
  auto grid = std::make_unique<RebuiltGrid>(map_config_);
  grid->max_shift = max_shift;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    grid->serial = stats_.rebuilds + 1;
    // The keyframes not processed yet are the tail's first entries; later ones join in observe.
    ready_.reset();  // superseded: never swapped in, no robot was told its correction
    tail_.clear();
    tail_done_ = 0;
    for (const Pending& p : queue_)
      if (std::optional<TailScan> t = tailScan(p)) tail_.push_back(std::move(*t));
    rebuilding_ = true;
    for (const auto& [name, track] : robots_)
      if (!track.keyframe_ids.empty()) grid->corrections[name] = robotCorrection(track);
  }
  // Updated in base_ (a region rebuild, or the whole map into an empty grid); the swap gets a
  // copy, or base_ itself when none is kept.
  if (!base_ || !params_.rebuild_region)
    base_.emplace(KeyframeGrid{map::SemanticOccupancyMap(map_config_), 0});
  grid->keyframes =
      updateGrid(base_->map, keyframes_, base_->keyframes, estimates_, regionRule(params_));
  base_->keyframes = keyframes_.size();
  if (params_.rebuild_region) {
    grid->map = base_->map.clone();
  } else {  // nothing kept: neither the grid nor (updateGrid) the keyframes' footprints
    grid->map = std::move(base_->map);
    base_.reset();
  }
  // Catch up with the keyframes observed meanwhile until none is left for the swap but the
  // last few.
  for (;;) {
    std::vector<TailScan> more;
    {
      std::lock_guard<std::mutex> lock(mutex_);
      more.assign(tail_.begin() + static_cast<std::ptrdiff_t>(tail_done_), tail_.end());
    }
    if (more.empty()) break;
    integrateTail(*grid, more);
    grid->keyframes += static_cast<int>(more.size());
    std::lock_guard<std::mutex> lock(mutex_);
    tail_done_ += more.size();
  }
  grid->seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  storeRebuild(*grid);  // before it can be taken: a checkpoint's mark names a stored rebuild
  std::lock_guard<std::mutex> lock(mutex_);
  applied_ = grid->corrections;
  ++stats_.rebuilds;
  if (grid->seconds >= stats_.max_rebuild_s) {  // the longest rebuild and its scans
    stats_.max_rebuild_s = grid->seconds;
    stats_.rebuild_keyframes = grid->keyframes;
  }
  stats_.rebuild_s += grid->seconds;
  stats_.rebuild_scans += grid->keyframes;
  stats_.base_bytes =
      base_ ? static_cast<std::size_t>(base_->map.stats().memory_bytes) + footprintBytes(keyframes_)
            : 0;
  ready_ = std::move(grid);
}

Eigen::Isometry3d ConsistencyService::robotCorrection(const RobotTrack& track) const {
  std::vector<CorrectionSample> samples;
  const double until = keyframes_[static_cast<std::size_t>(track.keyframe_ids.back())].travelled -
                       params_.correction_window;
  for (auto id = track.keyframe_ids.rbegin(); id != track.keyframe_ids.rend(); ++id) {
    const Keyframe& k = keyframes_[static_cast<std::size_t>(*id)];
    if (!samples.empty() && k.travelled < until) break;
    samples.push_back({k.odom_pose, estimates_[static_cast<std::size_t>(k.id)]});
  }
  return fitCorrection(samples);
}

void ConsistencyService::integrateTail(RebuiltGrid& grid, const std::vector<TailScan>& tail) const {
  for (const TailScan& t : tail) {
    const auto c = grid.corrections.find(t.robot);
    const Eigen::Isometry3d pose =
        c == grid.corrections.end() ? t.raw_pose : c->second * t.raw_pose;
    if (t.reduced)
      integrateScan(grid.map, pose, t.reduced->scan);
    else
      integrateScan(grid.map, pose, compactScan(*t.cloud, params_.rebuild_voxel));
  }
}

std::unique_ptr<RebuiltGrid> ConsistencyService::takeRebuild() {
  std::unique_ptr<RebuiltGrid> grid;
  std::vector<TailScan> rest;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    if (!ready_) return nullptr;
    grid = std::move(ready_);
    grid_serial_ = grid->serial;
    rest.assign(tail_.begin() + static_cast<std::ptrdiff_t>(tail_done_), tail_.end());
    tail_.clear();
    tail_done_ = 0;
    rebuilding_ = false;
  }
  integrateTail(*grid, rest);
  return grid;
}

std::optional<PoseEdge> ConsistencyService::measureOdometry(const Keyframe& kf,
                                                            const std::string& robot, bool& snap) {
  snap = false;
  int previous_id = -1;
  // The edge into previous as the graph measures it: the robot's motion before, a guess without
  // the jump when this edge holds one.
  std::optional<Eigen::Isometry3d> motion;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    const RobotTrack& track = robots_.at(robot);
    if (!track.keyframe_ids.empty()) previous_id = track.keyframe_ids.back();
    motion = track.last_motion;
  }
  if (previous_id < 0) return std::nullopt;
  // Only this thread changes keyframes_: reading them unlocked is safe here.
  const Keyframe& previous = keyframes_[static_cast<std::size_t>(previous_id)];
  OdometryEdgeCheck check;
  const PoseEdge edge = odometryEdge(previous, kf, kf.travelled - previous.travelled, motion,
                                     params_, map_config_, odom_config_, &check);
  std::lock_guard<std::mutex> lock(mutex_);
  tallyEdge(stats_.odometry_edges, check);
  if (check.checked) edge_checks_.emplace_back(kf.id, check);
  snap = check.snap;
  return edge;
}

void ConsistencyService::addToGraph(const Keyframe& kf, RobotTrack& track,
                                    const std::optional<PoseEdge>& odometry) {
  // The new node continues from its predecessor's optimized pose (the correction so far) by the
  // integrated relative pose: its estimate stays where the client's map puts it (the closure
  // guesses start there) even when the edge measures the scans' own relative pose instead.
  Eigen::Isometry3d estimate = kf.odom_pose;
  if (!track.keyframe_ids.empty() && odometry) {
    const Keyframe& previous = keyframes_[static_cast<std::size_t>(track.keyframe_ids.back())];
    estimate = estimates_[static_cast<std::size_t>(previous.id)] *
               (previous.odom_pose.inverse() * kf.odom_pose);
    graph_.addEdge(*odometry);
  }
  track.last_motion.reset();
  if (!track.keyframe_ids.empty() && odometry) track.last_motion = odometry->relative;
  graph_.addNode(estimate);
  estimates_.push_back(estimate);
  if (track.keyframe_ids.empty()) {
    PosePrior prior;
    prior.node = kf.id;
    prior.pose = kf.odom_pose;
    prior.fixed = kf.robot == 0;  // the first robot holds the map frame
    prior.information =
        isotropicInformation(params_.joined_prior_sigma_t, params_.joined_prior_sigma_r);
    graph_.addPrior(prior);
  }
  addGravityPrior(kf);
}

bool ConsistencyService::addGravityPrior(const Keyframe& kf) {
  if (kf.gravity) ++stats_.gravity_keyframes;
  if (!kf.gravity || !params_.gravity_priors) return false;
  // One up direction for the whole graph: every node is in the shared map frame. A robot
  // mapping in its own frame (odom_client --own-frame) integrates nothing until it is merged,
  // and its kept keyframes then arrive at their shared-frame poses; the up vector is in the
  // sensor frame, which the merge does not change.
  graph_.addGravityPrior(
      {kf.id, kf.gravity->up, std::max(kf.gravity->sigma, params_.gravity_sigma_floor)});
  return true;
}

Eigen::Isometry3d ConsistencyService::corrected(const std::string& robot, std::int64_t seq,
                                                const Eigen::Isometry3d& pose) const {
  std::lock_guard<std::mutex> lock(mutex_);
  const auto it = robots_.find(robot);
  if (it == robots_.end() || it->second.keyframe_seqs.empty()) return pose;
  const std::vector<std::int64_t>& seqs = it->second.keyframe_seqs;
  const auto correction = [&](std::size_t i) {
    const Keyframe& k = keyframes_[static_cast<std::size_t>(it->second.keyframe_ids[i])];
    return estimates_[static_cast<std::size_t>(k.id)] * k.odom_pose.inverse();
  };
  const auto after = std::upper_bound(seqs.begin(), seqs.end(), seq);
  if (after == seqs.begin()) return pose;
  const std::size_t i = static_cast<std::size_t>(after - seqs.begin()) - 1;
  if (after == seqs.end()) return correction(i) * pose;
  const double s = static_cast<double>(seq - seqs[i]) / static_cast<double>(*after - seqs[i]);
  return interpolatePose(correction(i), correction(i + 1), s) * pose;
}

ConsistencyStats ConsistencyService::stats() const {
  std::lock_guard<std::mutex> lock(mutex_);
  ConsistencyStats out = stats_;
  out.keyframes = static_cast<int>(keyframes_.size());
  out.pending = static_cast<int>(queue_.size());
  out.pending_clouds = pending_clouds_;
  out.robots = static_cast<int>(robots_.size());
  out.travelled = 0.0;
  for (const auto& [name, track] : robots_) out.travelled += track.travelled;
  return out;
}

std::vector<Closure> ConsistencyService::closures() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return closures_;
}

std::vector<ConsistencyService::KeyframePose> ConsistencyService::keyframePoses() const {
  std::lock_guard<std::mutex> lock(mutex_);
  std::vector<KeyframePose> out;
  for (const Keyframe& k : keyframes_)
    out.push_back({robot_names_[static_cast<std::size_t>(k.robot)], k.seq, k.odom_pose,
                   estimates_[static_cast<std::size_t>(k.id)], k.utime});
  return out;
}

std::vector<ConsistencyService::KeyframePose> ConsistencyService::robotKeyframes(
    const std::string& robot, std::int64_t from_seq, std::size_t max, bool* truncated) const {
  std::lock_guard<std::mutex> lock(mutex_);  // the worker updates estimates_ under it
  std::vector<KeyframePose> out;
  if (truncated != nullptr) *truncated = false;
  const auto it = robots_.find(robot);
  if (it == robots_.end()) return out;
  const std::vector<std::int64_t>& seqs = it->second.keyframe_seqs;
  for (auto i = static_cast<std::size_t>(std::lower_bound(seqs.begin(), seqs.end(), from_seq) -
                                         seqs.begin());
       i < seqs.size(); ++i) {
    if (out.size() == max) {
      if (truncated != nullptr) *truncated = true;
      break;
    }
    const Keyframe& k = keyframes_[static_cast<std::size_t>(it->second.keyframe_ids[i])];
    out.push_back({robot, k.seq, k.odom_pose, estimates_[static_cast<std::size_t>(k.id)], k.utime});
  }
  return out;
}

int ConsistencyService::unprocessed() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return static_cast<int>(queue_.size()) + (busy_ ? 1 : 0);
}

std::string ConsistencyService::anchorRobot() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return keyframes_.empty() ? std::string{}
                            : robot_names_[static_cast<std::size_t>(keyframes_.front().robot)];
}

void ConsistencyService::write(const std::filesystem::path& dir) const {
  std::filesystem::create_directories(dir);
  std::ofstream kf(dir / "keyframes.txt");
  kf.precision(9);
  for (const KeyframePose& k : keyframePoses()) {
    kf << k.robot << ' ' << k.seq;
    writePose(kf, k.odom_pose);
    writePose(kf, k.optimized);
    kf << '\n';
  }
  const std::vector<KeyframePose> poses = keyframePoses();
  std::ofstream cl(dir / "closures.txt");
  cl.precision(9);
  for (const Closure& c : closures()) {
    const KeyframePose& a = poses[static_cast<std::size_t>(c.from)];
    const KeyframePose& b = poses[static_cast<std::size_t>(c.to)];
    cl << a.robot << ' ' << a.seq << ' ' << b.robot << ' ' << b.seq;
    writePose(cl, c.relative);
    cl << ' ' << c.fitness << ' ' << c.free << ' ' << (c.by_descriptor ? 1 : 0) << '\n';
  }
  std::ofstream ed(dir / "odometry_edges.txt");
  {
    std::lock_guard<std::mutex> lock(mutex_);
    for (const auto& [id, c] : edge_checks_) {
      const Keyframe& k = keyframes_[static_cast<std::size_t>(id)];
      ed << robot_names_[static_cast<std::size_t>(k.robot)] << ' ' << k.seq << ' '
         << (c.registered ? 1 : 0) << ' ' << (c.snap ? 1 : 0) << ' ' << c.jump_t << ' ' << c.jump_r
         << ' ' << c.seconds;
      if (c.registered) writePose(ed, c.measured);
      ed << '\n';
    }
  }
  const ConsistencyStats s = stats();
  std::ofstream st(dir / "stats.txt");
  st << "robots " << s.robots << "\nkeyframes " << s.keyframes << "\nattempts "
     << s.recognition.attempts << "\nclosures " << s.recognition.verified << "\nverify_s "
     << s.recognition.seconds << "\nrefused " << s.recognition.refused << "\ninconsistent "
     << s.recognition.inconsistent << "\noptimizations " << s.optimizations
     << "\nlast_optimization_s " << s.last_optimization_s << "\nmax_correction_s "
     << s.max_correction_s << "\nkeyframe_bytes " << s.keyframe_bytes << "\ntravelled_m "
     << s.travelled << "\nscans_reduced_on_arrival " << s.scans_reduced_on_arrival
     << "\nscan_bytes " << s.scan_bytes << "\nrebuilds " << s.rebuilds << "\nmax_rebuild_s "
     << s.max_rebuild_s << "\nrebuild_keyframes " << s.rebuild_keyframes << "\nrebuild_s "
     << s.rebuild_s << "\nrebuild_scans " << s.rebuild_scans << "\nbase_bytes " << s.base_bytes
     << "\nedge_checks " << s.odometry_edges.checked << "\nedge_registered "
     << s.odometry_edges.registered << "\nedge_snaps " << s.odometry_edges.snaps
     << "\nedge_snaps_unclosed " << s.odometry_edges.snaps_unclosed << "\nedge_s "
     << s.odometry_edges.seconds << "\nedge_max_s " << s.odometry_edges.max_seconds
     << "\ngravity_keyframes " << s.gravity_keyframes << '\n';
  for (std::size_t i = 1; i < s.recognition.candidates_refused.size(); ++i)
    st << "candidates_refused_" << odom::refusalName(static_cast<odom::Refusal>(i)) << ' '
       << s.recognition.candidates_refused[i] << '\n';
  if (!kf || !cl || !ed || !st) throw std::runtime_error("cannot write " + dir.string());
}

}  // namespace socc::consistency
