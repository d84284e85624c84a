#include "socc/map/semantic_occupancy_map.hpp"

#include <algorithm>
#include <cmath>
#include <random>
#include <stdexcept>

#include "map_impl.hpp"
#include "socc/map/block_region.hpp"

namespace socc::map {

void SemanticOccupancyMap::Impl::recount() {
  num_observed = 0;
  num_occupied = 0;
  for (const auto& [key, block] : grid.blocks()) {
    for (int i = 0; i < kBlockVoxels; ++i) {
      if (!block->observed[i]) continue;
      ++num_observed;
      if (behaviour.isOccupied(block->log_odds[i])) ++num_occupied;
    }
  }
}

SemanticOccupancyMap::SemanticOccupancyMap(const MapConfig& config) {
  if (const std::string err = socc::map::validate(config); !err.empty())
    throw std::invalid_argument("invalid map config: " + err);
  impl_ = std::make_unique<Impl>(config);
}

SemanticOccupancyMap::~SemanticOccupancyMap() = default;
SemanticOccupancyMap::SemanticOccupancyMap(SemanticOccupancyMap&&) noexcept = default;
SemanticOccupancyMap& SemanticOccupancyMap::operator=(SemanticOccupancyMap&&) noexcept = default;

const MapConfig& SemanticOccupancyMap::config() const {
  return impl_->config;
}

std::string SemanticOccupancyMap::validate(const Eigen::Isometry3d& sensor_pose,
                                           const LabeledCloud& cloud) const {
  const MapConfig& c = impl_->config;
  const Eigen::Matrix4d& m = sensor_pose.matrix();
  if (!m.allFinite()) return "sensor pose is not finite";
  const Eigen::Matrix3d r = sensor_pose.linear();
  if (!(r.transpose() * r).isApprox(Eigen::Matrix3d::Identity(), 1e-3) || r.determinant() < 0.0)
    return "sensor pose rotation is not a proper rotation matrix";
  const Eigen::Vector3d t = sensor_pose.translation();
  if (t.cwiseAbs().maxCoeff() > c.max_abs_coordinate)
    return "sensor pose translation exceeds max_abs_coordinate (" +
           std::to_string(c.max_abs_coordinate) + " m)";
  if (cloud.points.size() > c.max_points_per_scan)
    return "too many points: " + std::to_string(cloud.points.size()) + " > max_points_per_scan " +
           std::to_string(c.max_points_per_scan);
  if (!cloud.labels.empty() && cloud.labels.size() != cloud.points.size())
    return "label count " + std::to_string(cloud.labels.size()) + " != point count " +
           std::to_string(cloud.points.size());
  if (!cloud.times.empty() && cloud.times.size() != cloud.points.size())
    return "time count " + std::to_string(cloud.times.size()) + " != point count " +
           std::to_string(cloud.points.size());
  // A rotation keeps a point's length: within max_abs_coordinate - |t| of the sensor, a point
  // is inside without being transformed (the margin covers rounding); the rest are transformed.
  const double safe = (c.max_abs_coordinate - t.cwiseAbs().maxCoeff()) * (1.0 - 1e-9);
  const double safe2 = safe > 0.0 ? safe * safe : -1.0;
  for (std::size_t i = 0; i < cloud.points.size(); ++i) {
    const Eigen::Vector3f& p = cloud.points[i];
    if (!p.allFinite()) return "point " + std::to_string(i) + " is not finite";
    if (p.cast<double>().squaredNorm() < safe2) continue;
    const Eigen::Vector3d q = sensor_pose * p.cast<double>();
    if (q.cwiseAbs().maxCoeff() > c.max_abs_coordinate)
      return "point " + std::to_string(i) + " lies beyond max_abs_coordinate (" +
             std::to_string(c.max_abs_coordinate) + " m) in the map frame";
  }
  for (std::size_t i = 0; i < cloud.labels.size(); ++i)
    if (!isValidClass(cloud.labels[i]))
      return "label " + std::to_string(cloud.labels[i]) + " of point " + std::to_string(i) +
             " is not a class (0.." + std::to_string(kNumClasses - 1) + ")";
  return {};
}

MapStats SemanticOccupancyMap::stats() const {
  MapStats s;
  s.num_voxels = impl_->num_observed;
  s.num_occupied = impl_->num_occupied;
  s.num_free = impl_->num_observed - impl_->num_occupied;
  s.num_blocks = static_cast<std::int64_t>(impl_->grid.numBlocks());
  s.memory_bytes = static_cast<std::int64_t>(impl_->grid.memoryBytes());
  s.version = impl_->version;
  return s;
}

std::int64_t SemanticOccupancyMap::version() const {
  return impl_->version;
}

void SemanticOccupancyMap::continueVersion(std::int64_t previous) {
  impl_->version = std::max(impl_->version, previous) + 1;
}

void SemanticOccupancyMap::clear() {
  impl_->grid.clear();
  impl_->num_observed = 0;
  impl_->num_occupied = 0;
  ++impl_->version;
  impl_->epoch = newEpoch();  // blocks vanished: no delta can say so
}

void SemanticOccupancyMap::erase(const BlockRegion& region) {
  for (const BlockKey& key : region.blocks()) impl_->grid.erase(key);
  impl_->recount();
  ++impl_->version;
  impl_->epoch = newEpoch();
}

SemanticOccupancyMap SemanticOccupancyMap::clone() const {
  SemanticOccupancyMap copy(impl_->config);
  Impl& c = *copy.impl_;
  c.grid = impl_->grid.clone();
  c.version = impl_->version;
  c.num_observed = impl_->num_observed;
  c.num_occupied = impl_->num_occupied;
  return copy;  // its own epoch, from its constructor
}

std::int64_t SemanticOccupancyMap::epoch() const {
  return impl_->epoch;
}

std::int64_t newEpoch() {
  std::random_device rd;
  std::int64_t e = 0;
  while (e == 0) e = (static_cast<std::int64_t>(rd()) << 31) ^ static_cast<std::int64_t>(rd());
  return e;
}

}  // namespace socc::map
