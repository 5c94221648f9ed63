#include "cogmap/sim/sensor_model.h"

#include <gtest/gtest.h>

#include "cogmap/core/angles.h"

namespace cogmap::sim {
namespace {

// A single long wall along x = 3.
World Wall() { return World({{{3, -50}, {3, 50}}}); }

sensors::RangeSensor Sonar() {
  sensors::RangeSensor s;
  s.beam_width_rad = DegToRad(30);
  s.min_range_m = 0.15;
  s.max_range_m = 5.0;
  return s;
}

SensorModelOptions Noiseless() {
  SensorModelOptions o;
  o.sonar_range_sigma_m = 0;
  o.sonar_range_sigma_frac = 0;
  o.sonar_crosstalk_probability = 0;
  o.sonar_multipath_probability = 0;
  return o;
}

TEST(SensorModel, DefaultsLockedToDocumentedValues) {
  const SensorModelOptions o;
  EXPECT_EQ(o.sonar_rays, 5);
  EXPECT_NEAR(o.sonar_critical_angle_rad, DegToRad(60), 1e-12);
  EXPECT_DOUBLE_EQ(o.sonar_range_sigma_frac, 0.01);
}

TEST(SensorModel, NormalIncidenceEchoesAtWallDistance) {
  std::mt19937_64 rng(1);
  const double r = SimulateReading(Wall(), Pose2{0, 0, 0}, Sonar(), Noiseless(), rng);
  EXPECT_NEAR(r, 3.0, 1e-12);
}

TEST(SensorModel, NearestRayOfConeWins) {
  // Sonar axis 15 degrees off the wall's normal; of the rays at 0, 15 and 30
  // degrees the one along the normal is the shortest: 3 m.
  std::mt19937_64 rng(1);
  SensorModelOptions o = Noiseless();
  o.sonar_rays = 3;
  const double r = SimulateReading(Wall(), Pose2{0, 0, DegToRad(15)}, Sonar(), o, rng);
  EXPECT_NEAR(r, 3.0, 1e-9);
}

TEST(SensorModel, GrazingWallGivesNoEcho) {
  // Axis 80 degrees from the normal: even the nearest ray (65 degrees) is past
  // the 60 degree critical angle, so the pulse is reflected away.
  std::mt19937_64 rng(1);
  const double r = SimulateReading(Wall(), Pose2{0, 0, DegToRad(80)}, Sonar(), Noiseless(), rng);
  EXPECT_DOUBLE_EQ(r, 5.0);
}

TEST(SensorModel, SpecularRayReturnsMultipathViaSecondWall) {
  // Wall A along x = 1 met 70 degrees from its normal; the mirrored ray meets
  // wall B (y = 4) 20 degrees from its normal, within the critical angle, so
  // the reading is the path length d1 + d2.
  const World world({{{1, -10}, {1, 10}}, {{-10, 4}, {10, 4}}});
  const double h = DegToRad(70);
  const double d1 = 1.0 / std::cos(h);
  const Vec2 p = Vec2(1.0, std::tan(h));
  const double d2 = (4.0 - p.y()) / std::sin(h);
  EXPECT_NEAR(SonarRayEcho(world, {0, 0}, h, 20.0, DegToRad(60), true), d1 + d2, 1e-6);
  EXPECT_LT(SonarRayEcho(world, {0, 0}, h, 20.0, DegToRad(60), false), 0.0);
}

TEST(SensorModel, LaserSeesGrazingWall) {
  std::mt19937_64 rng(1);
  sensors::RangeSensor s;
  s.kind = sensors::SensorKind::kLaser;
  s.max_range_m = 20;
  s.min_range_m = 0.02;
  SensorModelOptions o;
  o.laser_range_sigma_m = 0;
  const double r = SimulateReading(Wall(), Pose2{0, 0, DegToRad(80)}, s, o, rng);
  EXPECT_NEAR(r, 3.0 / std::cos(DegToRad(80)), 1e-9);
}

TEST(SensorModel, RangeNoiseHasConfiguredSpread) {
  std::mt19937_64 rng(3);
  SensorModelOptions o = Noiseless();
  o.sonar_range_sigma_m = 0.02;
  o.sonar_range_sigma_frac = 0.01;  // sigma = 0.02 + 0.03 = 0.05
  double sum = 0, sum2 = 0;
  const int n = 20000;
  for (int i = 0; i < n; ++i) {
    const double r = SimulateReading(Wall(), Pose2{0, 0, 0}, Sonar(), o, rng) - 3.0;
    sum += r;
    sum2 += r * r;
  }
  EXPECT_NEAR(sum / n, 0.0, 0.002);
  EXPECT_NEAR(std::sqrt(sum2 / n), 0.05, 0.002);
}

TEST(SensorModel, CrosstalkGivesShortOutliersAtConfiguredRate) {
  std::mt19937_64 rng(5);
  SensorModelOptions o = Noiseless();
  o.sonar_crosstalk_probability = 0.1;
  int short_count = 0;
  const int n = 20000;
  for (int i = 0; i < n; ++i)
    if (SimulateReading(Wall(), Pose2{0, 0, 0}, Sonar(), o, rng) < 2.999) ++short_count;
  EXPECT_NEAR(static_cast<double>(short_count) / n, 0.1, 0.01);
}

}  // namespace
}  // namespace cogmap::sim
