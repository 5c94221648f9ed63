#include "cogmap/draw/stages_picture.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "cogmap/draw/layout.h"

namespace cogmap::draw {
namespace {

constexpr io::Rgb kRed{220, 0, 0};
constexpr io::Rgb kPink{255, 190, 190};
const Colour kBlue = Rgb8(20, 60, 200);
const Colour kVertexRed = Rgb8(220, 0, 0);

io::Rgb CellColour(float v) {
  if (v == -100.0f) return kRed;
  if (v > 7.0f) return {0, 0, 0};
  if (v < 0.0f) {
    const double t = std::min(1.0, -v / 3.0);  // 0 grey -> -3 white
    const auto g = static_cast<uint8_t>(160 + t * 95);
    return {g, g, g};
  }
  const double t = std::min(1.0, v / 7.0);  // 0 grey -> 7 dark grey
  const auto g = static_cast<uint8_t>(160 - t * 100);
  return {g, g, g};
}
int Rank(float v) { return v == -100.0f ? 2 : (v > 7.0f ? 1 : 0); }

// The grid as a raster with y up, at most 'scale' <= 1 pixel per cell when
// the panel is smaller than the grid: each pixel the strongest of its cells.
io::RgbImage GridRaster(const grid::Grid2D<float>& g, double px_per_cell, bool faint) {
  const int w = g.limits().width(), h = g.limits().height();
  const double k = std::min(1.0, px_per_cell);
  const int rw = std::max(1, static_cast<int>(std::ceil(w * k))), rh = std::max(1, static_cast<int>(std::ceil(h * k)));
  io::RgbImage img(rw, rh, {255, 255, 255});
  std::vector<int> rank(static_cast<size_t>(rw) * rh, -1);
  for (int j = 0; j < h; ++j)
    for (int i = 0; i < w; ++i) {
      const float v = g.at(i, j);
      const int px = std::min(rw - 1, static_cast<int>(i * k)), py = std::min(rh - 1, static_cast<int>((h - 1 - j) * k));
      const int r = Rank(v);
      int& best = rank[static_cast<size_t>(py) * rw + px];
      if (r < best) continue;
      best = r;
      io::Rgb c = CellColour(v);
      if (faint) c = r == 2 ? kPink : (r == 1 ? io::Rgb{200, 200, 200} : io::Rgb{255, 255, 255});
      img.at(px, py) = c;
    }
  return img;
}

Colour ChainColour(size_t k) {
  static const Colour palette[] = {Rgb8(230, 25, 75),  Rgb8(60, 180, 75),  Rgb8(0, 130, 200),  Rgb8(245, 130, 48),
                                   Rgb8(145, 30, 180), Rgb8(70, 160, 160), Rgb8(240, 50, 230), Rgb8(128, 128, 0),
                                   Rgb8(0, 0, 128),    Rgb8(170, 110, 40)};
  return palette[k % (sizeof palette / sizeof palette[0])];
}

grid::Grid2D<float> Crop(const grid::Grid2D<float>& g, int x0, int y0, int w, int h) {
  const auto& lim = g.limits();
  grid::Grid2D<float> out(grid::MapLimits(lim.cell_m(), lim.origin() + Vec2(x0, y0) * lim.cell_m(), w, h), 0.0f);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) out.at(x, y) = g.get(x0 + x, y0 + y);
  return out;
}

}  // namespace

