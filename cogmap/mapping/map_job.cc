#include "cogmap/mapping/map_job.h"

#include <algorithm>
#include <charconv>
#include <chrono>
#include <cmath>
#include <exception>
#include <filesystem>
#include <future>
#include <iomanip>
#include <map>
#include <optional>
#include <set>
#include <sstream>

#include "cogmap/asr/mapper.h"
#include "cogmap/asr/room_metrics.h"
#include "cogmap/asr/store.h"
#include "cogmap/core/angles.h"
#include "cogmap/core/error.h"
#include "cogmap/core/process.h"
#include "cogmap/core/text.h"
#include "cogmap/draw/layout.h"
#include "cogmap/draw/map_picture.h"
#include "cogmap/draw/world_picture.h"
#include "cogmap/draw/plots.h"
#include "cogmap/eval/trajectory_metrics.h"
#include "cogmap/io/atomic_file.h"
#include "cogmap/io/log_lines.h"
#include "cogmap/io/log_reader.h"
#include "cogmap/io/map_files.h"
#include "cogmap/io/output_folder.h"
#include "cogmap/io/polyline_io.h"
#include "cogmap/io/read_ahead.h"
#include "cogmap/io/world_io.h"
#include "cogmap/localize/heading_corrector.h"
#include "cogmap/localize/heading_error.h"
#include "cogmap/mapping/floor_plan.h"
#include "cogmap/mapping/report.h"
#include "cogmap/plan/plan.h"
#include "cogmap/plan/plan_json.h"
#include "cogmap/sensors/robot_json.h"

