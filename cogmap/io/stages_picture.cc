#include "cogmap/io/stages_picture.h"

#include <algorithm>
#include <cmath>

namespace cogmap::io {
namespace {

constexpr Rgb kWhite{255, 255, 255};
constexpr Rgb kGrey{160, 160, 160};
constexpr Rgb kBlack{0, 0, 0};
constexpr Rgb kRed{220, 0, 0};
constexpr Rgb kPink{255, 190, 190};
constexpr Rgb kBlue{20, 60, 200};

Rgb CellColour(float v) {
  if (v == -100.0f) return kRed;
  if (v > 7.0f) return kBlack;
  if (v < 0.0f) {
    const double t = std::min(1.0, -v / 3.0);  // 0 grey -> -3 white
    const uint8_t g = static_cast<uint8_t>(160 + t * 95);
    return {g, g, g};
  }
  const double t = std::min(1.0, v / 7.0);  // 0 grey -> 7 dark grey
  const uint8_t g = static_cast<uint8_t>(160 - t * 100);
  return {g, g, g};
}

// One panel: cell (i, j) covers pixels [i s, (i+1) s) x [(h-1-j) s, (h-j) s).
struct Panel {
  double s = 1.0;
  int w = 0, h = 0;  // cells
  RgbImage img;
  double Px(double cx) const { return cx * s; }
  double Py(double cy) const { return (h - cy) * s; }
};

Panel MakePanel(int w, int h, int max_px) {
  Panel p;
  p.w = w;
  p.h = h;
  const int longest = std::max(1, std::max(w, h));
  p.s = std::min(6.0, static_cast<double>(max_px) / longest);
  p.img = RgbImage(std::max(1, static_cast<int>(std::ceil(w * p.s))), std::max(1, static_cast<int>(std::ceil(h * p.s))), kWhite);
  return p;
}

void FillCell(Panel& p, int i, int j, Rgb c) {
  const int x0 = static_cast<int>(std::floor(i * p.s)), x1 = std::max(x0 + 1, static_cast<int>(std::floor((i + 1) * p.s)));
  const int y0 = static_cast<int>(std::floor((p.h - 1 - j) * p.s)),
            y1 = std::max(y0 + 1, static_cast<int>(std::floor((p.h - j) * p.s)));
  for (int y = y0; y < y1; ++y)
    for (int x = x0; x < x1; ++x) p.img.Set(x, y, c);
}

// Paints a grid in passes so that, when cells are smaller than pixels,
// occupied and path cells stay visible.
void PaintGrid(Panel& p, const grid::Grid2D<float>& g, bool faint) {
  for (int pass = 0; pass < 3; ++pass)
    for (int j = 0; j < p.h; ++j)
      for (int i = 0; i < p.w; ++i) {
        const float v = g.at(i, j);
        const int rank = v == -100.0f ? 2 : (v > 7.0f ? 1 : 0);
        if (rank != pass) continue;
        Rgb c = CellColour(v);
        if (faint) c = rank == 2 ? kPink : (rank == 1 ? Rgb{200, 200, 200} : kWhite);
        FillCell(p, i, j, c);
      }
}

Rgb ChainColour(size_t k) {
  static const Rgb palette[] = {{230, 25, 75},  {60, 180, 75},  {0, 130, 200},  {245, 130, 48},
                                {145, 30, 180}, {70, 160, 160}, {240, 50, 230}, {128, 128, 0},
                                {0, 0, 128},    {170, 110, 40}};
  return palette[k % (sizeof palette / sizeof palette[0])];
}

void DrawChainLines(Panel& p, const std::vector<std::vector<Vec2>>& lines, Rgb line_c, Rgb dot_c, int thick) {
  const double r = std::max(1.5, p.s * 0.6);
  for (const auto& l : lines) {
    for (size_t k = 1; k < l.size(); ++k)
      p.img.DrawLine(p.Px(l[k - 1].x()), p.Py(l[k - 1].y()), p.Px(l[k].x()), p.Py(l[k].y()), line_c, thick);
    for (const auto& v : l) p.img.DrawDisc(p.Px(v.x()), p.Py(v.y()), r, dot_c);
  }
}

// The cells of 'g' inside [x0, x0 + w) x [y0, y0 + h).
grid::Grid2D<float> Crop(const grid::Grid2D<float>& g, int x0, int y0, int w, int h) {
  const auto& lim = g.limits();
  grid::Grid2D<float> out(grid::MapLimits(lim.cell_m(), lim.origin() + Vec2(x0, y0) * lim.cell_m(), w, h), 0.0f);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) out.at(x, y) = g.get(x0 + x, y0 + y);
  return out;
}

std::vector<std::vector<Vec2>> Shift(const std::vector<std::vector<Vec2>>& lines, const Vec2& d) {
  auto out = lines;
  for (auto& l : out)
    for (auto& v : l) v -= d;
  return out;
}

}  // namespace

