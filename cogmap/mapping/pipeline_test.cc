// The mapping API on a simulated run: the streaming pipeline and the whole job
// give the same map, options are checked, a stored run is continued.
#include "cogmap/mapping/pipeline.h"

#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>
#include <map>
#include <numeric>
#include <optional>
#include <set>
#include <thread>

#include "cogmap/core/angles.h"
#include "cogmap/core/error.h"
#include "cogmap/core/test_temp.h"
#include "cogmap/io/log_reader.h"
#include "cogmap/io/native_log.h"
#include "cogmap/io/world_io.h"
#include "cogmap/mapping/map_job.h"
#include "cogmap/sim/building.h"
#include "cogmap/sim/simulator.h"

namespace cogmap::mapping {
namespace {

using testing_util::TestTempPath;

// A robot (by default the 16-sonar Pioneer) driving nine_rooms with this drift.
std::vector<sensors::LogRecord> SimulatedRun(double drift_deg_per_m, const std::string& robot = "pioneer16",
                                             unsigned seed = 3) {
  const FloorPlan plan = io::ReadAriaMap(std::string(COGMAP_SHARED_DIR) + "/worlds/nine_rooms.map").plan;
  sim::SimulatorOptions so;
  so.seed = seed;
  so.odometry.drift_rad_per_m = DegToRad(drift_deg_per_m);
  std::vector<sensors::LogRecord> records;
  sim::Simulate(plan, sensors::BuiltinRobot(robot), so,
                [&records](const sensors::LogRecord& r) { records.push_back(r); });
  return records;
}

std::string WriteLog(const std::vector<sensors::LogRecord>& records, const std::string& name) {
  const std::string path = TestTempPath(name);
  std::ofstream out(path);
  io::NativeLogWriter w(out, sensors::BuiltinRobot("pioneer16"));
  for (const auto& r : records) w.Write(r);
  return path;
}

TEST(MappingOptions, RejectsOutOfRangeValuesNamingTheOption) {
  MappingOptions o;
  o.cell_m = 0.0;
  try {
    o.Validate();
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("--cell"), std::string::npos);
  }
  o = {};
  o.add_drift_rad_per_m = DegToRad(120.0);
  EXPECT_THROW(o.Validate(), InputError);
  o = {};
  o.threads = 3;
  EXPECT_THROW(o.Validate(), InputError);
  // Infinities and lengths that would cut every record.
  auto message = [](const MappingOptions& m) {
    try {
      m.Validate();
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  o = {};
  o.window_m = std::numeric_limits<double>::infinity();
  EXPECT_EQ(message(o), "--window inf: must be in [0.1, 100] metres (a cell at least)");
  o = {};
  o.max_asr_m = 1e-300;
  EXPECT_EQ(message(o), "--max-asr 1e-300: must be 0 (never) or in [0.5, 100000] metres");
  o.max_asr_m = 0.0;
  EXPECT_EQ(message(o), "no error");
  o = {};
  o.asr_length_m = std::nan("");
  EXPECT_EQ(message(o), "--asr-length nan: must be in [0.5, 100000] metres");
  o = {};
  EXPECT_NO_THROW(o.Validate());
}

TEST(MappingOptions, CorrectionFollowsTheModeAndFlags) {
  MappingOptions o;
  EXPECT_EQ(o.correction(), Correction::kPoseGraph);
  o.pose_graph = false;
  EXPECT_EQ(o.correction(), Correction::kDriftFilter);
  o.drift_filter = false;
  EXPECT_EQ(o.correction(), Correction::kPerAsrEm);
  o = {};
  o.paper = true;
  EXPECT_EQ(o.correction(), Correction::kPerAsrEm);
  o.correct = false;
  EXPECT_EQ(o.correction(), Correction::kNone);
}

TEST(MapperOptionsFor, WallLinesFollowTheModeAndTheRobot) {
  MappingOptions o;
  o.wall_lines = true;
  const auto sonar = MapperOptionsFor(sensors::BuiltinRobot("pioneer16"), o).vectorize;
  EXPECT_TRUE(sonar.wall_lines);
  EXPECT_TRUE(sonar.lines.all_occupied);
  EXPECT_NEAR(RadToDeg(sonar.lines.beam_half_width_rad), 15.0, 1e-9);
  EXPECT_DOUBLE_EQ(sonar.lines.path_clearance_m, sensors::BuiltinRobot("pioneer16").radius_m);
  const auto laser = MapperOptionsFor(sensors::BuiltinRobot("laser"), o).vectorize;
  EXPECT_TRUE(laser.wall_lines);
  EXPECT_FALSE(laser.lines.all_occupied);
  EXPECT_NEAR(RadToDeg(laser.lines.beam_half_width_rad), 0.5, 1e-9);  // 180 degrees over 180 steps, halved
  o.paper = true;
  EXPECT_FALSE(MapperOptionsFor(sensors::BuiltinRobot("pioneer16"), o).vectorize.wall_lines);
  o.paper = false;
  o.wall_lines = false;
  EXPECT_FALSE(MapperOptionsFor(sensors::BuiltinRobot("pioneer16"), o).vectorize.wall_lines);
}

// --cone-orientation takes the rooms' orientation from the cone grid for a
// ring that looks only forward, and only there: not by default, not on a
// full ring or a laser, not without the cone grid (--axis-walls, paper mode).
TEST(MapperOptionsFor, ConeOrientationForAForwardRingOnRequest) {
  const auto front = sensors::BuiltinRobot("pioneer8");
  MappingOptions o;
  EXPECT_FALSE(MapperOptionsFor(front, o).orientation_from_cone);
  o.cone_orientation = true;
  EXPECT_TRUE(MapperOptionsFor(front, o).orientation_from_cone);
  EXPECT_TRUE(MapperOptionsFor(sensors::BuiltinRobot("pioneer8-course"), o).orientation_from_cone);
  EXPECT_FALSE(MapperOptionsFor(sensors::BuiltinRobot("pioneer16"), o).orientation_from_cone);
  EXPECT_FALSE(MapperOptionsFor(sensors::BuiltinRobot("laser"), o).orientation_from_cone);
  MappingOptions axis = o;
  axis.cone_walls = false;
  EXPECT_FALSE(MapperOptionsFor(front, axis).orientation_from_cone);
  MappingOptions paper = o;
  paper.paper = true;
  EXPECT_FALSE(MapperOptionsFor(front, paper).orientation_from_cone);
}

// The hits' distances are kept for the pose graph's bend only.
TEST(MapperOptionsFor, SeenDistancesWithThePoseGraphOnly) {
  const auto robot = sensors::BuiltinRobot("pioneer16");
  MappingOptions o;
  EXPECT_TRUE(MapperOptionsFor(robot, o).seen_distances);
  o.pose_graph = false;  // the drift filter
  EXPECT_FALSE(MapperOptionsFor(robot, o).seen_distances);
  o.pose_graph = true;
  o.paper = true;
  EXPECT_FALSE(MapperOptionsFor(robot, o).seen_distances);
  o.paper = false;
  o.correct = false;
  EXPECT_FALSE(MapperOptionsFor(robot, o).seen_distances);
}

TEST(MapperOptionsFor, DoorGapIsDefaultModeOnRequestOnly) {
  MappingOptions o;
  const auto robot = sensors::BuiltinRobot("pioneer16");
  EXPECT_DOUBLE_EQ(MapperOptionsFor(robot, o).boundary.gap_m, 0.0);  // off by default
  o.door_gap = true;
  const auto b = MapperOptionsFor(robot, o).boundary;
  EXPECT_DOUBLE_EQ(b.gap_m, 2.0 * b.close_m);
  o.paper = true;
  EXPECT_DOUBLE_EQ(MapperOptionsFor(robot, o).boundary.gap_m, 0.0);  // the thesis's rule
  o.paper = false;
  o.door_gap = false;
  o.door_gap_m = 2.5;  // implies --door-gap
  EXPECT_DOUBLE_EQ(MapperOptionsFor(robot, o).boundary.gap_m, 2.5);
  o.door_gap_m = 9.0;
  EXPECT_THROW(o.Validate(), InputError);
}

TEST(OutputChoice, ParsesListsAndNamesAnUnknownOutput) {
  const OutputChoice d = OutputChoice::Parse("default");
  EXPECT_TRUE(d.plan && d.geojson && d.aria && d.gpkg && d.route);  // the fast set
  EXPECT_FALSE(d.svg || d.png || d.plan_png || d.pgm || d.compare || d.heading);
  const OutputChoice a = OutputChoice::Parse("all");
  EXPECT_TRUE(a.svg && a.png && a.plan && a.plan_png && a.pgm && a.compare && a.heading);
  const OutputChoice both = OutputChoice::Parse("plan");
  EXPECT_TRUE(both.plan && both.plan_png);
  const OutputChoice raster = OutputChoice::Parse("plan-png");
  EXPECT_TRUE(raster.plan_png && !raster.plan);
  const OutputChoice p = OutputChoice::Parse("png,heading");
  EXPECT_TRUE(p.png && p.heading);
  EXPECT_FALSE(p.svg);
  try {
    OutputChoice::Parse("svg,gif");
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("'gif'"), std::string::npos);
  }
}

TEST(DriftAdder, TurnsEachIncrementByTheRateTimesItsLength) {
  DriftAdder d(DegToRad(1.0));
  d.Add(Pose2{0, 0, 0});
  const Pose2 p = d.Add(Pose2{10, 0, 0});  // 10 m straight: 10 degrees of extra turn
  EXPECT_NEAR(RadToDeg(p.theta), 10.0, 1e-9);
  EXPECT_NEAR(std::hypot(p.x, p.y), 10.0, 1e-9);
  EXPECT_NEAR(RadToDeg(std::atan2(p.y, p.x)), 5.0, 1e-9);  // the chord follows the mean heading
}

// A log whose poses jitter by 3 cm across the way at every record (CARMEN's
// two interleaved odometry streams) while the robot drives 10 m straight: the
// drift added is that of 10 m within 3 % (the anchor's 0.1 m steps still see
// part of the jitter across them; summed record by record the jitter counted
// 31.6 m).
TEST(DriftAdder, CountsTheDistanceDrivenNotTheJitter) {
  DriftAdder d(DegToRad(1.0));
  Pose2 p;
  for (int i = 0; i <= 1000; ++i) p = d.Add(Pose2{0.01 * i, (i % 2) ? 0.03 : 0.0, 0.0});
  EXPECT_NEAR(RadToDeg(p.theta), 10.0, 0.3);
  // Standing still, jittering: no drift at all.
  DriftAdder still(DegToRad(1.0));
  for (int i = 0; i <= 1000; ++i) p = still.Add(Pose2{0.0, (i % 2) ? 0.03 : 0.0, 0.0});
  EXPECT_NEAR(p.theta, 0.0, 1e-12);
}

// --scan-match: a laser's scans correct the wheels before the rooms are
// mapped. nine_rooms at 2 deg/m of drift: the rooms' odometry poses (what
// the mapper gets) lean by degrees without it and stay within a degree of the
// truth with it; a sonar robot is left as it was.
TEST(MappingPipeline, ScanMatchingCorrectsALasersOdometryBeforeMapping) {
  const sensors::RobotDescription laser = sensors::BuiltinRobot("laser");
  const std::vector<sensors::LogRecord> records = SimulatedRun(2.0, "laser", 5);
  auto run = [&](bool scan_match, const std::string& name, RunResult* out) {
    auto store = asr::SqliteAsrStore::Open(TestTempPath(name), asr::SqliteAsrStore::OpenMode::kReplace);
    MappingOptions mo;
    mo.scan_match = scan_match ? ScanMatch::kOn : ScanMatch::kOff;
    MappingPipeline p(laser, mo, store.get());
    std::vector<double> errors;  // each room's odometry heading against the truth, relative to the first's
    std::optional<double> first;
    p.OnAsrClosed([&](const asr::Asr& x, const AsrSummary&) {
      if (x.true_path.empty() || x.path.empty()) return;
      const double e = NormalizeAngle(x.path.front().theta - x.true_path.front().theta);
      if (!first) first = e;
      errors.push_back(RadToDeg(std::abs(NormalizeAngle(e - *first))));
    });
    for (const auto& r : records) p.Push(r);
    *out = p.Finish();
    std::sort(errors.begin(), errors.end());
    return errors.empty() ? 0.0 : errors[errors.size() / 2];
  };
  RunResult wheels, scans;
  const double without = run(false, "wheels.sqlite", &wheels), with = run(true, "scans.sqlite", &scans);
  EXPECT_GT(without, 5.0);
  EXPECT_LT(with, 1.0);
  EXPECT_EQ(wheels.scan_match.scans, 0);
  EXPECT_GT(scans.scan_match.scans, 1000);
  EXPECT_GT(scans.scan_match.matched, 0.95 * scans.scan_match.scans);
  // A sonar ring is no laser: nothing to match.
  auto store = asr::SqliteAsrStore::Open(TestTempPath("sonar.sqlite"), asr::SqliteAsrStore::OpenMode::kReplace);
  MappingOptions mo;
  mo.scan_match = ScanMatch::kOn;
  MappingPipeline p(sensors::BuiltinRobot("pioneer16"), mo, store.get());
  for (const auto& r : SimulatedRun(0.0)) p.Push(r);
  const RunResult& sonar = p.Finish();
  EXPECT_EQ(sonar.scan_match.scans, 0);
  ASSERT_EQ(ScanMatchWarnings(mo, sonar).size(), 1u);  // nothing to match, and it says so
  EXPECT_TRUE(ScanMatchWarnings(mo, scans).empty());   // 10 scans a second: dense, all matched
  EXPECT_TRUE(ScanMatchWarnings({}, wheels).empty());  // not asked for
  // By default (auto): the laser's scans, 10 a second, are dense enough; the
  // sonar ring has none, and nothing is held back or decided for it.
  RunResult automatic;
  {
    auto st = asr::SqliteAsrStore::Open(TestTempPath("auto.sqlite"), asr::SqliteAsrStore::OpenMode::kReplace);
    MappingPipeline a(laser, {}, st.get());
    for (const auto& r : records) a.Push(r);
    automatic = a.Finish();
  }
  EXPECT_TRUE(automatic.scan_match_active);
  EXPECT_EQ(automatic.scan_match_gaps, 10);
  EXPECT_LE(automatic.scan_match_mean_step, 1.0);
  EXPECT_EQ(automatic.records, static_cast<long>(records.size()));  // every record held back was mapped
  // The records held back while it decided are matched too: the same run as
  // with it on from the start.
  EXPECT_EQ(automatic.scan_match.matched, scans.scan_match.matched);
  ASSERT_EQ(automatic.graph.asrs.size(), scans.graph.asrs.size());
  for (size_t i = 0; i < scans.graph.asrs.size(); ++i) EXPECT_EQ(automatic.graph.asrs[i].pose.x, scans.graph.asrs[i].pose.x);
  EXPECT_FALSE(sonar.scan_match_active);
  EXPECT_EQ(sonar.scan_match_gaps, 0);
}

TEST(MappingOptions, DistanceScaleIsAutoOffOrAScaleInRange) {
  EXPECT_TRUE(std::isnan(ParseDistanceScale("auto")));
  EXPECT_EQ(ParseDistanceScale("off"), 1.0);
  EXPECT_EQ(ParseDistanceScale("0.98"), 0.98);
  for (const char* bad : {"nan", "inf", "-1", "2.5", "0.4", "abc", "0.98x", ""}) {
    try {
      ParseDistanceScale(bad);
      ADD_FAILURE() << bad;
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find("--distance-scale"), std::string::npos) << bad;
    }
  }
  MappingOptions o;
  o.distance_scale = 3.0;
  EXPECT_THROW(o.Validate(), InputError);
  o.distance_scale = 1.01;
  o.distance_scale_prior = 0.0;
  EXPECT_THROW(o.Validate(), InputError);
}

// The distance scale: wheels that read 5 % long, measured by the sonars
// looking along the way (nine_rooms' route drives square at its walls) and
// taken out of the rooms' odometry as the run goes on; off, the odometry
// stays 5 % long.
TEST(MappingPipeline, TheRingMeasuresTheOdometrysDistanceScale) {
  const FloorPlan plan = io::ReadAriaMap(std::string(COGMAP_SHARED_DIR) + "/worlds/nine_rooms.map").plan;
  sim::SimulatorOptions so;
  so.seed = 4;
  so.odometry.drift_rad_per_m = DegToRad(1.0);
  so.odometry.scale_error = 0.05;
  std::vector<sensors::LogRecord> records;
  sim::Simulate(plan, sensors::BuiltinRobot("pioneer16"), so,
                [&records](const sensors::LogRecord& r) { records.push_back(r); });
  auto run = [&](double scale, const std::string& name, double* over_truth) {
    auto store = asr::SqliteAsrStore::Open(TestTempPath(name), asr::SqliteAsrStore::OpenMode::kReplace);
    MappingOptions mo;
    mo.distance_scale = scale;
    MappingPipeline p(sensors::BuiltinRobot("pioneer16"), mo, store.get());
    double odometry = 0.0, truth = 0.0;  // the second half of the run's rooms
    auto length = [](const std::vector<Pose2>& path) {
      double l = 0.0;
      for (size_t k = 1; k < path.size(); ++k) l += (path[k].translation() - path[k - 1].translation()).norm();
      return l;
    };
    p.OnAsrClosed([&](const asr::Asr& x, const AsrSummary&) {
      if (x.id < 8 || x.true_path.size() != x.path.size()) return;
      odometry += length(x.path);
      truth += length(x.true_path);
    });
    for (const auto& r : records) p.Push(r);
    RunResult out = p.Finish();
    *over_truth = odometry / truth;
    return out;
  };
  double measured_ratio = 0.0, off_ratio = 0.0;
  const RunResult measured = run(std::numeric_limits<double>::quiet_NaN(), "scale_auto.sqlite", &measured_ratio);
  const RunResult off = run(1.0, "scale_off.sqlite", &off_ratio);
  const localize::OdometryScaleEstimate& e = measured.distance_scale_estimate;
  ASSERT_TRUE(measured.distance_scale_measured);
  ASSERT_TRUE(e.valid);
  EXPECT_GE(e.runs, 10);
  EXPECT_LT(std::abs(e.scale - 1.0 / 1.05), 3.0 * e.sigma + 0.002) << e.scale << " +- " << e.sigma;
  // Shrunk towards 1, by little: the estimate is sure.
  EXPECT_LT(measured.distance_scale_applied, 0.97);
  EXPECT_GT(measured.distance_scale_applied, e.scale);
  EXPECT_NEAR(off_ratio, 1.05, 0.01);
  EXPECT_NEAR(measured_ratio, 1.0, 0.015);
  EXPECT_FALSE(off.distance_scale_measured);
  EXPECT_EQ(off.distance_scale_applied, 1.0);
  // 5 % is more than tyres do: the user hears of it.
  ASSERT_EQ(DistanceScaleWarnings(measured).size(), 1u);
  EXPECT_NE(DistanceScaleWarnings(measured)[0].find("long"), std::string::npos);
  // A run resumed on the store drives on with the scale its run ended with
  // (until its own runs give an estimate): its first rooms are not 5 % long.
  {
    auto store = asr::SqliteAsrStore::Open(TestTempPath("scale_auto.sqlite"), asr::SqliteAsrStore::OpenMode::kOpenExisting);
    const double stored = std::stod(store->GetMeta("distance_scale").value_or("0"));
    EXPECT_NEAR(stored, measured.distance_scale_applied, 1e-5);
    MappingPipeline p(sensors::BuiltinRobot("pioneer16"), {}, store.get());
    p.Resume();
    double odometry = 0.0, truth = 0.0;
    p.OnAsrClosed([&](const asr::Asr& x, const AsrSummary&) {
      for (size_t k = 1; k < x.path.size() && x.path.size() == x.true_path.size(); ++k) {
        odometry += (x.path[k].translation() - x.path[k - 1].translation()).norm();
        truth += (x.true_path[k].translation() - x.true_path[k - 1].translation()).norm();
      }
    });
    for (size_t i = 0; i < records.size() / 4; ++i) p.Push(records[i]);
    const RunResult& resumed = p.Finish();
    ASSERT_TRUE(resumed.distance_scale_carried.has_value());
    EXPECT_EQ(*resumed.distance_scale_carried, stored);
    EXPECT_NEAR(odometry / truth, 1.0, 0.015);
    // A damaged value is refused, naming the store's key.
    store->SetMeta("distance_scale", "7");
    MappingPipeline q(sensors::BuiltinRobot("pioneer16"), {}, store.get());
    try {
      q.Resume();
      ADD_FAILURE();
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find("distance_scale"), std::string::npos);
    }
  }
  // Paper mode and --no-correct leave the odometry as it comes.
  MappingOptions paper;
  paper.paper = true;
  MappingPipeline pp(sensors::BuiltinRobot("pioneer16"), paper, nullptr);
  for (size_t i = 0; i < 2000 && i < records.size(); ++i) pp.Push(records[i]);
  EXPECT_FALSE(pp.Finish().distance_scale_measured);
}

