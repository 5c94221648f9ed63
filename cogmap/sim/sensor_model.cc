#include "cogmap/sim/sensor_model.h"

#include <algorithm>
#include <cmath>

namespace cogmap::sim {

double SonarRayEcho(const World& world, const Vec2& origin, double heading_rad, double max_range_m,
                    double critical_angle_rad, bool allow_multipath, Vec2* end) {
  const RayHit hit = world.CastRay(origin, heading_rad, max_range_m);
  const Vec2 dir(std::cos(heading_rad), std::sin(heading_rad));
  if (end) *end = origin + dir * (hit.hit() ? hit.distance_m : max_range_m);
  if (!hit.hit()) return -1.0;
  const double cos_incidence = std::clamp(-dir.dot(hit.normal), -1.0, 1.0);
  if (std::acos(cos_incidence) <= critical_angle_rad) return hit.distance_m;
  if (!allow_multipath) return -1.0;
  // Mirror the ray about the wall and trace one bounce; back the new origin
  // off the wall a hair so that it does not hit the same wall again.
  const Vec2 reflected = dir - 2.0 * dir.dot(hit.normal) * hit.normal;
  const Vec2 bounce = origin + dir * hit.distance_m + hit.normal * 1e-6;
  const double remaining = max_range_m - hit.distance_m;
  if (remaining <= 0.0) return -1.0;
  const double heading2 = std::atan2(reflected.y(), reflected.x());
  const RayHit hit2 = world.CastRay(bounce, heading2, remaining);
  if (!hit2.hit()) return -1.0;
  const double cos2 = std::clamp(-reflected.dot(hit2.normal), -1.0, 1.0);
  if (std::acos(cos2) > critical_angle_rad) return -1.0;
  return hit.distance_m + hit2.distance_m;
}

double SimulateReading(const World& world, const Pose2& world_from_robot,
                       const sensors::RangeSensor& sensor, const SensorModelOptions& o,
                       std::mt19937_64& rng, std::vector<std::pair<Vec2, Vec2>>* rays) {
  const Pose2 sp = sensors::SensorPose(world_from_robot, sensor);
  const Vec2 origin = sp.translation();
  const double max_r = sensor.max_range_m;
  std::normal_distribution<double> gauss(0.0, 1.0);
  std::uniform_real_distribution<double> uniform(0.0, 1.0);

  if (sensor.kind == sensors::SensorKind::kLaser) {
    const RayHit hit = world.CastRay(origin, sp.theta, max_r);
    const double d = hit.hit() ? hit.distance_m : max_r;
    if (rays) rays->push_back({origin, origin + d * Vec2(std::cos(sp.theta), std::sin(sp.theta))});
    const double noise = gauss(rng) * o.laser_range_sigma_m;
    if (!hit.hit() || d < sensor.min_range_m) return max_r;
    return std::clamp(d + noise, sensor.min_range_m, max_r - 1e-6);
  }

  // Sonar: the cone sampled by n rays; the nearest echo wins. One multipath
  // draw per reading keeps the number of random draws fixed.
  const bool multipath = uniform(rng) < o.sonar_multipath_probability;
  const double crosstalk_u = uniform(rng), crosstalk_r = uniform(rng);
  const double noise = gauss(rng);
  const int n = std::max(1, o.sonar_rays);
  double best = -1.0;
  for (int i = 0; i < n; ++i) {
    const double off = n == 1 ? 0.0 : sensor.beam_width_rad * (static_cast<double>(i) / (n - 1) - 0.5);
    Vec2 end;
    const double e = SonarRayEcho(world, origin, sp.theta + off, max_r, o.sonar_critical_angle_rad,
                                  multipath, &end);
    if (rays) rays->push_back({origin, end});
    if (e >= 0.0 && (best < 0.0 || e < best)) best = e;
  }
  if (best < 0.0 || best < sensor.min_range_m || best >= max_r) return max_r;
  double r = best + noise * (o.sonar_range_sigma_m + o.sonar_range_sigma_frac * best);
  if (crosstalk_u < o.sonar_crosstalk_probability)
    r = sensor.min_range_m + crosstalk_r * (best - sensor.min_range_m);
  return std::clamp(r, sensor.min_range_m, max_r - 1e-6);
}

}  // namespace cogmap::sim
