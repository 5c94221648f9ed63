#include "cogmap/draw/layout.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace cogmap::draw {

namespace {

constexpr double kSidePx = kPageSidePx;
constexpr double kTitleFontPx = 20;
constexpr double kSmallFontPx = 12;
constexpr double kLegendFontPx = 13;
constexpr double kBarMaxPx = 220;     // the scale bar's longest length
constexpr double kArrowBoxPx = 44;    // north arrow's box
constexpr double kMinPageWidthPx = 420;
// A band's width less its legend's span: the margins, a full-length scale
// bar with the gap after it (LegendStart) and the north arrow with the gap
// before it (LegendEnd).
constexpr double kLegendMarginsPx = 2 * kSidePx + kBarMaxPx + 36 + kArrowBoxPx + 10;

const Font kTitleFont{kTitleFontPx, true};
const Font kSmallFont{kSmallFontPx, false};
const Font kLegendFont{kLegendFontPx, false};
const Font kNorthFont{14, true};

double LegendItemWidth(const LegendItem& item) { return 30 + Drawing::MeasureText(item.label, kLegendFont).width() + 18; }

// Rows the legend takes at a band of 'width' pixels.
int LegendRows(const std::vector<LegendItem>& legend, double width) {
  if (legend.empty()) return 0;
  int rows = 1;
  double x = 0;
  for (const auto& it : legend) {
    const double w = LegendItemWidth(it);
    if (x > 0 && x + w > width) {
      ++rows;
      x = 0;
    }
    x += w;
  }
  return rows;
}

std::string Fmt(const char* f, double v) {
  char b[64];
  std::snprintf(b, sizeof(b), f, v);
  return b;
}

// The narrowest page whose bands hold their text: the title beside the scale
// note ("1 m = ... px", at its widest), and the widest legend item between a
// scale bar of full length and the north arrow (a tall, narrow map drew its
// title over the note and its legend past the page's edge).
double DecorationWidth(const std::string& title, const std::vector<LegendItem>& legend) {
  double w = kMinPageWidthPx;
  if (!title.empty()) {
    const double note = Drawing::MeasureText("1 m = 00000 px", kSmallFont).width();
    w = std::max(w, 2 * kSidePx + Drawing::MeasureText(title, kTitleFont).width() + 24 + note);
  }
  double widest = 0.0;
  for (const auto& it : legend) widest = std::max(widest, LegendItemWidth(it));
  if (widest > 0.0) w = std::max(w, widest + kLegendMarginsPx);
  return w;
}

}  // namespace

std::vector<Font> PageFonts() { return {kTitleFont, kSmallFont, kLegendFont, kNorthFont}; }

double LegendSpan(double width_px) { return std::max(100.0, width_px - kLegendMarginsPx); }

double LegendEnd(double width_px) { return width_px - kSidePx - kArrowBoxPx - 10; }

double BottomBandHeight(const std::vector<LegendItem>& legend, double legend_span_px) {
  return std::max(kArrowBoxPx + 16, LegendRows(legend, legend_span_px) * 20.0 + 20);
}

double LegendStart(double left_px, double bar_px) { return left_px + std::max(bar_px, 60.0) + 36; }

ScaleBar DrawScaleBar(Drawing& d, double px_per_m, double left_px, double bar_y) {
  // A black bar with end ticks, its length above.
  const double len_m = NiceScaleLength(px_per_m, kBarMaxPx);
  const double len_px = len_m * px_per_m;
  const Vec2 a(left_px, bar_y), b(left_px + len_px, bar_y);
  const double thick = 5;
  d.Rectangle(Box{a.x(), bar_y - thick / 2, b.x(), bar_y + thick / 2}, kBlack);
  d.Line(Vec2(a.x(), bar_y - 9), Vec2(a.x(), bar_y - thick / 2), Stroke{kBlack, 1.5, {}, false});
  d.Line(Vec2(b.x(), bar_y - 9), Vec2(b.x(), bar_y - thick / 2), Stroke{kBlack, 1.5, {}, false});
  d.Text(Vec2((a.x() + b.x()) / 2, bar_y - 7), FormatLength(len_m), kSmallFont, kBlack, Align::kCenter,
         VAlign::kBottom);
  return ScaleBar{len_m, a, b, thick};
}

Box DrawNorthArrow(Drawing& d, double right_px, double bottom_px) {
  const double ax = right_px - 12, ay0 = bottom_px - 10, ay1 = bottom_px - kArrowBoxPx + 6;
  d.Polygon({Vec2(ax, ay1), Vec2(ax + 7, ay0), Vec2(ax, ay0 - 6), Vec2(ax - 7, ay0)}, kBlack);
  const Box north = d.Text(Vec2(ax - 12, (ay0 + ay1) / 2), "N", kNorthFont, kBlack, Align::kRight, VAlign::kMiddle);
  return Box{north.x0, ay1, ax + 7, ay0};
}

