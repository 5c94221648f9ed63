#include "cogmap/io/log_reader.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <optional>
#include <sstream>
#include <vector>

#include <zlib.h>

#include "cogmap/core/error.h"
#include "cogmap/io/carmen_log.h"
#include "cogmap/io/ev3_log.h"
#include "cogmap/io/log_lines.h"
#include "cogmap/io/native_log.h"
#include "cogmap/io/pioneer_log.h"
#include "cogmap/io/ros1_bag.h"
#include "cogmap/io/ros2_bag.h"
#include "cogmap/sensors/robot_json.h"
#include "cogmap/io/mrpt_rawlog.h"

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

// The first bytes of a file ("" when it cannot be read: LineSource says why).
std::string HeadBytes(const std::string& path, size_t n) {
  std::ifstream in(path, std::ios::binary);
  std::string head(n, '\0');
  in.read(head.data(), static_cast<std::streamsize>(n));
  head.resize(static_cast<size_t>(std::max<std::streamsize>(in.gcount(), 0)));
  return head;
}

bool EndsWith(const std::string& s, const std::string& tail) {
  return s.size() >= tail.size() && s.compare(s.size() - tail.size(), tail.size(), tail) == 0;
}

std::string SniffFormat(const std::string& path) {
  if (path == kStdinPath) {
    const std::string head = StdinHead();
    if (head.compare(0, 12, kRos1BagMagic) == 0) return "rosbag";
    if (head.rfind("#ROSBAG", 0) == 0)
      throw InputError(kStdinName, 1, "a ROS bag of another version than 2.0 ('" + head.substr(0, 12) +
                                          "'): cogmap reads 2.0");
    if (LooksLikeMrptRawlogHead(head)) return "rawlog";
    return SniffLines(StdinHeadLines(1000), kStdinName);
  }
  std::error_code ec;
  if (fs::is_directory(path, ec)) {
    if (fs::is_regular_file(fs::path(path) / "measurement.txt", ec)) return "pioneer";
    if (fs::is_regular_file(fs::path(path) / "metadata.yaml", ec)) return "ros2bag";
    throw InputError(path, 0,
                     "is a folder without measurement.txt and poses.txt (a pioneer log) or metadata.yaml (a ROS 2 bag)");
  }
  const std::string base = fs::path(path).filename().string();
  if (base == "measurement.txt" || base == "poses.txt") return "pioneer";
  if (base == "metadata.yaml" || EndsWith(base, ".db3") || EndsWith(base, ".mcap")) return "ros2bag";
  if (HeadBytes(path, 12) == kRos1BagMagic) return "rosbag";
  if (LooksLikeMrptRawlog(path)) return "rawlog";
  if (HeadBytes(path, 7) == "#ROSBAG")
    throw InputError(path, 1, "a ROS bag of another version than 2.0 ('" + HeadBytes(path, 12) + "'): cogmap reads 2.0");
  LineSource src(path);
  std::vector<std::string> lines;
  std::string line;
  while (lines.size() < 1000 && src.Next(&line)) lines.push_back(line);
  return SniffLines(lines, path);
}

// A bag or rawlog read from standard input: the reader opens a copy of it
// (StdinCopy), and every message and path() name "stdin", not the copy.
class StdinCopyReader : public LogReader {
 public:
  StdinCopyReader(const std::string& format, const LogOpenOptions& options) {
    Renaming([&] {
      inner_ = format == "rosbag" ? OpenRos1Bag(copy_.path(), options) : OpenMrptRawlog(copy_.path(), options);
    });
  }
  bool Next(sensors::LogRecord* record) override {
    bool more = false;
    Renaming([&] { more = inner_->Next(record); });
    return more;
  }
  std::optional<sensors::RobotDescription> robot_hint() const override { return inner_->robot_hint(); }
  std::map<std::string, long> skipped() const override { return inner_->skipped(); }
  double progress() const override { return inner_->progress(); }
  const std::string& path() const override { return name_; }
  std::vector<LogContent> contents() const override { return inner_->contents(); }

 private:
  template <typename F>
  void Renaming(F&& f) {
    try {
      f();
    } catch (const InputError& e) {
      std::string m = e.what();
      for (size_t at; (at = m.find(copy_.path())) != std::string::npos;) m.replace(at, copy_.path().size(), name_);
      throw InputError(m);
    }
  }

  StdinCopy copy_;
  std::string name_ = kStdinName;
  std::unique_ptr<LogReader> inner_;
};

}  // namespace

std::string DetectLogFormat(const std::string& path) {
  std::error_code ec;
  if (path != kStdinPath && !fs::exists(path, ec)) throw InputError(path, 0, "cannot open: no such file or folder");
  return SniffFormat(path);
}

std::vector<std::string> LogFormatNames() { return {"auto", "native", "carmen", "pioneer", "ev3", "rosbag", "ros2bag", "rawlog"}; }

LogOpenOptions MakeOpenOptions(const std::string& format, const std::vector<std::string>& topics,
                               const std::string& robot_spec) {
  LogOpenOptions o;
  o.format = format;
  o.topics = topics;
  if (!robot_spec.empty()) o.robot = sensors::ResolveRobot(robot_spec);
  return o;
}

sensors::RobotDescription RobotFor(const LogReader& log, const std::string& robot_spec) {
  if (!robot_spec.empty()) return sensors::ResolveRobot(robot_spec);
  if (auto hint = log.robot_hint()) return *hint;
  return sensors::BuiltinRobot("pioneer16");
}

