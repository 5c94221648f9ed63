#include "cogmap/io/svg.h"

#include <cstdio>

#include "cogmap/io/atomic_file.h"

namespace cogmap::io {
namespace {

std::string Num(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.4f", v);
  std::string s(buf);
  while (!s.empty() && s.back() == '0') s.pop_back();
  if (!s.empty() && s.back() == '.') s.pop_back();
  if (s == "-0") s = "0";
  return s;
}

}  // namespace

std::string XmlEscape(const std::string& text) {
  std::string out;
  for (char c : text) {
    switch (c) {
      case '&': out += "&amp;"; break;
      case '<': out += "&lt;"; break;
      case '>': out += "&gt;"; break;
      case '"': out += "&quot;"; break;
      case '\'': out += "&apos;"; break;
      default: out += c;
    }
  }
  return out;
}

SvgWriter::SvgWriter(const Vec2& min_m, const Vec2& max_m, double px_per_m)
    : min_(min_m), max_(max_m), px_per_m_(px_per_m) {}

void SvgWriter::BeginGroup(const std::string& id, const std::string& attributes) {
  body_ += "<g id=\"" + XmlEscape(id) + "\"" + (attributes.empty() ? "" : " " + attributes) + ">\n";
  ++open_groups_;
}

void SvgWriter::EndGroup() {
  if (open_groups_ == 0) return;
  body_ += "</g>\n";
  --open_groups_;
}

void SvgWriter::AddPolyline(const Polyline& line, const std::string& stroke, double width_m,
                            const std::string& extra) {
  if (line.empty()) return;
  body_ += "<polyline fill=\"none\" stroke=\"" + stroke + "\" stroke-width=\"" + Num(width_m) +
           "\" stroke-linejoin=\"round\" stroke-linecap=\"round\"" + (extra.empty() ? "" : " " + extra) +
           " points=\"";
  for (size_t i = 0; i < line.size(); ++i) {
    if (i) body_ += ' ';
    body_ += Num(line[i].x()) + "," + Num(Y(line[i].y()));
  }
  body_ += "\"/>\n";
}

void SvgWriter::AddSegment(const Segment2& s, const std::string& stroke, double width_m,
                           const std::string& extra) {
  body_ += "<line x1=\"" + Num(s.a.x()) + "\" y1=\"" + Num(Y(s.a.y())) + "\" x2=\"" + Num(s.b.x()) +
           "\" y2=\"" + Num(Y(s.b.y())) + "\" stroke=\"" + stroke + "\" stroke-width=\"" + Num(width_m) +
           "\"" + (extra.empty() ? "" : " " + extra) + "/>\n";
}

void SvgWriter::AddCircle(const Vec2& c, double radius_m, const std::string& fill, const std::string& extra) {
  body_ += "<circle cx=\"" + Num(c.x()) + "\" cy=\"" + Num(Y(c.y())) + "\" r=\"" + Num(radius_m) +
           "\" fill=\"" + fill + "\"" + (extra.empty() ? "" : " " + extra) + "/>\n";
}

void SvgWriter::AddText(const Vec2& p, const std::string& text, double size_m, const std::string& fill) {
  body_ += "<text x=\"" + Num(p.x()) + "\" y=\"" + Num(Y(p.y())) + "\" font-size=\"" + Num(size_m) +
           "\" font-family=\"sans-serif\" fill=\"" + fill + "\">" + XmlEscape(text) + "</text>\n";
}

void SvgWriter::AddRaw(const std::string& svg) { body_ += svg; }

std::string SvgWriter::str() const {
  const Vec2 size = max_ - min_;
  std::string out = "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n";
  out += "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" + Num(size.x() * px_per_m_) + "\" height=\"" +
         Num(size.y() * px_per_m_) + "\" viewBox=\"" + Num(min_.x()) + " " + Num(-max_.y()) + " " +
         Num(size.x()) + " " + Num(size.y()) + "\">\n";
  out += body_;
  for (int i = 0; i < open_groups_; ++i) out += "</g>\n";
  out += "</svg>\n";
  return out;
}

void SvgWriter::Write(const std::string& path) const { WriteFileAtomically(path, str()); }

}  // namespace cogmap::io
