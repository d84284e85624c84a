#include "socc/sim/primitive_grid.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <utility>

namespace socc::sim {

namespace {

// A direction component below this counts as parallel to the axis.
constexpr double kParallelEps = 1e-12;

// [t_enter, t_leave] of the 2D ray o + t d inside the box [lo, hi], within [0, max_range].
std::optional<std::pair<double, double>> clipToFootprint(const Eigen::Vector2d& o,
                                                         const Eigen::Vector2d& d,
                                                         const Eigen::Vector2d& lo,
                                                         const Eigen::Vector2d& hi,
                                                         double max_range) {
  double t_enter = 0.0;
  double t_leave = max_range;
  for (int a = 0; a < 2; ++a) {
    if (std::abs(d[a]) < kParallelEps) {
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
  return std::make_pair(t_enter, t_leave);
}

// 2D DDA (Amanatides & Woo) over an nx x ny grid of square cells from lo: the current cell and
// the ray parameters at which the next x and y cell boundaries are crossed.
struct CellWalk {
  CellWalk(const Eigen::Vector2d& o, const Eigen::Vector2d& d, const Eigen::Vector2d& lo,
           double cell_size, double t_start, int nx, int ny) {
    const Eigen::Vector2d start = o + t_start * d;
    ix = std::clamp(static_cast<int>(std::floor((start.x() - lo.x()) / cell_size)), 0, nx - 1);
    iy = std::clamp(static_cast<int>(std::floor((start.y() - lo.y()) / cell_size)), 0, ny - 1);
    step_x = d.x() > 0 ? 1 : -1;
    step_y = d.y() > 0 ? 1 : -1;
    const auto next_boundary = [&](int i, int step, int axis) {
      if (std::abs(d[axis]) < kParallelEps) return kInf;
      const double edge = lo[axis] + cell_size * (i + (step > 0 ? 1 : 0));
      return (edge - o[axis]) / d[axis];
    };
    t_next_x = next_boundary(ix, step_x, 0);
    t_next_y = next_boundary(iy, step_y, 1);
    dt_x = std::abs(d.x()) < kParallelEps ? kInf : cell_size / std::abs(d.x());
    dt_y = std::abs(d.y()) < kParallelEps ? kInf : cell_size / std::abs(d.y());
  }

  double exit() const { return std::min(t_next_x, t_next_y); }

  // Steps into the next cell; false when that leaves the grid.
  bool advance(int nx, int ny) {
    if (t_next_x < t_next_y) {
      ix += step_x;
      t_next_x += dt_x;
      return ix >= 0 && ix < nx;
    }
    iy += step_y;
    t_next_y += dt_y;
    return iy >= 0 && iy < ny;
  }

  int ix = 0, iy = 0, step_x = 1, step_y = 1;
  double t_next_x = kInf, t_next_y = kInf, dt_x = kInf, dt_y = kInf;
};

// Large primitives span several cells: remembers the last few tested to skip repeats.
class RecentIds {
 public:
  // True when id was tested already; otherwise remembers it.
  bool testedBefore(std::uint32_t id) {
    for (std::size_t k = 0; k < std::min(n_, kSize); ++k)
      if (ids_[k] == id) return true;
    ids_[n_++ % kSize] = id;
    return false;
  }

 private:
  static constexpr std::size_t kSize = 16;
  std::uint32_t ids_[kSize];
  std::size_t n_ = 0;
};

// Intersects the ray with the cell's primitives not tested yet; true when one is nearer than
// best (which it then replaces).
bool nearerHitInCell(const Ray& ray, const std::vector<std::uint32_t>& cell,
                     const std::vector<Primitive>& primitives, RecentIds& tested, Hit& best) {
  bool nearer = false;
  for (const std::uint32_t i : cell) {
    if (tested.testedBefore(i)) continue;
    const auto t = intersect(ray, primitives[i].shape);
    if (t && *t < best.range) {
      best = {*t, primitives[i].label, &primitives[i].shape};
      nearer = true;
    }
  }
  return nearer;
}

}  // namespace

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
  const Eigen::Vector2d hi = origin_ + cell_size_ * Eigen::Vector2d(nx_, ny_);
  const auto span = clipToFootprint(o, d, origin_, hi, max_range);
  if (!span) return std::nullopt;
  const auto [t_enter, t_leave] = *span;

  CellWalk walk(o, d, origin_, cell_size_, t_enter, nx_, ny_);
  Hit best{max_range, 0};
  bool found = false;
  RecentIds tested;
  double cell_entry = t_enter;
  while (true) {
    const double cell_exit = walk.exit();
    const std::size_t c = cellIndex(walk.ix, walk.iy);
    const double z_low =
        ray.origin.z() +
        std::min(cell_entry * ray.direction.z(), std::min(cell_exit, t_leave) * ray.direction.z());
    if (z_low <= cell_top_[c] && nearerHitInCell(ray, cells_[c], primitives_, tested, best))
      found = true;
    cell_entry = cell_exit;
    if ((found && best.range <= cell_exit) || cell_exit > t_leave) break;
    if (!walk.advance(nx_, ny_)) break;
  }
  if (!found) return std::nullopt;
  return best;
}

}  // namespace socc::sim
