#pragma once
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "cogmap/sensors/reading.h"
#include "cogmap/sensors/robot.h"

namespace cogmap::io {

// A run read one record at a time, so that long logs never sit in memory.
// Readers count lines: every InputError they throw names the file, the line
// and the problem ("run.log:112: expected 18 fields, got 17").
class LogReader {
 public:
  virtual ~LogReader() = default;
  // Reads the next record. Returns false at the end of the log. Throws
  // InputError on malformed input (including a truncated .gz).
  virtual bool Next(sensors::LogRecord* record) = 0;
  // The robot this log was recorded with, when the format says (a CARMEN laser
  // of n beams, the native log's "robot" header, the EV3's bearings).
  virtual std::optional<sensors::RobotDescription> robot_hint() const { return std::nullopt; }
  // Fraction of the input consumed so far, in [0, 1] (for progress bars).
  virtual double progress() const = 0;
  // The path as given by the user (for messages).
  virtual const std::string& path() const = 0;
};

// Log formats: "native", "carmen", "pioneer" (measurement.txt + poses.txt:
// give either file or their folder), "ev3", or "auto" (by content).
std::vector<std::string> LogFormatNames();

// Opens a log. Throws InputError naming the file for a missing file, an
// unknown format, or content that no reader recognises.
std::unique_ptr<LogReader> OpenLog(const std::string& path, const std::string& format = "auto");

// The format OpenLog(path, "auto") would choose ("native", "carmen", "pioneer"
// or "ev3"); InputError when the content matches none.
std::string DetectLogFormat(const std::string& path);

}  // namespace cogmap::io
