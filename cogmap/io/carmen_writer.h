#pragma once
// Records written as a CARMEN log (the messages carmen_log.h reads), so that a
// run from another format can be handed to CARMEN tools or read back as CARMEN:
//   TRUEPOS true_x true_y true_theta odom_x odom_y odom_theta timestamp host logger_timestamp
//     (a record with a reference pose), else
//   ODOM x y theta tv rv accel timestamp host logger_timestamp
// then, for a record with readings, at the same timestamp:
//   SONAR cone_angle n r1..rn x1 y1 theta1 .. xn yn thetan timestamp host logger_timestamp
//     (a sonar robot; CARMEN's SONAR carries every transducer at once, so each
//     record must hold one reading of every sonar, as a Pioneer log does), or
//   ROBOTLASER1 type start fov res max_range accuracy remission_mode n r1..rn 0
//     laser_x laser_y laser_theta x y theta tv rv fwd side turn timestamp host logger_timestamp
//     (a laser robot: one scanner, beams at equal angle steps; a beam without a
//     reading in the record is written at max range, CARMEN's no return).
// Velocities are written as 0 (the records carry none). The host is "cogmap".
// Numbers are written with the shortest text that reads back exactly.
#include <ostream>
#include <string>

#include "cogmap/core/pose2.h"
#include "cogmap/sensors/reading.h"
#include "cogmap/sensors/robot.h"

namespace cogmap::io {

class CarmenLogWriter {
 public:
  // Throws InputError (naming 'source') when the robot is neither all sonar
  // nor one evenly spaced laser, which CARMEN's messages cannot describe.
  CarmenLogWriter(std::ostream& out, const sensors::RobotDescription& robot, const std::string& source);
  // Throws InputError naming 'source' and the record's index when a sonar
  // record does not hold exactly one reading of every sonar.
  void Write(const sensors::LogRecord& record);
  long records_written() const { return records_; }

 private:
  std::ostream& out_;
  sensors::RobotDescription robot_;
  std::string source_;
  bool sonar_ = false;
  Pose2 laser_mount_;
  double laser_start_rad_ = 0.0, laser_step_rad_ = 0.0;
  long records_ = 0;
  std::string buf_;
};

}  // namespace cogmap::io
