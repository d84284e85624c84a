// Map pictures: PNG round trip, the legend lists exactly the classes present, the picture keeps
// the raster unscaled, the trajectory lands on its map position, the font draws.
#include <gtest/gtest.h>

#include "socc/render_request_t.hpp"
#include "socc/rgb_image.hpp"
#include "socc/tools/map_picture.hpp"

namespace {

using socc::Rgb;
using socc::RgbImage;

bool sameColor(Rgb a, Rgb b) {
  return a.r == b.r && a.g == b.g && a.b == b.b;
}

TEST(MapPicture, PngRoundTripKeepsPixels) {
  RgbImage image(7, 5, Rgb{10, 20, 30});
  image.set(6, 4, Rgb{200, 100, 0});
  const RgbImage back = socc::decodePng(socc::encodePng(image));
  ASSERT_EQ(back.width, 7);
  ASSERT_EQ(back.height, 5);
  EXPECT_EQ(back.rgb, image.rgb);
  EXPECT_THROW(socc::decodePng({1, 2, 3}), std::runtime_error);
}

TEST(MapPicture, LegendHasOnlyPresentClasses) {
  RgbImage raster(20, 10, Rgb{0, 0, 0});
  raster.set(1, 1, socc::classColor(socc::kRoad));
  raster.set(2, 1, socc::classColor(socc::kCar));
  raster.set(3, 1, socc::kUnlabeledVoxelColor);
  const std::vector<std::uint8_t> expected{socc::kCar, socc::kRoad, socc::kUnlabeled};
  EXPECT_EQ(socc::tools::presentClasses(raster), expected);
}

TEST(MapPicture, AutoPixelSizeGivesTheLongSide) {
  const double ps = socc::tools::autoPixelSize(240.0, 90.0);
  EXPECT_EQ(static_cast<int>(std::ceil(240.0 / ps)), socc::tools::kMapLongSidePixels);
  EXPECT_GE(socc::tools::kMapLongSidePixels, 1000);
}

TEST(MapPicture, TrackIsDrawnAtItsMapPosition) {
  RgbImage raster(400, 200, socc::classColor(socc::kRoad));
  socc::tools::PictureSpec spec;
  spec.mode = socc::render_request_t::MODE_CLASS;
  spec.x_min = -10.0;
  spec.y_min = -5.0;
  spec.pixel_size = 0.1;
  const Rgb cyan{0, 225, 255};
  spec.tracks.push_back({"estimate", cyan, {{0.0, 0.0}, {20.0, 0.0}}});
  const RgbImage picture = socc::tools::decorateMap(raster, spec);
  ASSERT_GT(picture.width, raster.width);
  ASSERT_GT(picture.height, raster.height);
  // Find the raster's top-left corner: the first road-coloured pixel.
  int ox = -1, oy = -1;
  for (int y = 0; y < picture.height && ox < 0; ++y)
    for (int x = 0; x < picture.width && ox < 0; ++x)
      if (sameColor(picture.at(x, y), socc::classColor(socc::kRoad))) ox = x, oy = y;
  ASSERT_GE(ox, 0);
  // (10 m, 0 m) -> column 200, row 200 - 50 = 150 of the raster.
  EXPECT_TRUE(sameColor(picture.at(ox + 200, oy + 150), cyan));
  EXPECT_TRUE(sameColor(picture.at(ox + 200, oy + 120), socc::classColor(socc::kRoad)));
}

TEST(MapPicture, TextDrawsInkInsideItsBox) {
  RgbImage image(100, 30, Rgb{255, 255, 255});
  socc::tools::drawText(image, 2, 2, "Road 10 m", Rgb{0, 0, 0}, 2);
  int ink = 0;
  for (int y = 0; y < image.height; ++y)
    for (int x = 0; x < image.width; ++x) ink += image.at(x, y).r == 0 ? 1 : 0;
  EXPECT_GT(ink, 50);
  EXPECT_EQ(socc::tools::textWidth("Road 10 m", 2), (9 * 6 - 1) * 2);
  EXPECT_EQ(image.at(2 + socc::tools::textWidth("Road 10 m", 2) + 1, 10).r, 255);
}

}  // namespace
