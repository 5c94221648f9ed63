#pragma once
// One drawing model, three outputs. A Drawing is a list of painting steps in
// pixel units (x right, y down, origin at the top-left corner); it is replayed
// onto a cairo surface of the format asked for: SVG, PNG or PDF. Text is laid
// out by pango (real fonts, anti-aliased), lines are anti-aliased by cairo.
// Every picture of cogmap is made of one of these (docs/pictures.md).
#include <functional>
#include <memory>
#include <ostream>
#include <string>
#include <utility>
#include <vector>

#include "cogmap/core/geometry.h"
#include "cogmap/io/image.h"

typedef struct _cairo cairo_t;

namespace cogmap::draw {

enum class Format { kSvg, kPng, kPdf };

// The format a file name asks for by its extension (.svg, .png, .pdf, any
// case). Throws InputError naming the path for any other extension.
Format FormatOfPath(const std::string& path);

struct Colour {
  double r = 0, g = 0, b = 0, a = 1;  // 0..1
};
// A colour from 8-bit channels.
constexpr Colour Rgb8(int r, int g, int b, double alpha = 1.0) {
  return Colour{r / 255.0, g / 255.0, b / 255.0, alpha};
}
constexpr Colour kBlack{0, 0, 0, 1};
constexpr Colour kWhite{1, 1, 1, 1};

struct Stroke {
  Stroke(Colour c = kBlack, double width = 1.0, std::vector<double> dash = {}, bool round_ends = true)
      : colour(c), width_px(width), dash_px(std::move(dash)), round(round_ends) {}
  Colour colour = kBlack;
  double width_px = 1.0;
  std::vector<double> dash_px;  // empty: solid
  bool round = true;            // round caps and joins (else butt / miter)
};

struct Font {
  double size_px = 13.0;
  bool bold = false;
};

// An axis-aligned box in pixels.
struct Box {
  double x0 = 0, y0 = 0, x1 = 0, y1 = 0;
  double width() const { return x1 - x0; }
  double height() const { return y1 - y0; }
  bool Overlaps(const Box& o) const { return x0 < o.x1 && o.x0 < x1 && y0 < o.y1 && o.y0 < y1; }
  bool Inside(const Box& outer) const {
    return x0 >= outer.x0 && y0 >= outer.y0 && x1 <= outer.x1 && y1 <= outer.y1;
  }
  Box Grown(double d) const { return {x0 - d, y0 - d, x1 + d, y1 + d}; }
};

enum class Align { kLeft, kCenter, kRight };
enum class VAlign { kTop, kMiddle, kBottom };

class Drawing {
 public:
  // A white page of width x height pixels (rounded up to whole pixels in PNG).
  Drawing(double width_px, double height_px, Colour background = kWhite);

  double width() const { return width_; }
  double height() const { return height_; }

  void Line(const Vec2& a, const Vec2& b, const Stroke& stroke);
  void Polyline(const std::vector<Vec2>& points, const Stroke& stroke, bool closed = false);
  // A filled polygon, outlined when 'outline' has a positive width.
  void Polygon(const std::vector<Vec2>& points, Colour fill, const Stroke& outline = Stroke{kBlack, 0.0});
  void Circle(const Vec2& centre, double radius_px, Colour fill);
  void Rectangle(const Box& box, Colour fill, const Stroke& outline = Stroke{kBlack, 0.0});
  // Text placed by its box: 'at' is the point the alignment names (e.g.
  // kCenter + kMiddle: the box's centre). Returns the box it covers.
  Box Text(const Vec2& at, const std::string& text, const Font& font, Colour colour = kBlack,
           Align align = Align::kLeft, VAlign valign = VAlign::kTop);
  // The size the text takes (x0 = y0 = 0).
  static Box MeasureText(const std::string& text, const Font& font);
  // Starts reading the system's font configuration and loading 'fonts' on a
  // thread of its own: called when a run begins, the text drawn at its end
  // does not wait for them (on nine_rooms' floor plan, 30 -> 11 ms for the
  // picture). Text measured or drawn meanwhile waits for that thread.
  static void PrepareFonts(const std::vector<Font>& fonts = {});
  // Starts loading the drawing libraries (cairo, pango and theirs, some 15
  // shared libraries bound at once) on a thread of their own, without
  // reading any font: for a run whose pictures are drawn at its end, when
  // the fonts' tables are better loaded late (PrepareFonts then finds the
  // libraries loaded).
  static void PrepareLibraries();
  // A raster drawn with its top-left corner at (x, y), each pixel a square of
  // 'scale' drawing pixels, without smoothing (cells stay crisp).
  void Image(const io::RgbImage& image, double x, double y, double scale);
  // Another drawing placed with its top-left corner at (x, y), scaled.
  void Place(const Drawing& other, double x, double y, double scale = 1.0);

  // The drawing as file bytes: SVG (units px), PNG (8-bit RGB, ceil(width) x
  // ceil(height) pixels) or PDF (1 px = 1 pt).
  std::string Encode(Format format) const;
  // The same, written to 'out' as cairo produces it.
  void EncodeTo(Format format, std::ostream& out) const;
  // Rasterised as the PNG would be.
  io::RgbImage Rasterize() const;
  // Writes the format the extension names, atomically (io::WriteFileAtomically).
  void Write(const std::string& path) const&;
  // The same for a drawing's last use (std::move(drawing).Write(path)): each
  // step goes as soon as cairo has taken it. Cairo's SVG and PDF surfaces
  // record the whole page before they write it, so a big picture is not
  // held twice. The drawing is blank afterwards.
  void Write(const std::string& path) &&;

  // Replays every step onto a cairo context (in the drawing's pixel units).
  void Replay(cairo_t* cr) const;

 private:
  using Step = std::function<void(cairo_t*)>;
  // 'release': each step goes once replayed (unless a copy shares them).
  void Replay(cairo_t* cr, bool release) const;
  void EncodeTo(Format format, std::ostream& out, bool release) const;
  void Write(const std::string& path, bool release) const;
  // A stroked polyline, joined to the last step when that one strokes the
  // same opaque way (drawing.cc).
  struct StrokeBatch;
  void Stroked(std::vector<Vec2> points, const Stroke& stroke, bool closed);
  double width_, height_;
  Colour background_;
  std::shared_ptr<std::vector<Step>> steps_;
  std::weak_ptr<StrokeBatch> open_batch_;  // the last step's lines, while it is one
  size_t open_batch_step_ = 0;
};

}  // namespace cogmap::draw
