#include "cogmap/io/log_reader.h"

#include <filesystem>

#include "cogmap/io/log_test_util.h"

namespace cogmap::io {
namespace {

using ::testing::ElementsAre;
using ::testing::HasSubstr;
using namespace testing_util;

TEST(OpenLog, FormatNames) {
  EXPECT_THAT(LogFormatNames(), ElementsAre("auto", "native", "carmen", "pioneer", "ev3"));
}

TEST(OpenLog, SniffsNative) {
  auto r = OpenLog(WriteTemp("sniff.log", "# cogmap-log 1\nrobot pioneer8\nODOM 0 0 0 0\nSWEEP 0 1 0 1\n"));
  EXPECT_EQ(r->robot_hint()->name, "pioneer8");
}

TEST(OpenLog, SniffsCarmenAfterComments) {
  auto r = OpenLog(WriteTemp("sniff.clf", "# CARMEN Logfile\n# comment\nPARAM a b h 0\nFLASER 1 2 0 0 0 0 0 0 1 h 1\n"));
  EXPECT_EQ(r->robot_hint()->name, "carmen-laser");
}

TEST(OpenLog, SniffsEv3) {
  auto r = OpenLog(WriteTemp("sniff_ev3.txt", "0 0 0 1 2 3 4 5 6 7 8 9 10 11 12 13\n"));
  EXPECT_EQ(r->robot_hint()->name, "ev3");
}

TEST(OpenLog, ExplicitFormatOverridesContent) {
  const std::string path = WriteTemp("forced.log", "0 0 0 1 2 3 4 5 6 7 8 9 10 11 12 13\n");
  EXPECT_THAT(ErrorReading(path, "native"), HasSubstr("forced.log:1: not a native cogmap log"));
}

TEST(OpenLog, UnknownContentAsksForFormat) {
  EXPECT_THAT(ErrorReading(WriteTemp("what.txt", "hello world\n"), "auto"),
              HasSubstr("what.txt:1: cannot tell the log format"));
}

TEST(OpenLog, UnknownFormatName) {
  EXPECT_THAT(ErrorReading(WriteTemp("x.log", "x\n"), "rosbag"), HasSubstr("unknown log format 'rosbag'"));
}

TEST(OpenLog, MissingFile) {
  EXPECT_THAT(ErrorReading(::cogmap::testing_util::TestTempPath("nope.log"), "auto"), HasSubstr("nope.log: cannot open"));
}

TEST(OpenLog, EmptyFile) {
  EXPECT_THAT(ErrorReading(WriteTemp("zero.log", ""), "auto"), HasSubstr("zero.log: empty log: no range readings"));
}

TEST(OpenLog, ProgressGoesFromZeroToOne) {
  std::string text = "# cogmap-log 1\nrobot pioneer8\n";
  for (int i = 0; i < 20000; ++i) text += "ODOM " + std::to_string(i) + " 0 0 0\nSWEEP 0 1 0 1\n";
  auto r = OpenLog(WriteTemp("progress.log", text));
  EXPECT_LT(r->progress(), 0.5);
  sensors::LogRecord rec;
  while (r->Next(&rec)) {
  }
  EXPECT_EQ(r->progress(), 1.0);
}

TEST(OpenLog, FixtureFilesSniff) {
  const std::string dir = std::string(COGMAP_SOURCE_DIR) + "/tests/data/logs/";
  EXPECT_EQ(ReadAll(dir + "tiny.clf", "auto").size(), 3u);
  EXPECT_EQ(ReadAll(dir + "tiny.ev3", "auto").size(), 2u);
  EXPECT_EQ(ReadAll(dir + "pioneer-pair", "auto").size(), 3u);
}

}  // namespace
}  // namespace cogmap::io

#include "cogmap/io/log_lines.h"
#include "cogmap/io/ev3_log.h"
#include "cogmap/io/native_log.h"
#include "cogmap/core/test_temp.h"

namespace cogmap::io {
namespace {

// The documented constants of docs/log-format.md.
TEST(LogConstants, MatchTheDocumentation) {
  EXPECT_EQ(kAbsurdRangeM, 1000.0);
  EXPECT_EQ(kNativeLogVersion, 1);
  EXPECT_EQ(kEv3DisagreeCm, 10.0);
  EXPECT_EQ(kEv3Bearings, 13);
}

}  // namespace
}  // namespace cogmap::io
