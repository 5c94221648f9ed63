#pragma once
// `cogmap eval` as one call: a folder written by `cogmap map` or `cogmap
// vectorize` scored against a world (walls, rooms, floor plan, headings,
// trajectory, calibration of the pose graph's covariances), or without one
// (headings and sizes against the log's reference poses).
#include <nlohmann/json.hpp>
#include <string>

namespace cogmap::mapping {

struct EvaluateOptions {
  std::string world;     // the world the log was driven in ("" = none)
  double range_m = -1.0; // sensor range for recall (< 0: what the folder recorded)
  std::string png;       // also draw the map walls over the true walls here ("" = no)
  // The true rooms as a room-segmentation image (io::ReadRoomSegmentation;
  // "" = the world's Room cairns): placed as a bitmap world is.
  std::string rooms;
};

struct Evaluation {
  nlohmann::json metrics;  // what `cogmap eval --json` prints
  std::string text;        // the human-readable summary
};

// 'dir': the folder (or its walls.json). Throws InputError naming the file
// for a folder without walls.json, a log without ground truth, a bad world,
// and naming the option for a range neither unset nor in (0, 1000] m.
Evaluation EvaluateFolder(const std::string& dir, const EvaluateOptions& options = {});

}  // namespace cogmap::mapping
