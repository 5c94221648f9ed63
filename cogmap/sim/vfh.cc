#include "cogmap/sim/vfh.h"

#include <algorithm>
#include <cmath>

namespace cogmap::sim {
namespace {

int SectorOf(double angle, int n, double sector) {
  const int k = static_cast<int>(std::floor((NormalizeAngle(angle) + kPi) / sector));
  return ((k % n) + n) % n;
}

}  // namespace

VfhResult VfhChoose(std::vector<double> histogram, double goal, const VfhOptions& o) {
  VfhResult r;
  const int n = static_cast<int>(histogram.size());
  r.histogram = std::move(histogram);
  if (n == 0) return r;
  auto blocked = [&](int k) { return r.histogram[((k % n) + n) % n] > o.threshold; };
  const int kt = SectorOf(goal, n, o.sector_rad);
  auto centre = [&](int k) { return NormalizeAngle(-kPi + (k + 0.5) * o.sector_rad); };
  if (!blocked(kt)) {
    r.free = true;
    r.heading_rad = NormalizeAngle(goal);
    return r;
  }
  // Nearest free sector on either side of the goal sector.
  for (int off = 1; off <= n / 2; ++off) {
    for (int side : {+1, -1}) {
      const int kn = kt + side * off;
      if (blocked(kn)) continue;
      // Extend the valley away from the goal up to s_max sectors.
      int kf = kn;
      int width = 1;
      while (width < o.wide_valley_sectors && !blocked(kf + side) && width < n) {
        kf += side;
        ++width;
      }
      const double mid = 0.5 * (kn + kf);
      r.free = true;
      r.heading_rad = centre(0) + mid * o.sector_rad;
      r.heading_rad = NormalizeAngle(r.heading_rad);
      return r;
    }
  }
  return r;  // everything blocked
}

namespace {

template <typename CertaintyAt>
VfhResult Steer(const grid::MapLimits& lim, CertaintyAt&& certainty_at, const Vec2& position,
                double goal_heading_rad, double robot_radius_m, const VfhOptions& o,
                double goal_distance_m) {
  const int n = std::max(1, static_cast<int>(std::lround(2 * kPi / o.sector_rad)));
  std::vector<double> hist(n, 0.0);
  const auto c0 = lim.CellOf(position);
  const int r = static_cast<int>(std::ceil(o.window_radius_m / lim.cell_m()));
  const double enlarge = robot_radius_m + o.safety_m;
  const double reach = std::min(o.window_radius_m, goal_distance_m + enlarge);
  for (int dy = -r; dy <= r; ++dy) {
    for (int dx = -r; dx <= r; ++dx) {
      const grid::CellIndex c(c0.x() + dx, c0.y() + dy);
      if (!lim.Contains(c)) continue;
      const double cert = certainty_at(lim.Flat(c));
      if (cert <= 0.0) continue;
      const Vec2 v = lim.CenterOf(c) - position;
      const double d = v.norm();
      if (d > reach) continue;
      const double m = cert * cert * (o.a - o.b * d);
      if (m <= 0) continue;
      const double beta = std::atan2(v.y(), v.x());
      const double gamma = d <= enlarge ? kPi / 2 : std::asin(enlarge / d);
      const int k0 = static_cast<int>(std::floor((beta - gamma + kPi) / o.sector_rad));
      const int k1 = static_cast<int>(std::floor((beta + gamma + kPi) / o.sector_rad));
      for (int k = k0; k <= k1; ++k) hist[((k % n) + n) % n] += m;
    }
  }
  return VfhChoose(std::move(hist), goal_heading_rad, o);
}

}  // namespace

VfhResult VfhSteer(const NavGrid& nav, const Vec2& position, double goal_heading_rad,
                   double robot_radius_m, const VfhOptions& o, double goal_distance_m) {
  return Steer(nav.limits(), [&](long f) { return nav.WallCell(f) ? 1.0 : 0.0; }, position,
               goal_heading_rad, robot_radius_m, o, goal_distance_m);
}

VfhResult VfhSteerCertainty(const grid::MapLimits& limits, const std::vector<uint8_t>& certainty,
                            double c_max, const Vec2& position, double goal_heading_rad,
                            double robot_radius_m, const VfhOptions& o, double goal_distance_m) {
  return Steer(limits, [&](long f) { return certainty[f] / c_max; }, position, goal_heading_rad,
               robot_radius_m, o, goal_distance_m);
}

}  // namespace cogmap::sim
