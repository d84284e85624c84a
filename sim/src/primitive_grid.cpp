#include "socc/sim/primitive_grid.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace socc::sim {

PrimitiveGrid::PrimitiveGrid(std::vector<Primitive> primitives, double cell_size)
    : primitives_(std::move(primitives)), cell_size_(cell_size) {
  if (!(cell_size > 0.0)) throw std::invalid_argument("grid cell size must be > 0");
  if (primitives_.empty()) return;
  Eigen::AlignedBox3d bounds;
  std::vector<Eigen::AlignedBox3d> boxes;
  boxes.reserve(primitives_.size());
  for (const auto& p : primitives_) {
    boxes.push_back(boundingBox(p.shape));
    bounds.extend(boxes.back());
  }
  origin_ = bounds.min().head<2>();
  const Eigen::Vector2d extent = bounds.max().head<2>() - origin_;
  nx_ = static_cast<int>(std::floor(extent.x() / cell_size_)) + 1;
  ny_ = static_cast<int>(std::floor(extent.y() / cell_size_)) + 1;
  if (static_cast<double>(nx_) * ny_ > 1e8) throw std::runtime_error("world too large for grid");
  cells_.resize(static_cast<std::size_t>(nx_) * static_cast<std::size_t>(ny_));
  cell_top_.assign(cells_.size(), -kInf);
  const auto index = [&](double v, double o, int n) {
    return std::clamp(static_cast<int>(std::floor((v - o) / cell_size_)), 0, n - 1);
  };
  for (std::size_t i = 0; i < boxes.size(); ++i) {
    const int x0 = index(boxes[i].min().x(), origin_.x(), nx_);
    const int x1 = index(boxes[i].max().x(), origin_.x(), nx_);
    const int y0 = index(boxes[i].min().y(), origin_.y(), ny_);
    const int y1 = index(boxes[i].max().y(), origin_.y(), ny_);
    for (int iy = y0; iy <= y1; ++iy) {
      for (int ix = x0; ix <= x1; ++ix) {
        cells_[cellIndex(ix, iy)].push_back(static_cast<std::uint32_t>(i));
        cell_top_[cellIndex(ix, iy)] = std::max(cell_top_[cellIndex(ix, iy)], boxes[i].max().z());
      }
    }
  }
}

std::optional<Hit> PrimitiveGrid::cast(const Ray& ray, double max_range) const {
  if (cells_.empty()) return std::nullopt;
  const Eigen::Vector2d o = ray.origin.head<2>();
  const Eigen::Vector2d d = ray.direction.head<2>();
  const Eigen::Vector2d lo = origin_;
  const Eigen::Vector2d hi = origin_ + cell_size_ * Eigen::Vector2d(nx_, ny_);

  // Clip the ray to the grid's footprint.
  double t_enter = 0.0;
  double t_leave = max_range;
  for (int a = 0; a < 2; ++a) {
    if (std::abs(d[a]) < 1e-12) {
      if (o[a] < lo[a] || o[a] > hi[a]) return std::nullopt;
      continue;
    }
    double t0 = (lo[a] - o[a]) / d[a];
    double t1 = (hi[a] - o[a]) / d[a];
    if (t0 > t1) std::swap(t0, t1);
    t_enter = std::max(t_enter, t0);
    t_leave = std::min(t_leave, t1);
  }
  if (t_enter > t_leave) return std::nullopt;

  const Eigen::Vector2d start = o + t_enter * d;
  int ix = std::clamp(static_cast<int>(std::floor((start.x() - lo.x()) / cell_size_)), 0, nx_ - 1);
  int iy = std::clamp(static_cast<int>(std::floor((start.y() - lo.y()) / cell_size_)), 0, ny_ - 1);
  const int step_x = d.x() > 0 ? 1 : -1;
  const int step_y = d.y() > 0 ? 1 : -1;
  const auto next_boundary = [&](int i, int step, int axis) {
    if (std::abs(d[axis]) < 1e-12) return kInf;
    const double edge = lo[axis] + cell_size_ * (i + (step > 0 ? 1 : 0));
    return (edge - o[axis]) / d[axis];
  };
  double t_next_x = next_boundary(ix, step_x, 0);
  double t_next_y = next_boundary(iy, step_y, 1);
  const double dt_x = std::abs(d.x()) < 1e-12 ? kInf : cell_size_ / std::abs(d.x());
  const double dt_y = std::abs(d.y()) < 1e-12 ? kInf : cell_size_ / std::abs(d.y());

  Hit best{max_range, 0};
  bool found = false;
  // Large primitives span several cells: remember the last few tested to skip repeats.
  constexpr std::size_t kMailbox = 16;
  std::uint32_t tested[kMailbox];
  std::size_t n_tested = 0;
  const auto already_tested = [&](std::uint32_t id) {
    for (std::size_t k = 0; k < std::min(n_tested, kMailbox); ++k)
      if (tested[k] == id) return true;
    tested[n_tested++ % kMailbox] = id;
    return false;
  };
  double cell_entry = t_enter;
  while (true) {
    const double cell_exit = std::min(t_next_x, t_next_y);
    const std::size_t c = cellIndex(ix, iy);
    const double z_low =
        ray.origin.z() +
        std::min(cell_entry * ray.direction.z(), std::min(cell_exit, t_leave) * ray.direction.z());
    if (z_low <= cell_top_[c]) {
      for (const std::uint32_t i : cells_[c]) {
        if (already_tested(i)) continue;
        const auto t = intersect(ray, primitives_[i].shape);
        if (t && *t < best.range) {
          best = {*t, primitives_[i].label};
          found = true;
        }
      }
    }
    cell_entry = cell_exit;
    if ((found && best.range <= cell_exit) || cell_exit > t_leave) break;
    if (t_next_x < t_next_y) {
      ix += step_x;
      t_next_x += dt_x;
      if (ix < 0 || ix >= nx_) break;
    } else {
      iy += step_y;
      t_next_y += dt_y;
      if (iy < 0 || iy >= ny_) break;
    }
  }
  if (!found) return std::nullopt;
  return best;
}

}  // namespace socc::sim
