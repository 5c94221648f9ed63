#include "cogmap/asr/asr.h"

#include <cmath>

namespace cogmap::asr {

std::vector<Pose2> CorrectedPath(const Asr& a, double rate) {
  return CorrectedPath(a.path, a.world_from_local_raw, a.world_from_local_corrected, rate);
}

std::vector<Pose2> CorrectedPath(const std::vector<Pose2>& path, const Pose2& world_from_local_raw,
                                 const Pose2& world_from_local_corrected, double rate) {
  std::vector<Pose2> out;
  out.reserve(path.size());
  const Pose2 local_from_world = world_from_local_raw.inverse();
  // Distance from the local origin to the first pose counts as driven.
  Pose2 prev_raw{0.0, 0.0, 0.0};
  Vec2 pos(0.0, 0.0);
  double s = 0.0;
  for (const Pose2& p : path) {
    const Pose2 q = local_from_world * p;
    const Vec2 d = q.translation() - prev_raw.translation();
    const double ds = d.norm();
    const double mid = s + 0.5 * ds;
    pos += RotateAbout(d, Vec2(0.0, 0.0), -rate * mid);
    s += ds;
    out.push_back(world_from_local_corrected * Pose2{pos.x(), pos.y(), NormalizeAngle(q.theta - rate * s)});
    prev_raw = q;
  }
  return out;
}

}  // namespace cogmap::asr
