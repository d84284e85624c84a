// PNG encoding with libpng's simplified API (no setjmp error handling needed).
#include <png.h>

#include <stdexcept>

#include "socc/map/semantic_occupancy_map.hpp"

namespace socc::map {

std::vector<std::uint8_t> encodePng(const SemanticOccupancyMap::Image& image) {
  if (image.width <= 0 || image.height <= 0 ||
      image.rgb.size() != static_cast<std::size_t>(image.width) * image.height * 3)
    throw std::invalid_argument("encodePng: image size does not match its pixel buffer");
  png_image png{};
  png.version = PNG_IMAGE_VERSION;
  png.width = static_cast<png_uint_32>(image.width);
  png.height = static_cast<png_uint_32>(image.height);
  png.format = PNG_FORMAT_RGB;
  png_alloc_size_t size = 0;
  // First call computes the size, second writes.
  if (!png_image_write_to_memory(&png, nullptr, &size, 0, image.rgb.data(), 0, nullptr))
    throw std::runtime_error(std::string("encodePng: ") + png.message);
  std::vector<std::uint8_t> out(size);
  if (!png_image_write_to_memory(&png, out.data(), &size, 0, image.rgb.data(), 0, nullptr))
    throw std::runtime_error(std::string("encodePng: ") + png.message);
  out.resize(size);
  png_image_free(&png);
  return out;
}

}  // namespace socc::map