std::unique_ptr<LogReader> OpenLog(const std::string& path, const std::string& format) {
  LogOpenOptions o;
  o.format = format;
  return OpenLog(path, o);
}

std::unique_ptr<LogReader> OpenLog(const std::string& path, const LogOpenOptions& options) {
  const std::string& format = options.format;
  const std::string f = format == "auto" ? DetectLogFormat(path) : format;
  if (f == "rosbag" || f == "rawlog") {
    // rosbag seeks and MRPT reads a file: standard input is copied first.
    if (path == kStdinPath) return std::make_unique<StdinCopyReader>(f, options);
    return f == "rosbag" ? OpenRos1Bag(path, options) : OpenMrptRawlog(path, options);
  }
  if (f == "ros2bag") {
    if (path == kStdinPath) throw InputError(kStdinName, 0, "a ROS 2 bag is a folder: give its path");
    return OpenRos2Bag(path, options);
  }
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

namespace {
constexpr std::uintmax_t kFingerprintBytes = 1u << 20;
constexpr std::uintmax_t kFolderFileBytes = 64u << 10;

// CRC-32 (zlib) of the first 'bytes' bytes of 'path' continuing 'crc'; false
// when the file cannot be read or is shorter.
bool CrcOfPrefix(const std::string& path, std::uintmax_t bytes, uLong* crc) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return false;
  std::vector<char> buf(64u << 10);
  while (bytes > 0) {
    const std::streamsize want = static_cast<std::streamsize>(std::min<std::uintmax_t>(bytes, buf.size()));
    in.read(buf.data(), want);
    if (in.gcount() != want) return false;
    *crc = crc32(*crc, reinterpret_cast<const Bytef*>(buf.data()), static_cast<uInt>(want));
    bytes -= static_cast<std::uintmax_t>(want);
  }
  return true;
}

std::string Hex(uLong crc) {
  char text[16];
  std::snprintf(text, sizeof text, "%08lx", crc & 0xfffffffful);
  return text;
}

std::string FolderFingerprint(const std::string& path) {
  std::error_code ec;
  std::vector<fs::path> files;
  for (fs::directory_iterator it(path, ec), end; !ec && it != end; it.increment(ec))
    if (it->is_regular_file(ec)) files.push_back(it->path());
  if (ec || files.empty()) return "";
  std::sort(files.begin(), files.end());
  uLong crc = crc32(0L, Z_NULL, 0);
  for (const fs::path& f : files) {
    const std::uintmax_t size = fs::file_size(f, ec);
    if (ec) return "";
    const std::string head = f.filename().string() + "\n" + std::to_string(size) + "\n";
    crc = crc32(crc, reinterpret_cast<const Bytef*>(head.data()), static_cast<uInt>(head.size()));
    if (!CrcOfPrefix(f.string(), std::min(size, kFolderFileBytes), &crc)) return "";
  }
  return "folder-crc32 " + Hex(crc);
}
}  // namespace

std::string LogFingerprint(const std::string& path) {
  if (path.empty() || path == "-" || path == kStdinName) return "";
  std::error_code ec;
  const fs::file_status st = fs::status(path, ec);
  if (ec) return "";
  if (fs::is_directory(st)) return FolderFingerprint(path);
  if (!fs::is_regular_file(st)) return "";  // a pipe or a device: read once
  const std::uintmax_t size = fs::file_size(path, ec);
  if (ec) return "";
  const std::uintmax_t bytes = std::min(size, kFingerprintBytes);
  uLong crc = crc32(0L, Z_NULL, 0);
  if (!CrcOfPrefix(path, bytes, &crc)) return "";
  return "crc32 " + Hex(crc) + " " + std::to_string(bytes);
}

namespace {
// A fingerprint LogFingerprint makes, taken apart: its kind ("crc32" or
// "folder-crc32"), CRC and (crc32) bytes; nullopt for anything else.
struct Fingerprint {
  std::string kind, hex;
  std::uintmax_t bytes = 0;
};
std::optional<Fingerprint> ParseFingerprint(const std::string& text) {
  std::istringstream in(text);
  Fingerprint f;
  in >> f.kind >> f.hex;
  const bool hex = f.hex.size() == 8 && f.hex.find_first_not_of("0123456789abcdef") == std::string::npos;
  if (f.kind == "folder-crc32" && hex && (in >> std::ws).eof()) return f;
  if (f.kind == "crc32" && hex && (in >> f.bytes) && f.bytes <= kFingerprintBytes && (in >> std::ws).eof()) return f;
  return std::nullopt;
}
}  // namespace

bool IsFingerprint(const std::string& text) { return text.empty() || ParseFingerprint(text).has_value(); }

bool IsLogOf(const std::string& path, const std::string& fingerprint) {
  const std::optional<Fingerprint> f = ParseFingerprint(fingerprint);
  if (!f) return false;
  if (f->kind == "folder-crc32") return LogFingerprint(path) == fingerprint;
  if (path.empty() || path == "-" || path == kStdinName) return false;
  std::error_code ec;
  if (!fs::is_regular_file(path, ec)) return false;
  uLong crc = crc32(0L, Z_NULL, 0);
  return CrcOfPrefix(path, f->bytes, &crc) && Hex(crc) == f->hex;
}

}  // namespace cogmap::io
