// map.svg as a browser shows it: headless Chromium renders the SVG cogmap
// writes, and the walls are where the map puts them (issue 11).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <string>

#include "cogmap/draw/map_picture.h"
#include "cogmap/draw/svg_test_util.h"

namespace cogmap::draw {
namespace {

std::string FindChromium() {
  for (const char* p : {"/usr/bin/chromium", "/usr/bin/chromium-browser", "/usr/bin/google-chrome"})
    if (std::filesystem::exists(p)) return p;
  return "";
}

io::MasterMap LShapedRooms() {
  io::MasterMap m;
  io::MasterRoom a;
  a.id = 0;
  a.walls = {{Vec2(0, 0), Vec2(6, 0), Vec2(6, 4)}, {Vec2(6, 5.5), Vec2(6, 8), Vec2(0, 8), Vec2(0, 0)}};
  a.path = {Vec2(1, 4), Vec2(5, 4)};
  a.label_m = Vec2(3, 4);
  io::MasterRoom b;
  b.id = 1;
  b.walls = {{Vec2(6, 4), Vec2(14, 4), Vec2(14, 5.5), Vec2(6, 5.5)}};
  b.path = {Vec2(6.5, 4.75), Vec2(13, 4.75)};
  b.label_m = Vec2(10, 4.75);
  m.rooms = {a, b};
  m.exits = {{0, 1, Vec2(6, 4.75), 1.5}};
  m.min = Vec2(0, 0);
  m.max = Vec2(14, 8);
  return m;
}

io::Rgb Rgb(const Colour& c) {
  return io::Rgb{static_cast<uint8_t>(c.r * 255 + 0.5), static_cast<uint8_t>(c.g * 255 + 0.5),
                 static_cast<uint8_t>(c.b * 255 + 0.5)};
}

TEST(MapSvgInChromium, WallPixelsAreWhereTheWallsAre) {
  const std::string chromium = FindChromium();
  if (chromium.empty()) GTEST_SKIP() << "chromium is not installed (scripts/install-deps.sh installs it)";
  const io::MasterMap map = LShapedRooms();
  MapPictureOptions options;
  options.picture.max_side_px = 800;
  const MapPicture pic = DrawMasterMap(map, options);
  const std::string dir = testing_util::TestTempDir();
  pic.drawing.Write(dir + "/map.svg");
  const int w = static_cast<int>(std::ceil(pic.drawing.width())), h = static_cast<int>(std::ceil(pic.drawing.height()));
  const std::string shot = dir + "/shot.png";
  const std::string cmd = chromium + " --headless --no-sandbox --disable-gpu --hide-scrollbars --force-device-scale-factor=1" +
                          " --user-data-dir=" + dir + "/profile --window-size=" + std::to_string(w) + "," +
                          std::to_string(h) + " --screenshot=" + shot + " file://" + dir + "/map.svg >" + dir +
                          "/chromium.log 2>&1";
  ASSERT_EQ(std::system(cmd.c_str()), 0) << cmd;
  const io::RgbImage img = io::ReadRgbPng(shot);
  ASSERT_EQ(img.width(), w);
  ASSERT_EQ(img.height(), h);
  int checked = 0;
  for (const auto& r : map.rooms) {
    const io::Rgb c = Rgb(RoomColour(r.id));
    for (const auto& l : r.walls)
      for (size_t i = 1; i < l.size(); ++i)
        for (double t : {0.2, 0.4, 0.6, 0.8}) {
          const Vec2 m = l[i - 1] + t * (l[i] - l[i - 1]);
          if ((m - map.exits[0].center_m).norm() < 0.5) continue;  // under the exit's disc
          if (r.id == 0 && std::abs(m.x() - 6) < 1e-9 && m.y() > 3.9 && m.y() < 5.6) continue;
          const Vec2 px = pic.Px(m);
          EXPECT_TRUE(test::ColourNear(img, px.x(), px.y(), c, 1, 50)) << "ASR " << r.id << " at " << m.transpose();
          ++checked;
        }
  }
  EXPECT_GT(checked, 20);
  // And nothing drawn in the middle of the big room, off the path and label.
  const Vec2 empty = pic.Px(Vec2(1.5, 6.5));
  EXPECT_EQ(img.at(static_cast<int>(empty.x()), static_cast<int>(empty.y())), (io::Rgb{255, 255, 255}));
}

}  // namespace
}  // namespace cogmap::draw
