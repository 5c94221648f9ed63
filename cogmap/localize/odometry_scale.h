#pragma once
// The odometry's distance scale, measured by the range sensors: while the
// robot drives straight towards (or away from) a wall, a sensor looking
// along the way sees the wall come nearer by the distance truly driven, and
// the odometry says how far it thinks it drove. The ratio over many such
// runs is the scale (true distance / odometry distance). No wall, no
// pose graph and no map enter it: only the readings of sensors looking
// along the way and the odometry between them (docs/pose-graph.md,
// "Distance scale").
#include <vector>

#include "cogmap/sensors/reading.h"
#include "cogmap/sensors/robot.h"

namespace cogmap::localize {

struct OdometryScaleOptions {
  // A sensor takes part when its axis lies within this of straight ahead or
  // straight behind the robot. Within it, a sonar's echo from a wall facing
  // the robot comes from the foot of the perpendicular (within its cone),
  // a laser beam's from a point the robot drives towards.
  double max_axis_rad = 0.1920;  // 11 degrees: the Pioneer's +-10 degree pair
  // A laser's beams take part only when asked: a laser robot's odometry is
  // the scan matcher's (localize::ScanOdometry measures the distance along
  // the way from the scans, wherever they can tell it), and beams within a
  // degree of the way read the scan-matched odometry of the random
  // buildings 0.3-1 % short (far walls met at a grazing angle, whose range
  // swings with the robot's wobble): 14 of 80 laser runs ended worse than
  // their odometry, 1 before (docs/BENCHMARKS.md, "Distance scale"). A laser beam (narrow)
  // must point along the way more tightly: its range falls by the distance
  // driven only along its own ray.
  bool lasers_too = false;
  double max_laser_axis_rad = 0.0175;  // 1 degree
  // A run ends when the odometry's heading has turned more than this since
  // its first reading (the robot no longer drives straight).
  double max_turn_rad = 0.1396;  // 8 degrees
  // A reading continues its run when it lies within this of the run's
  // last reading moved by the odometry's distance (the same wall).
  double max_jump_m = 0.06;
  double max_jump_per_m = 0.05;
  // A run counts when it spans this much travel and holds this many
  // readings, and its readings scatter about their line by at most this.
  double min_run_m = 1.0;
  int min_readings = 6;
  double max_rms_m = 0.04;
  // Readings this close to the sensor's max range (a fraction of it) or
  // beyond it are no echo.
  double max_range_fraction = 0.95;
  // A sonar's echo comes from the nearest point of the wall in its cone,
  // the foot of the perpendicular: it approaches by the distance driven
  // times the cosine of the angle between the way and the wall's normal,
  // which a robot crossing a room at a slant makes up to 10 % short. A
  // sonar's run counts only with a side wall seen over it (a sensor within
  // max_axis_rad of square to the way, readings spanning side_cover of the
  // run): the side wall's own approach is the sine of that angle, and the
  // two together give the distance (the wall ahead square to the side
  // walls, as in rectilinear buildings). A laser beam along the way needs
  // none.
  double side_cover = 0.6;
  // ... and a side wall no steeper than this (a slant of at most 5.7
  // degrees: the side sonar sees a wall along the way, not the wall ahead
  // entering its cone near a corner).
  double max_side_slope = 0.1;
  int side_min_readings = 4;
  // A sonar's run counts only when another sonar looking the same way ran
  // over the same stretch at the same range (within this, at the middle of
  // their overlap): the echo then lies where both cones overlap (for the
  // Pioneer's +-10 degree pair, within 5 degrees of the way), not on a
  // post or a table's corner off to the side, whose range falls by the
  // cosine of its bearing, nor on a wall at a slant.
  double pair_tolerance_m = 0.05;
  // The odometry's steps between readings: a run breaks at a step longer
  // than this (a gap in the log) or one that reverses the robot's motion.
  double max_step_m = 2.0;
  // Runs differ by more than their readings' noise: a slant the side wall
  // cannot show, a turn of up to max_turn_rad, a wall not quite square. Each
  // run's scale is taken as uncertain by at least this much between runs.
  double run_sigma_floor = 0.01;
};

struct OdometryScaleRun {
  int sensor = 0;
  int look = 0;           // +1: the sensor looks ahead, -1: behind
  double s_begin = 0.0, s_end = 0.0;  // the run on the odometry's distance driven
  double travel_m = 0.0;  // odometry distance the run spans
  int readings = 0;
  double scale = 1.0;     // the wall's approach over the odometry's distance
  double sigma = 0.0;     // its standard error from the readings' scatter
  double rms_m = 0.0;
  double side_slope = 0.0;  // sonar: the side wall's approach per metre driven (the slant's sine)
  bool sonar = false;
  double line_s = 0.0, line_r = 0.0, line_slope = 0.0;  // the fitted line: r = line_r + line_slope (s - line_s)
};

struct OdometryScaleEstimate {
  bool valid = false;     // at least min_runs runs
  double scale = 1.0;     // true distance / odometry distance
  double sigma = 0.0;     // 1-sigma of 'scale', from the runs' spread
  int runs = 0;           // independent runs: the runs of sensors looking the same way over the same stretch count once
  double travel_m = 0.0;  // odometry distance the runs span, summed
};

// Fed with a run's records in order; Estimate() at any time.
class OdometryScaleEstimator {
 public:
  OdometryScaleEstimator(const sensors::RobotDescription& robot, const OdometryScaleOptions& options = {});
  void Add(const sensors::LogRecord& record);
  // Closes the open runs (end of the log).
  void Finish();
  OdometryScaleEstimate Estimate(int min_runs = 5) const;
  const std::vector<OdometryScaleRun>& runs() const { return runs_; }

