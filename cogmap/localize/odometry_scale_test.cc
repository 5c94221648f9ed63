#include "cogmap/localize/odometry_scale.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

namespace cogmap::localize {
namespace {

// A ring's four sensors that matter: the +-10 degree pair ahead, one each
// side. Sonars of 30 degrees, 5 m.
sensors::RobotDescription Ring(bool with_sides = true, bool with_pair = true) {
  sensors::RobotDescription r;
  r.name = "test-ring";
  auto add = [&](double x, double y, double deg) {
    sensors::RangeSensor s;
    s.robot_from_sensor = {x, y, DegToRad(deg)};
    r.sensors.push_back(s);
  };
  add(0.115, 0.13, 10.0);
  if (with_pair) add(0.115, -0.13, -10.0);
  if (with_sides) {
    add(0.0, 0.14, 90.0);
    add(0.0, -0.14, -90.0);
  }
  return r;
}

// Legs of straight driving in a corridor 3 m wide (walls y = +-1.5 in the
// leg's frame) towards a wall square to it at x = 6, from x = 1.5 to x =
// 5.2, the robot's way turned by 'slant_deg' from the corridor's axis. The
// wheels read every distance 'odometry_over_truth' times the true one; the
// sonars see the perpendicular distance to each wall (its normal lies in
// their cones), with 1 cm of noise. A gap in the log between legs.
void DriveLegs(OdometryScaleEstimator* est, const sensors::RobotDescription& robot, int legs, double odometry_over_truth,
               double slant_deg, unsigned seed = 5) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> noise(0.0, 0.01);
  const double a = DegToRad(slant_deg);
  double odo_x = 0.0, t = 0.0;
  for (int leg = 0; leg < legs; ++leg) {
    odo_x += 10.0;  // the gap: far beyond max_step_m
    for (double s = 0.0; s <= 3.7; s += 0.08) {
      const Vec2 truth(1.5 + s * std::cos(a), s * std::sin(a));
      sensors::LogRecord rec;
      rec.time_s = (t += 0.2);
      rec.odom = {odo_x + odometry_over_truth * s, 0.0, 0.0};
      for (int i = 0; i < static_cast<int>(robot.sensors.size()); ++i) {
        const sensors::RangeSensor& sensor = robot.sensors[i];
        // The transducer in the corridor's frame (the robot turned by a).
        const Vec2 m = sensor.robot_from_sensor.translation();
        const Vec2 p = truth + Vec2(std::cos(a) * m.x() - std::sin(a) * m.y(), std::sin(a) * m.x() + std::cos(a) * m.y());
        const double dir = sensor.robot_from_sensor.theta;
        double r = 0.0;
        if (std::abs(dir) < DegToRad(45)) r = 6.0 - p.x();
        else r = dir > 0 ? 1.5 - p.y() : p.y() + 1.5;
        rec.ranges.push_back({i, r + noise(rng)});
      }
      est->Add(rec);
    }
  }
  est->Finish();
}

TEST(OdometryScale, WheelsReadingTwoPercentLongAreMeasured) {
  const auto robot = Ring();
  OdometryScaleEstimator est(robot);
  DriveLegs(&est, robot, 8, 1.02, 0.0);
  const OdometryScaleEstimate e = est.Estimate();
  ASSERT_TRUE(e.valid);
  EXPECT_EQ(e.runs, 8);  // the pair's runs over one leg count once
  EXPECT_NEAR(e.scale, 1.0 / 1.02, 0.002);
  EXPECT_LT(std::abs(e.scale - 1.0 / 1.02), 3.0 * e.sigma);
  EXPECT_GT(e.sigma, 0.0);
}

// Driving at a slant, the wall ahead comes nearer by the cosine of it; the
// side wall's approach (its sine) gives it back.
TEST(OdometryScale, ASlantIsTakenFromTheSideWall) {
  const auto robot = Ring();
  OdometryScaleEstimator est(robot);
  DriveLegs(&est, robot, 8, 1.0, 4.0);
  const OdometryScaleEstimate e = est.Estimate();
  ASSERT_TRUE(e.valid);
  EXPECT_NEAR(e.scale, 1.0, 0.002);  // the wall ahead alone: cos(4 deg) = 0.9976
  for (const auto& r : est.runs()) EXPECT_NEAR(std::abs(r.side_slope), std::sin(DegToRad(4.0)), 0.01);
}

// A slant beyond what the side wall vouches for (6.9 degrees: its slope
// 0.12) is not used; nor is a sonar run without a side wall, or one that no
// second sonar confirms.
TEST(OdometryScale, RunsTheRingCannotVouchForAreLeftOut) {
  {
    const auto robot = Ring();
    OdometryScaleEstimator est(robot);
    DriveLegs(&est, robot, 8, 1.0, 6.9);
    EXPECT_EQ(est.runs().size(), 0u);
    EXPECT_FALSE(est.Estimate().valid);
  }
  {
    const auto robot = Ring(/*with_sides=*/false);
    OdometryScaleEstimator est(robot);
    DriveLegs(&est, robot, 8, 1.02, 0.0);
    EXPECT_FALSE(est.Estimate().valid);
  }
  {
    const auto robot = Ring(true, /*with_pair=*/false);
    OdometryScaleEstimator est(robot);
    DriveLegs(&est, robot, 8, 1.02, 0.0);
    EXPECT_EQ(est.runs().size(), 8u);  // runs, but unconfirmed
    EXPECT_EQ(est.Estimate().runs, 0);
    EXPECT_FALSE(est.Estimate().valid);
  }
}

TEST(OdometryScale, FewRunsAreNoEstimate) {
  const auto robot = Ring();
  OdometryScaleEstimator est(robot);
  DriveLegs(&est, robot, 4, 1.02, 0.0);
  EXPECT_EQ(est.Estimate().runs, 4);
  EXPECT_FALSE(est.Estimate().valid);
  EXPECT_EQ(ShrunkScale(est.Estimate(), 0.01), 1.0);
}

TEST(OdometryScale, ShrunkTowardsOneByItsEvidence) {
  OdometryScaleEstimate e;
  e.valid = true;
  e.scale = 0.98;
  e.sigma = 0.001;  // 20 sigma from 1: surely off, shrunk by its noise alone
  EXPECT_NEAR(ShrunkScale(e, 0.01), 1.0 - 0.02 * 100.0 / 101.0, 1e-9);
  // Without the calibrated hypothesis: the Gaussian posterior mean.
  e.sigma = 0.01;
  EXPECT_NEAR(ShrunkScale(e, 0.01, 0.0), 0.99, 1e-12);
  // With it, one sigma from 1 and as noisy as the prior: the odds are
  // sqrt(1/2) exp(1/4) = 0.908 for "off", so 0.476 of the way to 0.99.
  e.scale = 0.99;
  const double odds = std::sqrt(0.5) * std::exp(0.25);
  EXPECT_NEAR(ShrunkScale(e, 0.01), 1.0 - 0.005 * odds / (odds + 1.0), 1e-12);
  EXPECT_GT(ShrunkScale(e, 0.01), 0.9975);
  e.valid = false;
  EXPECT_EQ(ShrunkScale(e, 0.01), 1.0);
}

TEST(DistanceScaler, ScalesDisplacementsFromWhereTheScaleChanged) {
  DistanceScaler d;
  const Pose2 a{1.0, 2.0, 0.3};
  const Pose2 out = d.Apply(a);
  EXPECT_EQ(out.x, 1.0);  // scale 1: exactly as it came
  EXPECT_EQ(d.Apply({3.0, 2.0, 0.1}).x, 3.0);
  d.SetScale(0.5);
  const Pose2 b = d.Apply({5.0, 4.0, -0.2});  // 0.5 x (2, 2) from (3, 2)
  EXPECT_NEAR(b.x, 4.0, 1e-12);
  EXPECT_NEAR(b.y, 3.0, 1e-12);
  EXPECT_EQ(b.theta, -0.2);  // headings as they came
  d.SetScale(2.0);
  const Pose2 c = d.Apply({6.0, 4.0, 0.0});  // 2 x (1, 0) from (4, 3)
  EXPECT_NEAR(c.x, 6.0, 1e-12);
  EXPECT_NEAR(c.y, 3.0, 1e-12);
}

}  // namespace
}  // namespace cogmap::localize
