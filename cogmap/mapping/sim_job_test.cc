// `cogmap simulate` and `cogmap render-world` as library calls, on a building
// generated in code.
#include "cogmap/mapping/sim_job.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>

#include "cogmap/core/angles.h"
#include "cogmap/core/error.h"
#include "cogmap/core/test_temp.h"
#include "cogmap/io/log_reader.h"
#include "cogmap/io/world_io.h"
#include "cogmap/sim/building.h"

namespace cogmap::mapping {
namespace {

namespace fs = std::filesystem;
using ::cogmap::testing_util::TestTempPath;

// Two rooms on a 12 m corridor, written as a 2D-Map; 'route' false drops the route.
std::string SmallBuilding(const std::string& name, bool route = true) {
  sim::BuildingOptions b;
  b.rooms = 2;
  b.corridor_m = 12.0;
  FloorPlan plan = sim::GenerateBuilding(b);
  if (!route) plan.route.clear();
  const std::string path = TestTempPath(name);
  io::WriteAriaMap(path, plan);
  return path;
}

TEST(ParseStartPose, ReadsMetresAndDegrees) {
  const Pose2 p = ParseStartPose("1.5,-2,90");
  EXPECT_EQ(p.x, 1.5);
  EXPECT_EQ(p.y, -2.0);
  EXPECT_DOUBLE_EQ(p.theta, kPi / 2);
  EXPECT_DOUBLE_EQ(ParseStartPose("0,0,270").theta, -kPi / 2);  // normalised
  try {
    ParseStartPose("1,2");
    FAIL();
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()), "--start: expected X,Y,THETA_DEG (3 numbers), got 2 in '1,2'");
  }
  EXPECT_THROW(ParseStartPose("1,x,3"), InputError);
  EXPECT_THROW(ParseStartPose("1,,3"), InputError);
  EXPECT_THROW(ParseStartPose("1,2,nan"), InputError);
}

TEST(SimulateJob, WritesTheRunAsANativeLog) {
  SimulateJob job;
  job.world_path = SmallBuilding("sim_building.map");
  job.options.max_time_s = 30.0;
  job.noiseless = true;
  job.output_path = TestTempPath("sim_run.log");
  std::vector<std::string> warnings;
  job.warning = [&warnings](const std::string& w) { warnings.push_back(w); };
  const SimulateJobResult r = RunSimulateJob(job);
  EXPECT_EQ(r.robot.name, "pioneer16");
  EXPECT_GT(r.stats.records, 100);
  EXPECT_LE(r.stats.simulated_s, 30.0 + 1e-9);
  EXPECT_EQ(warnings, r.stats.warnings);  // no world warnings: the run's, in order
  // The log holds every record; noiseless: odometry is the true pose.
  auto log = io::OpenLog(job.output_path);
  EXPECT_EQ(log->robot_hint()->name, "pioneer16");
  sensors::LogRecord rec;
  long n = 0;
  double max_odom_error_m = 0.0;
  while (log->Next(&rec)) {
    ++n;
    ASSERT_TRUE(rec.truth);
    max_odom_error_m = std::max(max_odom_error_m, (rec.odom.translation() - rec.truth->translation()).norm());
  }
  EXPECT_EQ(n, r.stats.records);
  EXPECT_LT(max_odom_error_m, 1e-6);
}

// --sonar-bank-size 1: every record with sonar readings holds the whole ring
// (what CARMEN's SONAR carries); 8: one firing of each of the two banks.
TEST(SimulateJob, SonarBankSizeSetsReadingsPerRecord) {
  for (int bank : {1, 8}) {
    SimulateJob job;
    job.world_path = SmallBuilding("sim_bank.map");
    job.options.max_time_s = 5.0;
    job.options.sonar_bank_size = bank;
    job.output_path = TestTempPath("sim_bank.log");
    RunSimulateJob(job);
    auto log = io::OpenLog(job.output_path);
    sensors::LogRecord rec;
    long sweeps = 0;
    while (log->Next(&rec)) {
      if (rec.ranges.empty()) continue;
      ++sweeps;
      ASSERT_EQ(rec.ranges.size(), bank == 1 ? 16u : 2u);
    }
    EXPECT_GT(sweeps, 50);
  }
}