StagesPicture DrawStages(const grid::Grid2D<float>& raw_full, const vectorize::VectorizeResult& r,
                         const StagesPictureOptions& options) {
  // Crop to the cells that hold anything (not unknown), plus a margin.
  const auto& flim = raw_full.limits();
  int x0 = flim.width(), y0 = flim.height(), x1 = -1, y1 = -1;
  for (int y = 0; y < flim.height(); ++y)
    for (int x = 0; x < flim.width(); ++x)
      if (raw_full.at(x, y) != 0.0f) x0 = std::min(x0, x), y0 = std::min(y0, y), x1 = std::max(x1, x), y1 = std::max(y1, y);
  if (x1 < 0) x0 = y0 = 0, x1 = flim.width() - 1, y1 = flim.height() - 1;
  const int m = options.crop_margin_cells;
  x0 = std::max(0, x0 - m), y0 = std::max(0, y0 - m);
  x1 = std::min(flim.width() - 1, x1 + m), y1 = std::min(flim.height() - 1, y1 + m);
  const int w = std::max(0, x1 - x0 + 1), h = std::max(0, y1 - y0 + 1);
  const bool cleaned_ok = r.cleaned.limits().width() == flim.width() && r.cleaned.limits().height() == flim.height();

  const double gap = options.gap_px, title_h = 34, label_h = 24;
  const double budget = std::max(200, options.max_side_px);
  const std::vector<LegendItem> legend = {{LegendItem::Kind::kFill, Rgb8(0, 0, 0), "occupied"},
                                          {LegendItem::Kind::kFill, Rgb8(255, 255, 255), "empty"},
                                          {LegendItem::Kind::kFill, Rgb8(160, 160, 160), "unknown"},
                                          {LegendItem::Kind::kLine, Rgb8(220, 0, 0), "robot path"},
                                          {LegendItem::Kind::kLine, ChainColour(0), "chains (a colour each)"},
                                          {LegendItem::Kind::kLine, kBlue, "simplified"},
                                          {LegendItem::Kind::kLine, kBlack, "fitted"},
                                          {LegendItem::Kind::kDisc, kVertexRed, "vertices"}};
  // Five panels and six gaps across the budget; the panel's height follows,
  // above the band (whose legend rows the strip's width decides).
  const double panel_w_max = (budget - 6 * gap) / 5;
  const double band_max = BottomBandHeight(legend, LegendSpan(budget));
  const double s =
      (w > 0 && h > 0) ? std::min(panel_w_max / w, (budget - title_h - label_h - 2 * gap - band_max) / h) : 1.0;
  const double pw = std::max(1.0, w * s), ph = std::max(1.0, h * s);
  const double strip_w = 6 * gap + 5 * pw;
  const double band = BottomBandHeight(legend, LegendSpan(strip_w));
  const double band_top = title_h + label_h + ph + 2 * gap;
  Drawing out(strip_w, band_top + band, Rgb8(235, 235, 235));
  out.Text(Vec2(gap, 8), options.title, Font{18, true});
  const char* titles[] = {"raw grid", "cleaned", "extracted", "simplified", "fitted"};
  // Cell coordinates (x right, y up, cell (i, j) spans [i, i+1) x [j, j+1))
  // to a panel's pixels.
  auto px = [&](const Vec2& c, double ox) { return Vec2(ox + (c.x() - x0) * s, title_h + label_h + (h - (c.y() - y0)) * s); };
  for (int k = 0; k < 5; ++k) {
    const double ox = gap + k * (pw + gap), oy = title_h + label_h;
    out.Text(Vec2(ox, title_h + 2), titles[k], Font{14, true});
    out.Rectangle(Box{ox, oy, ox + pw, oy + ph}, kWhite);
    if (w == 0 || h == 0) continue;
    const grid::Grid2D<float>* g = nullptr;
    grid::Grid2D<float> crop;
    if (k == 0) {
      crop = Crop(raw_full, x0, y0, w, h);
      g = &crop;
    } else if (cleaned_ok) {
      crop = Crop(r.cleaned, x0, y0, w, h);
      g = &crop;
    }
    if (g) {
      const io::RgbImage raster = GridRaster(*g, s, k >= 2);
      out.Image(raster, ox, oy, pw / raster.width());
    }
    const double dot = std::clamp(0.5 * s, 1.2, 4.0);
    if (k == 2) {
      for (size_t c = 0; c < r.chains.size(); ++c) {
        const auto pts = vectorize::ChainToCellCoords(r.chains[c]);
        std::vector<Vec2> p;
        for (const auto& v : pts) p.push_back(px(v, ox));
        out.Polyline(p, Stroke{ChainColour(c), 1});
        for (const auto& v : p) out.Circle(v, dot * 0.8, ChainColour(c));
      }
    }
    const auto& lines = k == 3 ? r.simplified : r.fitted;
    if (k >= 3)
      for (const auto& l : lines) {
        std::vector<Vec2> p;
        for (const auto& v : l) p.push_back(px(v, ox));
        out.Polyline(p, Stroke{k == 3 ? kBlue : kBlack, 2});
        for (const auto& v : p) out.Circle(v, dot, k == 3 ? kBlue : kVertexRed);
      }
  }
  // The band: white as on a map page, the panels' scale (pixels per cell
  // over the cell's size), the legend, the north arrow (the grid's +y).
  const double px_per_m = s / raw_full.limits().cell_m();
  out.Rectangle(Box{0, band_top, strip_w, band_top + band}, kWhite);
  out.Line(Vec2(0, band_top + 0.5), Vec2(strip_w, band_top + 0.5), Stroke{Rgb8(200, 200, 200), 1, {}, false});
  const ScaleBar bar = DrawScaleBar(out, px_per_m, kPageSidePx, band_top + band - 16);
  DrawNorthArrow(out, strip_w - kPageSidePx, band_top + band);
  DrawLegend(out, legend, LegendStart(kPageSidePx, bar.end_px.x() - bar.start_px.x()), LegendEnd(strip_w),
             band_top + 10);
  return StagesPicture{std::move(out), px_per_m, bar, band_top};
}

