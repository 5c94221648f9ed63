#include "cogmap/sensors/as_sonar.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "cogmap/core/angles.h"

namespace cogmap::sensors {

AsSonar::AsSonar(const RobotDescription& source, const RobotDescription& sonar, const AsSonarOptions& options)
    : source_(source), sonar_(sonar) {
  // Source headings, sorted on the circle, and the median gap between
  // neighbours as the beam spacing.
  std::vector<double> headings;
  for (const auto& s : source.sensors) headings.push_back(NormalizeAngle(s.robot_from_sensor.theta));
  std::sort(headings.begin(), headings.end());
  double spacing = 2.0 * kPi;
  if (headings.size() > 1) {
    std::vector<double> gaps;
    for (size_t i = 1; i < headings.size(); ++i)
      if (headings[i] - headings[i - 1] > 1e-12) gaps.push_back(headings[i] - headings[i - 1]);
    if (!gaps.empty()) {
      std::nth_element(gaps.begin(), gaps.begin() + gaps.size() / 2, gaps.end());
      spacing = gaps[gaps.size() / 2];
    }
  }
  // Whether the source looks at robot-frame point p: some source sensor's
  // heading within one spacing of p's bearing from that sensor.
  auto in_view = [&](const Vec2& p) {
    for (const auto& src : source.sensors) {
      const Vec2 d = p - src.robot_from_sensor.translation();
      if (d.norm() < 1e-9) return true;
      if (std::abs(AngleDiff(std::atan2(d.y(), d.x()), src.robot_from_sensor.theta)) <= spacing + 1e-9) return true;
    }
    return false;
  };
  // The same view as bearing tables, one per mount point (FireAt).
  for (const auto& src : source.sensors) {
    const Vec2 mount = src.robot_from_sensor.translation();
    auto it = std::find_if(view_.begin(), view_.end(), [&](const ViewGroup& g) { return (g.mount - mount).norm() < 1e-9; });
    if (it == view_.end()) {
      view_.push_back({mount, 0.0, std::vector<bool>(kViewBins, false)});
      it = view_.end() - 1;
    }
    it->max_range_m = std::max(it->max_range_m, src.max_range_m);
    const int reach = static_cast<int>(std::ceil(spacing / (2.0 * kPi / kViewBins)));
    const int centre = static_cast<int>(std::floor((NormalizeAngle(src.robot_from_sensor.theta) + kPi) / (2.0 * kPi) * kViewBins));
    for (int b = centre - reach; b <= centre + reach; ++b) {
      const int bin = ((b % kViewBins) + kViewBins) % kViewBins;
      const double mid = -kPi + (bin + 0.5) * (2.0 * kPi / kViewBins);
      if (std::abs(AngleDiff(mid, src.robot_from_sensor.theta)) <= spacing + 1e-9) it->bearing[bin] = true;
    }
  }
  constexpr int kAxisSamples = 20;
  for (const auto& s : sonar.sensors) {
    sonar_from_robot_.push_back(s.robot_from_sensor.inverse());
    bool covered = !options.skip_unseen_sonars;
    for (double h : headings)
      if (std::abs(AngleDiff(s.robot_from_sensor.theta, h)) <= spacing + 1e-9) covered = true;
    covered_.push_back(covered);
    bool no_echo = true;
    if (options.no_echo_only_when_in_view)
      for (int i = 1; i <= kAxisSamples && no_echo; ++i)
        no_echo = in_view(s.robot_from_sensor * Vec2(s.max_range_m * i / kAxisSamples, 0.0));
    no_echo_.push_back(no_echo);
  }
}

std::vector<RangeReading> AsSonar::Convert(const std::vector<RangeReading>& source_readings) const {
  std::vector<RangeReading> out;
  if (source_readings.empty()) return out;
  const std::vector<Vec2> points = Echoes(Pose2{}, source_readings).points;
  for (size_t k = 0; k < sonar_.sensors.size(); ++k) {
    if (!covered_[k]) continue;
    const RangeSensor& s = sonar_.sensors[k];
    const double half = 0.5 * s.beam_width_rad + 1e-12;
    double nearest = std::numeric_limits<double>::infinity();
    for (const Vec2& p : points) {
      const Vec2 q = sonar_from_robot_[k] * p;
      const double range = q.norm();
      if (range >= nearest) continue;
      if (std::abs(std::atan2(q.y(), q.x())) <= half) nearest = range;
    }
    if (nearest < s.max_range_m) out.push_back({static_cast<int>(k), nearest});
    else if (no_echo_[k]) out.push_back({static_cast<int>(k), s.max_range_m});
  }
  return out;
}

SourceScan AsSonar::Echoes(const Pose2& odom, const std::vector<RangeReading>& source_readings) const {
  SourceScan scan{odom, {}};
  scan.points.reserve(source_readings.size());
  const int n_source = static_cast<int>(source_.sensors.size());
  for (const auto& r : source_readings) {
    if (r.sensor < 0 || r.sensor >= n_source) continue;
    const RangeSensor& s = source_.sensors[r.sensor];
    if (!(r.range_m > 0.0) || r.range_m < s.min_range_m || r.range_m >= s.max_range_m) continue;
    scan.points.push_back(ReadingEndPoint(Pose2{}, s, r.range_m));
  }
  return scan;
}

bool AsSonar::InView(const Vec2& p) const {
  for (const ViewGroup& g : view_) {
    const Vec2 d = p - g.mount;
    const double r = d.norm();
    if (r < 1e-9) return true;
    if (r >= g.max_range_m) continue;
    const int bin = std::clamp(static_cast<int>(std::floor((std::atan2(d.y(), d.x()) + kPi) / (2.0 * kPi) * kViewBins)),
                               0, kViewBins - 1);
    if (g.bearing[bin]) return true;
  }
  return false;
}

std::vector<RangeReading> AsSonar::FireAt(const Pose2& odom, const std::vector<int>& sonars,
                                          const std::vector<const SourceScan*>& scans) const {
  std::vector<RangeReading> out;
  if (scans.empty()) return out;
  // Each scan's robot frame from the firing robot's, and back.
  std::vector<Pose2> here_from_scan, scan_from_here;
  for (const SourceScan* sc : scans) {
    here_from_scan.push_back(odom.inverse() * sc->odom);
    scan_from_here.push_back(here_from_scan.back().inverse());
  }
  auto seen = [&](const Vec2& here) {
    for (const Pose2& t : scan_from_here)
      if (InView(t * here)) return true;
    return false;
  };
  constexpr int kAxisSamples = 20;
  for (int k : sonars) {
    if (k < 0 || k >= static_cast<int>(sonar_.sensors.size())) continue;
    const RangeSensor& s = sonar_.sensors[k];
    const double half = 0.5 * s.beam_width_rad + 1e-12;
    double nearest = std::numeric_limits<double>::infinity();
    for (size_t j = 0; j < scans.size(); ++j) {
      const Pose2 sonar_from_scan = sonar_from_robot_[k] * here_from_scan[j];
      for (const Vec2& p : scans[j]->points) {
        const Vec2 q = sonar_from_scan * p;
        const double range = q.norm();
        if (range >= nearest) continue;
        if (std::abs(std::atan2(q.y(), q.x())) <= half) nearest = range;
      }
    }
    const double reach = std::min(nearest, s.max_range_m);
    bool in_view = true;
    for (int i = 1; i <= kAxisSamples && in_view; ++i)
      in_view = seen(s.robot_from_sensor * Vec2(reach * i / kAxisSamples, 0.0));
    if (!in_view) continue;
    out.push_back({k, nearest < s.max_range_m ? nearest : s.max_range_m});
  }
  return out;
}

}  // namespace cogmap::sensors
