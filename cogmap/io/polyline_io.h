#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include "cogmap/core/geometry.h"
#include "cogmap/vectorize/polyline_codec.h"

namespace cogmap::io {

// Polylines as data. The compact binary form is vectorize::EncodePolylines
// (1 cm quanta, zigzag varint deltas: see polyline_codec.h); these add files
// and a JSON form.

// Binary files, written atomically; reading throws InputError naming the file.
void WritePolylinesBinary(const std::string& path, const std::vector<Polyline>& lines,
                          const vectorize::PolylineCodecOptions& options = {});
std::vector<Polyline> ReadPolylinesBinary(const std::string& path);

// JSON form: [[[x, y], [x, y], ...], ...] in metres, 4 decimals (0.1 mm).
std::string PolylinesToJson(const std::vector<Polyline>& lines);
// Parses that form; throws InputError naming 'source' for anything else.
std::vector<Polyline> PolylinesFromJson(const std::string& text, const std::string& source);

// walls.json: what `cogmap vectorize` writes and `cogmap eval` reads.
struct WallsFile {
  std::vector<Polyline> polylines;  // map (odometry) frame, metres
  // Pose of the map frame in the world of the log's ground truth (identity
  // when the log has none, or when odometry starts at the true pose).
  Pose2 world_from_map;
  bool has_truth = false;           // the log carries ground-truth poses
  std::string log_path;             // absolute path of the log
  std::string log_format = "auto";
  std::string robot;                // robot name or JSON path given
  std::string mode;                 // "paper" or "default"
  double cell_m = 0.1;
  double sensor_range_m = 0.0;      // the robot's largest max range
  int64_t vertex_count = 0;
  int64_t bytes_grid = 0;
  int64_t bytes_vertices = 0;
  int64_t bytes_polylines = 0;
};
void WriteWallsJson(const std::string& path, const WallsFile& walls);
// Throws InputError naming the file for a missing file or a bad field.
WallsFile ReadWallsJson(const std::string& path);

}  // namespace cogmap::io
