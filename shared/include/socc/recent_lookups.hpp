#pragma once
// A small direct-mapped memo in front of a voxel or block table (key -> value: a slot, a
// pointer). A scan visits its voxels in runs and, sweep column by sweep column (the point order
// of spinning sensors that fire all rings at once), in the same order again, and rays from one
// origin keep crossing the same blocks: most lookups are answered here from the L1 cache instead
// of probing a table of thousands of entries.
#include <array>
#include <cstddef>

namespace socc {

template <typename Key, typename Value, typename Hash, std::size_t N = 256>
class RecentLookups {
  static_assert((N & (N - 1)) == 0, "N must be a power of two");

 public:
  /// The value remembered for key, or nullptr.
  const Value* find(const Key& key) const {
    const Entry& e = entries_[index(key)];
    return e.used && e.key == key ? &e.value : nullptr;
  }
  void remember(const Key& key, const Value& value) { entries_[index(key)] = {key, value, true}; }

 private:
  struct Entry {
    Key key{};
    Value value{};
    bool used = false;
  };
  static std::size_t index(const Key& key) { return Hash{}(key) & (N - 1); }

  std::array<Entry, N> entries_{};
};

}  // namespace socc
