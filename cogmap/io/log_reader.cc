#include "cogmap/io/log_reader.h"

#include <filesystem>

#include "cogmap/core/error.h"
#include "cogmap/io/carmen_log.h"
#include "cogmap/io/ev3_log.h"
#include "cogmap/io/log_lines.h"
#include "cogmap/io/native_log.h"
#include "cogmap/io/pioneer_log.h"

namespace cogmap::io {
namespace {

namespace fs = std::filesystem;

bool AllNumbers(const std::vector<std::string_view>& f) {
  for (const auto& t : f) {
    try {
      ParseNumber(t, "", 0, "");
    } catch (const InputError&) {
      return false;
    }
  }
  return true;
}

// The format by content: the first line of a native log; the first message
// name of a CARMEN log (after '#' comments); 3 + 13 k numbers for EV3; the
// pioneer pair by its folder or file names.
// The format of these first lines of a file ('name' for messages).
std::string SniffLines(const std::vector<std::string>& lines, const std::string& name) {
  bool any = false;
  long n = 0;
  for (const std::string& line : lines) {
    ++n;
    const auto f = SplitFields(line);
    if (f.empty()) continue;
    if (!any && line.rfind(kNativeLogMagic, 0) == 0) return "native";
    any = true;
    if (f[0][0] == '#') continue;  // CARMEN comments
    if (IsCarmenMessageName(std::string(f[0]))) return "carmen";
    if (AllNumbers(f) && f.size() >= 3 + kEv3Bearings && (f.size() - 3) % kEv3Bearings == 0) return "ev3";
    break;
  }
  if (!any) ThrowEmptyLog(name);
  throw InputError(name, n,
                   "cannot tell the log format from its content (give --format native, carmen, pioneer or ev3)");
}

std::string SniffFormat(const std::string& path) {
  if (path == kStdinPath) return SniffLines(StdinHeadLines(1000), kStdinName);
  std::error_code ec;
  if (fs::is_directory(path, ec)) {
    if (fs::is_regular_file(fs::path(path) / "measurement.txt", ec)) return "pioneer";
    throw InputError(path, 0, "is a folder without measurement.txt and poses.txt (not a pioneer log)");
  }
  const std::string base = fs::path(path).filename().string();
  if (base == "measurement.txt" || base == "poses.txt") return "pioneer";
  LineSource src(path);
  std::vector<std::string> lines;
  std::string line;
  while (lines.size() < 1000 && src.Next(&line)) lines.push_back(line);
  return SniffLines(lines, path);
}

}  // namespace

std::string DetectLogFormat(const std::string& path) {
  std::error_code ec;
  if (path != kStdinPath && !fs::exists(path, ec)) throw InputError(path, 0, "cannot open: no such file or folder");
  return SniffFormat(path);
}

std::vector<std::string> LogFormatNames() { return {"auto", "native", "carmen", "pioneer", "ev3"}; }

std::unique_ptr<LogReader> OpenLog(const std::string& path, const std::string& format) {
  const std::string f = format == "auto" ? DetectLogFormat(path) : format;
  if (f == "native") return OpenNativeLog(path);
  if (f == "carmen") return OpenCarmenLog(path);
  if (f == "pioneer") {
    if (path == kStdinPath)
      throw InputError(kStdinName, 0, "a pioneer log is two files (measurement.txt + poses.txt): give their folder");
    return OpenPioneerLog(path);
  }
  if (f == "ev3") return OpenEv3Log(path);
  std::string known;
  for (const auto& n : LogFormatNames()) known += (known.empty() ? "" : ", ") + n;
  throw InputError(path, 0, "unknown log format '" + format + "' (known: " + known + ")");
}

}  // namespace cogmap::io
