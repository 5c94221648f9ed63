#include "cogmap/draw/plots.h"

#include <gtest/gtest.h>

#include "cogmap/core/angles.h"
#include "cogmap/draw/svg_test_util.h"

namespace cogmap::draw {
namespace {

localize::HeadingErrorStats ThreeAsrs() {
  localize::HeadingErrorStats st;
  st.asrs = 3;
  for (int i = 0; i < 3; ++i) {
    localize::AsrHeadingError e;
    e.asr_id = i;
    e.raw_rad = DegToRad(i == 0 ? -10.0 : i == 1 ? 5.0 : 10.0);
    e.corrected_rad = DegToRad(0.3 * i);
    st.per_asr.push_back(e);
  }
  return st;
}

int CountNear(const io::RgbImage& img, io::Rgb c) {
  int n = 0;
  for (const auto& p : img.pixels())
    n += std::abs(p.r - c.r) < 20 && std::abs(p.g - c.g) < 20 && std::abs(p.b - c.b) < 20;
  return n;
}

TEST(PlotHeadingErrors, DrawsBothSeriesInTheirColours) {
  const io::RgbImage img = PlotHeadingErrors(ThreeAsrs(), 640, 360).Rasterize();
  EXPECT_EQ(img.width(), 640);
  EXPECT_EQ(img.height(), 360);
  EXPECT_GT(CountNear(img, {210, 40, 40}), 200);  // odometry, red
  EXPECT_GT(CountNear(img, {30, 80, 200}), 200);  // corrected, blue (in both panels)
}

TEST(PlotHeadingErrors, SeriesPointsSitOnTheirValues) {
  // Three ASRs: the odometry series goes -10, 5, 10 degrees: in the SVG the
  // red polyline falls 15 degrees, then 5, so its first step is 3 times its second.
  const auto paths = test::ParseSvgPaths(PlotHeadingErrors(ThreeAsrs(), 640, 360).Encode(Format::kSvg));
  int red_lines = 0;
  for (const auto& p : paths)
    if (p.stroked && p.r == 210 && p.g == 40 && p.points.size() == 3) {
      ++red_lines;
      EXPECT_NEAR(p.points[0].y() - p.points[1].y(), 3 * (p.points[1].y() - p.points[2].y()), 1e-3);
      EXPECT_NEAR(p.points[1].x() - p.points[0].x(), p.points[2].x() - p.points[1].x(), 1e-3);
      EXPECT_GT(p.points[0].y(), p.points[2].y());  // -10 below +10
    }
  EXPECT_EQ(red_lines, 1);
}

TEST(PlotHeadingErrors, WithoutTruthSaysSo) {
  const io::RgbImage img = PlotHeadingErrors(localize::HeadingErrorStats{}, 640, 360).Rasterize();
  EXPECT_EQ(CountNear(img, {210, 40, 40}), 0);
  EXPECT_GT(CountNear(img, {0, 0, 0}), 100);  // title and note
}

}  // namespace
}  // namespace cogmap::draw