std::vector<Box> DrawLegend(Drawing& d, const std::vector<LegendItem>& legend, double lx0, double lx1, double y) {
  std::vector<Box> used;
  double x = lx0;
  for (const auto& it : legend) {
    const double w = LegendItemWidth(it);
    if (x > lx0 && x + w > lx1) {
      x = lx0;
      y += 20;
    }
    const double cy = y + 8;
    switch (it.kind) {
      case LegendItem::Kind::kLine:
        d.Line(Vec2(x, cy), Vec2(x + 22, cy), Stroke{it.colour, 3});
        break;
      case LegendItem::Kind::kDashed:
        d.Line(Vec2(x, cy), Vec2(x + 22, cy), Stroke{it.colour, 2, {5, 3}, false});
        break;
      case LegendItem::Kind::kDisc:
        d.Circle(Vec2(x + 11, cy), 5, it.colour);
        break;
      case LegendItem::Kind::kFill:
        d.Rectangle(Box{x + 2, cy - 6, x + 20, cy + 6}, it.colour, Stroke{Rgb8(120, 120, 120), 1, {}, false});
        break;
    }
    used.push_back(d.Text(Vec2(x + 30, cy), it.label, kLegendFont, kBlack, Align::kLeft, VAlign::kMiddle));
    x += w;
  }
  return used;
}

double NiceScaleLength(double px_per_m, double max_px) {
  const double max_m = max_px / std::max(px_per_m, 1e-12);
  double p = std::pow(10.0, std::floor(std::log10(max_m)));
  double best = p;
  for (double m : {1.0, 2.0, 5.0, 10.0})
    if (m * p <= max_m * (1 + 1e-9)) best = m * p;
  return best;
}

std::string FormatLength(double m) {
  if (m >= 1000) return Fmt("%g km", m / 1000);
  if (m < 1) return Fmt("%g cm", std::round(m * 1000) / 10);
  return Fmt("%g m", m);
}

MapPage::MapPage(const Vec2& min_m, const Vec2& max_m, const PictureOptions& options,
                 const std::vector<LegendItem>& legend)
    : options_(options), legend_(legend) {
  Vec2 lo = min_m.cwiseMin(max_m), hi = max_m.cwiseMax(min_m);
  if (!std::isfinite(lo.x()) || !std::isfinite(lo.y()) || !std::isfinite(hi.x()) || !std::isfinite(hi.y()))
    lo = hi = Vec2(0, 0);
  const double margin = std::max(0.0, options.margin_m);
  lo -= Vec2(margin, margin);
  hi += Vec2(margin, margin);
  // A box of no size still gets one metre (a single point, an empty map).
  for (int k = 0; k < 2; ++k)
    if (hi[k] - lo[k] < 1e-6) {
      lo[k] -= 0.5;
      hi[k] += 0.5;
    }
  min_ = lo;
  max_ = hi;
  const double wm = hi.x() - lo.x(), hm = hi.y() - lo.y();
  const bool deco = options.decorations;
  top_band_ = deco ? 40 : kSidePx / 2;
  const double budget = std::clamp<double>(options.max_side_px, 64, kMaxSidePx);
  auto bottom_for = [&](double page_w) {
    if (!deco) return kSidePx / 2;
    return BottomBandHeight(legend_, LegendSpan(page_w));
  };
  const double side = deco ? kSidePx : kSidePx / 2;
  // Never wider than the budget allows (a budget that small squeezes the bands).
  const double min_w =
      deco ? std::min(DecorationWidth(options.title, legend_), options.px_per_m > 0 ? kMaxSidePx : budget) : 0.0;
  auto fit = [&](double page_w_guess) {
    bottom_band_ = bottom_for(page_w_guess);
    const double avail_w = budget - 2 * side, avail_h = budget - top_band_ - bottom_band_;
    return std::max(1e-9, std::min(avail_w / wm, avail_h / hm));
  };
  double k = fit(budget);
  if (options.px_per_m > 0) k = options.px_per_m;
  for (int iter = 0; iter < 3; ++iter) {
    const double page_w = std::max(min_w, wm * k + 2 * side);
    bottom_band_ = bottom_for(page_w);
    const double limit = options.px_per_m > 0 ? kMaxSidePx : budget;
    const double page_h = hm * k + top_band_ + bottom_band_;
    if (page_w <= limit + 1e-6 && page_h <= limit + 1e-6) break;
    // Too large: shrink the scale to fit the limit with this band.
    k = std::min(k, std::min((limit - 2 * side) / wm, (limit - top_band_ - bottom_band_) / hm));
    k = std::max(k, 1e-9);
  }
  px_per_m_ = k;
  const double map_w = wm * k, map_h = hm * k;
  width_ = std::max(deco ? min_w : 1.0, map_w + 2 * side);
  height_ = map_h + top_band_ + bottom_band_;
  origin_ = Vec2((width_ - map_w) / 2, top_band_);
  map_box_ = Box{origin_.x(), origin_.y(), origin_.x() + map_w, origin_.y() + map_h};
}

