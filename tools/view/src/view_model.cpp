#include "view_model.hpp"

#include <Eigen/Geometry>
#include <algorithm>

namespace socc::view {
namespace {

// Why a map_delta_t cannot be applied (its columns disagree with its counts), or empty.
std::string checkDelta(const map_delta_t& d) {
  if (d.num_blocks < 0 || d.num_voxels < 0) return "negative counts";
  if (!(d.voxel_size > 0.0) || d.block_dim <= 0 || d.block_dim > 64) return "bad geometry";
  if (d.block_key.size() != 3 || d.block_voxels.size() != static_cast<std::size_t>(d.num_blocks))
    return "block columns do not match num_blocks";
  for (const auto& row : d.block_key)
    if (row.size() != static_cast<std::size_t>(d.num_blocks)) return "block key rows";
  const auto n = static_cast<std::size_t>(d.num_voxels);
  if (d.local.size() != n || d.occupancy.size() != n || d.label.size() != n)
    return "voxel columns do not match num_voxels";
  std::int64_t sum = 0;
  for (const std::int16_t c : d.block_voxels) {
    if (c < 0) return "negative block voxel count";
    sum += c;
  }
  if (sum != d.num_voxels) return "block voxel counts do not add up to num_voxels";
  const int per_block = d.block_dim * d.block_dim * d.block_dim;
  for (const std::int16_t l : d.local)
    if (l < 0 || l >= per_block) return "local voxel index outside its block";
  return {};
}

// Whether block b of d shows the same as held (same voxels and classes, occupancy within the
// map server's kOccupancyStep of 16): the refresh cycle resends unchanged blocks.
bool sameAsHeld(const map_delta_t& d, std::size_t first, std::size_t n, const BlockContent& held) {
  if (held.local.size() != n) return false;
  for (std::size_t v = 0; v < n; ++v)
    if (held.local[v] != d.local[first + v] || held.label[v] != d.label[first + v] ||
        held.occupancy[v] / 16 != d.occupancy[first + v] / 16)
      return false;
  return true;
}

}  // namespace

void ViewModel::addListener(ModelListener* listener) {
  const std::lock_guard<std::mutex> lock(mutex_);
  listeners_.push_back(listener);
}

void ViewModel::removeListener(ModelListener* listener) {
  const std::lock_guard<std::mutex> lock(mutex_);
  listeners_.erase(std::remove(listeners_.begin(), listeners_.end(), listener), listeners_.end());
}

std::string ViewModel::applyDelta(const map_delta_t& d) {
  if (std::string why = checkDelta(d); !why.empty()) return why;
  const std::lock_guard<std::mutex> lock(mutex_);
  ++deltas_received_;
  if (d.epoch != epoch_) {  // another map (restart, load, clear): its robots report again
    epoch_ = d.epoch;
    blocks_.clear();
    robots_.clear();
    voxel_count_ = 0;
    for (ModelListener* l : listeners_) l->mapReset();
  }
  voxel_size_ = d.voxel_size;
  block_dim_ = d.block_dim;
  std::vector<BlockKey> keys;
  keys.reserve(static_cast<std::size_t>(d.num_blocks));
  std::size_t next = 0;
  for (std::size_t b = 0; b < d.block_voxels.size(); ++b) {
    const BlockKey key{d.block_key[0][b], d.block_key[1][b], d.block_key[2][b]};
    const auto n = static_cast<std::size_t>(d.block_voxels[b]);
    const auto it = blocks_.find(key);
    if (it == blocks_.end() ? n == 0 : sameAsHeld(d, next, n, it->second)) {
      next += n;
      continue;  // nothing to show
    }
    if (it != blocks_.end()) voxel_count_ -= static_cast<std::int64_t>(it->second.local.size());
    if (n == 0) {
      if (it != blocks_.end()) blocks_.erase(it);
    } else {
      BlockContent& c = blocks_[key];
      const auto first = static_cast<std::ptrdiff_t>(next);
      const auto last = static_cast<std::ptrdiff_t>(next + n);
      c.local.assign(d.local.begin() + first, d.local.begin() + last);
      c.occupancy.assign(d.occupancy.begin() + first, d.occupancy.begin() + last);
      c.label.assign(d.label.begin() + first, d.label.begin() + last);
      voxel_count_ += static_cast<std::int64_t>(n);
    }
    next += n;
    keys.push_back(key);
  }
  if (!keys.empty())
    for (ModelListener* l : listeners_) l->blocksChanged(keys);
  return {};
}

RobotView* ViewModel::robot(const std::string& id) {
  const auto it = robots_.find(id);
  if (it != robots_.end()) return &it->second;
  if (robots_.size() >= kMaxRobots) return nullptr;
  RobotView& r = robots_[id];
  r.id = id;
  return &r;
}

void ViewModel::extendTrajectory(RobotView& r) {
  const std::array<float, 3> p{static_cast<float>(r.translation[0]),
                               static_cast<float>(r.translation[1]),
                               static_cast<float>(r.translation[2])};
  if (!r.trajectory.empty()) {
    const auto& q = r.trajectory.back();
    const float dx = p[0] - q[0], dy = p[1] - q[1], dz = p[2] - q[2];
    if (dx * dx + dy * dy + dz * dz < kTrajectoryStep * kTrajectoryStep) return;
  }
  if (r.trajectory.size() < kMaxTrajectory) r.trajectory.push_back(p);
}

void ViewModel::applyStats(const map_stats_t& stats) {
  const std::lock_guard<std::mutex> lock(mutex_);
  stats_ = stats;
  for (const robot_state_t& s : stats.robots) {
    RobotView* known = robot(s.robot_id);
    if (known == nullptr) continue;
    RobotView& r = *known;
    r.tracking_state = s.tracking_state;
    r.tracking_reason = s.tracking_reason;
    r.integrations = s.integrations;
    r.refused = s.refused_integrations;
    if (s.last_seq >= r.last_seq) {  // the INTEGRATE stream may be ahead of the status
      r.last_seq = s.last_seq;
      for (int i = 0; i < 3; ++i) r.translation[i] = s.last_pose.translation[i];
      for (int i = 0; i < 4; ++i) r.quaternion[i] = s.last_pose.quaternion[i];
      extendTrajectory(r);
    }
  }
  for (ModelListener* l : listeners_) {
    l->statsChanged();
    l->robotsChanged();
  }
}

void ViewModel::applyIntegrate(const integrate_request_t& q) {
  const auto n = static_cast<std::size_t>(std::max(0, q.num_points));
  if (q.xyz.size() != 3 || !(q.xyz_resolution > 0.0f)) return;
  for (const auto& row : q.xyz)
    if (row.size() != n) return;
  const Eigen::Quaterniond rotation(q.sensor_pose.quaternion[0], q.sensor_pose.quaternion[1],
                                    q.sensor_pose.quaternion[2], q.sensor_pose.quaternion[3]);
  const Eigen::Vector3d t(q.sensor_pose.translation[0], q.sensor_pose.translation[1],
                          q.sensor_pose.translation[2]);
  if (!t.allFinite() || !rotation.coeffs().allFinite() || rotation.norm() < 0.5) return;
  const Eigen::Matrix3d rot = rotation.normalized().toRotationMatrix();
  // Every stride-th point: the view needs the scan's shape, not its density.
  const std::size_t stride = std::max<std::size_t>(1, (n + kMaxScanPoints - 1) / kMaxScanPoints);
  std::vector<float> scan;
  scan.reserve(3 * (n / stride + 1));
  for (std::size_t i = 0; i < n; i += stride) {
    const Eigen::Vector3d p =
        rot * Eigen::Vector3d(q.xyz[0][i], q.xyz[1][i], q.xyz[2][i]) * q.xyz_resolution + t;
    for (int a = 0; a < 3; ++a) scan.push_back(static_cast<float>(p[a]));
  }
  const std::lock_guard<std::mutex> lock(mutex_);
  RobotView* known = robot(q.header.client_id);
  if (known == nullptr) return;
  RobotView& r = *known;
  if (q.seq < r.scan_seq) return;  // a retry or reordering: keep the newer one
  r.scan_seq = q.seq;
  r.scan = std::move(scan);
  for (int i = 0; i < 3; ++i) r.translation[i] = t[i];
  for (int i = 0; i < 4; ++i) r.quaternion[i] = q.sensor_pose.quaternion[i];
  r.last_seq = std::max(r.last_seq, q.seq);
  extendTrajectory(r);
  for (ModelListener* l : listeners_) l->robotsChanged();
}

}  // namespace socc::view
