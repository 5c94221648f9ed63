// `cogmap map`: options in, mapping::RunMapJob, a summary out. The pipeline
// (cogmap/mapping) maps the log into OUTDIR/map.sqlite and writes the master
// map's files and report.json.
#include <cstdio>
#if defined(__GLIBC__)
#include <malloc.h>
#endif
#include <memory>
#include <string>
#include <vector>

#include "app/cli_util.h"
#include "app/command.h"
#include "app/log_warnings.h"
#include "app/progress.h"
#include "cogmap/core/angles.h"
#include "cogmap/core/error.h"
#include "cogmap/io/log_reader.h"
#include "cogmap/io/plan_files.h"
#include "cogmap/mapping/map_job.h"
#include "cogmap/sensors/robot_json.h"

namespace cogmap::app {
namespace {

struct MapArgs {
  mapping::MapJob job;  // most options bind to its fields
  std::string mode = "default", boundary = "doorway", outputs = "default", geo_anchor, walls = "default";
  bool no_correct = false, no_drift_filter = false, no_graph = false, no_smooth = false;
  double add_drift_deg_per_m = 0.0;
  double remove_drift_deg_per_m = 0.0;
  bool second_pass = false;
  std::string scan_match = "auto";
  std::string distance_scale = "auto";
  std::vector<std::string> topics;
};

int RunMap(MapArgs& a) {
#if defined(__GLIBC__)
  // Blocks of 1 MiB and more (the store's pages, cairo's record of a big
  // picture, grids) come from mmap and go back to the system when freed.
  // glibc's default threshold starts at 128 KiB and rises to every large
  // block freed, so after the mapping phase such blocks land in the heap
  // and leave it fragmented: at 1000 rooms the whole command peaks 1-2 MiB
  // lower with this (67.1-67.5 -> 65.7-66.6 MiB over four runs each, CPU
  // time unchanged within the machine's noise; docs/BENCHMARKS.md).
  mallopt(M_MMAP_THRESHOLD, 1 << 20);
  // Up to 1 MiB free at the top of the heap stays with the process (glibc
  // gives back whatever exceeds 128 KiB). Each room's grids, sweeps and
  // solves take and give back a few hundred KiB: with the default they went
  // back to the kernel after every room and were faulted in again for the
  // next (intel: 4,500 -> 3,150 page faults, 5 % of the wall time; the
  // 1000-room peak +0.5 MiB; a 4 MiB pad saved 6 % but cost 2 MiB of that
  // peak: docs/BENCHMARKS.md, "Pages kept").
  mallopt(M_TRIM_THRESHOLD, 1 << 20);
#endif
  mapping::MapJob& job = a.job;
  if (a.mode != "paper" && a.mode != "default") throw InputError("--mode " + a.mode + ": expected paper or default");
  if (a.boundary != "doorway" && a.boundary != "fixed")
    throw InputError("--boundary " + a.boundary + ": expected doorway or fixed");
  job.mapping.paper = a.mode == "paper";
  if (a.walls != "default" && a.walls != "lines" && a.walls != "chains")
    throw InputError("--walls " + a.walls + ": expected lines or chains");
  if (a.walls != "default") job.mapping.wall_lines = a.walls == "lines";
  job.mapping.boundary = a.boundary == "fixed" ? asr::BoundaryMode::kFixedLength : asr::BoundaryMode::kDoorway;
  job.mapping.correct = !a.no_correct;
  job.mapping.pose_graph = !a.no_graph;
  job.mapping.drift_filter = !a.no_drift_filter;
  job.mapping.smooth = !a.no_smooth;
  job.mapping.add_drift_rad_per_m = DegToRad(a.add_drift_deg_per_m);
  job.mapping.remove_drift_rad_per_m = DegToRad(a.remove_drift_deg_per_m);
  job.mapping.scan_match = mapping::ParseScanMatch(a.scan_match);
  job.mapping.distance_scale = mapping::ParseDistanceScale(a.distance_scale);
  job.mapping.Validate();
  job.outputs = mapping::OutputChoice::Parse(a.outputs);
  if (!a.geo_anchor.empty()) job.geo_anchor = io::ParseGeoAnchor(a.geo_anchor);
  if (!(job.px_per_m >= 0.0) || job.px_per_m > 1000.0)
    throw InputError("--px-per-m " + Num(job.px_per_m) + ": must be in (0, 1000] (0: fit)");
  ProgressBar bar("map");
  job.progress = [&bar](double f, int asrs) { bar.Update(f, std::to_string(asrs) + " ASRs"); };
  job.notice = [&bar](const std::string& s) {
    bar.Finish();
    std::fprintf(stderr, "cogmap: %s\n", s.c_str());
  };
  // Bags: the topics, and the robot that names a point cloud's sonars.
  const io::LogOpenOptions open_options = io::MakeOpenOptions(job.log_format, a.topics, job.robot_spec);
  auto log = io::OpenLog(job.log_path, open_options);
  job.second_pass = a.second_pass;
  if (job.log_path != "-")  // standard input is read once
    job.reopen_log = [&job, open_options] { return io::OpenLog(job.log_path, open_options); };
  job.started = ProcessStarted();
  const mapping::MapJobSummary s = mapping::RunMapJob(*log, job);
  bar.Finish();
  WarnSkipped(*log);
  std::fputs(mapping::MapSummaryText(s, job).c_str(), stdout);
  for (const auto& w : s.warnings) std::fprintf(stderr, "cogmap: warning: %s\n", w.c_str());
  return 0;
}

std::function<int()> SetupMap(CLI::App& sub) {
  auto a = std::make_shared<MapArgs>();
  sub.add_option("LOG", a->job.log_path, "The log to map (any format cogmap reads; - for standard input)")->required();
  sub.add_option("--format", a->job.log_format, "Log format: " + Join(io::LogFormatNames()))->capture_default_str();
  sub.add_option("--robot", a->job.robot_spec,
                 "Robot: a built-in name (" + Join(sensors::BuiltinRobotNames()) +
                     ") or a robot JSON file (default: the log's, else pioneer16)");
  sub.add_option("--cell", a->job.mapping.cell_m, "Cell size of each room's grid, metres")->capture_default_str();
  sub.add_option("--window", a->job.mapping.window_m, "MHIMM window w, metres")->capture_default_str();
  sub.add_option("--mode", a->mode,
                 "paper: the thesis's line fit and EM rotation per ASR; default: total least squares, robust EM and the pose graph "
                 "over ASRs (docs/pose-graph.md)")
      ->capture_default_str();
  sub.add_option("--boundary", a->boundary,
                 "doorway: fig. 3.4 with the corridor rule; fixed: a new ASR every --asr-length (thesis §4.2)")
      ->capture_default_str();
  sub.add_option("--asr-length", a->job.mapping.asr_length_m,
                 "Corridor / fixed-length ASR length, metres (4.5 in §3.1.2, 4 in §4.2)")
      ->capture_default_str();
  sub.add_option("--max-asr", a->job.mapping.max_asr_m,
                 "Default mode, doorway boundaries: cut a space after this many metres of driving without a "
                 "doorway or corridor cut (0 = never, as in paper mode)")
      ->capture_default_str();
  sub.add_option("--door-release", a->job.mapping.release_confirm_m,
                 "Default mode, doorway boundaries: an access point ends only when L or R stays released for "
                 "this many metres of driving; a shorter gap (a door on one side of a corridor) does not cut "
                 "the space (0 = at the first release, as in paper mode; intel's laser log: 86 -> 73 ASRs with 1)")
      ->capture_default_str();
  sub.add_flag("--door-gap", a->job.mapping.door_gap,
               "Default mode, doorway boundaries: L and R also come on together when the opening beside the "
               "robot is at most 1.4 m wide (twice the thesis's 0.7 m) wherever the robot is in it, the far side "
               "a door jamb, not a wall along the way; the thesis asks each side within 0.7 m and misses doors of "
               "1-1.2 m crossed off their middle. Off by default: on the bundled worlds it cuts more spaces than "
               "there are doorways (docs/BENCHMARKS.md, \"Doors wider than the thesis's\")");
  sub.add_option("--door-gap-m", a->job.mapping.door_gap_m,
                 "Default mode: --door-gap with this widest opening instead of 1.4 m (1 to 4; both sides then "
                 "jambs where both lie beyond 0.7 m): 2.5 for double doors and open passages of 1.6-2.4 m, which "
                 "no other rule cuts (a laser on buildings with 1.6 m doors: room IoU 0.26 -> 0.91). Not the "
                 "default: furniture rows whose gaps have table ends for jambs are cut as doors too (cluttered_lab, "
                 "laser: 0.92 -> 0.63-0.77; docs/BENCHMARKS.md, \"Double doors\")")
      ->capture_default_str();
  sub.add_flag("--sonar-cone", a->job.mapping.cone_hits,
               "Default mode, sonar: one grid per room, fused over the sonar's cone (the cone nearer than the echo is free, weighted towards the axis; the echo goes on its arc, at the cell nearest the axis not known empty), for the pose graph as well. Off by default: the walls kept already come from such a grid beside the axis grid, and the pose graph's closures, tuned on axis grids, accepted two wrong ones on cone grids (docs/walls.md, \"Sonar cone\")");
  sub.add_flag("--axis-walls", [a](int64_t) { a->job.mapping.cone_walls = false; },
               "Default mode, sonar: keep the walls of the axis grid (the thesis's MHIMM, which the pose graph "
               "matches) instead of those of the cone grid mapped beside it (docs/walls.md, \"Sonar cone\")");
  sub.add_flag("--cone-orientation", a->job.mapping.cone_orientation,
               "Default mode, a sonar ring that looks only forward (pioneer8, pioneer8-course, a panned EV3 sonar; "
               "no effect on a full ring or a laser): take each room's orientation, which its heading estimate "
               "and the pose graph's wall-direction factor refine to, from the cone grid rather than the axis "
               "grid, where the two agree within 5 degrees. On the axis grid such a ring's rooms lean 1-5 "
               "degrees with the way it drove round them. Not the default: on 160 runs of 80 random buildings "
               "with 8 sonars the heading median was better in 101 and worse in 58, but at 2 deg/m the walls "
               "were worse more often than better on one of the two sets and on never_worse's own worlds, and "
               "one winged building's run fell into wrong loop closures (docs/walls.md, \"A ring that looks "
               "only forward\")");
  sub.add_option("--direction-split", a->job.mapping.direction_split_m,
                 "Default mode, pose graph, laser walls: one wall-direction factor per this many metres of an "
                 "ASR's path where the directions turn with the distance driven, so drift inside a long ASR is "
                 "seen; tried after the solve with one direction per ASR and kept when it finds a drift and the "
                 "map stays as consistent (0 = one per ASR; docs/pose-graph.md, 'Drift inside an ASR')")
      ->capture_default_str();
  sub.add_option("--walls", a->walls,
                 "Default mode: how each room's walls are found: chains (the thesis's chain simplify and fit; "
                 "what default means) or lines (lines in each room's occupancy evidence, docs/walls.md); paper "
                 "mode always uses chains")
      ->capture_default_str();
  sub.add_option("--threads", a->job.mapping.threads,
                 "2: the log is read on a thread of its own (not standard input), and each room that ends is "
                 "vectorised (and what its placing needs of it alone made) on one more thread and placed and stored "
                 "on another while the next one is mapped (its loop-closure candidates searched on two), the floor "
                 "plan's room outlines filled and traced on two, and at the end the floor "
                 "plan's picture is drawn and the store closed beside the plan's files (the same map, sooner); 1: "
                 "all on one thread (the font library's own "
                 "helpers aside). With --no-graph the drift filter needs each room placed before the next one is "
                 "mapped: one thread")
      ->capture_default_str();
  sub.add_flag("--no-correct", a->no_correct, "Skip every correction: ASRs placed by odometry");
  sub.add_flag("--no-smooth", a->no_smooth,
               "With --no-graph: keep the corrections as computed while mapping (no revision at the end of the run)");
  sub.add_flag("--no-graph", a->no_graph,
               "Default mode without the pose graph (docs/pose-graph.md): the drift filter's odometry "
               "pre-correction, heading correction and smoothing only (the default before the pose graph). The filter "
               "takes a drift for granted and checks its map against nothing: on a building that is not square it "
               "can settle on a false drift and turn the map without a warning (the CARMEN logs as sonar without "
               "drift: heading median up to 56 deg; docs/BENCHMARKS.md); the pose graph tests whether there is a "
               "drift at all");
  sub.add_flag("--pre-bend", a->job.mapping.pre_bend,
               "Pose graph: once the graph has pinned the odometry's drift rate, build the rooms mapped next on "
               "odometry with that drift removed (sharper walls under strong drift; not the default: on real "
               "logs the maps move both ways, docs/pose-graph.md 'Drift removed while mapping')");
  sub.add_flag("--search-closures-again", a->job.mapping.search_closures_again,
               "Pose graph: at the end of the run, search the loop-closure candidates again against the solved "
               "graph where its prediction moved since they were searched (more closures when rooms are cut by "
               "distance, --max-asr; not the default: 6-16 % more time on intel for 3 closures; "
               "docs/pose-graph.md 'Closures searched again')");
  sub.add_option("--remove-drift-deg-per-m", a->remove_drift_deg_per_m,
                 "Pose graph: a heading drift known before the run (degrees per metre, CCW positive), removed "
                 "inside every room while it is mapped; the graph still estimates the whole drift (what the "
                 "second pass uses, docs/pose-graph.md 'Second pass')")
      ->capture_default_str();
  sub.add_flag("--second-pass", a->second_pass,
               "Pose graph: when the map found a drift (kept, not ambiguous), map the log again with that drift "
               "removed inside each room and write that map (walls that no longer lean with the drift; twice "
               "the mapping time; not with --resume or standard input; docs/pose-graph.md 'Second pass')");
  sub.add_flag("--no-drift-filter", a->no_drift_filter,
               "With --no-graph: without the drift-rate filter (one EM rotation per ASR, odometry used as it "
               "comes). The pose graph estimates the drift itself and never uses the filter");
  sub.add_option("--scan-match", a->scan_match,
                 "Laser robots: correct the odometry by matching each scan against a reference scan before "
                 "mapping (point-to-line ICP with the wheels as its prior; where the scans cannot tell, along a "
                 "corridor, the wheels are kept); the corrected odometry is the run's odometry in the store. auto: "
                 "when the first scans come at most 0.5 m or 15 degrees apart on average (default mode; paper "
                 "mode: never); on: always; off: never. No effect on sonar (docs/inputs.md 'Laser odometry')")
      ->capture_default_str();
  sub.add_option("--distance-scale", a->distance_scale,
                 "Default mode, correcting: the odometry's distance scale (true distance over odometry distance). "
                 "auto: measured while mapping by the range sensors looking along the way as the robot drives "
                 "straight at a wall (a sonar's run only with a side wall along it), applied from then on, shrunk "
                 "towards 1 by its evidence (report.json distance_scale); a number: that scale from the start (a "
                 "calibration); off: the odometry's distances as they come. The scaled odometry is the run's "
                 "odometry in the store (docs/pose-graph.md 'Distance scale')")
      ->capture_default_str();
  sub.add_option("--add-drift-deg-per-m", a->add_drift_deg_per_m,
                 "Add a systematic heading drift to the log's odometry, degrees per metre driven (CCW positive; "
                 "the log's ground truth stays): to test the correction on a real log")
      ->capture_default_str();
  sub.add_option("--outputs", a->outputs,
                 "Files to write beside map.sqlite, plan.json, walls.json and report.json, comma-separated: svg, "
                 "png (the master map: every ASR's walls, path, room graph), pgm (map_server PGM + YAML of the "
                 "floor plan), geojson, aria (map.map), gpkg (GeoPackage), route (route_graph.geojson for Nav2), "
                 "plan-svg, plan-png (the floor plan drawn; plan = both), compare (map_compare.svg/.png), "
                 "heading (heading_error.png); default = plan-svg,geojson,aria,gpkg,route (the fast set: the "
                 "diagnostic pictures and rasters on request); all = every one (docs/map-files.md, docs/pictures.md)")
      ->capture_default_str();
  sub.add_option("--topics", a->topics,
                 "Bags: the topics to read, comma separated (range, odometry); default: found by type "
                 "(docs/inputs.md)")
      ->delimiter(',');
  sub.add_option("--px-per-m", a->job.px_per_m,
                 "Pictures: this many pixels per metre (default 0: fit 2000 px on the longest side)");
  sub.add_option("--geo-anchor", a->geo_anchor,
                 "LAT,LON,HEADING_DEG: map.geojson in WGS 84, the map origin at this latitude/longitude and its +x "
                 "axis at this bearing (degrees clockwise from north); without it map.geojson is in local metres");
  sub.add_flag("--raw", a->job.raw, "Draw the master map at the raw odometry poses (the store keeps both)");
  sub.add_flag("--resume", a->job.resume,
               "Continue into OUTDIR/map.sqlite: new ASRs append with the next ids; the log's first pose is "
               "taken to be where the stored run ended. Given the log the store was mapped from (a killed run's), "
               "the run continues from the record where the stored one stopped (docs/store.md '--resume')");
  sub.add_option("--world", a->job.world,
                 "Ground-truth world (2D-Map with Room cairns): adds room_precision / room_recall to report.json");
  sub.add_option("-o,--output", a->job.output_dir, "Output folder (created)")->required();
  return [a] { return RunMap(*a); };
}

const bool kRegistered = RegisterCommand(
    {"map", "Map a log into ASRs (rooms), store them and write the master map", 50, SetupMap});

}  // namespace
}  // namespace cogmap::app
