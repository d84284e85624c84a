// Decoration of map rasters (see map_picture.hpp): layout, legends, scale bar, tracks.
#include "socc/tools/map_picture.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>

#include "socc/render_request_t.hpp"

namespace socc::tools {
namespace {

constexpr Rgb kInk{25, 25, 25};
constexpr Rgb kPaper{255, 255, 255};
constexpr int kMargin = 20, kTitleScale = 3, kTextScale = 2, kPanelWidth = 330;
constexpr int kMapTop = 60, kRowPitch = 26, kSwatch = 18;

struct Rect {
  int x, y, w, h;
  bool contains(double px, double py) const {
    return px >= x && py >= y && px < x + w && py < y + h;
  }
};

// Largest 1, 2 or 5 x 10^k not above max_m: scale bars and colour-bar ticks read as round numbers.
double niceLength(double max_m) {
  const double decade = std::pow(10.0, std::floor(std::log10(max_m)));
  for (const double f : {5.0, 2.0, 1.0})
    if (f * decade <= max_m) return f * decade;
  return decade;
}

std::string formatMetres(double m) {
  char text[32];
  std::snprintf(text, sizeof(text), m >= 1.0 ? "%.0f M" : "%.2g M", m);
  return text;
}

void stampDisc(RgbImage& canvas, const Rect& clip, double cx, double cy, double r, Rgb color) {
  for (int y = static_cast<int>(std::floor(cy - r)); y <= static_cast<int>(std::ceil(cy + r)); ++y)
    for (int x = static_cast<int>(std::floor(cx - r)); x <= static_cast<int>(std::ceil(cx + r));
         ++x) {
      const double dx = x + 0.5 - cx, dy = y + 0.5 - cy;
      if (dx * dx + dy * dy <= r * r && clip.contains(x, y)) canvas.set(x, y, color);
    }
}

// A polyline of discs every half pixel; drawn twice (dark and wide, then coloured) so the track
// stays visible on every class colour and on white free space.
void drawPolyline(RgbImage& canvas, const Rect& clip, const std::vector<Eigen::Vector2d>& pts,
                  double radius, Rgb color) {
  for (std::size_t i = 0; i < pts.size(); ++i) {
    const Eigen::Vector2d a = pts[i], b = i + 1 < pts.size() ? pts[i + 1] : pts[i];
    const int steps = std::max(1, static_cast<int>(std::ceil(2.0 * (b - a).norm())));
    for (int s = 0; s <= steps; ++s) {
      const Eigen::Vector2d p = a + (b - a) * (static_cast<double>(s) / steps);
      stampDisc(canvas, clip, p.x(), p.y(), radius, color);
    }
  }
}

void drawTrack(RgbImage& canvas, const Rect& map, const PictureSpec& spec,
               const PictureTrack& track) {
  const double radius = track.radius;
  std::vector<Eigen::Vector2d> px;
  px.reserve(track.xy.size());
  for (const Eigen::Vector2d& p : track.xy)
    px.emplace_back(map.x + (p.x() - spec.x_min) / spec.pixel_size,
                    map.y + map.h - (p.y() - spec.y_min) / spec.pixel_size);
  if (px.empty()) return;
  drawPolyline(canvas, map, px, radius + 1.2, kInk);
  drawPolyline(canvas, map, px, radius, track.color);
  stampDisc(canvas, map, px.front().x(), px.front().y(), radius + 5.2, kInk);  // start marker
  stampDisc(canvas, map, px.front().x(), px.front().y(), radius + 4.0, track.color);
}

// Bottom-left of the map: a bar of about a fifth of the width in four alternating segments.
void drawScaleBar(RgbImage& canvas, const Rect& map, double pixel_size) {
  const double metres = niceLength(0.2 * map.w * pixel_size);
  const int bar = std::max(4, static_cast<int>(std::lround(metres / pixel_size)));
  const std::string label = formatMetres(metres);
  const int box_w = std::max(bar, textWidth(label, kTextScale)) + 20;
  const int box_h = textHeight(kTextScale) + 34;
  const int x = map.x + 12, y = map.y + map.h - box_h - 12;
  canvas.fillRect(x, y, box_w, box_h, kPaper);
  drawText(canvas, x + 10, y + 8, label, kInk, kTextScale);
  const int bar_y = y + 14 + textHeight(kTextScale);
  canvas.fillRect(x + 10 - 1, bar_y - 1, bar + 2, 12, kInk);
  for (int s = 0; s < 4; ++s)
    if (s % 2 == 1) canvas.fillRect(x + 10 + s * bar / 4, bar_y + 1, bar / 4, 8, kPaper);
}

int drawSwatchRow(RgbImage& canvas, int x, int y, Rgb color, std::string_view name) {
  canvas.fillRect(x - 1, y - 1, kSwatch + 2, kSwatch + 2, kInk);
  canvas.fillRect(x, y, kSwatch, kSwatch, color);
  drawText(canvas, x + kSwatch + 12, y + (kSwatch - textHeight(kTextScale)) / 2, name, kInk,
           kTextScale);
  return y + kRowPitch;
}

int drawClassLegend(RgbImage& canvas, int x, int y, const RgbImage& raster) {
  drawText(canvas, x, y, "CLASSES", kInk, kTextScale);
  y += kRowPitch + 4;
  for (const std::uint8_t c : presentClasses(raster))
    y = drawSwatchRow(canvas, x, y, c == kUnlabeled ? kUnlabeledVoxelColor : classColor(c),
                      c == kUnlabeled ? "unlabeled" : className(c));
  return drawSwatchRow(canvas, x, y, Rgb{0, 0, 0}, "no occupied voxel");
}

// Vertical bar, probability 1 at the top, ticks every 0.25: the occupancy image's scale.
int drawOccupancyBar(RgbImage& canvas, int x, int y) {
  drawText(canvas, x, y, "OCCUPANCY P", kInk, kTextScale);
  y += kRowPitch + 4;
  constexpr int kBarH = 300, kBarW = 30;
  canvas.fillRect(x - 1, y - 1, kBarW + 2, kBarH + 2, kInk);
  for (int row = 0; row < kBarH; ++row)
    canvas.fillRect(x, y + row, kBarW, 1, occupancyColor(1.0 - (row + 0.5) / kBarH));
  for (int tick = 0; tick <= 4; ++tick) {
    const int ty = y + (kBarH - 1) * (4 - tick) / 4;
    canvas.fillRect(x + kBarW + 1, ty, 8, 2, kInk);
    char label[8];
    std::snprintf(label, sizeof(label), "%.2f", tick / 4.0);
    drawText(canvas, x + kBarW + 14, ty - textHeight(kTextScale) / 2, label, kInk, kTextScale);
  }
  return drawSwatchRow(canvas, x, y + kBarH + 16, kUnknownSpaceColor, "never observed");
}

int drawTrackLegend(RgbImage& canvas, int x, int y, const std::vector<PictureTrack>& tracks) {
  if (tracks.empty()) return y;
  drawText(canvas, x, y, "TRAJECTORIES", kInk, kTextScale);
  y += kRowPitch + 4;
  for (const PictureTrack& t : tracks) {
    const Rect clip{x, y, kSwatch + 14, kSwatch};
    const std::vector<Eigen::Vector2d> line{{x + 6.0, y + kSwatch / 2.0},
                                            {x + kSwatch + 6.0, y + kSwatch / 2.0}};
    drawPolyline(canvas, clip, line, t.radius + 1.2, kInk);
    drawPolyline(canvas, clip, line, t.radius, t.color);
    drawText(canvas, x + kSwatch + 22, y + (kSwatch - textHeight(kTextScale)) / 2, t.name, kInk,
             kTextScale);
    y += kRowPitch;
  }
  drawText(canvas, x, y, "(disc: start)", kInk, kTextScale);
  return y + kRowPitch;
}

}  // namespace

double autoPixelSize(double width_m, double height_m) {
  return std::max(width_m, height_m) / kMapLongSidePixels;
}

std::vector<std::uint8_t> presentClasses(const RgbImage& class_render) {
  std::array<bool, kNumClasses> seen{};
  for (int y = 0; y < class_render.height; ++y)
    for (int x = 0; x < class_render.width; ++x) {
      const Rgb p = class_render.at(x, y);
      const auto same = [&p](Rgb c) { return p.r == c.r && p.g == c.g && p.b == c.b; };
      if (same(kUnlabeledVoxelColor)) seen[kUnlabeled] = true;
      for (std::uint8_t c = 1; c < kNumClasses; ++c) seen[c] = seen[c] || same(classColor(c));
    }
  std::vector<std::uint8_t> out;
  for (std::uint8_t c = 1; c < kNumClasses; ++c)
    if (seen[c]) out.push_back(c);
  if (seen[kUnlabeled]) out.push_back(kUnlabeled);
  return out;
}

RgbImage decorateMap(const RgbImage& raster, const PictureSpec& spec) {
  const Rect map{kMargin, kMapTop, raster.width, raster.height};
  const int panel_x = map.x + map.w + 30;
  RgbImage canvas(panel_x + kPanelWidth, std::max(map.y + map.h + 50, 760), kPaper);
  drawText(canvas, kMargin, 18, spec.title, kInk, kTitleScale);
  canvas.fillRect(map.x - 1, map.y - 1, map.w + 2, map.h + 2, kInk);
  canvas.paste(raster, map.x, map.y);
  for (const PictureTrack& t : spec.tracks) drawTrack(canvas, map, spec, t);
  if (spec.pixel_size > 0.0) drawScaleBar(canvas, map, spec.pixel_size);
  char note[96];
  std::snprintf(note, sizeof(note), "X RIGHT, Y UP. %.3f M/PIXEL. CORNER (%.1f, %.1f) M",
                spec.pixel_size, spec.x_min, spec.y_min);
  drawText(canvas, map.x, map.y + map.h + 16, note, kInk, kTextScale);
  int y = map.y;
  if (spec.mode == render_request_t::MODE_CLASS) y = drawClassLegend(canvas, panel_x, y, raster);
  if (spec.mode == render_request_t::MODE_OCCUPANCY) y = drawOccupancyBar(canvas, panel_x, y);
  drawTrackLegend(canvas, panel_x, y + 20, spec.tracks);
  return canvas;
}

}  // namespace socc::tools