// Scans taken every 0.8 m or 30 degrees (as in the CARMEN logs) are too far
// apart to match against one another: auto keeps the wheels, and the map is
// the one made without it.
TEST(MappingPipeline, SparseLaserScansKeepTheWheels) {
  const sensors::RobotDescription laser = sensors::BuiltinRobot("laser");
  std::vector<sensors::LogRecord> records = SimulatedRun(1.0, "laser", 5);
  std::optional<Pose2> last;
  for (sensors::LogRecord& x : records) {
    // Keep a scan only 0.8 m or 30 degrees from the last kept (the rest odometry only).
    if (last) {
      const Pose2 d = last->inverse() * x.odom;
      if (std::hypot(d.x, d.y) < 0.8 && std::abs(d.theta) < DegToRad(30.0)) x.ranges.clear();
    }
    if (!x.ranges.empty()) last = x.odom;
  }
  auto run = [&](ScanMatch m, const std::string& name) {
    auto store = asr::SqliteAsrStore::Open(TestTempPath(name), asr::SqliteAsrStore::OpenMode::kReplace);
    MappingOptions mo;
    mo.scan_match = m;
    MappingPipeline p(laser, mo, store.get());
    for (const auto& r : records) p.Push(r);
    return p.Finish();
  };
  const RunResult a = run(ScanMatch::kAuto, "sparse_auto.sqlite"), off = run(ScanMatch::kOff, "sparse_off.sqlite");
  EXPECT_FALSE(a.scan_match_active);
  EXPECT_EQ(a.scan_match_gaps, 10);
  EXPECT_GT(a.scan_match_mean_step, 1.0);
  EXPECT_EQ(a.scan_match.scans, 0);
  ASSERT_EQ(a.graph.asrs.size(), off.graph.asrs.size());
  for (size_t i = 0; i < a.graph.asrs.size(); ++i) {
    EXPECT_EQ(a.graph.asrs[i].pose.x, off.graph.asrs[i].pose.x) << i;
    EXPECT_EQ(a.graph.asrs[i].pose.theta, off.graph.asrs[i].pose.theta) << i;
  }
}

