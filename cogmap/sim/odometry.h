#pragma once
#include <random>

#include "cogmap/core/pose2.h"

namespace cogmap::sim {

// Wheel odometry errors. Noise is drawn per motion increment with a variance
// proportional to the increment, so that the statistics do not depend on the
// simulation step: after travelling d metres in a straight line the heading
// error has mean drift_rad_per_m * d and standard deviation
// heading_sigma_rad_per_sqrt_m * sqrt(d); the distance error has mean
// scale_error * d and standard deviation trans_sigma_m_per_sqrt_m * sqrt(d).
// Defaults: a Pioneer on a hard floor (about 1 % distance error, about one
// degree of heading error per 10 m); the drift is what the EM of SPEC 5
// corrects (raise it with `cogmap simulate --drift-deg-per-m`).
struct OdometryNoiseOptions {
  double trans_sigma_m_per_sqrt_m = 0.01;        // 1 cm after 1 m
  double rot_sigma_rad_per_sqrt_rad = 0.005;     // turning: 0.3 deg after one radian
  double heading_sigma_rad_per_sqrt_m = 0.003;   // 0.17 deg after 1 m driven
  double drift_rad_per_m = 0.0017453292519943;   // 0.1 deg per metre, CCW (systematic)
  double scale_error = 0.01;                     // odometry reads 1 % long
};

// Dead reckoning fed with the true motion increments.
class OdometryModel {
 public:
  OdometryModel(const Pose2& start, const OdometryNoiseOptions& options)
      : odom_(start), options_(options) {}

  // The robot truly moved 'trans_m' along its heading and turned 'rot_rad'
  // (in that step, the turn split half before, half after the translation).
  void Step(double trans_m, double rot_rad, std::mt19937_64& rng);

  const Pose2& pose() const { return odom_; }
  double distance_m() const { return distance_m_; }

 private:
  Pose2 odom_;
  OdometryNoiseOptions options_;
  double distance_m_ = 0.0;
  std::normal_distribution<double> gauss_{0.0, 1.0};
};

}  // namespace cogmap::sim
