#pragma once
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "cogmap/core/pose2.h"
#include "cogmap/grid/grid2d.h"
#include "cogmap/grid/range_fusion.h"
#include "cogmap/io/log_reader.h"

namespace cogmap::io {

// ROS map_server's map: a P5 PGM and its YAML (trinary mode).
struct MapServerYaml {
  std::string image;             // as written in the YAML (relative to it)
  double resolution = 0.1;       // metres per pixel
  Vec2 origin{0, 0};             // world position of the lower-left pixel's corner
  double origin_yaw = 0.0;
  int negate = 0;
  double occupied_thresh = 0.65;
  double free_thresh = 0.196;
  std::string mode = "trinary";
};

// Pixel values of the trinary PGM (map_server with negate 0: p = (255 - v) / 255;
// p > occupied_thresh is occupied, p < free_thresh is free, else unknown).
constexpr uint8_t kPgmOccupied = 0;
constexpr uint8_t kPgmFree = 254;
constexpr uint8_t kPgmUnknown = 205;

// Writes 'base'.pgm and 'base'.yaml (each through WriteFileAtomically). Robot
// path cells count as free. The YAML's image is the PGM's file name.
void WriteMapServer(const std::string& base, const grid::Grid2D<grid::CellClass>& classes);

struct PgmImage {
  int width = 0, height = 0, max_value = 255;
  std::vector<uint8_t> pixels;  // row 0 on top
};
// Reads a binary (P5) PGM with 8-bit pixels; comments in the header allowed.
// Throws InputError naming the file and the problem.
PgmImage ReadPgm(const std::string& path);
std::string EncodePgm(const PgmImage& image);

// Parses a map_server YAML (keys image, resolution, origin, negate,
// occupied_thresh, free_thresh, mode). Throws InputError naming file:line.
MapServerYaml ReadMapServerYaml(const std::string& path);
std::string EncodeMapServerYaml(const MapServerYaml& yaml);

// A map as map_server loads it: occupancy per cell as in nav_msgs/OccupancyGrid
// (-1 unknown, 0 free, 100 occupied), row 0 at the bottom (world y up).
struct MapServerMap {
  MapServerYaml yaml;
  grid::Grid2D<int8_t> occupancy;
};
MapServerMap ReadMapServer(const std::string& yaml_path);

// The classes as map_server would see them back (for tests and later issues).
grid::Grid2D<grid::CellClass> ClassesFromMapServer(const MapServerMap& map);

// Running a whole log through a fusion rule.
struct FuseLogOptions {
  bool use_truth = false;  // fuse at the log's true pose where it has one
};
struct FuseLogStats {
  long records = 0;
  long readings = 0;
};
// Reads every record of 'log' and fuses its sweep at its pose (MarkRobot for
// every record, odometry-only ones too). 'progress' (may be empty) gets the
// fraction of the log read. Throws InputError naming the log for an empty log
// or a reading of a sensor the robot does not have.
FuseLogStats FuseLog(LogReader& log, const sensors::RobotDescription& robot,
                     grid::RangeFusion& fusion, const FuseLogOptions& options = {},
                     const std::function<void(double)>& progress = {});

}  // namespace cogmap::io