// The pipeline pushed record by record and the whole job on the same log
// store the same ASRs at the same corrected poses.
TEST(MappingPipeline, StreamingEqualsTheJobOnTheSameLog) {
  const auto records = SimulatedRun(1.0);
  ASSERT_GT(records.size(), 1000u);
  const std::string store_path = TestTempPath("stream.sqlite");
  std::vector<int> closed;
  {
    auto store = asr::SqliteAsrStore::Open(store_path, asr::SqliteAsrStore::OpenMode::kReplace);
    MappingPipeline p(sensors::BuiltinRobot("pioneer16"), {}, store.get());
    p.OnAsrClosed([&closed](const asr::Asr& x, const AsrSummary& s) {
      EXPECT_EQ(x.id, s.id);
      closed.push_back(x.id);
    });
    for (const auto& r : records) p.Push(r);
    const RunResult& r = p.Finish();
    EXPECT_EQ(r.correction, Correction::kPoseGraph);
    EXPECT_EQ(r.records, static_cast<long>(records.size()));
    EXPECT_EQ(r.asrs.size(), closed.size());
    EXPECT_EQ(r.graph.asrs.size(), closed.size());
    ASSERT_TRUE(r.world_from_map.has_value());
  }
  ASSERT_GE(closed.size(), 9u);

  MapJob job;
  job.log_path = WriteLog(records, "run.log");
  job.output_dir = TestTempPath("out");
  auto log = io::OpenLog(job.log_path);
  // The command began 2 s before the job (as `cogmap map` says when its
  // process began): the report's whole time counts from there.
  job.started = std::chrono::steady_clock::now() - std::chrono::seconds(2);
  const MapJobSummary s = RunMapJob(*log, job);
  EXPECT_EQ(s.asrs, static_cast<int>(closed.size()));
  {
    std::ifstream in(job.output_dir + "/report.json");
    const nlohmann::json report = nlohmann::json::parse(in);
    EXPECT_EQ(report["asr_count"].get<int>(), s.asrs);
    EXPECT_EQ(report["asrs"].size(), closed.size());
    EXPECT_EQ(report["pose_graph"]["placements"].size(), closed.size());
    const double startup = report["startup_seconds"].get<double>();
    const double total = report["total_seconds"].get<double>();
    EXPECT_GE(startup, 2.0);
    EXPECT_LT(startup, 2.0 + 0.5 * (total - startup) + 1.0);
    EXPECT_GE(total, startup + report["mapping_seconds"].get<double>());
    EXPECT_NEAR(report["times_real_time"].get<double>(), report["log_duration_s"].get<double>() / total, 1e-9);
  }
  // The default outputs (issue 14's fast set).
  for (const char* f : {"map.sqlite", "plan.svg", "map.geojson", "map.map", "map.gpkg", "route_graph.geojson",
                        "plan.json", "walls.json", "report.json"})
    EXPECT_TRUE(std::filesystem::exists(job.output_dir + "/" + f)) << f;
  for (const char* f : {"map.svg", "map.png", "plan.png"})  // on request
    EXPECT_FALSE(std::filesystem::exists(job.output_dir + "/" + f)) << f;

  auto a = asr::SqliteAsrStore::Open(store_path, asr::SqliteAsrStore::OpenMode::kReadOnly);
  auto b = asr::SqliteAsrStore::Open(job.output_dir + "/map.sqlite", asr::SqliteAsrStore::OpenMode::kReadOnly);
  ASSERT_EQ(a->Ids(), b->Ids());
  for (int id : a->Ids()) {
    const auto x = *a->Get(id), y = *b->Get(id);
    // The native log keeps 6 significant digits: the same map within millimetres.
    EXPECT_NEAR(x.world_from_local_corrected.x, y.world_from_local_corrected.x, 0.01) << id;
    EXPECT_NEAR(x.world_from_local_corrected.y, y.world_from_local_corrected.y, 0.01) << id;
    EXPECT_NEAR(x.world_from_local_corrected.theta, y.world_from_local_corrected.theta, 1e-3) << id;
    EXPECT_EQ(x.walls_local.size(), y.walls_local.size()) << id;
  }
}