RgbImage DrawStages(const grid::Grid2D<float>& raw_full, const vectorize::VectorizeResult& r_full,
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
  const grid::Grid2D<float> raw = Crop(raw_full, x0, y0, x1 - x0 + 1, y1 - y0 + 1);
  vectorize::VectorizeResult r;
  if (r_full.cleaned.limits().width() == flim.width() && r_full.cleaned.limits().height() == flim.height())
    r.cleaned = Crop(r_full.cleaned, x0, y0, x1 - x0 + 1, y1 - y0 + 1);
  r.chains = r_full.chains;
  for (auto& c : r.chains)
    for (auto& cell : c) cell -= grid::CellIndex(x0, y0);
  r.simplified = Shift(r_full.simplified, Vec2(x0, y0));
  r.fitted = Shift(r_full.fitted, Vec2(x0, y0));
  const int w = raw.limits().width(), h = raw.limits().height();
  const std::vector<std::string> titles = {"RAW GRID", "CLEANED", "EXTRACTED", "SIMPLIFIED", "FITTED"};
  std::vector<Panel> panels;
  for (int k = 0; k < 5; ++k) panels.push_back(MakePanel(w, h, options.max_panel_px));
  if (w > 0 && h > 0) {
    PaintGrid(panels[0], raw, false);
    if (r.cleaned.limits().width() == w && r.cleaned.limits().height() == h) {
      PaintGrid(panels[1], r.cleaned, false);
      for (int k = 2; k < 5; ++k) PaintGrid(panels[k], r.cleaned, true);
    }
    // Extracted points, one colour per chain, joined in walking order.
    for (size_t c = 0; c < r.chains.size(); ++c) {
      const auto pts = vectorize::ChainToCellCoords(r.chains[c]);
      const Rgb col = ChainColour(c);
      for (size_t k = 1; k < pts.size(); ++k)
        panels[2].img.DrawLine(panels[2].Px(pts[k - 1].x()), panels[2].Py(pts[k - 1].y()),
                               panels[2].Px(pts[k].x()), panels[2].Py(pts[k].y()), col, 1);
      for (const auto& v : pts)
        panels[2].img.DrawDisc(panels[2].Px(v.x()), panels[2].Py(v.y()), std::max(1.0, panels[2].s * 0.4), col);
    }
    DrawChainLines(panels[3], r.simplified, kBlue, kBlue, 2);
    DrawChainLines(panels[4], r.fitted, kBlack, kRed, 2);
  }
  (void)r_full;
  const int label_h = 7 * options.label_scale + 8;
  int total_w = options.gap_px;
  int panel_h = 0;
  for (const auto& p : panels) {
    total_w += p.img.width() + options.gap_px;
    panel_h = std::max(panel_h, p.img.height());
  }
  RgbImage out(std::max(total_w, 6 * options.label_scale * 12), panel_h + label_h + 2 * options.gap_px, {235, 235, 235});
  int x = options.gap_px;
  for (size_t k = 0; k < panels.size(); ++k) {
    out.DrawText(x, options.gap_px, titles[k], kBlack, options.label_scale);
    out.Blit(panels[k].img, x, options.gap_px + label_h);
    x += panels[k].img.width() + options.gap_px;
  }
  return out;
}

RgbImage DrawWalls(const std::vector<Polyline>& walls, const std::vector<Segment2>& truth, const Vec2& min,
                   const Vec2& max, double px_per_m) {
  const Vec2 size = max - min;
  const int w = std::max(1, static_cast<int>(std::ceil(size.x() * px_per_m)));
  const int h = std::max(1, static_cast<int>(std::ceil(size.y() * px_per_m)));
  RgbImage img(w, h, kWhite);
  auto px = [&](const Vec2& p) { return Vec2((p.x() - min.x()) * px_per_m, (max.y() - p.y()) * px_per_m); };
  for (const auto& s : truth) {
    const Vec2 a = px(s.a), b = px(s.b);
    img.DrawLine(a.x(), a.y(), b.x(), b.y(), {150, 190, 255}, 5);
  }
  for (const auto& l : walls) {
    for (size_t k = 1; k < l.size(); ++k) {
      const Vec2 a = px(l[k - 1]), b = px(l[k]);
      img.DrawLine(a.x(), a.y(), b.x(), b.y(), kBlack, 2);
    }
    for (const auto& v : l) {
      const Vec2 p = px(v);
      img.DrawDisc(p.x(), p.y(), 2.5, kRed);
    }
  }
  (void)kGrey;
  return img;
}

}  // namespace cogmap::io
