#pragma once
#include <random>
#include <vector>

#include "cogmap/core/pose2.h"
#include "cogmap/sensors/robot.h"
#include "cogmap/sim/world.h"

namespace cogmap::sim {

// How the simulated sonars and lasers behave. Beam width, min and max range
// come from each sensor of the robot description (Polaroid 6500: 30 degrees,
// 0.15 m, 5 m; SPEC 1); everything else is here. See docs/simulator.md.
struct SensorModelOptions {
  // Sonar.
  int sonar_rays = 5;  // rays sampling each sonar cone; the nearest echo wins
  // Beyond this angle between a ray and the wall's normal the wall reflects
  // the pulse away (specular reflection). A smooth wall seen by a Polaroid
  // transducer returns an echo up to roughly 60-70 degrees from the normal
  // when the whole cone is considered; per ray we use 60 degrees.
  double sonar_critical_angle_rad = 1.0471975511965976;  // 60 degrees
  // A specularly reflected ray is traced one bounce further; if it then meets a
  // wall within the critical angle, the reading is the total path length (a long
  // multipath reading) with this probability, else no echo.
  double sonar_multipath_probability = 0.5;
  double sonar_range_sigma_m = 0.01;      // Gaussian range noise: sigma_m +
  double sonar_range_sigma_frac = 0.01;   //   frac * range (Polaroid: +-1 %)
  // An echo from another transducer's pulse: the reading is replaced by a
  // uniform range between min range and the true reading.
  double sonar_crosstalk_probability = 0.005;

  // Laser (each laser sensor is one beam).
  double laser_range_sigma_m = 0.01;  // SICK LMS200: about 1 cm
};

// One simulated reading of 'sensor' with the robot at 'world_from_robot'.
// Returns the range in metres; the sensor's max range means no echo.
// 'rays' (when not null) receives the rays cast for the reading as
// (origin, end) pairs, for coverage bookkeeping.
double SimulateReading(const World& world, const Pose2& world_from_robot,
                       const sensors::RangeSensor& sensor, const SensorModelOptions& options,
                       std::mt19937_64& rng, std::vector<std::pair<Vec2, Vec2>>* rays = nullptr);

// The noise-free echo of one sonar ray: the hit distance when the wall is met
// within the critical angle; for a specular wall, the multipath length when
// 'allow_multipath' and the bounce returns; otherwise a negative value.
double SonarRayEcho(const World& world, const Vec2& origin, double heading_rad, double max_range_m,
                    double critical_angle_rad, bool allow_multipath, Vec2* end = nullptr);

}  // namespace cogmap::sim
