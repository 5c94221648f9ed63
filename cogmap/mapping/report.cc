#include "cogmap/mapping/report.h"

#include <cmath>
#include <map>
#include <filesystem>

#include "cogmap/core/angles.h"
#include "cogmap/io/json_stream.h"
#include "cogmap/mapping/map_job.h"

namespace cogmap::mapping {
namespace {

using io::JsonStreams;

nlohmann::json OrNull(double v) { return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(nullptr); }

nlohmann::json ClosureJson(const graph::LoopClosure& c) {
  return {{"from_asr", c.from_asr}, {"to_asr", c.to_asr}, {"accepted", c.accepted},
          {"same_room", c.same_room}, {"across_walls_only", c.across_walls_only},
          {"agreement", c.agreement}, {"rmse_m", c.rmse_m},
          {"mahalanobis2", c.mahalanobis2}, {"reason", c.reason},
          {"same_space", c.same_space >= 0.0 ? nlohmann::json(c.same_space) : nlohmann::json(nullptr)},
          {"relative", {c.relative.x, c.relative.y, RadToDeg(c.relative.theta)}}};
}

nlohmann::json PlacementJson(const graph::AsrEstimate& e) {
  nlohmann::json j = {{"id", e.asr_id}, {"room", e.room_id}, {"uncertain", e.uncertain},
                      {"building_direction", e.building_direction}};
  if (e.has_covariance) {
    j["sigma_x_m"] = std::sqrt(std::max(0.0, e.covariance(0, 0)));
    j["sigma_y_m"] = std::sqrt(std::max(0.0, e.covariance(1, 1)));
    j["sigma_theta_deg"] = RadToDeg(std::sqrt(std::max(0.0, e.covariance(2, 2))));
    j["sigma_position_aligned_m"] = e.position_sigma_aligned_m;
  }
  return j;
}

// Which of a room's grids gave the walls kept and the room's orientation: the
// axis grid (the thesis's MHIMM, each echo on its unit's axis) or the cone
// grid (each echo on its arc; docs/walls.md, "Sonar cone" and "A ring that
// looks only forward"); the orientation null where none is taken (a laser).
nlohmann::json GridsJson(const sensors::RobotDescription& robot, const MappingOptions& mo) {
  const asr::MapperOptions m = MapperOptionsFor(robot, mo);
  const bool one_cone = m.mhimm.cone_hits;
  return {{"walls_kept", one_cone || m.cone_output_walls ? "cone" : "axis"},
          {"orientation", !m.grid_orientation ? nlohmann::json(nullptr)
                          : nlohmann::json(one_cone || m.orientation_from_cone ? "cone" : "axis")}};
}

// Laser odometry: null when it was never considered (off, paper mode, no
// laser); else the mode, whether it ran and why, and its figures.
nlohmann::json ScanMatchJson(const MappingOptions& mo, const RunResult& run) {
  if (!(run.scan_match_active || run.scan_match_gaps > 0 || mo.scan_match == ScanMatch::kOn)) return nullptr;
  const localize::ScanOdometryStats& sm = run.scan_match;
  nlohmann::json j = {{"mode", ScanMatchName(mo.scan_match)},
                      {"active", run.scan_match_active},
                      {"scans", sm.scans},
                      {"matched", sm.matched},
                      {"references", sm.references},
                      {"rejected", sm.rejected},
                      {"rmse_mean_m", sm.matched > 0 ? sm.rmse_sum_m / sm.matched : 0.0},
                      {"mean_spacing_m", sm.MeanSpacing()},
                      {"warnings", ScanMatchWarnings(mo, run)}};
  if (mo.scan_match == ScanMatch::kAuto) {
    j["decided_on_gaps"] = run.scan_match_gaps;
    j["decided_mean_step"] = run.scan_match_mean_step;  // in units of the reference's spacing: dense at most 1
  }
  return j;
}

// The distance scale: null when neither measured nor given (paper mode,
// --no-correct); else the estimate and the scale applied at the end.
nlohmann::json DistanceScaleJson(const MappingOptions& mo, const RunResult& run) {
  if (!run.distance_scale_measured && run.distance_scale_applied == 1.0) return nullptr;
  const localize::OdometryScaleEstimate& e = run.distance_scale_estimate;
  nlohmann::json j = {{"mode", run.distance_scale_measured ? "auto" : "given"},
                      {"applied", run.distance_scale_applied}};
  if (run.distance_scale_measured) {
    j["estimate"] = e.valid ? nlohmann::json(e.scale) : nlohmann::json(nullptr);
    j["sigma"] = e.valid ? nlohmann::json(e.sigma) : nlohmann::json(nullptr);
    j["runs"] = e.runs;
    j["travel_m"] = e.travel_m;
    j["prior_sigma"] = mo.distance_scale_prior;
    j["carried"] = run.distance_scale_carried ? nlohmann::json(*run.distance_scale_carried) : nlohmann::json(nullptr);
    j["warnings"] = DistanceScaleWarnings(run);
  }
  return j;
}

// The pose_graph section, its two per-ASR arrays (closure_candidates,
// placements) left as streams of 'streams'.
nlohmann::json PoseGraphJson(const graph::OptimizerResult& g, int rooms, JsonStreams* streams) {
  nlohmann::json uncertain = nlohmann::json::array();
  int accepted = 0, same_room = 0;
  for (const auto& c : g.closures) {
    accepted += c.accepted ? 1 : 0;
    same_room += c.accepted && c.same_room ? 1 : 0;
  }
  for (const auto& e : g.asrs)
    if (e.uncertain) uncertain.push_back({{"id", e.asr_id}, {"why", e.why}});
  nlohmann::json hypotheses = nlohmann::json::array();
  for (const auto& h : g.drift_hypotheses)
    hypotheses.push_back({{"rate_deg_per_m", RadToDeg(h.rate_rad_per_m)},
                          {"weight", h.weight},
                          {"building_directions", h.building_directions}});
  const nlohmann::json directions = graph::BuildingDirectionsDeg(g);
  const nlohmann::json closures = streams->Add([&g, k = size_t{0}](nlohmann::json* out) mutable {
    if (k >= g.closures.size()) return false;
    *out = ClosureJson(g.closures[k++]);
    return true;
  });
  const nlohmann::json placements = streams->Add([&g, k = size_t{0}](nlohmann::json* out) mutable {
    if (k >= g.asrs.size()) return false;
    *out = PlacementJson(g.asrs[k++]);
    return true;
  });
  return {{"solution", g.solution},
          {"closures_accepted", accepted},
          {"revisits", same_room},
          {"closure_candidates", closures},
          {"rooms", rooms},
          {"registrations", g.registrations},
          {"direction_factors", g.direction_factors},
          {"drift_rate_deg_per_m", RadToDeg(g.drift_rate_rad_per_m)},
          {"drift_rate_sigma_deg_per_m", g.drift_rate_sigma_rad_per_m >= 0.0
                                             ? nlohmann::json(RadToDeg(g.drift_rate_sigma_rad_per_m))
                                             : nlohmann::json(nullptr)},
          {"drift_rate_spread_sigma_deg_per_m", g.drift_rate_spread_sigma_rad_per_m >= 0.0
                                                    ? nlohmann::json(RadToDeg(g.drift_rate_spread_sigma_rad_per_m))
                                                    : nlohmann::json(nullptr)},
          {"chi2", g.chi2},
          {"chi2_dof", g.chi2_dof},
          {"chi2_p999", g.chi2_p999},
          {"chi2_weighted", g.chi2_weighted},
          {"chi2_weighted_dof", g.chi2_weighted_dof},
          {"variance_factor", g.variance_factor},
          {"drift_detected", g.drift_detected},
          {"drift_alias_risk", g.drift_alias_risk},
          {"drift_hypotheses", hypotheses},
          {"building_directions_deg", directions},
          {"building_direction_chi2", g.building_direction_chi2},
          {"direction_split_asrs", g.split_asrs},
          {"direction_split_used", g.split_used},
          {"drift_test_chi2", g.drift_test_chi2},
          {"sigma_factors", {{"odometry", g.odometry_sigma_factor},
                             {"odometry_heading", g.odometry_heading_sigma_factor},
                             {"wall_direction", g.direction_sigma_factor},
                             {"registration", g.registration_sigma_factor}}},
          // The odometry heading's factor as first fitted when the fit was
          // tried again with it held at the model (null: not tried), and
          // whether that was kept.
          {"odometry_heading_fitted_factor",
           g.odometry_heading_fitted_factor > 0.0 ? nlohmann::json(g.odometry_heading_fitted_factor) : nlohmann::json(nullptr)},
          {"odometry_heading_held", g.odometry_heading_held},
          {"path_wall_crossings_odometry", g.crossings_odometry},
          {"path_wall_crossings_graph", g.crossings_graph},
          {"path_wall_crossings_chosen", g.crossings_chosen},
          {"path_overlap_odometry_m", g.overlap_odometry_m},
          {"path_overlap_graph_m", g.overlap_graph_m},
          {"odometry_within_3sigma", g.odometry_within_3sigma},
          {"odometry_within_3sigma_bent", g.odometry_within_3sigma_bent},
          {"moved_as_drift_deg_per_m", RadToDeg(g.moved_as_drift_rad_per_m)},
          {"solve_seconds", g.solve_seconds},
          {"covariance_seconds", g.covariance_seconds},
          {"uncertain_asrs", uncertain},
          {"placements", placements},
          {"warnings", g.warnings}};
}

}  // namespace

nlohmann::json AsrJson(const AsrSummary& s) {
  nlohmann::json heading = nullptr;
  if (const auto& e = s.estimate) {
    const auto& g = s.grid_orientation;
    heading = {{"accepted", e->accepted},
               {"decline", localize::DeclineName(e->decline)},
               {"direction_deg", RadToDeg(e->direction_rad)},
               {"uncertainty_deg", std::isfinite(e->uncertainty_rad) ? OrNull(RadToDeg(e->uncertainty_rad))
                                                                     : nlohmann::json(nullptr)},
               {"em_direction_deg", RadToDeg(e->em_direction_rad)},
               {"grid_refined", e->grid_refined},
               {"grid_direction_deg", g.valid ? nlohmann::json(RadToDeg(g.angle_rad)) : nlohmann::json(nullptr)},
               {"grid_contrast", g.contrast},
               {"grid_cells", g.cells}};
  }
  return {{"id", s.id},
          {"seconds", s.seconds},
          {"seconds_grid", s.seconds_grid},
          {"seconds_vectorize", s.seconds - s.seconds_grid},
          {"path_m", s.path_m},
          {"walls", s.walls},
          {"bytes_grid", s.bytes.grid},
          {"bytes_polylines", s.bytes.polylines},
          {"heading_correction_deg", RadToDeg(s.heading_correction_rad)},
          {"pre_bend_deg_per_m", RadToDeg(s.pre_bend_rad_per_m)},
          {"heading_estimate", heading}};
}

void WriteReport(const ReportContext& c, std::ostream& out) {
  namespace fs = std::filesystem;
  const MapJob& job = *c.job;
  const RunResult& run = *c.run;
  JsonStreams streams;
  // Per ASR of this run: its entry, with its heading error against the
  // truth (one global rotation removed) when the log has ground truth.
  std::map<int, const localize::AsrHeadingError*> heading_of;
  for (const auto& e : c.heading->per_asr) heading_of[e.asr_id] = &e;
  const nlohmann::json per_asr = streams.Add([&run, &heading_of, k = size_t{0}](nlohmann::json* j) mutable {
    if (k >= run.asrs.size()) return false;
    const AsrSummary& s = run.asrs[k++];
    *j = AsrJson(s);
    if (auto it = heading_of.find(s.id); it != heading_of.end()) {
      (*j)["heading_error_deg"] = RadToDeg(it->second->corrected_rad);
      (*j)["heading_error_raw_deg"] = RadToDeg(it->second->raw_rad);
    }
    return true;
  });
  asr::StageBytes bytes;
  nlohmann::json seconds_all = nlohmann::json::array();
  for (const auto& x : *c.all) {
    bytes.grid += x.bytes.grid;
    bytes.vertices += x.bytes.vertices;
    bytes.polylines += x.bytes.polylines;
    seconds_all.push_back(x.seconds.total());
  }
  const double duration = run.duration_s();
  const bool drift_filter = run.correction == Correction::kDriftFilter;
  nlohmann::json report = {
      {"log", job.log_path == "-" ? std::string("stdin") : fs::absolute(job.log_path).string()},
      {"format", job.log_format},
      {"robot", c.robot->name},
      {"mode", job.mapping.paper ? "paper" : "default"},
      {"boundary", job.mapping.boundary == asr::BoundaryMode::kFixedLength ? "fixed" : "doorway"},
      {"asr_length_m", job.mapping.asr_length_m},
      {"cell_m", job.mapping.cell_m},
      {"window_m", job.mapping.window_m},
      {"grids", GridsJson(*c.robot, job.mapping)},
      {"corrected", job.mapping.correct},
      {"drift_filter", drift_filter},
      {"smoothed_asrs", run.smoothed},
      {"added_drift_deg_per_m", RadToDeg(job.mapping.add_drift_rad_per_m)},
      {"scan_match", ScanMatchJson(job.mapping, run)},
      {"distance_scale", DistanceScaleJson(job.mapping, run)},
      {"resumed", job.resume},
      {"replayed_asrs", run.replayed},
      {"resumed_after_record", run.skipped_records},
      {"records", run.records},
      {"asr_count", static_cast<int>(c.all->size())},
      {"asr_count_this_run", static_cast<int>(run.asrs.size())},
      {"exit_count", c.exits},
      {"turn_backs", run.mapper.turn_backs},
      {"bytes_grid", bytes.grid},
      {"bytes_vertices", bytes.vertices},
      {"bytes_polylines", bytes.polylines},
      {"seconds_per_asr", seconds_all},
      {"asrs", per_asr},
      {"mapping_seconds", c.mapping_seconds},
      {"total_seconds", c.total_seconds},
      {"startup_seconds", c.startup_seconds},
      {"log_duration_s", duration},
      // The whole command up to this report: from the process's start (its
      // loading and the options, startup_seconds; `cogmap map`, else from the
      // job's start) through reading, mapping and every output file, all but
      // the commit of the files into place and the exit after it (a few ms);
      // mapping_times_real_time: the job's own start to the output files.
      // null when the log's timestamps do not advance (belgioioso's are
      // written to six digits: every record at 1.01893e+09 s).
      {"times_real_time", duration > 0 && c.total_seconds > 0 ? nlohmann::json(duration / c.total_seconds) : nullptr},
      {"mapping_times_real_time",
       duration > 0 && c.mapping_seconds > 0 ? nlohmann::json(duration / c.mapping_seconds) : nullptr},
      {"peak_grid_cells", run.mapper.peak_grid_cells},
      {"max_rss_kb_mapping", c.rss_mapping_kb},
      {"store", c.store_path},
      {"run_id", c.run_id},
  };
  if (drift_filter) {
    report["drift_rate_deg_per_m"] = RadToDeg(run.drift_rate_rad_per_m);
    report["drift_rate_sigma_deg_per_m"] = RadToDeg(run.drift_rate_sigma_rad_per_m);
    report["drift_filter_measurements"] = run.drift_measurements;
    report["drift_filter_rejects"] = run.drift_rejects;
    report["drift_filter_walk_deg_per_sqrt_m"] = RadToDeg(run.drift_walk_rad_per_sqrt_m);
    report["drift_filter_sigma_scale"] = run.drift_sigma_scale;
  }
  if (run.correction == Correction::kPoseGraph) {
    report["pose_graph"] = PoseGraphJson(run.graph, c.rooms, &streams);
    int bent = 0;
    for (const AsrSummary& s : run.asrs) bent += s.pre_bend_rad_per_m != 0.0 ? 1 : 0;
    report["pose_graph"]["pre_bent_asrs"] = bent;
    if (run.second_pass_drift_removed_rad_per_m != 0.0)
      report["pose_graph"]["second_pass"] = {
          {"drift_removed_deg_per_m", RadToDeg(run.second_pass_drift_removed_rad_per_m)},
          {"first_pass_drift_sigma_deg_per_m", run.first_pass_drift_rate_sigma_rad_per_m >= 0.0
                                                   ? nlohmann::json(RadToDeg(run.first_pass_drift_rate_sigma_rad_per_m))
                                                   : nlohmann::json(nullptr)},
          {"first_pass_seconds", run.first_pass_seconds}};
    else
      report["pose_graph"]["second_pass"] = nullptr;
  }
  for (const auto& [k, v] : localize::HeadingErrorEvalKeys(*c.heading)) report[k] = v;
  if (c.room_metrics) {
    report["world"] = fs::absolute(job.world).string();
    report["room_precision"] = c.room_metrics->room_precision;
    report["room_recall"] = c.room_metrics->room_recall;
    report["asr_rooms"] = c.room_metrics->asr_room;
  }
  streams.Write(out, report);
  out << "\n";
}

}  // namespace cogmap::mapping
