#include "cogmap/localize/scan_odometry.h"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>

namespace cogmap::localize {
namespace {

// A return's neighbours make a line when their spread across it is under a
// fifth of that along it (variance ratio 0.04): not a corner.
constexpr double kThin = 0.04;
constexpr int kMissesToStop = 3;

}  // namespace

bool HasLaser(const sensors::RobotDescription& robot) {
  for (const auto& s : robot.sensors)
    if (s.kind == sensors::SensorKind::kLaser) return true;
  return false;
}

const sensors::RangeSensor* LaserReturn(const sensors::RobotDescription& robot, const sensors::RangeReading& r) {
  if (r.sensor < 0 || r.sensor >= static_cast<int>(robot.sensors.size())) return nullptr;
  const sensors::RangeSensor& s = robot.sensors[r.sensor];
  if (s.kind != sensors::SensorKind::kLaser || !(r.range_m >= s.min_range_m && r.range_m < s.max_range_m))
    return nullptr;
  return &s;
}

ScanDensity::ScanDensity(const sensors::RobotDescription& robot, ScanOdometryOptions options, int gaps)
    : robot_(robot), o_(options), want_(std::max(1, gaps)) {}

bool ScanDensity::Add(const Pose2& odom, const std::vector<sensors::RangeReading>& ranges) {
  if (decided()) return true;
  bool scan = false;
  for (const auto& r : ranges) scan = scan || LaserReturn(robot_, r) != nullptr;
  if (!scan) return false;
  if (have_last_) {
    const Pose2 w = last_.inverse() * odom;
    steps_ += std::max(std::hypot(w.x, w.y) / o_.reference_m, std::abs(w.theta) / o_.reference_rad);
    ++gaps_;
  }
  last_ = odom;
  have_last_ = true;
  return decided();
}

ScanOdometry::ScanOdometry(sensors::RobotDescription robot, ScanOdometryOptions options)
    : robot_(std::move(robot)), o_(options) {
  has_laser_ = HasLaser(robot_);
}

std::vector<Vec2> ScanOdometry::ScanPoints(const std::vector<sensors::RangeReading>& ranges) const {
  std::vector<Vec2> out;
  out.reserve(ranges.size());
  for (const auto& r : ranges) {
    const sensors::RangeSensor* s = LaserReturn(robot_, r);
    if (!s || r.range_m > o_.max_point_range_m) continue;
    const Vec2 p = sensors::ReadingEndPoint(Pose2{}, *s, r.range_m);
    // Within max_point_range_m of the robot's centre (a sensor mounted far
    // off it, in a robot file, must not stretch the reference's grid).
    if (p.norm() <= o_.max_point_range_m) out.push_back(p);
  }
  return out;
}

std::vector<Vec2> ScanOdometry::Normals(const std::vector<Vec2>& pts) const {
  const int n = static_cast<int>(pts.size());
  std::vector<Vec2> normals(pts.size(), Vec2(0.0, 0.0));
  // Each point's line: the principal axis of the returns within neighbour_m
  // of it along the scan either side (a surface, not a jump to another one),
  // at least three of them and thin (their spread across the axis under a
  // fifth of that along it: no corner). With two neighbours alone the range
  // noise tilted the normals by degrees, and the tilt slid a corridor's scans
  // along it; so did a fixed count of beams at close range, where 15 beams of
  // a dense laser span a few centimetres of wall (a 0.7-degree laser 0.35 m
  // from a corridor's wall: lines 40 degrees off, which held the robot still
  // in the corridor for 3 m).
  // One pass over the neighbours (offsets from the point itself, so the
  // sums stay small), the 2 x 2 scatter's eigen-decomposition in closed form.
  const double r2 = o_.neighbour_m * o_.neighbour_m;
  for (int i = 0; i < n; ++i) {
    double sx = 0.0, sy = 0.0, sxx = 0.0, sxy = 0.0, syy = 0.0;
    int m = 0;
    // Outwards from the point on either side, over the returns within
    // neighbour_m, until kMissesToStop in a row lie farther (or line_beams).
    for (int dir : {-1, 1}) {
      int misses = 0;
      for (int j = dir < 0 ? i : i + 1, k = 0; j >= 0 && j < n && k <= o_.line_beams && misses < kMissesToStop;
           j += dir, ++k) {
        const Vec2 d = pts[j] - pts[i];
        if (d.squaredNorm() > r2) {
          ++misses;
          continue;
        }
        misses = 0;
        sx += d.x(), sy += d.y();
        sxx += d.x() * d.x(), sxy += d.x() * d.y(), syy += d.y() * d.y();
        ++m;
      }
    }
    if (m < 3) continue;
    const double a = sxx - sx * sx / m, b = sxy - sx * sy / m, c = syy - sy * sy / m;
    const double mid = 0.5 * (a + c), half = std::hypot(0.5 * (a - c), b);
    if (!(mid - half <= kThin * (mid + half))) continue;
    // The principal axis's angle; the normal is across it.
    const double phi = 0.5 * std::atan2(2.0 * b, a - c);
    normals[i] = Vec2(-std::sin(phi), std::cos(phi));
  }
  return normals;
}

void ScanOdometry::MakeReference(const std::vector<Vec2>& points, const std::vector<Vec2>& normals,
                                 const Pose2& corrected, const Pose2& odom) {
  Reference ref;
  ref.corrected = corrected;
  ref.odom = odom;
  ref.cell = o_.max_correspondence_m;
  for (size_t i = 0; i < points.size(); ++i)
    if (normals[i] != Vec2(0.0, 0.0)) {
      ref.points.push_back(points[i]);
      ref.normals.push_back(normals[i]);
    }
  if (!ref.points.empty()) {
    double x1 = ref.points[0].x(), y1 = ref.points[0].y();
    ref.x0 = x1, ref.y0 = y1;
    for (const Vec2& p : ref.points) {
      ref.x0 = std::min(ref.x0, p.x()), ref.y0 = std::min(ref.y0, p.y());
      x1 = std::max(x1, p.x()), y1 = std::max(y1, p.y());
    }
    // Points lie within max_point_range_m of the robot: a bounded grid.
    ref.nx = static_cast<int>((x1 - ref.x0) / ref.cell) + 1;
    ref.ny = static_cast<int>((y1 - ref.y0) / ref.cell) + 1;
    std::vector<int> cell_of(ref.points.size());
    ref.start.assign(static_cast<size_t>(ref.nx) * ref.ny + 1, 0);
    for (size_t i = 0; i < ref.points.size(); ++i) {
      const int cx = std::min(ref.nx - 1, static_cast<int>((ref.points[i].x() - ref.x0) / ref.cell));
      const int cy = std::min(ref.ny - 1, static_cast<int>((ref.points[i].y() - ref.y0) / ref.cell));
      cell_of[i] = cy * ref.nx + cx;
      ++ref.start[cell_of[i] + 1];
    }
    for (size_t c = 1; c < ref.start.size(); ++c) ref.start[c] += ref.start[c - 1];
    ref.order.resize(ref.points.size());
    std::vector<int> fill(ref.start.begin(), ref.start.end() - 1);
    for (size_t i = 0; i < ref.points.size(); ++i) ref.order[fill[cell_of[i]]++] = static_cast<int>(i);
  }
  ref_ = std::move(ref);
  has_reference_ = true;
  ++stats_.references;
}

int ScanOdometry::Nearest(const Vec2& q, double max_d, double* e) const {
  if (ref_.nx == 0) return -1;
  const double fx = (q.x() - ref_.x0) / ref_.cell, fy = (q.y() - ref_.y0) / ref_.cell;
  const int reach = static_cast<int>(std::ceil(max_d / ref_.cell));
  if (!(fx > -reach - 1 && fy > -reach - 1 && fx < ref_.nx + reach && fy < ref_.ny + reach)) return -1;  // also NaN
  const int cx = static_cast<int>(std::floor(fx)), cy = static_cast<int>(std::floor(fy));
  int best = -1;
  double best_d2 = max_d * max_d;
  for (int y = std::max(0, cy - reach); y <= std::min(ref_.ny - 1, cy + reach); ++y)
    for (int x = std::max(0, cx - reach); x <= std::min(ref_.nx - 1, cx + reach); ++x) {
      const int c = y * ref_.nx + x;
      for (int k = ref_.start[c]; k < ref_.start[c + 1]; ++k) {
        const int i = ref_.order[k];
        const double d2 = (ref_.points[i] - q).squaredNorm();
        if (d2 < best_d2 || (d2 == best_d2 && i < best)) {
          best_d2 = d2;
          best = i;
        }
      }
    }
  if (best < 0) return -1;
  // Only on the point's own piece of line: a point beyond the end of the
  // reference's surface (a corridor wall seen farther on, at the range's
  // limit) would pull along the line by whatever tilt its normal has.
  const Vec2 d = q - ref_.points[best];
  const Vec2& n = ref_.normals[best];
  if (std::abs(n.x() * d.y() - n.y() * d.x()) > 0.5 * o_.neighbour_m) return -1;
  *e = n.dot(d);
  return best;
}

Pose2 ScanOdometry::Correct(const Pose2& odom, const std::vector<sensors::RangeReading>& ranges) {
  if (!has_laser_) return odom;
  if (!started_) {
    started_ = true;
    last_odom_ = odom;
    last_corrected_ = odom;
  }
  // The wheels' motion since the last record, from its corrected pose.
  const Pose2 predicted = last_corrected_ * (last_odom_.inverse() * odom);
  last_odom_ = odom;
  last_corrected_ = predicted;
  std::vector<Vec2> points = ScanPoints(ranges);
  if (points.empty()) return predicted;
  ++stats_.scans;
  const std::vector<Vec2> normals = Normals(points);
  if (!has_reference_) {
    last_scan_odom_ = odom;
    if (static_cast<int>(points.size()) >= o_.min_matches) MakeReference(points, normals, predicted, odom);
    return predicted;
  }
  // The scan's pose in the reference's frame: the guess (the last scan's
  // pose and the wheels' motion since), and the prior's sigmas from that
  // motion: what the wheels can have got wrong since the last scan.
  const Pose2 guess = ref_.corrected.inverse() * predicted;
  const Pose2 wheels = last_scan_odom_.inverse() * odom;
  last_scan_odom_ = odom;
  const double dist = std::hypot(wheels.x, wheels.y), turn = std::abs(wheels.theta);
  stats_.spacing_sum_m += dist;
  const double sxy = o_.prior_xy_m + o_.prior_xy_per_m * dist;
  const double sth = o_.prior_theta_rad + o_.prior_theta_per_rad * turn + o_.prior_theta_per_m * dist;
  const Eigen::Vector3d prior_info(1.0 / (sxy * sxy), 1.0 / (sxy * sxy), 1.0 / (sth * sth));
  const double w_point = 1.0 / (o_.point_sigma_m * o_.point_sigma_m);
  Eigen::Vector3d T(guess.x, guess.y, guess.theta);
  double lever = 0.0;
  for (const Vec2& p : points) lever += p.squaredNorm();
  lever = std::max(0.1, std::sqrt(lever / points.size()));
  int matches = 0;
  double sum_e2 = 0.0;
  const double min_normal_cos = std::cos(o_.max_normal_angle_rad);
  for (int it = 0; it < o_.iterations; ++it) {
    const double frac = o_.iterations > 1 ? static_cast<double>(it) / (o_.iterations - 1) : 1.0;
    const double max_d = o_.max_correspondence_m + frac * (o_.final_correspondence_m - o_.max_correspondence_m);
    const double c = std::cos(T(2)), s = std::sin(T(2));
    Eigen::Matrix3d Hd = Eigen::Matrix3d::Zero();
    Eigen::Vector3d gd = Eigen::Vector3d::Zero();
    matches = 0;
    sum_e2 = 0.0;
    auto turned = [c, s](const Vec2& v) { return Vec2(c * v.x() - s * v.y(), s * v.x() + c * v.y()); };
    for (size_t i = 0; i < points.size(); ++i) {
      const Vec2 rp = turned(points[i]);
      const Vec2 q(rp.x() + T(0), rp.y() + T(1));
      double e = 0.0;
      const int k = Nearest(q, max_d, &e);
      if (k < 0) continue;
      const Vec2& n = ref_.normals[k];
      // A point on a surface of its own that faces another way than the
      // reference's is on another surface (through a door, the wall beside
      // the robot taken for the corridor's wall seen edge-on at the side of
      // the reference's view): it would measure the motion along its own
      // surface as none.
      const Vec2& own = normals[i];
      if (own != Vec2(0.0, 0.0) && std::abs(n.dot(turned(own))) < min_normal_cos) continue;
      const Eigen::Vector3d J(n.x(), n.y(), n.x() * -rp.y() + n.y() * rp.x());
      const double w = (std::abs(e) <= o_.huber_m ? 1.0 : o_.huber_m / std::abs(e)) * w_point;
      Hd += w * J * J.transpose();
      gd += w * J * e;
      sum_e2 += e * e;
      ++matches;
    }
    // What the scan tells, direction by direction (the heading scaled by the
    // returns' rms range, so that all three are in metres): a direction
    // whose information is under degenerate_ratio of the best one's is left
    // to the prior. Along a corridor the range noise tilts the returns'
    // lines by a degree or two, and that tilt alone "measures" the motion
    // along it as none (the scans slid back onto the reference: a 20 m
    // corridor driven read as 2.6 m at 3 cm of noise).
    const Eigen::Vector3d scale(1.0, 1.0, 1.0 / lever);
    const Eigen::Matrix3d Hs = scale.asDiagonal() * Hd * scale.asDiagonal();
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> es(Hs);
    const double top = es.eigenvalues()(2);
    Eigen::Matrix3d P = Eigen::Matrix3d::Zero();
    for (int i = 0; i < 3; ++i)
      if (top > 0.0 && es.eigenvalues()(i) >= o_.degenerate_ratio * top)
        P += es.eigenvectors().col(i) * es.eigenvectors().col(i).transpose();
    // Back to (x, y, theta): the projector on the determined directions.
    const Eigen::Matrix3d Pm = scale.asDiagonal() * P * scale.cwiseInverse().asDiagonal();
    Eigen::Matrix3d H = Pm.transpose() * Hd * Pm;
    H.diagonal() += prior_info;
    const Eigen::Vector3d g = Pm.transpose() * gd +
                              prior_info.cwiseProduct(Eigen::Vector3d(T(0) - guess.x, T(1) - guess.y,
                                                                      NormalizeAngle(T(2) - guess.theta)));
    const Eigen::Vector3d dx = -H.ldlt().solve(g);
    if (!dx.allFinite()) break;
    T += dx;
    // Settled: straight on to the last iteration's radius (the shrinking
    // radius only keeps far correspondences out once the scan is near).
    if (dx.head<2>().norm() < 1e-4 && std::abs(dx(2)) < 1e-5) {
      if (frac >= 1.0) break;
      it = std::max(it, o_.iterations - 2);
    }
  }
  // A match that moved the scan farther from the wheels' guess than their
  // uncertainty allows (chi^2 of 3 dof at 0.999 under the prior) found
  // another surface, not this one: the wheels are kept (aria/office: a
  // scan at a door slid 0.19 m while the wheels erred by 3 mm).
  const Eigen::Vector3d moved(T(0) - guess.x, T(1) - guess.y, NormalizeAngle(T(2) - guess.theta));
  const bool consistent = moved.dot(prior_info.cwiseProduct(moved)) <= 16.27;
  if (!consistent) ++stats_.rejected;
  const bool matched = consistent && matches >= o_.min_matches &&
                       matches >= o_.min_match_fraction * static_cast<double>(points.size()) && T.allFinite();
  Pose2 corrected = predicted;
  if (matched) {
    corrected = ref_.corrected * Pose2{T(0), T(1), NormalizeAngle(T(2))};
    ++stats_.matched;
    stats_.rmse_sum_m += std::sqrt(sum_e2 / matches);
  }
  last_corrected_ = corrected;
  const Pose2 rel = ref_.corrected.inverse() * corrected;
  if (!matched || std::hypot(rel.x, rel.y) > o_.reference_m || std::abs(rel.theta) > o_.reference_rad) {
    if (static_cast<int>(points.size()) >= o_.min_matches) MakeReference(points, normals, corrected, odom);
  }
  return corrected;
}

}  // namespace cogmap::localize
