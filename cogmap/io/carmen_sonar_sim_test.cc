// A CARMEN SONAR log written from a simulated Pioneer run reads back as the
// same sweeps on the same robot, and fuses into the same grid as the run
// itself (there is no real CARMEN sonar log in ../shared/data).
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cstdio>
#include <string>
#include <vector>

#include "cogmap/grid/range_fusion.h"
#include "cogmap/io/grid_io.h"
#include "cogmap/io/log_test_util.h"
#include "cogmap/io/world_io.h"
#include "cogmap/sensors/robot.h"
#include "cogmap/sim/simulator.h"

namespace cogmap::io {
namespace {

using namespace testing_util;

std::string G(double v) {
  char b[40];
  std::snprintf(b, sizeof b, "%.17g", v);
  return b;
}

// CARMEN's logger writes, per odometry step, "ODOM x y theta tv rv accel
// timestamp host logger_timestamp", and per sonar cycle "SONAR cone_angle n
// r1..rn x1 y1 theta1 .. xn yn thetan timestamp host logger_timestamp"
// (every transducer's range each time).
std::string ToCarmenSonar(const std::vector<sensors::LogRecord>& records, const sensors::RobotDescription& robot) {
  std::string out = "# CARMEN Logfile written from a cogmap simulation\n";
  const size_t n = robot.sensors.size();
  for (const auto& r : records) {
    const std::string t = G(r.time_s);
    out += "ODOM " + G(r.odom.x) + " " + G(r.odom.y) + " " + G(r.odom.theta) + " 0 0 0 " + t + " sim " + t + "\n";
    if (r.ranges.empty()) continue;
    EXPECT_EQ(r.ranges.size(), n);
    out += "SONAR " + G(robot.sensors[0].beam_width_rad) + " " + std::to_string(n);
    for (size_t i = 0; i < n; ++i) {
      EXPECT_EQ(r.ranges[i].sensor, static_cast<int>(i));
      out += " " + G(r.ranges[i].range_m);
    }
    for (const auto& s : robot.sensors)
      out += " " + G(s.robot_from_sensor.x) + " " + G(s.robot_from_sensor.y) + " " + G(s.robot_from_sensor.theta);
    out += " " + t + " sim " + t + "\n";
  }
  return out;
}

TEST(CarmenSonarFromSimulation, ReadsBackAndMapsLikeTheRun) {
  const FloorPlan plan = ReadAriaMap(std::string(COGMAP_SHARED_DIR) + "/worlds/nine_rooms.map").plan;
  const sensors::RobotDescription robot = sensors::BuiltinRobot("pioneer16");
  sim::SimulatorOptions o;
  o.seed = 3;
  o.max_time_s = 40.0;
  o.sonar_bank_size = 1;  // every transducer in every record, as CARMEN's SONAR has them
  std::vector<sensors::LogRecord> run;
  sim::Simulate(plan, robot, o, [&](const sensors::LogRecord& r) { run.push_back(r); });
  ASSERT_GT(run.size(), 100u);

  auto reader = OpenLog(WriteTemp("sim_sonar.clf", ToCarmenSonar(run, robot)), "auto");
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
  auto carmen = OpenLog(WriteTemp("sim_sonar.clf", ToCarmenSonar(run, robot)), "carmen");
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

}  // namespace
}  // namespace cogmap::io
