#pragma once
#include <string>
#include <vector>

#include "cogmap/core/geometry.h"

namespace cogmap::io {

// A small SVG writer in world metres: the viewBox covers [min, max] with y
// flipped (world y up, SVG y down), so coordinates stay in metres and any
// viewer scales the picture. Colours are CSS strings ("#c00", "black").
class SvgWriter {
 public:
  // 'px_per_m' sets the width/height attributes only (the default view size).
  SvgWriter(const Vec2& min_m, const Vec2& max_m, double px_per_m = 50.0);

  // Groups nest; 'attributes' is raw SVG, e.g. R"(stroke="red")".
  void BeginGroup(const std::string& id, const std::string& attributes = "");
  void EndGroup();

  void AddPolyline(const Polyline& line, const std::string& stroke, double width_m,
                   const std::string& extra = "");
  void AddSegment(const Segment2& s, const std::string& stroke, double width_m,
                  const std::string& extra = "");
  void AddCircle(const Vec2& c, double radius_m, const std::string& fill,
                 const std::string& extra = "");
  // Text with its baseline starting at 'p', upright.
  void AddText(const Vec2& p, const std::string& text, double size_m, const std::string& fill = "black");
  // Raw SVG inside the current group (coordinates must already be flipped:
  // use Y(y)).
  void AddRaw(const std::string& svg);

  double Y(double world_y) const { return -world_y; }
  // The document (closes any open group).
  std::string str() const;
  // Writes str() atomically.
  void Write(const std::string& path) const;

 private:
  Vec2 min_, max_;
  double px_per_m_;
  std::string body_;
  int open_groups_ = 0;
};

// XML-escapes text (&, <, >, ", ').
std::string XmlEscape(const std::string& text);

}  // namespace cogmap::io
