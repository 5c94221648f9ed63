#include "cogmap/io/map_files.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <sstream>

#include "cogmap/core/test_temp.h"
#include "cogmap/io/gpkg.h"
#include "cogmap/io/grid_io.h"
#include "cogmap/io/world_io.h"

namespace cogmap::io {
namespace {

namespace fs = std::filesystem;

std::string TempDir(const std::string& name) {
  const fs::path dir = fs::path(testing_util::TestTempDir()) / name;
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir.string();
}

std::string Slurp(const std::string& path) {
  std::ifstream in(path);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

// Two 4 m x 3 m rooms side by side, each an ASR with a local frame at its entry.
std::vector<asr::Asr> TwoAsrs() {
  std::vector<asr::Asr> out(2);
  for (int i = 0; i < 2; ++i) {
    asr::Asr& a = out[i];
    a.id = i;
    a.world_from_local_raw = {4.0 * i, 0.0, 0.0};
    a.world_from_local_corrected = a.world_from_local_raw;
    a.walls_local = {{{0, 0}, {4, 0}, {4, 3}, {0, 3}, {0, 0}}};
    for (int k = 0; k <= 10; ++k) a.path.push_back({4.0 * i + 0.5 + 0.3 * k, 1.5, 0.0});
  }
  out[0].exits.push_back({{4.0, 1.5}, 0.9, 0, 1});
  out[1].exits.push_back({{4.0, 1.5}, 0.9, 0, 1});
  return out;
}

TEST(MasterMap, PlacesAsrsAndKeepsEachExitOnce) {
  const MasterMap m = BuildMasterMap(TwoAsrs());
  ASSERT_EQ(m.rooms.size(), 2u);
  EXPECT_EQ(m.rooms[1].walls[0][1], Vec2(8, 0));
  ASSERT_EQ(m.exits.size(), 1u);
  EXPECT_EQ(m.exits[0].to_asr, 1);
  EXPECT_EQ(m.min, Vec2(0, 0));
  EXPECT_EQ(m.max, Vec2(8, 3));
  EXPECT_NEAR(m.rooms[0].label_m.x(), 2.0, 1e-12);
}

TEST(MasterMap, UsesTheCorrectedPoseAndCarriesExits) {
  auto asrs = TwoAsrs();
  asrs[0].world_from_local_corrected = {0.0, 0.0, kPi / 2};  // rotated about its origin
  const MasterMap m = BuildMasterMap(asrs, true);
  EXPECT_NEAR(m.rooms[0].walls[0][1].x(), 0.0, 1e-12);
  EXPECT_NEAR(m.rooms[0].walls[0][1].y(), 4.0, 1e-12);
  EXPECT_NEAR(m.exits[0].center_m.x(), -1.5, 1e-12);  // (4, 1.5) rotated by 90 degrees
  const MasterMap raw = BuildMasterMap(asrs, false);
  EXPECT_NEAR(raw.rooms[0].walls[0][1].x(), 4.0, 1e-12);
}

// A path as the correction placed it (the drift inside its ASR removed) is
// drawn as it is, not the raw path moved as a whole; an ASR without one
// keeps its raw path moved; the raw map ignores them.
TEST(MasterMap, DrawsEachPathAsPlaced) {
  const auto asrs = TwoAsrs();
  std::map<int, std::vector<Pose2>> placed;
  placed[0] = {{0.5, 1.0, 0.0}, {1.5, 1.0, 0.0}, {2.5, 1.0, 0.0}};
  const MasterMap m = BuildMasterMap(asrs, true, &placed);
  ASSERT_EQ(m.rooms[0].path.size(), 3u);
  EXPECT_EQ(m.rooms[0].path[2], Vec2(2.5, 1.0));
  EXPECT_NEAR(m.rooms[0].label_m.x(), 1.5, 1e-12);
  EXPECT_TRUE(placed[0].empty());  // freed once copied
  ASSERT_EQ(m.rooms[1].path.size(), asrs[1].path.size());
  EXPECT_EQ(m.rooms[1].path[0], asrs[1].path[0].translation());
  placed[0] = {{0.5, 1.0, 0.0}};
  const MasterMap raw = BuildMasterMap(asrs, false, &placed);
  EXPECT_EQ(raw.rooms[0].path.size(), asrs[0].path.size());
}

TEST(MapFiles, MapServerPairLoadsWithWallsOccupied) {
  const std::string dir = TempDir("pgm");
  const MasterMap m = BuildMasterMap(TwoAsrs());
  WriteMasterMapFiles(dir, m, {}, 0.05);
  const MapServerMap loaded = ReadMapServer(dir + "/map.yaml");
  EXPECT_EQ(loaded.yaml.image, "map.pgm");
  EXPECT_DOUBLE_EQ(loaded.yaml.resolution, 0.05);
  EXPECT_NEAR(loaded.yaml.origin.x(), -1.0, 1e-9);
  EXPECT_NEAR(loaded.yaml.origin.y(), -1.0, 1e-9);
  const auto& occ = loaded.occupancy;
  EXPECT_EQ(occ.limits().width(), 200);  // (8 + 2) m / 0.05
  EXPECT_EQ(occ.limits().height(), 100);
  auto at = [&](double x, double y) { return occ.at(occ.limits().CellOf(Vec2(x, y))); };
  EXPECT_EQ(at(2.0, 0.01), 100);   // bottom wall
  EXPECT_EQ(at(4.01, 2.0), 100);   // the shared wall
  EXPECT_EQ(at(8.0, 1.0), 100);    // right wall
  EXPECT_EQ(at(2.0, 1.5), 0);      // inside a room: free
  EXPECT_EQ(at(-0.5, -0.5), -1);   // margin: unknown
  int occupied = 0;
  for (int8_t v : occ.cells()) occupied += v == 100;
  EXPECT_GE(occupied, 160 + 160 + 3 * 60 - 10);  // the shared wall once
  EXPECT_LE(occupied, 160 + 160 + 3 * 60 + 10);
}

TEST(MapFiles, AriaMapParsesBackToTheSameWalls) {
  const std::string dir = TempDir("aria");
  const MasterMap m = BuildMasterMap(TwoAsrs());
  WriteMasterMapFiles(dir, m);
  const FloorPlan back = ReadAriaMap(dir + "/map.map").plan;
  const FloorPlan want = MapFloorPlan(m);
  ASSERT_EQ(back.walls.size(), want.walls.size());
  ASSERT_EQ(back.walls.size(), 8u);
  for (size_t i = 0; i < want.walls.size(); ++i) {
    EXPECT_NEAR((back.walls[i].a - want.walls[i].a).norm(), 0.0, 1e-3);
    EXPECT_NEAR((back.walls[i].b - want.walls[i].b).norm(), 0.0, 1e-3);
  }
}

TEST(MapFiles, GeoJsonHasWallsExitsAndRooms) {
  const std::string dir = TempDir("geojson");
  WriteMasterMapFiles(dir, BuildMasterMap(TwoAsrs()));
  const auto doc = nlohmann::json::parse(Slurp(dir + "/map.geojson"));
  EXPECT_EQ(doc["type"], "FeatureCollection");
  int walls = 0, exits = 0, rooms = 0, labels = 0;
  for (const auto& f : doc["features"]) {
    const std::string kind = f["properties"]["kind"];
    const std::string type = f["geometry"]["type"];
    if (kind == "wall") {
      ++walls;
      EXPECT_EQ(type, "LineString");
      EXPECT_TRUE(f["properties"].contains("asr"));
    }
    if (kind == "exit") {
      ++exits;
      EXPECT_EQ(type, "Point");
      EXPECT_EQ(f["properties"]["from"], 0);
      EXPECT_EQ(f["properties"]["to"], 1);
    }
    if (kind == "room") {
      ++rooms;
      EXPECT_EQ(type, "Polygon");
    }
    labels += kind == "label";
  }
  EXPECT_EQ(walls, 2);
  EXPECT_EQ(exits, 1);
  EXPECT_EQ(rooms, 2);
  EXPECT_EQ(labels, 2);
}

// A wall that shrank to one repeated point is not written as a line; the
// collection names its metre frame; the ARIA header calls nothing ground truth.
TEST(MapFiles, GeoJsonHasNoDegenerateLinesAndNamesItsFrame) {
  auto asrs = TwoAsrs();
  asrs[1].walls_local.push_back({{1, 1}, {1, 1}});
  const std::string dir = TempDir("degenerate");
  WriteMasterMapFiles(dir, BuildMasterMap(asrs));
  const auto doc = nlohmann::json::parse(Slurp(dir + "/map.geojson"));
  EXPECT_EQ(doc["crs"]["properties"]["name"], MapFrameWkt());
  int walls = 0;
  for (const auto& f : doc["features"]) {
    if (f["geometry"]["type"] != "LineString") continue;
    walls += f["properties"]["kind"] == "wall";
    const auto& c = f["geometry"]["coordinates"];
    ASSERT_GE(c.size(), 2u);
    for (size_t i = 1; i < c.size(); ++i) EXPECT_NE(c[i], c[i - 1]);
  }
  EXPECT_EQ(walls, 2);
  EXPECT_EQ(Slurp(dir + "/map.map").find("round-truth"), std::string::npos);
}

TEST(MapFiles, WritesTheFilesItIsAskedFor) {
  const std::string dir = TempDir("files");
  const auto files = WriteMasterMapFiles(dir, BuildMasterMap(TwoAsrs()));
  EXPECT_EQ(files.size(), 4u);  // pgm, yaml, geojson, map; the pictures are cogmap/draw's
  EXPECT_FALSE(std::filesystem::exists(dir + "/map.svg"));
  MasterMapOutputs only_geojson{false, false, false, true, false};
  const std::string dir2 = TempDir("geojson");
  EXPECT_EQ(WriteMasterMapFiles(dir2, BuildMasterMap(TwoAsrs()), {}, 0.05, only_geojson).size(), 1u);
}

}  // namespace
}  // namespace cogmap::io
