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
std::string SniffFormat(const std::string& path) {
  std::error_code ec;
  if (fs::is_directory(path, ec)) {
    if (fs::is_regular_file(fs::path(path) / "measurement.txt", ec)) return "pioneer";
    throw InputError(path, 0, "is a folder without measurement.txt and poses.txt (not a pioneer log)");
  }
  const std::string base = fs::path(path).filename().string();
  if (base == "measurement.txt" || base == "poses.txt") return "pioneer";
  LineSource src(path);
  std::string line;
  bool any = false;
  while (src.Next(&line) && src.line_number() <= 1000) {
    const auto f = SplitFields(line);
    if (f.empty()) continue;
    if (!any && line.rfind(kNativeLogMagic, 0) == 0) return "native";
    any = true;
    if (f[0][0] == '#') continue;  // CARMEN comments
    if (IsCarmenMessageName(std::string(f[0]))) return "carmen";
    if (AllNumbers(f) && f.size() >= 3 + kEv3Bearings && (f.size() - 3) % kEv3Bearings == 0) return "ev3";
    break;
  }
  if (!any) ThrowEmptyLog(path);
  throw InputError(path, src.line_number(),
                   "cannot tell the log format from its content (give --format native, carmen, pioneer or ev3)");
}

}  // namespace

std::string DetectLogFormat(const std::string& path) {
  std::error_code ec;
  if (!fs::exists(path, ec)) throw InputError(path, 0, "cannot open: no such file or folder");
  return SniffFormat(path);
}

std::vector<std::string> LogFormatNames() { return {"auto", "native", "carmen", "pioneer", "ev3"}; }

std::unique_ptr<LogReader> OpenLog(const std::string& path, const std::string& format) {
  const std::string f = format == "auto" ? DetectLogFormat(path) : format;
  if (f == "native") return OpenNativeLog(path);
  if (f == "carmen") return OpenCarmenLog(path);
  if (f == "pioneer") return OpenPioneerLog(path);
  if (f == "ev3") return OpenEv3Log(path);
  std::string known;
  for (const auto& n : LogFormatNames()) known += (known.empty() ? "" : ", ") + n;
  throw InputError(path, 0, "unknown log format '" + format + "' (known: " + known + ")");
}

}  // namespace cogmap::io
