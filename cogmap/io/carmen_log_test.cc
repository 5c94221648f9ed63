#include "cogmap/io/carmen_log.h"

#include <cmath>
#include <map>

#include "cogmap/core/angles.h"
#include "cogmap/io/log_test_util.h"

namespace cogmap::io {
namespace {

using ::testing::HasSubstr;
using namespace testing_util;

const std::string kTiny =
    "# message formats defined: PARAM SYNC ODOM FLASER RLASER TRUEPOS\n"
    "PARAM robot_frontlaser_offset 0.1 nohost 0\n"
    "ODOM 0 0 0 0 0 0 1.5 host 1.5\n"
    "NEFF 15\n"
    "SYNC tag 2.0 host 2.0\n"
    "FLASER 3 1.5 2.5 81.9 1.1 2.2 0.3 1 2 0.25 2.5 host 2.5\n"
    "ODOM 1 2 0.25 0 0 0 0 host 0\n"
    "TRUEPOS 1.2 2.1 0.3 1 2 0.25 3 host 3\n"
    "ODOM 1 2 0.25 0 0 0 1.28284e-153 host 1.28284e-153\n";

TEST(CarmenLog, FlaserOdomFieldsAreOdomAndPoseFieldsAreTruth) {
  const auto rs = ReadAll(WriteTemp("tiny.clf", kTiny), "carmen");
  ASSERT_EQ(rs.size(), 5u);
  const auto& f = rs[1];
  EXPECT_EQ(f.time_s, 2.5);
  EXPECT_EQ(f.odom.x, 1.0);
  EXPECT_EQ(f.odom.y, 2.0);
  EXPECT_EQ(f.odom.theta, 0.25);
  ASSERT_TRUE(f.truth);
  EXPECT_EQ(f.truth->x, 1.1);
  EXPECT_EQ(f.truth->y, 2.2);
  EXPECT_EQ(f.truth->theta, 0.3);
  ASSERT_EQ(f.ranges.size(), 3u);
  EXPECT_EQ(f.ranges[0].sensor, 0);
  EXPECT_EQ(f.ranges[0].range_m, 1.5);
  EXPECT_EQ(f.ranges[2].sensor, 2);
  EXPECT_EQ(f.ranges[2].range_m, 81.9);
}

TEST(CarmenLog, OdomIsAnOdometryOnlyRecord) {
  const auto rs = ReadAll(WriteTemp("tiny.clf", kTiny), "carmen");
  EXPECT_EQ(rs[0].time_s, 1.5);
  EXPECT_TRUE(rs[0].ranges.empty());
  EXPECT_FALSE(rs[0].truth);
}

TEST(CarmenLog, ZeroTimestampTakesThePreviousTime) {
  const auto rs = ReadAll(WriteTemp("tiny.clf", kTiny), "carmen");
  EXPECT_EQ(rs[2].time_s, 2.5);
  EXPECT_EQ(rs[2].odom.x, 1.0);
  EXPECT_EQ(rs[4].time_s, 3.0);  // uninitialised-memory timestamp: missing
}

TEST(CarmenLog, TrueposCarriesTruthAndOdom) {
  const auto rs = ReadAll(WriteTemp("tiny.clf", kTiny), "carmen");
  ASSERT_TRUE(rs[3].truth);
  EXPECT_EQ(rs[3].truth->x, 1.2);
  EXPECT_EQ(rs[3].odom.theta, 0.25);
  EXPECT_EQ(rs[3].time_s, 3.0);
}

TEST(CarmenLog, RobotHintIsTheFrontLaserAtItsOffset) {
  auto r = OpenLog(WriteTemp("tiny.clf", kTiny), "carmen");
  ASSERT_TRUE(r->robot_hint());
  const auto robot = *r->robot_hint();
  ASSERT_EQ(robot.sensors.size(), 3u);
  EXPECT_EQ(robot.sensors[0].robot_from_sensor.x, 0.1);
  EXPECT_DOUBLE_EQ(robot.sensors[0].robot_from_sensor.theta, -kPi / 2);
  EXPECT_DOUBLE_EQ(robot.sensors[1].robot_from_sensor.theta, 0.0);
  EXPECT_EQ(robot.sensors[0].kind, sensors::SensorKind::kLaser);
  // Largest reading 81.9 m >= 20 m: that is the no-return value.
  EXPECT_EQ(robot.sensors[0].max_range_m, 81.9);
}

TEST(CarmenLog, MaxRangeDefaultsToSickCodeWhenReadingsAreShort) {
  auto r = OpenLog(WriteTemp("short.clf", "FLASER 2 1.5 2.5 0 0 0 0 0 0 1 h 1\n"), "carmen");
  EXPECT_EQ(r->robot_hint()->sensors[0].max_range_m, 81.9);
}

// The largest reading, however it is written: the opening pass parses
// only the readings that may exceed the largest so far (a plain decimal with
// fewer digits before its point cannot).
TEST(CarmenLog, MaxRangeIsTheLargestReadingHoweverWritten) {
  const std::pair<const char*, double> cases[] = {
      {"FLASER 4 25.5 3 9.99 26 0 0 0 0 0 0 1 h 1\n", 26.0},
      {"FLASER 4 25.5 3 0030.25 26 0 0 0 0 0 0 1 h 1\n", 30.25},
      {"FLASER 4 25.5 3 .5 25.75 0 0 0 0 0 0 1 h 1\n", 25.75},
      {"FLASER 4 25.5 3 1e2 26 0 0 0 0 0 0 1 h 1\n", 100.0},
      {"FLASER 2 9.5 81.25 0 0 0 0 0 0 1 h 1\nFLASER 2 99.5 7 0 0 0 0 0 0 2 h 2\n", 99.5},
      {"FLASER 2 30 1 0 0 0 0 0 0 1 h 1\nFLASER 2 100 2 0 0 0 0 0 0 2 h 2\n", 100.0},
  };
  for (const auto& [text, want] : cases) {
    auto r = OpenLog(WriteTemp("largest.clf", text), "carmen");
    EXPECT_EQ(r->robot_hint()->sensors[0].max_range_m, want) << text;
  }
  // A malformed reading ends the opening pass's look at its line, as before:
  // the readings after it on that line are not taken (Next() reports it).
  auto r = OpenLog(WriteTemp("largest_bad.clf", "FLASER 3 22 x. 50 0 0 0 0 0 0 1 h 1\n"), "carmen");
  EXPECT_EQ(r->robot_hint()->sensors[0].max_range_m, 22.0);
}

TEST(CarmenLog, MaxRangeFromParam) {
  auto r = OpenLog(WriteTemp("param.clf", "PARAM robot_front_laser_max 30 h 0\n"
                                         "FLASER 2 1.5 50 0 0 0 0 0 0 1 h 1\n"),
                   "carmen");
  EXPECT_EQ(r->robot_hint()->sensors[1].max_range_m, 30.0);
}

TEST(CarmenLog, CarmenFieldOfViewConvention) {
  EXPECT_DOUBLE_EQ(CarmenLaserFov(180), DegToRad(179));
  EXPECT_DOUBLE_EQ(CarmenLaserFov(181), kPi);
  EXPECT_DOUBLE_EQ(CarmenLaserFov(361), kPi);
  auto robot = *OpenLog(WriteTemp("fov.clf", "FLASER 180" + [] {
                          std::string s;
                          for (int i = 0; i < 180; ++i) s += " 1";
                          return s;
                        }() + " 0 0 0 0 0 0 1 h 1\n"),
                        "carmen")
                    ->robot_hint();
  // 1 degree steps from -89.5 to +89.5 degrees.
  EXPECT_NEAR(robot.sensors[0].robot_from_sensor.theta, DegToRad(-89.5), 1e-12);
  EXPECT_NEAR(robot.sensors[1].robot_from_sensor.theta, DegToRad(-88.5), 1e-12);
  EXPECT_NEAR(robot.sensors[179].robot_from_sensor.theta, DegToRad(89.5), 1e-12);
}

TEST(CarmenLog, RearLaserFollowsTheFrontOneAndFacesBack) {
  auto r = OpenLog(WriteTemp("rear.clf", "FLASER 2 1 2 0 0 0 0 0 0 1 h 1\n"
                                        "RLASER 3 3 4 5 0 0 0 0 0 0 1 h 1\n"),
                   "carmen");
  const auto robot = *r->robot_hint();
  ASSERT_EQ(robot.sensors.size(), 5u);
  EXPECT_NEAR(robot.sensors[3].robot_from_sensor.theta, kPi, 1e-12);
  const auto rs = ReadAll(*r);
  ASSERT_EQ(rs.size(), 2u);
  EXPECT_EQ(rs[1].ranges[0].sensor, 2);
  EXPECT_EQ(rs[1].ranges[2].sensor, 4);
}

TEST(CarmenLog, RobotLaser1UsesItsOwnGeometry) {
  // type start fov res max acc mode n r.. m e.. laser(3) robot(3) tv rv fwd side turn ts host lts
  const std::string line =
      "ROBOTLASER1 0 -1.5 3 1.5 20 0.01 0 3 1 2 3 0 1.1 2 0 1 2 0 0 0 0 0 0 7 h 7\n";
  auto r = OpenLog(WriteTemp("rl1.clf", line), "carmen");
  const auto robot = *r->robot_hint();
  ASSERT_EQ(robot.sensors.size(), 3u);
  EXPECT_NEAR(robot.sensors[0].robot_from_sensor.x, 0.1, 1e-12);
  EXPECT_NEAR(robot.sensors[0].robot_from_sensor.theta, -1.5, 1e-12);
  EXPECT_NEAR(robot.sensors[2].robot_from_sensor.theta, 1.5, 1e-12);
  EXPECT_EQ(robot.sensors[0].max_range_m, 20.0);
  const auto rs = ReadAll(*r);
  ASSERT_EQ(rs.size(), 1u);
  EXPECT_EQ(rs[0].odom.x, 1.0);
  EXPECT_EQ(rs[0].time_s, 7.0);
  EXPECT_EQ(rs[0].ranges[1].range_m, 2.0);
}

TEST(CarmenLog, ReadsGzip) {
  const std::string path = WriteTemp("tiny.clf.gz", GzipBytes(kTiny));
  EXPECT_EQ(ReadAll(path, "auto").size(), 5u);
}

TEST(CarmenLog, TruncatedGzipIsAnErrorNamingTheFile) {
  std::string content;
  for (int i = 0; i < 2000; ++i)
    content += "FLASER 3 1.5 2.5 3.5 1 2 0.3 1 2 0.25 " + std::to_string(i) + " host 0\n";
  const std::string gz = GzipBytes(content);
  const std::string path = WriteTemp("cut.clf.gz", gz.substr(0, gz.size() / 2));
  const std::string e = ErrorReading(path, "carmen");
  EXPECT_THAT(e, HasSubstr("cut.clf.gz:"));
  EXPECT_THAT(e, HasSubstr("truncated or corrupt gzip data"));
  // The lines before the cut were readable: the error names a later line.
  EXPECT_THAT(e, ::testing::Not(HasSubstr("cut.clf.gz:1:")));
}

TEST(CarmenLog, GzipMissingOnlyItsTrailerIsAnError) {
  const std::string gz = GzipBytes(kTiny);
  const std::string path = WriteTemp("trailer.clf.gz", gz.substr(0, gz.size() - 4));
  EXPECT_THAT(ErrorReading(path, "carmen"), HasSubstr("trailer.clf.gz:10: truncated or corrupt gzip data (unexpected end of file)"));
}

struct BadCase {
  const char* name;
  const char* body;
  const char* message;
};

class CarmenLogBad : public ::testing::TestWithParam<BadCase> {};

TEST_P(CarmenLogBad, NamesFileLineAndProblem) {
  const BadCase& c = GetParam();
  EXPECT_THAT(ErrorReading(WriteTemp(std::string(c.name) + ".clf", c.body), "carmen"), HasSubstr(c.message));
}

INSTANTIATE_TEST_SUITE_P(
    Cases, CarmenLogBad,
    ::testing::Values(
        BadCase{"odom_count", "ODOM 0 0 0 0 0 0 1 h\n", ".clf:1: ODOM: expected 10 fields"},
        BadCase{"flaser_count", "NEFF 1\nFLASER 3 1 2 0 0 0 0 0 0 1 h 1\n", ":2: FLASER: expected 14 fields"},
        BadCase{"flaser_number", "FLASER 2 1 x 0 0 0 0 0 0 1 h 1\n", ":1: range: 'x' is not a number"},
        BadCase{"flaser_nan", "FLASER 2 1 NaN 0 0 0 0 0 0 1 h 1\n", ":1: range: 'NaN' is not a"},
        BadCase{"flaser_negative", "FLASER 2 1 -2 0 0 0 0 0 0 1 h 1\n", ":1: beam 1: negative range -2 m"},
        BadCase{"flaser_absurd", "FLASER 2 1 2000 0 0 0 0 0 0 1 h 1\n", ":1: beam 1: absurd range 2000 m (more than 1000 m)"},
        BadCase{"flaser_pose", "FLASER 2 1 2 0 y 0 0 0 0 1 h 1\n", ":1: y: 'y' is not a number"},
        BadCase{"flaser_beams", "FLASER 2 1 2 0 0 0 0 0 0 1 h 1\nFLASER 1 1 0 0 0 0 0 0 1 h 1\n",
                ":2: FLASER with 1 beams, but the first one had 2"},
        BadCase{"flaser_n", "FLASER two 1 2\n", ":1: beam count: 'two' is not a whole number"},
        BadCase{"truepos_count", "TRUEPOS 0 0 0 0 0 0\n", ":1: TRUEPOS: expected 10 fields"},
        BadCase{"param_short", "PARAM x\n", ":1: PARAM: expected"},
        BadCase{"no_laser", "ODOM 0 0 0 0 0 0 1 h 1\nNEFF 3\n",
                "no_laser.clf:2: empty log: no range readings (1 odometry messages, no laser or sonar message; "
                "skipped 1 NEFF)"},
        BadCase{"only_comments", "# nothing\n", "only_comments.clf:1: empty log: no range readings"},
        BadCase{"unknown_type", "ODOM 0 0 0 0 0 0 1 h 1\nLIDARSCAN 3 1 2 3\n",
                "unknown_type.clf:2: unknown message type 'LIDARSCAN'"},
        BadCase{"garbage_line", "ODOM 0 0 0 0 0 0 1 h 1\n0.5 0.25\n", "garbage_line.clf:2: unknown message type '0.5'"},
        BadCase{"sonar_cut", "ODOM 0 0 0 0 0 0 1 h 1\nSONAR 0.5 2 1 2 0 0 0 0 0 3.14 5 h\n",
                "sonar_cut.clf:2: SONAR: expected 14 fields"},
        BadCase{"sonar_no_count", "SONAR 0.5\n", "sonar_no_count.clf:1: SONAR: message cut short before the sonar count"},
        BadCase{"sonar_degrees", "ODOM 0 0 0 0 0 0 1 h 1\nSONAR 30 1 2 0 0 0 5 h 5\n",
                ":2: SONAR: cone_angle 30 must be in (0, 2 pi] radians"},
        BadCase{"sonar_negative", "ODOM 0 0 0 0 0 0 1 h 1\nSONAR 0.5 1 -2 0 0 0 5 h 5\n", ":2: sonar 0: negative range"},
        BadCase{"sonar_count_changes", "ODOM 0 0 0 0 0 0 1 h 1\nSONAR 0.5 1 2 0 0 0 5 h 5\nSONAR 0.5 0 6 h 6\n",
                ":3: SONAR with 0 sonars, but the first one had 1"},
        BadCase{"sonar_before_odom", "SONAR 0.5 1 2 0 0 0 5 h 5\n",
                "sonar_before_odom.clf:1: empty log: no range readings (0 odometry messages, no laser or sonar "
                "message; skipped 1 SONAR (before the first odometry: no pose))"},
        BadCase{"rawlaser_cut", "ODOM 0 0 0 0 0 0 1 h 1\nRAWLASER1 0 -1.5 3 1.5 20 0.01 0 3 1 2 3 0 7 h\n",
                ":2: RAWLASER1: expected 16 fields"},
        BadCase{"rawlaser_remissions", "RAWLASER1 0 -1.5 3 1.5 20 0.01 0 1 1 x\n",
                ":1: remission count: 'x' is not a whole number"},
        BadCase{"robotlaser2_cut", "ROBOTLASER2 0 -1.5 3 1.5 20 0.01 0 2 1 2 0 0 0 0 0 0 0 0 0 0 0 0 7 h\n",
                ":1: ROBOTLASER2: expected 26 fields"},
        // Hostile counts (issue 14): refused before anything is sized by them.
        BadCase{"flaser_huge", "FLASER 30000000\n", "flaser_huge.clf:1: beam count 30000000 is absurd"},
        BadCase{"flaser_overflow", "FLASER 9223372036854775807 1 2\n", ":1: beam count 9223372036854775807 is absurd"},
        BadCase{"remission_huge", "ROBOTLASER1 0 -1.5 3 1.5 20 0.01 0 1 1 9223372036854775807 0 0\n",
                ":1: remission count 9223372036854775807 is absurd"},
        BadCase{"sonar_huge", "ODOM 0 0 0 0 0 0 1 h 1\nSONAR 0.5 4611686018427387904 1\n",
                ":2: sonar count 4611686018427387904 is absurd"},
        BadCase{"far_pose", "FLASER 2 1 2 1e300 0 0 0 0 0 1 h 1\n",
                ":1: pose: absurd position (1e+300, 0) m (more than 100000 km from the origin)"}),
    [](const auto& info) { return std::string(info.param.name); });

// CARMEN's message formats (readlog.c): RAWLASERk has no pose and takes the
// latest odometry; SONAR likewise; ROBOTLASER2 is parsed like ROBOTLASER1.
const std::string kRaw =
    "PARAM robot_frontlaser_offset 0.2 h 0\n"
    "ODOM 1 2 0.5 0 0 0 10 h 10\n"
    // type start fov res max acc mode n r1..r3 m e1 e2 ts host lts
    "RAWLASER1 0 -1.5 3 1.5 30 0.01 0 3 1.25 2.5 30 2 0.75 0.5 11 h 11\n"
    "TRUEPOS 3.5 4.5 0.25 3 4 0.2 12 h 12\n"
    "RAWLASER1 0 -1.5 3 1.5 30 0.01 0 3 4 5 6 0 0 h 13\n";

TEST(CarmenLog, RawLaserTakesTheLatestOdometry) {
  const auto rs = ReadAll(WriteTemp("raw.clf", kRaw), "carmen");
  ASSERT_EQ(rs.size(), 4u);
  const auto& a = rs[1];
  EXPECT_EQ(a.time_s, 11.0);
  EXPECT_EQ(a.odom.x, 1.0);
  EXPECT_EQ(a.odom.y, 2.0);
  EXPECT_EQ(a.odom.theta, 0.5);
  EXPECT_FALSE(a.truth);
  ASSERT_EQ(a.ranges.size(), 3u);
  EXPECT_EQ(a.ranges[0].sensor, 0);
  EXPECT_EQ(a.ranges[0].range_m, 1.25);
  EXPECT_EQ(a.ranges[1].range_m, 2.5);
  EXPECT_EQ(a.ranges[2].sensor, 2);
  EXPECT_EQ(a.ranges[2].range_m, 30.0);
  // After a TRUEPOS: its odometry and its truth; timestamp 0 -> logger time.
  const auto& b = rs[3];
  EXPECT_EQ(b.time_s, 13.0);
  EXPECT_EQ(b.odom.x, 3.0);
  EXPECT_EQ(b.odom.theta, 0.2);
  ASSERT_TRUE(b.truth);
  EXPECT_EQ(b.truth->x, 3.5);
  EXPECT_EQ(b.ranges[2].range_m, 6.0);
}

TEST(CarmenLog, RawLaserGeometryFromItsFields) {
  auto r = OpenLog(WriteTemp("raw.clf", kRaw), "carmen");
  const auto robot = *r->robot_hint();
  EXPECT_EQ(robot.name, "carmen-laser");
  ASSERT_EQ(robot.sensors.size(), 3u);
  EXPECT_EQ(robot.sensors[0].robot_from_sensor.x, 0.2);  // laser 1: the front laser's offset
  EXPECT_DOUBLE_EQ(robot.sensors[0].robot_from_sensor.theta, -1.5);
  EXPECT_DOUBLE_EQ(robot.sensors[1].robot_from_sensor.theta, 0.0);
  EXPECT_DOUBLE_EQ(robot.sensors[2].robot_from_sensor.theta, 1.5);
  EXPECT_EQ(robot.sensors[0].beam_width_rad, 1.5);
  EXPECT_EQ(robot.sensors[0].max_range_m, 30.0);
  EXPECT_EQ(robot.sensors[0].kind, sensors::SensorKind::kLaser);
}

TEST(CarmenLog, RawLaserBeforeAnyOdometryIsSkippedAndCounted) {
  auto r = OpenLog(WriteTemp("raw_first.clf", "RAWLASER3 0 -1.5 3 1.5 30 0.01 0 1 1 0 5 h 5\n" + kRaw), "carmen");
  EXPECT_EQ(ReadAll(*r).size(), 4u);
  EXPECT_EQ(r->skipped(), (std::map<std::string, long>{{"RAWLASER3 (before the first odometry: no pose)", 1}}));
  // RAWLASER1 first, then RAWLASER3 at the robot centre.
  EXPECT_EQ(r->robot_hint()->sensors.size(), 4u);
  EXPECT_EQ(r->robot_hint()->sensors[3].robot_from_sensor.x, 0.0);
}

TEST(CarmenLog, RawLaserOfALaserWithPosesIsSkipped) {
  // ROBOTLASER1 carries laser 1's scans with poses: RAWLASER1 repeats them.
  const std::string log =
      "ROBOTLASER1 0 -1.5 3 1.5 20 0.01 0 3 1 2 3 0 1.1 2 0 1 2 0 0 0 0 0 0 7 h 7\n"
      "RAWLASER1 0 -1.5 3 1.5 20 0.01 0 3 1 2 3 0 7 h 7\n";
  auto r = OpenLog(WriteTemp("raw_shadow.clf", log), "carmen");
  EXPECT_EQ(r->robot_hint()->sensors.size(), 3u);
  EXPECT_EQ(ReadAll(*r).size(), 1u);
  EXPECT_EQ(r->skipped(), (std::map<std::string, long>{
                              {"RAWLASER1 (the same scans as FLASER/ROBOTLASER1, which carry poses)", 1}}));
}

TEST(CarmenLog, RobotLaser2ComesAfterRobotLaser1) {
  const std::string log =
      "ROBOTLASER1 0 -1.5 3 1.5 20 0.01 0 3 1 2 3 0 1.1 2 0 1 2 0 0 0 0 0 0 7 h 7\n"
      "ROBOTLASER2 0 -0.5 1 1 10 0.01 0 2 4 5 1 9 0.5 2 3.14159 1 2 0 0 0 0 0 0 8 h 8\n";
  auto r = OpenLog(WriteTemp("rl2.clf", log), "carmen");
  const auto robot = *r->robot_hint();
  ASSERT_EQ(robot.sensors.size(), 5u);
  EXPECT_NEAR(robot.sensors[3].robot_from_sensor.x, -0.5, 1e-12);
  EXPECT_NEAR(robot.sensors[3].robot_from_sensor.theta, 3.14159 - 0.5, 1e-12);
  EXPECT_EQ(robot.sensors[3].max_range_m, 10.0);
  const auto rs = ReadAll(*r);
  ASSERT_EQ(rs.size(), 2u);
  EXPECT_EQ(rs[1].time_s, 8.0);
  EXPECT_EQ(rs[1].odom.x, 1.0);
  ASSERT_EQ(rs[1].ranges.size(), 2u);
  EXPECT_EQ(rs[1].ranges[0].sensor, 3);
  EXPECT_EQ(rs[1].ranges[1].sensor, 4);
  EXPECT_EQ(rs[1].ranges[1].range_m, 5.0);
}

// cone n r1..rn (x y theta)*n ts host lts
const std::string kSonar =
    "ODOM 1 2 0.5 0 0 0 10 h 10\n"
    "NEFF 1\n"
    "SONAR 0.5 3 1.5 5 2.25 0.1 0.2 1.5 0.15 0 0 0.1 -0.2 -1.5 12 h 12\n"
    "NEFF 2\n"
    "SYNC x 1 h 1\n";

TEST(CarmenLog, SonarTakesTheLatestOdometry) {
  auto r = OpenLog(WriteTemp("sonar.clf", kSonar), "carmen");
  const auto rs = ReadAll(*r);
  ASSERT_EQ(rs.size(), 2u);
  const auto& s = rs[1];
  EXPECT_EQ(s.time_s, 12.0);
  EXPECT_EQ(s.odom.x, 1.0);
  EXPECT_EQ(s.odom.y, 2.0);
  EXPECT_EQ(s.odom.theta, 0.5);
  ASSERT_EQ(s.ranges.size(), 3u);
  EXPECT_EQ(s.ranges[0].sensor, 0);
  EXPECT_EQ(s.ranges[0].range_m, 1.5);
  EXPECT_EQ(s.ranges[1].range_m, 5.0);
  EXPECT_EQ(s.ranges[2].sensor, 2);
  EXPECT_EQ(s.ranges[2].range_m, 2.25);
  EXPECT_EQ(r->skipped(), (std::map<std::string, long>{{"NEFF", 2}, {"SYNC", 1}}));
}

TEST(CarmenLog, SonarRingFromTheFirstMessage) {
  auto r = OpenLog(WriteTemp("sonar.clf", kSonar), "carmen");
  const auto robot = *r->robot_hint();
  EXPECT_EQ(robot.name, "carmen-sonar");
  ASSERT_EQ(robot.sensors.size(), 3u);
  EXPECT_EQ(robot.sensors[0].robot_from_sensor.x, 0.1);
  EXPECT_EQ(robot.sensors[0].robot_from_sensor.y, 0.2);
  EXPECT_EQ(robot.sensors[0].robot_from_sensor.theta, 1.5);
  EXPECT_EQ(robot.sensors[2].robot_from_sensor.y, -0.2);
  EXPECT_EQ(robot.sensors[2].robot_from_sensor.theta, -1.5);
  for (const auto& sensor : robot.sensors) {
    EXPECT_EQ(sensor.kind, sensors::SensorKind::kSonar);
    EXPECT_EQ(sensor.beam_width_rad, 0.5);
    EXPECT_EQ(sensor.max_range_m, 5.0);  // largest reading 5 m: the Pioneer's 5 m
    EXPECT_EQ(sensor.min_range_m, 0.15);
  }
}

TEST(CarmenLog, SonarMaxRangeIsTheLargestReadingAboveFiveMetres) {
  auto r = OpenLog(WriteTemp("sonar_far.clf", "ODOM 0 0 0 0 0 0 1 h 1\nSONAR 0.5 1 6.5 0 0 0 5 h 5\n"), "carmen");
  EXPECT_EQ(r->robot_hint()->sensors[0].max_range_m, 6.5);
}

TEST(CarmenLog, LaserAndSonarInOneLog) {
  auto r = OpenLog(WriteTemp("both.clf", kSonar + "FLASER 2 1 2 0 0 0 0 0 0 13 h 13\n"), "carmen");
  const auto robot = *r->robot_hint();
  EXPECT_EQ(robot.name, "carmen-laser-sonar");
  ASSERT_EQ(robot.sensors.size(), 5u);
  EXPECT_EQ(robot.sensors[2].kind, sensors::SensorKind::kSonar);
  const auto rs = ReadAll(*r);
  EXPECT_EQ(rs[1].ranges[0].sensor, 2);
  EXPECT_EQ(rs[2].ranges[1].sensor, 1);
}

TEST(CarmenLog, RadishLogsSkipOnlyNeff) {
  auto r = OpenLog(std::string(COGMAP_SHARED_DIR) + "/data/carmen/aces-corrected.log.gz", "auto");
  ReadAll(*r);
  EXPECT_EQ(r->skipped(), (std::map<std::string, long>{{"NEFF", 440}}));
}

// The real Radish logs (../shared/data/carmen).
const std::string kIntel = std::string(COGMAP_SHARED_DIR) + "/data/carmen/intel-corrected.log.gz";
const std::string kAces = std::string(COGMAP_SHARED_DIR) + "/data/carmen/aces-corrected.log.gz";

TEST(CarmenLogRealData, IntelFirstRecordsAreExact) {
  auto r = OpenLog(kIntel, "auto");
  sensors::LogRecord rec;
  ASSERT_TRUE(r->Next(&rec));
  EXPECT_EQ(rec.time_s, 0.000246);
  EXPECT_EQ(rec.odom.x, 0.0);
  EXPECT_TRUE(rec.ranges.empty());
  while (rec.ranges.empty()) ASSERT_TRUE(r->Next(&rec));
  ASSERT_EQ(rec.ranges.size(), 180u);
  EXPECT_EQ(rec.ranges[0].range_m, 1.09);
  EXPECT_EQ(rec.ranges[1].range_m, 1.08);
  EXPECT_EQ(rec.ranges[179].range_m, 1.23);
  EXPECT_EQ(rec.odom.x, 0.600266);
  EXPECT_EQ(rec.odom.y, -0.0320327);
  EXPECT_EQ(rec.odom.theta, -0.354665);
  ASSERT_TRUE(rec.truth);
  EXPECT_EQ(rec.truth->x, 0.600266);
  EXPECT_EQ(rec.time_s, 32.9068);
  EXPECT_EQ(r->robot_hint()->sensors.size(), 180u);
  EXPECT_EQ(r->robot_hint()->sensors[0].max_range_m, 81.83);
}

TEST(CarmenLogRealData, IntelWholeLogCounts) {
  auto r = OpenLog(kIntel, "auto");
  long records = 0, sweeps = 0;
  sensors::LogRecord rec;
  while (r->Next(&rec)) {
    ++records;
    if (!rec.ranges.empty()) ++sweeps;
  }
  EXPECT_EQ(records, 14541 + 910);
  EXPECT_EQ(sweeps, 910);
  EXPECT_EQ(r->progress(), 1.0);
}

TEST(CarmenLogRealData, AcesNoReturnIsFiftyMetres) {
  auto r = OpenLog(kAces, "auto");
  EXPECT_EQ(r->robot_hint()->sensors[0].max_range_m, 50.0);
  sensors::LogRecord rec;
  do ASSERT_TRUE(r->Next(&rec));
  while (rec.ranges.empty());
  EXPECT_EQ(rec.ranges[0].range_m, 6.66);
  EXPECT_EQ(rec.ranges[1].range_m, 6.86);
  EXPECT_EQ(rec.ranges[17].range_m, 50.0);
  EXPECT_EQ(rec.odom.x, 0.89706);
  EXPECT_EQ(rec.time_s, 21.0199);
}

}  // namespace
}  // namespace cogmap::io
