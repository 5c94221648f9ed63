#pragma once
// CARMEN logs (plain or .gz, or standard input "-"), as recorded by CARMEN's
// logger and stored on Radish. One message per line; read here (fields as
// CARMEN's readlog.c parses them):
//   ODOM x y theta tv rv accel timestamp host logger_timestamp
//   FLASER / RLASER n r1..rn x y theta odom_x odom_y odom_theta timestamp host logger_timestamp
//   ROBOTLASER1 / ROBOTLASER2 type start fov res max_range accuracy remission_mode n r1..rn
//               m e1..em laser_x laser_y laser_theta x y theta tv rv fwd side turn
//               timestamp host logger_timestamp
//   RAWLASER1..4 type start fov res max_range accuracy remission_mode n r1..rn m e1..em
//               timestamp host logger_timestamp
//   SONAR cone_angle n r1..rn x1 y1 theta1 .. xn yn thetan timestamp host logger_timestamp
//   TRUEPOS true_x true_y true_theta odom_x odom_y odom_theta timestamp host logger_timestamp
//   PARAM name value ...
// The other CARMEN messages (NEFF, SYNC, GPS...) are skipped and counted
// (LogReader::skipped()); '#' lines are comments. A word that is no CARMEN
// message, or a malformed message of a known type, is an InputError naming
// file:line; so is a log without any laser or sonar reading (the message
// names the odometry count and the skipped types).
//
// Records: ODOM -> odometry-only record (no truth); TRUEPOS -> odometry-only
// record with truth; FLASER/RLASER -> record whose odom is the odom_* fields
// and whose truth is the x y theta fields (in the "-corrected" logs both are
// the SLAM-corrected poses: the reference trajectory); ROBOTLASERk -> record
// at its robot pose (odom; no truth). RAWLASERk and SONAR carry no pose: their
// record takes the pose (odom, and truth if any) of the latest pose-carrying
// message (ODOM, TRUEPOS, FLASER, RLASER, ROBOTLASERk); before the first one
// they are skipped and counted. RAWLASER1 (2) is skipped and counted when the
// log has FLASER or ROBOTLASER1 (RLASER or ROBOTLASER2): the same scans with
// poses. Time: the message's ipc timestamp; a 0 timestamp (the Radish
// corrected logs write an ODOM with timestamp 0 after each FLASER) takes the
// logger timestamp, or if that is 0 too, the previous record's time. Times are
// not required to increase (the Intel log has a few ODOM messages out of
// order).
//
// Robot (robot_hint, named carmen-laser, carmen-sonar or carmen-laser-sonar):
// the devices present in the log, in this sensor order: FLASER beams, RLASER,
// ROBOTLASER1, ROBOTLASER2, RAWLASER1..4, then the sonars.
// FLASER/RLASER geometry follows CARMEN (carmen_laser_get_fov): 180 beams span
// 179 degrees at 1 degree steps centred ahead (181 beams: 180 degrees; 360: 179.5;
// 361: 180; 400: 99.75; 401: 100; other counts: 180 degrees), i.e.
// MakeLaser(n, fov); the front laser sits at x = PARAM robot_frontlaser_offset,
// the rear one at x = -robot_rearlaser_offset facing backwards. Max range: PARAM
// robot_front_laser_max / laser_front_laser_max_range (rear likewise) when the
// log has it; otherwise, when the largest reading in the log is at least 20 m,
// that value (the laser's no-return code: 81.83 in intel, 50 in aces); else
// 81.9 m (SICK's 8191 cm no-return code). Readings at or above it are no echo.
// ROBOTLASERk / RAWLASERk: beam i at start + i * res (from the first message),
// max range its maximum_range field; ROBOTLASERk mounted where its laser pose
// sits relative to its robot pose, RAWLASER1 at the front laser offset,
// RAWLASER2 at the rear one facing back, RAWLASER3/4 at the robot centre.
// SONAR: transducer i at (xi, yi, thetai) of the first message, beam width
// cone_angle (radians, in (0, 2 pi]), max range the largest sonar reading in
// the log or 5 m (the Pioneer's range) if that is larger, min range 0.15 m.
#include <memory>
#include <string>

#include "cogmap/io/log_reader.h"

namespace cogmap::io {

// Opens a CARMEN log. Reads it once at opening to find the lasers, sonars and
// their no-return values (streaming; nothing is kept in memory). "-" copies
// standard input to a temporary file first (removed with the reader), since
// the robot needs that whole first pass.
std::unique_ptr<LogReader> OpenCarmenLog(const std::string& path);

// CARMEN's field of view (radians) for an old-style FLASER/RLASER of n beams.
double CarmenLaserFov(int beams);

// True when 'word' is a CARMEN message name this reader knows or skips
// knowingly (used to sniff the format).
bool IsCarmenMessageName(const std::string& word);

}  // namespace cogmap::io
