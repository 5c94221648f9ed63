// `cogmap map`: the whole cognitive mapper (issue 5). A log goes in; each room
// becomes an ASR in OUTDIR/map.sqlite, and the master map is written as SVG,
// PNG, ROS map_server PGM + YAML, GeoJSON and an ARIA 2D-Map, with report.json.
#include <sys/resource.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <exception>
#include <filesystem>
#include <functional>
#include <map>
#include <nlohmann/json.hpp>
#include <set>
#include <sstream>
#include <string>

#include "app/cli_util.h"
#include "app/command.h"
#include "app/log_warnings.h"
#include "app/progress.h"
#include "cogmap/asr/mapper.h"
#include "cogmap/asr/room_metrics.h"
#include "cogmap/asr/store.h"
#include "cogmap/core/error.h"
#include "cogmap/graph/map_optimizer.h"
#include "cogmap/io/atomic_file.h"
#include "cogmap/io/log_reader.h"
#include "cogmap/io/map_files.h"
#include "cogmap/io/output_folder.h"
#include "cogmap/io/polyline_io.h"
#include "cogmap/io/world_io.h"
#include "cogmap/localize/correction_figures.h"
#include "cogmap/localize/heading_corrector.h"
#include "cogmap/localize/heading_error.h"
#include "cogmap/localize/odometry_corrector.h"
#include "cogmap/sensors/robot_json.h"

namespace cogmap::app {
namespace {

struct MapArgs {
  std::string log;
  std::string format = "auto";
  std::string robot;
  double cell_m = 0.1;
  double window_m = 3.0;
  std::string mode = "default";
  std::string boundary = "doorway";
  double asr_length_m = 4.5;
  double max_asr_m = 15.0;
  bool no_correct = false;
  bool no_drift_filter = false;
  bool no_graph = false;
  std::string outputs = "default";
  bool no_smooth = false;
  double add_drift_deg_per_m = 0.0;
  bool resume = false;
  bool raw = false;
  std::string world;
  std::string output;
};

long MaxRssKb() {
  rusage u{};
  getrusage(RUSAGE_SELF, &u);
  return u.ru_maxrss;
}

// Adds a systematic heading drift to a log's odometry (the truth stays): each
// odometry increment turns by an extra rate x its length, and the positions
// follow the drifted heading (the bench's way to drift a real log).
class DriftAdder {
 public:
  explicit DriftAdder(double rad_per_m) : rate_(rad_per_m) {}
  Pose2 Add(const Pose2& odom) {
    if (!last_) {
      last_ = odom;
      out_ = odom;
      return out_;
    }
    Pose2 inc = last_->inverse() * odom;
    const double ds = std::hypot(inc.x, inc.y);
    const double extra = rate_ * ds;
    const Vec2 t = RotateAbout(inc.translation(), Vec2(0.0, 0.0), 0.5 * extra);
    out_ = out_ * Pose2{t.x(), t.y(), inc.theta + extra};
    last_ = odom;
    return out_;
  }

