#include "cogmap/sim/world.h"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <limits>

namespace cogmap::sim {

double RaySegmentDistance(const Vec2& origin, const Vec2& dir, const Vec2& a, const Vec2& b) {
  const Vec2 e = b - a;
  const Vec2 ao = a - origin;
  const double denom = Cross(dir, e);
  const double len = e.norm();
  if (std::abs(denom) <= 1e-12 * std::max(len, 1.0)) {
    // Parallel: only a collinear overlap counts (the nearest point ahead).
    if (std::abs(Cross(ao, dir)) > 1e-9 * std::max(len, 1.0)) return -1.0;
    const double ta = ao.dot(dir), tb = (b - origin).dot(dir);
    if (std::max(ta, tb) < 0.0) return -1.0;
    if (std::min(ta, tb) <= 0.0) return 0.0;
    return std::min(ta, tb);
  }
  const double t = Cross(ao, e) / denom;
  const double s = Cross(ao, dir) / denom;
  constexpr double kEps = 1e-12;
  if (t < -kEps || s < -kEps || s > 1.0 + kEps) return -1.0;
  return std::max(t, 0.0);
}

World::World(std::vector<Segment2> walls, double bucket_m) : walls_(std::move(walls)) {
  if (walls_.empty()) {
    min_ = max_ = origin_ = Vec2(0, 0);
    bucket_m_ = 1.0;
    nx_ = ny_ = 1;
    bucket_start_.assign(2, 0);
    return;
  }
  min_ = Vec2(std::numeric_limits<double>::infinity(), std::numeric_limits<double>::infinity());
  max_ = -min_;
  for (const auto& w : walls_) {
    min_ = min_.cwiseMin(w.a).cwiseMin(w.b);
    max_ = max_.cwiseMax(w.a).cwiseMax(w.b);
  }
  const Vec2 extent = max_ - min_;
  if (bucket_m <= 0.0) {
    bucket_m = 1.0;
    while ((extent.x() / bucket_m + 2) * (extent.y() / bucket_m + 2) > 4e6) bucket_m *= 2.0;
  }
  bucket_m_ = bucket_m;
  origin_ = min_ - Vec2(bucket_m_, bucket_m_) * 0.5;
  nx_ = static_cast<int>(std::floor(extent.x() / bucket_m_)) + 2;
  ny_ = static_cast<int>(std::floor(extent.y() / bucket_m_)) + 2;

  // Two passes (count, fill) over the buckets each wall crosses: for each row
  // of buckets, the x-range of the part of the wall inside that row.
  std::vector<uint32_t> count(static_cast<size_t>(nx_) * ny_ + 1, 0);
  auto for_buckets_of = [&](const Segment2& w, auto&& add) {
    const Vec2 a = (w.a - origin_) / bucket_m_, b = (w.b - origin_) / bucket_m_;
    const int iy0 = std::clamp(static_cast<int>(std::floor(std::min(a.y(), b.y()))), 0, ny_ - 1);
    const int iy1 = std::clamp(static_cast<int>(std::floor(std::max(a.y(), b.y()))), 0, ny_ - 1);
    for (int iy = iy0; iy <= iy1; ++iy) {
      double xlo, xhi;
      if (std::abs(b.y() - a.y()) < 1e-12) {
        xlo = std::min(a.x(), b.x());
        xhi = std::max(a.x(), b.x());
      } else {
        const double t0 = std::clamp((iy - a.y()) / (b.y() - a.y()), 0.0, 1.0);
        const double t1 = std::clamp((iy + 1 - a.y()) / (b.y() - a.y()), 0.0, 1.0);
        const double x0 = a.x() + t0 * (b.x() - a.x()), x1 = a.x() + t1 * (b.x() - a.x());
        xlo = std::min(x0, x1);
        xhi = std::max(x0, x1);
      }
      const int ix0 = std::clamp(static_cast<int>(std::floor(xlo - 1e-9)), 0, nx_ - 1);
      const int ix1 = std::clamp(static_cast<int>(std::floor(xhi + 1e-9)), 0, nx_ - 1);
      for (int ix = ix0; ix <= ix1; ++ix) add(BucketFlat(ix, iy));
    }
  };
  for (const auto& w : walls_) for_buckets_of(w, [&](long b) { ++count[b]; });
  bucket_start_.assign(count.size(), 0);
  uint32_t acc = 0;
  for (size_t b = 0; b + 1 < count.size(); ++b) {
    bucket_start_[b] = acc;
    acc += count[b];
  }
  bucket_start_.back() = acc;
  bucket_walls_.resize(acc);
  std::vector<uint32_t> fill(bucket_start_.begin(), bucket_start_.end() - 1);
  for (uint32_t i = 0; i < walls_.size(); ++i)
    for_buckets_of(walls_[i], [&](long b) {
      // A wall may be added twice to a bucket on a row boundary; skip repeats.
      if (fill[b] > bucket_start_[b] && bucket_walls_[fill[b] - 1] == i) return;
      bucket_walls_[fill[b]++] = i;
    });
  // Compact the skipped repeats away.
  std::vector<uint32_t> start(bucket_start_.size(), 0), packed;
  packed.reserve(acc);
  for (size_t b = 0; b + 1 < bucket_start_.size(); ++b) {
    start[b] = static_cast<uint32_t>(packed.size());
    packed.insert(packed.end(), bucket_walls_.begin() + bucket_start_[b], bucket_walls_.begin() + fill[b]);
  }
  start.back() = static_cast<uint32_t>(packed.size());
  bucket_start_ = std::move(start);
  bucket_walls_ = std::move(packed);
}

template <typename Visit>
void World::ForBucketsInBox(const Vec2& lo, const Vec2& hi, Visit&& visit) const {
  const Vec2 l = (lo - origin_) / bucket_m_, h = (hi - origin_) / bucket_m_;
  if (h.x() < 0 || h.y() < 0 || l.x() >= nx_ || l.y() >= ny_) return;
  const int ix0 = std::max(0, static_cast<int>(std::floor(l.x())));
  const int iy0 = std::max(0, static_cast<int>(std::floor(l.y())));
  const int ix1 = std::min(nx_ - 1, static_cast<int>(std::floor(h.x())));
  const int iy1 = std::min(ny_ - 1, static_cast<int>(std::floor(h.y())));
  for (int iy = iy0; iy <= iy1; ++iy)
    for (int ix = ix0; ix <= ix1; ++ix) visit(BucketFlat(ix, iy));
}

RayHit World::CastRay(const Vec2& origin, double heading_rad, double max_range_m) const {
  RayHit best;
  if (walls_.empty() || !(max_range_m > 0.0)) return best;
  const Vec2 dir(std::cos(heading_rad), std::sin(heading_rad));
  const Vec2 o = (origin - origin_) / bucket_m_;  // bucket coordinates
  const double range_b = max_range_m / bucket_m_;
  // Clip the ray to the bucket grid [0, nx] x [0, ny] (slab test).
  double t_in = 0.0, t_out = range_b;
  for (int k = 0; k < 2; ++k) {
    const double ok = o[k], dk = dir[k], n = k == 0 ? nx_ : ny_;
    if (std::abs(dk) < 1e-15) {
      if (ok < 0 || ok > n) return best;
    } else {
      double t0 = (0 - ok) / dk, t1 = (n - ok) / dk;
      if (t0 > t1) std::swap(t0, t1);
      t_in = std::max(t_in, t0);
      t_out = std::min(t_out, t1);
    }
  }
  if (t_in > t_out) return best;
  const Vec2 p = o + t_in * dir;
  int ix = std::clamp(static_cast<int>(std::floor(p.x())), 0, nx_ - 1);
  int iy = std::clamp(static_cast<int>(std::floor(p.y())), 0, ny_ - 1);
  const int step_x = dir.x() > 0 ? 1 : -1, step_y = dir.y() > 0 ? 1 : -1;
  const double inf = std::numeric_limits<double>::infinity();
  const double dt_x = std::abs(dir.x()) < 1e-15 ? inf : 1.0 / std::abs(dir.x());
  const double dt_y = std::abs(dir.y()) < 1e-15 ? inf : 1.0 / std::abs(dir.y());
  double t_max_x = std::abs(dir.x()) < 1e-15 ? inf
                   : ((dir.x() > 0 ? ix + 1 - o.x() : ix - o.x()) / dir.x());
  double t_max_y = std::abs(dir.y()) < 1e-15 ? inf
                   : ((dir.y() > 0 ? iy + 1 - o.y() : iy - o.y()) / dir.y());
  double best_t = inf;  // metres
  for (;;) {
    const long b = BucketFlat(ix, iy);
    for (uint32_t k = bucket_start_[b]; k < bucket_start_[b + 1]; ++k) {
      const uint32_t w = bucket_walls_[k];
      const double t = RaySegmentDistance(origin, dir, walls_[w].a, walls_[w].b);
      if (t >= 0.0 && t < best_t) {
        best_t = t;
        best.wall = static_cast<int>(w);
      }
    }
    const double t_exit = std::min(t_max_x, t_max_y);  // bucket units
    if (best_t <= t_exit * bucket_m_ || t_exit > t_out) break;
    if (t_max_x < t_max_y) {
      ix += step_x;
      t_max_x += dt_x;
    } else {
      iy += step_y;
      t_max_y += dt_y;
    }
    if (ix < 0 || iy < 0 || ix >= nx_ || iy >= ny_) break;
  }
  if (best.wall < 0 || best_t > max_range_m) return RayHit{};
  best.distance_m = best_t;
  const Vec2 e = walls_[best.wall].b - walls_[best.wall].a;
  Vec2 n(-e.y(), e.x());
  const double len = n.norm();
  n = len > 0 ? Vec2(n / len) : Vec2(-dir);
  if (n.dot(dir) > 0) n = -n;
  best.normal = n;
  return best;
}

double World::Clearance(const Vec2& p, double limit_m) const {
  double best = limit_m;
  const Vec2 r(limit_m, limit_m);
  ForBucketsInBox(p - r, p + r, [&](long b) {
    for (uint32_t k = bucket_start_[b]; k < bucket_start_[b + 1]; ++k) {
      const auto& w = walls_[bucket_walls_[k]];
      best = std::min(best, PointSegmentDistance(p, w.a, w.b));
    }
  });
  return best;
}

bool World::LineOfSight(const Vec2& a, const Vec2& b) const {
  const Vec2 d = b - a;
  const double len = d.norm();
  if (len <= 0.0) return Clearance(a, 1e-9) > 0.0;
  return !CastRay(a, std::atan2(d.y(), d.x()), len).hit();
}

}  // namespace cogmap::sim
