#include "cogmap/io/pioneer_log.h"

#include <filesystem>

#include "cogmap/core/angles.h"
#include "cogmap/core/error.h"
#include "cogmap/io/log_lines.h"

namespace cogmap::io {
namespace {

namespace fs = std::filesystem;

constexpr int kSonars = 8;

class PioneerReader : public LogReader {
 public:
  PioneerReader(const std::string& path, const PioneerPairPaths& pair)
      : path_(path), meas_(pair.measurements), poses_(pair.poses), robot_(sensors::BuiltinRobot("pioneer8-course")) {}

  bool Next(sensors::LogRecord* out) override {
    std::string m, p;
    bool has_m = NextData(meas_, &m);
    bool has_p = NextData(poses_, &p);
    if (!has_m && !has_p) {
      if (readings_ == 0) ThrowEmptyLog(path_);
      return false;
    }
    if (has_m != has_p) {
      const LineSource& longer = has_m ? meas_ : poses_;
      const LineSource& shorter = has_m ? poses_ : meas_;
      throw InputError(longer.path(), longer.line_number(),
                       "has more lines than " + shorter.path() + " (" + std::to_string(shorter.line_number()) +
                           " lines); the two files must pair line by line");
    }
    const auto fm = SplitFields(m);
    const auto fp = SplitFields(p);
    const long lm = meas_.line_number(), lp = poses_.line_number();
    if (fm.size() != 1 + kSonars)
      throw InputError(meas_.path(), lm, "expected 9 fields (timestamp r0..r7), got " + std::to_string(fm.size()));
    if (fp.size() != 4)
      throw InputError(poses_.path(), lp,
                       "expected 4 fields (timestamp x_mm y_mm theta), got " + std::to_string(fp.size()));
    const double tm = ParseNumber(fm[0], meas_.path(), lm, "timestamp");
    const double tp = ParseNumber(fp[0], poses_.path(), lp, "timestamp");
    if (tm != tp)
      throw InputError(meas_.path(), lm, "timestamp " + std::string(fm[0]) + " but " + poses_.path() + ":" +
                                             std::to_string(lp) + " has " + std::string(fp[0]) +
                                             "; the two files must pair line by line");
    *out = {};
    out->time_s = tm / 1000.0;
    out->odom = CheckPosition({ParseNumber(fp[1], poses_.path(), lp, "x_mm") / 1000.0,
                               ParseNumber(fp[2], poses_.path(), lp, "y_mm") / 1000.0,
                               DegToRad(ParseNumber(fp[3], poses_.path(), lp, "theta") / 10.0)},
                              poses_.path(), lp, "pose");
    out->ranges.resize(kSonars);
    for (int i = 0; i < kSonars; ++i) {
      const double r = ParseNumber(fm[1 + i], meas_.path(), lm, "r" + std::to_string(i)) / 1000.0;
      if (!RangeAccepted(r)) CheckRange(r, meas_.path(), lm, "r" + std::to_string(i));
      out->ranges[i] = {i, r};
    }
    readings_ += kSonars;
    return true;
  }

  std::optional<sensors::RobotDescription> robot_hint() const override { return robot_; }
  double progress() const override { return meas_.progress(); }
  const std::string& path() const override { return path_; }

 private:
  static bool NextData(LineSource& src, std::string* line) {
    while (src.Next(line))
      if (!SplitFields(*line).empty()) return true;
    return false;
  }

  std::string path_;
  LineSource meas_, poses_;
  sensors::RobotDescription robot_;
  long readings_ = 0;
};

}  // namespace

PioneerPairPaths ResolvePioneerPair(const std::string& path) {
  std::error_code ec;
  fs::path dir;
  if (fs::is_directory(path, ec)) {
    dir = path;
  } else {
    const fs::path p(path);
    const std::string base = p.filename().string();
    if (base != "measurement.txt" && base != "poses.txt") {
      if (!fs::exists(path, ec)) throw InputError(path, 0, "cannot open: no such file or folder");
      throw InputError(path, 0, "pioneer logs are a folder with measurement.txt and poses.txt (give the folder or one of them)");
    }
    dir = p.parent_path();
  }
  PioneerPairPaths r;
  r.measurements = (dir / "measurement.txt").string();
  r.poses = (dir / "poses.txt").string();
  for (const auto& f : {r.measurements, r.poses})
    if (!fs::is_regular_file(f, ec))
      throw InputError(f, 0, "missing: a pioneer log needs both measurement.txt and poses.txt");
  return r;
}

std::unique_ptr<LogReader> OpenPioneerLog(const std::string& path) {
  return std::make_unique<PioneerReader>(path, ResolvePioneerPair(path));
}

}  // namespace cogmap::io
