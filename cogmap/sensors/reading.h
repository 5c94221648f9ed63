#pragma once
#include <optional>
#include <vector>

#include "cogmap/core/pose2.h"

namespace cogmap::sensors {

// One range reading: which sensor of the robot description, and the range in
// metres from the transducer. A range at or above the sensor's max range means
// "no echo" (data, not an error).
struct RangeReading {
  int sensor = 0;
  double range_m = 0.0;
};

// One step of a run: the odometry pose at 'time_s', the true pose when the log
// has one, and the readings of one sweep taken at that pose (may be empty for
// an odometry-only step).
struct LogRecord {
  double time_s = 0.0;
  Pose2 odom;                  // world_from_robot by dead reckoning
  std::optional<Pose2> truth;  // ground truth, when known
  std::vector<RangeReading> ranges;
};

}  // namespace cogmap::sensors
