#include "cogmap/io/ev3_log.h"

#include "cogmap/core/angles.h"
#include "cogmap/io/log_test_util.h"

namespace cogmap::io {
namespace {

using ::testing::HasSubstr;
using namespace testing_util;

// A line with pose (x_cm, y_cm, theta) and k samples per bearing, sample j of
// bearing b = value(b, j).
template <typename F>
std::string Line(double x, double y, double th, int k, F value) {
  std::string s = std::to_string(x) + " " + std::to_string(y) + " " + std::to_string(th);
  for (int b = 0; b < 13; ++b)
    for (int j = 0; j < k; ++j) s += " " + std::to_string(value(b, j));
  return s + "\n";
}

TEST(Ev3Log, OneRecordPerLineWithLineIndexAsTime) {
  const std::string text = Line(0, 0, 0, 1, [](int b, int) { return 10.0 + b; }) +
                           Line(150, -50, 0.5, 1, [](int b, int) { return 20.0 + b; });
  const auto rs = ReadAll(WriteTemp("a.ev3", text), "ev3");
  ASSERT_EQ(rs.size(), 2u);
  EXPECT_EQ(rs[1].time_s, 1.0);
  EXPECT_EQ(rs[1].odom.x, 1.5);
  EXPECT_EQ(rs[1].odom.y, -0.5);
  EXPECT_EQ(rs[1].odom.theta, 0.5);
  ASSERT_EQ(rs[1].ranges.size(), 13u);
  EXPECT_EQ(rs[1].ranges[12].sensor, 12);
  EXPECT_DOUBLE_EQ(rs[1].ranges[12].range_m, 0.32);
}

TEST(Ev3Log, RangeIsTheLowerMedianOfTheSamples) {
  // Bearing 0: samples 50, 40, 255, 30 -> sorted 30 40 50 255 -> lower median 40.
  const double s0[4] = {50, 40, 255, 30};
  const auto rs = ReadAll(WriteTemp("median.ev3", Line(0, 0, 0, 4, [&](int b, int j) {
                                      return b == 0 ? s0[j] : 100.0;
                                    })),
                          "ev3");
  EXPECT_DOUBLE_EQ(rs[0].ranges[0].range_m, 0.4);
  EXPECT_EQ(rs[0].ranges[1].range_m, 1.0);
}

TEST(Ev3Log, OddSampleCountTakesTheMiddle) {
  const double s0[5] = {255, 255, 255, 30, 31};
  const auto rs = ReadAll(WriteTemp("odd.ev3", Line(0, 0, 0, 5, [&](int b, int j) { return s0[j]; })), "ev3");
  EXPECT_EQ(rs[0].ranges[0].range_m, 2.55);
}

TEST(Ev3Log, NoEchoIsExactlyTheMaxRange) {
  auto r = OpenLog(WriteTemp("noecho.ev3", Line(0, 0, 0, 1, [](int, int) { return 255.0; })), "ev3");
  const auto rs = ReadAll(*r);
  EXPECT_EQ(rs[0].ranges[0].range_m, r->robot_hint()->sensors[0].max_range_m);
}

TEST(Ev3Log, CountsLinesWhoseSamplesDisagree) {
  const std::string text = Line(0, 0, 0, 2, [](int b, int j) { return b == 3 && j == 1 ? 80.0 : 50.0; }) +
                           Line(0, 0, 0, 2, [](int, int j) { return 50.0 + 5 * j; });
  auto r = OpenEv3Log(WriteTemp("disagree.ev3", text));
  ReadAll(*r);
  EXPECT_EQ(r->samples_per_bearing(), 2);
  EXPECT_EQ(r->disagreeing_lines(), 1);
}

TEST(Ev3Log, RobotHasThirteenBearingsAtTheCentre) {
  const auto robot = Ev3Robot();
  ASSERT_EQ(robot.sensors.size(), 13u);
  EXPECT_EQ(robot.name, "ev3");
  EXPECT_DOUBLE_EQ(robot.sensors[0].robot_from_sensor.theta, kPi / 2);
  EXPECT_DOUBLE_EQ(robot.sensors[6].robot_from_sensor.theta, 0.0);
  EXPECT_DOUBLE_EQ(robot.sensors[12].robot_from_sensor.theta, -kPi / 2);
  EXPECT_EQ(robot.sensors[5].robot_from_sensor.x, 0.0);
  EXPECT_DOUBLE_EQ(robot.sensors[0].beam_width_rad, DegToRad(25));
  EXPECT_EQ(robot.sensors[0].min_range_m, 0.03);
  EXPECT_EQ(robot.sensors[0].max_range_m, 2.55);
}

struct BadCase {
  const char* name;
  std::string body;
  const char* message;
};

class Ev3LogBad : public ::testing::TestWithParam<BadCase> {};

TEST_P(Ev3LogBad, NamesFileLineAndProblem) {
  const BadCase& c = GetParam();
  EXPECT_THAT(ErrorReading(WriteTemp(std::string(c.name) + ".ev3", c.body), "ev3"), HasSubstr(c.message));
}

std::string Ones(int k) { return Line(0, 0, 0, k, [](int, int) { return 1.0; }); }

INSTANTIATE_TEST_SUITE_P(
    Cases, Ev3LogBad,
    ::testing::Values(
        BadCase{"short", "0 0 0 1 2 3\n", ".ev3:1: expected x y theta and 13 bearings"},
        BadCase{"not_multiple", Ones(1) + "0 0 0 1 2 3 4 5 6 7 8 9 10 11 12 13 14\n", ".ev3:2: expected x y theta"},
        BadCase{"k_changes", Ones(2) + Ones(1), ".ev3:2: 1 samples per bearing, but the first line had 2"},
        BadCase{"not_number", "0 zero 0 1 1 1 1 1 1 1 1 1 1 1 1 1\n", ":1: y: 'zero' is not a number"},
        BadCase{"nan", "0 0 0 1 1 1 1 1 nan 1 1 1 1 1 1 1\n", ":1: bearing 5 sample 0: 'nan' is not a finite"},
        BadCase{"negative", "0 0 0 1 1 1 1 1 1 1 1 1 1 1 1 -1\n", ":1: bearing 12 sample 0: negative range"},
        BadCase{"absurd", "0 0 0 1e9 1 1 1 1 1 1 1 1 1 1 1 1\n", ":1: bearing 0 sample 0: absurd range"},
        BadCase{"empty", "\n\n", "empty.ev3: empty log: no range readings"}),
    [](const auto& info) { return std::string(info.param.name); });

const std::string kEv3Dir = std::string(COGMAP_SHARED_DIR) + "/data/ev3-sonar/";

TEST(Ev3LogRealData, Ev3_69FirstRecordsAreExact) {
  auto r = OpenEv3Log(kEv3Dir + "ev3-69.log");
  const auto rs = ReadAll(*r);
  ASSERT_EQ(rs.size(), 69u);
  EXPECT_EQ(r->samples_per_bearing(), 10);
  // Bearing 0 of line 1: 36.5 x 10 -> 0.365 m; bearing 1: 37.4 x 10.
  EXPECT_DOUBLE_EQ(rs[0].ranges[0].range_m, 0.365);
  EXPECT_DOUBLE_EQ(rs[0].ranges[1].range_m, 0.374);
  EXPECT_DOUBLE_EQ(rs[1].odom.x, 0.1759);
  // Line 2, bearing 0: 37 37 37 37 37 37 36.7 36.7 37 36.7 -> lower median 37.
  EXPECT_DOUBLE_EQ(rs[1].ranges[0].range_m, 0.37);
}

TEST(Ev3LogRealData, Ev3_154HasOneSamplePerBearing) {
  auto r = OpenLog(kEv3Dir + "ev3-154.log", "auto");
  const auto rs = ReadAll(*r);
  ASSERT_EQ(rs.size(), 154u);
  EXPECT_DOUBLE_EQ(rs[0].ranges[0].range_m, 0.448);
  EXPECT_DOUBLE_EQ(rs[0].ranges[12].range_m, 0.6478);
  EXPECT_DOUBLE_EQ(rs[1].odom.x, 0.1759);
  EXPECT_EQ(r->robot_hint()->name, "ev3");
}

}  // namespace
}  // namespace cogmap::io
