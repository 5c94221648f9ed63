#include "cogmap/core/geometry.h"

namespace cogmap {

std::vector<Segment2> ToSegments(const std::vector<Polyline>& lines) {
  std::vector<Segment2> out;
  for (const auto& line : lines)
    for (size_t i = 1; i < line.size(); ++i) out.push_back({line[i - 1], line[i]});
  return out;
}

std::vector<Vec2> ConvexHull(std::vector<Vec2> p) {
  std::sort(p.begin(), p.end(), [](const Vec2& a, const Vec2& b) {
    return a.x() < b.x() || (a.x() == b.x() && a.y() < b.y());
  });
  p.erase(std::unique(p.begin(), p.end()), p.end());
  if (p.size() < 3) return p;
  auto cross = [](const Vec2& o, const Vec2& a, const Vec2& b) {
    return (a.x() - o.x()) * (b.y() - o.y()) - (a.y() - o.y()) * (b.x() - o.x());
  };
  std::vector<Vec2> h(2 * p.size());
  size_t k = 0;
  for (size_t i = 0; i < p.size(); ++i) {
    while (k >= 2 && cross(h[k - 2], h[k - 1], p[i]) <= 0) --k;
    h[k++] = p[i];
  }
  for (size_t i = p.size() - 1, t = k + 1; i > 0; --i) {
    while (k >= t && cross(h[k - 2], h[k - 1], p[i - 1]) <= 0) --k;
    h[k++] = p[i - 1];
  }
  h.resize(k - 1);
  h.shrink_to_fit();
  return h;
}

double SignedArea(const std::vector<Vec2>& ring) {
  double a = 0.0;
  for (size_t i = 0; i < ring.size(); ++i) {
    const Vec2& p = ring[i];
    const Vec2& q = ring[(i + 1) % ring.size()];
    a += p.x() * q.y() - q.x() * p.y();
  }
  return 0.5 * a;
}

Polyline Transform(const Pose2& pose, const Polyline& line) {
  Polyline out;
  out.reserve(line.size());
  for (const auto& p : line) out.push_back(pose * p);
  return out;
}

std::vector<Polyline> Transform(const Pose2& pose, const std::vector<Polyline>& lines) {
  std::vector<Polyline> out;
  out.reserve(lines.size());
  for (const auto& l : lines) out.push_back(Transform(pose, l));
  return out;
}

Pose2 AlignPoints(const std::vector<Vec2>& from, const std::vector<Vec2>& to) {
  const size_t n = std::min(from.size(), to.size());
  if (n == 0) return {};
  Vec2 cf(0, 0), ct(0, 0);
  for (size_t i = 0; i < n; ++i) cf += from[i], ct += to[i];
  cf /= static_cast<double>(n);
  ct /= static_cast<double>(n);
  // The rotation maximising sum (R a_i) . b_i for centred a, b: atan2 of the
  // summed cross and dot products.
  double dot = 0.0, cross = 0.0;
  for (size_t i = 0; i < n; ++i) {
    const Vec2 a = from[i] - cf, b = to[i] - ct;
    dot += a.dot(b);
    cross += a.x() * b.y() - a.y() * b.x();
  }
  const double theta = (dot == 0.0 && cross == 0.0) ? 0.0 : std::atan2(cross, dot);
  const Pose2 rotation{0.0, 0.0, theta};
  const Vec2 t = ct - rotation * cf;
  return {t.x(), t.y(), theta};
}

}  // namespace cogmap
