#include "cogmap/io/ev3_log.h"

#include <algorithm>

#include "cogmap/core/angles.h"
#include "cogmap/core/error.h"
#include "cogmap/io/log_lines.h"

namespace cogmap::io {
namespace {

class Ev3Reader : public Ev3LogReader {
 public:
  explicit Ev3Reader(const std::string& path) : src_(path), robot_(Ev3Robot()) {}

  bool Next(sensors::LogRecord* out) override {
    std::string line;
    while (src_.Next(&line)) {
      const auto f = SplitFields(line);
      if (f.empty()) continue;
      const long n = src_.line_number();
      const std::string& p = src_.path();
      if (f.size() < 3 + kEv3Bearings || (f.size() - 3) % kEv3Bearings != 0)
        throw InputError(p, n, "expected x y theta and 13 bearings of k samples (3 + 13 k fields), got " +
                                   std::to_string(f.size()) + " fields");
      const int k = static_cast<int>((f.size() - 3) / kEv3Bearings);
      if (k_ == 0) k_ = k;
      if (k != k_)
        throw InputError(p, n, std::to_string(k) + " samples per bearing, but the first line had " +
                                   std::to_string(k_) + " (expected " + std::to_string(3 + 13 * k_) + " fields)");
      *out = {};
      out->time_s = static_cast<double>(index_++);
      out->odom = CheckPosition({ParseNumber(f[0], p, n, "x") / 100.0, ParseNumber(f[1], p, n, "y") / 100.0,
                                 ParseNumber(f[2], p, n, "theta")},
                                p, n, "pose");
      bool disagree = false;
      samples_.resize(k);
      out->ranges.resize(kEv3Bearings);
      for (int b = 0; b < kEv3Bearings; ++b) {
        for (int i = 0; i < k; ++i) {
          const std::string what = "bearing " + std::to_string(b) + " sample " + std::to_string(i);
          const double cm = ParseNumber(f[3 + b * k + i], p, n, what);
          CheckRange(cm / 100.0, p, n, what);
          samples_[i] = cm;
        }
        std::sort(samples_.begin(), samples_.end());
        if (samples_.back() - samples_.front() > kEv3DisagreeCm) disagree = true;
        out->ranges[b] = {b, samples_[(k - 1) / 2] / 100.0};
      }
      if (disagree) ++disagreeing_;
      readings_ += kEv3Bearings;
      return true;
    }
    if (readings_ == 0) ThrowEmptyLog(src_.path());
    return false;
  }

  std::optional<sensors::RobotDescription> robot_hint() const override { return robot_; }
  double progress() const override { return src_.progress(); }
  const std::string& path() const override { return src_.path(); }
  int samples_per_bearing() const override { return k_; }
  long disagreeing_lines() const override { return disagreeing_; }

 private:
  LineSource src_;
  sensors::RobotDescription robot_;
  std::vector<double> samples_;
  int k_ = 0;
  long index_ = 0;
  long readings_ = 0;
  long disagreeing_ = 0;
};

}  // namespace

sensors::RobotDescription Ev3Robot() {
  sensors::RobotDescription r;
  r.name = "ev3";
  r.radius_m = 0.10;  // a small EV3 rover
  for (int b = 0; b < kEv3Bearings; ++b) {
    sensors::RangeSensor s;
    // The first bearing of a line is the robot's left (+90, CCW): with that
    // order the walls of both logs come out straight (entropy 0.80 -> 0.61 and
    // 0.78 -> 0.65, line fraction 0.58 -> 0.68 and 0.32 -> 0.45 against the
    // reverse order; grid::Summarize on ev3-69 / ev3-154).
    s.robot_from_sensor = {0.0, 0.0, DegToRad(90.0 - 15.0 * b)};
    s.beam_width_rad = DegToRad(25.0);
    s.min_range_m = 0.03;
    s.max_range_m = 2.55;  // 255 cm = no echo
    s.kind = sensors::SensorKind::kSonar;
    r.sensors.push_back(s);
  }
  return r;
}

std::unique_ptr<Ev3LogReader> OpenEv3Log(const std::string& path) { return std::make_unique<Ev3Reader>(path); }

}  // namespace cogmap::io