 private:
  double rate_;
  std::optional<Pose2> last_;
  Pose2 out_;
};

// `--outputs`: which files beside map.sqlite, walls.json and report.json.
struct OutputChoice {
  io::MasterMapOutputs map;
  bool compare = false;  // map_compare.svg/.png
  bool heading = false;  // heading_error.png
};
OutputChoice ParseOutputs(const std::string& text) {
  OutputChoice c;
  c.map = io::MasterMapOutputs{false, false, false, false, false};
  std::stringstream in(text);
  std::string item;
  bool any = false;
  while (std::getline(in, item, ',')) {
    any = true;
    if (item == "all") {
      c.map = io::MasterMapOutputs{};
      c.compare = c.heading = true;
    } else if (item == "default") {
      c.map.svg = c.map.geojson = c.map.aria = true;
    } else if (item == "svg") c.map.svg = true;
    else if (item == "png") c.map.png = true;
    else if (item == "pgm") c.map.pgm = true;
    else if (item == "geojson") c.map.geojson = true;
    else if (item == "aria") c.map.aria = true;
    else if (item == "compare") c.compare = true;
    else if (item == "heading") c.heading = true;
    else
      throw InputError("--outputs " + text + ": unknown output '" + item +
                       "' (expected default, all, svg, png, pgm, geojson, aria, compare, heading)");
  }
  if (!any) throw InputError("--outputs: empty list");
  return c;
}

std::optional<Pose2> ParsePose(const std::optional<std::string>& text) {
  if (!text) return std::nullopt;
  std::istringstream in(*text);
  Pose2 p;
  if (!(in >> p.x >> p.y >> p.theta)) return std::nullopt;
  return p;
}

int RunMap(const MapArgs& a) {
  namespace fs = std::filesystem;
  const auto start = std::chrono::steady_clock::now();
  if (!(a.cell_m > 0.0) || a.cell_m > 10.0) throw InputError("--cell " + Num(a.cell_m) + ": must be in (0, 10] metres");
  if (!(a.window_m > 0.0)) throw InputError("--window " + Num(a.window_m) + ": must be positive");
  if (!(a.asr_length_m > 0.0)) throw InputError("--asr-length " + Num(a.asr_length_m) + ": must be positive");
  if (a.mode != "paper" && a.mode != "default") throw InputError("--mode " + a.mode + ": expected paper or default");
  if (!std::isfinite(a.add_drift_deg_per_m) || std::abs(a.add_drift_deg_per_m) > 90.0)
    throw InputError("--add-drift-deg-per-m " + Num(a.add_drift_deg_per_m) + ": must be in [-90, 90]");
  const OutputChoice outputs = ParseOutputs(a.outputs);
  if (a.boundary != "doorway" && a.boundary != "fixed")
    throw InputError("--boundary " + a.boundary + ": expected doorway or fixed");

  auto log = io::OpenLog(a.log, a.format);
  sensors::RobotDescription robot;
  if (!a.robot.empty()) robot = sensors::ResolveRobot(a.robot);
  else if (auto hint = log->robot_hint()) robot = *hint;
  else robot = sensors::BuiltinRobot("pioneer16");
  std::optional<FloorPlan> truth_plan;
  if (!a.world.empty()) truth_plan = io::ReadWorld(a.world).plan;

  // The output folder (docs/store.md): locked for this run ("OUTDIR: locked by
  // another cogmap run (pid N)"); the store and every file are written into its
  // staging folder and moved into place at the end. A run that fails leaves the
  // previous map untouched and its own partial result in OUTDIR/failed-run-*/.
  auto folder = io::OutputFolder::Open(a.output);
  struct SetAsideOnFailure {
    io::OutputFolder* folder;
    ~SetAsideOnFailure() {  // after the store is closed (declared before it)
      if (folder->committed() || std::uncaught_exceptions() == 0) return;
      const std::string kept = folder->Abandon();
      if (!kept.empty())
        std::fprintf(stderr, "cogmap: %s: this run's partial result (the previous map is untouched)\n", kept.c_str());
    }
  } set_aside{folder.get()};
  const std::string store_path = folder->Final("map.sqlite");
  std::unique_ptr<asr::SqliteAsrStore> store;
  if (a.resume) {
    // Checked where it is (before the log is mapped; errors name it), then
    // continued in a copy: the stored map stays as it was until the end.
    asr::SqliteAsrStore::Open(store_path, asr::SqliteAsrStore::OpenMode::kReadOnly);
    folder->CopyIntoStaging("map.sqlite");
    store = asr::SqliteAsrStore::Open(folder->Staged("map.sqlite"), asr::SqliteAsrStore::OpenMode::kOpenExisting);
  } else {
    // A new run replaces a cogmap store, never another file (nor a store of a
    // newer cogmap): checked before mapping, as a store opened in place was.
    std::error_code ec;
    if (fs::exists(store_path, ec) && fs::file_size(store_path, ec) > 0)
      asr::SqliteAsrStore::Open(store_path, asr::SqliteAsrStore::OpenMode::kReadOnly);
    store = asr::SqliteAsrStore::Open(folder->Staged("map.sqlite"), asr::SqliteAsrStore::OpenMode::kReplace);
  }
  // report.json carries the same id: a reader can check that they belong together.
  store->SetMeta("run_id", folder->run_id());

  asr::MapperOptions options;
  options.cell_m = a.cell_m;
  options.mhimm.window_m = a.window_m;
  options.vectorize = a.mode == "paper" ? vectorize::VectorizeOptions::Paper() : vectorize::VectorizeOptions{};
  options.boundary.mode = a.boundary == "fixed" ? asr::BoundaryMode::kFixedLength : asr::BoundaryMode::kDoorway;
  options.boundary.asr_length_m = a.asr_length_m;
  // Default mode also bounds how far an ASR runs without a doorway (a hall, a
  // wide corridor); paper mode leaves such a space whole, as the papers do.
  if (a.mode != "paper") options.boundary.max_asr_m = a.max_asr_m;

  nlohmann::json per_asr = nlohmann::json::array();
  asr::StageBytes bytes_run;
  int closed = 0;
  // The heading estimate of the ASR that has just closed (set once the
  // corrector is chosen below; null without correction).
  std::function<const localize::DirectionEstimate*()> last_estimate = [] { return nullptr; };
  // The grid orientation serves the heading correction's grid refinement,
  // which is for sonar robots only (below): not computed for a laser.
  const bool laser_only = std::all_of(robot.sensors.begin(), robot.sensors.end(),
                                      [](const auto& s) { return s.kind == sensors::SensorKind::kLaser; });
  options.grid_orientation = !laser_only;
  asr::CognitiveMapper mapper(robot, options, store.get(), [&](const asr::Asr& x) {
    ++closed;
    nlohmann::json heading = nullptr;
    if (const localize::DirectionEstimate* e = last_estimate()) {
      heading = {{"accepted", e->accepted},
                 {"decline", localize::DeclineName(e->decline)},
                 {"direction_deg", RadToDeg(e->direction_rad)},
                 {"uncertainty_deg", std::isfinite(e->uncertainty_rad) ? nlohmann::json(RadToDeg(e->uncertainty_rad))
                                                                       : nlohmann::json(nullptr)},
                 {"em_direction_deg", RadToDeg(e->em_direction_rad)},
                 {"grid_refined", e->grid_refined},
                 {"grid_direction_deg", x.grid_orientation.valid ? nlohmann::json(RadToDeg(x.grid_orientation.angle_rad))
                                                                 : nlohmann::json(nullptr)},
                 {"grid_contrast", x.grid_orientation.contrast},
                 {"grid_cells", x.grid_orientation.cells}};
    }
    bytes_run.grid += x.bytes.grid;
    bytes_run.vertices += x.bytes.vertices;
    bytes_run.polylines += x.bytes.polylines;
    per_asr.push_back({{"id", x.id},
                       {"seconds", x.seconds.total()},
                       {"seconds_grid", x.seconds.grid},
                       {"seconds_vectorize", x.seconds.total() - x.seconds.grid},
                       {"path_m", [&] {
                          double s = 0;
                          for (size_t i = 1; i < x.path.size(); ++i)
                            s += (x.path[i].translation() - x.path[i - 1].translation()).norm();
                          return s;
                        }()},
                       {"walls", x.walls_local.size()},
                       {"bytes_grid", x.bytes.grid},
                       {"bytes_polylines", x.bytes.polylines},
                       {"heading_correction_deg", RadToDeg(x.heading_correction_rad)},
                       {"heading_estimate", heading}});
  });

  // Heading correction (SPEC 5). On --resume the corrector continues from the
  // stored run: its last correction and reference direction (docs/store.md).
  localize::HeadingCorrectionOptions hc_options;
  hc_options.mode = a.mode == "paper" ? localize::HeadingMode::kPaper : localize::HeadingMode::kDefault;
  // The grid refinement is for sonar, whose polylines wobble; a laser's
  // polylines give the EM a better direction than the room's occupied cells,
  // which lean towards where the laser first saw the walls when the odometry
  // drifts through the room (docs/heading-correction.md).
  hc_options.grid_refine = !laser_only;
  localize::HeadingCorrector corrector(hc_options);
  // Default mode: drift-rate estimation with odometry pre-correction
  // (docs/heading-correction.md); paper mode corrects one rotation per ASR.
  // Default mode: the pose graph over ASRs (docs/pose-graph.md) places every
  // ASR and estimates the drift itself, in the raw odometry frame; the drift
  // filter's pre-correction is used without it (--no-graph).
  const bool use_graph = !a.no_correct && !a.no_graph && a.mode == "default";
  const bool drift_filter = !a.no_correct && !a.no_drift_filter && a.mode == "default" && !use_graph;
  localize::DriftHeadingCorrector drift_corrector(hc_options);
  Pose2 carried;  // raw -> corrected at the end of the stored run (identity on a new run)
  if (a.resume) {
    const int last = store->MaxId();
    asr::MapperResume r;
    r.next_id = last + 1;
    if (auto next = store->GetMeta(asr::kMetaNextId)) r.next_id = std::max(r.next_id, std::atoi(next->c_str()));
    std::optional<double> reference;
    if (last >= 0) {
      r.previous_asr = last;
      carried = localize::CorrectionOf(*store->Get(last));
      for (int id : store->Ids()) {  // one ASR at a time: the first accepted one sets it
        reference = localize::ReferenceDirection({*store->Get(id)}, hc_options);
        if (reference) break;
      }
    }
    corrector.Restore(carried, reference);
    drift_corrector.Restore(carried, reference);
    r.last_raw_pose = ParsePose(store->GetMeta(asr::kMetaLastRawPose));
    mapper.Resume(r);
  }
  if (drift_filter) {
    mapper.SetOdometryFilter(
        [&drift_corrector](const Pose2& raw, double t) { return drift_corrector.CorrectOdometry(raw, t); });
    mapper.SetCorrector([&drift_corrector](asr::Asr pre) { return drift_corrector.Close(std::move(pre)); });
    last_estimate = [&drift_corrector] { return &drift_corrector.LastEstimate(); };
  } else if (use_graph) {
    // The pose graph's placer (below) places every ASR.
  } else if (!a.no_correct) {
    mapper.SetCorrector([&corrector](asr::Asr raw) { return corrector.Close(std::move(raw)); });
    last_estimate = [&corrector] { return &corrector.LastEstimate(); };
  } else if (carried.theta != 0.0 || carried.x != 0.0 || carried.y != 0.0) {
    mapper.SetCorrector([carried](asr::Asr raw) {
      raw.world_from_local_corrected = carried * raw.world_from_local_raw;
      raw.heading_correction_rad = carried.theta;
      return raw;
    });
  }

  graph::MapOptimizerOptions graph_options;
  graph_options.heading = hc_options;
  graph::MapOptimizer optimizer(graph_options);
  if (use_graph) {
    if (a.resume)
      for (int id : store->Ids()) optimizer.AddStored(*store->Get(id), store->RoomOf(id));
    mapper.SetPlacer([&optimizer](asr::Asr x) { return optimizer.Place(std::move(x)); });
    last_estimate = [&optimizer] { return &optimizer.LastEstimate(); };
  }

  ProgressBar bar("map");
  sensors::LogRecord rec;
  double t_first = 0.0, t_last = 0.0;
  long records = 0;
  std::optional<Pose2> first_odom, first_truth;
  DriftAdder drift_adder(DegToRad(a.add_drift_deg_per_m));
  try {
    while (log->Next(&rec)) {
      if (a.add_drift_deg_per_m != 0.0) rec.odom = drift_adder.Add(rec.odom);
      if (records == 0) t_first = rec.time_s;
      if (!first_odom) first_odom = rec.odom;
      if (!first_truth && rec.truth) first_truth = *rec.truth * rec.odom.inverse();  // world_from_map
      t_last = rec.time_s;
      mapper.Push(rec);
      if (++records % 256 == 0) bar.Update(log->progress(), std::to_string(closed) + " ASRs");
    }
    mapper.Finish();
    WarnSkipped(*log);
  } catch (...) {
    // Every ASR closed before the bad line is in the staging store (one
    // transaction each); SetAsideOnFailure keeps it under failed-run-*. A new
    // store that holds none is no partial result: no failed-run folder for it.
    bar.Finish();
    if (!a.resume && closed == 0) {
      store.reset();
      std::error_code ec;
      for (const char* suffix : {"", "-wal", "-shm", "-journal"}) fs::remove(folder->Staged("map.sqlite") + suffix, ec);
    }
    throw;
  }
  bar.Finish();
  // Default mode: the drift rate learnt along the run revises the corrections
  // of this run's ASRs (RTS smoothing), the first ones above all.
  int smoothed = 0;
  graph::OptimizerResult graph_result;
  if (use_graph) {
    graph_result = optimizer.Finish();
    std::map<int, double> revised_deg;
    std::vector<asr::Asr> updated;
    std::vector<asr::Placement> placements;
    std::vector<asr::ClosureRecord> closure_records;
    for (const auto& e : graph_result.asrs) {
      asr::Placement p;
      p.asr_id = e.asr_id;
      p.room_id = e.room_id;
      p.covariance = e.covariance;
      p.uncertain = e.uncertain;
      p.drift_rate_rad_per_m = e.drift_rate_rad_per_m;
      p.corrected_path = e.corrected_path;
      for (const auto& w : e.why) p.why += (p.why.empty() ? "" : "; ") + w;
      placements.push_back(p);
      auto x = store->Get(e.asr_id);
      if (!x) continue;
      x->world_from_local_corrected = e.pose;
      if (!e.corrected_walls.empty() || x->walls_local.empty()) x->walls_local = e.corrected_walls;
      x->heading_correction_rad = localize::CorrectionOf(*x).theta;
      if (e.has_covariance)
        x->heading_uncertainty_rad = std::sqrt(std::max(0.0, e.covariance(2, 2)));
      updated.push_back(*x);
      revised_deg[e.asr_id] = RadToDeg(x->heading_correction_rad);
    }
    for (const auto& c : graph_result.closures)
      closure_records.push_back({c.from_asr, c.to_asr, c.relative, c.agreement, c.rmse_m, c.mahalanobis2, c.accepted,
                                 c.same_room, c.reason});
    store->PutPlacements(updated, placements, closure_records);
    for (auto& j : per_asr)
      if (auto it = revised_deg.find(j["id"].get<int>()); it != revised_deg.end())
        j["heading_correction_deg"] = it->second;
  } else if (drift_filter && !a.no_smooth) {
    std::map<int, double> revised_deg;
    for (const auto& r : drift_corrector.Smooth()) {
      auto x = store->Get(r.asr_id);
      if (!x) continue;
      x->world_from_local_corrected = r.delta * x->world_from_local_corrected;
      x->heading_correction_rad = localize::CorrectionOf(*x).theta;
      store->Put(*x);
      revised_deg[r.asr_id] = RadToDeg(x->heading_correction_rad);
      ++smoothed;
    }
    for (auto& j : per_asr)
      if (auto it = revised_deg.find(j["id"].get<int>()); it != revised_deg.end())
        j["heading_correction_deg"] = it->second;
  }
  const double mapping_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  const long rss_mapping_kb = MaxRssKb();

  // The master map from everything in the store (earlier runs included).
  std::vector<asr::Asr> all;
  for (int id : store->Ids()) all.push_back(*store->Get(id));
  const io::MasterMap master = io::BuildMasterMap(all, !a.raw);
  std::vector<std::string> written = {"map.sqlite"};
  for (const auto& f : io::WriteMasterMapFiles(folder->staging(), master, {}, 0.05, outputs.map))
    written.push_back(fs::path(f).filename().string());

  // Before / after correction side by side, and the heading error per ASR.
  if (outputs.compare) {
    const io::MasterMap raw_map = io::BuildMasterMap(all, false);
    const io::MasterMap cor_map = a.raw ? io::BuildMasterMap(all, true) : master;
    auto style_for = [](const io::MasterMap& m) {
      io::MasterMapStyle st;
      const double extent = std::max(m.max.x() - m.min.x(), m.max.y() - m.min.y()) + 2.0 * st.margin_m;
      st.px_per_m = std::clamp(1000.0 / std::max(extent, 1e-6), 2.0, 40.0);
      return st;
    };
    // With pre-correction each ASR's walls were mapped on corrected odometry:
    // the left picture places them by odometry (the true raw map: --no-correct).
    const std::string lt = drift_filter ? "BEFORE: ASRS AT THEIR ODOMETRY POSES" : "BEFORE: ODOMETRY";
    const std::string rt = a.no_correct ? "AFTER: NOT CORRECTED (--NO-CORRECT)"
                           : use_graph  ? std::string("AFTER: POSE GRAPH (DEFAULT)")
                                        : "AFTER: HEADING CORRECTION (" + a.mode + ")";
    io::WriteFileAtomically((fs::path(folder->staging()) / "map_compare.svg").string(),
                            localize::SideBySideSvg(io::FormatMapSvg(raw_map, style_for(raw_map)), lt,
                                                    io::FormatMapSvg(cor_map, style_for(cor_map)), rt));
    io::WritePng((fs::path(folder->staging()) / "map_compare.png").string(),
                 localize::SideBySide(io::RenderMap(raw_map, style_for(raw_map)), lt,
                                      io::RenderMap(cor_map, style_for(cor_map)), rt));
    written.push_back("map_compare.svg");
    written.push_back("map_compare.png");
  }
  std::map<int, std::vector<Pose2>> placed_paths;
  for (int id : store->Ids())
    if (auto p = store->GetPlacement(id)) placed_paths[id] = std::move(p->corrected_path);
  const localize::HeadingErrorStats heading = localize::ComputeHeadingErrors(all, placed_paths);
  // Per ASR of this run: its heading error against the truth (one global
  // rotation removed), when the log has ground truth.
  for (const auto& e : heading.per_asr)
    for (auto& j : per_asr)
      if (j["id"].get<int>() == e.asr_id) {
        j["heading_error_deg"] = RadToDeg(e.corrected_rad);
        j["heading_error_raw_deg"] = RadToDeg(e.raw_rad);
      }
  if (outputs.heading && heading.asrs > 0) {
    io::WritePng((fs::path(folder->staging()) / "heading_error.png").string(), localize::PlotHeadingErrors(heading));
    written.push_back("heading_error.png");
  }

  // walls.json for `cogmap eval` (the master map's walls; map frame = the raw
  // odometry frame of the first run, placed in the truth's world when known).
  if (!a.resume && first_truth) {
    const Pose2 w = *first_truth;
    store->SetMeta("world_from_map", std::to_string(w.x) + " " + std::to_string(w.y) + " " + std::to_string(w.theta));
  }
  io::WallsFile wf;
  for (const auto& r : master.rooms) wf.polylines.insert(wf.polylines.end(), r.walls.begin(), r.walls.end());
  if (auto w = ParsePose(store->GetMeta("world_from_map"))) {
    wf.world_from_map = *w;
    wf.has_truth = true;
  }
  wf.log_path = fs::absolute(a.log).string();
  wf.log_format = a.format;
  wf.robot = a.robot.empty() ? robot.name : a.robot;
  wf.mode = a.mode;
  wf.cell_m = a.cell_m;
  // The range within which walls get mapped (as cogmap vectorize records it):
  // min(max range, window), so that recall counts only walls the grid could hold.
  for (const auto& s : robot.sensors)
    wf.sensor_range_m = std::max(wf.sensor_range_m, std::min(s.max_range_m, a.window_m));
  for (const auto& l : wf.polylines) wf.vertex_count += static_cast<int64_t>(l.size());
  for (const auto& x : all) {
    wf.bytes_grid += x.bytes.grid;
    wf.bytes_vertices += x.bytes.vertices;
    wf.bytes_polylines += x.bytes.polylines;
  }
  io::WriteWallsJson((fs::path(folder->staging()) / "walls.json").string(), wf);

  asr::StageBytes bytes_all;
  nlohmann::json seconds_all = nlohmann::json::array();
  for (const auto& x : all) {
    bytes_all.grid += x.bytes.grid;
    bytes_all.vertices += x.bytes.vertices;
    bytes_all.polylines += x.bytes.polylines;
    seconds_all.push_back(x.seconds.total());
  }
  const double total_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  const double duration = t_last - t_first;
  nlohmann::json report = {
      {"log", a.log == "-" ? std::string("stdin") : fs::absolute(a.log).string()},
      {"format", a.format},
      {"robot", robot.name},
      {"mode", a.mode},
      {"boundary", a.boundary},
      {"asr_length_m", a.asr_length_m},
      {"cell_m", a.cell_m},
      {"window_m", a.window_m},
      {"corrected", !a.no_correct},
      {"drift_filter", drift_filter},
      {"smoothed_asrs", smoothed},
      {"added_drift_deg_per_m", a.add_drift_deg_per_m},
      {"resumed", a.resume},
      {"records", records},
      {"asr_count", static_cast<int>(all.size())},
      {"asr_count_this_run", closed},
      {"exit_count", master.exits.size()},
      {"turn_backs", mapper.stats().turn_backs},
      {"bytes_grid", bytes_all.grid},
      {"bytes_vertices", bytes_all.vertices},
      {"bytes_polylines", bytes_all.polylines},
      {"seconds_per_asr", seconds_all},
      {"asrs", per_asr},
      {"mapping_seconds", mapping_seconds},
      {"total_seconds", total_seconds},
      {"log_duration_s", duration},
      // The whole command up to this report (reading, mapping, every output
      // file); mapping_times_real_time: before the output files.
      {"times_real_time", total_seconds > 0 ? duration / total_seconds : 0.0},
      {"mapping_times_real_time", mapping_seconds > 0 ? duration / mapping_seconds : 0.0},
      {"peak_grid_cells", mapper.stats().peak_grid_cells},
      {"max_rss_kb_mapping", rss_mapping_kb},
      {"store", store_path},
      {"run_id", folder->run_id()},
  };
  if (drift_filter) {
    report["drift_rate_deg_per_m"] = RadToDeg(drift_corrector.odometry().rate_rad_per_m());
    report["drift_rate_sigma_deg_per_m"] = RadToDeg(drift_corrector.odometry().rate_sigma_rad_per_m());
    report["drift_filter_measurements"] = drift_corrector.odometry().measurements();
    report["drift_filter_rejects"] = drift_corrector.odometry().rejects();
    report["drift_filter_walk_deg_per_sqrt_m"] = RadToDeg(drift_corrector.odometry().heading_walk_rad_per_sqrt_m());
    report["drift_filter_sigma_scale"] = drift_corrector.odometry().sigma_scale();
  }
  if (use_graph) {
    nlohmann::json closures = nlohmann::json::array(), uncertain = nlohmann::json::array(),
                   placements = nlohmann::json::array();
    int accepted = 0, same_room = 0;
    for (const auto& c : graph_result.closures) {
      accepted += c.accepted ? 1 : 0;
      same_room += c.accepted && c.same_room ? 1 : 0;
      closures.push_back({{"from_asr", c.from_asr}, {"to_asr", c.to_asr}, {"accepted", c.accepted},
                          {"same_room", c.same_room}, {"agreement", c.agreement}, {"rmse_m", c.rmse_m},
                          {"mahalanobis2", c.mahalanobis2}, {"reason", c.reason},
                          {"relative", {c.relative.x, c.relative.y, RadToDeg(c.relative.theta)}}});
    }
    std::set<int> rooms;
    for (int id : store->Ids()) rooms.insert(store->RoomOf(id));
    for (const auto& e : graph_result.asrs) {
      nlohmann::json j = {{"id", e.asr_id}, {"room", e.room_id}, {"uncertain", e.uncertain}};
      if (e.has_covariance) {
        j["sigma_x_m"] = std::sqrt(std::max(0.0, e.covariance(0, 0)));
        j["sigma_y_m"] = std::sqrt(std::max(0.0, e.covariance(1, 1)));
        j["sigma_theta_deg"] = RadToDeg(std::sqrt(std::max(0.0, e.covariance(2, 2))));
      }
      placements.push_back(j);
      if (e.uncertain) uncertain.push_back({{"id", e.asr_id}, {"why", e.why}});
    }
    report["pose_graph"] = {{"solution", graph_result.solution},
                            {"closures_accepted", accepted},
                            {"revisits", same_room},
                            {"closure_candidates", closures},
                            {"rooms", static_cast<int>(rooms.size())},
                            {"registrations", graph_result.registrations},
                            {"direction_factors", graph_result.direction_factors},
                            {"drift_rate_deg_per_m", RadToDeg(graph_result.drift_rate_rad_per_m)},
                            {"chi2", graph_result.chi2},
                            {"chi2_dof", graph_result.chi2_dof},
                            {"chi2_p999", graph_result.chi2_p999},
                            {"variance_factor", graph_result.variance_factor},
                            {"drift_detected", graph_result.drift_detected},
                            {"drift_alias_risk", graph_result.drift_alias_risk},
                            {"drift_test_chi2", graph_result.drift_test_chi2},
                            {"sigma_factors", {{"odometry", graph_result.odometry_sigma_factor},
                                               {"wall_direction", graph_result.direction_sigma_factor},
                                               {"registration", graph_result.registration_sigma_factor}}},
                            {"path_wall_crossings_odometry", graph_result.crossings_odometry},
                            {"path_wall_crossings_graph", graph_result.crossings_graph},
                            {"path_wall_crossings_chosen", graph_result.crossings_chosen},
                            {"path_overlap_odometry_m", graph_result.overlap_odometry_m},
                            {"path_overlap_graph_m", graph_result.overlap_graph_m},
                            {"solve_seconds", graph_result.solve_seconds},
                            {"covariance_seconds", graph_result.covariance_seconds},
                            {"uncertain_asrs", uncertain},
                            {"placements", placements},
                            {"warnings", graph_result.warnings}};
  }
  for (const auto& [k, v] : localize::HeadingErrorEvalKeys(heading)) report[k] = v;
  if (truth_plan) {
    const asr::RoomMetrics m = asr::EvaluateRooms(all, truth_plan->rooms);
    report["world"] = fs::absolute(a.world).string();
    report["room_precision"] = m.room_precision;
    report["room_recall"] = m.room_recall;
    report["asr_rooms"] = m.asr_room;
  }
  const std::string report_path = (fs::path(folder->staging()) / "report.json").string();
  io::WriteFileAtomically(report_path, report.dump(2) + "\n");
  // Everything is written: close the store (checkpointed, without WAL) and
  // move the files into place, the store last.
  store.reset();
  folder->Commit("map.sqlite");

  std::printf("%s: %ld records, %d ASRs (%d this run), %zu exits, grid %.1f KB -> polylines %.2f KB, %.2f s "
              "(%.1fx real time)\n",
              a.log.c_str(), records, static_cast<int>(all.size()), closed, master.exits.size(),
              bytes_all.grid / 1024.0, bytes_all.polylines / 1024.0, total_seconds,
              total_seconds > 0 ? duration / total_seconds : 0.0);
  if (truth_plan)
    std::printf("rooms: precision %.3f recall %.3f\n", report["room_precision"].get<double>(),
                report["room_recall"].get<double>());
  if (heading.asrs > 0)
    std::printf("heading error per ASR (deg): corrected median %.2f max %.2f, odometry median %.2f max %.2f\n",
                heading.median_deg, heading.max_deg, heading.median_raw_deg, heading.max_raw_deg);
  if (use_graph) {
    int accepted = 0;
    for (const auto& c : graph_result.closures) accepted += c.accepted ? 1 : 0;
    std::printf("pose graph: %s, %d loop closures (%zu candidates), %d rooms, drift %.3f deg/m\n",
                graph_result.solution.c_str(), accepted, graph_result.closures.size(),
                report["pose_graph"]["rooms"].get<int>(), RadToDeg(graph_result.drift_rate_rad_per_m));
    for (const auto& w : graph_result.warnings) std::fprintf(stderr, "cogmap: warning: %s\n", w.c_str());
  } else if (drift_filter)
    std::printf("estimated heading drift: %.3f +- %.3f deg/m\n", RadToDeg(drift_corrector.odometry().rate_rad_per_m()),
                RadToDeg(drift_corrector.odometry().rate_sigma_rad_per_m()));
  std::string listed;
  for (const auto& w : written) listed += w + " ";
  std::printf("outputs in %s: %swalls.json report.json\n", a.output.c_str(), listed.c_str());
  return 0;
}

std::function<int()> SetupMap(CLI::App& sub) {
  auto a = std::make_shared<MapArgs>();
  sub.add_option("LOG", a->log, "The log to map (native, CARMEN, Pioneer pair, EV3)")->required();
  sub.add_option("--format", a->format, "Log format: " + Join(io::LogFormatNames()))->capture_default_str();
  sub.add_option("--robot", a->robot,
                 "Robot: a built-in name (" + Join(sensors::BuiltinRobotNames()) +
                     ") or a robot JSON file (default: the log's, else pioneer16)");
  sub.add_option("--cell", a->cell_m, "Cell size of each room's grid, metres")->capture_default_str();
  sub.add_option("--window", a->window_m, "MHIMM window w, metres")->capture_default_str();
  sub.add_option("--mode", a->mode,
                 "paper: the thesis's line fit and EM rotation per ASR; default: total least squares, robust EM and the pose graph "
                 "over ASRs (docs/pose-graph.md)")
      ->capture_default_str();
  sub.add_option("--boundary", a->boundary,
                 "doorway: fig. 3.4 with the corridor rule; fixed: a new ASR every --asr-length (thesis §4.2)")
      ->capture_default_str();
  sub.add_option("--asr-length", a->asr_length_m,
                 "Corridor / fixed-length ASR length, metres (4.5 in §3.1.2, 4 in §4.2)")
      ->capture_default_str();
  sub.add_option("--max-asr", a->max_asr_m,
                 "Default mode, doorway boundaries: cut a space after this many metres of driving without a "
                 "doorway or corridor cut (0 = never, as in paper mode)")
      ->capture_default_str();
  sub.add_flag("--no-correct", a->no_correct, "Skip every correction: ASRs placed by odometry");
  sub.add_flag("--no-smooth", a->no_smooth,
               "With --no-graph: keep the corrections as computed while mapping (no revision at the end of the run)");
  sub.add_flag("--no-graph", a->no_graph,
               "Default mode without the pose graph (docs/pose-graph.md): the drift filter's odometry "
               "pre-correction, heading correction and smoothing only (the default before the pose graph)");
  sub.add_flag("--no-drift-filter", a->no_drift_filter,
               "With --no-graph: without the drift-rate filter (one EM rotation per ASR, odometry used as it "
               "comes). The pose graph estimates the drift itself and never uses the filter");
  sub.add_option("--add-drift-deg-per-m", a->add_drift_deg_per_m,
                 "Add a systematic heading drift to the log's odometry, degrees per metre driven (CCW positive; "
                 "the log's ground truth stays): to test the correction on a real log")
      ->capture_default_str();
  sub.add_option("--outputs", a->outputs,
                 "Files to write beside map.sqlite, walls.json and report.json, comma-separated: svg, png, pgm "
                 "(map_server PGM + YAML), geojson, aria (map.map), compare (map_compare.svg/.png), heading "
                 "(heading_error.png); default = svg,geojson,aria; all = every one")
      ->capture_default_str();
  sub.add_flag("--raw", a->raw, "Draw the master map at the raw odometry poses (the store keeps both)");
  sub.add_flag("--resume", a->resume,
               "Continue into OUTDIR/map.sqlite: new ASRs append with the next ids; the log's first pose is "
               "taken to be where the stored run ended");
  sub.add_option("--world", a->world,
                 "Ground-truth world (2D-Map with Room cairns): adds room_precision / room_recall to report.json");
  sub.add_option("-o,--output", a->output, "Output folder (created)")->required();
  return [a] { return RunMap(*a); };
}

const bool kRegistered = RegisterCommand(
    {"map", "Map a log into ASRs (rooms), store them and write the master map", 50, SetupMap});

}  // namespace
}  // namespace cogmap::app
