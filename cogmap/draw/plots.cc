#include "cogmap/draw/plots.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>

#include "cogmap/core/angles.h"

namespace cogmap::draw {
namespace {

const Colour kGridLine = Rgb8(225, 225, 225);
const Colour kZeroLine = Rgb8(120, 120, 120);
const Font kTick{11};
const Font kPanelTitle{13, true};

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

// One panel: the chosen series over the ASRs in the box, with grid, ticks, axes.
void Panel(Drawing& d, const std::vector<localize::AsrHeadingError>& e, bool raw, bool corrected, const Box& box,
           const std::string& title) {
  double ymax = 0.5;
  for (const auto& a : e) {
    if (raw) ymax = std::max(ymax, std::abs(RadToDeg(a.raw_rad)));
    if (corrected) ymax = std::max(ymax, std::abs(RadToDeg(a.corrected_rad)));
  }
  const double step = NiceStep(2.0 * ymax, 6);
  ymax = std::ceil(ymax / step - 1e-9) * step;
  const size_t n = e.size();
  auto X = [&](size_t i) { return n == 1 ? 0.5 * (box.x0 + box.x1) : box.x0 + box.width() * double(i) / double(n - 1); };
  auto Y = [&](double deg) { return box.y0 + box.height() * (ymax - deg) / (2.0 * ymax); };
  const int digits = step < 1.0 ? 1 : 0;
  for (double v = -ymax; v <= ymax + 1e-9; v += step) {
    const double y = Y(v);
    d.Line(Vec2(box.x0, y), Vec2(box.x1, y), Stroke{std::abs(v) < 1e-9 ? kZeroLine : kGridLine, 1, {}, false});
    d.Text(Vec2(box.x0 - 6, y), Fixed(v, digits), kTick, kBlack, Align::kRight, VAlign::kMiddle);
  }
  const size_t xstep = std::max<size_t>(1, static_cast<size_t>(NiceStep(double(n), 10)));
  for (size_t i = 0; i < n; i += xstep) {
    d.Line(Vec2(X(i), box.y1), Vec2(X(i), box.y1 + 5), Stroke{kBlack, 1, {}, false});
    d.Text(Vec2(X(i), box.y1 + 7), std::to_string(e[i].asr_id), kTick, kBlack, Align::kCenter, VAlign::kTop);
  }
  d.Polyline({Vec2(box.x0, box.y0), Vec2(box.x0, box.y1), Vec2(box.x1, box.y1)}, Stroke{kBlack, 1.2, {}, false});
  d.Text(Vec2(box.x0 + 8, box.y0 + 2), title, kPanelTitle, kBlack);
  for (int series = 0; series < 2; ++series) {
    if ((series == 0 && !raw) || (series == 1 && !corrected)) continue;
    const Colour c = series == 0 ? kRawSeries : kCorrectedSeries;
    std::vector<Vec2> pts;
    for (size_t i = 0; i < n; ++i) pts.emplace_back(X(i), Y(RadToDeg(series == 0 ? e[i].raw_rad : e[i].corrected_rad)));
    d.Polyline(pts, Stroke{c, 2});
    for (const auto& p : pts) d.Circle(p, 3, c);
  }
}

}  // namespace

Drawing PlotHeadingErrors(const localize::HeadingErrorStats& stats, double width, double height) {
  Drawing d(std::max(width, 300.0), std::max(height, 240.0));
  const double left = 64, right = 20, top = 64, gap = 48, bottom = 44;
  d.Text(Vec2(left, 10), "Heading error per ASR, degrees (one global rotation removed)", Font{18, true});
  if (stats.per_asr.empty()) {
    d.Text(Vec2(d.width() / 2, d.height() / 2), "No ground truth in the log", Font{16}, kBlack, Align::kCenter,
           VAlign::kMiddle);
    return d;
  }
  // Legend under the title.
  const double ly = 44;
  d.Line(Vec2(left, ly), Vec2(left + 24, ly), Stroke{kRawSeries, 3});
  const Box b = d.Text(Vec2(left + 30, ly),
                       "odometry: median " + Fixed(stats.median_raw_deg, 2) + ", max " + Fixed(stats.max_raw_deg, 2),
                       Font{13}, kBlack, Align::kLeft, VAlign::kMiddle);
  const double lx = b.x1 + 30;
  d.Line(Vec2(lx, ly), Vec2(lx + 24, ly), Stroke{kCorrectedSeries, 3});
  d.Text(Vec2(lx + 30, ly), "corrected: median " + Fixed(stats.median_deg, 2) + ", max " + Fixed(stats.max_deg, 2),
         Font{13}, kBlack, Align::kLeft, VAlign::kMiddle);
  // Top: both series; bottom: the corrected one on its own scale.
  const double x0 = left, x1 = d.width() - right;
  const double h = (d.height() - top - gap - bottom) / 2;
  Panel(d, stats.per_asr, true, true, Box{x0, top, x1, top + h}, "odometry and corrected");
  Panel(d, stats.per_asr, false, true, Box{x0, top + h + gap, x1, top + 2 * h + gap}, "corrected, on its own scale");
  d.Text(Vec2((x0 + x1) / 2, d.height() - 6), "ASR (visiting order)", Font{12}, kBlack, Align::kCenter, VAlign::kBottom);
  return d;
}

}  // namespace cogmap::draw
