#include "cogmap/localize/odometry_scale.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "cogmap/core/angles.h"

namespace cogmap::localize {
namespace {

// Range against distance driven, by least squares, over the points with s
// in [s0, s1]: their count and span, means, slope and rms about the line.
struct RangeLine {
  int n = 0;
  double lo = 0.0, hi = 0.0, ms = 0.0, mr = 0.0, sss = 0.0, slope = 0.0, rms = 0.0;
};

template <class Points>
RangeLine FitRangeLine(const Points& points, double s0, double s1) {
  RangeLine l;
  l.lo = std::numeric_limits<double>::infinity();
  l.hi = -l.lo;
  for (const auto& q : points)
    if (q.s >= s0 && q.s <= s1) l.lo = std::min(l.lo, q.s), l.hi = std::max(l.hi, q.s), l.ms += q.s, l.mr += q.r, ++l.n;
  if (l.n == 0) return l;
  l.ms /= l.n, l.mr /= l.n;
  double ssr = 0.0;
  for (const auto& q : points)
    if (q.s >= s0 && q.s <= s1) l.sss += (q.s - l.ms) * (q.s - l.ms), ssr += (q.s - l.ms) * (q.r - l.mr);
  if (!(l.sss > 0.0)) return l;
  l.slope = ssr / l.sss;
  double rss = 0.0;
  for (const auto& q : points)
    if (q.s >= s0 && q.s <= s1) {
      const double e = q.r - (l.mr + l.slope * (q.s - l.ms));
      rss += e * e;
    }
  l.rms = std::sqrt(rss / std::max(1, l.n - 2));
  return l;
}

}  // namespace

OdometryScaleEstimator::OdometryScaleEstimator(const sensors::RobotDescription& robot,
                                               const OdometryScaleOptions& options)
    : robot_(robot), options_(options) {
  along_.assign(robot_.sensors.size(), 0);
  open_.resize(robot_.sensors.size());
  side_.assign(robot_.sensors.size(), 0);
  seen_.resize(robot_.sensors.size());
  for (size_t i = 0; i < robot_.sensors.size(); ++i) {
    const auto& s = robot_.sensors[i];
    // A laser's beams only with lasers_too (OdometryScaleOptions).
    if (s.kind == sensors::SensorKind::kLaser && !options_.lasers_too) continue;
    const double limit = s.kind == sensors::SensorKind::kLaser ? options_.max_laser_axis_rad : options_.max_axis_rad;
    const double a = s.robot_from_sensor.theta;
    if (std::abs(NormalizeAngle(a)) <= limit) along_[i] = +1;
    else if (std::abs(NormalizeAngle(a - kPi)) <= limit) along_[i] = -1;
    if (std::abs(std::abs(NormalizeAngle(a)) - kPi / 2) <= limit) side_[i] = 1;
  }
}

void OdometryScaleEstimator::Add(const sensors::LogRecord& record) {
  const Pose2& p = record.odom;
  // The odometry between readings only: a log's odometry-only records (a
  // CARMEN log's, interleaved with its scans) may jitter back and forth.
  if (record.ranges.empty()) return;
  if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.theta)) return;
  if (have_last_) {
    const Vec2 d = p.translation() - last_.translation();
    const double mid = last_.theta + 0.5 * AngleDiff(p.theta, last_.theta);
    const double step = d.x() * std::cos(mid) + d.y() * std::sin(mid);
    theta_ += AngleDiff(p.theta, last_.theta);
    // A gap in the log or a reversal of the motion ends every run.
    const int dir = step > 0.005 ? 1 : step < -0.005 ? -1 : 0;
    if (d.norm() > options_.max_step_m || (dir != 0 && direction_ != 0 && dir != direction_)) {
      for (size_t i = 0; i < open_.size(); ++i) Close(static_cast<int>(i));
      for (auto& v : seen_) v.clear();
    }
    if (dir != 0) direction_ = dir;
    s_ += step;
  } else {
    theta_ = p.theta;
  }
  last_ = p;
  have_last_ = true;

  for (const auto& reading : record.ranges) {
    const int i = reading.sensor;
    if (i < 0 || i >= static_cast<int>(along_.size())) continue;
    const auto& sensor = robot_.sensors[i];
    const double r = reading.range_m;
    const bool echo = std::isfinite(r) && r >= sensor.min_range_m && r < options_.max_range_fraction * sensor.max_range_m;
    if (side_[i]) {
      auto& v = seen_[i];
      if (echo) v.push_back({s_, r});
      // Kept over the longest run a sonar can make (its max range) and more.
      const double keep = 2.0 * sensor.max_range_m + 2.0;
      size_t drop = 0;
      while (drop < v.size() && std::abs(s_ - v[drop].s) > keep) ++drop;
      if (drop > 0) v.erase(v.begin(), v.begin() + static_cast<long>(drop));
    }
    if (along_[i] == 0) continue;
    Open& run = open_[i];
    if (!echo) {
      Close(i);
      continue;
    }
    if (!run.points.empty()) {
      const Point& last = run.points.back();
      const double ds = s_ - last.s;
      // Nearer by the distance driven towards it (a sensor behind: farther).
      const double predicted = last.r - along_[i] * ds;
      const double jump = options_.max_jump_m + options_.max_jump_per_m * std::abs(ds);
      if (std::abs(r - predicted) > jump || std::abs(theta_ - run.theta0) > options_.max_turn_rad) Close(i);
    }
    if (run.points.empty()) run.theta0 = theta_;
    run.points.push_back({s_, r});
  }
}

