#pragma once
// Reference clouds of ../shared/data/raw_sensors (nebula's ground_truth_*.pcd: binary x y z
// float32) and a nearest-neighbour check on a 1 cm hash grid.
#include <Eigen/Core>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <unordered_map>
#include <vector>

namespace socc::sensors::test {

inline std::vector<Eigen::Vector3f> readBinaryXyzPcd(const std::filesystem::path& file) {
  std::ifstream in(file, std::ios::binary);
  std::string line;
  std::size_t points = 0;
  while (std::getline(in, line)) {
    if (line.rfind("POINTS", 0) == 0) points = std::stoul(line.substr(7));
    if (line.rfind("FIELDS", 0) == 0 && line != "FIELDS x y z")
      throw std::runtime_error("unexpected " + line);
    if (line.rfind("DATA", 0) == 0) {
      if (line != "DATA binary") throw std::runtime_error("unexpected " + line);
      break;
    }
  }
  std::vector<Eigen::Vector3f> cloud(points);
  for (Eigen::Vector3f& p : cloud) in.read(reinterpret_cast<char*>(p.data()), 12);
  if (!in) throw std::runtime_error(file.string() + ": short");
  return cloud;
}

/// Fraction of `points` that have a point of `reference` within `radius` (radius <= cell size).
inline double fractionWithin(const std::vector<Eigen::Vector3f>& points,
                             const std::vector<Eigen::Vector3f>& reference, float radius) {
  const float cell = radius;
  auto key = [cell](int x, int y, int z) {
    return (static_cast<std::int64_t>(x) * 73856093) ^ (static_cast<std::int64_t>(y) * 19349663) ^
           (static_cast<std::int64_t>(z) * 83492791);
  };
  std::unordered_multimap<std::int64_t, Eigen::Vector3f> grid;
  for (const Eigen::Vector3f& r : reference)
    grid.emplace(
        key(static_cast<int>(std::floor(r.x() / cell)), static_cast<int>(std::floor(r.y() / cell)),
            static_cast<int>(std::floor(r.z() / cell))),
        r);
  std::size_t hits = 0;
  for (const Eigen::Vector3f& p : points) {
    const int cx = static_cast<int>(std::floor(p.x() / cell)),
              cy = static_cast<int>(std::floor(p.y() / cell)),
              cz = static_cast<int>(std::floor(p.z() / cell));
    bool found = false;
    for (int dx = -1; dx <= 1 && !found; ++dx)
      for (int dy = -1; dy <= 1 && !found; ++dy)
        for (int dz = -1; dz <= 1 && !found; ++dz) {
          const auto range = grid.equal_range(key(cx + dx, cy + dy, cz + dz));
          for (auto it = range.first; it != range.second && !found; ++it)
            found = (it->second - p).norm() <= radius;
        }
    if (found) ++hits;
  }
  return points.empty() ? 0.0 : static_cast<double>(hits) / static_cast<double>(points.size());
}

}  // namespace socc::sensors::test
