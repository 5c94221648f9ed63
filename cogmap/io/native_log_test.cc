#include "cogmap/io/native_log.h"

#include <sstream>

#include "cogmap/io/log_test_util.h"
#include "cogmap/sensors/robot_json.h"

namespace cogmap::io {
namespace {

using ::testing::HasSubstr;
using namespace testing_util;

std::string Header() { return "# cogmap-log 1\nrobot pioneer8\n"; }

std::vector<sensors::LogRecord> SampleRecords() {
  std::vector<sensors::LogRecord> rs(3);
  rs[0].time_s = 0.1;
  rs[0].odom = {1.0 / 3.0, -2.5e-7, 3.141592653589793};
  rs[0].ranges = {{0, 0.1 + 0.2}, {7, 5.0}, {3, 1e-3}};
  rs[1].time_s = 0.2;
  rs[1].odom = {12345.678901234567, 0.0, -0.5};
  rs[1].truth = Pose2{12345.6, 1e-300, -0.49999999999999994};
  rs[2].time_s = 1e9 + 0.123456789;
  rs[2].odom = {2.0, 3.0, 1.0};
  rs[2].truth = Pose2{2.1, 2.9, 1.1};
  rs[2].ranges = {{1, 2.718281828459045}};
  return rs;
}

void ExpectSame(const sensors::LogRecord& a, const sensors::LogRecord& b) {
  EXPECT_EQ(a.time_s, b.time_s);
  EXPECT_EQ(a.odom.x, b.odom.x);
  EXPECT_EQ(a.odom.y, b.odom.y);
  EXPECT_EQ(a.odom.theta, b.odom.theta);
  ASSERT_EQ(a.truth.has_value(), b.truth.has_value());
  if (a.truth) {
    EXPECT_EQ(a.truth->x, b.truth->x);
    EXPECT_EQ(a.truth->y, b.truth->y);
    EXPECT_EQ(a.truth->theta, b.truth->theta);
  }
  ASSERT_EQ(a.ranges.size(), b.ranges.size());
  for (size_t i = 0; i < a.ranges.size(); ++i) {
    EXPECT_EQ(a.ranges[i].sensor, b.ranges[i].sensor);
    EXPECT_EQ(a.ranges[i].range_m, b.ranges[i].range_m);
  }
}

std::string WriteLog(const sensors::RobotDescription& robot, const std::vector<sensors::LogRecord>& rs) {
  std::ostringstream out;
  NativeLogWriter w(out, robot);
  for (const auto& r : rs) w.Write(r);
  return out.str();
}

TEST(NativeLog, RoundTripIsBitExact) {
  const auto rs = SampleRecords();
  const std::string path = WriteTemp("roundtrip.log", WriteLog(sensors::BuiltinRobot("pioneer8"), rs));
  const auto back = ReadAll(path, "native");
  ASSERT_EQ(back.size(), rs.size());
  for (size_t i = 0; i < rs.size(); ++i) ExpectSame(back[i], rs[i]);
}

TEST(NativeLog, WriterNamesABuiltinRobot) {
  const std::string text = WriteLog(sensors::BuiltinRobot("pioneer16"), {});
  EXPECT_EQ(text, "# cogmap-log 1\nrobot pioneer16\n");
}

TEST(NativeLog, CustomRobotRoundTripsAsJson) {
  auto robot = sensors::BuiltinRobot("pioneer8");
  robot.name = "my-pioneer";
  robot.sensors[2].robot_from_sensor.theta = 0.123456789;
  const std::string text = WriteLog(robot, SampleRecords());
  EXPECT_THAT(text, HasSubstr("\nrobot-json {"));
  auto reader = OpenLog(WriteTemp("custom.log", text), "native");
  ASSERT_TRUE(reader->robot_hint());
  EXPECT_TRUE(sensors::SameRobot(*reader->robot_hint(), robot));
}

TEST(NativeLog, ModifiedBuiltinIsNotCalledByItsName) {
  auto robot = sensors::BuiltinRobot("pioneer8");
  robot.sensors[0].max_range_m = 3.0;
  EXPECT_THAT(WriteLog(robot, {}), HasSubstr("robot-json"));
}

TEST(NativeLog, RecordLinesAreDocumentedKeywords) {
  sensors::LogRecord r;
  r.time_s = 1.5;
  r.odom = {1, 2, 0.5};
  r.truth = Pose2{1.25, 2, 0.5};
  r.ranges = {{0, 1.5}, {3, 5}};
  EXPECT_EQ(WriteLog(sensors::BuiltinRobot("pioneer8"), {r}),
            Header() + "ODOM 1.5 1 2 0.5\nTRUTH 1.5 1.25 2 0.5\nSWEEP 1.5 2 0 1.5 3 5\n");
}

TEST(NativeLog, SweepWithoutOdomTakesTheLatestPose) {
  const auto rs = ReadAll(WriteTemp("latest.log", Header() +
                                                     "# a comment\n\nODOM 1 1 2 0\nTRUTH 1 1.1 2 0\n"
                                                     "SWEEP 1.5 1 0 2.5\nSWEEP 2 1 1 3.5\n"),
                          "native");
  ASSERT_EQ(rs.size(), 2u);
  EXPECT_EQ(rs[0].time_s, 1.5);
  EXPECT_EQ(rs[1].time_s, 2.0);
  EXPECT_EQ(rs[1].odom.x, 1.0);
  ASSERT_TRUE(rs[1].truth);
  EXPECT_EQ(rs[1].truth->x, 1.1);
  ASSERT_EQ(rs[1].ranges.size(), 1u);
  EXPECT_EQ(rs[1].ranges[0].sensor, 1);
  EXPECT_EQ(rs[1].ranges[0].range_m, 3.5);
}

TEST(NativeLog, OdometryOnlyRecordsAreKept) {
  const auto rs = ReadAll(WriteTemp("odomonly.log", Header() + "ODOM 0 0 0 0\nODOM 1 1 0 0\nSWEEP 1 1 0 2\n"),
                          "native");
  ASSERT_EQ(rs.size(), 2u);
  EXPECT_TRUE(rs[0].ranges.empty());
  EXPECT_EQ(rs[1].ranges.size(), 1u);
}

TEST(NativeLog, MaxRangeReadingIsData) {
  const auto rs = ReadAll(WriteTemp("maxrange.log", Header() + "ODOM 0 0 0 0\nSWEEP 0 1 0 5\n"), "native");
  EXPECT_EQ(rs[0].ranges[0].range_m, 5.0);
}

TEST(NativeLog, ReadsGzip) {
  const std::string path = WriteTemp("native.log.gz", GzipBytes(Header() + "ODOM 0 0 0 0\nSWEEP 0 1 0 2\n"));
  EXPECT_EQ(ReadAll(path, "auto").size(), 1u);
}

TEST(NativeLog, NewerVersionIsAClearError) {
  EXPECT_THAT(ErrorReading(WriteTemp("v2.log", "# cogmap-log 2\nrobot pioneer8\n"), "native"),
              HasSubstr("v2.log:1: log format version 2 is newer than this cogmap reads (1)"));
}

struct BadCase {
  const char* name;
  const char* body;
  const char* message;
};

class NativeLogBad : public ::testing::TestWithParam<BadCase> {};

TEST_P(NativeLogBad, NamesFileLineAndProblem) {
  const BadCase& c = GetParam();
  const std::string path = WriteTemp(std::string(c.name) + ".log", c.body);
  EXPECT_THAT(ErrorReading(path, "native"), HasSubstr(c.message));
}

INSTANTIATE_TEST_SUITE_P(
    Cases, NativeLogBad,
    ::testing::Values(
        BadCase{"wrong_count", "# cogmap-log 1\nrobot pioneer8\nODOM 0 0 0\n", ".log:3: ODOM: expected 5 fields"},
        BadCase{"not_number", "# cogmap-log 1\nrobot pioneer8\nODOM 0 0 abc 0\n", ":3: y: 'abc' is not a number"},
        BadCase{"nan", "# cogmap-log 1\nrobot pioneer8\nODOM 0 0 0 0\nSWEEP 0 1 0 nan\n",
                ":4: range: 'nan' is not a finite number"},
        BadCase{"negative", "# cogmap-log 1\nrobot pioneer8\nODOM 0 0 0 0\nSWEEP 0 1 0 -1\n",
                ":4: sensor 0: negative range"},
        BadCase{"absurd", "# cogmap-log 1\nrobot pioneer8\nODOM 0 0 0 0\nSWEEP 0 1 0 1e6\n",
                ":4: sensor 0: absurd range"},
        BadCase{"far_pose", "# cogmap-log 1\nrobot pioneer8\nODOM 0 1e300 0 0\n",
                ":3: ODOM: absurd position (1e+300, 0) m (more than 100000 km from the origin)"},
        BadCase{"sweep_count", "# cogmap-log 1\nrobot pioneer8\nODOM 0 0 0 0\nSWEEP 0 2 0 1\n",
                ":4: SWEEP: expected 7 fields for 2 readings, got 5"},
        BadCase{"sensor_index", "# cogmap-log 1\nrobot pioneer8\nODOM 0 0 0 0\nSWEEP 0 1 8 1\n",
                ":4: sensor index 8 but robot 'pioneer8' has 8 sensors"},
        BadCase{"keyword", "# cogmap-log 1\nrobot pioneer8\nPOSE 0 0 0 0\n", ":3: unknown record 'POSE'"},
        BadCase{"truth_first", "# cogmap-log 1\nrobot pioneer8\nTRUTH 0 0 0 0\n",
                ":3: TRUTH must follow an ODOM line"},
        BadCase{"sweep_first", "# cogmap-log 1\nrobot pioneer8\nSWEEP 0 1 0 1\n", ":3: SWEEP before any ODOM"},
        BadCase{"no_robot", "# cogmap-log 1\nODOM 0 0 0 0\n", ":2: expected a 'robot' or 'robot-json' line"},
        BadCase{"bad_robot", "# cogmap-log 1\nrobot r2d2\n", ":2: unknown robot 'r2d2'"},
        BadCase{"bad_json", "# cogmap-log 1\nrobot-json {\"name\": \"x\", \"wheels\": 3}\n",
                ":2: robot-json: unknown key 'wheels'"},
        // Hostile sizes and numbers (issue 14): refused before any allocation or overflow.
        BadCase{"huge_count", "# cogmap-log 1\nrobot pioneer8\nODOM 0 0 0 0\nSWEEP 0 9223372036854775807 0 1\n",
                ":4: SWEEP: reading count 9223372036854775807 is absurd (at most 100000)"},
        BadCase{"big_count", "# cogmap-log 1\nrobot pioneer8\nODOM 0 0 0 0\nSWEEP 0 4611686018427387904 0 1\n",
                ":4: SWEEP: reading count 4611686018427387904 is absurd"},
        BadCase{"json_overflow", "# cogmap-log 1\nrobot-json {\"name\": \"x\", \"radius\": 1e999}\n",
                "json_overflow.log:2: robot-json: invalid JSON: "},
        BadCase{"no_magic", "ODOM 0 0 0 0\n", ":1: not a native cogmap log"},
        BadCase{"empty", "# cogmap-log 1\nrobot pioneer8\n", "empty.log: empty log: no range readings"},
        BadCase{"odom_only", "# cogmap-log 1\nrobot pioneer8\nODOM 0 0 0 0\n",
                "odom_only.log: empty log: no range readings"},
        BadCase{"zero_bytes", "", "zero_bytes.log: empty log: no range readings"},
        // A log cut while it was written: its last numbers may parse ("2." for 2.3).
        BadCase{"cut_mid_line", "# cogmap-log 1\nrobot pioneer8\nODOM 0 0 0 0\nSWEEP 0 1 0 2.3\nSWEEP 0.1 1 0 2.",
                "cut_mid_line.log:5: the last line has no end of line: the log is truncated"}),
    [](const auto& info) { return std::string(info.param.name); });

TEST(NativeLog, GzipCutMidLineIsTruncated) {
  // The same check through zlib's reader: a whole gzip stream whose text ends
  // in the middle of a line.
  const std::string path = WriteTemp("cut.log.gz", GzipBytes("# cogmap-log 1\nrobot pioneer8\nODOM 0 0 0 0\nSWEEP 0 1 0 2."));
  EXPECT_THAT(ErrorReading(path, "native"), HasSubstr("cut.log.gz:4: the last line has no end of line"));
  const std::string whole = WriteTemp("whole.log.gz", GzipBytes("# cogmap-log 1\nrobot pioneer8\nODOM 0 0 0 0\nSWEEP 0 1 0 2.\n"));
  EXPECT_EQ(ReadAll(whole, "native").size(), 1u);
}

TEST(NativeLog, FixtureFileReads) {
  const auto rs = ReadAll(std::string(COGMAP_SOURCE_DIR) + "/tests/data/logs/tiny.log", "auto");
  ASSERT_EQ(rs.size(), 3u);
  EXPECT_EQ(rs[1].ranges.size(), 8u);
  ASSERT_TRUE(rs[2].truth);
  EXPECT_EQ(rs[2].truth->x, 0.52);
}

}  // namespace
}  // namespace cogmap::io