// Closing each ASR on a second thread changes when the callback comes, not
// the map: the same ASRs, walls, placements and estimates, bit for bit, and
// every callback on the caller's thread, in order.
TEST(MappingPipeline, SecondThreadGivesTheSameMapAsOne) {
  const auto records = SimulatedRun(1.0);
  struct Run {
    std::vector<asr::Asr> stored;
    std::vector<int> closed;
    std::vector<double> estimates;
    std::vector<Pose2> placed;
    std::vector<Eigen::Matrix3d> covariances;
  };
  auto map = [&records](int threads) {
    Run out;
    const std::string path = TestTempPath("threads" + std::to_string(threads) + ".sqlite");
    auto store = asr::SqliteAsrStore::Open(path, asr::SqliteAsrStore::OpenMode::kReplace);
    MappingOptions o;
    o.threads = threads;
    o.pre_bend = true;
    MappingPipeline p(sensors::BuiltinRobot("pioneer16"), o, store.get());
    const std::thread::id caller = std::this_thread::get_id();
    p.OnAsrClosed([&](const asr::Asr& x, const AsrSummary& s) {
      EXPECT_EQ(std::this_thread::get_id(), caller);
      out.closed.push_back(x.id);
      out.estimates.push_back(s.estimate ? s.estimate->direction_rad : -99.0);
    });
    for (const auto& r : records) p.Push(r);
    const RunResult& r = p.Finish();
    for (const auto& e : r.graph.asrs) out.placed.push_back(e.pose);
    for (const auto& e : r.graph.asrs) out.covariances.push_back(e.covariance);
    for (int id : store->Ids()) out.stored.push_back(*store->Get(id));
    return out;
  };
  const Run one = map(1), two = map(2);
  ASSERT_GE(one.closed.size(), 9u);
  EXPECT_EQ(one.closed, two.closed);
  std::vector<int> in_order(one.closed.size());
  std::iota(in_order.begin(), in_order.end(), 0);
  EXPECT_EQ(two.closed, in_order);
  EXPECT_EQ(one.estimates, two.estimates);
  ASSERT_EQ(one.placed.size(), two.placed.size());
  for (size_t i = 0; i < one.placed.size(); ++i) {
    EXPECT_EQ(one.placed[i].x, two.placed[i].x) << i;
    EXPECT_EQ(one.placed[i].theta, two.placed[i].theta) << i;
    // To the last bit, wherever the heap put the graph's blocks in each run.
    for (int a = 0; a < 9; ++a) EXPECT_EQ(one.covariances[i](a / 3, a % 3), two.covariances[i](a / 3, a % 3)) << i;
  }
  ASSERT_EQ(one.stored.size(), two.stored.size());
  // At 1 deg/m the graph pins the drift within the run: the rooms mapped
  // after that are pre-bent, by the same rate with either thread count.
  int bent = 0;
  for (const asr::Asr& a : two.stored) bent += a.pre_bend_rad_per_m != 0.0 ? 1 : 0;
  EXPECT_GE(bent, 1);
  for (size_t i = 0; i < one.stored.size(); ++i) {
    const asr::Asr &a = one.stored[i], &b = two.stored[i];
    EXPECT_EQ(a.pre_bend_rad_per_m, b.pre_bend_rad_per_m) << i;
    EXPECT_EQ(a.world_from_local_corrected.x, b.world_from_local_corrected.x) << i;
    EXPECT_EQ(a.world_from_local_corrected.theta, b.world_from_local_corrected.theta) << i;
    ASSERT_EQ(a.walls_local.size(), b.walls_local.size()) << i;
    for (size_t w = 0; w < a.walls_local.size(); ++w) EXPECT_EQ(a.walls_local[w], b.walls_local[w]) << i;
    EXPECT_EQ(a.exits.size(), b.exits.size()) << i;
  }
}

