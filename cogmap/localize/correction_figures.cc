#include "cogmap/localize/correction_figures.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <regex>
#include <sstream>

namespace cogmap::localize {
namespace {

constexpr io::Rgb kBlack{0, 0, 0};
constexpr io::Rgb kGrid{225, 225, 225};
constexpr io::Rgb kRaw{210, 40, 40};
constexpr io::Rgb kCorrected{30, 80, 200};

std::string Fixed(double v, int digits) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.*f", digits, v);
  return buf;
}

// A tick step of 1, 2 or 5 x 10^k giving about 'ticks' intervals over 'span'.
double NiceStep(double span, int ticks) {
  const double raw = span / std::max(1, ticks);
  const double p = std::pow(10.0, std::floor(std::log10(raw)));
  for (double m : {1.0, 2.0, 5.0, 10.0})
    if (m * p >= raw) return m * p;
  return 10.0 * p;
}

std::string XmlEscape(const std::string& s) {
  std::string out;
  for (char c : s) {
    if (c == '&') out += "&amp;";
    else if (c == '<') out += "&lt;";
    else if (c == '>') out += "&gt;";
    else if (c == '"') out += "&quot;";
    else out += c;
  }
  return out;
}

double Attribute(const std::string& tag, const std::string& name) {
  const std::regex re("\\s" + name + "=\"([0-9.eE+-]+)\"");
  std::smatch m;
  if (std::regex_search(tag, m, re)) return std::atof(m[1].str().c_str());
  return 0.0;
}

// The document without its XML declaration, and its root's width and height.
struct SvgDoc {
  std::string body;
  double width = 0.0, height = 0.0;
};
SvgDoc ParseSvg(const std::string& svg) {
  SvgDoc d;
  size_t start = svg.find("<svg");
  if (start == std::string::npos) return d;
  d.body = svg.substr(start);
  const size_t end = d.body.find('>');
  const std::string tag = d.body.substr(0, end);
  d.width = Attribute(tag, "width");
  d.height = Attribute(tag, "height");
  return d;
}

}  // namespace

namespace {

// One panel of the heading error plot: the chosen series over the ASRs, in
// the rectangle [x0, x1] x [y0, y1] (pixels), with grid, ticks and axes.
void DrawPanel(io::RgbImage& img, const std::vector<AsrHeadingError>& e, bool raw, bool corrected, int x0,
               int x1, int y0, int y1, const std::string& title) {
  double ymax = 0.5;
  for (const auto& a : e) {
    if (raw) ymax = std::max(ymax, std::abs(RadToDeg(a.raw_rad)));
    if (corrected) ymax = std::max(ymax, std::abs(RadToDeg(a.corrected_rad)));
  }
  const double step = NiceStep(2.0 * ymax, 6);
  ymax = std::ceil(ymax / step - 1e-9) * step;
  const size_t n = e.size();
  auto X = [&](size_t i) { return n == 1 ? 0.5 * (x0 + x1) : x0 + (x1 - x0) * double(i) / double(n - 1); };
  auto Y = [&](double deg) { return y0 + (y1 - y0) * (ymax - deg) / (2.0 * ymax); };
  const int digits = step < 1.0 ? 1 : 0;
  for (double v = -ymax; v <= ymax + 1e-9; v += step) {
    const double y = Y(v);
    img.DrawLine(x0, y, x1, y, std::abs(v) < 1e-9 ? io::Rgb{120, 120, 120} : kGrid);
    const std::string label = Fixed(v, digits);
    img.DrawText(x0 - 8 - 6 * static_cast<int>(label.size()), static_cast<int>(y) - 3, label, kBlack);
  }
  const size_t xstep = std::max<size_t>(1, static_cast<size_t>(NiceStep(double(n), 10)));
  for (size_t i = 0; i < n; i += xstep) {
    img.DrawLine(X(i), y1, X(i), y1 + 5, kBlack);
    const std::string label = std::to_string(e[i].asr_id);
    img.DrawText(static_cast<int>(X(i)) - 3 * static_cast<int>(label.size()), y1 + 9, label, kBlack);
  }
  img.DrawLine(x0, y0, x0, y1, kBlack);
  img.DrawLine(x0, y1, x1, y1, kBlack);
  img.DrawText(x0 + 6, y0 + 4, title, kBlack);
  for (int series = 0; series < 2; ++series) {
    if ((series == 0 && !raw) || (series == 1 && !corrected)) continue;
    const io::Rgb c = series == 0 ? kRaw : kCorrected;
    for (size_t i = 0; i < n; ++i) {
      const double v = RadToDeg(series == 0 ? e[i].raw_rad : e[i].corrected_rad);
      if (i > 0) {
        const double u = RadToDeg(series == 0 ? e[i - 1].raw_rad : e[i - 1].corrected_rad);
        img.DrawLine(X(i - 1), Y(u), X(i), Y(v), c, 2);
      }
      img.DrawDisc(X(i), Y(v), 2.5, c);
    }
  }
}

}  // namespace

