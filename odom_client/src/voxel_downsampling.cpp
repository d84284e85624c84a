#include "socc/odom/voxel_downsampling.hpp"

#include <tsl/robin_map.h>

#include <algorithm>
#include <cmath>
#include <optional>

#include "socc/voxel.hpp"

namespace socc::odom {
namespace {

struct VoxelKey {
  VoxelIndex index;
  std::uint8_t label;
  bool operator==(const VoxelKey& o) const { return index == o.index && label == o.label; }
};

struct VoxelKeyHash {
  std::size_t operator()(const VoxelKey& k) const {
    return VoxelIndexHash{}(k.index) ^ (static_cast<std::size_t>(k.label) << 56);
  }
};

struct Sum {
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  double time_sum = 0.0;
  int count = 0;
  std::size_t order = 0;  // first point's index: keeps the output deterministic
};

}  // namespace

LabeledCloud semanticVoxelDownsample(const LabeledCloud& cloud, double voxel_size,
                                     const std::array<double, kNumClasses>& class_factor) {
  std::array<double, kNumClasses> inv_size{};
  for (int c = 0; c < kNumClasses; ++c)
    inv_size[c] = class_factor[c] > 0.0 ? 1.0 / (class_factor[c] * voxel_size) : 0.0;

  // Not reserved for the cloud's size: a downsampled scan has a few thousand voxels, and a table
  // sized for a quarter of its points misses the cache and is cleared at every call.
  tsl::robin_map<VoxelKey, Sum, VoxelKeyHash> voxels;
  // A scan's consecutive points mostly share a voxel: its sum is reused without a lookup (valid
  // until the next insertion, which replaces it).
  std::optional<VoxelKey> last_key;
  Sum* last = nullptr;
  for (std::size_t i = 0; i < cloud.size(); ++i) {
    const std::uint8_t label = cloud.hasLabels() ? cloud.labels[i] : std::uint8_t{kUnlabeled};
    if (!isValidClass(label) || inv_size[label] == 0.0) continue;
    const Eigen::Vector3d p = cloud.points[i].cast<double>();
    if (!p.allFinite()) continue;
    const VoxelKey key{voxelIndex(p, inv_size[label]), label};
    if (!last_key || !(key == *last_key)) {
      auto [it, inserted] = voxels.try_emplace(key);
      last = &it.value();
      last_key = key;
      if (inserted) last->order = i;
    }
    Sum& s = *last;
    s.sum += p;
    if (cloud.hasTimes()) s.time_sum += cloud.times[i];
    ++s.count;
  }

  std::vector<std::pair<std::size_t, const Sum*>> ordered;
  ordered.reserve(voxels.size());
  for (const auto& [key, s] : voxels) ordered.push_back({s.order, &s});
  std::sort(ordered.begin(), ordered.end(),
            [](const auto& a, const auto& b) { return a.first < b.first; });

  LabeledCloud out;
  out.points.reserve(ordered.size());
  out.labels.reserve(ordered.size());
  for (const auto& [order, s] : ordered) {
    out.points.push_back((s->sum / s->count).cast<float>());
    out.labels.push_back(cloud.hasLabels() ? cloud.labels[order] : std::uint8_t{kUnlabeled});
    if (cloud.hasTimes()) out.times.push_back(static_cast<float>(s->time_sum / s->count));
  }
  return out;
}

AdaptiveVoxelSize::AdaptiveVoxelSize(double initial, double min_size, double max_size, int target)
    : size_(initial), min_size_(min_size), max_size_(max_size), target_(target) {}

void AdaptiveVoxelSize::update(std::size_t count) {
  const double ratio = static_cast<double>(std::max<std::size_t>(count, 1)) / target_;
  const double step = std::clamp(std::sqrt(ratio), 0.5, 2.0);
  size_ = std::clamp(size_ * step, min_size_, max_size_);
}

bool AdaptiveVoxelSize::farOff(std::size_t count) const {
  const double ratio = static_cast<double>(count) / target_;
  const bool can_shrink = size_ > min_size_;
  const bool can_grow = size_ < max_size_;
  return (ratio < 0.5 && can_shrink) || (ratio > 2.0 && can_grow);
}

}  // namespace socc::odom