// Settle: right after a room is cut, the room still being closed on the
// mapper's threads is placed, stored and handed to the callback before
// Settle returns, as one thread does within Push.
TEST(MappingPipeline, SettleHandsOverTheRoomsBeingClosed) {
  const auto records = SimulatedRun(1.0);
  // With one thread: the record whose Push closed the fourth room.
  size_t cut = 0;
  {
    auto store = asr::SqliteAsrStore::Open(TestTempPath("settle1.sqlite"), asr::SqliteAsrStore::OpenMode::kReplace);
    MappingOptions o;
    o.threads = 1;
    MappingPipeline p(sensors::BuiltinRobot("pioneer16"), o, store.get());
    int closed = 0;
    p.OnAsrClosed([&](const asr::Asr&, const AsrSummary&) { ++closed; });
    for (size_t i = 0; i < records.size() && closed < 4; ++i) {
      p.Push(records[i]);
      cut = i;
    }
    ASSERT_EQ(closed, 4);
  }
  auto store = asr::SqliteAsrStore::Open(TestTempPath("settle2.sqlite"), asr::SqliteAsrStore::OpenMode::kReplace);
  MappingOptions o;
  o.threads = 2;
  MappingPipeline p(sensors::BuiltinRobot("pioneer16"), o, store.get());
  std::vector<int> closed;
  p.OnAsrClosed([&](const asr::Asr& x, const AsrSummary&) { closed.push_back(x.id); });
  for (size_t i = 0; i <= cut; ++i) p.Push(records[i]);
  p.Settle();
  EXPECT_EQ(closed, (std::vector<int>{0, 1, 2, 3}));
  EXPECT_EQ(store->Ids(), closed);
  // Mapping goes on after it.
  for (size_t i = cut + 1; i < records.size(); ++i) p.Push(records[i]);
  p.Finish();
  EXPECT_GT(closed.size(), 4u);
  EXPECT_EQ(store->Ids(), closed);
}

