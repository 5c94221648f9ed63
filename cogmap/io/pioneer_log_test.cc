#include "cogmap/io/pioneer_log.h"

#include <filesystem>

#include "cogmap/core/angles.h"
#include "cogmap/io/log_test_util.h"
#include "cogmap/core/test_temp.h"

namespace cogmap::io {
namespace {

using ::testing::HasSubstr;
using namespace testing_util;

// A pioneer pair in its own folder under the test temp dir.
std::string MakePair(const std::string& name, const std::string& meas, const std::string& poses) {
  const std::string dir = ::cogmap::testing_util::TestTempPath(name);
  std::filesystem::create_directories(dir);
  WriteTemp(name + "/measurement.txt", meas);
  WriteTemp(name + "/poses.txt", poses);
  return dir;
}

const char* kMeas = "1000 5110 5110 2320 2360 5110 5110 2160 1190\n2500 100 200 300 400 500 600 700 800\n";
const char* kPoses = "1000 0 0 0\n2500 1500 -250 900\n";

TEST(PioneerLog, ConvertsMillimetresTenthsOfDegreesAndMilliseconds) {
  const auto rs = ReadAll(MakePair("pair_ok", kMeas, kPoses), "pioneer");
  ASSERT_EQ(rs.size(), 2u);
  EXPECT_EQ(rs[1].time_s, 2.5);
  EXPECT_EQ(rs[1].odom.x, 1.5);
  EXPECT_EQ(rs[1].odom.y, -0.25);
  EXPECT_DOUBLE_EQ(rs[1].odom.theta, kPi / 2);
  EXPECT_FALSE(rs[1].truth);
  ASSERT_EQ(rs[1].ranges.size(), 8u);
  EXPECT_DOUBLE_EQ(rs[1].ranges[0].range_m, 0.1);
  EXPECT_EQ(rs[1].ranges[7].sensor, 7);
  EXPECT_DOUBLE_EQ(rs[1].ranges[7].range_m, 0.8);
}

TEST(PioneerLog, NoEchoIsAtOrAboveMaxRange) {
  auto r = OpenLog(MakePair("pair_noecho", kMeas, kPoses), "pioneer");
  const auto rs = ReadAll(*r);
  EXPECT_EQ(rs[0].ranges[0].range_m, 5.11);
  EXPECT_GE(rs[0].ranges[0].range_m, r->robot_hint()->sensors[0].max_range_m);
  EXPECT_EQ(r->robot_hint()->name, "pioneer8-course");
}

TEST(PioneerLog, AcceptsFolderOrEitherFile) {
  const std::string dir = MakePair("pair_paths", kMeas, kPoses);
  EXPECT_EQ(ReadAll(dir, "auto").size(), 2u);
  EXPECT_EQ(ReadAll(dir + "/measurement.txt", "auto").size(), 2u);
  EXPECT_EQ(ReadAll(dir + "/poses.txt", "pioneer").size(), 2u);
}

TEST(PioneerLog, MissingPartnerFileIsAnError) {
  const std::string dir = ::cogmap::testing_util::TestTempPath("pair_alone");
  std::filesystem::create_directories(dir);
  WriteTemp("pair_alone/measurement.txt", kMeas);
  EXPECT_THAT(ErrorReading(dir + "/measurement.txt", "pioneer"), HasSubstr("poses.txt: missing"));
}

TEST(PioneerLog, TimestampMismatchNamesBothFiles) {
  const std::string dir = MakePair("pair_ts", kMeas, "1000 0 0 0\n2600 0 0 0\n");
  const std::string e = ErrorReading(dir, "pioneer");
  EXPECT_THAT(e, HasSubstr("measurement.txt:2: timestamp 2500 but "));
  EXPECT_THAT(e, HasSubstr("poses.txt:2 has 2600"));
}

TEST(PioneerLog, CountMismatchNamesBothFiles) {
  const std::string dir = MakePair("pair_count", kMeas, "1000 0 0 0\n");
  const std::string e = ErrorReading(dir, "pioneer");
  EXPECT_THAT(e, HasSubstr("measurement.txt:2: has more lines than "));
  EXPECT_THAT(e, HasSubstr("poses.txt (1 lines)"));
}

struct BadCase {
  const char* name;
  const char* meas;
  const char* poses;
  const char* message;
};

class PioneerLogBad : public ::testing::TestWithParam<BadCase> {};

TEST_P(PioneerLogBad, NamesFileLineAndProblem) {
  const BadCase& c = GetParam();
  EXPECT_THAT(ErrorReading(MakePair(std::string("bad_") + c.name, c.meas, c.poses), "pioneer"),
              HasSubstr(c.message));
}

INSTANTIATE_TEST_SUITE_P(
    Cases, PioneerLogBad,
    ::testing::Values(
        BadCase{"meas_count", "1 1 2 3 4 5 6 7\n", "1 0 0 0\n", "measurement.txt:1: expected 9 fields"},
        BadCase{"pose_count", "1 1 2 3 4 5 6 7 8\n", "1 0 0\n", "poses.txt:1: expected 4 fields"},
        BadCase{"not_number", "1 1 2 3 4 5 6 7 eight\n", "1 0 0 0\n", "measurement.txt:1: r7: 'eight' is not"},
        BadCase{"nan", "1 1 2 3 4 nan 6 7 8\n", "1 0 0 0\n", "measurement.txt:1: r4: 'nan' is not a finite"},
        BadCase{"negative", "1 1 2 -3 4 5 6 7 8\n", "1 0 0 0\n", "measurement.txt:1: r2: negative range"},
        BadCase{"absurd", "1 1 2 3 4 5 6 7 9e9\n", "1 0 0 0\n", "measurement.txt:1: r7: absurd range"},
        BadCase{"pose_nan", "1 1 2 3 4 5 6 7 8\n", "1 0 NaN 0\n", "poses.txt:1: y_mm: 'NaN' is not"},
        BadCase{"empty", "", "", "empty log: no range readings"}),
    [](const auto& info) { return std::string(info.param.name); });

const std::string kRobond = std::string(COGMAP_SHARED_DIR) + "/data/pioneer-sonar-robond";

TEST(PioneerLogRealData, FirstAndLastRecordsAreExact) {
  const auto rs = ReadAll(kRobond, "auto");
  ASSERT_EQ(rs.size(), 413u);  // 413 lines: the last has no newline
  EXPECT_EQ(rs[0].time_s, 1686.487);
  EXPECT_EQ(rs[0].ranges[2].range_m, 2.32);
  EXPECT_EQ(rs[0].ranges[7].range_m, 1.19);
  EXPECT_EQ(rs[0].odom.x, 0.0);
  EXPECT_EQ(rs.back().time_s, 1779.324);
  EXPECT_EQ(rs.back().odom.x, 16.842);
  EXPECT_EQ(rs.back().odom.y, -9.437);
  EXPECT_DOUBLE_EQ(rs.back().odom.theta, DegToRad(263.1));
  EXPECT_EQ(rs.back().ranges[1].range_m, 1.04);
}

}  // namespace
}  // namespace cogmap::io