namespace cogmap::mapping {
namespace fs = std::filesystem;
namespace {

// A drawing to STEM.svg and / or STEM.png in 'folder' (listed in 'written');
// the last file lets the drawing go as cairo takes it.
void WriteSvgAndPng(draw::Drawing picture, const std::string& folder, const std::string& stem, bool svg, bool png,
                    std::vector<std::string>* written) {
  if (svg) {
    const std::string path = (fs::path(folder) / (stem + ".svg")).string();
    png ? picture.Write(path) : std::move(picture).Write(path);
    written->push_back(stem + ".svg");
  }
  if (png) {
    std::move(picture).Write((fs::path(folder) / (stem + ".png")).string());
    written->push_back(stem + ".png");
  }
}

// Opens the run's store in the folder's staging area: a copy of the stored map
// to continue (--resume, checked where it is first), or a new one (which may
// replace a cogmap store, never another file nor a newer cogmap's store).
std::unique_ptr<asr::SqliteAsrStore> OpenStore(io::OutputFolder& folder, bool resume) {
  const std::string store_path = folder.Final("map.sqlite");
  if (resume) {
    std::error_code ec;
    if (!fs::exists(store_path, ec)) {
      // A run killed before it ever committed a map leaves its store in a
      // failed-run-*-killed folder (set aside when this run opened the
      // folder): say where, and how to continue it.
      std::string killed;
      for (fs::directory_iterator it(fs::path(store_path).parent_path(), ec), end; !ec && it != end; it.increment(ec)) {
        const std::string name = it->path().filename().string();
        if (name.rfind("failed-run-", 0) == 0 && name.size() > 7 && name.compare(name.size() - 7, 7, "-killed") == 0 &&
            fs::exists(it->path() / "map.sqlite") && it->path().string() > killed)
          killed = it->path().string();
      }
      if (!killed.empty())
        throw InputError(store_path, 0,
                         "no such store; a killed run's store is in " + killed + "/: continue it with -o " + killed +
                             " --resume (with its log: from where it stopped)");
    }
    // Every row read where it is, so that a damaged one is named as the
    // user's file, not as the staging copy the run continues.
    const auto original = asr::SqliteAsrStore::Open(store_path, asr::SqliteAsrStore::OpenMode::kReadOnly);
    for (int id : original->Ids()) {
      original->Get(id);
      original->GetPlacement(id);
    }
    // And the values the run continues from (MappingPipeline::Resume).
    asr::FinishedThrough(*original);
    asr::NextAsrId(*original);
    asr::LastRawPose(*original);
    original->GetMetaPose("world_from_map");
    folder.CopyIntoStaging("map.sqlite");
    return asr::SqliteAsrStore::Open(folder.Staged("map.sqlite"), asr::SqliteAsrStore::OpenMode::kOpenExisting);
  }
  std::error_code ec;
  if (fs::exists(store_path, ec) && fs::file_size(store_path, ec) > 0)
    asr::SqliteAsrStore::Open(store_path, asr::SqliteAsrStore::OpenMode::kReadOnly);
  return asr::SqliteAsrStore::Open(folder.Staged("map.sqlite"), asr::SqliteAsrStore::OpenMode::kReplace);
}

// How far from the robot its ASR grids took readings: the largest of
// min(max range, MHIMM window) over its sensors, from the robot's centre.
double SensorReach(const sensors::RobotDescription& robot, double window_m) {
  double reach = 0.0;
  for (const auto& s : robot.sensors)
    reach = std::max(reach, s.robot_from_sensor.translation().norm() + std::min(s.max_range_m, window_m));
  return reach > 0.0 ? reach : window_m;
}

// Pictures drawn once the floor plan is built: the plan's and the heading
// error's.
bool PicturesAfterPlan(const OutputChoice& o) { return o.plan || o.plan_png || o.heading; }

// The most ASRs a map may have for its fonts to load during the end-of-run
// solve rather than once its floor plan is built (pictures after the plan
// only). The fonts' tables (some 4 MB, held to the end) then raise the run's
// peak by at most their own size, for the plan's working set (about 40 KB
// per ASR: 42 MB at 1000 rooms) is under them; and the plan's picture, drawn
// beside its files, no longer waits some 5 ms for them (5 % of nine_rooms'
// whole run). A larger map keeps the fonts for after its plan, whose largest
// structures are gone by then (a 1000-room run's peak 3.5 MiB lower).
constexpr int kFontsDuringSolveMaxAsrs = 100;

}  // namespace

OutputChoice OutputChoice::All() {
  OutputChoice c;
  c.svg = c.png = c.pgm = c.geojson = c.aria = c.gpkg = c.route = c.plan = c.plan_png = c.compare = c.heading = true;
  return c;
}

std::string OutputChoice::Names() {
  return "default, all, svg, png, pgm, geojson, aria, gpkg, route, plan, plan-svg, plan-png, compare, heading";
}

OutputChoice OutputChoice::Parse(const std::string& text) {
  OutputChoice c;
  c.svg = c.png = c.pgm = c.geojson = c.aria = c.gpkg = c.route = c.plan = c.plan_png = c.compare = c.heading = false;
  std::stringstream in(text);
  std::string item;
  bool any = false;
  while (std::getline(in, item, ',')) {
    any = true;
    if (item == "all") c = All();
    // The fast set (issue 14): the floor plan as SVG and the vector files;
    // the diagnostic pictures and the rasters on request.
    else if (item == "default") c.geojson = c.aria = c.gpkg = c.route = c.plan = true;
    else if (item == "svg") c.svg = true;
    else if (item == "png") c.png = true;
    else if (item == "pgm") c.pgm = true;
    else if (item == "geojson") c.geojson = true;
    else if (item == "aria") c.aria = true;
    else if (item == "gpkg") c.gpkg = true;
    else if (item == "route") c.route = true;
    else if (item == "plan") c.plan = c.plan_png = true;
    else if (item == "plan-svg") c.plan = true;
    else if (item == "plan-png") c.plan_png = true;
    else if (item == "compare") c.compare = true;
    else if (item == "heading") c.heading = true;
    else throw InputError("--outputs " + text + ": unknown output '" + item + "' (expected " + Names() + ")");
  }
  if (!any) throw InputError("--outputs: empty list");
  return c;
}

MapJobSummary RunMapJob(io::LogReader& log, const MapJob& job) {
  const auto start = std::chrono::steady_clock::now();
  job.mapping.Validate();
  const sensors::RobotDescription robot = io::RobotFor(log, job.robot_spec);
  if (!job.world.empty()) io::ReadWorld(job.world);  // a bad world fails before mapping
  const OutputChoice& o = job.outputs;
  // The drawing libraries load on a thread of their own while the log is
  // mapped, and so do their fonts (some 4 MB of fontconfig's and pango's
  // tables, held to the end) when a picture is drawn before the floor plan
  // (the master map's); when all come after it, the fonts load during the
  // end-of-run solve for a small map (kFontsDuringSolveMaxAsrs), else once
  // the plan is built (its largest structures are gone by then), while its
  // files are written: a 1000-room run's peak is then 3.5 MiB lower. With
  // --threads 1, all by the first picture drawn.
  if (job.mapping.threads >= 2 && (o.svg || o.png || o.compare))
    draw::Drawing::PrepareFonts(draw::PageFonts());
  else if (job.mapping.threads >= 2 && PicturesAfterPlan(o))
    draw::Drawing::PrepareLibraries();

  // The output folder (docs/store.md): locked for this run, everything written
  // into its staging folder and moved into place at the end.
  auto folder = io::OutputFolder::Open(job.output_dir);
  struct SetAsideOnFailure {
    io::OutputFolder* folder;
    const MapJob* job;
    ~SetAsideOnFailure() {  // after the store is closed (declared before it)
      if (folder->committed() || std::uncaught_exceptions() == 0) return;
      const std::string kept = folder->Abandon();
      if (!kept.empty() && job->notice) job->notice(kept + ": this run's partial result (the previous map is untouched)");
    }
  } set_aside{folder.get(), &job};
  std::unique_ptr<asr::SqliteAsrStore> store;
  std::unique_ptr<MappingPipeline> pipeline;
  // One pass over a log into a new staging store (or the resumed one).
  auto map_pass = [&](io::LogReader& from, const MappingOptions& mapping) {
    pipeline.reset();
    store.reset();
    store = OpenStore(*folder, job.resume);
    // report.json carries the same id: a reader can check that they belong together.
    store->SetMeta("run_id", folder->run_id());
    asr::SetRobotRadius(store.get(), robot.radius_m);
    asr::SetSensorReach(store.get(), SensorReach(robot, job.mapping.window_m));
    asr::SetSensorBeam(store.get(), sensors::WidestBeamRad(robot));
    pipeline = std::make_unique<MappingPipeline>(robot, mapping, store.get());
    const int stored_max = store->MaxId();
    const int stored_count = store->Count();
    if (job.resume) pipeline->Resume();
    // The log's identity goes into the store with every ASR. Resumed with
    // the log the store was mapped from (or that log grown since), the run
    // continues where the stored one stopped: its last stored ASR closed at
    // record N (whose pose is the stored last_raw_pose), so records 1..N-1
    // are skipped and record N, pushed again, joins the two (docs/store.md).
    const std::string fingerprint = io::LogFingerprint(from.path());
    long skip = 0;
    std::string damaged;  // a resumed store's log identity that no run wrote
    if (job.resume) {
      const auto stored = store->GetMeta(asr::kMetaLogFingerprint);
      const auto last = store->GetMeta(asr::kMetaLastRecord);
      if (stored && last) {
        long through = 0;
        const char* end = last->data() + last->size();
        const auto [at, ec] = std::from_chars(last->data(), end, through);
        if (ec != std::errc() || at != end || through < 1 || !io::IsFingerprint(*stored))
          damaged = "a damaged store: its log_fingerprint '" + *stored + "' and last_record '" + *last +
                    "' do not name a log and a record of it";
        else if (io::IsLogOf(from.path(), *stored))
          skip = through - 1;
      }
    }
    pipeline->SetLogIdentity(fingerprint, skip);
    sensors::LogRecord rec;
    // With threads to spare the log is read on one of its own, ahead of the
    // grids (not standard input: a live robot's stream may pause for long).
    std::optional<io::ReadAhead> ahead;
    if (mapping.threads >= 2 && from.path() != "-" && from.path() != io::kStdinName) ahead.emplace(from);
    io::LogReader& src = ahead ? static_cast<io::LogReader&>(*ahead) : from;
    try {
      if (!damaged.empty()) throw InputError(folder->Final("map.sqlite"), 0, damaged);
      long n = 0;
      if (skip > 0) {
        long k = 0;
        while (k < skip && src.Next(&rec)) ++k;
        sensors::LogRecord join;
        const bool has_join = k == skip && src.Next(&join);
        if (!has_join)
          throw InputError(from.path() + ": the store was mapped from this log up to record " + std::to_string(skip + 1) +
                           ", but it has only " + std::to_string(k) +
                           " records: not the same log (give another log to continue the map)");
        const bool more = src.Next(&rec);
        // A run killed after its last room closed (in its end-of-run solve or
        // its outputs) has every record stored but was never finished: its
        // rooms are placed and its files written now.
        const auto through = asr::FinishedThrough(*store);
        const bool unfinished = through && *through < stored_max;
        if (!more && !unfinished)
          throw InputError(from.path() + ": nothing to resume: the store already holds this log to its end (all " +
                           std::to_string(skip + 1) + " records); give the log that continues it");
        if (job.notice)
          job.notice(from.path() + ": the store was mapped from this log up to record " + std::to_string(skip + 1) +
                     (more ? ": continuing from there" : ", its last; finishing the run that was cut short"));
        if (more) {
          pipeline->Push(join);
          pipeline->Push(rec);
          n = 2;
        }
      }
      while (src.Next(&rec)) {
        pipeline->Push(rec);
        if (++n % 256 == 0 && job.progress) job.progress(src.progress(), pipeline->asrs_closed());
      }
      if (mapping.threads >= 2 && PicturesAfterPlan(o) &&
          stored_count + pipeline->asrs_closed() + 1 <= kFontsDuringSolveMaxAsrs)  // + 1: the room still open
        draw::Drawing::PrepareFonts(draw::PageFonts());
      pipeline->Finish();
    } catch (...) {
      // Every ASR closed before the bad line is in the staging store (one
      // transaction each; the pipeline's threads finish storing the ones they
      // hold as it goes); SetAsideOnFailure keeps it under failed-run-*. A new
      // store that holds none is no partial result: no failed-run folder for it.
      pipeline.reset();
      // Nor a resumed store given nothing new (its copy is the map already in place).
      if ((!job.resume && store->Count() == 0) || (job.resume && store->MaxId() == stored_max)) {
        store.reset();
        std::error_code ec;
        for (const char* suffix : {"", "-wal", "-shm", "-journal"}) fs::remove(folder->Staged("map.sqlite") + suffix, ec);
      }
      throw;
    }
  };
  map_pass(log, job.mapping);
  // The second pass (MapJob::second_pass): the drift the first found, kept
  // and not ambiguous, removed inside every room while the log is mapped
  // again. The first pass's store is replaced; its figures go to report.json.
  {
    const RunResult& first = pipeline->result();
    const graph::OptimizerResult& g = first.graph;
    // Why a second pass asked for is not made ("": it is).
    std::string not_made;
    if (!job.reopen_log) not_made = "the log cannot be read again (standard input)";
    else if (job.resume) not_made = "not with --resume";
    else if (job.mapping.pre_bend) not_made = "not with --pre-bend";
    else if (job.mapping.remove_drift_rad_per_m != 0.0) not_made = "a drift was given (--remove-drift-deg-per-m)";
    else if (first.correction != Correction::kPoseGraph) not_made = "only with the pose graph";
    else if (g.solution == "odometry") not_made = "the map was left at its odometry";
    else if (!g.drift_detected || g.drift_rate_rad_per_m == 0.0 || !std::isfinite(g.drift_rate_rad_per_m))
      not_made = "no drift found";
    else if (g.drift_alias_risk) not_made = "the drift found is ambiguous";
    if (job.second_pass && !not_made.empty() && job.notice) job.notice("second pass not made: " + not_made);
    if (job.second_pass && not_made.empty()) {
      const double rate = g.drift_rate_rad_per_m, sigma = g.drift_rate_sigma_rad_per_m;
      const double first_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
      if (job.notice) {
        std::string text;
        AppendF(&text, "second pass: the log mapped again with the drift found (%.3f deg/m) removed inside each room",
                RadToDeg(rate));
        job.notice(text);
      }
      std::unique_ptr<io::LogReader> again = job.reopen_log();
      MappingOptions mapping = job.mapping;
      mapping.remove_drift_rad_per_m = rate;
      map_pass(*again, mapping);
      pipeline->NoteSecondPass(rate, first_seconds, sigma);
    }
  }
  const RunResult& run = pipeline->result();
  OutputContext ctx;
  ctx.store_path = folder->Final("map.sqlite");
  ctx.run_id = folder->run_id();
  ctx.start = job.started.value_or(start);
  ctx.startup_seconds = std::chrono::duration<double>(start - ctx.start).count();
  ctx.mapping_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  ctx.rss_mapping_kb = PeakResidentKib();
  // The store is closed (checkpointed, without WAL: a few ms of writing and
  // syncing) on a thread of its own while the files made from the floor
  // plan are written; joined before anything is committed (or, on an
  // error, before the staging folder is set aside: destroyed first).
  std::future<void> closing;
  if (job.mapping.threads >= 2)  // --threads 1: all on one thread, the store closed below
    ctx.store_read = [&] { closing = std::async(std::launch::async, [&store] { store.reset(); }); };
  MapJobSummary out = WriteMapOutputs(*store, run, job, robot, folder->staging(), ctx);
  // Everything is written: the store closed, the files moved into place, the
  // store last.
  if (closing.valid()) closing.get();
  store.reset();
  folder->Commit("map.sqlite");
  return out;
}

MapJobSummary WriteMapOutputs(asr::SqliteAsrStore& store_ref, const RunResult& run, const MapJob& job,
                              const sensors::RobotDescription& robot, const std::string& dir,
                              const OutputContext& octx) {
  asr::SqliteAsrStore* store = &store_ref;
  const std::string& staging = dir;
  std::optional<FloorPlan> truth_plan;
  if (!job.world.empty()) truth_plan = io::ReadWorld(job.world).plan;
  // Everything in the store (earlier runs included), in one pass: the ASRs,
  // the robot's path through each as placed (drift inside it removed), their
  // rooms.
  std::vector<asr::Asr> all;
  std::map<int, std::vector<Pose2>> placed_paths;
  std::map<int, int> room_of;
  for (int id : store->Ids()) {
    all.push_back(*store->Get(id));
    if (auto p = store->GetPlacement(id)) placed_paths[id] = std::move(p->corrected_path);
    room_of[id] = store->RoomOf(id);
  }
  // What reads the true paths comes first (the heading error per ASR, the
  // rooms against the truth); then they go: nothing below reads them.
  const localize::HeadingErrorStats heading = localize::ComputeHeadingErrors(all, placed_paths);
  std::optional<asr::RoomMetrics> room_metrics;
  if (truth_plan) room_metrics = asr::EvaluateRooms(all, truth_plan->rooms);
  // The truth's frame at the first record of the store's first run with truth
  // (walls.json): its path and truth paired from the end, as the trajectory
  // metrics pair them (a CARMEN log's first poses have no truth).
  const std::optional<Pose2> first_world_from_map = all.empty() ? std::nullopt : eval::TruthFromRaw(all.front());
  for (auto& x : all) std::vector<Pose2>().swap(x.true_path);
  // The placed paths are read again from the store for the floor plan: they
  // are not held while the master map's pictures are encoded (5.9 MB at
  // 1000 rooms).
  std::set<int> placed_ids;  // the ASRs with a placed path
  for (const auto& [id, p] : placed_paths)
    if (!p.empty()) placed_ids.insert(id);
  // The master map: each path as placed (the drift inside its ASR removed),
  // each placed path freed as it is copied.
  io::MasterMap master = io::BuildMasterMap(all, !job.raw, job.raw ? nullptr : &placed_paths);
  std::map<int, std::vector<Pose2>>().swap(placed_paths);
  MapJobSummary out;
  out.written = {"map.sqlite"};
  // walls.json for `cogmap eval` (the master map's walls; map frame = the raw
  // odometry frame of the first run, placed in the truth's world when known),
  // written first: the master map's walls can go once they are drawn.
  // A resumed store keeps the frame its first run wrote. One killed before
  // writing it has it from its first ASR: the truth and the raw pose at the
  // first record of the first run (a resumed log's first record is where
  // the drift had taken the odometry by then, not where the frames meet).
  std::optional<Pose2> world_from_map = run.world_from_map;
  if (job.resume) world_from_map = store->GetMeta("world_from_map") ? std::nullopt : first_world_from_map;
  if (world_from_map) {
    const Pose2 w = *world_from_map;
    store->SetMeta("world_from_map", std::to_string(w.x) + " " + std::to_string(w.y) + " " + std::to_string(w.theta));
  }
  io::WallsFile wf;
  for (const auto& r : master.rooms) wf.polylines.insert(wf.polylines.end(), r.walls.begin(), r.walls.end());
  if (auto w = store->GetMetaPose("world_from_map")) {
    wf.world_from_map = *w;
    wf.has_truth = true;
  }
  wf.log_path = job.log_path == "-" ? "-" : fs::absolute(job.log_path).string();
  wf.log_format = job.log_format;
  wf.robot = job.robot_spec.empty() ? robot.name : job.robot_spec;
  wf.mode = job.mapping.paper ? "paper" : "default";
  wf.cell_m = job.mapping.cell_m;
  // The range within which walls get mapped (as cogmap vectorize records it):
  // min(max range, window), so that recall counts only walls the grid could hold.
  for (const auto& s : robot.sensors)
    wf.sensor_range_m = std::max(wf.sensor_range_m, std::min(s.max_range_m, job.mapping.window_m));
  for (const auto& l : wf.polylines) wf.vertex_count += static_cast<int64_t>(l.size());
  for (const auto& x : all) {
    wf.bytes_grid += x.bytes.grid;
    wf.bytes_vertices += x.bytes.vertices;
    wf.bytes_polylines += x.bytes.polylines;
  }
  io::WriteWallsJson((fs::path(staging) / "walls.json").string(), wf);
  const int exit_count = static_cast<int>(master.exits.size());
  const int64_t bytes_grid = wf.bytes_grid, bytes_polylines = wf.bytes_polylines;
  wf = {};

  // What the pictures below no longer need goes before they are encoded: the
  // raw paths (the master map holds them as drawn; the floor plan reads the
  // placed paths, an ASR without one keeps its raw path), and, once the map
  // is drawn, the master map itself (the drawing holds what it shows,
  // walls.json its walls): a 1000-room map.svg is some 5 MB, which cairo's
  // SVG surface records whole before writing it. The comparison (drawn after the map: cairo numbers
  // its surfaces in order, and the files stay as they were) reads both.
  auto drop_raw_paths = [&] {
    for (auto& x : all)
      if (placed_ids.count(x.id)) std::vector<Pose2>().swap(x.path);
  };
  if (!job.outputs.compare) drop_raw_paths();
  // The master map's pictures (every ASR's walls); its files come from the
  // floor plan below.
  if (job.outputs.svg || job.outputs.png) {
    draw::MapPictureOptions map_picture;
    map_picture.picture.px_per_m = job.px_per_m;
    draw::Drawing picture = draw::DrawMasterMap(master, map_picture).drawing;
    if (!job.outputs.compare) master = {};  // the drawing holds what it shows
    WriteSvgAndPng(std::move(picture), staging, "map", job.outputs.svg, job.outputs.png, &out.written);
  }

  // Before / after correction side by side (drawn before the floor plan,
  // listed after it).
  std::vector<std::string> compare_written;
  if (job.outputs.compare) {
    const io::MasterMap raw_map = io::BuildMasterMap(all, false);
    const io::MasterMap cor_map = job.raw ? io::BuildMasterMap(all, true) : master;
    // With pre-correction each ASR's walls were mapped on corrected odometry:
    // the left picture places them by odometry (the true raw map: --no-correct).
    const std::string lt = run.correction == Correction::kDriftFilter ? "Before: ASRs at their odometry poses"
                                                                      : "Before: odometry";
    const std::string rt = run.correction == Correction::kNone        ? "After: not corrected (--no-correct)"
                           : run.correction == Correction::kPoseGraph ? std::string("After: pose graph (default)")
                           : "After: heading correction (" + std::string(job.mapping.paper ? "paper" : "default") + ")";
    draw::Drawing compare = draw::DrawSideBySide(raw_map, lt, cor_map, rt);
    compare.Write((fs::path(staging) / "map_compare.svg").string());
    std::move(compare).Write((fs::path(staging) / "map_compare.png").string());
    compare_written = {"map_compare.svg", "map_compare.png"};
  }
  // What is drawn is drawn: the paths go before the floor plan is built, and
  // the master map (walls.json has its walls).
  drop_raw_paths();
  master = {};

  // The floor plan (docs/floor-plan.md): plan.json always (cogmap eval reads
  // it), and the files made from it.
  for (const asr::Asr& x : all)
    if (placed_ids.count(x.id))
      if (auto p = store->GetPlacement(x.id)) placed_paths[x.id] = std::move(p->corrected_path);
  // Nothing below reads the placed paths, nor the ASRs' walls, paths and
  // floor (walls.json and report.json take their counts, sizes and times):
  // the plan releases them as soon as it has read them, before it floods its
  // rooms; the exits go after it.
  plan::PlanOptions plan_options = PlanOptionsOfStore(*store);
  plan_options.threads = job.mapping.threads;
  const plan::Plan floor_plan = plan::BuildPlanReleasing(&all, room_of, plan_options, &placed_paths);
  if (octx.store_read) octx.store_read();  // the store is not read below
  if (job.mapping.threads >= 2 && PicturesAfterPlan(job.outputs))
    draw::Drawing::PrepareFonts(draw::PageFonts());  // (a no-op when loaded before)
  for (auto& x : all) std::vector<asr::Exit>().swap(x.exits);
  out.written.push_back("plan.json");
  io::PlanFileOptions pf;
  pf.threads = job.mapping.threads;
  pf.geo_anchor = job.geo_anchor;
  pf.gpkg = job.outputs.gpkg;
  pf.geojson = job.outputs.geojson;
  pf.route_graph = job.outputs.route;
  pf.aria = job.outputs.aria;
  pf.map_server = job.outputs.pgm;
  // The plan's picture is drawn and written on a thread of its own, and
  // plan.json on another, while its files are written here, two at a time
  // (all only read the plan; the mapping's threads are done, a core is
  // free: intel's files 15 -> 10 ms); with --threads 1 one after the other,
  // on this thread. Listed in the same order either way.
  std::vector<std::string> plan_pictures;
  std::future<void> drawing;
  if (job.outputs.plan || job.outputs.plan_png)
    drawing = std::async(job.mapping.threads >= 2 ? std::launch::async : std::launch::deferred, [&] {
      draw::PlanPictureOptions pp;
      pp.picture.px_per_m = job.px_per_m;
      draw::Drawing picture = draw::DrawPlan(floor_plan, pp).drawing;
      WriteSvgAndPng(std::move(picture), staging, "plan", job.outputs.plan, job.outputs.plan_png, &plan_pictures);
    });
  std::future<void> plan_json =
      std::async(job.mapping.threads >= 2 ? std::launch::async : std::launch::deferred, [&] {
        io::WriteFileAtomically((fs::path(staging) / "plan.json").string(),
                                [&](std::ostream& o) { plan::WritePlanJson(o, floor_plan); });
      });
  // Should this throw, the picture's and plan.json's threads are waited for
  // all the same: the future of std::async waits in its destructor (declared
  // after the plan it reads); a deferred one never runs.
  for (const auto& f : io::WritePlanFiles(staging, floor_plan, pf)) out.written.push_back(fs::path(f).filename().string());
  plan_json.get();
  if (drawing.valid()) drawing.get();  // their errors, if any, are raised here
  out.written.insert(out.written.end(), plan_pictures.begin(), plan_pictures.end());
  out.plan_rooms = static_cast<int>(floor_plan.rooms.size());
  out.plan_walls = static_cast<int>(floor_plan.walls.size());
  out.plan_doors = static_cast<int>(floor_plan.doors.size());
  out.written.insert(out.written.end(), compare_written.begin(), compare_written.end());

  // The heading error per ASR against the truth, on the path as placed.
  if (job.outputs.heading && heading.asrs > 0) {
    draw::PlotHeadingErrors(heading).Write((fs::path(staging) / "heading_error.png").string());
    out.written.push_back("heading_error.png");
  }


  // The summary and report.json.
  out.records = run.records;
  out.asrs = static_cast<int>(all.size());
  out.asrs_this_run = static_cast<int>(run.asrs.size());
  out.exits = exit_count;
  out.bytes_grid = bytes_grid;
  out.bytes_polylines = bytes_polylines;
  std::set<int> rooms;
  for (const auto& [id, room] : room_of) rooms.insert(room);
  out.rooms = static_cast<int>(rooms.size());
  out.heading_asrs = heading.asrs;
  out.heading_median_deg = heading.median_deg;
  out.heading_max_deg = heading.max_deg;
  out.heading_median_raw_deg = heading.median_raw_deg;
  out.heading_max_raw_deg = heading.max_raw_deg;
  if (heading.drift_asrs >= 3) out.odometry_drift_deg_per_m = RadToDeg(heading.odometry_drift_rad_per_m);
  ReportContext ctx;
  ctx.job = &job;
  ctx.robot = &robot;
  ctx.run = &run;
  ctx.all = &all;
  ctx.heading = &heading;
  ctx.exits = out.exits;
  ctx.rooms = out.rooms;
  ctx.store_path = octx.store_path;
  ctx.run_id = octx.run_id;
  ctx.mapping_seconds = octx.mapping_seconds;
  ctx.startup_seconds = octx.startup_seconds;
  ctx.rss_mapping_kb = octx.rss_mapping_kb;
  if (room_metrics) {
    out.room_precision = room_metrics->room_precision;
    out.room_recall = room_metrics->room_recall;
    ctx.room_metrics = *room_metrics;
  }
  out.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - octx.start).count();
  out.times_real_time = out.seconds > 0 ? run.duration_s() / out.seconds : 0.0;
  ctx.total_seconds = out.seconds;
  io::WriteFileAtomically((fs::path(staging) / "report.json").string(),
                          [&](std::ostream& o) { WriteReport(ctx, o); });
  out.run = run;
  out.warnings = run.graph.warnings;
  for (const std::string& w : ScanMatchWarnings(job.mapping, run)) out.warnings.push_back(w);
  for (const std::string& w : DistanceScaleWarnings(run)) out.warnings.push_back(w);
  return out;
}