// --resume continues a copy of OUTDIR/map.sqlite: a damaged row of it is
// one error naming OUTDIR/map.sqlite (not the staging copy, which the error
// would then move aside), and the stored map is left as it was.
TEST(MapJob, ResumeIntoAStoreWithADamagedRowNamesTheUsersStore) {
  const auto records = SimulatedRun(1.0);
  const std::string log_path =
      WriteLog(std::vector<sensors::LogRecord>(records.begin(), records.begin() + records.size() / 3), "resume_bad.log");
  MapJob job;
  job.log_path = log_path;
  job.output_dir = TestTempPath("resume_damaged");
  std::filesystem::remove_all(job.output_dir);
  {
    auto log = io::OpenLog(job.log_path);
    RunMapJob(*log, job);
  }
  const std::string store_path = job.output_dir + "/map.sqlite";
  size_t poses = 0;
  {
    auto store = asr::SqliteAsrStore::Open(store_path, asr::SqliteAsrStore::OpenMode::kOpenExisting);
    asr::Asr a = *store->Get(0);
    poses = a.path.size();
    a.path_turn_rad.assign(3, 0.1);  // not one per path pose: not this ASR's
    store->Put(a);
  }
  std::ifstream in(store_path, std::ios::binary);
  const std::string before((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  job.resume = true;
  try {
    auto log = io::OpenLog(job.log_path);
    RunMapJob(*log, job);
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()),
              store_path + ": ASR 0: 3 path turns for " + std::to_string(poses) + " path poses");
  }
  std::ifstream again(store_path, std::ios::binary);
  EXPECT_EQ(std::string((std::istreambuf_iterator<char>(again)), std::istreambuf_iterator<char>()), before);
  for (const auto& e : std::filesystem::directory_iterator(job.output_dir))
    EXPECT_NE(e.path().filename().string().rfind("failed-run-", 0), 0u) << e.path();
}

// A bad line right after the first room closes: the room may still be on the
// pipeline's threads when the error comes. The failed run's partial store
// keeps it (the threads finish it before the store is looked at and closed).
TEST(MapJob, ABadLineWhileARoomIsBeingClosedKeepsThatRoomAside) {
  const auto records = SimulatedRun(1.0);
  size_t cut_at = 0;
  {
    MappingOptions o;
    o.threads = 1;
    MappingPipeline p(sensors::BuiltinRobot("pioneer16"), o, nullptr);
    size_t i = 0;
    p.OnAsrClosed([&](const asr::Asr&, const AsrSummary&) {
      if (!cut_at) cut_at = i;
    });
    for (; i < records.size() && !cut_at; ++i) p.Push(records[i]);
  }
  ASSERT_GT(cut_at, 0u);
  const std::string log_path =
      WriteLog(std::vector<sensors::LogRecord>(records.begin(), records.begin() + cut_at + 1), "cut_then_bad.log");
  {
    std::ofstream out(log_path, std::ios::app);
    out << "SWEEP 0 1 0 nan\n";
  }
  for (int trial = 0; trial < 5; ++trial) {
    MapJob job;
    job.log_path = log_path;
    job.output_dir = TestTempPath("bad_after_cut" + std::to_string(trial));
    std::string kept;
    job.notice = [&kept](const std::string& text) { kept = text.substr(0, text.find(':')); };
    auto log = io::OpenLog(job.log_path);
    EXPECT_THROW(RunMapJob(*log, job), InputError);
    ASSERT_FALSE(kept.empty()) << "trial " << trial << ": no partial result kept";
    auto store = asr::SqliteAsrStore::Open(kept + "/map.sqlite", asr::SqliteAsrStore::OpenMode::kReadOnly);
    EXPECT_EQ(store->Count(), 1) << "trial " << trial;
    EXPECT_FALSE(std::filesystem::exists(job.output_dir + "/map.sqlite"));
  }
}

// A second run resumed into the store appends ASRs with the next ids.
TEST(MappingPipeline, ResumeContinuesTheStoredRunsIds) {
  const auto records = SimulatedRun(0.0);
  const size_t half = records.size() / 2;
  const std::string store_path = TestTempPath("resume.sqlite");
  int first_run = 0;
  {
    auto store = asr::SqliteAsrStore::Open(store_path, asr::SqliteAsrStore::OpenMode::kReplace);
    MappingPipeline p(sensors::BuiltinRobot("pioneer16"), {}, store.get());
    for (size_t i = 0; i < half; ++i) p.Push(records[i]);
    first_run = static_cast<int>(p.Finish().asrs.size());
  }
  ASSERT_GT(first_run, 0);
  auto store = asr::SqliteAsrStore::Open(store_path, asr::SqliteAsrStore::OpenMode::kOpenExisting);
  MappingPipeline p(sensors::BuiltinRobot("pioneer16"), {}, store.get());
  p.Resume();
  for (size_t i = half; i < records.size(); ++i) p.Push(records[i]);
  const RunResult& r = p.Finish();
  ASSERT_FALSE(r.asrs.empty());
  EXPECT_GE(r.asrs.front().id, first_run);
  EXPECT_EQ(store->Count(), first_run + static_cast<int>(r.asrs.size()));
}

// The distinct rooms of a store (the pose graph's room identities).
size_t RoomCount(const asr::SqliteAsrStore& store) {
  std::set<int> rooms;
  for (int id : store.Ids()) rooms.insert(store.RoomOf(id));
  return rooms.size();
}

// A run killed after some ASRs (no Finish: no placements, no room ids) and
// resumed with the rest of its log ends with the rooms of the uninterrupted
// run: the cut-short ASRs are placed again, so the loop closures among them
// (the corridor seen three times) and their room identities are not lost.
// Held fixed as stored, as before, they gave one room per ASR.
// The log of a generated building of 'rooms' rooms along a corridor of
// 'corridor_m', driven by 'robot' with the given seed and heading drift.
std::vector<sensors::LogRecord> SimulatedBuilding(int rooms, double corridor_m, int seed,
                                                  const sensors::RobotDescription& robot, double drift_rad_per_m) {
  sim::BuildingOptions bo;
  bo.rooms = rooms;
  bo.corridor_m = corridor_m;
  const FloorPlan plan = sim::GenerateBuilding(bo);
  sim::SimulatorOptions so;
  so.seed = seed;
  so.odometry.drift_rad_per_m = drift_rad_per_m;
  std::vector<sensors::LogRecord> records;
  sim::Simulate(plan, robot, so, [&records](const sensors::LogRecord& r) { records.push_back(r); });
  return records;
}

