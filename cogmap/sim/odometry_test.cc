#include "cogmap/sim/odometry.h"

#include <cmath>

#include <gtest/gtest.h>

#include "cogmap/core/angles.h"

namespace cogmap::sim {
namespace {

TEST(Odometry, NoiselessOdometryFollowsTruth) {
  OdometryNoiseOptions o{0, 0, 0, 0, 0};
  OdometryModel odo({1, 2, 0}, o);
  std::mt19937_64 rng(1);
  for (int i = 0; i < 100; ++i) odo.Step(0.01, 0.0, rng);
  odo.Step(0.0, kPi / 2, rng);
  for (int i = 0; i < 100; ++i) odo.Step(0.01, 0.0, rng);
  EXPECT_NEAR(odo.pose().x, 2.0, 1e-9);
  EXPECT_NEAR(odo.pose().y, 3.0, 1e-9);
  EXPECT_NEAR(odo.pose().theta, kPi / 2, 1e-12);
}

// Drives 10 m straight in 1 cm steps, many times; checks mean and spread of
// the heading and distance errors against the settings.
TEST(Odometry, NoiseStatisticsMatchSettings) {
  OdometryNoiseOptions o;
  o.trans_sigma_m_per_sqrt_m = 0.02;
  o.heading_sigma_rad_per_sqrt_m = 0.004;
  o.rot_sigma_rad_per_sqrt_rad = 0.0;
  o.drift_rad_per_m = DegToRad(1.0);
  o.scale_error = 0.02;
  std::mt19937_64 rng(42);
  const int runs = 400, steps = 1000;
  const double step = 0.01, d = steps * step;
  double sh = 0, sh2 = 0, sd = 0, sd2 = 0;
  for (int r = 0; r < runs; ++r) {
    OdometryModel odo({0, 0, 0}, o);
    double along = 0;  // distance measured along the odometry path
    for (int i = 0; i < steps; ++i) {
      const Pose2 before = odo.pose();
      odo.Step(step, 0.0, rng);
      along += (odo.pose().translation() - before.translation()).norm();
    }
    const double h = odo.pose().theta, e = along - d;
    sh += h;
    sh2 += h * h;
    sd += e;
    sd2 += e * e;
  }
  const double mh = sh / runs, vh = sh2 / runs - mh * mh;
  const double md = sd / runs, vd = sd2 / runs - md * md;
  EXPECT_NEAR(mh, DegToRad(1.0) * d, 0.0015);                 // 10 degrees of drift
  EXPECT_NEAR(std::sqrt(vh), 0.004 * std::sqrt(d), 0.0015);   // 0.0126 rad
  EXPECT_NEAR(md, 0.02 * d, 0.01);                            // 0.2 m long
  EXPECT_NEAR(std::sqrt(vd), 0.02 * std::sqrt(d), 0.01);      // 0.063 m
}

TEST(Odometry, RotationNoiseScalesWithTurn) {
  OdometryNoiseOptions o{0, 0.05, 0, 0, 0};
  std::mt19937_64 rng(9);
  double s2 = 0;
  const int runs = 2000;
  for (int r = 0; r < runs; ++r) {
    OdometryModel odo({0, 0, 0}, o);
    for (int i = 0; i < 100; ++i) odo.Step(0.0, 0.01, rng);  // one radian in total
    s2 += std::pow(odo.pose().theta - 1.0, 2);
  }
  EXPECT_NEAR(std::sqrt(s2 / runs), 0.05, 0.004);
}

TEST(Odometry, DefaultsLocked) {
  const OdometryNoiseOptions o;
  EXPECT_NEAR(o.drift_rad_per_m, DegToRad(0.1), 1e-12);
  EXPECT_DOUBLE_EQ(o.scale_error, 0.01);
  EXPECT_DOUBLE_EQ(o.trans_sigma_m_per_sqrt_m, 0.01);
}

}  // namespace
}  // namespace cogmap::sim