void OdometryScaleEstimator::Finish() {
  for (size_t i = 0; i < open_.size(); ++i) Close(static_cast<int>(i));
}

void OdometryScaleEstimator::Close(int sensor) {
  Open& run = open_[sensor];
  std::vector<Point> pts;
  pts.swap(run.points);
  const RangeLine line = FitRangeLine(pts, -std::numeric_limits<double>::infinity(),
                                      std::numeric_limits<double>::infinity());
  if (line.n < std::max(3, options_.min_readings) || line.hi - line.lo < options_.min_run_m) return;
  if (!(line.sss > 0.0) || line.rms > options_.max_rms_m) return;
  const bool sonar = robot_.sensors[sensor].kind == sensors::SensorKind::kSonar;
  double scale = -along_[sensor] * line.slope, sigma = line.rms / std::sqrt(line.sss), side = 0.0;
  if (sonar) {
    double side_sigma = 0.0;
    if (!SideSlope(line.lo, line.hi, &side, &side_sigma)) return;
    if (std::abs(side) > options_.max_side_slope) return;
    // Ahead k cos(a), aside k sin(a): k = hypot (its sigma by propagation).
    const double k = std::hypot(scale, side);
    if (!(k > 0.0)) return;
    sigma = std::hypot(scale * sigma, side * side_sigma) / k;
    scale = k;
  }
  OdometryScaleRun out;
  out.sensor = sensor;
  out.side_slope = side;
  out.sonar = sonar;
  out.line_s = line.ms;
  out.line_r = line.mr;
  out.line_slope = line.slope;
  out.look = along_[sensor];
  out.s_begin = line.lo;
  out.s_end = line.hi;
  out.travel_m = line.hi - line.lo;
  out.readings = line.n;
  out.scale = scale;
  out.sigma = sigma;
  out.rms_m = line.rms;
  runs_.push_back(out);
}

bool OdometryScaleEstimator::SideSlope(double s0, double s1, double* slope, double* sigma) const {
  bool found = false;
  for (size_t i = 0; i < seen_.size(); ++i) {
    if (!side_[i]) continue;
    const RangeLine line = FitRangeLine(seen_[i], s0, s1);
    if (line.n < std::max(3, options_.side_min_readings) || line.hi - line.lo < options_.side_cover * (s1 - s0)) continue;
    if (!(line.sss > 0.0)) continue;
    if (line.rms > options_.max_rms_m) continue;  // not one wall (a doorway, furniture)
    const double b = line.slope, se = line.rms / std::sqrt(line.sss);
    if (!found || se < *sigma) *slope = b, *sigma = se, found = true;
  }
  return found;
}

OdometryScaleEstimate OdometryScaleEstimator::Estimate(int min_runs) const {
  return CombineScaleRuns(runs_, min_runs, options_.run_sigma_floor, options_.pair_tolerance_m);
}

Pose2 DistanceScaler::Apply(const Pose2& raw) {
  const Vec2 p = raw.translation();
  if (!have_) {
    have_ = true;
    anchor_raw_ = anchor_scaled_ = p;
  }
  last_raw_ = p;
  last_scaled_ = identity_ ? p : Vec2(anchor_scaled_ + scale_ * (p - anchor_raw_));
  return {last_scaled_.x(), last_scaled_.y(), raw.theta};
}

void DistanceScaler::SetScale(double scale) {
  if (!(scale > 0.0) || !std::isfinite(scale) || scale == scale_) return;
  anchor_raw_ = last_raw_;
  anchor_scaled_ = last_scaled_;
  scale_ = scale;
  identity_ = false;
}

