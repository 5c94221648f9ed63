#pragma once
// `cogmap vectorize` as one call: a whole log fused into one MHIMM grid (one
// space), its walls extracted as polylines (SPEC 3: clean, extract, simplify,
// fit), and the outputs written into a folder staged like `cogmap map`'s
// (io::OutputFolder): walls.json, walls.svg, stages.png, report.json.
#include <functional>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "cogmap/core/pose2.h"
#include "cogmap/grid/map_limits.h"
#include "cogmap/io/log_reader.h"
#include "cogmap/sensors/robot.h"
#include "cogmap/vectorize/vectorize.h"

namespace cogmap::mapping {

struct VectorizeJob {
  std::string log_path;        // for walls.json and the report
  std::string log_format = "auto";
  std::string robot_spec;      // "" = the log's robot, else pioneer16
  double cell_m = 0.1;         // cell side
  double window_m = 3.0;       // MHIMM window w; also the cleaning range max_dist
  bool paper = false;          // the thesis's line fit (VectorizeOptions::Paper())
  // Default mode: the grid fuses each sonar echo over its cone
  // (grid::MhimmOptions::cone_hits), as the walls `cogmap map` keeps;
  // --axis-walls (cone_hits false): on its axis alone, as the thesis. A
  // laser's grid is the same either way.
  bool cone_hits = true;
  bool use_truth = false;      // fuse at the log's true poses where it has them
  // Stage overrides; negative (or empty): the mode's default.
  double gamma_cells = -1, tau_cells = -1, eta_cells = -1, max_rms_cells = -1;
  int min_chain_points = -1;
  int smooth_half_window = -1;
  std::optional<vectorize::KeepCell> keep;
  // Default mode: walls as lines (true) or from the chains (false); empty:
  // MappingOptions' default. Paper mode: always the chains.
  std::optional<bool> wall_lines;
  std::string output_dir;
  std::function<void(double fraction)> progress;  // fraction of the log read
  // A failed run's partial outputs set aside (the folder's path); the library never prints.
  std::function<void(const std::string&)> notice;

  // Throws InputError naming the option ("--cell 0: must be in (0, 10] metres").
  void Validate() const;
  // The mode's stage options with the overrides applied.
  vectorize::VectorizeOptions StageOptions() const;
};

struct VectorizeJobResult {
  sensors::RobotDescription robot;
  long records = 0;
  long readings = 0;
  long echoes = 0;            // readings nearer than their sensor's max range
  long truth_records = 0;     // records with a true pose
  grid::MapLimits limits;     // of the fused grid
  Pose2 world_from_map;       // the map (odometry) frame in the truth's world
  vectorize::VectorizeResult walls;
  double grid_seconds = 0.0;  // reading and fusing the log
  nlohmann::json report;      // what report.json holds
  std::vector<std::string> written;  // file names in the output folder
};

// Maps 'log' as one space into job.output_dir. The folder is locked for the
// run and every file is written into its staging folder, then moved into
// place; a failure (a bad log line, a full disk) leaves the previous outputs
// untouched and rethrows.
VectorizeJobResult RunVectorizeJob(io::LogReader& log, const VectorizeJob& job);

}  // namespace cogmap::mapping
