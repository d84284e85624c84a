#pragma once
// A small direct-mapped memo in front of a voxel table (key -> slot). A scan visits its voxels
// in runs and, sweep column by sweep column (the point order of spinning sensors that fire all
// rings at once), in the same order again: most lookups are answered here from the L1 cache
// instead of probing a table of thousands of voxels.
#include <array>
#include <cstddef>
#include <cstdint>

namespace socc::odom {

template <typename Key, typename Hash, std::size_t N = 256>
class RecentSlots {
  static_assert((N & (N - 1)) == 0, "N must be a power of two");

 public:
  /// The slot remembered for key, or nullptr.
  const std::uint32_t* find(const Key& key) const {
    const Entry& e = entries_[index(key)];
    return e.used && e.key == key ? &e.slot : nullptr;
  }
  void remember(const Key& key, std::uint32_t slot) { entries_[index(key)] = {key, slot, true}; }

 private:
  struct Entry {
    Key key{};
    std::uint32_t slot = 0;
    bool used = false;
  };
  static std::size_t index(const Key& key) { return Hash{}(key) & (N - 1); }

  std::array<Entry, N> entries_{};
};

}  // namespace socc::odom