double ShrunkScale(const OdometryScaleEstimate& e, double prior_sigma, double prior_calibrated) {
  if (!e.valid || !(prior_sigma > 0.0) || !(e.sigma > 0.0)) return 1.0;
  const double p2 = prior_sigma * prior_sigma, s2 = e.sigma * e.sigma, d = e.scale - 1.0;
  // The odds of "off by N(0, prior_sigma^2)" against "calibrated" given d.
  const double log_bf = 0.5 * std::log(s2 / (s2 + p2)) + 0.5 * d * d * (1.0 / s2 - 1.0 / (s2 + p2));
  const double pc = std::clamp(prior_calibrated, 0.0, 1.0);
  const double odds = (1.0 - pc) * std::exp(std::min(log_bf, 700.0));
  const double off = pc > 0.0 ? odds / (odds + pc) : 1.0;
  return 1.0 + off * d * p2 / (p2 + s2);
}

OdometryScaleEstimate CombineScaleRuns(const std::vector<OdometryScaleRun>& all, int min_runs,
                                       double run_sigma_floor, double pair_tolerance_m) {
  OdometryScaleEstimate e;
  for (const auto& r : all) e.travel_m += r.travel_m;
  // Groups: same look, overlapping stretches.
  std::vector<OdometryScaleRun> sorted = all;
  std::sort(sorted.begin(), sorted.end(), [](const auto& a, const auto& b) {
    return a.look != b.look ? a.look < b.look : a.s_begin < b.s_begin;
  });
  std::vector<OdometryScaleRun> runs;
  for (size_t i = 0; i < sorted.size();) {
    size_t j = i + 1;
    double end = sorted[i].s_end, sw = 1.0 / (sorted[i].sigma * sorted[i].sigma + 1e-12);
    double swx = sw * sorted[i].scale, best = sorted[i].sigma;
    bool sonar = sorted[i].sonar, paired = false;
    while (j < sorted.size() && sorted[j].look == sorted[i].look && sorted[j].s_begin < end) {
      const double w = 1.0 / (sorted[j].sigma * sorted[j].sigma + 1e-12);
      sw += w, swx += w * sorted[j].scale;
      best = std::min(best, sorted[j].sigma);
      end = std::max(end, sorted[j].s_end);
      sonar = sonar || sorted[j].sonar;
      ++j;
    }
    for (size_t a = i; a < j && !paired; ++a)
      for (size_t b = a + 1; b < j && !paired; ++b) {
        const auto &p = sorted[a], &q = sorted[b];
        if (p.sensor == q.sensor) continue;
        const double lo = std::max(p.s_begin, q.s_begin), hi = std::min(p.s_end, q.s_end);
        if (hi <= lo) continue;
        const double m = 0.5 * (lo + hi);
        paired = std::abs(p.line_r + p.line_slope * (m - p.line_s) - q.line_r - q.line_slope * (m - q.line_s)) <=
                 pair_tolerance_m;
      }
    if (sonar && !paired) {
      i = j;
      continue;
    }
    OdometryScaleRun g = sorted[i];
    g.scale = swx / sw;
    g.sigma = best;
    g.s_end = end;
    runs.push_back(g);
    i = j;
  }
  e.runs = static_cast<int>(runs.size());
  if (e.runs < std::max(2, min_runs)) return e;
  // Random effects (DerSimonian-Laird): the spread between runs beyond
  // their own standard errors, tau^2, added to every run's variance.
  auto mean_with = [&](double tau2, double* var) {
    double sw = 0.0, swx = 0.0;
    for (const auto& r : runs) {
      const double w = 1.0 / (r.sigma * r.sigma + tau2 + 1e-12);
      sw += w, swx += w * r.scale;
    }
    *var = 1.0 / sw;
    return swx / sw;
  };
  double var = 0.0;
  const double fixed = mean_with(0.0, &var);
  double q = 0.0, sw = 0.0, sw2 = 0.0;
  for (const auto& r : runs) {
    const double w = 1.0 / (r.sigma * r.sigma + 1e-12);
    q += w * (r.scale - fixed) * (r.scale - fixed);
    sw += w, sw2 += w * w;
  }
  const double tau2 = std::max(run_sigma_floor * run_sigma_floor, (q - (e.runs - 1)) / std::max(1e-12, sw - sw2 / sw));
  e.scale = mean_with(tau2, &var);
  e.sigma = std::sqrt(var);
  e.valid = true;
  return e;
}

}  // namespace cogmap::localize
