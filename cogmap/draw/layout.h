#pragma once
// The page of a map picture: a title band on top, the map in metres scaled to
// a pixel budget, and a band below with the scale bar, the legend and the
// north arrow. Labels are placed by LabelPlacer so that they never overlap.
#include <optional>
#include <string>
#include <vector>

#include "cogmap/core/geometry.h"
#include "cogmap/draw/drawing.h"

namespace cogmap::draw {

// The largest side a picture may take even with a px_per_m override.
constexpr int kMaxSidePx = 16000;
// A page's margin left and right (the scale bar and north arrow stand in it).
constexpr double kPageSidePx = 16;

// The fonts of every page's bands (title, scale, legend, north arrow): the
// ones worth loading before a picture is drawn (Drawing::PrepareFonts).
std::vector<Font> PageFonts();

struct PictureOptions {
  int max_side_px = 2000;  // pixel budget: the longest side of the picture
  double px_per_m = 0.0;   // > 0: this scale instead of fitting the budget (capped at kMaxSidePx)
  double margin_m = 0.5;   // world margin around the content
  std::string title;
  bool decorations = true;  // title, scale bar, legend, north arrow
};

struct LegendItem {
  enum class Kind { kLine, kDashed, kDisc, kFill };
  Kind kind = Kind::kLine;
  Colour colour = kBlack;
  std::string label;
};

// Where the scale bar was drawn (for tests and documentation).
struct ScaleBar {
  double length_m = 0.0;
  Vec2 start_px{0, 0}, end_px{0, 0};  // the bar's centre line, left to right
  double thickness_px = 0.0;
};

// Map frame (metres, x east, y north) to page pixels (x right, y down).
class MapPage {
 public:
  // Lays out a page for the world box [min_m, max_m] (grown by the margin):
  // the scale fits the longest side to the budget (up or down), unless
  // options.px_per_m overrides it; the page is never narrower than its
  // decorations need.
  MapPage(const Vec2& min_m, const Vec2& max_m, const PictureOptions& options,
          const std::vector<LegendItem>& legend);

  double px_per_m() const { return px_per_m_; }
  double width_px() const { return width_; }
  double height_px() const { return height_; }
  Box map_box() const { return map_box_; }  // where the map's box lies on the page
  Vec2 Px(const Vec2& world_m) const {
    return Vec2(origin_.x() + (world_m.x() - min_.x()) * px_per_m_, origin_.y() + (max_.y() - world_m.y()) * px_per_m_);
  }
  std::vector<Vec2> Px(const std::vector<Vec2>& world_m) const;

  // A white drawing of the page's size.
  Drawing NewDrawing() const { return Drawing(width_, height_); }
  // Title, scale bar, legend and north arrow (nothing when decorations are
  // off). Returns the boxes they cover (for LabelPlacer::Block).
  std::vector<Box> Decorate(Drawing& d);
  const ScaleBar& scale_bar() const { return bar_; }

 private:
  PictureOptions options_;
  std::vector<LegendItem> legend_;
  Vec2 min_, max_;           // world box with margin
  double px_per_m_ = 1.0;
  Vec2 origin_{0, 0};        // page pixel of (min.x, max.y)
  double width_ = 0, height_ = 0;
  Box map_box_;
  double top_band_ = 0, bottom_band_ = 0;
  ScaleBar bar_;
};

// The bottom band's pieces, for a page laid out by hand (the stages strip)
// as MapPage lays out its own. The band's height for 'legend' when its rows
// may span 'legend_span_px' (at least the north arrow's).
double BottomBandHeight(const std::vector<LegendItem>& legend, double legend_span_px);
// The span a band of 'width_px' gives its legend beside a full-length scale bar.
double LegendSpan(double width_px);
// Where the legend of a band of 'width_px' ends (before the north arrow).
double LegendEnd(double width_px);
// A scale bar at 'px_per_m' starting at 'left_px' on the line 'bar_y_px' (its
// length the longest NiceScaleLength within kBarMaxPx), its length above it.
ScaleBar DrawScaleBar(Drawing& d, double px_per_m, double left_px, double bar_y_px);
// The north arrow (the map frame's +y) in the band's bottom right corner
// ('right_px', 'bottom_px'); returns its box.
Box DrawNorthArrow(Drawing& d, double right_px, double bottom_px);
// The legend's items in rows of 20 px from (x0, y), wrapped at x1; returns
// its labels' boxes.
std::vector<Box> DrawLegend(Drawing& d, const std::vector<LegendItem>& legend, double x0, double x1, double y);
// Where DrawLegend starts beside a scale bar of 'bar_px' drawn from 'left_px'.
double LegendStart(double left_px, double bar_px);

// The length of a scale bar: 1, 2 or 5 times a power of ten metres, the
// longest of them not over 'max_px' pixels at 'px_per_m'.
double NiceScaleLength(double px_per_m, double max_px);
// "50 cm", "2 m", "500 m", "2 km".
std::string FormatLength(double metres);

// Greedy label placement with collision boxes: each label goes at its anchor
// if that is free, else at the nearest free spot around it (then drawn with
// a leader line), else it is dropped.
class LabelPlacer {
 public:
  explicit LabelPlacer(const Box& bounds) : bounds_(bounds) {}
  // Space already taken (title, legend, other labels).
  void Block(const Box& box) { taken_.push_back(box); }
  struct Placed {
    Box box;
    bool moved = false;  // away from its anchor: draw a leader line
  };
  // 'size' is the label's size (x0 = y0 = 0); the label is centred on the
  // anchor when it can be.
  std::optional<Placed> Place(const Vec2& anchor_px, const Box& size);
  // Places and draws a text label (with a leader line when moved). Returns
  // whether it was drawn.
  bool Label(Drawing& d, const Vec2& anchor_px, const std::string& text, const Font& font, Colour colour,
             Colour halo = Rgb8(255, 255, 255, 0.75));
  int placed() const { return placed_; }
  int dropped() const { return dropped_; }

 private:
  bool Free(const Box& b) const;
  Box bounds_;
  std::vector<Box> taken_;
  int placed_ = 0, dropped_ = 0;
};

}  // namespace cogmap::draw
