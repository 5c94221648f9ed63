// CarmenLogWriter: a CARMEN SONAR log written from a simulated Pioneer run
// reads back as the same sweeps on the same robot, and fuses into the same
// grid as the run itself (there is no real CARMEN sonar log in
// ../shared/data); a laser run reads back as the same scans; robots and
// records CARMEN's messages cannot hold are refused.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <sstream>
#include <string>
#include <vector>

#include "cogmap/core/angles.h"
#include "cogmap/core/error.h"
#include "cogmap/grid/range_fusion.h"
#include "cogmap/io/carmen_writer.h"
#include "cogmap/io/grid_io.h"
#include "cogmap/io/log_test_util.h"
#include "cogmap/io/world_io.h"
#include "cogmap/sensors/robot.h"
#include "cogmap/sim/simulator.h"

namespace cogmap::io {
namespace {

using namespace testing_util;
using ::testing::HasSubstr;

std::string ToCarmen(const std::vector<sensors::LogRecord>& records, const sensors::RobotDescription& robot) {
  std::ostringstream out;
  CarmenLogWriter writer(out, robot, "sim");
  for (const auto& r : records) writer.Write(r);
  return out.str();
}

// A simulated run through nine_rooms.
std::vector<sensors::LogRecord> SimulatedRun(const sensors::RobotDescription& robot, unsigned seed, double max_time_s,
                                             int sonar_bank_size = 8) {
  const FloorPlan plan = ReadAriaMap(std::string(COGMAP_SHARED_DIR) + "/worlds/nine_rooms.map").plan;
  sim::SimulatorOptions o;
  o.seed = seed;
  o.max_time_s = max_time_s;
  o.sonar_bank_size = sonar_bank_size;
  std::vector<sensors::LogRecord> run;
  sim::Simulate(plan, robot, o, [&](const sensors::LogRecord& r) { run.push_back(r); });
  return run;
}

TEST(CarmenSonarFromSimulation, ReadsBackAndMapsLikeTheRun) {
  const sensors::RobotDescription robot = sensors::BuiltinRobot("pioneer16");
  // Bank size 1: every transducer in every record, as CARMEN's SONAR has them.
  const std::vector<sensors::LogRecord> run = SimulatedRun(robot, 3, 40.0, 1);
  ASSERT_GT(run.size(), 100u);

  auto reader = OpenLog(WriteTemp("sim_sonar.clf", ToCarmen(run, robot)), "auto");
  const auto hint = *reader->robot_hint();
  EXPECT_EQ(hint.name, "carmen-sonar");
  ASSERT_EQ(hint.sensors.size(), robot.sensors.size());
  for (size_t i = 0; i < robot.sensors.size(); ++i) {
    const auto &a = hint.sensors[i], &b = robot.sensors[i];
    EXPECT_EQ(a.robot_from_sensor.x, b.robot_from_sensor.x);
    EXPECT_EQ(a.robot_from_sensor.y, b.robot_from_sensor.y);
    EXPECT_EQ(a.robot_from_sensor.theta, b.robot_from_sensor.theta);
    EXPECT_EQ(a.beam_width_rad, b.beam_width_rad);
    EXPECT_EQ(a.min_range_m, b.min_range_m);
    EXPECT_EQ(a.max_range_m, b.max_range_m);
    EXPECT_EQ(a.kind, b.kind);
  }
  // ODOM -> odometry-only record; SONAR -> the sweep at that odometry.
  const auto back = ReadAll(*reader);
  std::vector<sensors::LogRecord> sweeps;
  for (const auto& r : back)
    if (!r.ranges.empty()) sweeps.push_back(r);
  std::vector<sensors::LogRecord> want;
  for (const auto& r : run)
    if (!r.ranges.empty()) want.push_back(r);
  ASSERT_EQ(sweeps.size(), want.size());
  for (size_t k = 0; k < want.size(); ++k) {
    ASSERT_EQ(sweeps[k].odom.x, want[k].odom.x);
    ASSERT_EQ(sweeps[k].odom.theta, want[k].odom.theta);
    ASSERT_EQ(sweeps[k].time_s, want[k].time_s);
    for (size_t i = 0; i < want[k].ranges.size(); ++i) ASSERT_EQ(sweeps[k].ranges[i].range_m, want[k].ranges[i].range_m);
  }
  EXPECT_TRUE(reader->skipped().empty());

  // The same MHIMM grid from the CARMEN log (with its own robot) and the run.
  auto from_carmen = grid::MakeFusion(grid::FusionRule::kMhimm);
  auto carmen = OpenLog(WriteTemp("sim_sonar.clf", ToCarmen(run, robot)), "carmen");
  FuseLog(*carmen, hint, *from_carmen);
  auto from_run = grid::MakeFusion(grid::FusionRule::kMhimm);
  for (const auto& r : run) from_run->InsertSweep(r.odom, robot, r.ranges);
  const auto a = from_carmen->Values(), b = from_run->Values();
  ASSERT_EQ(a.cells().size(), b.cells().size());
  EXPECT_TRUE(a.cells() == b.cells());
  long occupied = 0;
  for (float v : a.cells()) occupied += v > 7.0f;
  EXPECT_GT(occupied, 50);
}

// One record of each kind, character for character as CARMEN lays them out.
TEST(CarmenLogWriter, WritesCarmenFieldOrder) {
  sensors::RobotDescription robot;
  robot.name = "two";
  for (double th : {0.5, -0.5}) {
    sensors::RangeSensor s;
    s.robot_from_sensor = {0.25, 0.0, th};
    s.beam_width_rad = 0.25;
    robot.sensors.push_back(s);
  }
  std::ostringstream out;
  CarmenLogWriter w(out, robot, "x");
  sensors::LogRecord r;
  r.time_s = 2.5;
  r.odom = {1, 2, 0.5};
  w.Write(r);
  r.truth = Pose2{3, 4, -0.25};
  r.ranges = {{0, 1.5}, {1, 4}};
  w.Write(r);
  EXPECT_EQ(out.str(),
            "# CARMEN Logfile\n# written by cogmap convert from x\n# robot two\n"
            "ODOM 1 2 0.5 0 0 0 2.5 cogmap 2.5\n"
            "TRUEPOS 3 4 -0.25 1 2 0.5 2.5 cogmap 2.5\n"
            "SONAR 0.25 2 1.5 4 0.25 0 0.5 0.25 0 -0.5 2.5 cogmap 2.5\n");
  EXPECT_EQ(w.records_written(), 2);
}

// A simulated laser run: ROBOTLASER1 messages read back as the same scans on
// a laser with the same beams.
TEST(CarmenLogWriter, LaserRunReadsBackAsTheSameScans) {
  const sensors::RobotDescription robot = sensors::BuiltinRobot("laser");
  const std::vector<sensors::LogRecord> run = SimulatedRun(robot, 5, 20.0);
  std::vector<sensors::LogRecord> want;
  for (const auto& r : run)
    if (!r.ranges.empty()) want.push_back(r);
  ASSERT_GT(want.size(), 20u);

  auto reader = OpenLog(WriteTemp("sim_laser.clf", ToCarmen(run, robot)), "auto");
  const auto hint = *reader->robot_hint();
  EXPECT_EQ(hint.name, "carmen-laser");
  ASSERT_EQ(hint.sensors.size(), robot.sensors.size());
  for (size_t i = 0; i < robot.sensors.size(); ++i) {
    const auto &a = hint.sensors[i].robot_from_sensor, &b = robot.sensors[i].robot_from_sensor;
    EXPECT_NEAR(a.x, b.x, 1e-12);
    EXPECT_NEAR(a.y, b.y, 1e-12);
    EXPECT_NEAR(AngleDiff(a.theta, b.theta), 0.0, 1e-12);
    EXPECT_EQ(hint.sensors[i].max_range_m, robot.sensors[i].max_range_m);
  }
  std::vector<sensors::LogRecord> scans, truths;
  for (const auto& r : ReadAll(*reader)) (r.ranges.empty() ? truths : scans).push_back(r);
  ASSERT_EQ(scans.size(), want.size());
  for (size_t k = 0; k < want.size(); ++k) {
    ASSERT_EQ(scans[k].time_s, want[k].time_s);
    ASSERT_EQ(scans[k].odom.x, want[k].odom.x);
    ASSERT_EQ(scans[k].odom.theta, want[k].odom.theta);
    ASSERT_EQ(scans[k].ranges.size(), want[k].ranges.size());
    for (size_t i = 0; i < want[k].ranges.size(); ++i) ASSERT_EQ(scans[k].ranges[i].range_m, want[k].ranges[i].range_m);
  }
  // The reference poses come back through TRUEPOS.
  ASSERT_EQ(truths.size(), run.size());
  for (size_t k = 0; k < run.size(); ++k) {
    ASSERT_TRUE(truths[k].truth.has_value());
    ASSERT_EQ(truths[k].truth->x, run[k].truth->x);
  }
}

TEST(CarmenLogWriter, RefusesWhatCarmenCannotHold) {
  auto error_of = [](const sensors::RobotDescription& robot, const sensors::LogRecord* r) {
    try {
      std::ostringstream out;
      CarmenLogWriter w(out, robot, "in.log");
      if (r) w.Write(*r);
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  // A Pioneer run fires one transducer per bank at a time: not a SONAR message.
  sensors::LogRecord partial;
  partial.ranges = {{0, 1.0}, {8, 2.0}};
  EXPECT_THAT(error_of(sensors::BuiltinRobot("pioneer16"), &partial),
              HasSubstr("in.log: record 1 has 2 readings, not one of each of the 16 sonars"));
  sensors::LogRecord shuffled;
  for (int i = 0; i < 16; ++i) shuffled.ranges.push_back({15 - i, 1.0});
  EXPECT_THAT(error_of(sensors::BuiltinRobot("pioneer16"), &shuffled), HasSubstr("in sensor order"));
  EXPECT_EQ(error_of(sensors::BuiltinRobot("pioneer16"), nullptr), "");

  sensors::RobotDescription mixed = sensors::BuiltinRobot("pioneer8");
  mixed.sensors.push_back(sensors::BuiltinRobot("laser").sensors[0]);
  EXPECT_THAT(error_of(mixed, nullptr), HasSubstr("mixes sonars and lasers"));
  sensors::RobotDescription uneven = sensors::BuiltinRobot("laser");
  uneven.sensors[3].robot_from_sensor.theta += 0.01;
  EXPECT_THAT(error_of(uneven, nullptr), HasSubstr("not at equal angle steps (beam 3)"));
  sensors::RobotDescription two = sensors::BuiltinRobot("laser");
  two.sensors.back().robot_from_sensor.x += 0.1;
  EXPECT_THAT(error_of(two, nullptr), HasSubstr("more than one scanner"));
  EXPECT_THAT(error_of(sensors::RobotDescription{}, nullptr), HasSubstr("has no sensors"));
}

}  // namespace
}  // namespace cogmap::io