// A laser run's scan odometry is decided on its first scans. A run killed
// and resumed keeps that decision (store meta scan_odometry): the resumed
// run matches scans from its first record and places the killed run's ASRs
// again with the noise model they were placed with. Before, the replayed
// ASRs were placed with the wheels' model and the run decided again on the
// tail's scans: hallway_loop's resumed maps ended at wall p95 0.47-0.57 m
// against the uninterrupted run's 0.30 (0.29-0.33 now).
TEST(MappingPipeline, ResumeAfterAKillKeepsTheLaserOdometryDecision) {
  const sensors::RobotDescription laser = sensors::BuiltinRobot("laser");
  const std::vector<sensors::LogRecord> records = SimulatedBuilding(6, 30.0, 2, laser, sim::SimulatorOptions{}.odometry.drift_rad_per_m);
  MappingOptions one_thread;
  one_thread.threads = 1;
  auto whole = asr::SqliteAsrStore::Open(TestTempPath("laser_whole.sqlite"), asr::SqliteAsrStore::OpenMode::kReplace);
  {
    MappingPipeline p(laser, one_thread, whole.get());
    for (const auto& r : records) p.Push(r);
    ASSERT_TRUE(p.Finish().scan_match_active);
  }
  const int kill_after = 4;
  const std::string path = TestTempPath("laser_killed.sqlite");
  size_t resume_at = 0;
  {
    auto store = asr::SqliteAsrStore::Open(path, asr::SqliteAsrStore::OpenMode::kReplace);
    MappingPipeline p(laser, one_thread, store.get());
    bool killed = false;
    p.OnAsrClosed([&](const asr::Asr& x, const AsrSummary&) { killed |= x.id == kill_after; });
    for (size_t i = 0; i < records.size() && !killed; ++i) {
      p.Push(records[i]);
      resume_at = i;
    }
    ASSERT_TRUE(killed);
  }  // no Finish()
  auto store = asr::SqliteAsrStore::Open(path, asr::SqliteAsrStore::OpenMode::kOpenExisting);
  EXPECT_EQ(store->GetMeta("scan_odometry").value_or(""), "1");
  MappingPipeline p(laser, one_thread, store.get());
  p.Resume();
  for (size_t i = resume_at; i < records.size(); ++i) p.Push(records[i]);
  const RunResult& r = p.Finish();
  EXPECT_TRUE(r.scan_match_active);
  EXPECT_EQ(r.replayed, kill_after + 1);
  for (int id = 0; id <= kill_after; ++id) {
    const Pose2 a = store->Get(id)->world_from_local_corrected, b = whole->Get(id)->world_from_local_corrected;
    EXPECT_NEAR(a.x, b.x, 0.05) << id;
    EXPECT_NEAR(a.y, b.y, 0.05) << id;
    EXPECT_NEAR(a.theta, b.theta, DegToRad(0.5)) << id;
  }
}

TEST(MappingPipeline, ResumeAfterAKillKeepsTheRunsLoopClosuresAndRooms) {
  const std::vector<sensors::LogRecord> records =
      SimulatedBuilding(8, 40.0, 1, sensors::BuiltinRobot("pioneer16"), DegToRad(1.0));

  // With the pre-bend (--pre-bend): the replayed ASRs are placed with the
  // drift their grids were built without, read back from the store.
  MappingOptions bent;
  bent.pre_bend = true;
  const std::string whole_path = TestTempPath("uninterrupted.sqlite");
  auto whole = asr::SqliteAsrStore::Open(whole_path, asr::SqliteAsrStore::OpenMode::kReplace);
  int whole_asrs = 0, whole_closures = 0;
  {
    MappingPipeline p(sensors::BuiltinRobot("pioneer16"), bent, whole.get());
    for (const auto& r : records) p.Push(r);
    const RunResult& r = p.Finish();
    whole_asrs = static_cast<int>(r.asrs.size());
    for (const auto& c : r.graph.closures) whole_closures += c.accepted;
  }
  ASSERT_GE(whole_closures, 2);  // the corridor is revisited and recognised
  ASSERT_LT(RoomCount(*whole), static_cast<size_t>(whole_asrs));

  // The kill: after the ASR that follows the first two accepted closures,
  // and once more after some ASRs were mapped with the drift removed (from
  // ASR 13 on in this run).
  for (const int kill_after : {6, 15}) {
    SCOPED_TRACE(kill_after);
    const std::string path = TestTempPath("killed" + std::to_string(kill_after) + ".sqlite");
    size_t resume_at = 0;
    {
      auto store = asr::SqliteAsrStore::Open(path, asr::SqliteAsrStore::OpenMode::kReplace);
      // One thread: the callback then comes right after each ASR is stored,
      // which is where this kill happens.
      MappingOptions one_thread;
      one_thread.threads = 1;
      one_thread.pre_bend = true;
      MappingPipeline p(sensors::BuiltinRobot("pioneer16"), one_thread, store.get());
      bool killed = false;
      p.OnAsrClosed([&](const asr::Asr& x, const AsrSummary&) { killed |= x.id == kill_after; });
      for (size_t i = 0; i < records.size() && !killed; ++i) {
        p.Push(records[i]);
        resume_at = i;  // the record at which the last stored ASR was written
      }
      ASSERT_TRUE(killed);
    }  // no Finish()
    auto store = asr::SqliteAsrStore::Open(path, asr::SqliteAsrStore::OpenMode::kOpenExisting);
    ASSERT_EQ(store->MaxId(), kill_after);
    EXPECT_FALSE(store->GetPlacement(0));
    MappingPipeline p(sensors::BuiltinRobot("pioneer16"), bent, store.get());
    p.Resume();
    for (size_t i = resume_at; i < records.size(); ++i) p.Push(records[i]);
    const RunResult& r = p.Finish();
    EXPECT_EQ(r.replayed, kill_after + 1);
    int closures = 0;
    for (const auto& c : r.graph.closures) closures += c.accepted;
    EXPECT_GE(closures, 2);
    // The join costs at most an ASR (the robot restarts at the last close, not at the door).
    EXPECT_NEAR(store->Count(), whole->Count(), 1);
    EXPECT_NEAR(static_cast<double>(RoomCount(*store)), static_cast<double>(RoomCount(*whole)), 1.0);
    // The join goes through the doorway the killed run left its last ASR by,
    // as in the uninterrupted run (not a width-0 exit where the tail starts).
    bool joined = false;
    for (const auto& e : store->Edges())
      if (e.from_asr == kill_after && e.to_asr == kill_after + 1) {
        joined = true;
        EXPECT_GT(e.width_m, 0.5);
      }
    EXPECT_TRUE(joined);
    // The ASRs placed again end where the uninterrupted run put them.
    int pre_bent = 0;
    for (int id = 0; id <= kill_after; ++id) {
      EXPECT_EQ(store->Get(id)->pre_bend_rad_per_m, whole->Get(id)->pre_bend_rad_per_m) << id;
      pre_bent += store->Get(id)->pre_bend_rad_per_m != 0.0 ? 1 : 0;
      const Pose2 a = store->Get(id)->world_from_local_corrected, b = whole->Get(id)->world_from_local_corrected;
      EXPECT_NEAR(a.x, b.x, 0.05) << id;
      EXPECT_NEAR(a.y, b.y, 0.05) << id;
      EXPECT_NEAR(a.theta, b.theta, DegToRad(0.5)) << id;
    }
    if (kill_after == 15) {
      EXPECT_GE(pre_bent, 1);
    }
    // A finished run is the end of a session: resumed again, nothing is replayed.
    MappingPipeline again(sensors::BuiltinRobot("pioneer16"), {}, store.get());
    again.Resume();
    EXPECT_EQ(again.Finish().replayed, 0);
  }
}

// `cogmap gen-building --rooms --corridor-m --corridor-width-m
// --room-depth-m --door-m --wing-deg --seed`.
sim::BuildingOptions Wing(int rooms, double corridor_m, double corridor_width_m, double room_depth_m,
                          double door_width_m, double wing_deg, int seed) {
  sim::BuildingOptions bo;
  bo.rooms = rooms;
  bo.corridor_m = corridor_m;
  bo.corridor_width_m = corridor_width_m;
  bo.room_depth_m = room_depth_m;
  bo.door_width_m = door_width_m;
  bo.wing_deg = wing_deg;
  bo.seed = seed;
  return bo;
}

