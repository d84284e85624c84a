#pragma once
// Synthetic scans for the map tests.
#include <Eigen/Geometry>
#include <random>

#include "service/chunk_reply.hpp"
#include "socc/labels.hpp"
#include "socc/map/semantic_occupancy_map.hpp"

namespace socc::map::test {

/// A wall x = wall_x spanning y, z in [-half, half] with the given label, seen from the origin.
inline LabeledCloud wall(double wall_x, double half, double step, std::uint8_t label) {
  LabeledCloud c;
  for (double y = -half; y <= half; y += step)
    for (double z = -half; z <= half; z += step) {
      c.points.emplace_back(static_cast<float>(wall_x), static_cast<float>(y),
                            static_cast<float>(z));
      c.labels.push_back(label);
    }
  return c;
}

inline void append(LabeledCloud& a, const LabeledCloud& b) {
  a.points.insert(a.points.end(), b.points.begin(), b.points.end());
  a.labels.insert(a.labels.end(), b.labels.begin(), b.labels.end());
}

/// A random cloud of n points in a cube around the origin with random labels.
inline LabeledCloud randomCloud(std::size_t n, double half, std::uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> u(static_cast<float>(-half), static_cast<float>(half));
  std::uniform_int_distribution<int> label(0, 19);
  LabeledCloud c;
  for (std::size_t i = 0; i < n; ++i) {
    c.points.emplace_back(u(rng), u(rng), u(rng));
    c.labels.push_back(static_cast<std::uint8_t>(label(rng)));
  }
  return c;
}

/// The query's answer in its wire form, as GET_CHUNK sends it.
inline chunk_reply_t query(const SemanticOccupancyMap& map, const ChunkQuery& q) {
  return service::queryChunkReply(map, q);
}

}  // namespace socc::map::test