io::RgbImage PlotHeadingErrors(const HeadingErrorStats& stats, int width, int height) {
  io::RgbImage img(std::max(width, 200), std::max(height, 200));
  const int left = 70, right = 20, top = 46, gap = 44, bottom = 40;
  img.DrawText(left, 8, "HEADING ERROR PER ASR, DEGREES (ONE GLOBAL ROTATION REMOVED)", kBlack, 2);
  if (stats.per_asr.empty()) {
    img.DrawText(left, img.height() / 2, "NO GROUND TRUTH IN THE LOG", kBlack, 2);
    return img;
  }
  // Top: both series; bottom: the corrected one on its own scale.
  const int x0 = left, x1 = img.width() - right;
  const int h = (img.height() - top - gap - bottom) / 2;
  DrawPanel(img, stats.per_asr, true, true, x0, x1, top, top + h, "ODOMETRY AND CORRECTED");
  DrawPanel(img, stats.per_asr, false, true, x0, x1, top + h + gap, top + 2 * h + gap, "CORRECTED, ITS OWN SCALE");
  img.DrawText((x0 + x1) / 2 - 60, img.height() - 14, "ASR (VISITING ORDER)", kBlack, 1);
  // Legend.
  const int ly = 30;
  img.DrawLine(left, ly + 3, left + 24, ly + 3, kRaw, 3);
  img.DrawText(left + 30, ly,
               "ODOMETRY: MEDIAN " + Fixed(stats.median_raw_deg, 2) + " MAX " + Fixed(stats.max_raw_deg, 2), kRaw);
  const int lx = left + 300;
  img.DrawLine(lx, ly + 3, lx + 24, ly + 3, kCorrected, 3);
  img.DrawText(lx + 30, ly, "CORRECTED: MEDIAN " + Fixed(stats.median_deg, 2) + " MAX " + Fixed(stats.max_deg, 2),
               kCorrected);
  return img;
}

io::RgbImage SideBySide(const io::RgbImage& l, const std::string& lt, const io::RgbImage& r,
                        const std::string& rt) {
  const int title = 30, gap = 20;
  io::RgbImage out(l.width() + gap + r.width(), title + std::max(l.height(), r.height()));
  out.DrawText(6, 8, lt, kBlack, 2);
  out.DrawText(l.width() + gap + 6, 8, rt, kBlack, 2);
  out.Blit(l, 0, title);
  out.Blit(r, l.width() + gap, title);
  out.DrawLine(l.width() + gap / 2.0, 0, l.width() + gap / 2.0, out.height() - 1, io::Rgb{180, 180, 180});
  return out;
}

std::string SideBySideSvg(const std::string& left_svg, const std::string& left_title,
                          const std::string& right_svg, const std::string& right_title) {
  const SvgDoc l = ParseSvg(left_svg), r = ParseSvg(right_svg);
  const double title = 30, gap = 20;
  const double w = l.width + gap + r.width, h = title + std::max(l.height, r.height);
  std::ostringstream s;
  s << "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n"
    << "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" << w << "\" height=\"" << h << "\" viewBox=\"0 0 "
    << w << " " << h << "\">\n"
    << "<rect x=\"0\" y=\"0\" width=\"" << w << "\" height=\"" << h << "\" fill=\"white\"/>\n"
    << "<text x=\"6\" y=\"20\" font-family=\"sans-serif\" font-size=\"16\">" << XmlEscape(left_title)
    << "</text>\n"
    << "<text x=\"" << l.width + gap + 6 << "\" y=\"20\" font-family=\"sans-serif\" font-size=\"16\">"
    << XmlEscape(right_title) << "</text>\n";
  // Nested documents, placed by x / y on their root element.
  if (!l.body.empty()) s << "<svg x=\"0\" y=\"" << title << "\"" << l.body.substr(4) << "\n";
  if (!r.body.empty()) s << "<svg x=\"" << l.width + gap << "\" y=\"" << title << "\"" << r.body.substr(4) << "\n";
  s << "</svg>\n";
  return s.str();
}

}  // namespace cogmap::localize
