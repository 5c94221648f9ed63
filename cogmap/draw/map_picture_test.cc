#include "cogmap/draw/map_picture.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>

#include "cogmap/draw/svg_test_util.h"

namespace cogmap::draw {
namespace {

// One room, walls on the box [x0, x0 + w] x [0, h], its path along the middle.
io::MasterRoom Room(int id, double x0, double w, double h) {
  io::MasterRoom r;
  r.id = id;
  r.walls = {{Vec2(x0, 0), Vec2(x0 + w, 0), Vec2(x0 + w, h), Vec2(x0, h), Vec2(x0, 0)}};
  r.path = {Vec2(x0 + 0.3 * w, h / 2), Vec2(x0 + 0.7 * w, h / 2)};
  r.label_m = Vec2(x0 + w / 2, h / 2);
  return r;
}

io::MasterMap Rooms(int n, double w, double h) {
  io::MasterMap m;
  for (int i = 0; i < n; ++i) m.rooms.push_back(Room(i, i * w, w, h));
  for (int i = 0; i + 1 < n; ++i) m.exits.push_back({i, i + 1, Vec2((i + 1) * w, h / 2), 0.9});
  m.min = Vec2(0, 0);
  m.max = Vec2(n * w, h);
  return m;
}

io::Rgb Rgb(const Colour& c) {
  return io::Rgb{static_cast<uint8_t>(c.r * 255 + 0.5), static_cast<uint8_t>(c.g * 255 + 0.5),
                 static_cast<uint8_t>(c.b * 255 + 0.5)};
}

TEST(DrawMasterMap, FitsTheLongestSideToTheBudget) {
  const MapPicture p = DrawMasterMap(Rooms(2, 4, 3));  // 8 x 3 m
  const double longest = std::max(p.drawing.width(), p.drawing.height());
  EXPECT_LE(longest, 2000);
  EXPECT_GE(longest, 1990);
  EXPECT_NEAR(p.map_box.width(), (8 + 1) * p.px_per_m, 1e-6);  // 0.5 m margin each side
}

TEST(DrawMasterMap, SmallCourseIsScaledUp) {
  const MapPicture p = DrawMasterMap(Rooms(1, 2, 1.5));  // a 2 m EV3 course
  EXPECT_GT(p.px_per_m, 500);
  EXPECT_LE(std::max(p.drawing.width(), p.drawing.height()), 2000);
}

TEST(DrawMasterMap, ThousandRoomsStayWithinTheBudget) {
  const MapPicture p = DrawMasterMap(Rooms(1000, 5, 4));  // 5 km long
  EXPECT_LE(p.drawing.width(), 2000);
  EXPECT_LE(p.drawing.height(), 2000);
  EXPECT_GE(p.drawing.width(), 1990);
  EXPECT_GT(p.labels_dropped, 0);  // 1000 labels do not fit in 2000 px
  const io::RgbImage img = p.drawing.Rasterize();
  EXPECT_LE(img.width(), 2000);
  EXPECT_LE(img.height(), 2000);
}

TEST(DrawMasterMap, PxPerMetreOverrides) {
  MapPictureOptions o;
  o.picture.px_per_m = 10;
  const MapPicture p = DrawMasterMap(Rooms(2, 4, 3), o);
  EXPECT_DOUBLE_EQ(p.px_per_m, 10);
  EXPECT_NEAR(p.map_box.width(), 90, 1e-9);
}

TEST(DrawMasterMap, PngHasWallPixelsWhereTheWallsAre) {
  const io::MasterMap m = Rooms(2, 4, 3);
  const MapPicture p = DrawMasterMap(m);
  const io::RgbImage img = test::DecodePng(p.drawing.Encode(Format::kPng), "map.png");
  EXPECT_EQ(img.width(), static_cast<int>(std::ceil(p.drawing.width())));
  for (const auto& r : m.rooms) {
    const io::Rgb c = Rgb(RoomColour(r.id));
    const auto& l = r.walls[0];
    for (size_t i = 1; i < l.size(); ++i)
      for (double t : {0.25, 0.5, 0.75}) {
        const Vec2 px = p.Px(l[i - 1] + t * (l[i] - l[i - 1]));
        // Where two rooms share a wall the later one is drawn on top.
        const bool shared = std::abs(l[i - 1].x() - 4) < 1e-9 && std::abs(l[i].x() - 4) < 1e-9;
        if (shared && r.id == 0) continue;
        if (std::abs(t - 0.5) < 1e-9 && shared) continue;  // the exit's disc
        EXPECT_TRUE(test::ColourNear(img, px.x(), px.y(), c)) << r.id << " " << px.transpose();
      }
  }
  // Inside a room, away from path, label and exits: white.
  const Vec2 in = p.Px(Vec2(1, 0.6));
  EXPECT_EQ(img.at(static_cast<int>(in.x()), static_cast<int>(in.y())), (io::Rgb{255, 255, 255}));
}

TEST(DrawMasterMap, ScaleBarIsItsMetresTimesTheScale) {
  const MapPicture p = DrawMasterMap(Rooms(3, 4, 3));
  const io::RgbImage img = p.drawing.Rasterize();
  const int y = static_cast<int>(p.scale_bar.start_px.y());
  int x = static_cast<int>(p.scale_bar.start_px.x()) - 3;
  while (x < img.width() && img.at(x, y).r > 128) ++x;  // to the bar's left end
  const int left = x;
  while (x < img.width() && img.at(x, y).r <= 128) ++x;
  const int length_px = x - left;
  EXPECT_NEAR(length_px, p.scale_bar.length_m * p.px_per_m, 1.0);
  EXPECT_GT(length_px, 40);
  EXPECT_NEAR(left, p.scale_bar.start_px.x(), 1.0);
}

TEST(DrawMasterMap, SvgWallsAreAtTheirPixels) {
  const io::MasterMap m = Rooms(2, 4, 3);
  const MapPicture p = DrawMasterMap(m);
  const auto paths = test::ParseSvgPaths(p.drawing.Encode(Format::kSvg));
  for (const auto& r : m.rooms) {
    const io::Rgb c = Rgb(RoomColour(r.id));
    int found = 0;
    for (const auto& path : paths) {
      if (!path.stroked || path.r != c.r || path.g != c.g || path.b != c.b || path.points.size() != 5) continue;
      ++found;
      for (size_t i = 0; i < 5; ++i) {
        const Vec2 want = p.Px(r.walls[0][i]);
        EXPECT_NEAR(path.points[i].x(), want.x(), 0.01);
        EXPECT_NEAR(path.points[i].y(), want.y(), 0.01);
      }
    }
    EXPECT_EQ(found, 1) << r.id;
  }
}

TEST(DrawMasterMap, LabelsDoNotOverlap) {
  // Twenty rooms whose labels all sit at the same point.
  io::MasterMap m = Rooms(20, 0.5, 0.5);
  for (auto& r : m.rooms) r.label_m = Vec2(5, 0.25);
  const MapPicture p = DrawMasterMap(m);
  EXPECT_EQ(p.labels_placed + p.labels_dropped, 20);
  EXPECT_GT(p.labels_placed, 5);
}

TEST(MapPage, ANarrowMapKeepsItsTitleScaleNoteAndLegendApartAndOnThePage) {
  // A corridor 60 m long and 3 m wide, standing up, with a long title: the
  // map alone would make a page some 130 px wide.
  PictureOptions o;
  o.max_side_px = 1000;
  o.title = "After: pose graph (default)";
  const std::vector<LegendItem> legend = {{LegendItem::Kind::kLine, kBlack, "walls (a colour per ASR)"},
                                          {LegendItem::Kind::kLine, kBlack, "robot path"},
                                          {LegendItem::Kind::kDisc, kBlack, "exit"},
                                          {LegendItem::Kind::kDashed, kBlack, "room graph"}};
  MapPage page(Vec2(0, 0), Vec2(3, 90), o, legend);
  ASSERT_LT(page.px_per_m(), 10.0);  // the scale note at its longest: "1 m = 9.99 px"
  Drawing d = page.NewDrawing();
  std::vector<Box> used = page.Decorate(d);
  const Box whole{0, 0, page.width_px(), page.height_px()};
  // (Less the bottom band's own box, which holds the legend, bar and arrow.)
  used.erase(std::remove_if(used.begin(), used.end(), [&](const Box& b) { return b.width() >= whole.width(); }),
             used.end());
  ASSERT_EQ(used.size(), 2u + legend.size() + 1u);  // title, note, legend labels, north arrow
  for (size_t i = 0; i < used.size(); ++i) {
    EXPECT_TRUE(used[i].Inside(whole)) << i << ": " << used[i].x0 << " " << used[i].x1 << " of " << page.width_px();
    for (size_t j = i + 1; j < used.size(); ++j) EXPECT_FALSE(used[i].Overlaps(used[j])) << i << " and " << j;
  }
  EXPECT_LE(page.height_px(), 1000);
  EXPECT_LE(page.width_px(), 1000);
}

TEST(DrawSideBySide, BothPanelsFitTheBudget) {
  const Drawing d = DrawSideBySide(Rooms(2, 4, 3), "before", Rooms(2, 4, 3), "after");
  EXPECT_LE(d.width(), 2000);
  EXPECT_GT(d.width(), 1500);
}

}  // namespace
}  // namespace cogmap::draw