MapPicture DrawWalls(const std::vector<Polyline>& walls, const std::vector<Segment2>& truth, const Polyline& path,
                     const PictureOptions& options) {
  const double inf = std::numeric_limits<double>::infinity();
  Vec2 lo(inf, inf), hi(-inf, -inf);
  auto grow = [&](const Vec2& p) { lo = lo.cwiseMin(p), hi = hi.cwiseMax(p); };
  for (const auto& l : walls)
    for (const auto& p : l) grow(p);
  for (const auto& s : truth) grow(s.a), grow(s.b);
  for (const auto& p : path) grow(p);
  if (lo.x() > hi.x()) lo = hi = Vec2(0, 0);
  std::vector<LegendItem> legend = {{LegendItem::Kind::kLine, kBlack, "walls"},
                                    {LegendItem::Kind::kDisc, kVertexRed, "vertices"}};
  if (!truth.empty()) legend.push_back({LegendItem::Kind::kLine, Rgb8(150, 190, 255), "true walls"});
  if (!path.empty()) legend.push_back({LegendItem::Kind::kLine, Rgb8(255, 140, 140), "robot path"});
  MapPage page(lo, hi, options, legend);
  Drawing d = page.NewDrawing();
  const double k = page.px_per_m();
  for (const auto& s : truth) d.Line(page.Px(s.a), page.Px(s.b), Stroke{Rgb8(150, 190, 255), std::clamp(0.12 * k, 3.0, 8.0)});
  d.Polyline(page.Px(path), Stroke{Rgb8(255, 140, 140), std::clamp(0.03 * k, 1.0, 2.0)});
  for (const auto& l : walls) d.Polyline(page.Px(l), Stroke{kBlack, std::clamp(0.05 * k, 1.5, 4.0)});
  const double r = std::clamp(0.05 * k, 1.5, 4.0);
  for (const auto& l : walls)
    for (const auto& v : l) d.Circle(page.Px(v), r, kVertexRed);
  page.Decorate(d);
  MapPicture out;
  out.drawing = std::move(d);
  out.px_per_m = k;
  out.scale_bar = page.scale_bar();
  out.map_box = page.map_box();
  out.origin_px = page.Px(Vec2(0, 0));
  return out;
}

}  // namespace cogmap::draw
