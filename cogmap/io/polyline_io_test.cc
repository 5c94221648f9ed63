#include "cogmap/io/polyline_io.h"

#include <gtest/gtest.h>

#include <filesystem>

#include "cogmap/core/error.h"
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

}  // namespace
}  // namespace cogmap::io
