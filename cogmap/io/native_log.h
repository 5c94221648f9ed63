#pragma once
// The native cogmap text log (docs/log-format.md):
//   # cogmap-log 1
//   robot pioneer16                 (or: robot-json {...one-line robot JSON...})
//   ODOM t x y theta                starts a record (metres, radians CCW, seconds)
//   TRUTH t x y theta               optional: the record's true pose
//   SWEEP t n s0 r0 s1 r1 ...       optional: the record's readings (sensor, metres)
// A SWEEP with no ODOM since the last SWEEP makes a new record at the latest
// ODOM/TRUTH. Numbers are written in the shortest form that reads back to the
// same double, so a log round-trips bit-exactly.
#include <memory>
#include <ostream>
#include <string>

#include "cogmap/io/log_reader.h"
#include "cogmap/sensors/reading.h"
#include "cogmap/sensors/robot.h"

namespace cogmap::io {

// The version this build writes and the newest it reads.
constexpr int kNativeLogVersion = 1;
// The first line of every native log starts with this.
inline constexpr const char* kNativeLogMagic = "# cogmap-log";

// Streams records to 'out' in the native format. Writes the header at
// construction: "robot <name>" when 'robot' is bit-identical to the built-in
// robot of that name, else "robot-json <json>" (angles in radians, exact).
class NativeLogWriter {
 public:
  NativeLogWriter(std::ostream& out, const sensors::RobotDescription& robot);
  // Writes one record: ODOM, then TRUTH if known, then SWEEP if it has readings.
  void Write(const sensors::LogRecord& record);
  long records_written() const { return records_; }

 private:
  std::ostream& out_;
  long records_ = 0;
  std::string buf_;
};

// Opens a native log (plain or .gz). Throws InputError for a missing file, a
// bad header or a newer version.
std::unique_ptr<LogReader> OpenNativeLog(const std::string& path);

}  // namespace cogmap::io
