#pragma once
// A uniform 2D grid (over x, y) of primitive bounding boxes: rays walk the cells they cross
// (2D DDA) and stop at the first cell that ends beyond the nearest hit found so far. Worlds are
// 2.5D (streets, corridors), so a horizontal grid prunes almost everything.
#include <cstdint>
#include <optional>
#include <vector>

#include "socc/sim/primitives.hpp"

namespace socc::sim {

struct Hit {
  double range = 0.0;
  std::uint16_t label = 0;
  const Shape* shape = nullptr;  // the primitive hit (none for planes); lives with the grid
};

class PrimitiveGrid {
 public:
  PrimitiveGrid() = default;
  PrimitiveGrid(std::vector<Primitive> primitives, double cell_size);

  /// Nearest hit with range < max_range.
  std::optional<Hit> cast(const Ray& ray, double max_range) const;
  const std::vector<Primitive>& primitives() const { return primitives_; }

 private:
  std::size_t cellIndex(int ix, int iy) const {
    return static_cast<std::size_t>(iy) * static_cast<std::size_t>(nx_) +
           static_cast<std::size_t>(ix);
  }

  std::vector<Primitive> primitives_;
  std::vector<std::vector<std::uint32_t>> cells_;
  std::vector<double> cell_top_;  // highest bounding-box top per cell: rays above it skip it
  Eigen::Vector2d origin_ = Eigen::Vector2d::Zero();
  double cell_size_ = 1.0;
  int nx_ = 0;
  int ny_ = 0;
};

}  // namespace socc::sim