std::vector<Vec2> MapPage::Px(const std::vector<Vec2>& world_m) const {
  std::vector<Vec2> out;
  out.reserve(world_m.size());
  for (const auto& p : world_m) out.push_back(Px(p));
  return out;
}

std::vector<Box> MapPage::Decorate(Drawing& d) {
  std::vector<Box> used;
  if (!options_.decorations) return used;
  // Title band: the title, and the scale note where it does not cover it
  // (only a page squeezed below its decorations' width lacks the room).
  Box title_box{kSidePx, 9, kSidePx, 9};
  if (!options_.title.empty())
    used.push_back(title_box =
                       d.Text(Vec2(kSidePx, 9), options_.title, kTitleFont, kBlack, Align::kLeft, VAlign::kTop));
  const std::string scale_note = "1 m = " + Fmt(px_per_m_ >= 10 ? "%.0f" : "%.3g", px_per_m_) + " px";
  if (Drawing::MeasureText(scale_note, kSmallFont).width() + 12 <= width_ - kSidePx - title_box.x1)
    used.push_back(d.Text(Vec2(width_ - kSidePx, 13), scale_note, kSmallFont, Rgb8(90, 90, 90), Align::kRight,
                          VAlign::kTop));
  const double band_top = height_ - bottom_band_;
  used.push_back(Box{0, band_top, width_, height_});
  d.Line(Vec2(0, band_top + 0.5), Vec2(width_, band_top + 0.5), Stroke{Rgb8(200, 200, 200), 1, {}, false});

  // Scale bar bottom left, north arrow bottom right, the legend between.
  bar_ = DrawScaleBar(d, px_per_m_, kSidePx, height_ - 16);
  used.push_back(DrawNorthArrow(d, width_ - kSidePx, height_));
  const double lx0 = LegendStart(kSidePx, bar_.end_px.x() - bar_.start_px.x());
  for (const Box& b : DrawLegend(d, legend_, lx0, LegendEnd(width_), band_top + 10)) used.push_back(b);
  return used;
}

bool LabelPlacer::Free(const Box& b) const {
  if (!b.Inside(bounds_)) return false;
  for (const auto& t : taken_)
    if (t.Overlaps(b)) return false;
  return true;
}

std::optional<LabelPlacer::Placed> LabelPlacer::Place(const Vec2& anchor, const Box& size) {
  const double w = size.width(), h = size.height();
  auto at = [&](double cx, double cy) { return Box{cx - w / 2, cy - h / 2, cx + w / 2, cy + h / 2}; };
  const Box centred = at(anchor.x(), anchor.y());
  if (Free(centred)) {
    taken_.push_back(centred);
    ++placed_;
    return Placed{centred, false};
  }
  // Around the anchor: eight directions, at two distances.
  for (double ring : {1.0, 2.2}) {
    const double dx = (w / 2 + h) * ring, dy = h * ring;
    const Vec2 offsets[] = {{0, -dy}, {0, dy}, {dx, 0}, {-dx, 0}, {dx, -dy}, {-dx, -dy}, {dx, dy}, {-dx, dy}};
    for (const auto& o : offsets) {
      const Box b = at(anchor.x() + o.x(), anchor.y() + o.y());
      if (Free(b)) {
        taken_.push_back(b);
        ++placed_;
        return Placed{b, true};
      }
    }
  }
  ++dropped_;
  return std::nullopt;
}

bool LabelPlacer::Label(Drawing& d, const Vec2& anchor, const std::string& text, const Font& font, Colour colour,
                        Colour halo) {
  const Box size = Drawing::MeasureText(text, font);
  const auto p = Place(anchor, size.Grown(1));
  if (!p) return false;
  const Vec2 c((p->box.x0 + p->box.x1) / 2, (p->box.y0 + p->box.y1) / 2);
  if (p->moved) {
    // Leader from the anchor to the nearest point of the label's box.
    const Vec2 q(std::clamp(anchor.x(), p->box.x0, p->box.x1), std::clamp(anchor.y(), p->box.y0, p->box.y1));
    d.Line(anchor, q, Stroke{Rgb8(90, 90, 90), 0.8});
    d.Circle(anchor, 1.8, Rgb8(90, 90, 90));
  }
  if (halo.a > 0) d.Rectangle(p->box, halo);
  d.Text(c, text, font, colour, Align::kCenter, VAlign::kMiddle);
  return true;
}

}  // namespace cogmap::draw
