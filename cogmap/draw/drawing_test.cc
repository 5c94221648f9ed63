#include "cogmap/draw/drawing.h"

#include <gtest/gtest.h>

#include <cmath>

#include "cogmap/core/error.h"
#include "cogmap/draw/layout.h"
#include "cogmap/draw/svg_test_util.h"
#include "cogmap/draw/cairo_api.h"

namespace cogmap::draw {
namespace {

TEST(FormatOfPath, ByExtensionAnyCase) {
  EXPECT_EQ(FormatOfPath("a/map.svg"), Format::kSvg);
  EXPECT_EQ(FormatOfPath("MAP.PNG"), Format::kPng);
  EXPECT_EQ(FormatOfPath("x.pdf"), Format::kPdf);
  EXPECT_THROW(FormatOfPath("x.jpg"), InputError);
  EXPECT_THROW(FormatOfPath("noext"), InputError);
}

TEST(Drawing, PngHasTheDrawingsSizeAndItsLine) {
  Drawing d(40.5, 20);
  d.Line(Vec2(5, 10), Vec2(35, 10), Stroke{kBlack, 3, {}, false});
  const io::RgbImage img = test::DecodePng(d.Encode(Format::kPng), "line.png");
  EXPECT_EQ(img.width(), 41);
  EXPECT_EQ(img.height(), 20);
  EXPECT_EQ(img.at(20, 10), (io::Rgb{0, 0, 0}));
  EXPECT_EQ(img.at(20, 5), (io::Rgb{255, 255, 255}));
  EXPECT_EQ(img.at(2, 10), (io::Rgb{255, 255, 255}));  // butt cap: nothing before x = 5
}

TEST(Drawing, LinesAreAntiAliased) {
  Drawing d(20, 20);
  d.Line(Vec2(0, 0), Vec2(20, 13), Stroke{kBlack, 1.5});
  const io::RgbImage img = d.Rasterize();
  int grey = 0;
  for (const auto& p : img.pixels()) grey += p.r > 10 && p.r < 245;
  EXPECT_GT(grey, 10);  // partial coverage at the edges of a slanted line
}

TEST(Drawing, SvgKeepsCoordinatesAndColours) {
  Drawing d(100, 50);
  d.Polyline({Vec2(10, 20), Vec2(30.5, 40), Vec2(90, 40)}, Stroke{Rgb8(255, 0, 0), 2});
  const std::string svg = d.Encode(Format::kSvg);
  EXPECT_NE(svg.find("width=\"100px\""), std::string::npos);
  const auto paths = test::ParseSvgPaths(svg);
  int red = 0;
  for (const auto& p : paths)
    if (p.stroked && p.r == 255 && p.g == 0) {
      ++red;
      ASSERT_EQ(p.points.size(), 3u);
      EXPECT_NEAR(p.points[1].x(), 30.5, 1e-6);
      EXPECT_NEAR(p.points[1].y(), 40, 1e-6);
      EXPECT_NEAR(p.width, 2, 1e-9);
    }
  EXPECT_EQ(red, 1);
}

TEST(Drawing, PdfIsAPdf) {
  Drawing d(100, 50);
  d.Text(Vec2(10, 10), "Hello", Font{});
  const std::string pdf = d.Encode(Format::kPdf);
  EXPECT_EQ(pdf.rfind("%PDF-", 0), 0u);
  EXPECT_NE(pdf.find("%%EOF"), std::string::npos);
}

TEST(Drawing, TextIsMeasuredAndDrawnInItsBox) {
  const Box a = Drawing::MeasureText("A1", Font{14});
  const Box b = Drawing::MeasureText("Room 12 (34.5 m2)", Font{14});
  EXPECT_GT(a.width(), 8);
  EXPECT_GT(b.width(), 4 * a.width());
  EXPECT_NEAR(a.height(), b.height(), 1e-9);
  Drawing d(200, 60);
  const Box box = d.Text(Vec2(100, 30), "WWW", Font{20, true}, kBlack, Align::kCenter, VAlign::kMiddle);
  EXPECT_NEAR((box.x0 + box.x1) / 2, 100, 1e-9);
  const io::RgbImage img = d.Rasterize();
  int dark_in = 0, dark_out = 0;
  for (int y = 0; y < img.height(); ++y)
    for (int x = 0; x < img.width(); ++x) {
      if (img.at(x, y).r > 100) continue;
      (x >= box.x0 - 1 && x <= box.x1 + 1 && y >= box.y0 - 1 && y <= box.y1 + 1 ? dark_in : dark_out)++;
    }
  EXPECT_GT(dark_in, 50);
  EXPECT_EQ(dark_out, 0);
}

TEST(Drawing, TextIsSetInDejaVuSansWhateverTheSystemsFonts) {
  // DejaVu Sans (2048 units per em): 'A' advances 1401 units, '1' 1303, so
  // at 14 px 9.58 and 8.91 px, laid out at whole pixels (pango rounds glyph
  // positions): "A1" is 10 + 9 = 19 px wide, from the bundled faces whatever
  // fonts the system's configuration would pick (Liberation Sans: 9 + 8).
  EXPECT_EQ(Drawing::MeasureText("A1", Font{14}).width(),
            std::round(1401.0 / 2048.0 * 14.0) + std::round(1303.0 / 2048.0 * 14.0));
}

TEST(Drawing, TextTheBundledFacesLackIsStillMeasuredAndDrawn) {
  // A room or file name in another script goes to the system's fonts; bytes
  // that are not UTF-8 too. Either way a box, and nothing drawn outside it.
  for (const std::string& text : {std::string("\xe6\xbc\xa2\xe5\xad\x97 2"), std::string("bad \xff\xfe byte")}) {
    const Box size = Drawing::MeasureText(text, Font{14});
    EXPECT_GT(size.width(), 0.0) << text;
    Drawing d(300, 60);
    d.Text(Vec2(10, 10), text, Font{14}, kBlack);
    EXPECT_EQ(d.Rasterize().width(), 300);
  }
}

TEST(Drawing, ImageCellsStayCrisp) {
  io::RgbImage cells(2, 1);
  cells.at(0, 0) = {255, 0, 0};
  cells.at(1, 0) = {0, 0, 255};
  Drawing d(20, 10);
  d.Image(cells, 0, 0, 10);
  const io::RgbImage img = d.Rasterize();
  EXPECT_EQ(img.at(9, 5), (io::Rgb{255, 0, 0}));
  EXPECT_EQ(img.at(10, 5), (io::Rgb{0, 0, 255}));
}

TEST(Drawing, PlaceDrawsAnotherDrawingAtItsOffset) {
  Drawing inner(10, 10, Rgb8(0, 255, 0));
  Drawing outer(30, 30);
  outer.Place(inner, 15, 5);
  const io::RgbImage img = outer.Rasterize();
  EXPECT_EQ(img.at(20, 10), (io::Rgb{0, 255, 0}));
  EXPECT_EQ(img.at(10, 10), (io::Rgb{255, 255, 255}));
  EXPECT_EQ(img.at(20, 20), (io::Rgb{255, 255, 255}));
}

TEST(NiceScaleLength, OneTwoFiveTimesAPowerOfTen) {
  EXPECT_DOUBLE_EQ(NiceScaleLength(100, 220), 2.0);
  EXPECT_DOUBLE_EQ(NiceScaleLength(40, 220), 5.0);
  EXPECT_DOUBLE_EQ(NiceScaleLength(1000, 220), 0.2);
  EXPECT_DOUBLE_EQ(NiceScaleLength(0.01, 220), 20000.0);
  EXPECT_EQ(FormatLength(0.5), "50 cm");
  EXPECT_EQ(FormatLength(2), "2 m");
  EXPECT_EQ(FormatLength(20000), "20 km");
}

TEST(LabelPlacer, LabelsNeverOverlapAndTheRestAreDropped) {
  LabelPlacer placer(Box{0, 0, 200, 100});
  std::vector<Box> boxes;
  for (int i = 0; i < 40; ++i) {
    const auto p = placer.Place(Vec2(100, 50), Box{0, 0, 30, 12});
    if (p) boxes.push_back(p->box);
  }
  EXPECT_EQ(placer.placed(), static_cast<int>(boxes.size()));
  EXPECT_EQ(placer.placed() + placer.dropped(), 40);
  EXPECT_GT(placer.dropped(), 0);
  EXPECT_GE(placer.placed(), 9);  // the centre and its first ring
  for (size_t i = 0; i < boxes.size(); ++i) {
    EXPECT_TRUE(boxes[i].Inside(Box{0, 0, 200, 100}));
    for (size_t j = i + 1; j < boxes.size(); ++j) EXPECT_FALSE(boxes[i].Overlaps(boxes[j])) << i << " " << j;
  }
}

// Every function drawing.cc calls resolves in the installed drawing stack
// (a version without one would fail here, not in the middle of a run).
TEST(DrawingStack, EveryFunctionResolves) {
  const dl::Api& api = dl::Get();
#define COGMAP_EXPECT_RESOLVED(name) EXPECT_NE(api.name, nullptr) << #name;
  COGMAP_DRAW_FUNCTIONS(COGMAP_EXPECT_RESOLVED)
#undef COGMAP_EXPECT_RESOLVED
  EXPECT_EQ(&dl::Get(), &api);  // loaded once
}

TEST(LabelPlacer, BlockedSpaceIsAvoided) {
  LabelPlacer placer(Box{0, 0, 200, 100});
  placer.Block(Box{0, 0, 200, 60});
  const auto p = placer.Place(Vec2(100, 50), Box{0, 0, 30, 12});
  ASSERT_TRUE(p);
  EXPECT_TRUE(p->moved);
  EXPECT_GE(p->box.y0, 60);
}

}  // namespace
}  // namespace cogmap::draw
