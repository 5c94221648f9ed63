#pragma once
// Shared pieces of the log readers: a line source over plain or gzip files, and
// number parsing that names file:line in every error.
#include <string>
#include <string_view>
#include <vector>

namespace cogmap::io {

// Reads a text file line by line, plain or gzip (zlib detects which), without
// loading it into memory. Lines have their "\r\n" / "\n" removed.
class LineSource {
 public:
  // Throws InputError naming 'path' when it cannot be opened.
  explicit LineSource(const std::string& path);
  ~LineSource();
  LineSource(const LineSource&) = delete;
  LineSource& operator=(const LineSource&) = delete;

  // Next line, or false at the end. Throws InputError for a truncated or
  // corrupt .gz ("path:line: truncated or corrupt gzip data (...)"), a read
  // error, or a line longer than 64 MiB.
  bool Next(std::string* line);
  // 1-based number of the line last returned (0 before the first).
  long line_number() const { return line_; }
  // Fraction of the file's bytes consumed (compressed bytes for .gz).
  double progress() const;
  const std::string& path() const { return path_; }

 private:
  std::string path_;
  void* gz_ = nullptr;  // gzFile
  long line_ = 0;
  double size_bytes_ = 0;
  bool done_ = false;
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

// "empty log: no range readings" naming the file.
[[noreturn]] void ThrowEmptyLog(const std::string& path);

}  // namespace cogmap::io
