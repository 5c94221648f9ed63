#pragma once
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "cogmap/core/pose2.h"
#include "cogmap/grid/grid2d.h"
#include "cogmap/grid/range_fusion.h"
#include "cogmap/io/image.h"
#include "cogmap/io/log_reader.h"

namespace cogmap::io {

// How grids become pictures. Images put world y up (row 0 = the grid's top row).
struct GridRenderOptions {
  int scale = 1;                    // pixels per cell side
  float occupied_threshold = 7.0f;  // epsilon (table 4.1): darker than this = black
  float min_value = -3.0f;          // MHIMM's lower clamp: whitest
  float robot_path = -100.0f;       // MHIMM's path marker: red
};

// The MHIMM colours: unknown (0) grey, empty (< 0) white, occupied (> epsilon)
// black, robot path red; values between are shaded (0 -> min_value fades grey
// to white, 0 -> epsilon fades grey to dark grey). HIMM values render the same
// way (HIMM's 0 is "unknown or empty": grey).
constexpr Rgb kUnknownRgb{160, 160, 160};
constexpr Rgb kEmptyRgb{255, 255, 255};
constexpr Rgb kOccupiedRgb{0, 0, 0};
constexpr Rgb kRobotPathRgb{220, 0, 0};
RgbImage RenderCertainty(const grid::Grid2D<float>& values, const GridRenderOptions& options = {});

// Probability of occupied as grey (0 white, 1 black); untouched cells grey
// (kUnknownRgb) and robot path cells red, from 'classes'.
RgbImage RenderProbability(const grid::Grid2D<float>& occupancy,
                           const grid::Grid2D<grid::CellClass>& classes, int scale = 1);

// Picks the picture that suits the rule: certainty colours for HIMM / MHIMM,
// probability grey for Bayes / Dempster-Shafer.
RgbImage RenderFusion(const grid::RangeFusion& fusion, const GridRenderOptions& options = {});

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
