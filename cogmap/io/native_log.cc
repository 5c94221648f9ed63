#include "cogmap/io/native_log.h"

#include <charconv>
#include <nlohmann/json.hpp>

#include "cogmap/core/error.h"
#include "cogmap/io/log_lines.h"
#include "cogmap/sensors/robot_json.h"

namespace cogmap::io {
namespace {

// More readings in one SWEEP than this is absurd (the largest laser has a few
// thousand beams); checked before any arithmetic on the count.
constexpr long kMaxSweepReadings = 100000;

void AppendNumber(std::string* s, double v) {
  char buf[64];
  const auto r = std::to_chars(buf, buf + sizeof buf, v);
  s->push_back(' ');
  s->append(buf, r.ptr);
}

void AppendPose(std::string* s, const char* key, double t, const Pose2& p) {
  s->append(key);
  AppendNumber(s, t);
  AppendNumber(s, p.x);
  AppendNumber(s, p.y);
  AppendNumber(s, p.theta);
  s->push_back('\n');
}

class NativeLogReader : public LogReader {
 public:
  explicit NativeLogReader(const std::string& path) : src_(path) {
    std::string line;
    if (!src_.Next(&line)) ThrowEmptyLog(path);
    const std::string magic = kNativeLogMagic;
    if (line.rfind(magic, 0) != 0)
      throw InputError(path, 1, "not a native cogmap log: expected '" + magic + " 1' on the first line");
    const auto f = SplitFields(std::string_view(line).substr(magic.size()));
    if (f.size() != 1) throw InputError(path, 1, "expected '" + magic + " <version>'");
    const long version = ParseCount(f[0], path, 1, "log version");
    if (version > kNativeLogVersion)
      throw InputError(path, 1, "log format version " + std::to_string(version) +
                                    " is newer than this cogmap reads (" +
                                    std::to_string(kNativeLogVersion) + "); update cogmap");
    if (version < 1) throw InputError(path, 1, "log format version must be at least 1");
    // The robot line: the first line that is neither blank nor a comment.
    while (src_.Next(&line)) {
      const auto g = SplitFields(line);
      if (g.empty() || g[0][0] == '#') continue;
      const long n = src_.line_number();
      if (g[0] == "robot") {
        if (g.size() != 2) throw InputError(path, n, "expected 'robot <built-in name>'");
        try {
          robot_ = sensors::BuiltinRobot(std::string(g[1]));
        } catch (const InputError& e) {
          throw InputError(path, n, e.what());
        }
      } else if (g[0] == "robot-json") {
        const size_t at = line.find("robot-json") + 10;
        nlohmann::json j;
        try {
          j = nlohmann::json::parse(line.substr(at));
        } catch (const nlohmann::json::exception& e) {  // parse_error, out_of_range (1e999), ...
          throw InputError(path, n, std::string("robot-json: invalid JSON: ") + e.what());
        }
        try {
          robot_ = sensors::ParseRobotJson(j, "robot-json");
        } catch (const InputError& e) {
          throw InputError(path, n, e.what());
        }
      } else {
        throw InputError(path, n, "expected a 'robot' or 'robot-json' line before the records, got '" +
                                      std::string(g[0]) + "'");
      }
      return;
    }
    ThrowEmptyLog(path);
  }

