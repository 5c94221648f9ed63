#include "cogmap/plan/plan_json.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "cogmap/core/error.h"

namespace cogmap::plan {
namespace {

Plan Sample() {
  Plan p;
  Wall w;
  w.points = {{0, 0}, {4, 0}, {4, 3.5}};
  w.free_on_left = false;
  w.weight = 7.25;
  w.asr_ids = {2, 5};
  w.squared = true;
  p.walls.push_back(w);
  Wall t;
  t.points = {{1, 1}, {1, 2}};
  t.two_sided = true;
  p.walls.push_back(t);
  Room r;
  r.id = 0;
  r.name = "Room 1";
  r.polygon = {{0, 0}, {4, 0}, {4, 3}, {0, 3}};
  r.area_m2 = 12;
  r.label = {2, 1.5};
  r.doors = {0};
  r.asr_ids = {2, 5};
  r.graph_rooms = {2};
  p.rooms.push_back(r);
  Room c = r;
  c.id = 1;
  c.name = "Corridor 1";
  c.corridor = true;
  c.polygon = {{4, 0}, {9, 0}, {9, 2}, {4, 2}};
  p.rooms.push_back(c);
  Door d;
  d.id = 0;
  d.a = {4, 1};
  d.b = {4, 1.9};
  d.room_a = 0;
  d.room_b = 1;
  d.from_asr = 2;
  d.to_asr = 3;
  p.doors.push_back(d);
  p.edges.push_back({0, 1, 0});
  p.home = Pose2{0.5, 0.25, -1.5};
  p.min = {0, 0};
  p.max = {9, 3.5};
  p.dominant_direction_rad = 0.125;
  return p;
}

TEST(PlanJson, RoundTrip) {
  const Plan a = Sample();
  const Plan b = ParsePlanJson(PlanToJsonText(a), "plan.json");
  ASSERT_EQ(b.walls.size(), 2u);
  EXPECT_EQ(b.walls[0].points, a.walls[0].points);
  EXPECT_FALSE(b.walls[0].free_on_left);
  EXPECT_EQ(b.walls[0].weight, 7.25);
  EXPECT_EQ(b.walls[0].asr_ids, (std::vector<int>{2, 5}));
  EXPECT_TRUE(b.walls[0].squared);
  EXPECT_TRUE(b.walls[1].two_sided);
  ASSERT_EQ(b.rooms.size(), 2u);
  EXPECT_EQ(b.rooms[1].name, "Corridor 1");
  EXPECT_TRUE(b.rooms[1].corridor);
  EXPECT_EQ(b.rooms[0].polygon, a.rooms[0].polygon);
  EXPECT_EQ(b.rooms[0].label, a.rooms[0].label);
  EXPECT_EQ(b.rooms[0].graph_rooms, (std::vector<int>{2}));
  ASSERT_EQ(b.doors.size(), 1u);
  EXPECT_EQ(b.doors[0].b, a.doors[0].b);
  EXPECT_EQ(b.doors[0].to_asr, 3);
  ASSERT_EQ(b.edges.size(), 1u);
  EXPECT_EQ(b.edges[0].room_b, 1);
  ASSERT_TRUE(b.home.has_value());
  EXPECT_EQ(b.home->theta, -1.5);
  EXPECT_EQ(b.max, a.max);
  EXPECT_EQ(b.dominant_direction_rad, 0.125);
  // And again: the text is stable.
  EXPECT_EQ(PlanToJsonText(b), PlanToJsonText(a));
}

// plan.json is written a list element at a time (WritePlanJson): the text
// is the document's, as the json library indents it, to the byte.
TEST(PlanJson, StreamedTextIsTheDocumentsDump) {
  Plan a = Sample();
  a.rooms[1].name = "Corridor \"1\"\n";  // escapes stay on one line
  EXPECT_EQ(PlanToJsonText(a), PlanToJson(a).dump(2) + "\n");
  Plan empty;  // empty lists print as [] and no home as null
  EXPECT_EQ(PlanToJsonText(empty), PlanToJson(empty).dump(2) + "\n");
  Plan one_each;
  one_each.walls.push_back(a.walls[1]);
  one_each.home = a.home;
  one_each.edges.push_back({0, 0, 0});
  EXPECT_EQ(PlanToJsonText(one_each), PlanToJson(one_each).dump(2) + "\n");
}

void ExpectError(const nlohmann::json& j, const std::string& fragment) {
  try {
    PlanFromJson(j, "out/plan.json");
    FAIL() << "no error for " << fragment;
  } catch (const InputError& e) {
    const std::string what = e.what();
    EXPECT_EQ(what.rfind("out/plan.json: ", 0), 0u) << what;
    EXPECT_NE(what.find(fragment), std::string::npos) << what;
  }
}

TEST(PlanJson, BadFilesNameTheProblem) {
  const nlohmann::json good = PlanToJson(Sample());
  auto j = good;
  j["format"] = "geojson";
  ExpectError(j, "format");
  j = good;
  j["version"] = 7;
  ExpectError(j, "version: 7 is not supported");
  j = good;
  j["walls"][0]["points"] = nlohmann::json::array({nlohmann::json::array({0, 0})});
  ExpectError(j, "walls[0].points: a wall needs at least 2 points");
  j = good;
  j["rooms"][1]["polygon"][2][0] = "x";
  ExpectError(j, "rooms[1].polygon[2][0]: expected a number");
  j = good;
  j["doors"][0]["room_b"] = 9;
  ExpectError(j, "doors[0].room_b: no room 9");
  j = good;
  j["edges"][0]["door"] = 3;
  ExpectError(j, "edges[0].door: no door 3");
  j = good;
  j["rooms"][0].erase("name");
  ExpectError(j, "rooms[0]: missing \"name\"");
  j = good;
  j["rooms"][0]["doors"] = {4};
  ExpectError(j, "rooms[0].doors: no door 4");
}

TEST(PlanJson, NotJsonAndMissingFile) {
  EXPECT_THROW(ParsePlanJson("{\"format\": ", "p.json"), InputError);
  try {
    ParsePlanJson("[1e999]", "p.json");
    FAIL();
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()).rfind("p.json: ", 0), 0u);
  }
  const auto missing = std::filesystem::temp_directory_path() / "cogmap_no_such_plan.json";
  std::filesystem::remove(missing);
  try {
    ReadPlanJson(missing.string());
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("cannot be read"), std::string::npos);
  }
}

}  // namespace
}  // namespace cogmap::plan
