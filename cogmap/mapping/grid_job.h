#pragma once
// `cogmap grid` as one call: a whole log fused into one occupancy grid by a
// fusion rule, drawn as a picture and, when asked, written as a ROS
// map_server PGM + YAML pair (README.md, "Commands"; docs/pictures.md).
#include <functional>
#include <memory>
#include <optional>
#include <string>

#include "cogmap/grid/grid_summary.h"
#include "cogmap/grid/range_fusion.h"
#include "cogmap/io/log_reader.h"
#include "cogmap/sensors/robot.h"

namespace cogmap::mapping {

struct GridJob {
  std::string log_path;                 // for the picture's title
  std::string robot_spec;               // "" = the log's robot, else pioneer16
  grid::FusionRule rule = grid::FusionRule::kMhimm;
  double cell_m = 0.1;                  // cell side
  double window_m = 3.0;                // HIMM / MHIMM / cone window w
  bool use_truth = false;               // fuse at the log's true poses where it has them
  std::string picture_path;             // .png, .svg or .pdf
  std::string pgm_base;                 // "" = none; else base.pgm + base.yaml
  int px_per_cell = 0;                  // picture scale: pixels per cell side (0: px_per_m)
  double px_per_m = 0.0;                // pixels per metre (0: fit 2000 px)
  bool summarize = false;               // also compute the grid's statistics
  std::function<void(double fraction)> progress;  // fraction of the log read

  // Throws InputError naming the option ("--cell 0: must be in (0, 10] metres")
  // or the picture path whose extension is not a picture format.
  void Validate() const;
};

struct GridJobResult {
  sensors::RobotDescription robot;
  long records = 0;
  long readings = 0;
  std::unique_ptr<grid::RangeFusion> fusion;  // the fused grid
  std::optional<grid::GridSummary> summary;   // when job.summarize
  double seconds = 0.0;                       // the whole job
};

// Fuses 'log' whole (io::FuseLog) and writes job.picture_path (and the PGM
// pair). Throws InputError for a bad option, an empty log or a reading of a
// sensor the robot does not have; nothing is written then.
GridJobResult RunGridJob(io::LogReader& log, const GridJob& job);

}  // namespace cogmap::mapping
