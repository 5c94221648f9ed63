#pragma once
// `cogmap map` as one call: a log mapped into an output folder with every
// chosen output (docs/store.md for the folder, docs/pose-graph.md for the
// report's pose_graph section). The command line, the Python bindings and the
// ROS node's "write the floor plan" service call it; MappingPipeline is the
// streaming part.
#include <chrono>
#include <functional>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "cogmap/io/log_reader.h"
#include "cogmap/io/plan_files.h"
#include "cogmap/mapping/pipeline.h"

namespace cogmap::mapping {

// `--outputs`: which files beside map.sqlite, plan.json, walls.json and
// report.json. The floor plan's files (docs/map-files.md) are made from the
// floor plan (docs/floor-plan.md); the master map pictures from the ASRs.
struct OutputChoice {
  bool svg = false;      // map.svg (every ASR's walls, the path, the room graph)
  bool png = false;      // map.png
  bool pgm = false;      // map.pgm + map.yaml (ROS map_server: the floor plan's free space)
  bool geojson = true;   // map.geojson (floor plan: local metres, or WGS 84 with a geo anchor)
  bool aria = true;      // map.map (ARIA 2D-Map: walls, RobotHome, rooms, doors)
  bool gpkg = true;      // map.gpkg (GeoPackage: rooms, walls, doors, room graph)
  bool route = true;     // route_graph.geojson (Nav2 Route Server)
  bool plan = true;      // plan.svg: the floor plan drawn
  bool plan_png = false; // plan.png: the same drawing as a raster
  bool compare = false;  // map_compare.svg/.png
  bool heading = false;  // heading_error.png
  static OutputChoice All();
  // "default", "all" or a comma-separated list of the names above; throws
  // InputError naming an unknown one.
  static OutputChoice Parse(const std::string& text);
  static std::string Names();
};

struct MapJob {
  std::string log_path;                  // for the report ("-": standard input)
  std::string log_format = "auto";
  std::string robot_spec;                // what the user gave ("" = the log's hint, else pioneer16)
  MappingOptions mapping;
  OutputChoice outputs;
  std::string output_dir;
  bool resume = false;                   // continue OUTDIR/map.sqlite
  bool raw = false;                      // draw the master map at the raw odometry poses
  std::string world;                     // ground-truth world: room precision / recall
  std::optional<io::GeoAnchor> geo_anchor;  // map.geojson in WGS 84 at this anchor
  double px_per_m = 0.0;                 // pictures: this scale (0: fit 2000 px on the longest side)
  // `cogmap map --second-pass` (pose graph): when the first pass finds a
  // drift (kept, not ambiguous), the log is mapped again with that drift
  // removed inside every room (MappingOptions::remove_drift_rad_per_m), so
  // that the walls no longer lean with it, and that second map is the one
  // written (docs/pose-graph.md, "Second pass"). Needs 'reopen_log' (a log
  // that can be read again: not standard input); not with --resume,
  // --pre-bend or a drift given with --remove-drift-deg-per-m. Not the
  // default: --resume, the ROS node and Python's Mapper map in one pass.
  bool second_pass = false;
  std::function<std::unique_ptr<io::LogReader>()> reopen_log;
  // Progress: fraction of the log read, ASRs closed. Called every 256 records.
  std::function<void(double fraction, int asrs)> progress;
  // Messages for the user that cannot wait for the summary (a failed run's
  // partial result kept aside); the library never prints.
  std::function<void(const std::string&)> notice;
  // When the command began (`cogmap map`: the process, its loading
  // included), for report.json's total_seconds and times_real_time; unset:
  // when RunMapJob is called.
  std::optional<std::chrono::steady_clock::time_point> started;
};

struct MapJobSummary {
  long records = 0;
  int asrs = 0;               // in the store (earlier runs included)
  int asrs_this_run = 0;
  int exits = 0;
  int64_t bytes_grid = 0;
  int64_t bytes_polylines = 0;
  double seconds = 0.0;       // the whole job
  double times_real_time = 0.0;
  std::optional<double> room_precision, room_recall;  // with a world
  int heading_asrs = 0;       // ASRs with a true heading error
  double heading_median_deg = 0.0, heading_max_deg = 0.0;
  double heading_median_raw_deg = 0.0, heading_max_raw_deg = 0.0;
  // The odometry's heading drift against the truth (deg/m), when the log has
  // truth (localize::HeadingErrorStats::odometry_drift_rad_per_m).
  std::optional<double> odometry_drift_deg_per_m;
  RunResult run;
  int rooms = 0;              // store rooms (revisits share one)
  int plan_rooms = 0, plan_walls = 0, plan_doors = 0;  // the floor plan
  std::vector<std::string> written;  // file names in the output folder
  std::vector<std::string> warnings; // for the user (one line each)
  // report.json is written as it is made (WriteReport), never held whole:
  // read it from the output folder.
};

// Maps 'log' into job.output_dir. The folder is locked for the run, every file
// is written into its staging folder and moved into place at the end; a run
// that fails (an InputError from the log, a full disk) leaves the previous map
// untouched and its own partial result in OUTDIR/failed-run-*/, then rethrows.
MapJobSummary RunMapJob(io::LogReader& log, const MapJob& job);

// What `cogmap map` prints after a run: records, ASRs, exits, bytes, time,
// the floor plan's counts, room precision/recall and heading errors when
// known, the correction's result, the files written (one fact per line).
std::string MapSummaryText(const MapJobSummary& summary, const MapJob& job);

// What report.json says about the run besides the store (RunMapJob fills it).
struct OutputContext {
  std::string store_path;
  std::string run_id;
  std::chrono::steady_clock::time_point start = std::chrono::steady_clock::now();  // of the whole command
  double startup_seconds = 0.0;  // from 'start' to the job's own start (loading, options, the log opened)
  double mapping_seconds = 0.0;
  long rss_mapping_kb = 0;
  // Called once nothing WriteMapOutputs does next reads the store (its
  // floor plan is built): the caller may close the store meanwhile.
  std::function<void()> store_read;
};

// Every output of a mapped store, written into 'dir' (each file atomically):
// the master map's files, the chosen pictures, walls.json and report.json.
// 'run' is the pipeline's result for this run (RunMapJob; the ROS node when it
// writes the floor plan). Returns the summary; does not commit anything.
MapJobSummary WriteMapOutputs(asr::SqliteAsrStore& store, const RunResult& run, const MapJob& job,
                              const sensors::RobotDescription& robot, const std::string& dir,
                              const OutputContext& context);

}  // namespace cogmap::mapping