 private:
  struct Point {
    double s, r;
  };
  struct Open {
    std::vector<Point> points;
    double theta0 = 0.0;
  };
  void Close(int sensor);
  // The best-determined side wall over [s0, s1]: its slope and standard
  // error; false when no side sensor saw one wall over it.
  bool SideSlope(double s0, double s1, double* slope, double* sigma) const;

  sensors::RobotDescription robot_;
  OdometryScaleOptions options_;
  std::vector<int> along_;  // per sensor: +1 ahead, -1 behind, 0 not used
  std::vector<Open> open_;
  std::vector<char> side_;               // per sensor: square to the way
  std::vector<std::vector<Point>> seen_;  // side sensors' recent echoes
  std::vector<OdometryScaleRun> runs_;
  bool have_last_ = false;
  Pose2 last_;
  double s_ = 0.0;  // signed odometry distance driven (forward positive)
  double theta_ = 0.0;  // unwrapped odometry heading
  int direction_ = 0;   // sign of the last step
};

// The odometry re-integrated with a distance scale that may change as the
// run goes on: each position is the last one at which the scale changed plus
// the scale times the odometry's displacement since; headings are kept.
// Scale 1 from the start: the poses as they come.
class DistanceScaler {
 public:
  Pose2 Apply(const Pose2& raw);
  // From the next pose on (continuous: the pose before it stays where it was).
  void SetScale(double scale);
  double scale() const { return scale_; }

 private:
  bool have_ = false;
  bool identity_ = true;  // scale 1 so far: poses pass through unchanged
  double scale_ = 1.0;
  Vec2 anchor_raw_{0, 0}, anchor_scaled_{0, 0};
  Vec2 last_raw_{0, 0}, last_scaled_{0, 0};
};

// The scale to drive with, given an estimate: its posterior mean under a
// prior that a robot is either calibrated (scale 1, with probability
// prior_calibrated) or off by N(0, prior_sigma^2) (a wheel's diameter and
// tyres: wheel odometry reads within a percent or two), so that an
// estimate within its own noise of 1 (a calibrated robot measured by a few
// runs) moves the odometry little, and a clear one nearly all the way.
// 1 while the estimate is not valid.
double ShrunkScale(const OdometryScaleEstimate& e, double prior_sigma, double prior_calibrated = 0.5);

// The runs of sensors looking the same way over overlapping stretches of the
// way (a laser's neighbouring beams, a ring's two forward transducers) are
// one wall's approach: a group of sonar runs counts only when two of its
// sensors agree on the range (pair_tolerance_m), and each group counts once, at its members' mean
// scale and its best member's sigma. Then the groups' weighted mean, each
// weighted by its own variance plus the spread between groups (a random-
// effects mean: groups differ by more than their readings' noise, by how
// squarely the wall faced the robot), and its standard error.
OdometryScaleEstimate CombineScaleRuns(const std::vector<OdometryScaleRun>& runs, int min_runs = 5,
                                       double run_sigma_floor = 0.0, double pair_tolerance_m = 0.05);

}  // namespace cogmap::localize
