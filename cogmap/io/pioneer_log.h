#pragma once
// The Pioneer sonar pair (a robotics course's occupancy-grid exercise):
//   measurement.txt: "timestamp r0 .. r7"   ranges in mm; 5110 = no echo
//   poses.txt:       "timestamp x_mm y_mm theta"   theta in tenths of a degree
// Line i of one file goes with line i of the other and both must carry the
// same timestamp (milliseconds; time_s = timestamp / 1000). One record per
// line pair, odometry only (no truth), readings for sensors 0..7. Theta is
// converted as is (not wrapped). The robot hint is BuiltinRobot("pioneer8")
// (max range 5 m, so 5110 mm is no echo); docs/robots/pioneer8-course.json
// holds the course's own headings.
#include <memory>
#include <string>

#include "cogmap/io/log_reader.h"

namespace cogmap::io {

struct PioneerPairPaths {
  std::string measurements;
  std::string poses;
};

// Accepts the folder holding both files, or either file (the other must sit
// beside it). Throws InputError when it cannot find the pair.
PioneerPairPaths ResolvePioneerPair(const std::string& path);

std::unique_ptr<LogReader> OpenPioneerLog(const std::string& path);

}  // namespace cogmap::io