TEST(SimulateJob, SameSeedSameLog) {
  SimulateJob job;
  job.world_path = SmallBuilding("sim_seed.map");
  job.options.max_time_s = 10.0;
  job.output_path = TestTempPath("sim_seed_a.log");
  RunSimulateJob(job);
  job.output_path = TestTempPath("sim_seed_b.log");
  RunSimulateJob(job);
  auto text = [](const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    return std::string(std::istreambuf_iterator<char>(in), {});
  };
  const std::string a = text(TestTempPath("sim_seed_a.log"));
  EXPECT_GT(a.size(), 1000u);
  EXPECT_EQ(a, text(TestTempPath("sim_seed_b.log")));
}

TEST(SimulateJob, RejectsBadOptionsAndARouteRunWithoutARoute) {
  SimulateJob job;
  job.world_path = SmallBuilding("sim_noroute.map", false);
  job.output_path = TestTempPath("sim_noroute.log");
  job.options.cruise_mps = 0.0;
  try {
    job.Validate();
    FAIL();
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()), "--speed must be in (0, 2] m/s");
  }
  job.options.cruise_mps = 0.5;
  job.options.sensor.sonar_rays = 0;
  EXPECT_THROW(job.Validate(), InputError);
  job.options.sensor.sonar_rays = 5;
  job.options.max_time_s = -1;
  EXPECT_THROW(job.Validate(), InputError);
  job.options.max_time_s = 10;
  job.options.sonar_bank_size = 0;
  EXPECT_THROW(job.Validate(), InputError);
  job.options.sonar_bank_size = 8;
  // Not a number is no drift, scale or resolution: before, a NaN drift
  // wrote a log of NaN odometry with exit 0.
  auto message = [&job] {
    try {
      job.Validate();
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  job.options.odometry.drift_rad_per_m = std::nan("");
  EXPECT_EQ(message(), "--drift-deg-per-m nan: must be in [-90, 90]");
  job.options.odometry.drift_rad_per_m = DegToRad(1.0);
  job.options.odometry.scale_error = std::numeric_limits<double>::infinity();
  EXPECT_EQ(message(), "--scale-error inf: must be in (-0.5, 0.5)");
  job.options.odometry.scale_error = 0.01;
  job.m_per_pixel = std::nan("");
  EXPECT_EQ(message(), "--m-per-pixel nan: must be in (0, 1] metres");
  job.m_per_pixel = 0.05;
  job.options.max_time_s = std::numeric_limits<double>::infinity();
  EXPECT_EQ(message(), "--max-time must be in [0, 1e7] s (0: from the route; NaN and infinity are none)");
  job.options.max_time_s = 10;
  EXPECT_EQ(message(), "no error");
  try {
    RunSimulateJob(job);
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("no route"), std::string::npos) << e.what();
  }
  EXPECT_FALSE(fs::exists(job.output_path));
  job.options.mode = sim::SimMode::kExplore;  // explores instead
  EXPECT_GT(RunSimulateJob(job).stats.records, 0);
  EXPECT_TRUE(fs::exists(job.output_path));
}

TEST(RenderWorldJob, DrawsTheWorldAndARunsPaths) {
  RenderWorldJob job;
  job.world_path = SmallBuilding("render_building.map");
  job.picture_path = TestTempPath("render_building.png");
  job.px_per_m = 20;
  const RenderWorldResult r = RunRenderWorldJob(job);
  EXPECT_EQ(r.world.rooms.size(), 3u);  // two rooms and the corridor
  EXPECT_GT(r.width_px, 12 * 20);       // the corridor's length at 20 px/m
  EXPECT_TRUE(fs::exists(job.picture_path));
  job.picture_path = TestTempPath("render_building.txt");
  EXPECT_THROW(RunRenderWorldJob(job), InputError);  // not a picture format
  EXPECT_FALSE(fs::exists(job.picture_path));
  job.picture_path = TestTempPath("render_building.svg");
  job.log_path = TestTempPath("missing.log");
  EXPECT_THROW(RunRenderWorldJob(job), InputError);
}

}  // namespace
}  // namespace cogmap::mapping
