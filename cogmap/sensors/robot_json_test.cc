#include "cogmap/sensors/robot_json.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <fstream>

#include "cogmap/core/angles.h"
#include "cogmap/core/error.h"
#include "cogmap/core/test_temp.h"

namespace cogmap::sensors {
namespace {

using nlohmann::json;
using ::testing::HasSubstr;

std::string ErrorOf(const json& j) {
  try {
    ParseRobotJson(j, "r.json");
  } catch (const InputError& e) {
    return e.what();
  }
  return "no error";
}

json OneSonar() {
  return json::parse(R"({"name": "one", "units": "mm", "radius": 200,
    "sensors": [{"x": 100, "y": -50, "heading": 45, "beam_width": 20,
                 "min_range": 100, "max_range": 3000, "kind": "sonar"}]})");
}

TEST(RobotJson, ParsesMillimetresAndDegrees) {
  const auto r = ParseRobotJson(OneSonar(), "r.json");
  EXPECT_EQ(r.name, "one");
  EXPECT_DOUBLE_EQ(r.radius_m, 0.2);
  ASSERT_EQ(r.sensors.size(), 1u);
  EXPECT_DOUBLE_EQ(r.sensors[0].robot_from_sensor.x, 0.1);
  EXPECT_DOUBLE_EQ(r.sensors[0].robot_from_sensor.y, -0.05);
  EXPECT_DOUBLE_EQ(r.sensors[0].robot_from_sensor.theta, kPi / 4);
  EXPECT_DOUBLE_EQ(r.sensors[0].beam_width_rad, DegToRad(20));
  EXPECT_DOUBLE_EQ(r.sensors[0].min_range_m, 0.1);
  EXPECT_DOUBLE_EQ(r.sensors[0].max_range_m, 3.0);
  EXPECT_EQ(r.sensors[0].kind, SensorKind::kSonar);
}

TEST(RobotJson, LaserSectionAddsBeamsAfterSensors) {
  json j = OneSonar();
  j["laser"] = {{"beams", 5}, {"fov", 180000.0 / 1000}, {"max_range", 10000}};
  const auto r = ParseRobotJson(j, "r.json");
  ASSERT_EQ(r.sensors.size(), 6u);
  EXPECT_EQ(r.sensors[1].kind, SensorKind::kLaser);
  EXPECT_DOUBLE_EQ(r.sensors[1].robot_from_sensor.theta, -kPi / 2);
  EXPECT_DOUBLE_EQ(r.sensors[5].robot_from_sensor.theta, kPi / 2);
  EXPECT_DOUBLE_EQ(r.sensors[5].max_range_m, 10.0);
}

TEST(RobotJson, RoundTripsBuiltinsExactlyInRadians) {
  for (const auto& name : BuiltinRobotNames()) {
    const auto r = BuiltinRobot(name);
    EXPECT_TRUE(SameRobot(ParseRobotJson(RobotToJson(r, false), "x"), r)) << name;
  }
}

TEST(RobotJson, RoundTripsInDegreesClosely) {
  const auto r = BuiltinRobot("pioneer16");
  const auto back = ParseRobotJson(RobotToJson(r), "x");
  ASSERT_EQ(back.sensors.size(), 16u);
  for (int i = 0; i < 16; ++i)
    EXPECT_NEAR(back.sensors[i].robot_from_sensor.theta, r.sensors[i].robot_from_sensor.theta, 1e-12);
}

TEST(RobotJson, UnknownTopLevelKeyNamesFileAndKey) {
  json j = OneSonar();
  j["wheels"] = 2;
  EXPECT_THAT(ErrorOf(j), HasSubstr("r.json: unknown key 'wheels'"));
}

TEST(RobotJson, UnknownSensorKeyNamesSensor) {
  json j = OneSonar();
  j["sensors"][0]["colour"] = "red";
  EXPECT_THAT(ErrorOf(j), HasSubstr("r.json: unknown key 'sensors[0].colour'"));
}

TEST(RobotJson, MissingHeadingIsAnError) {
  json j = OneSonar();
  j["sensors"][0].erase("heading");
  EXPECT_THAT(ErrorOf(j), HasSubstr("sensors[0].heading: missing"));
}

TEST(RobotJson, NonNumberIsAnError) {
  json j = OneSonar();
  j["sensors"][0]["x"] = "ten";
  EXPECT_THAT(ErrorOf(j), HasSubstr("sensors[0].x: expected a number"));
}

TEST(RobotJson, BadUnitsKindAndRangesAreErrors) {
  json j = OneSonar();
  j["units"] = "inch";
  EXPECT_THAT(ErrorOf(j), HasSubstr("units: expected"));
  j = OneSonar();
  j["sensors"][0]["kind"] = "radar";
  EXPECT_THAT(ErrorOf(j), HasSubstr("sensors[0].kind"));
  j = OneSonar();
  j["sensors"][0]["max_range"] = 50;
  EXPECT_THAT(ErrorOf(j), HasSubstr("max_range: must exceed min_range"));
  j = OneSonar();
  j["radius"] = -1;
  EXPECT_THAT(ErrorOf(j), HasSubstr("radius: must be in (0, 5] metres"));
  // Sizes no robot has (each was taken before).
  j = OneSonar();
  j["radius"] = 1e300;
  EXPECT_THAT(ErrorOf(j), HasSubstr("radius: must be in (0, 5] metres"));
  j = OneSonar();
  j["sensors"][0]["max_range"] = 1e300;
  EXPECT_THAT(ErrorOf(j), HasSubstr("sensors[0].max_range: at most 1000 metres"));
  j = OneSonar();
  j["sensors"][0]["x"] = 1e9;
  EXPECT_THAT(ErrorOf(j), HasSubstr("sensors[0]: x, y must lie within 10 m"));
  j = json::parse(R"({"name": "l", "units": "m", "radius": 0.2, "laser": {"beams": 10, "max_range": 1e300}})");
  EXPECT_THAT(ErrorOf(j), HasSubstr("laser.max_range: at most 1000 metres"));
}

TEST(RobotJson, NoSensorsIsAnError) {
  EXPECT_THAT(ErrorOf(json::parse(R"({"name": "x"})")), HasSubstr("no sensors"));
}

TEST(RobotJson, LoadReportsBadJsonWithPath) {
  const std::string path = ::cogmap::testing_util::TestTempPath("bad_robot.json");
  std::ofstream(path) << "{\"name\": ";
  try {
    LoadRobotJson(path);
    FAIL();
  } catch (const InputError& e) {
    EXPECT_THAT(e.what(), HasSubstr(path + ": invalid JSON"));
  }
}

TEST(RobotJson, OverflowingNumberIsAnErrorNamingTheFile) {
  // nlohmann throws out_of_range (not parse_error) for 1e999.
  const std::string path = ::cogmap::testing_util::TestTempPath("overflow.json");
  std::ofstream(path) << R"({"name": "x", "radius": 1e999, "laser": {"beams": 10}})";
  try {
    LoadRobotJson(path);
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_THAT(e.what(), HasSubstr(path + ": invalid JSON: "));
  }
}

TEST(RobotJson, ResolveTakesBuiltinNameOrFile) {
  EXPECT_EQ(ResolveRobot("pioneer8").sensors.size(), 8u);
  const std::string path = ::cogmap::testing_util::TestTempPath("one_robot.json");
  std::ofstream(path) << OneSonar().dump();
  EXPECT_EQ(ResolveRobot(path).name, "one");
  EXPECT_THROW(ResolveRobot("no-such-robot"), InputError);
}

TEST(RobotJson, ShippedCourseRobotMatchesPioneer8Mounts) {
  const auto course = LoadRobotJson(std::string(COGMAP_SOURCE_DIR) + "/docs/robots/pioneer8-course.json");
  const auto stock = BuiltinRobot("pioneer8");
  ASSERT_EQ(course.sensors.size(), 8u);
  const double headings[8] = {90, 37.5, 22.5, 7.5, -7.5, -22.5, -37.5, -90};
  for (int i = 0; i < 8; ++i) {
    EXPECT_DOUBLE_EQ(course.sensors[i].robot_from_sensor.x, stock.sensors[i].robot_from_sensor.x);
    EXPECT_DOUBLE_EQ(course.sensors[i].robot_from_sensor.y, stock.sensors[i].robot_from_sensor.y);
    EXPECT_DOUBLE_EQ(course.sensors[i].robot_from_sensor.theta, DegToRad(headings[i]));
  }
}

TEST(RobotJson, ShippedLaserRobotsAreWhatTheirNamesSay) {
  const auto scanner = LoadRobotJson(std::string(COGMAP_SOURCE_DIR) + "/docs/robots/laser-240deg-4m.json");
  ASSERT_EQ(scanner.sensors.size(), 341u);
  EXPECT_NEAR(RadToDeg(scanner.sensors.back().robot_from_sensor.theta - scanner.sensors.front().robot_from_sensor.theta),
              240.0, 1e-9);
  EXPECT_DOUBLE_EQ(scanner.sensors.front().max_range_m, 4.0);
  const auto depth = LoadRobotJson(std::string(COGMAP_SOURCE_DIR) + "/docs/robots/depth-camera-57deg-4m.json");
  ASSERT_EQ(depth.sensors.size(), 160u);
  EXPECT_NEAR(RadToDeg(depth.sensors.back().robot_from_sensor.theta - depth.sensors.front().robot_from_sensor.theta),
              57.0, 1e-9);
  EXPECT_DOUBLE_EQ(depth.sensors.front().min_range_m, 0.45);
  for (const auto* r : {&scanner, &depth})
    for (const RangeSensor& s : r->sensors) EXPECT_EQ(s.kind, SensorKind::kLaser);
}

}  // namespace
}  // namespace cogmap::sensors
