#include "cogmap/localize/correction_figures.h"

#include <gtest/gtest.h>

namespace cogmap::localize {
namespace {

int CountColour(const io::RgbImage& img, io::Rgb c) {
  int n = 0;
  for (const auto& p : img.pixels()) n += p == c;
  return n;
}

int Count(const std::string& s, const std::string& what) {
  int n = 0;
  for (size_t p = s.find(what); p != std::string::npos; p = s.find(what, p + 1)) ++n;
  return n;
}

HeadingErrorStats ThreeAsrs() {
  HeadingErrorStats st;
  st.asrs = 3;
  for (int i = 0; i < 3; ++i) {
    AsrHeadingError e;
    e.asr_id = i;
    e.raw_rad = DegToRad(10.0 * i - 10.0);
    e.corrected_rad = DegToRad(0.3 * i);
    st.per_asr.push_back(e);
  }
  return st;
}

TEST(PlotHeadingErrors, DrawsBothSeriesInTheirColours) {
  const io::RgbImage img = PlotHeadingErrors(ThreeAsrs(), 640, 360);
  EXPECT_EQ(img.width(), 640);
  EXPECT_EQ(img.height(), 360);
  EXPECT_GT(CountColour(img, {210, 40, 40}), 200);  // odometry, red
  EXPECT_GT(CountColour(img, {30, 80, 200}), 200);  // corrected, blue
}

TEST(PlotHeadingErrors, WithoutTruthSaysSo) {
  const io::RgbImage img = PlotHeadingErrors(HeadingErrorStats{}, 640, 360);
  EXPECT_EQ(CountColour(img, {210, 40, 40}), 0);
  EXPECT_GT(CountColour(img, {0, 0, 0}), 100);  // title and note
}

TEST(SideBySide, PlacesBothPicturesUnderTheirTitles) {
  const io::RgbImage a(100, 50, {255, 0, 0}), b(80, 70, {0, 0, 255});
  const io::RgbImage out = SideBySide(a, "RAW", b, "CORRECTED");
  EXPECT_EQ(out.width(), 200);
  EXPECT_EQ(out.height(), 100);
  EXPECT_EQ(out.at(10, 40), (io::Rgb{255, 0, 0}));
  EXPECT_EQ(out.at(150, 90), (io::Rgb{0, 0, 255}));
}

TEST(SideBySideSvg, NestsBothDocuments) {
  const std::string a =
      "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"100\" "
      "height=\"50\" viewBox=\"0 0 5 2.5\">\n<rect/>\n</svg>\n";
  const std::string b =
      "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"80\" height=\"70\" viewBox=\"0 0 4 3.5\">\n</svg>\n";
  const std::string s = SideBySideSvg(a, "before & after", b, "after");
  EXPECT_EQ(Count(s, "<svg"), 3);
  EXPECT_EQ(Count(s, "</svg>"), 3);
  EXPECT_EQ(Count(s, "<?xml"), 1);
  EXPECT_NE(s.find("width=\"200\" height=\"100\""), std::string::npos);
  EXPECT_NE(s.find("<svg x=\"120\" y=\"30\" xmlns"), std::string::npos);
  EXPECT_NE(s.find("before &amp; after"), std::string::npos);
}

}  // namespace
}  // namespace cogmap::localize
