#include "cogmap/io/plan_files.h"

#include <gtest/gtest.h>
#include <sqlite3.h>

#include <array>
#include <cstring>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <queue>
#include <regex>
#include <set>
#include <sstream>

#include "cogmap/core/angles.h"
#include "cogmap/core/error.h"
#include "cogmap/core/test_temp.h"
#include "cogmap/io/grid_io.h"
#include "cogmap/io/world_io.h"
#include "cogmap/plan/plan.h"
#include "cogmap/sim/building.h"

namespace cogmap::io {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

std::string Slurp(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

std::string FreshDir(const std::string& name) {
  const std::string dir = testing_util::TestTempPath(name);
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

// Runs a shell command; returns its exit status and stdout + stderr.
std::pair<int, std::string> Shell(const std::string& command) {
  std::string out;
  FILE* p = ::popen((command + " 2>&1").c_str(), "r");
  if (!p) return {-1, "popen failed"};
  char buf[4096];
  size_t n;
  while ((n = std::fread(buf, 1, sizeof buf, p)) > 0) out.append(buf, n);
  const int status = ::pclose(p);
  return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, out};
}

// The part of `ogrinfo -so` output about one layer.
std::string LayerBlock(const std::string& out, const std::string& layer) {
  const size_t at = out.find("Layer name: " + layer + "\n");
  if (at == std::string::npos) return "";
  const size_t end = out.find("Layer name: ", at + 1);
  return out.substr(at, end == std::string::npos ? std::string::npos : end - at);
}

bool HaveTool(const std::string& name) { return Shell("command -v " + name).first == 0; }

plan::Room Box(int id, const std::string& name, Vec2 lo, Vec2 hi, bool corridor = false) {
  plan::Room r;
  r.id = id;
  r.name = name;
  r.corridor = corridor;
  r.polygon = {lo, {hi.x(), lo.y()}, hi, {lo.x(), hi.y()}};
  r.area_m2 = (hi - lo).prod();
  r.label = 0.5 * (lo + hi);
  return r;
}

plan::Wall Wall(std::vector<Vec2> pts, double weight = 1.0) {
  plan::Wall w;
  w.points = std::move(pts);
  w.weight = weight;
  w.squared = true;
  return w;
}

// A corridor [0,10]x[0,2] with two rooms above it, [0,5]x[2,6] and
// [5,10]x[2,6]; doors corridor-room 1 at x 2..2.9, corridor-room 2 at x
// 7..7.9 (y = 2), and room 1-room 2 at y 4..4.9 (x = 5). One degenerate wall
// (a single repeated point) that no file may carry.
plan::Plan CorridorAndTwoRooms() {
  plan::Plan p;
  p.rooms = {Box(10, "Corridor 1", {0, 0}, {10, 2}, true), Box(11, "Room 1", {0, 2}, {5, 6}),
             Box(12, "Room 2", {5, 2}, {10, 6})};
  p.rooms[0].doors = {0, 1};
  p.rooms[1].doors = {0, 2};
  p.rooms[2].doors = {1, 2};
  p.doors.resize(3);
  p.doors[0] = {0, {2.0, 2.0}, {2.9, 2.0}, 10, 11, 0, 1};
  p.doors[1] = {1, {7.0, 2.0}, {7.9, 2.0}, 10, 12, 0, 2};
  p.doors[2] = {2, {5.0, 4.0}, {5.0, 4.9}, 11, 12, 1, 2};
  p.edges = {{10, 11, 0}, {10, 12, 1}, {11, 12, 2}};
  p.walls = {Wall({{0, 0}, {10, 0}, {10, 6}, {0, 6}, {0, 0}}, 40.0),
             Wall({{0, 2}, {2, 2}}),
             Wall({{2.9, 2}, {7, 2}}),
             Wall({{7.9, 2}, {10, 2}}),
             Wall({{5, 2}, {5, 4}}),
             Wall({{5, 4.9}, {5, 6}}),
             Wall({{3, 3}, {3, 3}})};
  p.home = Pose2{1.0, 1.0, 0.0};
  p.min = {0, 0};
  p.max = {10, 6};
  return p;
}
// Wall segments of CorridorAndTwoRooms, the degenerate one left out.
constexpr size_t kWallSegments = 4 + 5;

// A plan from a world's truth (rooms are its boxes, doors its doorways, walls
// its LINES): a floor plan of the size of the world, for the end-to-end tests.
plan::Plan PlanFromWorld(const FloorPlan& world) {
  plan::Plan p;
  for (size_t i = 0; i < world.rooms.size(); ++i) {
    const auto& b = world.rooms[i];
    const bool corridor = b.name.find("corridor") != std::string::npos;
    p.rooms.push_back(Box(static_cast<int>(i), b.name, b.min, b.max, corridor));
  }
  // The smallest box holding a point (a corridor box may hold a room's).
  auto room_at = [&](const Vec2& v) {
    int best = -1;
    double best_area = 0;
    for (size_t i = 0; i < world.rooms.size(); ++i)
      if (world.rooms[i].Contains(v) && (best < 0 || p.rooms[i].area_m2 < best_area)) {
        best = static_cast<int>(i);
        best_area = p.rooms[i].area_m2;
      }
    return best;
  };
  for (size_t i = 0; i < world.doorways.size(); ++i) {
    const Segment2& s = world.doorways[i].line;
    plan::Door d;
    d.id = static_cast<int>(i);
    d.a = s.a;
    d.b = s.b;
    const Vec2 u = (s.b - s.a).normalized();
    const Vec2 n(-u.y(), u.x());
    d.room_a = room_at(d.center() + 0.3 * n);
    d.room_b = room_at(d.center() - 0.3 * n);
    for (int r : {d.room_a, d.room_b})
      if (r >= 0) p.rooms[r].doors.push_back(d.id);
    if (d.room_a >= 0 && d.room_b >= 0 && d.room_a != d.room_b) p.edges.push_back({d.room_a, d.room_b, d.id});
    p.doors.push_back(d);
  }
  for (const auto& w : world.walls) p.walls.push_back(Wall({w.a, w.b}));
  p.home = world.home;
  p.min = world.min;
  p.max = world.max;
  return p;
}

// ------------------------------------------------------------------ anchor

TEST(GeoAnchor, ParsesThreeNumbers) {
  const GeoAnchor a = ParseGeoAnchor(" 48.8584, 2.2945 ,-30.5");
  EXPECT_DOUBLE_EQ(a.lat_deg, 48.8584);
  EXPECT_DOUBLE_EQ(a.lon_deg, 2.2945);
  EXPECT_DOUBLE_EQ(a.heading_deg, -30.5);
}

TEST(GeoAnchor, ErrorsNameTheProblem) {
  auto message = [](const std::string& text) {
    try {
      ParseGeoAnchor(text);
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_EQ(message("48.1,2.3"),
            "--geo-anchor '48.1,2.3': expected LAT,LON,HEADING_DEG (three numbers separated by commas), got 2 fields");
  EXPECT_EQ(message("48,2,0,"), "--geo-anchor '48,2,0,': expected LAT,LON,HEADING_DEG (three numbers separated by "
                                "commas), got 4 fields");
  EXPECT_EQ(message("north,2,0"), "--geo-anchor 'north,2,0': latitude 'north' is not a number");
  EXPECT_EQ(message("48,,0"), "--geo-anchor '48,,0': longitude '' is not a number");
  EXPECT_EQ(message("48,2,90deg"), "--geo-anchor '48,2,90deg': heading '90deg' is not a number");
  EXPECT_EQ(message("90,2,0"), "--geo-anchor '90,2,0': latitude 90 is outside (-90, 90) degrees (poles excluded)");
  EXPECT_EQ(message("45,181,0"), "--geo-anchor '45,181,0': longitude 181 is outside [-180, 180] degrees");
  EXPECT_EQ(message("45,nan,0"), "--geo-anchor '45,nan,0': longitude 'nan' is not a number");
}

TEST(GeoAnchor, OriginIsTheAnchor) {
  const GeoAnchor a{48.8584, 2.2945, 37.0};
  const Vec2 ll = LonLatOf(a, {0, 0});
  EXPECT_NEAR(ll.x(), 2.2945, 1e-12);
  EXPECT_NEAR(ll.y(), 48.8584, 1e-12);
}

// Heading 90: +x is east. A point d metres east on the tangent plane lies at
// longitude lon0 + atan(d / (N cos(lat0))) (N: prime vertical radius).
TEST(GeoAnchor, PlusXIsEastAtHeadingNinety) {
  const double lat0 = 48.0, d = 1000.0;
  const double e2 = (1 / 298.257223563) * (2 - 1 / 298.257223563);
  const double n = 6378137.0 / std::sqrt(1 - e2 * std::pow(std::sin(DegToRad(lat0)), 2));
  const Vec2 ll = LonLatOf({lat0, 2.0, 90.0}, {d, 0});
  EXPECT_NEAR(ll.x(), 2.0 + RadToDeg(std::atan(d / (n * std::cos(DegToRad(lat0))))), 1e-12);
  EXPECT_NEAR(ll.y(), lat0, 1e-6);  // the tangent plane rises 8 cm above the ellipsoid at 1 km
  // +y is north at heading 90: about d / M degrees of latitude (M: meridian radius).
  const double m = 6378137.0 * (1 - e2) / std::pow(1 - e2 * std::pow(std::sin(DegToRad(lat0)), 2), 1.5);
  const Vec2 north = LonLatOf({lat0, 2.0, 90.0}, {0, d});
  EXPECT_NEAR(north.x(), 2.0, 1e-12);
  EXPECT_NEAR(north.y(), lat0 + RadToDeg(d / m), 1e-6);
}

// Heading 0: +x points north and +y west.
TEST(GeoAnchor, HeadingZeroTurnsPlusXNorth) {
  const Vec2 x = LonLatOf({10.0, 20.0, 0.0}, {100, 0});
  EXPECT_NEAR(x.x(), 20.0, 1e-12);
  EXPECT_GT(x.y(), 10.0);
  const Vec2 y = LonLatOf({10.0, 20.0, 0.0}, {0, 100});
  EXPECT_LT(y.x(), 20.0);
  EXPECT_NEAR(y.y(), 10.0, 1e-8);
}

// ------------------------------------------------------------------ GeoPackage

uint32_t U32(const std::string& s, size_t at) {
  uint32_t v = 0;
  for (int i = 3; i >= 0; --i) v = (v << 8) | static_cast<uint8_t>(s[at + i]);
  return v;
}
double F64(const std::string& s, size_t at) {
  uint64_t bits = 0;
  for (int i = 7; i >= 0; --i) bits = (bits << 8) | static_cast<uint8_t>(s[at + i]);
  double v;
  std::memcpy(&v, &bits, sizeof v);
  return v;
}

TEST(Gpkg, LineStringBinaryHasHeaderEnvelopeAndWkb) {
  const std::string b = EncodeGpkgGeometry({GpkgGeometryType::kLineString, {{1, 2}, {4, -3}}}, 100000);
  ASSERT_EQ(b.size(), 8u + 32u + 9u + 32u);
  EXPECT_EQ(b.substr(0, 2), "GP");
  EXPECT_EQ(b[2], 0);
  EXPECT_EQ(b[3], 0x03);  // little endian, xy envelope
  EXPECT_EQ(U32(b, 4), 100000u);
  EXPECT_EQ(F64(b, 8), 1.0);    // min x
  EXPECT_EQ(F64(b, 16), 4.0);   // max x
  EXPECT_EQ(F64(b, 24), -3.0);  // min y
  EXPECT_EQ(F64(b, 32), 2.0);   // max y
  EXPECT_EQ(b[40], 1);          // WKB little endian
  EXPECT_EQ(U32(b, 41), 2u);    // LineString
  EXPECT_EQ(U32(b, 45), 2u);
  EXPECT_EQ(F64(b, 49), 1.0);
  EXPECT_EQ(F64(b, 73), -3.0);
}

TEST(Gpkg, PolygonRingIsClosedAndPointHasNoEnvelope) {
  const std::string poly = EncodeGpkgGeometry({GpkgGeometryType::kPolygon, {{0, 0}, {1, 0}, {0, 1}}}, 7);
  EXPECT_EQ(U32(poly, 41), 3u);  // Polygon
  EXPECT_EQ(U32(poly, 45), 1u);  // one ring
  EXPECT_EQ(U32(poly, 49), 4u);  // three points and the closing one
  EXPECT_EQ(F64(poly, 53 + 3 * 16), 0.0);
  EXPECT_EQ(F64(poly, 53 + 3 * 16 + 8), 0.0);
  const std::string pt = EncodeGpkgGeometry({GpkgGeometryType::kPoint, {{5, 6}}}, 7);
  ASSERT_EQ(pt.size(), 8u + 21u);
  EXPECT_EQ(pt[3], 0x01);
  EXPECT_EQ(U32(pt, 9), 1u);
  EXPECT_EQ(F64(pt, 13), 5.0);
  EXPECT_EQ(F64(pt, 21), 6.0);
}

TEST(Gpkg, BadLayerNameOrValueCountIsAnErrorAndLeavesNoFile) {
  const std::string dir = FreshDir("gpkg_errors");
  const std::string path = dir + "/x.gpkg";
  GpkgLayer bad{"Rooms; drop", "", GpkgGeometryType::kPoint, {}, {}};
  EXPECT_THROW(WriteGeoPackage(path, MapFrameSrs(), {bad}), InputError);
  GpkgLayer counts{"pts", "", GpkgGeometryType::kPoint, {{"a", GpkgFieldType::kReal}}, {}};
  counts.features.push_back({{GpkgGeometryType::kPoint, {{0, 0}}}, {}});
  try {
    WriteGeoPackage(path, MapFrameSrs(), {counts});
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()), path + ": layer 'pts' feature 1: 0 values for 1 fields");
  }
  EXPECT_TRUE(fs::is_empty(dir));
}

TEST(PlanFiles, GpkgLayersCarryTheAttributes) {
  const auto layers = PlanGpkgLayers(CorridorAndTwoRooms());
  ASSERT_EQ(layers.size(), 5u);
  EXPECT_EQ(layers[0].name, "rooms");
  ASSERT_EQ(layers[0].features.size(), 3u);
  EXPECT_EQ(std::get<std::string>(layers[0].features[1].values[1]), "Room 1");
  EXPECT_EQ(std::get<double>(layers[0].features[1].values[2]), 20.0);
  EXPECT_TRUE(std::get<bool>(layers[0].features[0].values[3]));
  EXPECT_EQ(layers[1].name, "walls");
  EXPECT_EQ(layers[1].features.size(), 6u);  // the degenerate one left out
  EXPECT_EQ(std::get<double>(layers[1].features[0].values[4]), 32.0);  // length_m of the outline
  EXPECT_EQ(layers[2].name, "doors");
  EXPECT_EQ(std::get<std::string>(layers[2].features[2].values[4]), "Room 1 | Room 2");
  EXPECT_NEAR(std::get<double>(layers[2].features[2].values[1]), 0.9, 1e-12);
  EXPECT_EQ(layers[3].name, "room_graph");
  ASSERT_EQ(layers[3].features.size(), 3u);
  EXPECT_EQ(layers[3].features[0].geometry.points,
            (std::vector<Vec2>{{5, 1}, {2.45, 2}, {2.5, 4}}));  // label -> door -> label
  EXPECT_EQ(layers[4].name, "robot_home");
}

// ogrinfo (GDAL) reads map.gpkg: five layers in an engineering system in
// metres, the counts and extents of the plan, and every geometry valid.
TEST(PlanFiles, OgrinfoReadsTheGeoPackageInMetresWithValidGeometries) {
  if (!HaveTool("ogrinfo")) GTEST_SKIP() << "ogrinfo (gdal-bin) is not installed";
  const std::string dir = FreshDir("gpkg_ogr");
  PlanFileOptions o;
  o.geojson = o.route_graph = o.aria = o.map_server = false;
  const auto written = WritePlanFiles(dir, CorridorAndTwoRooms(), o);
  ASSERT_EQ(written, std::vector<std::string>{dir + "/map.gpkg"});
  const auto [rc, out] = Shell("ogrinfo -ro -al -so " + dir + "/map.gpkg");
  ASSERT_EQ(rc, 0) << out;
  EXPECT_EQ(out.find("ERROR"), std::string::npos) << out;
  EXPECT_EQ(out.find("Warning"), std::string::npos) << out;
  const std::string rooms = LayerBlock(out, "rooms");
  for (const char* expected : {"Geometry: Polygon\n", "Feature Count: 3\n",
                               "Extent: (0.000000, 0.000000) - (10.000000, 6.000000)\n", "area_m2: Real",
                               "corridor: Integer(Boolean)", "ENGCRS[\"cogmap map frame\"", "LENGTHUNIT[\"metre\",1"})
    EXPECT_NE(rooms.find(expected), std::string::npos) << "missing: " << expected << "\n" << rooms;
  EXPECT_NE(LayerBlock(out, "walls").find("Geometry: Line String\nFeature Count: 6\n"), std::string::npos) << out;
  EXPECT_NE(LayerBlock(out, "doors").find("Geometry: Line String\nFeature Count: 3\n"), std::string::npos) << out;
  EXPECT_NE(LayerBlock(out, "doors").find("width_m: Real"), std::string::npos) << out;
  EXPECT_NE(LayerBlock(out, "room_graph").find("Geometry: Line String\nFeature Count: 3\n"), std::string::npos)
      << out;
  EXPECT_NE(LayerBlock(out, "robot_home")
                .find("Geometry: Point\nFeature Count: 1\nExtent: (1.000000, 1.000000) - (1.000000, 1.000000)\n"),
            std::string::npos)
      << out;
  for (const char* layer : {"walls", "doors", "room_graph", "robot_home"})
    EXPECT_NE(LayerBlock(out, layer).find("LENGTHUNIT[\"metre\",1"), std::string::npos) << layer;
  EXPECT_EQ(out.find("GEOGCRS"), std::string::npos) << out;  // no layer in degrees
  // Validity through SpatiaLite's ST_IsValid (GDAL 3.6 has no -checkvalidity).
  for (const char* layer : {"rooms", "walls", "doors", "room_graph", "robot_home"}) {
    const auto [vrc, vout] = Shell(std::string("ogrinfo -ro -dialect sqlite -sql \"SELECT COUNT(*) AS bad FROM ") +
                                 layer + " WHERE geom IS NOT NULL AND ST_IsValid(geom) <> 1\" " + dir + "/map.gpkg");
    ASSERT_EQ(vrc, 0) << vout;
    EXPECT_NE(vout.find("bad (Integer) = 0"), std::string::npos) << layer << ":\n" << vout;
  }
  const auto [arc, aout] = Shell("ogrinfo -ro -dialect sqlite -sql \"SELECT SUM(ST_Area(geom)) AS a FROM rooms\" " +
                               dir + "/map.gpkg");
  EXPECT_NE(aout.find("a (Real) = 60"), std::string::npos) << aout;
}

// The validity check above can fail: a bow-tie room is caught.
TEST(PlanFiles, OgrinfoValidityCheckCatchesABowTie) {
  if (!HaveTool("ogrinfo")) GTEST_SKIP() << "ogrinfo (gdal-bin) is not installed";
  const std::string path = FreshDir("gpkg_bowtie") + "/bow.gpkg";
  GpkgLayer l{"rooms", "", GpkgGeometryType::kPolygon, {{"name", GpkgFieldType::kText}}, {}};
  l.features.push_back({{GpkgGeometryType::kPolygon, {{0, 0}, {1, 1}, {1, 0}, {0, 1}}}, {std::string("bow")}});
  l.features.push_back({{GpkgGeometryType::kPolygon, {{0, 0}, {1, 0}, {1, 1}, {0, 1}}}, {std::string("box")}});
  WriteGeoPackage(path, MapFrameSrs(), {l});
  const auto [rc, out] = Shell(
      "ogrinfo -ro -dialect sqlite -sql \"SELECT COUNT(*) AS bad FROM rooms WHERE ST_IsValid(geom) <> 1\" " + path);
  ASSERT_EQ(rc, 0) << out;
  EXPECT_NE(out.find("bad (Integer) = 1"), std::string::npos) << out;
}

// ------------------------------------------------------------------ GeoJSON

std::map<std::string, std::vector<json>> ByLayer(const json& doc) {
  std::map<std::string, std::vector<json>> out;
  for (const auto& f : doc["features"]) out[f["properties"]["layer"]].push_back(f);
  return out;
}

TEST(PlanFiles, GeoJsonInMetresSaysSoAndHasNoDegenerateLines) {
  const json doc = json::parse(FormatPlanGeoJson(CorridorAndTwoRooms()));
  EXPECT_EQ(doc["crs"]["properties"]["name"], MapFrameWkt());
  EXPECT_EQ(doc["cogmap"]["units"], "metre");
  auto layers = ByLayer(doc);
  EXPECT_EQ(layers["rooms"].size(), 3u);
  EXPECT_EQ(layers["walls"].size(), 6u);
  EXPECT_EQ(layers["doors"].size(), 3u);
  EXPECT_EQ(layers["room_graph"].size(), 3u);
  EXPECT_EQ(layers["robot_home"].size(), 1u);
  for (const auto& f : doc["features"]) {
    const auto& g = f["geometry"];
    if (g["type"] == "LineString") {
      ASSERT_GE(g["coordinates"].size(), 2u);
      for (size_t i = 1; i < g["coordinates"].size(); ++i) EXPECT_NE(g["coordinates"][i], g["coordinates"][i - 1]);
    }
  }
  const auto& ring = layers["rooms"][1]["geometry"]["coordinates"][0];
  ASSERT_EQ(ring.size(), 5u);
  EXPECT_EQ(ring.front(), ring.back());
  EXPECT_EQ(ring[1], json::array({5.0, 2.0}));
  EXPECT_EQ(layers["rooms"][1]["properties"]["area_m2"], 20.0);
}

TEST(PlanFiles, OgrinfoReadsTheLocalGeoJsonInMetres) {
  if (!HaveTool("ogrinfo")) GTEST_SKIP() << "ogrinfo (gdal-bin) is not installed";
  const std::string dir = FreshDir("geojson_local");
  PlanFileOptions o;
  o.gpkg = o.route_graph = o.aria = o.map_server = false;
  WritePlanFiles(dir, CorridorAndTwoRooms(), o);
  const auto [rc, out] = Shell("ogrinfo -ro -al -so " + dir + "/map.geojson");
  ASSERT_EQ(rc, 0) << out;
  EXPECT_NE(out.find("Extent: (0.000000, 0.000000) - (10.000000, 6.000000)"), std::string::npos) << out;
  EXPECT_NE(out.find("ENGCRS[\"cogmap map frame\""), std::string::npos) << out;
  EXPECT_NE(out.find("LENGTHUNIT[\"metre\",1"), std::string::npos) << out;
  EXPECT_EQ(out.find("WGS 84"), std::string::npos) << out;
}

// With an anchor the features land at the anchor: GDAL reads WGS 84 and the
// extent is the plan's corners placed by LonLatOf.
TEST(PlanFiles, AnchoredGeoJsonLandsAtTheAnchor) {
  if (!HaveTool("ogrinfo")) GTEST_SKIP() << "ogrinfo (gdal-bin) is not installed";
  const std::string dir = FreshDir("geojson_anchor");
  PlanFileOptions o;
  o.gpkg = o.route_graph = o.aria = o.map_server = false;
  o.geo_anchor = ParseGeoAnchor("48.8584,2.2945,90");
  WritePlanFiles(dir, CorridorAndTwoRooms(), o);
  const json doc = json::parse(Slurp(dir + "/map.geojson"));
  EXPECT_FALSE(doc.contains("crs"));
  EXPECT_EQ(doc["cogmap"]["geo_anchor"]["lat_deg"], 48.8584);
  const auto [rc, out] = Shell("ogrinfo -ro -al -so " + dir + "/map.geojson");
  ASSERT_EQ(rc, 0) << out;
  EXPECT_NE(out.find("GEOGCRS[\"WGS 84\""), std::string::npos) << out;
  std::smatch m;
  const std::regex extent(R"(Extent: \(([-0-9.]+), ([-0-9.]+)\) - \(([-0-9.]+), ([-0-9.]+)\))");
  ASSERT_TRUE(std::regex_search(out, m, extent)) << out;
  // Heading 90: (0, 0) is the south-west corner, (10, 6) the north-east one.
  const Vec2 sw = LonLatOf(*o.geo_anchor, {0, 0}), ne = LonLatOf(*o.geo_anchor, {10, 6});
  EXPECT_NEAR(std::stod(m[1]), sw.x(), 2e-6);  // ogrinfo prints 6 decimals
  EXPECT_NEAR(std::stod(m[2]), sw.y(), 2e-6);
  EXPECT_NEAR(std::stod(m[3]), ne.x(), 2e-6);
  EXPECT_NEAR(std::stod(m[4]), ne.y(), 2e-6);
  EXPECT_NEAR(std::stod(m[1]), 2.2945, 1e-6);
  EXPECT_NEAR(std::stod(m[2]), 48.8584, 1e-6);
  // 10 m east at 48.86 N: 0.000136 degrees of longitude; 6 m north: 0.000054.
  EXPECT_NEAR(std::stod(m[3]) - 2.2945, 10.0 / (111320.0 * std::cos(DegToRad(48.8584))), 2e-6);
  EXPECT_NEAR(std::stod(m[4]) - 48.8584, 6.0 / 111200.0, 2e-6);
  // The robot's home at (1, 1), exactly as placed (1e-8 degree rounding).
  for (const auto& f : doc["features"])
    if (f["properties"]["layer"] == "robot_home") {
      const Vec2 home = LonLatOf(*o.geo_anchor, {1, 1});
      EXPECT_NEAR(f["geometry"]["coordinates"][0].get<double>(), home.x(), 6e-9);
      EXPECT_NEAR(f["geometry"]["coordinates"][1].get<double>(), home.y(), 6e-9);
      EXPECT_EQ(f["properties"]["bearing_deg"], 90.0);
    }
}

// ------------------------------------------------------------------ Nav2 route graph

// Parses route_graph.geojson as the Nav2 loader does (Point -> node with
// properties.id; (Multi)LineString -> directed edge startid -> endid) and
// returns the rooms joined through a door node, as plan room ids.
std::set<std::pair<int, int>> RoomLinksOfRouteGraph(const json& doc, size_t* nodes, size_t* edges) {
  std::map<unsigned, json> node;
  std::map<unsigned, std::set<unsigned>> out;
  std::set<unsigned> ids;
  *nodes = *edges = 0;
  for (const auto& f : doc["features"]) {
    const unsigned id = f["properties"]["id"].get<unsigned>();
    EXPECT_TRUE(ids.insert(id).second) << "id " << id << " used twice";
    if (f["geometry"]["type"] == "Point") {
      EXPECT_EQ(f["properties"]["frame"], "map");
      node[id] = f;
      ++*nodes;
    }
  }
  for (const auto& f : doc["features"]) {
    if (f["geometry"]["type"] != "MultiLineString") continue;
    const unsigned s = f["properties"]["startid"].get<unsigned>(), t = f["properties"]["endid"].get<unsigned>();
    EXPECT_TRUE(node.count(s) && node.count(t));
    // The edge's line runs from its start node to its end node.
    EXPECT_EQ(f["geometry"]["coordinates"][0][0], node[s]["geometry"]["coordinates"]);
    EXPECT_EQ(f["geometry"]["coordinates"][0][1], node[t]["geometry"]["coordinates"]);
    out[s].insert(t);
    ++*edges;
  }
  std::set<std::pair<int, int>> links;
  for (const auto& [id, f] : node) {
    if (f["properties"]["metadata"]["kind"] != "door") continue;
    for (unsigned a : out[id])
      for (unsigned b : out[id]) {
        EXPECT_TRUE(out[a].count(id)) << "edge " << a << " -> door " << id << " missing";
        if (a >= b) continue;
        const int ra = node[a]["properties"]["metadata"]["room_id"], rb = node[b]["properties"]["metadata"]["room_id"];
        links.insert({std::min(ra, rb), std::max(ra, rb)});
      }
  }
  return links;
}

std::set<std::pair<int, int>> RoomLinksOfPlan(const plan::Plan& p) {
  std::set<std::pair<int, int>> links;
  for (const auto& e : p.edges) links.insert({std::min(e.room_a, e.room_b), std::max(e.room_a, e.room_b)});
  return links;
}

TEST(PlanFiles, RouteGraphConnectsTheRoomsOfThePlanThroughDoors) {
  const plan::Plan p = CorridorAndTwoRooms();
  const json doc = json::parse(FormatRouteGraphGeoJson(p));
  size_t nodes = 0, edges = 0;
  EXPECT_EQ(RoomLinksOfRouteGraph(doc, &nodes, &edges), RoomLinksOfPlan(p));
  EXPECT_EQ(nodes, 3u + 3u);
  EXPECT_EQ(edges, 2u * 2u * 3u);  // two links per door, both ways
}

TEST(PlanFiles, RouteGraphKeepsADoorToUnexploredSpace) {
  plan::Plan p = CorridorAndTwoRooms();
  p.doors.push_back({3, {10, 0.5}, {10, 1.4}, 10, -1, 0, -1});
  const json doc = json::parse(FormatRouteGraphGeoJson(p));
  size_t nodes = 0, edges = 0;
  EXPECT_EQ(RoomLinksOfRouteGraph(doc, &nodes, &edges), RoomLinksOfPlan(p));
  EXPECT_EQ(nodes, 7u);
  EXPECT_EQ(edges, 14u);
}

// ------------------------------------------------------------------ ARIA

TEST(PlanFiles, AriaMapReadsBackWithHomeRoomsDoorsAndLines) {
  const std::string dir = FreshDir("aria");
  PlanFileOptions o;
  o.gpkg = o.geojson = o.route_graph = o.map_server = false;
  WritePlanFiles(dir, CorridorAndTwoRooms(), o);
  const std::string text = Slurp(dir + "/map.map");
  EXPECT_EQ(text.find("round-truth"), std::string::npos);
  const WorldReadResult r = ReadWorld(dir + "/map.map");
  EXPECT_TRUE(r.warnings.empty());
  ASSERT_TRUE(r.plan.home.has_value());
  EXPECT_EQ(r.plan.home->translation(), Vec2(1, 1));
  EXPECT_EQ(r.plan.home->theta, 0.0);
  ASSERT_EQ(r.plan.rooms.size(), 3u);
  EXPECT_EQ(r.plan.rooms[0].name, "Corridor 1");
  EXPECT_EQ(r.plan.rooms[2].name, "Room 2");
  EXPECT_EQ(r.plan.rooms[2].min, Vec2(5, 2));
  EXPECT_EQ(r.plan.rooms[2].max, Vec2(10, 6));
  ASSERT_EQ(r.plan.doorways.size(), 3u);
  EXPECT_EQ(r.plan.doorways[2].line.a, Vec2(5, 4));
  EXPECT_EQ(r.plan.doorways[2].line.b, Vec2(5, 4.9));
  ASSERT_EQ(r.plan.walls.size(), kWallSegments);
  EXPECT_EQ(r.plan.walls[4].a, Vec2(0, 2));
  EXPECT_EQ(r.plan.walls[4].b, Vec2(2, 2));
  EXPECT_EQ(r.plan.min, Vec2(0, 0));
  EXPECT_EQ(r.plan.max, Vec2(10, 6));
}

plan::Plan Rotated(plan::Plan p, double angle_rad) {
  const Pose2 r{0, 0, angle_rad};
  for (auto& w : p.walls)
    for (auto& v : w.points) v = r * v;
  for (auto& room : p.rooms) {
    for (auto& v : room.polygon) v = r * v;
    room.label = r * room.label;
  }
  for (auto& d : p.doors) {
    d.a = r * d.a;
    d.b = r * d.b;
  }
  p.home = r * *p.home;
  p.min = p.max = Vec2(0, 0);  // bounds from the contents
  return p;
}

TEST(PlanFiles, DominantWallDirectionIsTheBuildingsAxisModuloRightAngles) {
  EXPECT_NEAR(DominantWallDirection(CorridorAndTwoRooms()), 0.0, 1e-12);
  EXPECT_NEAR(DominantWallDirection(Rotated(CorridorAndTwoRooms(), DegToRad(30))), DegToRad(30), 1e-9);
  EXPECT_NEAR(DominantWallDirection(Rotated(CorridorAndTwoRooms(), DegToRad(120))), DegToRad(30), 1e-9);
  EXPECT_NEAR(DominantWallDirection(Rotated(CorridorAndTwoRooms(), DegToRad(-70))), DegToRad(20), 1e-9);
}

// A building at 30 degrees to the map axes: each room is a sector rotated by
// 30 degrees whose from/to are the room's own corners in the building's frame
// (axis-aligned boxes would overlap their neighbours).
TEST(PlanFiles, AriaSectorsFollowARotatedBuilding) {
  const plan::Plan p = Rotated(CorridorAndTwoRooms(), DegToRad(30));
  const std::string text = FormatPlanAriaMap(p);
  EXPECT_NE(text.find("ICON \"Room 2\" 5000 2000 10000 6000\n"), std::string::npos) << text;
  EXPECT_NE(text.find("Cairn: Room "), std::string::npos);
  std::istringstream in(text);
  std::string line;
  int rooms = 0;
  while (std::getline(in, line)) {
    if (line.rfind("Cairn: Room ", 0) != 0) continue;
    ++rooms;
    std::istringstream f(line.substr(12));
    double x, y, theta;
    f >> x >> y >> theta;
    EXPECT_EQ(theta, 30.0) << line;
  }
  EXPECT_EQ(rooms, 3);
  EXPECT_NE(text.find("Cairn: RobotHome 366 1366 30 \"\" ICON \"Home\""), std::string::npos) << text;
  // cogmap's reader: the box around the rotated rectangle.
  const WorldReadResult back = ParseAriaMap(text, "rotated.map");
  ASSERT_EQ(back.plan.rooms.size(), 3u);
  Vec2 lo = p.rooms[2].polygon[0], hi = lo;
  for (const Vec2& v : p.rooms[2].polygon) {
    lo = lo.cwiseMin(v);
    hi = hi.cwiseMax(v);
  }
  EXPECT_NEAR((back.plan.rooms[2].min - lo).norm(), 0.0, 2e-3);
  EXPECT_NEAR((back.plan.rooms[2].max - hi).norm(), 0.0, 2e-3);
}

// ------------------------------------------------------------------ map_server

// 8-connected flood fill over free cells from 'start'.
std::vector<char> Reach(const grid::Grid2D<grid::CellClass>& g, const grid::CellIndex& start) {
  const auto& lim = g.limits();
  std::vector<char> seen(lim.cell_count(), 0);
  std::queue<grid::CellIndex> q;
  q.push(start);
  seen[lim.Flat(start)] = 1;
  while (!q.empty()) {
    const auto c = q.front();
    q.pop();
    for (int dy = -1; dy <= 1; ++dy)
      for (int dx = -1; dx <= 1; ++dx) {
        const grid::CellIndex n(c.x() + dx, c.y() + dy);
        if (!lim.Contains(n) || seen[lim.Flat(n)] || g.at(n) != grid::CellClass::kEmpty) continue;
        seen[lim.Flat(n)] = 1;
        q.push(n);
      }
  }
  return seen;
}

TEST(PlanFiles, RasterHasRoomsFreeWallsOccupiedAndDoorsOpen) {
  const plan::Plan p = CorridorAndTwoRooms();
  const auto g = RasterizePlan(p, 0.05, 0.5);
  const auto& lim = g.limits();
  EXPECT_EQ(lim.origin(), Vec2(-0.5, -0.5));
  EXPECT_EQ(lim.width(), 220);
  EXPECT_EQ(lim.height(), 140);
  auto at = [&](double x, double y) { return g.at(lim.CellOf({x, y})); };
  EXPECT_EQ(at(2.5, 4.0), grid::CellClass::kEmpty);
  EXPECT_EQ(at(5.0, 3.0), grid::CellClass::kOccupied);   // the wall between the rooms
  EXPECT_EQ(at(5.0, 4.45), grid::CellClass::kEmpty);     // its door
  EXPECT_EQ(at(2.45, 2.0), grid::CellClass::kEmpty);     // the corridor door
  EXPECT_EQ(at(2.0, 2.0), grid::CellClass::kOccupied);   // its jamb
  EXPECT_EQ(at(-0.3, 3.0), grid::CellClass::kUnknown);   // outside
  // Every room reachable from home; nothing outside the outline reachable.
  const auto seen = Reach(g, lim.CellOf(p.home->translation()));
  for (const auto& r : p.rooms) EXPECT_TRUE(seen[lim.Flat(lim.CellOf(r.label))]) << r.name;
  for (int y = 0; y < lim.height(); ++y)
    for (int x = 0; x < lim.width(); ++x) {
      const Vec2 c = lim.CenterOf({x, y});
      if (c.x() < 0 || c.x() > 10 || c.y() < 0 || c.y() > 6) {
        ASSERT_FALSE(seen[lim.Flat(x, y)]) << c.transpose();
      }
    }
}

// A gap in a wall with no door stays a wall gap: the far side is not made
// free (a convex hull of the room would have been).
TEST(PlanFiles, RasterDoesNotLeakThroughAWallGap) {
  plan::Plan p = CorridorAndTwoRooms();
  // An L-shaped room 2: its notch [8,10]x[4,6] is outside it.
  p.rooms[2].polygon = {{5, 2}, {10, 2}, {10, 4}, {8, 4}, {8, 6}, {5, 6}};
  p.walls[0] = Wall({{10, 6}, {0, 6}, {0, 0}, {10, 0}, {10, 4}});  // the outline opened at the notch
  p.walls.push_back(Wall({{10, 4}, {8, 4}, {8, 5}}));               // gap from (8, 5) to (8, 6)
  const auto g = RasterizePlan(p, 0.05, 0.5);
  const auto& lim = g.limits();
  EXPECT_EQ(g.at(lim.CellOf({9, 5})), grid::CellClass::kUnknown);
  const auto seen = Reach(g, lim.CellOf(p.home->translation()));
  EXPECT_FALSE(seen[lim.Flat(lim.CellOf({9, 5}))]);
}

TEST(PlanFiles, RasterCellKeepsLargeBuildingsWithinThePixelBudget) {
  plan::Plan p = CorridorAndTwoRooms();
  PlanFileOptions o;
  EXPECT_EQ(PlanRasterCell(p, o), 0.05);  // small: the finest cell
  p.max = {2000, 80};                      // a 2 km building
  const double cell = PlanRasterCell(p, o);
  EXPECT_GT(cell, 0.05);
  EXPECT_LE(std::ceil(2001 / cell) * std::ceil(81 / cell), o.raster_max_pixels);
  EXPECT_GT(std::ceil(2001 / (cell - 0.001)) * std::ceil(81 / (cell - 0.001)), o.raster_max_pixels);
  o.raster_cell_m = 0.5;
  EXPECT_EQ(PlanRasterCell(p, o), 0.5);
}

// MRPT loads the pair (ros-map-yaml2mrpt converts it to a .gridmap).
TEST(PlanFiles, MrptLoadsTheMapServerPair) {
  if (!HaveTool("ros-map-yaml2mrpt")) GTEST_SKIP() << "ros-map-yaml2mrpt (mrpt-apps) is not installed";
  const std::string dir = FreshDir("mrpt");
  PlanFileOptions o;
  o.gpkg = o.geojson = o.route_graph = o.aria = false;
  const auto written = WritePlanFiles(dir, CorridorAndTwoRooms(), o);
  ASSERT_EQ(written, (std::vector<std::string>{dir + "/map.pgm", dir + "/map.yaml"}));
  const MapServerMap back = ReadMapServer(dir + "/map.yaml");
  EXPECT_EQ(back.yaml.resolution, 0.05);
  const auto [rc, out] = Shell("ros-map-yaml2mrpt -w -i " + dir + "/map.yaml -d " + dir);
  ASSERT_EQ(rc, 0) << out;
  ASSERT_TRUE(fs::exists(dir + "/map.gridmap.gz")) << out;
  EXPECT_GT(fs::file_size(dir + "/map.gridmap.gz"), 100u);
}

// ------------------------------------------------------------------ all files, end to end

TEST(PlanFiles, WritesEveryFileAtomically) {
  const std::string dir = FreshDir("all");
  const auto written = WritePlanFiles(dir, CorridorAndTwoRooms());
  const std::vector<std::string> expected = {dir + "/map.gpkg", dir + "/map.geojson", dir + "/route_graph.geojson",
                                             dir + "/map.map",  dir + "/map.pgm",     dir + "/map.yaml"};
  EXPECT_EQ(written, expected);
  size_t files = 0;
  for (const auto& e : fs::directory_iterator(dir)) {
    ++files;
    EXPECT_EQ(e.path().string().find(".tmp-"), std::string::npos) << e.path();
  }
  EXPECT_EQ(files, expected.size());
  EXPECT_THROW(WritePlanFiles(dir + "/missing", CorridorAndTwoRooms()), InputError);
}

// Written two at a time, the files are the ones written one after the other,
// byte for byte (the GeoPackage's tables row for row: gpkg_contents holds the
// time it was written), listed in the same order; a folder that cannot be
// written is an error.
TEST(PlanFiles, WrittenAtOnceTheFilesAreTheSame) {
  const std::string one = FreshDir("one_at_a_time"), two = FreshDir("two_at_once");
  PlanFileOptions o;
  const auto a = WritePlanFiles(one, CorridorAndTwoRooms(), o);
  o.threads = 2;
  const auto b = WritePlanFiles(two, CorridorAndTwoRooms(), o);
  ASSERT_EQ(a.size(), b.size());
  auto bytes = [](const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    return std::string(std::istreambuf_iterator<char>(in), {});
  };
  for (size_t k = 0; k < a.size(); ++k) {
    const std::string name = fs::path(a[k]).filename().string();
    EXPECT_EQ(fs::path(b[k]).filename().string(), name);
    if (name == "map.gpkg") continue;
    EXPECT_EQ(bytes(a[k]), bytes(b[k])) << name;
  }
  auto rows = [](const std::string& gpkg, const std::string& table) {
    sqlite3* db = nullptr;
    std::string out;
    if (sqlite3_open_v2(gpkg.c_str(), &db, SQLITE_OPEN_READONLY, nullptr) == SQLITE_OK) {
      sqlite3_stmt* st = nullptr;
      if (sqlite3_prepare_v2(db, ("SELECT * FROM " + table).c_str(), -1, &st, nullptr) == SQLITE_OK) {
        while (sqlite3_step(st) == SQLITE_ROW) {
          for (int c = 0; c < sqlite3_column_count(st); ++c) {
            const void* blob = sqlite3_column_blob(st, c);
            out.append(static_cast<const char*>(blob), static_cast<size_t>(sqlite3_column_bytes(st, c)));
            out += '|';
          }
          out += '\n';
        }
      }
      sqlite3_finalize(st);
    }
    sqlite3_close(db);
    return out;
  };
  for (const char* table : {"rooms", "walls", "doors", "room_graph"}) {
    EXPECT_FALSE(rows(one + "/map.gpkg", table).empty()) << table;
    EXPECT_EQ(rows(one + "/map.gpkg", table), rows(two + "/map.gpkg", table)) << table;
  }
  EXPECT_THROW(WritePlanFiles(two + "/missing", CorridorAndTwoRooms(), o), InputError);
}

// The real floor plan (plan::BuildPlan) of two placed ASRs joined by an exit:
// every file is written, the GeoPackage's geometries are valid for GDAL, the
// route graph is the plan's room graph and the raster joins both rooms.
TEST(PlanFiles, RealFloorPlanOfTwoRooms) {
  auto make = [](int id, Polyline walls, Vec2 a, Vec2 b, double t0) {
    asr::Asr x;
    x.id = id;
    x.walls_local = {std::move(walls)};
    for (int i = 0; i <= 25; ++i) {
      const Vec2 p = a + (b - a) * (i / 25.0);
      x.path.push_back(Pose2{p.x(), p.y(), kPi / 2});
    }
    x.start_time_s = t0;
    return x;
  };
  asr::Asr a = make(0, {{0, 0}, {6, 0}, {6, 4}, {0, 4}, {0, 0}}, {3, 1}, {3, 3.5}, 0.0);
  asr::Asr b = make(1, {{0, 4}, {6, 4}, {6, 8}, {0, 8}, {0, 4}}, {3, 4.5}, {3, 7}, 10.0);
  a.exits.push_back({{3.0, 4.0}, 0.9, 0, 1});
  b.exits.push_back({{3.0, 4.0}, 0.9, 0, 1});
  plan::Plan p = plan::BuildPlan({a, b}, {});
  p.home = a.path.front();
  ASSERT_EQ(p.rooms.size(), 2u);
  ASSERT_EQ(p.edges.size(), 1u);
  const std::string dir = FreshDir("real_plan");
  EXPECT_EQ(WritePlanFiles(dir, p).size(), 6u);
  size_t nodes = 0, edges = 0;
  EXPECT_EQ(RoomLinksOfRouteGraph(json::parse(Slurp(dir + "/route_graph.geojson")), &nodes, &edges),
            RoomLinksOfPlan(p));
  const MapServerMap m = ReadMapServer(dir + "/map.yaml");
  const auto& lim = m.occupancy.limits();
  const auto seen = Reach(ClassesFromMapServer(m), lim.CellOf(p.home->translation()));
  for (const auto& r : p.rooms) EXPECT_TRUE(seen[lim.Flat(lim.CellOf(r.label))]) << r.name;
  EXPECT_EQ(ReadWorld(dir + "/map.map").plan.rooms.size(), 2u);
  if (HaveTool("ogrinfo"))
    for (const char* layer : {"rooms", "walls", "doors", "room_graph"}) {
      const auto [rc, out] = Shell(std::string("ogrinfo -ro -dialect sqlite -sql \"SELECT COUNT(*) AS bad FROM ") +
                                   layer + " WHERE geom IS NOT NULL AND ST_IsValid(geom) <> 1\" " + dir + "/map.gpkg");
      EXPECT_NE(out.find("bad (Integer) = 0"), std::string::npos) << layer << ":\n" << out;
    }
}

// nine_rooms' truth as a plan: every file opens in its tool, the route
// graph matches the room graph, the ARIA map reads back.
TEST(PlanFiles, NineRoomsWorldEndToEnd) {
  const FloorPlan world = ReadWorld(std::string(COGMAP_SHARED_DIR) + "/worlds/nine_rooms.map").plan;
  const plan::Plan p = PlanFromWorld(world);
  ASSERT_GE(p.rooms.size(), 9u);
  ASSERT_GE(p.edges.size(), 8u);
  const std::string dir = FreshDir("nine_rooms");
  WritePlanFiles(dir, p);
  size_t nodes = 0, edges = 0;
  EXPECT_EQ(RoomLinksOfRouteGraph(json::parse(Slurp(dir + "/route_graph.geojson")), &nodes, &edges),
            RoomLinksOfPlan(p));
  const WorldReadResult back = ReadWorld(dir + "/map.map");
  EXPECT_EQ(back.plan.walls.size(), world.walls.size());
  EXPECT_EQ(back.plan.rooms.size(), world.rooms.size());
  EXPECT_EQ(back.plan.doorways.size(), world.doorways.size());
  if (HaveTool("ogrinfo")) {
    const auto [rc, out] = Shell("ogrinfo -ro -al -so " + dir + "/map.gpkg");
    ASSERT_EQ(rc, 0) << out;
    EXPECT_NE(out.find("Feature Count: " + std::to_string(p.rooms.size())), std::string::npos) << out;
    const auto [vrc, vout] = Shell("ogrinfo -ro -dialect sqlite -sql \"SELECT COUNT(*) AS bad FROM walls WHERE "
                                 "ST_IsValid(geom) <> 1\" " + dir + "/map.gpkg");
    EXPECT_NE(vout.find("bad (Integer) = 0"), std::string::npos) << vout;
  }
}

// A generated 1000-room building: the raster stays within the pixel budget
// and keeps every room reachable from home through the doors.
TEST(PlanFiles, ThousandRoomBuildingStaysWithinTheBudget) {
  sim::BuildingOptions b;
  b.rooms = 1000;
  b.corridor_m = 2000;
  const plan::Plan p = PlanFromWorld(sim::GenerateBuilding(b));
  ASSERT_EQ(p.rooms.size(), 1001u);
  const std::string dir = FreshDir("building");
  const PlanFileOptions o;
  WritePlanFiles(dir, p, o);
  const MapServerMap m = ReadMapServer(dir + "/map.yaml");
  const auto& lim = m.occupancy.limits();
  EXPECT_LE(static_cast<double>(lim.width()) * lim.height(), o.raster_max_pixels);
  const auto classes = ClassesFromMapServer(m);
  const auto seen = Reach(classes, lim.CellOf(p.home->translation()));
  int reached = 0;
  for (const auto& r : p.rooms) reached += seen[lim.Flat(lim.CellOf(r.label))];
  EXPECT_EQ(reached, 1001);
  size_t nodes = 0, edges = 0;
  EXPECT_EQ(RoomLinksOfRouteGraph(json::parse(Slurp(dir + "/route_graph.geojson")), &nodes, &edges),
            RoomLinksOfPlan(p));
  if (HaveTool("ogrinfo")) {
    const auto [rc, out] = Shell("ogrinfo -ro -al -so " + dir + "/map.gpkg rooms");
    ASSERT_EQ(rc, 0) << out;
    EXPECT_NE(out.find("Feature Count: 1001"), std::string::npos) << out;
  }
}

}  // namespace
}  // namespace cogmap::io
