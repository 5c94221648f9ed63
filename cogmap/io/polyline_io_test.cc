#include "cogmap/io/polyline_io.h"

#include <gtest/gtest.h>

#include <filesystem>

#include "cogmap/core/error.h"
#include "cogmap/io/stages_picture.h"
#include "cogmap/io/svg.h"
#include "cogmap/vectorize/synthetic_grid.h"
#include "cogmap/core/test_temp.h"

namespace cogmap::io {
namespace {

std::string TempPath(const std::string& name) {
  const auto dir = std::filesystem::path(::cogmap::testing_util::TestTempPath("vector_files"));
  std::filesystem::create_directories(dir);
  return (dir / name).string();
}

const std::vector<Polyline> kLines = {{Vec2(0, 0), Vec2(1.25, 0), Vec2(1.25, -2.5)}, {Vec2(3.1416, 2.7183)}};

TEST(PolylineJson, RoundTrip) {
  const auto back = PolylinesFromJson(PolylinesToJson(kLines), "t");
  ASSERT_EQ(back.size(), 2u);
  EXPECT_EQ(back[0], kLines[0]);
  EXPECT_EQ(back[1][0], kLines[1][0]);
}

TEST(PolylineJson, BadInputNamesTheSource) {
  try {
    PolylinesFromJson("[[[1, 2], [3]]]", "walls.json");
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("walls.json"), std::string::npos);
    EXPECT_NE(std::string(e.what()).find("vertex 1"), std::string::npos);
  }
  EXPECT_THROW(PolylinesFromJson("{", "x"), InputError);
  EXPECT_THROW(PolylinesFromJson("{}", "x"), InputError);
}

TEST(PolylineBinary, FileRoundTrip) {
  const auto path = TempPath("walls.cpl");
  WritePolylinesBinary(path, kLines);
  const auto back = ReadPolylinesBinary(path);
  ASSERT_EQ(back.size(), 2u);
  EXPECT_NEAR(back[0][2].y(), -2.5, 1e-9);
  EXPECT_NEAR(back[1][0].x(), 3.14, 1e-9);  // 1 cm quanta
  EXPECT_THROW(ReadPolylinesBinary(TempPath("missing.cpl")), InputError);
}

TEST(WallsFile, RoundTrip) {
  WallsFile w;
  w.polylines = kLines;
  w.world_from_map = Pose2{1, 2, 0.5};
  w.has_truth = true;
  w.log_path = "/tmp/run.log";
  w.mode = "paper";
  w.sensor_range_m = 5.0;
  w.vertex_count = 4;
  w.bytes_grid = 1000;
  w.bytes_vertices = 80;
  w.bytes_polylines = 17;
  const auto path = TempPath("walls.json");
  WriteWallsJson(path, w);
  const auto r = ReadWallsJson(path);
  EXPECT_EQ(r.polylines, w.polylines);
  EXPECT_EQ(r.world_from_map.theta, 0.5);
  EXPECT_TRUE(r.has_truth);
  EXPECT_EQ(r.log_path, "/tmp/run.log");
  EXPECT_EQ(r.mode, "paper");
  EXPECT_EQ(r.bytes_polylines, 17);
  EXPECT_THROW(ReadWallsJson(TempPath("nope.json")), InputError);
}

TEST(Svg, ViewBoxInMetresWithYFlipped) {
  SvgWriter svg(Vec2(-1, 2), Vec2(3, 5), 10.0);
  svg.BeginGroup("walls", "stroke=\"black\"");
  svg.AddPolyline({Vec2(0, 3), Vec2(1, 4)}, "black", 0.05);
  svg.AddCircle(Vec2(0.5, 2.5), 0.1, "red");
  svg.AddText(Vec2(0, 4.5), "a<b", 0.2);
  const std::string s = svg.str();
  EXPECT_NE(s.find("viewBox=\"-1 -5 4 3\""), std::string::npos) << s;
  EXPECT_NE(s.find("width=\"40\" height=\"30\""), std::string::npos);
  EXPECT_NE(s.find("points=\"0,-3 1,-4\""), std::string::npos) << s;
  EXPECT_NE(s.find("cy=\"-2.5\""), std::string::npos);
  EXPECT_NE(s.find("a&lt;b"), std::string::npos);
  EXPECT_NE(s.find("</g>"), std::string::npos);  // closed by str()
}

TEST(StagesPicture, FivePanelsAndWalls) {
  const auto walls = vectorize::RectangleWalls(Vec2(1, 1), Vec2(5, 4));
  const Polyline path = {Vec2(1.8, 1.8), Vec2(4.2, 1.8), Vec2(4.2, 3.2)};
  const auto grid = vectorize::MakeSyntheticGrid(walls, path);
  const auto r = vectorize::Vectorize(grid);
  StagesPictureOptions o;
  const auto img = DrawStages(grid, r, o);
  const int w = grid.limits().width(), h = grid.limits().height();
  const double s = std::min(6.0, 360.0 / std::max(w, h));
  EXPECT_EQ(img.width(), 8 + 5 * (static_cast<int>(std::ceil(w * s)) + 8));
  EXPECT_GT(img.height(), static_cast<int>(h * s));
  const auto walls_img = DrawWalls(r.polylines, walls, Vec2(0, 0), Vec2(6, 5), 20);
  EXPECT_EQ(walls_img.width(), 120);
  EXPECT_EQ(walls_img.height(), 100);
  // An empty result draws blank panels, no crash.
  EXPECT_GT(DrawStages(grid::Grid2D<float>(), vectorize::VectorizeResult{}).width(), 0);
}

}  // namespace
}  // namespace cogmap::io
