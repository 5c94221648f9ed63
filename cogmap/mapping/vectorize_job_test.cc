// `cogmap vectorize` as a library call, on a corridor log built in code.
#include "cogmap/mapping/vectorize_job.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "cogmap/core/error.h"
#include "cogmap/core/test_temp.h"
#include "cogmap/io/log_reader.h"
#include "cogmap/io/polyline_io.h"
#include "cogmap/mapping/job_test_util.h"

namespace cogmap::mapping {
namespace {

namespace fs = std::filesystem;
using ::cogmap::testing_util::TestTempPath;
using testing_util::CorridorRecords;
using testing_util::WriteCorridorLog;

std::string ReadText(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

// Names in 'dir' that a finished run must not leave: staging or failed-run folders.
std::vector<std::string> Leftovers(const std::string& dir) {
  std::vector<std::string> out;
  for (const auto& e : fs::directory_iterator(dir)) {
    const std::string n = e.path().filename().string();
    if (n.rfind(".staging-", 0) == 0 || n.rfind("failed-run-", 0) == 0) out.push_back(n);
  }
  return out;
}

TEST(VectorizeJob, StageOptionsAreTheModesWithTheOverrides) {
  VectorizeJob job;
  job.cell_m = 0.05;
  job.window_m = 2.5;
  vectorize::VectorizeOptions d = job.StageOptions();
  EXPECT_EQ(d.clean.keep, vectorize::KeepCell::kRunMiddle);
  EXPECT_EQ(d.clean.max_dist_cells, 50);  // window / cell
  EXPECT_EQ(d.min_chain_points, vectorize::VectorizeOptions{}.min_chain_points);
  job.paper = true;
  job.gamma_cells = 3;
  job.tau_cells = 1.5;
  job.eta_cells = 1;
  job.max_rms_cells = 0.8;
  job.min_chain_points = 5;
  job.smooth_half_window = 2;
  job.keep = vectorize::KeepCell::kRunMiddle;
  const vectorize::VectorizeOptions p = job.StageOptions();
  EXPECT_EQ(p.fit.mode, vectorize::VectorizeOptions::Paper().fit.mode);
  EXPECT_EQ(p.clean.keep, vectorize::KeepCell::kRunMiddle);  // the override beats the paper's face
  EXPECT_EQ(p.extract.gamma_cells, 3);
  EXPECT_EQ(p.vertex_simplify.tau_cells, 1.5);
  EXPECT_EQ(p.douglas_peucker.eta_cells, 1);
  EXPECT_EQ(p.fit.max_rms_cells, 0.8);
  EXPECT_EQ(p.min_chain_points, 5);
  EXPECT_EQ(p.smooth_half_window, 2);
  job = {};
  job.paper = true;
  EXPECT_EQ(job.StageOptions().clean.keep, vectorize::KeepCell::kFace);
}

TEST(VectorizeJob, FindsTheCorridorWallsAndWritesEveryOutput) {
  const auto records = CorridorRecords();
  long echoes = 0;
  for (const auto& r : records)
    for (const auto& x : r.ranges) echoes += x.range_m < 8.0 ? 1 : 0;
  const std::string log_path = WriteCorridorLog("vec_corridor.log", records);
  VectorizeJob job;
  job.log_path = log_path;
  job.output_dir = TestTempPath("vec_corridor");
  auto log = io::OpenLog(log_path);
  const VectorizeJobResult r = RunVectorizeJob(*log, job);
  EXPECT_EQ(r.records, 81);
  EXPECT_EQ(r.readings, 81 * 19);
  EXPECT_EQ(r.echoes, echoes);
  EXPECT_EQ(r.truth_records, 81);
  EXPECT_EQ(r.robot.name, "corridor-laser");
  EXPECT_EQ(r.world_from_map.x, 0.0);  // odometry = truth
  EXPECT_EQ(r.world_from_map.y, 0.0);
  // Every wall vertex near one of the corridor's walls (within a cell and a half).
  ASSERT_FALSE(r.walls.polylines.empty());
  double near_top = 0, near_bottom = 0;
  for (const auto& line : r.walls.polylines)
    for (const Vec2& v : line) {
      const double d = std::min({std::abs(v.y() - 1.0), std::abs(v.y() + 1.0), std::abs(v.x() - 6.0)});
      EXPECT_LT(d, 0.15) << v.transpose();
      near_top += std::abs(v.y() - 1.0) < 0.15 ? 1 : 0;
      near_bottom += std::abs(v.y() + 1.0) < 0.15 ? 1 : 0;
    }
  EXPECT_GE(near_top, 2);
  EXPECT_GE(near_bottom, 2);

  // The files, moved into place; walls.json holds the result's walls.
  for (const char* f : {"walls.json", "walls.svg", "stages.png", "report.json"})
    EXPECT_TRUE(fs::exists(fs::path(job.output_dir) / f)) << f;
  EXPECT_EQ(r.written.size(), 4u);
  EXPECT_TRUE(Leftovers(job.output_dir).empty());
  const io::WallsFile wf = io::ReadWallsJson((fs::path(job.output_dir) / "walls.json").string());
  ASSERT_EQ(wf.polylines.size(), r.walls.polylines.size());
  EXPECT_EQ(wf.vertex_count, r.walls.vertex_count);
  EXPECT_EQ(wf.robot, "corridor-laser");
  EXPECT_EQ(wf.mode, "default");
  EXPECT_TRUE(wf.has_truth);
  EXPECT_EQ(wf.sensor_range_m, 3.0);  // min(8 m range, 3 m window)
  EXPECT_EQ(r.report["records"], 81);
  EXPECT_EQ(r.report["counts"]["polylines"], r.walls.polylines.size());
  EXPECT_EQ(r.report["fused_at"], "odometry");
}

TEST(VectorizeJob, OdometryFrameIsPlacedInTheTruthsWorld) {
  const std::string log_path = WriteCorridorLog("vec_offset.log", CorridorRecords(81, Vec2(0.0, 0.5)));
  VectorizeJob job;
  job.log_path = log_path;
  job.output_dir = TestTempPath("vec_offset");
  auto log = io::OpenLog(log_path);
  const VectorizeJobResult odom = RunVectorizeJob(*log, job);
  EXPECT_NEAR(odom.world_from_map.x, 0.0, 1e-12);
  EXPECT_NEAR(odom.world_from_map.y, -0.5, 1e-12);
  EXPECT_NEAR(odom.world_from_map.theta, 0.0, 1e-12);
  for (const auto& line : odom.walls.polylines)  // the map frame: walls 0.5 m up
    for (const Vec2& v : line)
      EXPECT_LT(std::min({std::abs(v.y() - 1.5), std::abs(v.y() + 0.5), std::abs(v.x() - 6.0)}), 0.15);
  job.use_truth = true;
  auto log2 = io::OpenLog(log_path);
  const VectorizeJobResult truth = RunVectorizeJob(*log2, job);
  EXPECT_EQ(truth.world_from_map.y, 0.0);  // fused in the truth's frame
  EXPECT_EQ(truth.report["fused_at"], "truth");
}

TEST(VectorizeJob, AFailedRunLeavesThePreviousOutputsUntouched) {
  const auto records = CorridorRecords();
  const std::string good = WriteCorridorLog("vec_good.log", records);
  VectorizeJob job;
  job.log_path = good;
  job.output_dir = TestTempPath("vec_failed");
  auto log = io::OpenLog(good);
  RunVectorizeJob(*log, job);
  const std::string walls = ReadText(job.output_dir + "/walls.json");
  const std::string report = ReadText(job.output_dir + "/report.json");
  // The same log cut in the middle of a record: the reader throws after 40 records.
  std::string text = ReadText(good);
  size_t cut = 0;
  for (int i = 0; i < 40 * 3 + 1; ++i) cut = text.find('\n', cut) + 1;
  const std::string bad = TestTempPath("vec_bad.log");
  std::ofstream(bad) << text.substr(0, cut) << "SWEEP 1 2 3\n";
  job.log_path = bad;
  auto bad_log = io::OpenLog(bad);
  EXPECT_THROW(RunVectorizeJob(*bad_log, job), InputError);
  EXPECT_EQ(ReadText(job.output_dir + "/walls.json"), walls);
  EXPECT_EQ(ReadText(job.output_dir + "/report.json"), report);
  EXPECT_TRUE(Leftovers(job.output_dir).empty());  // nothing was staged
}

TEST(VectorizeJob, RejectsBadOptionsNamingThem) {
  VectorizeJob job;
  job.window_m = -1;
  try {
    job.Validate();
    FAIL();
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()), "--window -1: must be in [0.1, 100] metres (a cell at least)");
  }
  job.window_m = 3;
  job.cell_m = 11;
  EXPECT_THROW(job.Validate(), InputError);
  // A stage's length: unset (-1) or one a grid can have; NaN was ignored.
  job.cell_m = 0.1;
  job.tau_cells = std::nan("");
  try {
    job.Validate();
    FAIL();
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()), "--tau nan: must be in (0, 1000] cells");
  }
  job.tau_cells = -1;
  EXPECT_NO_THROW(job.Validate());
}

}  // namespace
}  // namespace cogmap::mapping