// A generated building with a wing, driven by the 8-sonar ring with exact
// odometry (as bench/never_worse drives its random buildings): whether a
// drift was found, and each ASR's placed heading against the truth,
// relative to the first's, in degrees, sorted.
struct WingRun {
  bool drift_detected = false;
  double drift_deg_per_m = 0.0;
  std::vector<double> errors_deg;
  std::vector<std::string> warnings;  // the pose graph's
};
WingRun MapWingWithoutDrift(const sim::BuildingOptions& bo, const std::string& name, double max_time_s = 0.0) {
  // As `cogmap gen-building` and `cogmap simulate` write them: the map in
  // millimetres, the log in its own precision.
  const FloorPlan plan = io::ParseAriaMap(io::FormatAriaMap(sim::GenerateBuilding(bo)), name + ".map").plan;
  const sensors::RobotDescription robot = sensors::BuiltinRobot("pioneer8");
  sim::SimulatorOptions so;
  so.seed = 11;
  so.max_time_s = max_time_s;  // 0: from the route, as `cogmap simulate` bounds it
  so.odometry.drift_rad_per_m = 0.0;
  const std::string log_path = TestTempPath(name + ".log");
  {
    std::ofstream out(log_path);
    io::NativeLogWriter w(out, robot);
    sim::Simulate(plan, robot, so, [&w](const sensors::LogRecord& r) { w.Write(r); });
  }
  auto store = asr::SqliteAsrStore::Open(TestTempPath(name + ".sqlite"), asr::SqliteAsrStore::OpenMode::kReplace);
  MappingPipeline p(robot, {}, store.get());
  std::map<int, double> truth;  // each ASR's first true heading
  p.OnAsrClosed([&](const asr::Asr& x, const AsrSummary&) {
    // The ASR's frame is its first raw pose; its truth, the same instant's.
    if (!x.true_path.empty() && !x.path.empty())
      truth[x.id] = NormalizeAngle(x.true_path.front().theta - (x.path.front().theta - x.world_from_local_raw.theta));
  });
  auto log = io::OpenLog(log_path);
  for (sensors::LogRecord rec; log->Next(&rec);) p.Push(rec);
  const RunResult& r = p.Finish();
  EXPECT_EQ(r.correction, Correction::kPoseGraph);
  WingRun out;
  out.drift_detected = r.graph.drift_detected;
  out.drift_deg_per_m = RadToDeg(r.graph.drift_rate_rad_per_m);
  out.warnings = r.graph.warnings;
  std::optional<double> first;
  for (const graph::AsrEstimate& e : r.graph.asrs) {
    const auto t = truth.find(e.asr_id);
    if (t == truth.end()) continue;
    const double d = NormalizeAngle(e.pose.theta - t->second);
    if (!first) first = d;
    out.errors_deg.push_back(RadToDeg(std::abs(NormalizeAngle(d - *first))));
  }
  std::sort(out.errors_deg.begin(), out.errors_deg.end());
  return out;
}

// A generated building whose second wing turns 35 degrees clockwise (six
// rooms on a 40 m corridor and six more in the wing). Its rooms' walls read
// 0 degrees before the wing and -34 in it, a few rooms 6-13 degrees off.
// One grouping of them is the wing, which needs no drift; another, 18
// degrees apart, fitted the walls a little better (a chi2 of 1.2) at a
// drift of -0.28 deg/m that the walls need under it. Ranked by that chi2
// alone, the map took the drift: heading errors up to 32 degrees (median
// 17) where the odometry's stay under 2.3 (bench/never_worse, seed 44).
// Against a grouping that needs none, a drift must clear the drift test's
// quantile: no drift is found, and the map keeps the odometry's headings.
TEST(MappingPipeline, AWingWithoutDriftIsNotReadAsADrift) {
  const WingRun run = MapWingWithoutDrift(Wing(6, 40.0, 2.5, 8.0, 0.9, -35.0, 17), "wing35", 900.0);
  EXPECT_FALSE(run.drift_detected) << run.drift_deg_per_m << " deg/m";
  ASSERT_GE(run.errors_deg.size(), 20u);
  EXPECT_LT(run.errors_deg[run.errors_deg.size() / 2], 2.0);
  EXPECT_LT(run.errors_deg.back(), 6.0);
}

// A wing turned 45 degrees, half-way between two quarter-turn branches
// (twelve rooms on a 40 m corridor and twelve more in the wing). The wing
// as it is, two directions 44 degrees apart without drift, cleared the
// test; but three directions (12, 28 and -42 degrees) at a drift of -0.37
// deg/m then replaced it, their likelihood better by a chi2 of 13.2 against
// the quantile of one direction more (12.1). The drift they need is a
// parameter more (against two, 15.2): counted, the wing stands. Before, the
// map's heading median was 27 degrees (the odometry's 0.4) and its ATE
// 5.2 m (0.3; bench/never_worse, seed 45).
TEST(MappingPipeline, AThirdDirectionAndADriftAreTwoParametersMore) {
  const WingRun run = MapWingWithoutDrift(Wing(12, 40.0, 2.5, 4.5, 0.9, -45.0, 20), "wing45");
  EXPECT_FALSE(run.drift_detected) << run.drift_deg_per_m << " deg/m";
  ASSERT_GE(run.errors_deg.size(), 30u);
  EXPECT_LT(run.errors_deg[run.errors_deg.size() / 2], 2.0);
  EXPECT_LT(run.errors_deg.back(), 6.0);
}

// A wing turned 15 degrees (six rooms on a 25 m corridor 3 m wide, and six
// in the wing), the 8-sonar ring, exact odometry. The walls find a drift of
// 0.23 deg/m with one building direction (the wing read as a ramp), and the
// wing without drift fits them about as well (1.2:1 against it): the map
// keeps the drift, and its headings are off by 10 degrees (median; the
// odometry's 0.5). The covariances hold both maps; the warning says so,
// naming the wing, where before the run warned only of uncertain ASRs.
TEST(MappingPipeline, ADriftThatAWingFitsAsWellIsWarnedOf) {
  const WingRun run = MapWingWithoutDrift(Wing(6, 25.0, 3.0, 4.5, 1.0, 15.0, 28), "wing15");
  ASSERT_TRUE(run.drift_detected);
  int named = 0;
  for (const std::string& w : run.warnings)
    named += w.rfind("a drift of", 0) == 0 && w.find("a wing turned") != std::string::npos &&
             w.find("without drift") != std::string::npos;
  EXPECT_EQ(named, 1) << ::testing::PrintToString(run.warnings);
}

}  // namespace
}  // namespace cogmap::mapping
