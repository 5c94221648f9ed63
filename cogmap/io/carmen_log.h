#pragma once
// CARMEN logs (plain or .gz), as recorded by CARMEN's logger and stored on
// Radish. One message per line; read here:
//   ODOM x y theta tv rv accel timestamp host logger_timestamp
//   FLASER / RLASER n r1..rn x y theta odom_x odom_y odom_theta timestamp host logger_timestamp
//   ROBOTLASER1 type start fov res max_range accuracy remission_mode n r1..rn
//               m e1..em laser_x laser_y laser_theta x y theta tv rv fwd side turn
//               timestamp host logger_timestamp
//   TRUEPOS true_x true_y true_theta odom_x odom_y odom_theta timestamp host logger_timestamp
//   PARAM name value ...
// Every other message (NEFF, SYNC, GPS...) and '#' lines are skipped. A
// malformed message of a known type is an InputError naming file:line.
//
// Records: ODOM -> odometry-only record (no truth); TRUEPOS -> odometry-only
// record with truth; FLASER/RLASER -> record whose odom is the odom_* fields
// and whose truth is the x y theta fields (in the "-corrected" logs both are
// the SLAM-corrected poses: the reference trajectory); ROBOTLASER1 -> record
// at its robot pose (odom; no truth). Time: the message's ipc timestamp; a 0
// timestamp (the Radish corrected logs write an ODOM with timestamp 0 after
// each FLASER) takes the logger timestamp, or if that is 0 too, the previous
// record's time. Times are not required to increase (the Intel log has a few
// ODOM messages out of order).
//
// Robot (robot_hint): the lasers present in the log, in this sensor order:
// front (FLASER) beams, then rear (RLASER) beams, then ROBOTLASER1 beams.
// FLASER/RLASER geometry follows CARMEN (carmen_laser_get_fov): 180 beams span
// 179 degrees at 1 degree steps centred ahead (181 beams: 180 degrees; 360: 179.5;
// 361: 180; 400: 99.75; 401: 100; other counts: 180 degrees), i.e.
// MakeLaser(n, fov); the front laser sits at x = PARAM robot_frontlaser_offset,
// the rear one at x = -robot_rearlaser_offset facing backwards. Max range: PARAM
// robot_front_laser_max / laser_front_laser_max_range (rear likewise) when the
// log has it; otherwise, when the largest reading in the log is at least 20 m,
// that value (the laser's no-return code: 81.83 in intel, 50 in aces); else
// 81.9 m (SICK's 8191 cm no-return code). Readings at or above it are no echo.
#include <memory>
#include <string>

#include "cogmap/io/log_reader.h"

namespace cogmap::io {

// Opens a CARMEN log. Reads it once at opening to find the lasers and their
// no-return value (streaming; nothing is kept in memory).
std::unique_ptr<LogReader> OpenCarmenLog(const std::string& path);

// CARMEN's field of view (radians) for an old-style FLASER/RLASER of n beams.
double CarmenLaserFov(int beams);

// True when 'word' is a CARMEN message name this reader knows or skips
// knowingly (used to sniff the format).
bool IsCarmenMessageName(const std::string& word);

}  // namespace cogmap::io
