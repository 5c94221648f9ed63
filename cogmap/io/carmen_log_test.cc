#include "cogmap/io/carmen_log.h"

#include <cmath>

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
  EXPECT_THAT(ErrorReading(path, "carmen"), HasSubstr("trailer.clf.gz:10: truncated or corrupt gzip data"));
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
        BadCase{"flaser_negative", "FLASER 2 1 -2 0 0 0 0 0 0 1 h 1\n", ":1: beam 1: negative range"},
        BadCase{"flaser_absurd", "FLASER 2 1 2000 0 0 0 0 0 0 1 h 1\n", ":1: beam 1: absurd range"},
        BadCase{"flaser_pose", "FLASER 2 1 2 0 y 0 0 0 0 1 h 1\n", ":1: y: 'y' is not a number"},
        BadCase{"flaser_beams", "FLASER 2 1 2 0 0 0 0 0 0 1 h 1\nFLASER 1 1 0 0 0 0 0 0 1 h 1\n",
                ":2: FLASER with 1 beams, but the first one had 2"},
        BadCase{"flaser_n", "FLASER two 1 2\n", ":1: beam count: 'two' is not a whole number"},
        BadCase{"truepos_count", "TRUEPOS 0 0 0 0 0 0\n", ":1: TRUEPOS: expected 10 fields"},
        BadCase{"param_short", "PARAM x\n", ":1: PARAM: expected"},
        BadCase{"no_laser", "ODOM 0 0 0 0 0 0 1 h 1\n", "no_laser.clf: empty log: no range readings"},
        BadCase{"only_comments", "# nothing\n", "only_comments.clf: empty log: no range readings"}),
    [](const auto& info) { return std::string(info.param.name); });

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
