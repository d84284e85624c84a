#pragma once
// Map pictures for people: the server's top-down render (RENDER) decorated client-side with a
// title, a legend of the classes present, an occupancy colour bar, a scale bar and trajectories.
// The server keeps rendering plain rasters; every annotation is drawn here, once.
#include <Eigen/Core>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "socc/rgb_image.hpp"

namespace socc::tools {

/// Long side [px] of the map raster when the caller gives no pixel size.
inline constexpr int kMapLongSidePixels = 1200;

/// Pixel size [m] that draws a width x height [m] region with kMapLongSidePixels on its long side.
double autoPixelSize(double width_m, double height_m);

/// Built-in 5x7 bitmap font (upper case; lower case is drawn as upper case), scaled by `scale`.
int textWidth(std::string_view text, int scale);
inline int textHeight(int scale) {
  return 7 * scale;
}
void drawText(RgbImage& image, int x, int y, std::string_view text, Rgb color, int scale);

/// Classes whose colour occurs in a class-mode render, in class order; kUnlabeled when
/// unlabelled occupied voxels are shown.
std::vector<std::uint8_t> presentClasses(const RgbImage& class_render);

/// A trajectory to draw: xy positions in the map frame. A reference drawn wider under an
/// estimate stays visible as a casing where the estimate lies exactly on it.
struct PictureTrack {
  std::string name;
  Rgb color;
  std::vector<Eigen::Vector2d> xy;
  double radius = 1.8;  // [px] half the line width
};

struct PictureSpec {
  int mode = 0;        // render_request_t mode of the raster
  double x_min = 0.0;  // map frame of the raster's bottom-left corner [m]
  double y_min = 0.0;
  double pixel_size = 0.0;  // [m]
  std::string title;
  std::vector<PictureTrack> tracks;  // drawn in order: the last is on top
};

/// The decorated picture: raster, legend (classes present or occupancy colour bar), scale bar,
/// tracks with start markers, axis note. The raster's pixels are copied unscaled.
RgbImage decorateMap(const RgbImage& raster, const PictureSpec& spec);

}  // namespace socc::tools
