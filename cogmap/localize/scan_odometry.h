#pragma once
// Laser odometry: each scan of a planar laser matched against a reference
// scan (point-to-line ICP with the wheel odometry as its prior), so that the
// rooms are mapped on poses whose heading and translation come from the
// scans where the scans determine them and from the wheels where they do not
// (a corridor's length). `cogmap map --scan-match` (docs/inputs.md, "Laser
// odometry").
#include <vector>

#include "cogmap/core/pose2.h"
#include "cogmap/sensors/reading.h"
#include "cogmap/sensors/robot.h"

namespace cogmap::localize {

struct ScanOdometryOptions {
  // A scan becomes the reference for the next ones once it lies this far
  // (or turned this much) from the current reference, or when it could not
  // be matched: every scan in between is matched to the same reference, so
  // the error accumulates per reference, not per scan.
  double reference_m = 0.5;
  double reference_rad = 0.26;  // 15 degrees
  // Returns farther than this take no part (their angular error grows with
  // range, and a laser's far returns are sparse).
  double max_point_range_m = 20.0;
  // Returns of nearby beams at most this far from a reference point lie on
  // its surface: the point's local line (its normal) is fitted to them.
  double neighbour_m = 0.3;
  int line_beams = 200;  // ... of at most this many beams either side (a bound on the work)
  // Correspondences within this distance, shrinking linearly from the first
  // to the last iteration.
  double max_correspondence_m = 0.5;
  // A return whose own line (Normals) is turned by more than this from the
  // line of the reference return nearest to it is not matched to it. Scans
  // 0.5 m apart see a surface turned by the match's rotation alone (a few
  // degrees); a pair further apart lies on two surfaces (a corner, a jamb).
  double max_normal_angle_rad = 0.785398163397448;  // 45 degrees
  double final_correspondence_m = 0.15;
  int iterations = 20;
  // Residuals beyond this weigh less (Huber).
  double huber_m = 0.05;
  // The returns' scatter about their surface (range noise and the surface's
  // roughness), metres: each matched point's sigma.
  double point_sigma_m = 0.03;
  // A direction of the pose the scan determines with less than this part of
  // the information of its best-determined one is left to the prior.
  double degenerate_ratio = 0.01;
  // A match is used when at least this many points, and this part of the
  // scan's usable points, found a surface; else the odometry is kept.
  int min_matches = 30;
  double min_match_fraction = 0.3;
  // The prior: the wheels' motion since the last scan (from that scan's
  // corrected pose), with sigma xy_m + xy_per_m x distance in x and y and
  // theta_rad + theta_per_rad x turn + theta_per_m x distance in heading
  // (a drift of up to 3 degrees per metre passes). It holds what the scan
  // cannot tell (the length of a corridor, a scan of one wall) and gates a
  // match that slid onto another surface.
  double prior_xy_m = 0.02;
  double prior_xy_per_m = 0.1;
  double prior_theta_rad = 0.0087;     // 0.5 degrees
  double prior_theta_per_rad = 0.1;
  double prior_theta_per_m = 0.05;     // about 3 degrees per metre
};

struct ScanOdometryStats {
  long scans = 0;       // records with laser returns
  long matched = 0;     // of them, placed by the scan match
  long references = 0;  // reference scans taken
  long rejected = 0;    // matches farther from the wheels than their uncertainty allows (wheels kept)
  double rmse_sum_m = 0.0;  // of the matched scans' residuals, summed (mean: / matched)
  double spacing_sum_m = 0.0;  // the wheels' distance between consecutive scans, summed (mean: / (scans - 1))
  double MeanSpacing() const { return scans > 1 ? spacing_sum_m / (scans - 1) : 0.0; }
};

// Are a log's laser scans dense enough for ScanOdometry (`cogmap map`'s
// default, `--scan-match` auto)? Each gap between consecutive scans (the
// wheels' motion) in units of the reference's spacing: its travel over
// reference_m or its turn over reference_rad, the larger. Dense when the
// mean over the first `gaps` gaps is at most 1: a scan farther from the
// last is matched against it alone, with less overlap (the CARMEN logs,
// 0.55-0.83 m and up to 30 degrees apart: worse than their odometry).
class ScanDensity {
 public:
  explicit ScanDensity(const sensors::RobotDescription& robot, ScanOdometryOptions options = {}, int gaps = 10);
  // One record, in the log's order: counted when it has laser returns.
  // Returns decided().
  bool Add(const Pose2& odom, const std::vector<sensors::RangeReading>& ranges);
  bool decided() const { return gaps_ >= want_; }
  bool dense() const { return gaps_ > 0 && mean_step() <= 1.0; }
  double mean_step() const { return gaps_ > 0 ? steps_ / gaps_ : 0.0; }
  int gaps() const { return gaps_; }

 private:
  sensors::RobotDescription robot_;
  ScanOdometryOptions o_;
  int want_ = 10, gaps_ = 0;
  double steps_ = 0.0;
  bool have_last_ = false;
  Pose2 last_;
};

// True when the robot has at least one laser beam (SensorKind::kLaser).
bool HasLaser(const sensors::RobotDescription& robot);

// The laser beam that took reading r when it is a return (a laser's, in
// [min_range_m, max_range_m)), else null.
const sensors::RangeSensor* LaserReturn(const sensors::RobotDescription& robot, const sensors::RangeReading& r);

class ScanOdometry {
 public:
  // The robot's laser beams (SensorKind::kLaser) are used; a robot with none
  // gets the odometry back unchanged.
  explicit ScanOdometry(sensors::RobotDescription robot, ScanOdometryOptions options = {});

  // The corrected pose of a record at wheel-odometry pose 'odom' with these
  // readings (called in the log's order). The first record keeps its pose.
  Pose2 Correct(const Pose2& odom, const std::vector<sensors::RangeReading>& ranges);

  const ScanOdometryStats& stats() const { return stats_; }

 private:
  // What scans are matched against: the reference scan's returns that have
  // a line, in its frame.
  struct Reference {
    std::vector<Vec2> points, normals;
    // The points by cell of a grid over their bounding box (cells of the
    // first correspondence radius): cell c's points are
    // order[start[c] .. start[c + 1]).
    double cell = 0.5;
    double x0 = 0.0, y0 = 0.0;
    int nx = 0, ny = 0;
    std::vector<int> start, order;
    Pose2 corrected, odom;  // the reference scan's poses
  };
  // Each return's normal (robot frame) where it lies on a line, else (0, 0).
  std::vector<Vec2> Normals(const std::vector<Vec2>& points) const;
  // A scan's returns in the robot frame, in beam order (lasers only, within range).
  std::vector<Vec2> ScanPoints(const std::vector<sensors::RangeReading>& ranges) const;
  void MakeReference(const std::vector<Vec2>& points, const std::vector<Vec2>& normals, const Pose2& corrected,
                     const Pose2& odom);
  int Nearest(const Vec2& q, double max_d, double* e) const;  // index into ref_.points, or -1

  sensors::RobotDescription robot_;
  ScanOdometryOptions o_;
  bool has_laser_ = false;
  bool started_ = false;
  bool has_reference_ = false;
  Reference ref_;
  Pose2 last_odom_, last_corrected_, last_scan_odom_;
  ScanOdometryStats stats_;
};

}  // namespace cogmap::localize
