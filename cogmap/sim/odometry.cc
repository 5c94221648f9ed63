#include "cogmap/sim/odometry.h"

#include <cmath>

namespace cogmap::sim {

void OdometryModel::Step(double trans_m, double rot_rad, std::mt19937_64& rng) {
  const auto& o = options_;
  const double d = std::abs(trans_m), r = std::abs(rot_rad);
  // Always draw the same number of variates so that runs stay reproducible.
  const double n_trans = gauss_(rng), n_rot = gauss_(rng), n_head = gauss_(rng);
  const double trans = trans_m * (1.0 + o.scale_error) + n_trans * o.trans_sigma_m_per_sqrt_m * std::sqrt(d);
  const double rot = rot_rad + n_rot * o.rot_sigma_rad_per_sqrt_rad * std::sqrt(r) +
                     n_head * o.heading_sigma_rad_per_sqrt_m * std::sqrt(d) + o.drift_rad_per_m * d;
  const double mid = odom_.theta + 0.5 * rot;
  odom_.x += trans * std::cos(mid);
  odom_.y += trans * std::sin(mid);
  odom_.theta = NormalizeAngle(odom_.theta + rot);
  distance_m_ += d;
}

}  // namespace cogmap::sim
