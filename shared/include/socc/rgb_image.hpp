#pragma once
// An 8-bit RGB raster, its PNG encoding (libpng) and the occupancy colour scale. Shared so the
// server's renderer and the CLI's picture decoration use one codec and one colour scale.
#include <cstdint>
#include <vector>

#include "socc/labels.hpp"

namespace socc {

struct RgbImage {
  int width = 0, height = 0;
  std::vector<std::uint8_t> rgb;  // width * height * 3, row-major, top row first

  RgbImage() = default;
  RgbImage(int w, int h, Rgb fill);
  bool contains(int x, int y) const { return x >= 0 && y >= 0 && x < width && y < height; }
  Rgb at(int x, int y) const;
  void set(int x, int y, Rgb c);  // ignores pixels outside the image
  void fillRect(int x0, int y0, int w, int h, Rgb c);
  /// Copies src with its top-left corner at (x, y), clipped to this image.
  void paste(const RgbImage& src, int x, int y);
};

/// PNG bytes of an image. Throws std::invalid_argument if the buffer does not match the size.
std::vector<std::uint8_t> encodePng(const RgbImage& image);
/// Decodes any PNG to RGB. Throws std::runtime_error on malformed data.
RgbImage decodePng(const std::vector<std::uint8_t>& png);

/// Occupancy probability in [0, 1] as a colour: free white through grey to occupied black.
Rgb occupancyColor(double probability);
/// Occupied voxels without a class in class images.
inline constexpr Rgb kUnlabeledVoxelColor{128, 128, 128};
/// Never-observed space in occupancy images: a blue grey no probability maps to.
inline constexpr Rgb kUnknownSpaceColor{150, 170, 205};

}  // namespace socc
