#include "cogmap/io/log_reader.h"

#include <filesystem>

#include "cogmap/core/error.h"
#include "cogmap/io/log_test_util.h"
#include "cogmap/io/log_tools.h"

namespace cogmap::io {
namespace {

using ::testing::ElementsAre;
using ::testing::HasSubstr;
using namespace testing_util;

TEST(OpenLog, FormatNames) {
  EXPECT_THAT(LogFormatNames(), ElementsAre("auto", "native", "carmen", "pioneer", "ev3", "rosbag", "ros2bag", "rawlog"));
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
  EXPECT_THAT(ErrorReading(WriteTemp("x.log", "x\n"), "rawbag"), HasSubstr("unknown log format 'rawbag'"));
}

TEST(OpenLog, TextFileGivenAsRosbagIsAnError) {
  EXPECT_THAT(ErrorReading(WriteTemp("x.log", "x\n"), "rosbag"), HasSubstr("x.log: not a complete ROS 1 bag"));
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
#include "cogmap/io/mrpt_rawlog.h"
#include "cogmap/io/native_log.h"
#include "cogmap/io/ros1_bag.h"
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

// Standard input and streams: "-" reads the stream once; the format is told
// from its buffered head and the reader gets the head again.
#include <sys/wait.h>
#include <unistd.h>

#include <fstream>
#include <functional>
#include <sstream>
#include <thread>

namespace cogmap::io {
namespace {

using namespace testing_util;


bool SameRecords(const std::vector<sensors::LogRecord>& a, const std::vector<sensors::LogRecord>& b) {
  if (a.size() != b.size()) return false;
  for (size_t i = 0; i < a.size(); ++i) {
    const auto &x = a[i], &y = b[i];
    if (x.time_s != y.time_s || x.odom.x != y.odom.x || x.odom.y != y.odom.y || x.odom.theta != y.odom.theta)
      return false;
    if (x.truth.has_value() != y.truth.has_value()) return false;
    if (x.truth && (x.truth->x != y.truth->x || x.truth->y != y.truth->y || x.truth->theta != y.truth->theta))
      return false;
    if (x.ranges.size() != y.ranges.size()) return false;
    for (size_t k = 0; k < x.ranges.size(); ++k)
      if (x.ranges[k].sensor != y.ranges[k].sensor || x.ranges[k].range_m != y.ranges[k].range_m) return false;
  }
  return true;
}

std::vector<std::string> Lines(LineSource& src) {
  std::vector<std::string> out;
  std::string line;
  while (src.Next(&line)) out.push_back(line);
  return out;
}

TEST(LineSourceStream, PlainAndGzipStreamsGiveTheFileLines) {
  const std::string text = "a b\r\nc\n\nlast without newline";
  LineSource file(WriteTemp("lines.txt", text));
  const auto want = Lines(file);
  ASSERT_EQ(want.size(), 4u);
  LineSource plain(std::make_unique<std::istringstream>(text), "plain");
  EXPECT_EQ(Lines(plain), want);
  LineSource gz(std::make_unique<std::istringstream>(GzipBytes(text)), "gz");
  EXPECT_EQ(Lines(gz), want);
  EXPECT_EQ(gz.progress(), 1.0);
}

TEST(LineSourceStream, ConcatenatedGzipMembersAreOneStream) {
  LineSource gz(std::make_unique<std::istringstream>(GzipBytes("one\ntwo\n") + GzipBytes("three\n")), "gz");
  EXPECT_EQ(Lines(gz), (std::vector<std::string>{"one", "two", "three"}));
}

TEST(LineSourceStream, TruncatedGzipStreamNamesTheLine) {
  std::string text;
  for (int i = 0; i < 5000; ++i) text += "ODOM " + std::to_string(i) + " 0 0 0 0 0 1 h 1\n";
  const std::string gz = GzipBytes(text);
  LineSource src(std::make_unique<std::istringstream>(gz.substr(0, gz.size() / 2)), "stdin");
  std::string line;
  try {
    while (src.Next(&line)) {
    }
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_THAT(e.what(), HasSubstr("stdin:" + std::to_string(src.line_number() + 1) +
                                    ": truncated or corrupt gzip data (unexpected end of file)"));
    EXPECT_GT(src.line_number(), 100);
  }
}

// Runs 'body' in a child process whose standard input is a pipe fed with
// 'bytes' (standard input is read once per process). True when the child
// exits with 0.
bool WithStdinPipe(const std::string& bytes, const std::function<bool()>& body) {
  const pid_t pid = fork();
  if (pid == 0) {
    int fds[2];
    if (pipe(fds) != 0) _exit(3);
    std::thread writer([&] {
      for (size_t done = 0; done < bytes.size();) {
        const ssize_t w = write(fds[1], bytes.data() + done, bytes.size() - done);
        if (w <= 0) break;
        done += static_cast<size_t>(w);
      }
      close(fds[1]);
    });
    dup2(fds[0], 0);
    close(fds[0]);
    bool ok = false;
    try {
      ok = body();
    } catch (const std::exception& e) {
      std::fprintf(stderr, "child: %s\n", e.what());
    }
    writer.join();
    _exit(ok ? 0 : 1);
  }
  int status = 0;
  waitpid(pid, &status, 0);
  return WIFEXITED(status) && WEXITSTATUS(status) == 0;
}

// The same records from the file and from a pipe, through OpenLog("-").
void ExpectPipeGivesFileRecords(const std::string& path, const std::string& bytes, const std::string& format) {
  const auto want = ReadAll(path, "auto");
  ASSERT_FALSE(want.empty());
  EXPECT_TRUE(WithStdinPipe(bytes, [&] {
    if (DetectLogFormat("-") != format) return false;
    return SameRecords(ReadAll("-", "auto"), want);
  })) << path;
}

TEST(StdinLog, NativeThroughAPipe) {
  const std::string path = std::string(COGMAP_SOURCE_DIR) + "/tests/data/logs/tiny.log";
  ExpectPipeGivesFileRecords(path, FileBytes(path), "native");
}

TEST(StdinLog, Ev3ThroughAPipe) {
  const std::string path = std::string(COGMAP_SHARED_DIR) + "/data/ev3-sonar/ev3-69.log";
  ExpectPipeGivesFileRecords(path, FileBytes(path), "ev3");
}

TEST(StdinLog, GzipCarmenThroughAPipe) {
  // The whole Intel log (about 1 MB compressed: far more than the buffered head).
  const std::string path = std::string(COGMAP_SHARED_DIR) + "/data/carmen/intel-corrected.log.gz";
  ExpectPipeGivesFileRecords(path, FileBytes(path), "carmen");
  EXPECT_TRUE(WithStdinPipe(FileBytes(path), [] {
    auto r = OpenLog("-", "auto");
    return r->robot_hint()->sensors[0].max_range_m == 81.83 && r->path() == "stdin";
  }));
}

TEST(StdinLog, LongNativeLogThroughAPipe) {
  std::string text = "# cogmap-log 1\nrobot pioneer8\n";
  for (int i = 0; i < 20000; ++i) text += "ODOM " + std::to_string(i) + " 0.5 0 0\nSWEEP 0 2 0 1.5 7 4.25\n";
  const std::string path = WriteTemp("long_pipe.log", text);
  ExpectPipeGivesFileRecords(path, text, "native");
  ExpectPipeGivesFileRecords(path, GzipBytes(text), "native");
}

TEST(StdinLog, ErrorsNameStdin) {
  EXPECT_TRUE(WithStdinPipe("ODOM 0 0 0 0 0 0 1 h 1\nODOM 1 2\n", [] {
    try {
      ReadAll("-", "auto");
    } catch (const InputError& e) {
      return std::string(e.what()) == "stdin:2: ODOM: expected 10 fields (ODOM x y theta tv rv accel timestamp "
                                      "host logger_timestamp), got 3";
    }
    return false;
  }));
  EXPECT_TRUE(WithStdinPipe("", [] {
    try {
      ReadAll("-", "auto");
    } catch (const InputError& e) {
      return std::string(e.what()) == "stdin: empty log: no range readings";
    }
    return false;
  }));
  EXPECT_TRUE(WithStdinPipe("0 0 0 1 2 3 4 5 6 7 8 9 10 11 12 13\n", [] {
    try {
      OpenLog("-", "pioneer");
    } catch (const InputError& e) {
      return std::string(e.what()).find("stdin: a pioneer log is two files") == 0;
    }
    return false;
  }));
}

// Bags and rawlogs need a file (rosbag seeks): standard input is copied to one,
// and the records are those of the file.
std::string BinaryLogFrom(const std::string& native, const std::string& to) {
  auto reader = OpenLog(native, "native");
  const auto robot = *reader->robot_hint();
  const std::string out = ::cogmap::testing_util::TestTempPath("pipe_binary." + to);
  auto next = [&](sensors::LogRecord* r) { return reader->Next(r); };
  if (to == "bag")
    WriteRosAriaBag(out, robot, next);
  else
    WriteMrptRawlog(out, robot, next);
  return out;
}

TEST(StdinLog, RosBagAndRawlogThroughAPipe) {
  const std::string native = std::string(COGMAP_SOURCE_DIR) + "/tests/data/logs/tiny.log";
  const std::string bag = BinaryLogFrom(native, "bag");
  ExpectPipeGivesFileRecords(bag, FileBytes(bag), "rosbag");
  const std::string rawlog = BinaryLogFrom(native, "rawlog");
  ExpectPipeGivesFileRecords(rawlog, FileBytes(rawlog), "rawlog");  // MRPT writes it gzipped
  // What the reader says names stdin, never the copy; the copy is removed.
  EXPECT_TRUE(WithStdinPipe(FileBytes(bag), [] {
    std::string copy;
    {
      auto r = OpenLog("-", "auto");
      if (r->path() != "stdin") return false;
      for (const auto& e : std::filesystem::directory_iterator(std::filesystem::temp_directory_path()))
        if (e.path().filename().string().rfind("cogmap-stdin-", 0) == 0) copy = e.path().string();
    }
    return !copy.empty() && !std::filesystem::exists(copy);
  }));
  const std::string cut = FileBytes(bag).substr(0, FileBytes(bag).size() / 2);
  EXPECT_TRUE(WithStdinPipe(cut, [] {
    try {
      ReadAll("-", "auto");
    } catch (const InputError& e) {
      const std::string m = e.what();
      return m.rfind("stdin", 0) == 0 && m.find("cogmap-stdin-") == std::string::npos;
    }
    return false;
  }));
}

TEST(StdinLog, StandardInputIsReadOnce) {
  EXPECT_TRUE(WithStdinPipe("0 0 0 1 2 3 4 5 6 7 8 9 10 11 12 13\n", [] {
    auto r = OpenLog("-", "auto");
    try {
      OpenLog("-", "auto");
    } catch (const InputError& e) {
      return std::string(e.what()) == "stdin: standard input was already read (give '-' once)";
    }
    return false;
  }));
}

// --resume knows the log a store was mapped from by its fingerprint: the
// same bytes, or the same log grown since; not another log, nor standard
// input (read once, no identity).
TEST(ConvertLog, AsSonarTakesALaserLogAndASonarRing) {
  auto error = [](const std::string& path, const std::string& robot) {
    LogToolOptions o;
    o.as_sonar = robot;
    try {
      ConvertLog(path, o, "native", ::cogmap::testing_util::TestTempPath("as_sonar_out.log"));
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  const std::string laser = WriteTemp("laser.clf", "FLASER 3 1.5 2.5 81.9 1.1 2.2 0.3 1 2 0.25 2.5 host 2.5\n");
  const std::string sonar = WriteTemp("sonar.log", "# cogmap-log 1\nrobot pioneer8\nODOM 0 0 0 0\nSWEEP 0 1 0 1.5\n");
  // A laser's beams written as "sonar" readings: no conversion.
  EXPECT_EQ(error(laser, "laser"), "--as-sonar laser: robot 'laser' is not a sonar ring (181 of its 181 sensors are laser beams)");
  // A sonar log has no laser returns to take the nearest of.
  EXPECT_THAT(error(sonar, "pioneer16"), HasSubstr(sonar + ": --as-sonar turns a laser's readings into sonar readings"));
  EXPECT_FALSE(std::filesystem::exists(::cogmap::testing_util::TestTempPath("as_sonar_out.log")));  // nothing written
  EXPECT_EQ(error(laser, "pioneer16"), "");
  EXPECT_TRUE(std::filesystem::exists(::cogmap::testing_util::TestTempPath("as_sonar_out.log")));
}

// --ring-timing scans: the ring fires where the laser scanned: three scans
// over 2 m of odometry, with two odometry records between them.
TEST(ConvertLog, AsSonarSaysHowOftenTheRingFires) {
  const std::string laser = WriteTemp("laser_sparse.clf",
                                      "FLASER 3 1.5 2.5 1.9 0 0 0 0 0 0 1.0 host 1.0\n"
                                      "ODOM 0.5 0 0 0.5 0 0 2.0 host 2.0\n"
                                      "FLASER 3 1.5 2.5 1.9 1 0 0 1 0 0 3.0 host 3.0\n"
                                      "ODOM 1.5 0 0 0.5 0 0 4.0 host 4.0\n"
                                      "FLASER 3 1.5 2.5 1.9 2 0 0 2 0 0 5.0 host 5.0\n");
  LogToolOptions o;
  o.as_sonar = "pioneer16";
  o.ring_timing = "scans";
  const ConvertSummary s = ConvertLog(laser, o, "native", ::cogmap::testing_util::TestTempPath("as_sonar_sparse.log"));
  EXPECT_THAT(s.text, HasSubstr("the ring fires at 3 of 5 records (the laser's scans): once every 0.67 m of the 2 m driven"))
      << s.text;
  o.ring_timing = "sometimes";
  EXPECT_THROW(ConvertLog(laser, o, "native", ::cogmap::testing_util::TestTempPath("as_sonar_sparse_bad.log")), InputError);
  EXPECT_FALSE(std::filesystem::exists(::cogmap::testing_util::TestTempPath("as_sonar_sparse_bad.log")));
}

// --ring-timing pioneer (the default): one sonar per bank every 40 ms by
// the log's clock, at most one sweep of each bank per record, odometry
// records between scans included (their readings from the scans before and
// after them). A laser scan every 0.5 s, odometry every 0.1 s: each record
// fires 2 or 3 transducers of each of pioneer16's two banks, of which the
// front bank's (0-7) are in the forward laser's view.
TEST(ConvertLog, AsSonarFiresTheRingAsAPioneerDoes) {
  std::string text;
  for (int k = 0; k <= 20; ++k) {
    const double t = 0.1 * k, x = 0.05 * k;
    char line[200];
    if (k % 5 == 0)  // a wall 3 m ahead of the start, 181 beams over 180 degrees
    {
      std::string ranges;
      for (int b = 0; b < 181; ++b) {
        const double c = std::cos((b - 90) * 3.14159265358979323846 / 180.0);
        const double r = c > 1e-9 ? std::min((3.0 - x) / c, 8.1) : 8.1;
        char v[32];
        std::snprintf(v, sizeof v, " %.4f", r);
        ranges += v;
      }
      std::snprintf(line, sizeof line, " %.3f 0 0 %.3f 0 0 %.2f host %.2f\n", x, x, t, t);
      text += "FLASER 181" + ranges + line;
    } else {
      std::snprintf(line, sizeof line, "ODOM %.3f 0 0 0.5 0 0 %.2f host %.2f\n", x, t, t);
      text += line;
    }
  }
  const std::string laser = WriteTemp("laser_ring.clf", text);
  LogToolOptions o;
  o.as_sonar = "pioneer16";
  const std::string out = ::cogmap::testing_util::TestTempPath("as_sonar_ring.log");
  const ConvertSummary s = ConvertLog(laser, o, "native", out);
  EXPECT_THAT(s.text, HasSubstr("the ring fires as a Pioneer's (one sonar per bank every 40 ms)")) << s.text;
  auto reader = OpenLog(out);
  sensors::LogRecord r;
  int records = 0, with = 0, odometry_with = 0;
  long readings = 0;
  while (reader->Next(&r)) {
    ++records;
    with += r.ranges.empty() ? 0 : 1;
    odometry_with += (!r.ranges.empty() && records % 5 != 1) ? 1 : 0;
    readings += static_cast<long>(r.ranges.size());
    for (const auto& q : r.ranges) {
      // The rear bank looks where the laser does not, but for its side
      // sonars (8 and 15, +-90 degrees behind the laser), whose axes an
      // earlier scan taken farther back did see.
      EXPECT_TRUE((q.sensor >= 0 && q.sensor <= 8) || q.sensor == 15) << q.sensor;
      // The front sonars (3 and 4, +-10 degrees) see the wall 3 m from the
      // start, less the distance driven and their mounts.
      if (q.sensor == 3 || q.sensor == 4) {
        EXPECT_GT(q.range_m, 3.0 - 0.05 * (records - 1) - 0.25);
        EXPECT_LT(q.range_m, 3.0 - 0.05 * (records - 1));
      }
    }
  }
  EXPECT_EQ(records, 21);
  EXPECT_GE(odometry_with, 12);  // the odometry records between scans fire too
  // 2 s of clock: 50 slots of each bank, the first record firing none: the
  // front bank's 50 (in view) and at most a quarter of the rear bank's.
  EXPECT_GE(readings, 45);
  EXPECT_LE(readings, 63);
  // A clock that never advances (stamps of six digits, as belgioioso's):
  // the ring fires by the distance driven at 0.5 m/s, 1 m in 2 s, about as
  // often as by the clock above.
  std::string frozen;
  for (size_t at = 0, end; at < text.size(); at = end + 1) {
    end = text.find('\n', at);
    std::string line = text.substr(at, end - at);
    std::string::size_type cut = line.rfind(" host ");
    const std::string::size_type stamp = line.rfind(' ', cut - 1);
    line = line.substr(0, stamp) + " 1.01893e+09 host 1.01893e+09";
    frozen += line + "\n";
  }
  const ConvertSummary f = ConvertLog(WriteTemp("laser_ring_frozen.clf", frozen), o, "native", out);
  EXPECT_THAT(f.text, HasSubstr("the log's clock did not advance over 20 of 21 records where the robot moved")) << f.text;
  auto again = OpenLog(out);
  long frozen_readings = 0;
  while (again->Next(&r)) frozen_readings += static_cast<long>(r.ranges.size());
  EXPECT_GE(frozen_readings, 45);
  EXPECT_LE(frozen_readings, 63);
}

TEST(LogFingerprint, TheSameLogOrItGrownSinceButNoOther) {
  const std::string text = "# cogmap-log 1\nrobot pioneer8\nODOM 0 0 0 0\nSWEEP 0 1 0 1\n";
  const std::string path = WriteTemp("fingerprint.log", text);
  const std::string fp = LogFingerprint(path);
  EXPECT_THAT(fp, ::testing::StartsWith("crc32 "));
  EXPECT_THAT(fp, ::testing::EndsWith(" " + std::to_string(text.size())));
  EXPECT_TRUE(IsLogOf(path, fp));
  EXPECT_TRUE(IsLogOf(WriteTemp("fingerprint_grown.log", text + "ODOM 1 0.1 0 0\n"), fp));
  std::string changed = text;
  changed[20] = 'X';
  EXPECT_FALSE(IsLogOf(WriteTemp("fingerprint_changed.log", changed), fp));
  EXPECT_FALSE(IsLogOf(WriteTemp("fingerprint_short.log", text.substr(0, 10)), fp));
  EXPECT_EQ(LogFingerprint("-"), "");
  EXPECT_FALSE(IsLogOf("-", fp));
  EXPECT_FALSE(IsLogOf(path, ""));
  EXPECT_FALSE(IsLogOf(path, "crc32 00000000 999999999999"));
  EXPECT_EQ(LogFingerprint(path + ".missing"), "");
  // What a store may hold: a fingerprint as made, or none (standard input).
  EXPECT_TRUE(IsFingerprint(fp));
  EXPECT_TRUE(IsFingerprint(""));
  EXPECT_FALSE(IsFingerprint("crc32 zz 12"));
  EXPECT_FALSE(IsFingerprint("crc32 0123abcd 99999999999"));
  EXPECT_FALSE(IsFingerprint(fp + " more"));
  // A folder (a ROS 2 bag): its files' names, sizes and first bytes.
  const std::filesystem::path dir = std::filesystem::path(path).parent_path() / "fingerprint_bag";
  std::filesystem::create_directories(dir);
  WriteTemp("fingerprint_bag/metadata.yaml", "rosbag2_bagfile_information: {}\n");
  const std::string folder = LogFingerprint(dir.string());
  EXPECT_THAT(folder, ::testing::StartsWith("folder-crc32 "));
  EXPECT_TRUE(IsLogOf(dir.string(), folder));
  EXPECT_TRUE(IsFingerprint(folder));
  WriteTemp("fingerprint_bag/metadata.yaml", "rosbag2_bagfile_information: {x}\n");
  EXPECT_FALSE(IsLogOf(dir.string(), folder));
}

}  // namespace
}  // namespace cogmap::io
