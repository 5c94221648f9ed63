#pragma once
// Test helpers: the elements of an SVG that cairo wrote, parsed (paths with
// their stroke colour, width and points), and PNG bytes decoded.
#include <gtest/gtest.h>

#include <cstdio>
#include <fstream>
#include <regex>
#include <string>
#include <vector>

#include "cogmap/core/geometry.h"
#include "cogmap/core/test_temp.h"
#include "cogmap/io/image.h"

namespace cogmap::draw::test {

struct SvgPath {
  std::string style;
  std::vector<Vec2> points;  // every coordinate pair of the path data (M, L, C ends)
  bool stroked = false;
  int r = -1, g = -1, b = -1;  // stroke colour (0..255), when stroked
  double width = 0;
};

inline std::string Attr(const std::string& element, const std::string& name) {
  const std::regex re("\\s" + name + "=\"([^\"]*)\"");
  std::smatch m;
  return std::regex_search(element, m, re) ? m[1].str() : std::string();
}

// Every subpath of every <path> of the document, in order, each with its
// path's style (lines stroked alike are one <path> of several subpaths: see
// Drawing::Polyline).
inline std::vector<SvgPath> ParseSvgPaths(const std::string& svg) {
  std::vector<SvgPath> out;
  const std::regex path_re("<path[^>]*>");
  for (auto it = std::sregex_iterator(svg.begin(), svg.end(), path_re); it != std::sregex_iterator(); ++it) {
    const std::string e = it->str();
    if (e.find(" transform=") != std::string::npos) continue;  // glyph outlines and the like
    SvgPath style;
    style.style = Attr(e, "style");
    std::smatch m;
    const std::regex stroke_re("stroke:rgb\\(([0-9.]+)%,\\s*([0-9.]+)%,\\s*([0-9.]+)%\\)");
    if (std::regex_search(style.style, m, stroke_re)) {
      style.stroked = true;
      style.r = static_cast<int>(std::lround(std::stod(m[1]) * 2.55));
      style.g = static_cast<int>(std::lround(std::stod(m[2]) * 2.55));
      style.b = static_cast<int>(std::lround(std::stod(m[3]) * 2.55));
    }
    const std::regex width_re("stroke-width:([0-9.]+)");
    if (std::regex_search(style.style, m, width_re)) style.width = std::stod(m[1]);
    const std::string d = Attr(e, "d");
    const size_t first = out.size();
    const std::regex sub_re("M[^M]*");
    const std::regex num_re("-?[0-9]+(\\.[0-9]+)?(e-?[0-9]+)?");
    for (auto sub = std::sregex_iterator(d.begin(), d.end(), sub_re); sub != std::sregex_iterator(); ++sub) {
      const std::string part = sub->str();
      std::vector<double> nums;
      for (auto n = std::sregex_iterator(part.begin(), part.end(), num_re); n != std::sregex_iterator(); ++n)
        nums.push_back(std::stod(n->str()));
      SvgPath p = style;
      for (size_t i = 0; i + 1 < nums.size(); i += 2) p.points.emplace_back(nums[i], nums[i + 1]);
      // cairo ends a closed subpath with "Z M x y", the start again: that
      // point stays with the subpath it closes, as in a path of its own.
      if (p.points.size() == 1 && out.size() > first && part.find('L') == std::string::npos &&
          part.find('C') == std::string::npos) {
        out.back().points.push_back(p.points[0]);
        continue;
      }
      out.push_back(std::move(p));
    }
  }
  return out;
}

inline io::RgbImage DecodePng(const std::string& bytes, const std::string& name) {
  const std::string path = testing_util::TestTempPath(name);
  std::ofstream(path, std::ios::binary) << bytes;
  return io::ReadRgbPng(path);
}

// Whether some pixel within 'radius' of (x, y) has colour near 'c'.
inline bool ColourNear(const io::RgbImage& img, double x, double y, io::Rgb c, int radius = 1, int tol = 40) {
  for (int j = -radius; j <= radius; ++j)
    for (int i = -radius; i <= radius; ++i) {
      const int px = static_cast<int>(x) + i, py = static_cast<int>(y) + j;
      if (!img.Inside(px, py)) continue;
      const io::Rgb p = img.at(px, py);
      if (std::abs(p.r - c.r) <= tol && std::abs(p.g - c.g) <= tol && std::abs(p.b - c.b) <= tol) return true;
    }
  return false;
}

}  // namespace cogmap::draw::test