  bool Next(sensors::LogRecord* out) override {
    std::string line;
    while (src_.Next(&line)) {
      const auto f = SplitFields(line);
      if (f.empty() || f[0][0] == '#') continue;
      const long n = src_.line_number();
      const std::string& p = src_.path();
      // cogmap ends every line it writes: a last line without its end of
      // line is a log cut while it was written, whose last numbers may be
      // cut short and still parse (a range of 2.3 read as 2.).
      if (!src_.line_terminated())
        throw InputError(p, n, "the last line has no end of line: the log is truncated (cut while it was "
                               "written?); delete that line to map the rest");
      if (f[0] == "ODOM" || f[0] == "TRUTH") {
        if (f.size() != 5)
          throw InputError(p, n, std::string(f[0]) + ": expected 5 fields (" + std::string(f[0]) +
                                     " t x y theta), got " + std::to_string(f.size()));
        const double t = ParseNumber(f[1], p, n, "time");
        const Pose2 pose = CheckPosition({ParseNumber(f[2], p, n, "x"), ParseNumber(f[3], p, n, "y"),
                                          ParseNumber(f[4], p, n, "theta")},
                                         p, n, std::string(f[0]));
        if (f[0] == "ODOM") {
          const bool had = pending_;
          sensors::LogRecord prev = current_;
          current_ = {};
          current_.time_s = t;
          current_.odom = pose;
          pending_ = true;
          have_odom_ = true;
          if (had) {
            *out = std::move(prev);
            return true;
          }
        } else {
          if (!pending_) throw InputError(p, n, "TRUTH must follow an ODOM line");
          if (current_.truth) throw InputError(p, n, "second TRUTH for one ODOM");
          current_.truth = pose;
        }
      } else if (f[0] == "SWEEP") {
        if (!have_odom_) throw InputError(p, n, "SWEEP before any ODOM line");
        if (f.size() < 3) throw InputError(p, n, "SWEEP: expected 'SWEEP t n s0 r0 ...'");
        const double t = ParseNumber(f[1], p, n, "time");
        const long count = ParseCount(f[2], p, n, "reading count");
        if (count > kMaxSweepReadings)
          throw InputError(p, n, "SWEEP: reading count " + std::to_string(count) + " is absurd (at most " +
                                     std::to_string(kMaxSweepReadings) + ")");
        if (f.size() != 3 + 2 * static_cast<size_t>(count))
          throw InputError(p, n, "SWEEP: expected " + std::to_string(3 + 2 * count) + " fields for " +
                                     std::to_string(count) + " readings, got " + std::to_string(f.size()));
        // Without a new ODOM this sweep repeats the latest pose (and truth).
        current_.time_s = t;
        current_.ranges.clear();
        for (long i = 0; i < count; ++i) {
          const long s = ParseCount(f[3 + 2 * i], p, n, "sensor index");
          if (s >= static_cast<long>(robot_.sensors.size()))
            throw InputError(p, n, "sensor index " + std::to_string(s) + " but robot '" + robot_.name +
                                       "' has " + std::to_string(robot_.sensors.size()) + " sensors");
          const double r = ParseNumber(f[4 + 2 * i], p, n, "range");
          if (!RangeAccepted(r)) CheckRange(r, p, n, "sensor " + std::to_string(s));
          current_.ranges.push_back({static_cast<int>(s), r});
        }
        readings_ += count;
        pending_ = false;
        *out = current_;
        return true;
      } else {
        throw InputError(p, n, "unknown record '" + std::string(f[0]) + "' (expected ODOM, TRUTH or SWEEP)");
      }
    }
    if (pending_) {
      pending_ = false;
      *out = std::move(current_);
      current_ = {};
      return true;
    }
    if (readings_ == 0) ThrowEmptyLog(src_.path());
    return false;
  }

  std::optional<sensors::RobotDescription> robot_hint() const override { return robot_; }
  double progress() const override { return src_.progress(); }
  const std::string& path() const override { return src_.path(); }

 private:
  LineSource src_;
  sensors::RobotDescription robot_;
  sensors::LogRecord current_;
  bool pending_ = false;    // current_ holds an ODOM not yet returned
  bool have_odom_ = false;
  long readings_ = 0;
};

}  // namespace

NativeLogWriter::NativeLogWriter(std::ostream& out, const sensors::RobotDescription& robot) : out_(out) {
  out_ << kNativeLogMagic << ' ' << kNativeLogVersion << '\n';
  bool builtin = false;
  for (const auto& name : sensors::BuiltinRobotNames())
    if (name == robot.name && sensors::SameRobot(robot, sensors::BuiltinRobot(name))) builtin = true;
  if (builtin)
    out_ << "robot " << robot.name << '\n';
  else
    out_ << "robot-json " << sensors::RobotToJson(robot, /*angles_in_degrees=*/false).dump() << '\n';
}

void NativeLogWriter::Write(const sensors::LogRecord& r) {
  buf_.clear();
  AppendPose(&buf_, "ODOM", r.time_s, r.odom);
  if (r.truth) AppendPose(&buf_, "TRUTH", r.time_s, *r.truth);
  if (!r.ranges.empty()) {
    buf_.append("SWEEP");
    AppendNumber(&buf_, r.time_s);
    buf_ += ' ' + std::to_string(r.ranges.size());
    for (const auto& q : r.ranges) {
      buf_ += ' ' + std::to_string(q.sensor);
      AppendNumber(&buf_, q.range_m);
    }
    buf_.push_back('\n');
  }
  out_ << buf_;
  ++records_;
}

std::unique_ptr<LogReader> OpenNativeLog(const std::string& path) {
  return std::make_unique<NativeLogReader>(path);
}

}  // namespace cogmap::io
