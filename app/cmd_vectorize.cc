// `cogmap vectorize` (mapping::RunVectorizeJob: a whole log as one space, its
// MHIMM grid turned into wall polylines, SPEC 3) and `cogmap eval`
// (mapping::EvaluateFolder): options in, one library call, a summary out.
#include <cstdio>
#include <iostream>
#include <string>

#include "app/cli_util.h"
#include "app/command.h"
#include "app/progress.h"
#include "cogmap/core/error.h"
#include "cogmap/io/log_reader.h"
#include "cogmap/mapping/evaluate.h"
#include "cogmap/mapping/vectorize_job.h"
#include "cogmap/sensors/robot_json.h"

namespace cogmap::app {
namespace {

struct VectorizeArgs {
  mapping::VectorizeJob job;  // the options bind to its fields
  std::string mode = "default";
  std::string keep;
  std::string walls = "default";
};

int RunVectorize(VectorizeArgs& a) {
  mapping::VectorizeJob& job = a.job;
  job.Validate();
  if (a.mode != "paper" && a.mode != "default") throw InputError("--mode " + a.mode + ": expected paper or default");
  job.paper = a.mode == "paper";
  if (a.keep == "face") job.keep = vectorize::KeepCell::kFace;
  else if (a.keep == "middle") job.keep = vectorize::KeepCell::kRunMiddle;
  else if (!a.keep.empty()) throw InputError("--keep " + a.keep + ": expected face or middle");
  if (a.walls != "default" && a.walls != "lines" && a.walls != "chains")
    throw InputError("--walls " + a.walls + ": expected lines or chains");
  if (a.walls != "default") job.wall_lines = a.walls == "lines";
  ProgressBar bar("vectorize");
  job.progress = [&bar](double f) { bar.Update(f); };
  job.notice = [&bar](const std::string& s) {
    bar.Finish();
    std::fprintf(stderr, "cogmap: %s\n", s.c_str());
  };
  auto log = io::OpenLog(job.log_path, job.log_format);
  const mapping::VectorizeJobResult out = mapping::RunVectorizeJob(*log, job);
  bar.Finish();

  const vectorize::VectorizeResult& r = out.walls;
  auto ll = [](int64_t v) { return static_cast<long long>(v); };
  std::printf("%s: %ld records, grid %dx%d, %lld occupied -> %lld cleaned -> %lld points -> %zu polylines, "
              "%lld vertices; bytes grid %lld / vertices %lld / polylines %lld; vectorize %.1f ms -> %s\n",
              job.log_path.c_str(), out.records, out.limits.width(), out.limits.height(), ll(r.clean_stats.occupied_in),
              ll(r.clean_stats.kept), ll(r.extract_stats.points), r.polylines.size(), ll(r.vertex_count),
              ll(r.bytes.grid), ll(r.bytes.vertices), ll(r.bytes.polylines), r.seconds.total() * 1e3,
              job.output_dir.c_str());
  if (r.polylines.empty()) {
    if (r.clean_stats.occupied_in == 0)
      std::printf("no walls: the grid has no occupied cells (no echo nearer than the window)\n");
    else if (r.clean_stats.path_cells == 0)
      std::printf("no walls: the grid has no robot path, so cleaning keeps nothing\n");
    else
      std::printf("no walls: no occupied cell is seen from the path within the window\n");
  }
  return 0;
}

std::function<int()> SetupVectorize(CLI::App& sub) {
  auto a = std::make_shared<VectorizeArgs>();
  sub.add_option("LOG", a->job.log_path, "The log (any format cogmap reads), mapped as one space")->required();
  sub.add_option("--format", a->job.log_format, "Log format: " + Join(io::LogFormatNames()) + " (default auto)")
      ->capture_default_str();
  sub.add_option("--robot", a->job.robot_spec,
                 "Robot: a built-in name (" + Join(sensors::BuiltinRobotNames()) +
                     ") or a robot JSON file (default: the log's own robot, else pioneer16)");
  sub.add_flag("--axis-walls", [a](int64_t) { a->job.cone_hits = false; },
               "Default mode, sonar: fuse each echo on its axis alone, as the thesis (by default each echo is fused over the sonar's cone: the cone nearer than the echo is free, weighted towards the axis, and the echo goes on its arc, at the cell nearest the axis not known empty; walls at the true poses are better on every bench world; docs/walls.md, \"Sonar cone\")");
  sub.add_flag("--sonar-cone", a->job.cone_hits, "The default (kept for scripts that ask for it)");
  sub.add_option("--cell", a->job.cell_m, "Cell size in metres")->capture_default_str();
  sub.add_option("--window", a->job.window_m,
                 "Window w in metres (MHIMM hits nearer than w; also the cleaning range max_dist)")
      ->capture_default_str();
  sub.add_option("--mode", a->mode,
                 "Line fit: paper (least squares + Pearson |rho| >= 0.9) or default (total least "
                 "squares, rotation-invariant test, corners closed)")
      ->capture_default_str();
  sub.add_flag("--truth", a->job.use_truth, "Fuse at the log's ground-truth poses instead of odometry");
  sub.add_option("--walls", a->walls,
                 "Default mode: chains (the thesis's simplify and fit; what default means) or lines (walls as "
                 "lines in the occupancy evidence, docs/walls.md); paper mode always uses chains")
      ->capture_default_str();
  sub.add_option("--keep", a->keep,
                 "Cell a wall keeps when cleaned: face (the paper) or middle (of the band behind the "
                 "face; the default mode's)");
  sub.add_option("--gamma", a->job.gamma_cells, "Extract: a step longer than this (cells) ends a polyline (4)");
  sub.add_option("--tau", a->job.tau_cells, "Vertex simplify tolerance, cells (2)");
  sub.add_option("--eta", a->job.eta_cells, "Douglas-Peucker tolerance, cells (1.5)");
  sub.add_option("--max-rms", a->job.max_rms_cells, "Default fit: largest RMS residual of a straight edge, cells");
  sub.add_option("--min-chain", a->job.min_chain_points,
                 "Chains of fewer extracted cells are not walls (default: the mode's)");
  sub.add_option("--smooth", a->job.smooth_half_window,
                 "Moving mean over this many points either side along each extracted chain (0 = off)");
  sub.add_option("-o,--output", a->job.output_dir,
                 "Folder to write walls.svg, walls.json, stages.png and report.json into (staged as cogmap map's: a "
                 "failed run leaves the previous outputs untouched)")
      ->required();
  return [a] { return RunVectorize(*a); };
}

struct EvalArgs {
  std::string dir;
  std::string world;
  double range_m = -1.0;
  bool json = false;
  std::string png;
  std::string rooms;
};

int RunEval(const EvalArgs& a) {
  mapping::EvaluateOptions o;
  o.world = a.world;
  o.range_m = a.range_m;
  o.png = a.png;
  o.rooms = a.rooms;
  const mapping::Evaluation e = mapping::EvaluateFolder(a.dir, o);
  if (a.json) std::cout << e.metrics.dump(2) << "\n";
  else std::fputs(e.text.c_str(), stdout);
  return 0;
}

std::function<int()> SetupEval(CLI::App& sub) {
  auto a = std::make_shared<EvalArgs>();
  sub.add_option("OUTDIR", a->dir, "A folder written by cogmap vectorize or cogmap map (or its walls.json); with a map.sqlite beside it, also ASR count, room precision/recall, heading errors, the trajectory errors (ATE, RPE over 1/5/20 m; corrected, and the odometry as the store holds it, keys ending _raw: scaled when map applied a distance scale) and, for a map placed by the pose graph, the calibration of its covariances (pose_calibration_3sigma: share of placed ASRs whose true pose, relative to the first ASR, is within 3 sigma); with a plan.json beside it, the floor plan's wall precision (p50/p95), recall, duplication, room IoU median, room overlap and vertices per metre (docs/floor-plan.md)")->required();
  sub.add_option("--world", a->world,
                 "The world the log was driven in (ARIA 2D-Map or PNG); without it only the heading errors "
                 "(against the log's reference poses) and the sizes are reported");
  sub.add_option("--range", a->range_m,
                 "Sensor range for recall, metres (default: the effective range recorded by vectorize, "
                 "min(max range, window))");
  sub.add_option("--rooms", a->rooms,
                 "The true rooms as a room-segmentation image of a PNG world (the benchmark's "
                 "*_gt_segmentation.png: each room a region of white or coloured pixels, doors closed; placed as "
                 "the world's pixels): room precision/recall and the floor plan's room IoU against them instead of "
                 "the world's Room cairns");
  sub.add_flag("--json", a->json, "Print the metrics as JSON");
  sub.add_option("--png", a->png, "Also draw the map walls (black, red vertices) over the true walls (light blue)");
  return [a] { return RunEval(*a); };
}

const bool kVectorize = RegisterCommand(
    {"vectorize", "Turn a whole log's MHIMM grid into wall polylines (clean, extract, simplify, fit)", 40,
     SetupVectorize});
const bool kEval = RegisterCommand(
    {"eval", "Score a vectorize or map folder against a world: walls, rooms, headings, bytes", 41, SetupEval});

}  // namespace
}  // namespace cogmap::app
