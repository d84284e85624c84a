#include "socc/map/ray_traversal.hpp"

#include <cmath>
#include <limits>

namespace socc::map {

void traverseRay(const Eigen::Vector3d& from, const Eigen::Vector3d& to, double voxel_size,
                 std::vector<VoxelIndex>& out) {
  const double inv = 1.0 / voxel_size;
  const Eigen::Vector3d a = from * inv;  // in voxel units
  const Eigen::Vector3d b = to * inv;
  VoxelIndex v = a.array().floor().cast<int>();
  const VoxelIndex end = b.array().floor().cast<int>();
  const Eigen::Vector3d d = b - a;

  int step[3];
  double t_max[3];
  double t_delta[3];
  int total = 0;
  constexpr double kInf = std::numeric_limits<double>::infinity();
  for (int i = 0; i < 3; ++i) {
    step[i] = end[i] > v[i] ? 1 : (end[i] < v[i] ? -1 : 0);
    total += std::abs(end[i] - v[i]);
    if (step[i] == 0) {  // this axis never moves (also covers d[i] == 0)
      t_max[i] = kInf;
      t_delta[i] = kInf;
      continue;
    }
    const double boundary = step[i] > 0 ? v[i] + 1.0 : static_cast<double>(v[i]);
    t_max[i] = (boundary - a[i]) / d[i];
    t_delta[i] = 1.0 / std::abs(d[i]);
  }

  // The walk takes exactly |end - start|_1 steps; an axis that reached its end index gets
  // t_max = inf, so rounding can never make it overshoot.
  const std::size_t first = out.size();
  out.resize(first + static_cast<std::size_t>(total) + 1);
  VoxelIndex* o = out.data() + first;
  *o++ = v;
  for (int k = 0; k < total; ++k) {
    const int axis =
        t_max[0] < t_max[1] ? (t_max[0] < t_max[2] ? 0 : 2) : (t_max[1] < t_max[2] ? 1 : 2);
    v[axis] += step[axis];
    t_max[axis] = v[axis] == end[axis] ? kInf : t_max[axis] + t_delta[axis];
    *o++ = v;
  }
}

}  // namespace socc::map
