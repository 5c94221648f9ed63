#pragma once
// EV3 stop-and-scan logs (a LEGO EV3 rover with one ultrasonic sensor on a
// servo). Each line: "x y theta" (dead reckoning; cm, radians, unwrapped), then
// 13 bearings from -90 to +90 degrees in 15 degree steps, each with k repeated
// samples in cm (255 = no echo). k is the same on every line of a file: the
// README's logs have k = 25, the shared ev3-69.log has k = 10 and ev3-154.log
// k = 1 (so a line has 3 + 13 k numbers).
//
// One record per line, odometry only, 13 readings (sensor i = bearing
// -90 + 15 i degrees): the range of each is the LOWER MEDIAN of its k samples
// (the ceil(k/2)-th smallest), always one of the measured values, so a
// half-no-echo bearing never averages a hit with 255. Time: the log has no
// timestamps, so time_s is the 0-based line index.
#include <memory>
#include <string>

#include "cogmap/io/log_reader.h"

namespace cogmap::io {

constexpr int kEv3Bearings = 13;

// The EV3 robot: 13 sonar "sensors" at the robot centre, one per bearing
// -90..+90 degrees (15 degree steps), beam width 25 degrees, range 0.03..2.55 m.
sensors::RobotDescription Ev3Robot();

// A bearing's samples "disagree" when their spread (max - min, no-echo samples
// included) exceeds this.
constexpr double kEv3DisagreeCm = 10.0;

class Ev3LogReader : public LogReader {
 public:
  virtual ~Ev3LogReader() = default;
  // Samples per bearing (k), known after the first record.
  virtual int samples_per_bearing() const = 0;
  // Lines read so far where at least one bearing's samples disagree.
  virtual long disagreeing_lines() const = 0;
};

std::unique_ptr<Ev3LogReader> OpenEv3Log(const std::string& path);

}  // namespace cogmap::io