std::string MapSummaryText(const MapJobSummary& s, const MapJob& job) {
  std::string out;
  std::string pace = "x real time unknown: the log's timestamps do not advance";
  if (s.times_real_time > 0.0) pace.clear(), AppendF(&pace, "%.1fx real time", s.times_real_time);
  AppendF(&out, "%s: %ld records, %d ASRs (%d this run), %d exits, grid %.1f KB -> polylines %.2f KB, %.2f s (%s)\n",
          job.log_path.c_str(), s.records, s.asrs, s.asrs_this_run, s.exits, s.bytes_grid / 1024.0,
          s.bytes_polylines / 1024.0, s.seconds, pace.c_str());
  AppendF(&out, "floor plan: %d rooms, %d walls, %d doors\n", s.plan_rooms, s.plan_walls, s.plan_doors);
  if (s.room_precision) AppendF(&out, "rooms: precision %.3f recall %.3f\n", *s.room_precision, *s.room_recall);
  if (s.heading_asrs > 0)
    AppendF(&out, "heading error per ASR (deg): corrected median %.2f max %.2f, odometry median %.2f max %.2f\n",
            s.heading_median_deg, s.heading_max_deg, s.heading_median_raw_deg, s.heading_max_raw_deg);
  const RunResult& r = s.run;
  if (r.correction == Correction::kPoseGraph) {
    int accepted = 0;
    for (const auto& c : r.graph.closures) accepted += c.accepted ? 1 : 0;
    std::string sigma, tail;
    if (r.graph.drift_rate_sigma_rad_per_m >= 0.0)
      AppendF(&sigma, " +- %.3f", RadToDeg(r.graph.drift_rate_sigma_rad_per_m));
    // Other rates the walls fit about as well: the rate's sigma over all of
    // them, when it says more than the kept fit's own (a sparse sonar ring
    // on a real building: 0.000 +- 0.062 alone, +- 2.4 over its fits).
    const double own = r.graph.drift_rate_sigma_rad_per_m, all = r.graph.drift_rate_spread_sigma_rad_per_m;
    if (own >= 0.0 && all > 1.5 * own && r.graph.drift_hypotheses.size() > 1)
      AppendF(&tail, "; +- %.3f over the %zu rates the walls fit", RadToDeg(all), r.graph.drift_hypotheses.size());
    // With truth: the odometry's own drift, and how many sigmas from it.
    if (s.odometry_drift_deg_per_m) {
      AppendF(&tail, "; truth %.3f", *s.odometry_drift_deg_per_m);
      const double sig = all >= 0.0 ? all : own;
      if (sig > 0.0)
        AppendF(&tail, " (%.1f sigma)",
                std::abs(RadToDeg(r.graph.drift_rate_rad_per_m) - *s.odometry_drift_deg_per_m) / RadToDeg(sig));
    }
    AppendF(&out, "pose graph: %s, %d loop closures (%zu candidates), %d rooms, drift %.3f%s deg/m%s%s\n",
            r.graph.solution.c_str(), accepted, r.graph.closures.size(), s.rooms,
            RadToDeg(r.graph.drift_rate_rad_per_m), sigma.c_str(), r.graph.drift_detected ? "" : " (none found)",
            tail.c_str());
    // A wing turned against the rest (docs/pose-graph.md): its directions,
    // each modulo a quarter turn, and how many ASRs follow each.
    const std::vector<double> dirs = graph::BuildingDirectionsDeg(r.graph);
    if (dirs.size() > 1) {
      std::vector<int> count(dirs.size(), 0);
      for (const auto& e : r.graph.asrs)
        if (e.direction_factor && e.building_direction >= 0 && e.building_direction < static_cast<int>(dirs.size()))
          ++count[e.building_direction];
      // Listed as found, not called a wing: a wing kept under the test's
      // margin may draw together when solved with the whole map, and
      // MapOptimizer's warning then says so.
      AppendF(&out, "building directions (each modulo a quarter turn, and the ASRs held to each):");
      for (size_t k = 0; k < dirs.size(); ++k) {
        AppendF(&out, "%s %.1f deg (%d ASRs)", k ? "," : "", dirs[k], count[k]);
      }
      AppendF(&out, "\n");
    }
    // The odometry's heading held at its motion model (docs/pose-graph.md,
    // "The odometry's heading held at its model").
    if (r.graph.odometry_heading_held)
      AppendF(&out,
              "odometry heading: held at its motion model (the walls fitted it %.1f times as noisy, with no drift "
              "found, and turned the map through walls)\n",
              r.graph.odometry_heading_fitted_factor);
  } else if (r.correction == Correction::kDriftFilter) {
    AppendF(&out, "estimated heading drift: %.3f +- %.3f deg/m\n", RadToDeg(r.drift_rate_rad_per_m),
            RadToDeg(r.drift_rate_sigma_rad_per_m));
  }
  // The distance scale (docs/pose-graph.md, "Distance scale").
  if (r.distance_scale_measured) {
    const localize::OdometryScaleEstimate& e = r.distance_scale_estimate;
    if (e.valid)
      AppendF(&out, "distance scale: %.4f +- %.4f from %d runs at walls; odometry scaled by %.4f\n", e.scale, e.sigma,
              e.runs, r.distance_scale_applied);
    else
      AppendF(&out, "distance scale: not measured (%d runs at walls, 5 needed); odometry as it came\n", e.runs);
  } else if (r.distance_scale_applied != 1.0) {
    AppendF(&out, "distance scale: odometry scaled by %.4f (given)\n", r.distance_scale_applied);
  }
  std::string listed;
  for (const auto& w : s.written) listed += w + " ";
  AppendF(&out, "outputs in %s: %swalls.json report.json\n", job.output_dir.c_str(), listed.c_str());
  return out;
}

}  // namespace cogmap::mapping
