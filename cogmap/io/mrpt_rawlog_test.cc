// MRPT rawlogs written here with MRPT itself, read back through OpenLog.
#include "cogmap/io/mrpt_rawlog.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <mrpt/core/Clock.h>
#include <mrpt/io/CFileGZOutputStream.h>
#include <mrpt/io/CFileOutputStream.h>
#include <mrpt/obs/CActionCollection.h>
#include <mrpt/obs/CActionRobotMovement2D.h>
#include <mrpt/obs/CObservation2DRangeScan.h>
#include <mrpt/obs/CObservationOdometry.h>
#include <mrpt/obs/CObservationRange.h>
#include <mrpt/obs/CSensoryFrame.h>
#include <mrpt/serialization/CArchive.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "cogmap/core/angles.h"
#include "cogmap/io/log_test_util.h"
#include "cogmap/io/world_io.h"
#include "cogmap/sensors/robot.h"
#include "cogmap/sim/simulator.h"

namespace cogmap::io {
namespace {

using namespace testing_util;
using ::testing::HasSubstr;
namespace fs = std::filesystem;

mrpt::obs::CObservationOdometry::Ptr Odometry(double t, const Pose2& p) {
  auto o = mrpt::obs::CObservationOdometry::Create();
  o->timestamp = mrpt::Clock::fromDouble(t);
  o->sensorLabel = "ODOMETRY";
  o->odometry = mrpt::poses::CPose2D(p.x, p.y, p.theta);
  return o;
}

mrpt::obs::CObservationRange::Ptr Sonar(double t, const sensors::RobotDescription& robot,
                                        const std::vector<sensors::RangeReading>& ranges) {
  auto o = mrpt::obs::CObservationRange::Create();
  o->timestamp = mrpt::Clock::fromDouble(t);
  o->sensorLabel = "SONAR";
  o->minSensorDistance = static_cast<float>(robot.sensors[0].min_range_m);
  o->maxSensorDistance = static_cast<float>(robot.sensors[0].max_range_m);
  o->sensorConeApperture = static_cast<float>(robot.sensors[0].beam_width_rad);
  for (const auto& q : ranges) {
    mrpt::obs::CObservationRange::TMeasurement m;
    const Pose2& p = robot.sensors[q.sensor].robot_from_sensor;
    m.sensorID = static_cast<uint16_t>(q.sensor);
    m.sensorPose = mrpt::math::TPose3D(p.x, p.y, 0.0, p.theta, 0.0, 0.0);
    m.sensedDistance = static_cast<float>(q.range_m);
    o->sensedData.push_back(m);
  }
  return o;
}

std::vector<sensors::LogRecord> SimulatedRun(double seconds) {
  const FloorPlan plan = ReadAriaMap(std::string(COGMAP_SHARED_DIR) + "/worlds/nine_rooms.map").plan;
  sim::SimulatorOptions o;
  o.seed = 7;
  o.max_time_s = seconds;
  std::vector<sensors::LogRecord> run;
  sim::Simulate(plan, sensors::BuiltinRobot("pioneer16"), o, [&](const sensors::LogRecord& r) { run.push_back(r); });
  return run;
}

// An observations-only rawlog of a run: per record a CObservationOdometry and,
// when it has readings, a CObservationRange.
std::string WriteObservationsRawlog(const std::string& name, const std::vector<sensors::LogRecord>& run, bool gz) {
  const auto robot = sensors::BuiltinRobot("pioneer16");
  const std::string path = ::cogmap::testing_util::TestTempPath(name);
  auto write = [&](mrpt::io::CStream& f) {
    auto arch = mrpt::serialization::archiveFrom(f);
    for (const auto& r : run) {
      arch << *Odometry(r.time_s, r.odom);
      if (!r.ranges.empty()) arch << *Sonar(r.time_s, robot, r.ranges);
    }
  };
  if (gz) {
    mrpt::io::CFileGZOutputStream f(path);
    write(f);
  } else {
    mrpt::io::CFileOutputStream f(path);
    write(f);
  }
  return path;
}

TEST(MrptRawlog, ObservationsOnlyRunReadsBack) {
  const auto run = SimulatedRun(15.0);
  const std::string path = WriteObservationsRawlog("run.rawlog", run, true);
  EXPECT_EQ(DetectLogFormat(path), "rawlog");
  auto reader = OpenLog(path);
  EXPECT_EQ(reader->robot_hint()->name, "pioneer16");  // the sonars' poses, cones and ranges
  const auto back = ReadAll(*reader);
  size_t k = 0;
  for (const auto& r : run) {
    // The odometry record, then the readings at that pose.
    ASSERT_LT(k, back.size());
    EXPECT_NEAR(back[k].time_s, r.time_s, 1e-6);
    EXPECT_EQ(back[k].odom.x, r.odom.x);
    EXPECT_NEAR(back[k].odom.theta, r.odom.theta, 1e-15);
    EXPECT_TRUE(back[k].ranges.empty());
    ++k;
    if (r.ranges.empty()) continue;
    ASSERT_LT(k, back.size());
    EXPECT_EQ(back[k].odom.y, r.odom.y);
    ASSERT_EQ(back[k].ranges.size(), r.ranges.size());
    for (size_t i = 0; i < r.ranges.size(); ++i) {
      EXPECT_EQ(back[k].ranges[i].sensor, r.ranges[i].sensor);
      EXPECT_NEAR(back[k].ranges[i].range_m, r.ranges[i].range_m, 2e-6);
    }
    ++k;
  }
  EXPECT_EQ(k, back.size());
  bool range_used = false;
  for (const auto& c : reader->contents()) range_used |= c.name == "CObservationRange" && !c.use.empty();
  EXPECT_TRUE(range_used);
}

// Actions-observations: movement (1, 0, 0) then a sweep of a 3-beam laser 0.1 m
// ahead; then a quarter turn and another sweep.
TEST(MrptRawlog, ActionsObservationsComposeOdometryIncrements) {
  const std::string path = ::cogmap::testing_util::TestTempPath("ao.rawlog");
  {
    mrpt::io::CFileGZOutputStream f(path);
    auto arch = mrpt::serialization::archiveFrom(f);
    const mrpt::poses::CPose2D steps[2] = {{1.0, 0.0, 0.0}, {0.0, 0.0, kPi / 2}};
    for (int k = 0; k < 2; ++k) {
      mrpt::obs::CActionCollection acts;
      mrpt::obs::CActionRobotMovement2D move;
      move.timestamp = mrpt::Clock::fromDouble(10.0 + k);
      move.computeFromOdometry(steps[k], mrpt::obs::CActionRobotMovement2D::TMotionModelOptions());
      acts.insert(move);
      arch << acts;
      mrpt::obs::CSensoryFrame sf;
      auto scan = mrpt::obs::CObservation2DRangeScan::Create();
      scan->timestamp = mrpt::Clock::fromDouble(10.5 + k);
      scan->sensorLabel = "LASER";
      scan->aperture = static_cast<float>(kPi / 2);
      scan->rightToLeft = true;
      scan->maxRange = 4.0f;
      scan->sensorPose = mrpt::poses::CPose3D(0.1, 0.0, 0.0, 0.0, 0.0, 0.0);
      scan->resizeScan(3);
      const float ranges[3] = {1.0f, 2.0f, 3.0f};
      for (int i = 0; i < 3; ++i) {
        scan->setScanRange(i, ranges[i]);
        scan->setScanRangeValidity(i, i != 2);  // the third: no return
      }
      sf.insert(scan);
      arch << sf;
    }
  }
  auto reader = OpenLog(path);
  const auto robot = *reader->robot_hint();
  EXPECT_EQ(robot.name, "mrpt-laser");
  ASSERT_EQ(robot.sensors.size(), 3u);
  EXPECT_DOUBLE_EQ(robot.sensors[0].robot_from_sensor.x, 0.1);
  EXPECT_NEAR(robot.sensors[0].robot_from_sensor.theta, -kPi / 4, 1e-6);
  EXPECT_NEAR(robot.sensors[2].robot_from_sensor.theta, kPi / 4, 1e-6);
  EXPECT_EQ(robot.sensors[1].max_range_m, 4.0);
  const auto back = ReadAll(*reader);
  ASSERT_EQ(back.size(), 4u);
  EXPECT_NEAR(back[0].time_s, 10.0, 1e-6);
  EXPECT_DOUBLE_EQ(back[0].odom.x, 1.0);
  EXPECT_TRUE(back[0].ranges.empty());
  EXPECT_NEAR(back[1].time_s, 10.5, 1e-6);
  EXPECT_DOUBLE_EQ(back[1].odom.x, 1.0);
  ASSERT_EQ(back[1].ranges.size(), 3u);
  EXPECT_EQ(back[1].ranges[0].range_m, 1.0);
  EXPECT_EQ(back[1].ranges[1].range_m, 2.0);
  EXPECT_EQ(back[1].ranges[2].range_m, 4.0);  // invalid: no echo
  EXPECT_DOUBLE_EQ(back[2].odom.x, 1.0);
  EXPECT_DOUBLE_EQ(back[2].odom.theta, kPi / 2);
  EXPECT_DOUBLE_EQ(back[3].odom.theta, kPi / 2);
}

TEST(MrptRawlog, TruncatedRawlogIsOneErrorNamingTheEntry) {
  const auto run = SimulatedRun(3.0);
  const std::string path = WriteObservationsRawlog("cut.rawlog", run, false);
  fs::resize_file(path, fs::file_size(path) - 7);
  EXPECT_THAT(ErrorReading(path, "auto"), HasSubstr(path + ": entry "));
  EXPECT_THAT(ErrorReading(path, "auto"), HasSubstr("truncated"));
}

TEST(MrptRawlog, AbsurdOdometryIsAnErrorNamingTheEntry) {
  // A pose of 1e300 m failed later, in the grid, without naming the rawlog.
  auto run = SimulatedRun(3.0);
  run[2].odom.x = 1e300;
  const std::string path = WriteObservationsRawlog("far.rawlog", run, false);
  EXPECT_THAT(ErrorReading(path, "auto"), HasSubstr(path + ": entry "));
  EXPECT_THAT(ErrorReading(path, "auto"), HasSubstr(": odometry: absurd position (1e+300, "));
}

// A rawlog whose first entry claims a serialization version this MRPT does
// not know (as a file from another MRPT version would).
TEST(MrptRawlog, EntryOfAnotherVersionIsOneError) {
  const auto run = SimulatedRun(3.0);
  const std::string path = WriteObservationsRawlog("version.rawlog", run, false);
  std::string bytes;
  {
    std::ifstream in(path, std::ios::binary);
    bytes.assign(std::istreambuf_iterator<char>(in), {});
  }
  const size_t name_len = static_cast<unsigned char>(bytes[0]) & 0x7F;
  ASSERT_EQ(bytes.substr(1, name_len), "mrpt::obs::CObservationOdometry");
  bytes[1 + name_len] = 99;  // the version byte after the class name
  std::ofstream(path, std::ios::binary) << bytes;
  EXPECT_THAT(ErrorReading(path, "rawlog"), HasSubstr(path + ": entry 1: not an MRPT rawlog entry"));
}

// MRPT sizes a CObservationRange's measurements from the count before them
// and reads nothing first: a count of four thousand million would allocate
// gigabytes for minutes. Read first in a child with bounded memory
// (child_check.h): one error naming the entry, at once.
TEST(MrptRawlog, DamagedCountIsOneErrorNotGigabytes) {
  const std::string path = ::cogmap::testing_util::TestTempPath("count.rawlog");
  const auto robot = sensors::BuiltinRobot("pioneer16");
  {
    mrpt::io::CFileOutputStream f(path);
    auto arch = mrpt::serialization::archiveFrom(f);
    arch << *Odometry(0.0, Pose2{});
    arch << *Sonar(0.0, robot, {{0, 1.0}, {1, 2.0}, {2, 3.0}});
  }
  std::string bytes;
  {
    std::ifstream in(path, std::ios::binary);
    bytes.assign(std::istreambuf_iterator<char>(in), {});
  }
  // The count (3, little-endian) after the range entry's class name.
  const size_t name = bytes.find("mrpt::obs::CObservationRange");
  ASSERT_NE(name, std::string::npos);
  const size_t count = bytes.find(std::string("\x03\x00\x00\x00", 4), name);
  ASSERT_NE(count, std::string::npos);
  bytes.replace(count, 4, "\xF0\xFF\xFF\xFF");
  std::ofstream(path, std::ios::binary) << bytes;
  EXPECT_THAT(ErrorReading(path, "rawlog"),
              HasSubstr(path + ": entry 2: a damaged entry: a count in it asks for more memory"));
}

TEST(MrptRawlog, TextFileAsRawlogIsOneError) {
  const std::string path = WriteTemp("not.rawlog", "# cogmap-log 1\nrobot pioneer8\n");
  EXPECT_THAT(ErrorReading(path, "rawlog"), HasSubstr(path + ": entry 1: not an MRPT rawlog entry"));
}

}  // namespace
}  // namespace cogmap::io
