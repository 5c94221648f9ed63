// `cogmap vectorize`: a whole log as one space, its MHIMM grid turned into
// wall polylines (SPEC 3), with the stages as pictures and a report.
// `cogmap eval`: those walls against a world's true walls.
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <map>
#include <optional>
#include <nlohmann/json.hpp>
#include <string>

#include "app/cli_util.h"
#include "app/command.h"
#include "app/progress.h"
#include "cogmap/asr/room_metrics.h"
#include "cogmap/asr/store.h"
#include "cogmap/core/error.h"
#include "cogmap/eval/plan_metrics.h"
#include "cogmap/eval/trajectory_metrics.h"
#include "cogmap/eval/wall_metrics.h"
#include "cogmap/grid/range_fusion.h"
#include "cogmap/io/atomic_file.h"
#include "cogmap/io/image.h"
#include "cogmap/io/log_reader.h"
#include "cogmap/io/polyline_io.h"
#include "cogmap/draw/stages_picture.h"
#include "cogmap/io/world_io.h"
#include "cogmap/localize/heading_error.h"
#include "cogmap/mapping/evaluate.h"
#include "cogmap/plan/plan_json.h"
#include "cogmap/sensors/robot_json.h"
#include "cogmap/vectorize/vectorize.h"

namespace cogmap::app {
namespace {

struct VectorizeArgs {
  std::string log;
  std::string format = "auto";
  std::string robot;
  double cell_m = 0.1;
  double window_m = 3.0;
  std::string mode = "default";
  std::string outdir;
  bool truth = false;
  // Stage overrides (< 0: the mode's default).
  double gamma_cells = -1, tau_cells = -1, eta_cells = -1, max_rms_cells = -1;
  int min_chain_points = -1;
  int smooth = -1;
  std::string keep;
};

nlohmann::json PoseJson(const Pose2& p) { return {{"x", p.x}, {"y", p.y}, {"theta", p.theta}}; }

int RunVectorize(const VectorizeArgs& a) {
  if (!(a.cell_m > 0.0) || a.cell_m > 10.0) throw InputError("--cell " + Num(a.cell_m) + ": must be in (0, 10] metres");
  if (!(a.window_m > 0.0)) throw InputError("--window " + Num(a.window_m) + ": must be positive");
  if (a.mode != "paper" && a.mode != "default")
    throw InputError("--mode " + a.mode + ": expected paper or default");
  std::error_code ec;
  std::filesystem::create_directories(a.outdir, ec);
  if (ec || !std::filesystem::is_directory(a.outdir))
    throw InputError(a.outdir, 0, "cannot create the output folder");

  auto log = io::OpenLog(a.log, a.format);
  sensors::RobotDescription robot;
  if (!a.robot.empty()) robot = sensors::ResolveRobot(a.robot);
  else if (auto hint = log->robot_hint()) robot = *hint;
  else robot = sensors::BuiltinRobot("pioneer16");
  double max_range_m = 0.0;
  for (const auto& s : robot.sensors) max_range_m = std::max(max_range_m, s.max_range_m);

  grid::FusionOptions fo;
  fo.bounds.cell_m = a.cell_m;
  fo.mhimm.window_m = a.window_m;
  auto fusion = grid::MakeFusion(grid::FusionRule::kMhimm, fo);

  // Fuse the whole log as one space.
  const auto t_grid = std::chrono::steady_clock::now();
  ProgressBar bar("vectorize");
  sensors::LogRecord rec;
  long records = 0, readings = 0, echoes = 0, truth_records = 0;
  std::optional<Pose2> first_odom, first_truth;
  Polyline path;  // the fused poses, thinned to 5 cm (for walls.svg)
  while (log->Next(&rec)) {
    ++records;
    if (rec.truth) {
      ++truth_records;
      if (!first_truth) first_truth = rec.truth, first_odom = rec.odom;
    }
    const Pose2 pose = (a.truth && rec.truth) ? *rec.truth : rec.odom;
    fusion->InsertSweep(pose, robot, rec.ranges);
    if (path.empty() || (pose.translation() - path.back()).norm() >= 0.05) path.push_back(pose.translation());
    readings += static_cast<long>(rec.ranges.size());
    for (const auto& r : rec.ranges)
      if (r.sensor >= 0 && r.sensor < static_cast<int>(robot.sensors.size()) &&
          r.range_m < robot.sensors[r.sensor].max_range_m)
        ++echoes;
    if ((records & 255) == 0) bar.Update(log->progress());
  }
  bar.Finish();
  if (records == 0) throw InputError(a.log, 0, "the log has no records");
  const double grid_s = Seconds(t_grid);
  const auto* himm = dynamic_cast<const grid::HimmFusion*>(fusion.get());
  const grid::Grid2D<float>& values = himm->values();

  vectorize::VectorizeOptions vo = a.mode == "paper" ? vectorize::VectorizeOptions::Paper() : vectorize::VectorizeOptions{};
  vo.clean.max_dist_cells = std::max(1, static_cast<int>(std::lround(a.window_m / a.cell_m)));
  if (a.gamma_cells > 0) vo.extract.gamma_cells = a.gamma_cells;
  if (a.tau_cells > 0) vo.vertex_simplify.tau_cells = a.tau_cells;
  if (a.eta_cells > 0) vo.douglas_peucker.eta_cells = a.eta_cells;
  if (a.max_rms_cells > 0) vo.fit.max_rms_cells = a.max_rms_cells;
  if (a.min_chain_points >= 0) vo.min_chain_points = a.min_chain_points;
  if (a.smooth >= 0) vo.smooth_half_window = a.smooth;
  if (a.keep == "face") vo.clean.keep = vectorize::KeepCell::kFace;
  else if (a.keep == "middle") vo.clean.keep = vectorize::KeepCell::kRunMiddle;
  else if (!a.keep.empty()) throw InputError("--keep " + a.keep + ": expected face or middle");
  const vectorize::VectorizeResult r = vectorize::Vectorize(values, vo);

  // The map frame is the odometry frame; its pose in the truth's world.
  Pose2 world_from_map;
  if (first_truth && !a.truth) world_from_map = (*first_truth) * first_odom->inverse();

  io::WallsFile wf;
  wf.polylines = r.polylines;
  wf.world_from_map = world_from_map;
  wf.has_truth = truth_records > 0;
  wf.log_path = std::filesystem::absolute(a.log).lexically_normal().string();
  wf.log_format = a.format;
  wf.robot = a.robot.empty() ? robot.name : a.robot;
  wf.mode = a.mode;
  wf.cell_m = a.cell_m;
  // The effective range (SPEC 3.1): no reading beyond the window marks a wall.
  wf.sensor_range_m = std::min(max_range_m, a.window_m);
  wf.vertex_count = r.vertex_count;
  wf.bytes_grid = r.bytes.grid;
  wf.bytes_vertices = r.bytes.vertices;
  wf.bytes_polylines = r.bytes.polylines;
  const std::filesystem::path out(a.outdir);
  io::WriteWallsJson((out / "walls.json").string(), wf);

  const auto& lim = values.limits();
  // walls.svg: the walls (black, vertices red) over the path (faint).
  draw::PictureOptions walls_picture;
  walls_picture.title = "Walls: " + std::filesystem::path(a.log).filename().string();
  draw::DrawWalls(r.polylines, {}, path, walls_picture).drawing.Write((out / "walls.svg").string());

  draw::DrawStages(values, r).Write((out / "stages.png").string());

  nlohmann::json rep;
  rep["log"] = wf.log_path;
  rep["log_format"] = a.format;
  rep["robot"] = robot.name;
  rep["mode"] = a.mode;
  rep["records"] = records;
  rep["readings"] = readings;
  rep["echoes"] = echoes;
  rep["truth_records"] = truth_records;
  rep["fused_at"] = a.truth ? "truth" : "odometry";
  rep["world_from_map"] = PoseJson(world_from_map);
  rep["grid"] = {{"width", lim.width()}, {"height", lim.height()}, {"cell_m", lim.cell_m()},
                 {"origin", {lim.origin().x(), lim.origin().y()}}};
  rep["options"] = {
      {"cell_m", a.cell_m},
      {"window_m", a.window_m},
      {"epsilon", vo.clean.classes.occupied_above},
      {"max_dist_cells", vo.clean.max_dist_cells},
      {"gamma_cells", vo.extract.gamma_cells},
      {"close_loops", vo.extract.close_loops},
      {"clean_keep", vo.clean.keep == vectorize::KeepCell::kFace ? "face" : "middle"},
      {"tau_cells", vo.vertex_simplify.tau_cells},
      {"eta_cells", vo.douglas_peucker.eta_cells},
      {"fit_mode", a.mode},
      {"min_abs_pearson", vo.fit.min_abs_pearson},
      {"max_rms_cells", vo.fit.max_rms_cells},
      {"min_corner_deg", vo.fit.min_corner_deg},
      {"min_chain_points", vo.min_chain_points},
      {"smooth_half_window", vo.smooth_half_window},
      {"quantum_mm", vo.codec.quantum_mm}};
  rep["counts"] = {{"occupied_cells", r.clean_stats.occupied_in},
                   {"cleaned_cells", r.clean_stats.kept},
                   {"path_cells", r.clean_stats.path_cells},
                   {"extracted_points", r.extract_stats.points},
                   {"chains", r.extract_stats.chains},
                   {"closed_chains", r.extract_stats.closed},
                   {"dropped_chains", r.dropped_chains},
                   {"vertices_after_vertex_simplify", r.vertices_after_vertex_simplify},
                   {"polylines", r.polylines.size()},
                   {"vertex_count", r.vertex_count},
                   {"edges", r.fit_stats.edges},
                   {"fits_accepted", r.fit_stats.fitted},
                   {"fits_rejected", r.fit_stats.rejected},
                   {"edges_too_few_points", r.fit_stats.too_few_points},
                   {"corners_joined", r.fit_stats.corners_joined},
                   {"chamfers_removed", r.fit_stats.chamfers_removed}};
  rep["bytes"] = {{"grid", r.bytes.grid}, {"vertices", r.bytes.vertices}, {"polylines", r.bytes.polylines}};
  rep["seconds"] = {{"grid", grid_s},
                    {"clean", r.seconds.clean},
                    {"extract", r.seconds.extract},
                    {"simplify", r.seconds.simplify},
                    {"fit", r.seconds.fit},
                    {"vectorize_total", r.seconds.total()}};
  io::WriteFileAtomically((out / "report.json").string(), rep.dump(2) + "\n");

  std::printf("%s: %ld records, grid %dx%d, %lld occupied -> %lld cleaned -> %lld points -> %zu polylines, "
              "%lld vertices; bytes grid %lld / vertices %lld / polylines %lld; vectorize %.1f ms -> %s\n",
              a.log.c_str(), records, lim.width(), lim.height(), static_cast<long long>(r.clean_stats.occupied_in),
              static_cast<long long>(r.clean_stats.kept), static_cast<long long>(r.extract_stats.points),
              r.polylines.size(), static_cast<long long>(r.vertex_count), static_cast<long long>(r.bytes.grid),
              static_cast<long long>(r.bytes.vertices), static_cast<long long>(r.bytes.polylines),
              r.seconds.total() * 1e3, a.outdir.c_str());
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
  sub.add_option("LOG", a->log, "The log (any format cogmap reads), mapped as one space")->required();
  sub.add_option("--format", a->format, "Log format: " + Join(io::LogFormatNames()) + " (default auto)")
      ->capture_default_str();
  sub.add_option("--robot", a->robot,
                 "Robot: a built-in name (" + Join(sensors::BuiltinRobotNames()) +
                     ") or a robot JSON file (default: the log's own robot, else pioneer16)");
  sub.add_option("--cell", a->cell_m, "Cell size in metres")->capture_default_str();
  sub.add_option("--window", a->window_m,
                 "Window w in metres (MHIMM hits nearer than w; also the cleaning range max_dist)")
      ->capture_default_str();
  sub.add_option("--mode", a->mode,
                 "Line fit: paper (least squares + Pearson |rho| >= 0.9) or default (total least "
                 "squares, rotation-invariant test, corners closed)")
      ->capture_default_str();
  sub.add_flag("--truth", a->truth, "Fuse at the log's ground-truth poses instead of odometry");
  sub.add_option("--keep", a->keep,
                 "Cell a wall keeps when cleaned: face (the paper) or middle (of the band behind the "
                 "face; the default mode's)");
  sub.add_option("--gamma", a->gamma_cells, "Extract: a step longer than this (cells) ends a polyline (4)");
  sub.add_option("--tau", a->tau_cells, "Vertex simplify tolerance, cells (2)");
  sub.add_option("--eta", a->eta_cells, "Douglas-Peucker tolerance, cells (1.5)");
  sub.add_option("--max-rms", a->max_rms_cells, "Default fit: largest RMS residual of a straight edge, cells");
  sub.add_option("--min-chain", a->min_chain_points,
                 "Chains of fewer extracted cells are not walls (default: the mode's)");
  sub.add_option("--smooth", a->smooth,
                 "Moving mean over this many points either side along each extracted chain (0 = off)");
  sub.add_option("-o,--output", a->outdir,
                 "Folder to write walls.svg, walls.json, stages.png and report.json into")
      ->required();
  return [a] { return RunVectorize(*a); };
}

struct EvalArgs {
  std::string dir;
  std::string world;
  double range_m = -1.0;
  bool json = false;
  std::string png;
};

int RunEval(const EvalArgs& a) {
  mapping::EvaluateOptions o;
  o.world = a.world;
  o.range_m = a.range_m;
  o.png = a.png;
  const mapping::Evaluation e = mapping::EvaluateFolder(a.dir, o);
  if (a.json) std::cout << e.metrics.dump(2) << "\n";
  else std::fputs(e.text.c_str(), stdout);
  return 0;
}

std::function<int()> SetupEval(CLI::App& sub) {
  auto a = std::make_shared<EvalArgs>();
  sub.add_option("OUTDIR", a->dir, "A folder written by cogmap vectorize or cogmap map (or its walls.json); with a map.sqlite beside it, also ASR count, room precision/recall, heading errors, the trajectory errors (ATE, RPE over 1/5/20 m; corrected and raw odometry) and, for a map placed by the pose graph, the calibration of its covariances (pose_calibration_3sigma: share of placed ASRs whose true pose, relative to the first ASR, is within 3 sigma); with a plan.json beside it, the floor plan's wall precision (p50/p95), recall, duplication, room IoU median, room overlap and vertices per metre (docs/floor-plan.md)")->required();
  sub.add_option("--world", a->world,
                 "The world the log was driven in (ARIA 2D-Map or PNG); without it only the heading errors "
                 "(against the log's reference poses) and the sizes are reported");
  sub.add_option("--range", a->range_m,
                 "Sensor range for recall, metres (default: the effective range recorded by vectorize, "
                 "min(max range, window))");
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
