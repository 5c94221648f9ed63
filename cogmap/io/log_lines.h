#pragma once
// Shared pieces of the log readers: a line source over plain or gzip files (or
// standard input), and number parsing that names file:line in every error.
#include <cmath>
#include <cstdio>
#include <istream>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "cogmap/core/pose2.h"

namespace cogmap::io {

// The path that means standard input, and the name messages give it
// ("stdin:12: ODOM: expected 10 fields ...").
inline constexpr const char* kStdinPath = "-";
inline constexpr const char* kStdinName = "stdin";

// Reads a text file line by line, plain or gzip (zlib detects which), without
// loading it into memory. Lines have their "\r\n" / "\n" removed.
class LineSource {
 public:
  // Throws InputError naming 'path' when it cannot be opened. "-" reads
  // standard input (through TakeStdin(): its buffered head, then the rest).
  explicit LineSource(const std::string& path);
  // Opens 'path' but names it 'name_for_messages' in errors and path() (a
  // spooled copy of standard input).
  LineSource(const std::string& path, const std::string& name_for_messages);
  // Reads 'in' (plain or gzip, told by its first two bytes) to its end.
  LineSource(std::unique_ptr<std::istream> in, const std::string& name_for_messages);
  ~LineSource();
  LineSource(const LineSource&) = delete;
  LineSource& operator=(const LineSource&) = delete;

  // Next line, or false at the end. Throws InputError for a truncated or
  // corrupt .gz ("path:line: truncated or corrupt gzip data (...)"), a read
  // error, or a line longer than 64 MiB.
  bool Next(std::string* line);
  // 1-based number of the line last returned (0 before the first).
  long line_number() const { return line_; }
  // Whether the line last returned ended with an end of line. Only the file's
  // last line can lack one: a file cut while it was written (a recorder
  // killed, a copy interrupted) ends in the middle of a line.
  bool line_terminated() const { return terminated_; }
  // Fraction of the file's bytes consumed (compressed bytes for .gz; a stream
  // of unknown length stays at 0 until its end).
  double progress() const;
  const std::string& path() const { return path_; }

 private:
  struct Stream;
  void OpenFile(const std::string& open_path);
  bool NextFromStream(std::string* line);

  std::string path_;
  std::string open_path_;  // the file opened (path_ names it in messages)
  void* gz_ = nullptr;  // gzFile
  std::unique_ptr<Stream> stream_;
  long line_ = 0;
  bool terminated_ = true;
  double size_bytes_ = 0;
  bool done_ = false;
};

// Standard input is read once per process: its first bytes (up to
// kStdinHeadBytes, fewer at its end) are kept so that the format can be told
// from them (StdinHeadLines) and still be read by the reader (TakeStdin).
inline constexpr size_t kStdinHeadBytes = size_t{64} << 10;
// The complete text lines of the head, gunzipped when it is gzip (at most
// max_lines). Reads the head on the first call.
std::vector<std::string> StdinHeadLines(size_t max_lines = 1000);
// A stream that replays the head and continues with the rest of standard
// input. Only one reader may take it: a second call throws InputError
// "stdin: standard input was already read".
std::unique_ptr<std::istream> TakeStdin();

// The head's bytes, gunzipped when it is gzip (as much as the compressed head
// gives); '*whole' tells whether that is all of standard input.
std::string StdinHead(bool* whole = nullptr);

// Standard input copied whole to a temporary file, for readers that need a
// file (two passes, or seeking: bags, rawlogs); the file is removed with the
// copy. Takes standard input (TakeStdin).
class StdinCopy {
 public:
  StdinCopy();
  ~StdinCopy();
  StdinCopy(const StdinCopy&) = delete;
  StdinCopy& operator=(const StdinCopy&) = delete;
  const std::string& path() const { return path_; }

 private:
  std::string path_;
};

// Splits on spaces and tabs.
std::vector<std::string_view> SplitFields(std::string_view line);

// A finite number, or InputError "path:line: <what>: '<text>' is not a number"
// (NaN and infinities are rejected as "not a finite number").
double ParseNumber(std::string_view text, const std::string& path, long line, const std::string& what);
// A whole number >= 0.
long ParseCount(std::string_view text, const std::string& path, long line, const std::string& what);

// Largest range accepted as data; anything larger is an absurd reading.
constexpr double kAbsurdRangeM = 1000.0;
// Throws unless 0 <= range_m <= kAbsurdRangeM ("negative range", "absurd range").
void CheckRange(double range_m, const std::string& path, long line, const std::string& what);
// What CheckRange accepts, tested without a message: readers call CheckRange
// (and build the reading's name) only for a range outside it.
inline bool RangeAccepted(double range_m) { return !(range_m < 0 || range_m > kAbsurdRangeM); }

// Farthest a pose may lie from its log's origin: more than twice round the
// Earth (UTM coordinates, some 5e6 m, pass); a pose of 1e300 m failed later,
// in the grid, without naming the file.
constexpr double kAbsurdPositionM = 1e8;
// Returns 'pose' unless its x or y lies beyond kAbsurdPositionM: InputError
// "path:line: <what>: absurd position (x, y) m (more than 100000 km from the origin)".
const Pose2& CheckPosition(const Pose2& pose, const std::string& path, long line, const std::string& what);
// What is wrong with a pose read from a binary log (a bag's odometry or tf,
// a rawlog's odometry), or "" when nothing is: a coordinate or heading that
// is not a finite number, or a position beyond kAbsurdPositionM. The text
// readers parse only finite numbers and call CheckPosition. Inline: the
// MRPT module (cogmap/io/plugin_api.h) does not link this library.
inline std::string AbsurdPosition(const Pose2& pose) {
  char text[128];
  std::snprintf(text, sizeof text, "absurd position (%g, %g) m (more than 100000 km from the origin)", pose.x, pose.y);
  return text;
}
inline std::string PoseProblem(const Pose2& pose) {
  if (!std::isfinite(pose.x) || !std::isfinite(pose.y) || !std::isfinite(pose.theta)) {
    char text[160];
    std::snprintf(text, sizeof text, "pose (%g, %g, %g) is not finite", pose.x, pose.y, pose.theta);
    return text;
  }
  if (std::abs(pose.x) > kAbsurdPositionM || std::abs(pose.y) > kAbsurdPositionM) return AbsurdPosition(pose);
  return "";
}

// "empty log: no range readings" naming the file.
[[noreturn]] void ThrowEmptyLog(const std::string& path);

}  // namespace cogmap::io
