#include "cogmap/draw/grid_picture.h"

#include <algorithm>
#include <cmath>
#include <vector>

namespace cogmap::draw {
namespace {

uint8_t Lerp(uint8_t a, uint8_t b, float t) {
  t = std::clamp(t, 0.0f, 1.0f);
  return static_cast<uint8_t>(std::lround(a + (static_cast<float>(b) - a) * t));
}

io::Rgb Grey(uint8_t v) { return {v, v, v}; }

// Paints cell (x, y) as a scale x scale block, world y up.
void PaintCell(io::RgbImage* img, int x, int y, int grid_height, int scale, io::Rgb c) {
  const int row0 = (grid_height - 1 - y) * scale, col0 = x * scale;
  for (int r = 0; r < scale; ++r)
    for (int k = 0; k < scale; ++k) img->at(col0 + k, row0 + r) = c;
}

}  // namespace

io::RgbImage RenderCertainty(const grid::Grid2D<float>& values, const GridRenderOptions& options) {
  const int w = values.limits().width(), h = values.limits().height(), s = std::max(1, options.scale);
  io::RgbImage img(w * s, h * s, kUnknownRgb);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const float v = values.at(x, y);
      io::Rgb c = kUnknownRgb;
      if (v == options.robot_path) c = kRobotPathRgb;
      else if (v > options.occupied_threshold) c = kOccupiedRgb;
      else if (v > 0) c = Grey(Lerp(kUnknownRgb.r, 64, v / options.occupied_threshold));
      else if (v < 0) c = Grey(Lerp(kUnknownRgb.r, kEmptyRgb.r, v / options.min_value));
      PaintCell(&img, x, y, h, s, c);
    }
  return img;
}

io::RgbImage RenderProbability(const grid::Grid2D<float>& occupancy,
                           const grid::Grid2D<grid::CellClass>& classes, int scale) {
  const int w = occupancy.limits().width(), h = occupancy.limits().height(), s = std::max(1, scale);
  io::RgbImage img(w * s, h * s, kUnknownRgb);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const grid::CellClass k = classes.get(x, y);
      io::Rgb c;
      if (k == grid::CellClass::kRobotPath) c = kRobotPathRgb;
      else if (k == grid::CellClass::kUnknown && occupancy.at(x, y) == 0.5f) c = kUnknownRgb;
      else c = Grey(Lerp(255, 0, occupancy.at(x, y)));
      PaintCell(&img, x, y, h, s, c);
    }
  return img;
}

io::RgbImage RenderFusion(const grid::RangeFusion& fusion, const GridRenderOptions& options) {
  switch (fusion.rule()) {
    case grid::FusionRule::kHimm:
    case grid::FusionRule::kMhimm: {
      GridRenderOptions o = options;
      if (const auto* h = dynamic_cast<const grid::HimmFusion*>(&fusion)) {
        o.occupied_threshold = h->options().occupied_threshold;
        o.min_value = h->options().min_value < 0 ? h->options().min_value : -1.0f;
        if (fusion.rule() == grid::FusionRule::kMhimm) o.robot_path = h->options().robot_path;
        else o.robot_path = -1e30f;
      }
      return RenderCertainty(fusion.Values(), o);
    }
    case grid::FusionRule::kBayes:
    case grid::FusionRule::kDempsterShafer:
      return RenderProbability(fusion.Occupancy(), fusion.Classes(), options.scale);
  }
  return {};
}

io::RgbImage ShrinkKeepingDarkest(const io::RgbImage& image, double k) {
  if (k >= 1.0) return image;
  const int w = std::max(1, static_cast<int>(std::ceil(image.width() * k)));
  const int h = std::max(1, static_cast<int>(std::ceil(image.height() * k)));
  io::RgbImage out(w, h);
  std::vector<int> best(static_cast<size_t>(w) * h, -1);
  for (int y = 0; y < image.height(); ++y)
    for (int x = 0; x < image.width(); ++x) {
      const io::Rgb c = image.at(x, y);
      const int rank = c == kRobotPathRgb ? 1000 : 765 - (c.r + c.g + c.b);
      const int ox = std::min(w - 1, static_cast<int>(x * k)), oy = std::min(h - 1, static_cast<int>(y * k));
      int& b = best[static_cast<size_t>(oy) * w + ox];
      if (rank > b) {
        b = rank;
        out.at(ox, oy) = c;
      }
    }
  return out;
}

Drawing DrawGrid(const grid::RangeFusion& fusion, const PictureOptions& options, const GridRenderOptions& render) {
  GridRenderOptions one = render;
  one.scale = 1;
  const io::RgbImage cells = RenderFusion(fusion, one);
  const auto& lim = fusion.limits();
  const std::vector<LegendItem> legend = {
      {LegendItem::Kind::kFill, Rgb8(kOccupiedRgb.r, kOccupiedRgb.g, kOccupiedRgb.b), "occupied"},
      {LegendItem::Kind::kFill, Rgb8(kEmptyRgb.r, kEmptyRgb.g, kEmptyRgb.b), "empty"},
      {LegendItem::Kind::kFill, Rgb8(kUnknownRgb.r, kUnknownRgb.g, kUnknownRgb.b), "unknown"},
      {LegendItem::Kind::kFill, Rgb8(kRobotPathRgb.r, kRobotPathRgb.g, kRobotPathRgb.b), "robot path"}};
  PictureOptions o = options;
  o.margin_m = 0;
  MapPage page(lim.origin(), lim.max(), o, legend);
  Drawing d = page.NewDrawing();
  const double px_per_cell = page.px_per_m() * lim.cell_m();
  const io::RgbImage shown = ShrinkKeepingDarkest(cells, px_per_cell);
  const Vec2 top_left = page.Px(Vec2(lim.origin().x(), lim.max().y()));
  d.Image(shown, top_left.x(), top_left.y(), cells.width() * px_per_cell / shown.width());
  page.Decorate(d);
  return d;
}

}  // namespace cogmap::draw
