#include "socc/odom/voxel_downsampling.hpp"

#include <tbb/parallel_invoke.h>
#include <tsl/robin_map.h>

#include <algorithm>
#include <cmath>
#include <optional>

#include "socc/recent_lookups.hpp"
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
  VoxelKey key;
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  double time_sum = 0.0;
  int count = 0;
  std::size_t first = 0;  // first point's index (its label is the voxel's)
};

using SlotTable = tsl::robin_map<VoxelKey, std::uint32_t, VoxelKeyHash>;

// The voxels of points [begin, end), in the order of their first points, and their slots.
struct RangeVoxels {
  SlotTable slot_of;
  std::vector<Sum> voxels;
};

void sumRange(const LabeledCloud& cloud, std::size_t begin, std::size_t end,
              const std::array<double, kNumClasses>& inv_size, const SweepMotion* motion,
              RangeVoxels& out) {
  // Not reserved for the cloud's size: a downsampled scan has a few thousand voxels, and a
  // table sized for a quarter of its points misses the cache and is cleared at every call.
  SlotTable& slot_of = out.slot_of;
  std::vector<Sum>& voxels = out.voxels;
  // Consecutive points mostly share a voxel (its slot is reused without a lookup), and the
  // recent ones are remembered (socc/recent_lookups.hpp).
  std::optional<VoxelKey> last_key;
  Sum* last = nullptr;
  RecentLookups<VoxelKey, std::uint32_t, VoxelKeyHash> recent;
  for (std::size_t i = begin; i < end; ++i) {
    const std::uint8_t label = cloud.hasLabels() ? cloud.labels[i] : std::uint8_t{kUnlabeled};
    if (!isValidClass(label) || inv_size[label] == 0.0) continue;
    const Eigen::Vector3d p =
        (motion ? (*motion)(cloud.points[i], cloud.times[i]) : cloud.points[i]).cast<double>();
    if (!p.allFinite()) continue;
    const VoxelKey key{voxelIndex(p, inv_size[label]), label};
    if (!last_key || !(key == *last_key)) {
      last_key = key;
      const std::uint32_t* remembered = recent.find(key);
      std::uint32_t slot = remembered ? *remembered : 0;
      if (!remembered) {
        const auto [it, inserted] =
            slot_of.try_emplace(key, static_cast<std::uint32_t>(voxels.size()));
        if (inserted) voxels.push_back(Sum{key, Eigen::Vector3d::Zero(), 0.0, 0, i});
        slot = it->second;
        recent.remember(key, slot);
      }
      last = &voxels[slot];  // valid until the next insertion, which replaces it
    }
    Sum& s = *last;
    s.sum += p;
    if (cloud.hasTimes()) s.time_sum += cloud.times[i];
    ++s.count;
  }
}

// Scans of this many points are summed in two halves at once (the downsampling is on the path
// of every frame); the halves are the same however many threads run, and so are the sums.
constexpr std::size_t kHalvesFrom = 16384;

}  // namespace

LabeledCloud semanticVoxelDownsample(const LabeledCloud& cloud, double voxel_size,
                                     const std::array<double, kNumClasses>& class_factor,
                                     const SweepMotion* motion) {
  if (motion && motion->identity()) motion = nullptr;
  std::array<double, kNumClasses> inv_size{};
  for (int c = 0; c < kNumClasses; ++c)
    inv_size[c] = class_factor[c] > 0.0 ? 1.0 / (class_factor[c] * voxel_size) : 0.0;

  // Voxels in the order of their first points (deterministic output).
  const std::size_t n = cloud.size();
  RangeVoxels front, back;
  if (n < kHalvesFrom) {
    sumRange(cloud, 0, n, inv_size, motion, front);
  } else {
    tbb::parallel_invoke([&] { sumRange(cloud, 0, n / 2, inv_size, motion, front); },
                         [&] { sumRange(cloud, n / 2, n, inv_size, motion, back); });
  }
  std::vector<Sum>& voxels = front.voxels;
  for (const Sum& b : back.voxels) {
    const auto it = front.slot_of.find(b.key);
    if (it == front.slot_of.end()) {
      voxels.push_back(b);
      continue;
    }
    Sum& s = voxels[it->second];
    s.sum += b.sum;
    s.time_sum += b.time_sum;
    s.count += b.count;
  }

  LabeledCloud out;
  out.points.reserve(voxels.size());
  out.labels.reserve(voxels.size());
  for (const Sum& s : voxels) {
    out.points.push_back((s.sum / s.count).cast<float>());
    out.labels.push_back(cloud.hasLabels() ? cloud.labels[s.first] : std::uint8_t{kUnlabeled});
    if (cloud.hasTimes()) out.times.push_back(static_cast<float>(s.time_sum / s.count));
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
