#include "cogmap/mapping/vectorize_job.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>

#include "cogmap/core/error.h"
#include "cogmap/core/text.h"
#include "cogmap/draw/stages_picture.h"
#include "cogmap/grid/range_fusion.h"
#include "cogmap/io/atomic_file.h"
#include "cogmap/io/output_folder.h"
#include "cogmap/io/polyline_io.h"
#include "cogmap/mapping/pipeline.h"
#include "cogmap/sensors/robot_json.h"

namespace cogmap::mapping {
namespace fs = std::filesystem;
namespace {

nlohmann::json PoseJson(const Pose2& p) { return {{"x", p.x}, {"y", p.y}, {"theta", p.theta}}; }

// What the fusion of the whole log gives: the grid and what was read.
struct FusedLog {
  std::unique_ptr<grid::RangeFusion> fusion;
  Polyline path;  // the fused poses, thinned to 5 cm (for walls.svg)
  long records = 0, readings = 0, echoes = 0, truth_records = 0;
  std::optional<Pose2> first_odom, first_truth;
};

FusedLog FuseWholeLog(io::LogReader& log, const sensors::RobotDescription& robot, const VectorizeJob& job) {
  grid::FusionOptions fo;
  fo.bounds.cell_m = job.cell_m;
  fo.mhimm.window_m = job.window_m;
  fo.mhimm.cone_hits = !job.paper && job.cone_hits;
  FusedLog f;
  f.fusion = grid::MakeFusion(grid::FusionRule::kMhimm, fo);
  sensors::LogRecord rec;
  while (log.Next(&rec)) {
    ++f.records;
    if (rec.truth) {
      ++f.truth_records;
      if (!f.first_truth) f.first_truth = rec.truth, f.first_odom = rec.odom;
    }
    const Pose2 pose = (job.use_truth && rec.truth) ? *rec.truth : rec.odom;
    f.fusion->InsertSweep(pose, robot, rec.ranges);
    if (f.path.empty() || (pose.translation() - f.path.back()).norm() >= 0.05) f.path.push_back(pose.translation());
    f.readings += static_cast<long>(rec.ranges.size());
    for (const auto& r : rec.ranges)
      if (r.sensor >= 0 && r.sensor < static_cast<int>(robot.sensors.size()) &&
          r.range_m < robot.sensors[r.sensor].max_range_m)
        ++f.echoes;
    if ((f.records & 255) == 0 && job.progress) job.progress(log.progress());
  }
  if (job.progress) job.progress(1.0);
  if (f.records == 0) throw InputError(job.log_path, 0, "the log has no records");
  return f;
}

nlohmann::json MakeVectorizeReport(const VectorizeJob& job, const vectorize::VectorizeOptions& vo,
                                   const VectorizeJobResult& out, const std::string& log_path) {
  const vectorize::VectorizeResult& r = out.walls;
  const grid::MapLimits& lim = out.limits;
  const std::string mode = job.paper ? "paper" : "default";
  nlohmann::json rep;
  rep["log"] = log_path;
  rep["log_format"] = job.log_format;
  rep["robot"] = out.robot.name;
  rep["mode"] = mode;
  rep["records"] = out.records;
  rep["readings"] = out.readings;
  rep["echoes"] = out.echoes;
  rep["truth_records"] = out.truth_records;
  rep["fused_at"] = job.use_truth ? "truth" : "odometry";
  rep["world_from_map"] = PoseJson(out.world_from_map);
  rep["grid"] = {{"width", lim.width()}, {"height", lim.height()}, {"cell_m", lim.cell_m()},
                 {"origin", {lim.origin().x(), lim.origin().y()}}};
  rep["options"] = {
      {"cell_m", job.cell_m},
      {"window_m", job.window_m},
      {"epsilon", vo.clean.classes.occupied_above},
      {"max_dist_cells", vo.clean.max_dist_cells},
      {"gamma_cells", vo.extract.gamma_cells},
      {"close_loops", vo.extract.close_loops},
      {"clean_keep", vo.clean.keep == vectorize::KeepCell::kFace ? "face" : "middle"},
      {"tau_cells", vo.vertex_simplify.tau_cells},
      {"eta_cells", vo.douglas_peucker.eta_cells},
      {"fit_mode", mode},
      {"min_abs_pearson", vo.fit.min_abs_pearson},
      {"max_rms_cells", vo.fit.max_rms_cells},
      {"min_corner_deg", vo.fit.min_corner_deg},
      {"min_chain_points", vo.min_chain_points},
      {"smooth_half_window", vo.smooth_half_window},
      {"wall_lines", vo.wall_lines},
      {"beam_half_width_deg", vo.lines.beam_half_width_rad * 180.0 / 3.14159265358979323846},
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
                   {"chamfers_removed", r.fit_stats.chamfers_removed},
                   {"line_peaks", r.line_stats.lines},
                   {"line_segments", r.line_stats.segments},
                   {"line_runs_rejected", r.line_stats.rejected_runs},
                   {"line_corners_joined", r.line_stats.corners_joined},
                   {"line_t_joins", r.line_stats.t_joins},
                   {"line_chamfers_removed", r.line_stats.chamfers_removed}};
  rep["bytes"] = {{"grid", r.bytes.grid}, {"vertices", r.bytes.vertices}, {"polylines", r.bytes.polylines}};
  rep["seconds"] = {{"grid", out.grid_seconds},
                    {"clean", r.seconds.clean},
                    {"extract", r.seconds.extract},
                    {"simplify", r.seconds.simplify},
                    {"fit", r.seconds.fit},
                    {"vectorize_total", r.seconds.total()}};
  return rep;
}

}  // namespace

void VectorizeJob::Validate() const {
  std::string m = CellAndWindowProblem(cell_m, window_m);
  // The stages' lengths in cells: unset (-1, the stage's own) or a length
  // a grid can have (NaN was ignored, infinity taken).
  const std::pair<const char*, double> cells[] = {
      {"--gamma", gamma_cells}, {"--tau", tau_cells}, {"--eta", eta_cells}, {"--max-rms", max_rms_cells}};
  for (const auto& [name, v] : cells)
    if (m.empty() && v != -1.0 && !(v > 0.0 && v <= 1000.0))
      AppendF(&m, "%s %g: must be in (0, 1000] cells", name, v);
  if (!m.empty()) throw InputError(m);
}

vectorize::VectorizeOptions VectorizeJob::StageOptions() const {
  vectorize::VectorizeOptions vo = paper ? vectorize::VectorizeOptions::Paper() : vectorize::VectorizeOptions{};
  vo.clean.max_dist_cells = std::max(1, static_cast<int>(std::lround(window_m / cell_m)));
  if (gamma_cells > 0) vo.extract.gamma_cells = gamma_cells;
  if (tau_cells > 0) vo.vertex_simplify.tau_cells = tau_cells;
  if (eta_cells > 0) vo.douglas_peucker.eta_cells = eta_cells;
  if (max_rms_cells > 0) vo.fit.max_rms_cells = max_rms_cells;
  if (min_chain_points >= 0) vo.min_chain_points = min_chain_points;
  if (smooth_half_window >= 0) vo.smooth_half_window = smooth_half_window;
  if (keep) vo.clean.keep = *keep;
  return vo;
}

VectorizeJobResult RunVectorizeJob(io::LogReader& log, const VectorizeJob& job) {
  job.Validate();
  vectorize::VectorizeOptions vo = job.StageOptions();
  // The output folder as `cogmap map` uses it (docs/store.md): locked, staged,
  // moved into place at the end.
  auto folder = io::OutputFolder::Open(job.output_dir);
  try {
    VectorizeJobResult out;
    out.robot = io::RobotFor(log, job.robot_spec);
    double max_range_m = 0.0;
    for (const auto& s : out.robot.sensors) max_range_m = std::max(max_range_m, s.max_range_m);
    if (!job.paper) ConfigureWallLines(out.robot, job.wall_lines.value_or(MappingOptions{}.wall_lines), &vo);

    // Fuse the whole log as one space.
    const auto t_grid = std::chrono::steady_clock::now();
    const FusedLog fused = FuseWholeLog(log, out.robot, job);
    out.grid_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t_grid).count();
    out.records = fused.records;
    out.readings = fused.readings;
    out.echoes = fused.echoes;
    out.truth_records = fused.truth_records;
    const auto* himm = dynamic_cast<const grid::HimmFusion*>(fused.fusion.get());
    const grid::Grid2D<float>& values = himm->values();
    out.limits = values.limits();
    out.walls = vectorize::Vectorize(values, vo);
    // The map frame is the odometry frame; its pose in the truth's world.
    if (fused.first_truth && !job.use_truth) out.world_from_map = (*fused.first_truth) * fused.first_odom->inverse();

    io::WallsFile wf;
    wf.polylines = out.walls.polylines;
    wf.world_from_map = out.world_from_map;
    wf.has_truth = out.truth_records > 0;
    wf.log_path = fs::absolute(job.log_path).lexically_normal().string();
    wf.log_format = job.log_format;
    wf.robot = job.robot_spec.empty() ? out.robot.name : job.robot_spec;
    wf.mode = job.paper ? "paper" : "default";
    wf.cell_m = job.cell_m;
    // The effective range (SPEC 3.1): no reading beyond the window marks a wall.
    wf.sensor_range_m = std::min(max_range_m, job.window_m);
    wf.vertex_count = out.walls.vertex_count;
    wf.bytes_grid = out.walls.bytes.grid;
    wf.bytes_vertices = out.walls.bytes.vertices;
    wf.bytes_polylines = out.walls.bytes.polylines;
    io::WriteWallsJson(folder->Staged("walls.json"), wf);

    // walls.svg: the walls (black, vertices red) over the path (faint).
    draw::PictureOptions walls_picture;
    walls_picture.title = "Walls: " + fs::path(job.log_path).filename().string();
    draw::DrawWalls(out.walls.polylines, {}, fused.path, walls_picture).drawing.Write(folder->Staged("walls.svg"));
    draw::DrawStages(values, out.walls).drawing.Write(folder->Staged("stages.png"));
    out.report = MakeVectorizeReport(job, vo, out, wf.log_path);
    io::WriteFileAtomically(folder->Staged("report.json"), out.report.dump(2) + "\n");
    out.written = {"walls.json", "walls.svg", "stages.png", "report.json"};
    folder->Commit("walls.json");  // walls.json last: `cogmap eval` reads it
    return out;
  } catch (...) {
    const std::string kept = folder->Abandon();
    if (!kept.empty() && job.notice) job.notice(kept + ": this run's partial result (the previous outputs are untouched)");
    throw;
  }
}

}  // namespace cogmap::mapping
