// Top-down rendering (render_request_t): each voxel is splatted onto the pixels its footprint
// covers; a pixel keeps the top-most occupied voxel and the highest occupancy probability of
// the observed voxels above it (the occupancy image: a wall shows even over free ground).
#include <cmath>
#include <limits>
#include <stdexcept>

#include "map_impl.hpp"
#include "region.hpp"
#include "socc/render_request_t.hpp"

namespace socc::map {
namespace {

constexpr int kMaxImageSide = 4096;

struct Column {
  double top_z = -std::numeric_limits<double>::infinity();
  double max_probability = -1.0;  // < 0: no observed voxel in this column
  std::uint8_t label = kUnlabeled;
  bool occupied = false;
};

Rgb heightColor(double t) {  // blue (low) -> green -> red (high)
  t = std::clamp(t, 0.0, 1.0);
  const auto u8 = [](double v) { return static_cast<std::uint8_t>(std::lround(v * 255.0)); };
  if (t < 0.5) return {0, u8(2.0 * t), u8(1.0 - 2.0 * t)};
  return {u8(2.0 * t - 1.0), u8(2.0 - 2.0 * t), 0};
}

Rgb pixelColor(const Column& c, int mode, double zmin, double zmax) {
  if (mode == render_request_t::MODE_OCCUPANCY)
    return c.max_probability < 0.0 ? kUnknownSpaceColor : occupancyColor(c.max_probability);
  if (!c.occupied) return {0, 0, 0};
  if (mode == render_request_t::MODE_HEIGHT)
    return heightColor(zmax > zmin ? (c.top_z - zmin) / (zmax - zmin) : 0.5);
  return c.label == kUnlabeled ? kUnlabeledVoxelColor : classColor(c.label);
}

void checkRenderArguments(const Eigen::Vector3d& box_min, const Eigen::Vector3d& box_max,
                          double pixel_size, int mode, double occupancy_threshold) {
  if (!box_min.allFinite() || !box_max.allFinite() || box_max.x() <= box_min.x() ||
      box_max.y() <= box_min.y() || box_max.z() < box_min.z())
    throw std::invalid_argument("render: box needs finite corners with box_min < box_max");
  if (!std::isfinite(pixel_size) || pixel_size < 0.0)
    throw std::invalid_argument("render: pixel_size must be finite and >= 0");
  if (mode != render_request_t::MODE_CLASS && mode != render_request_t::MODE_OCCUPANCY &&
      mode != render_request_t::MODE_HEIGHT)
    throw std::invalid_argument("render: unknown mode " + std::to_string(mode));
  if (!(occupancy_threshold >= 0.0 && occupancy_threshold <= 1.0))
    throw std::invalid_argument("render: occupancy_threshold must be in [0, 1]");
}

// The image's pixels over the box's x-y extent; row 0 of the image is the box's top (+y).
struct PixelGrid {
  double x0, y0, pixel;
  int width, height;

  static PixelGrid over(const Eigen::Vector3d& box_min, const Eigen::Vector3d& box_max,
                        double pixel) {
    const double wd = std::ceil((box_max.x() - box_min.x()) / pixel);
    const double hd = std::ceil((box_max.y() - box_min.y()) / pixel);
    if (wd > kMaxImageSide || hd > kMaxImageSide)
      throw std::invalid_argument("render: image would be " + std::to_string(wd) + " x " +
                                  std::to_string(hd) + " pixels (max " +
                                  std::to_string(kMaxImageSide) + " per side)");
    return {box_min.x(), box_min.y(), pixel, std::max(1, static_cast<int>(wd)),
            std::max(1, static_cast<int>(hd))};
  }
  /// The pixels [first, last] the interval [lo, hi) covers along an axis starting at origin.
  std::pair<int, int> range(double lo, double hi, double origin, int n) const {
    const int a = std::max(0, clampedFloor((lo - origin) / pixel));
    const int b = std::min(n - 1, clampedFloor(std::nextafter((hi - origin) / pixel, -1e300)));
    return {a, b};
  }
  std::size_t columnOf(int px, int py) const {
    return static_cast<std::size_t>(height - 1 - py) * width + px;
  }
};

/// Splats every observed voxel of the box onto the pixels its footprint covers.
std::vector<Column> splatVoxels(const Grid& grid, const IndexBox& box, const PixelGrid& pixels,
                                double occupancy_threshold) {
  const VoxelGeometry geometry = grid.geometry();
  const double vs = geometry.size;
  std::vector<Column> columns(static_cast<std::size_t>(pixels.width) * pixels.height);
  for (const BlockKey& key : grid.blocksIn(box.blockLo(), box.blockHi())) {
    const Block& block = *grid.find(key);
    for (int local = 0; local < kBlockVoxels; ++local) {
      if (!block.observed[local]) continue;
      const VoxelIndex v = voxelOf(key, local);
      if ((v.array() < box.lo.array()).any() || (v.array() > box.hi.array()).any()) continue;
      const double p = probability(block.log_odds[local]);
      const bool occupied = p >= occupancy_threshold;
      const double z = geometry.centre(v).z();
      const VoxelStats* stats = block.statsOf(local);
      const auto [x0, x1] = pixels.range(v.x() * vs, (v.x() + 1) * vs, pixels.x0, pixels.width);
      const auto [y0, y1] = pixels.range(v.y() * vs, (v.y() + 1) * vs, pixels.y0, pixels.height);
      for (int py = y0; py <= y1; ++py) {
        for (int px = x0; px <= x1; ++px) {
          Column& c = columns[pixels.columnOf(px, py)];
          c.max_probability = std::max(c.max_probability, p);
          if (occupied && z > c.top_z) {
            c.top_z = z;
            c.occupied = true;
            c.label = stats != nullptr ? stats->label : std::uint8_t{kUnlabeled};
          }
        }
      }
    }
  }
  return columns;
}

}  // namespace

SemanticOccupancyMap::Image SemanticOccupancyMap::render(const Eigen::Vector3d& box_min,
                                                         const Eigen::Vector3d& box_max,
                                                         double pixel_size, int mode,
                                                         double occupancy_threshold) const {
  checkRenderArguments(box_min, box_max, pixel_size, mode, occupancy_threshold);
  const double vs = impl_->config.voxel_size;
  const PixelGrid pixels = PixelGrid::over(box_min, box_max, pixel_size > 0.0 ? pixel_size : vs);
  const std::vector<Column> columns =
      splatVoxels(impl_->grid, IndexBox::of(box_min, box_max, vs), pixels, occupancy_threshold);
  Image img;
  img.width = pixels.width;
  img.height = pixels.height;
  img.rgb.resize(columns.size() * 3);
  for (int y = 0; y < img.height; ++y)
    for (int x = 0; x < img.width; ++x)
      img.set(x, y,
              pixelColor(columns[static_cast<std::size_t>(y) * img.width + x], mode, box_min.z(),
                         box_max.z()));
  return img;
}

}  // namespace socc::map
