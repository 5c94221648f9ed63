#include "cogmap/eval/wall_metrics.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "cogmap/eval/nearest_segment.h"

namespace cogmap::eval {
namespace {


// Proper or touching intersection of segments [p, q] and [a, b].
bool SegmentsIntersect(const Vec2& p, const Vec2& q, const Vec2& a, const Vec2& b) {
  const Vec2 r = q - p, s = b - a;
  const double den = Cross(r, s);
  const Vec2 ap = a - p;
  if (std::abs(den) < 1e-15) {
    // Parallel: intersect only when collinear and overlapping.
    if (std::abs(Cross(ap, r)) > 1e-12) return false;
    const double rr = r.squaredNorm();
    if (rr <= 0.0) return PointSegmentDistance(p, a, b) < 1e-12;
    const double t0 = ap.dot(r) / rr, t1 = (b - p).dot(r) / rr;
    return std::max(t0, t1) >= 0.0 && std::min(t0, t1) <= 1.0;
  }
  const double t = Cross(ap, s) / den, u = Cross(ap, r) / den;
  return t >= 0.0 && t <= 1.0 && u >= 0.0 && u <= 1.0;
}

}  // namespace

std::vector<Vec2> SampleSegment(const Segment2& s, double step_m) {
  const double len = s.length();
  if (len <= 0.0) return {s.a};
  const int n = std::max(1, static_cast<int>(std::ceil(len / step_m - 1e-9)));
  std::vector<Vec2> out;
  out.reserve(n + 1);
  for (int i = 0; i <= n; ++i) out.push_back(s.a + (s.b - s.a) * (static_cast<double>(i) / n));
  return out;
}

PrecisionStats WallPrecision(const std::vector<Polyline>& map_walls, const std::vector<Segment2>& true_walls,
                             const WallMetricsOptions& options) {
  PrecisionStats st;
  const NearestSegment index(true_walls);
  std::vector<double> d;
  for (const auto& seg : ToSegments(map_walls)) {
    const auto pts = SampleSegment(seg, options.sample_step_m);
    for (size_t i = 0; i < pts.size(); ++i) {
      if (i + 1 == pts.size() && seg.length() > 0.0) continue;  // next segment starts here
      d.push_back(index.Distance(pts[i]));
    }
  }
  // Each polyline's last vertex.
  for (const auto& l : map_walls)
    if (l.size() >= 2) d.push_back(index.Distance(l.back()));
  st.samples = static_cast<int64_t>(d.size());
  if (d.empty()) return st;
  double sum = 0.0;
  for (double x : d) sum += x;
  st.mean_m = sum / d.size();
  std::sort(d.begin(), d.end());
  const size_t rank = static_cast<size_t>(std::ceil(0.95 * d.size()));
  st.p95_m = d[std::max<size_t>(rank, 1) - 1];
  st.max_m = d.back();
  return st;
}

bool ClearLineOfSight(const Vec2& from, const Vec2& to, const std::vector<Segment2>& walls,
                      double tolerance_m) {
  const Vec2 d = to - from;
  const double len = d.norm();
  if (len <= tolerance_m) return true;
  const Vec2 end = from + d * ((len - tolerance_m) / len);
  for (const auto& w : walls)
    if (SegmentsIntersect(from, end, w.a, w.b)) return false;
  return true;
}

std::vector<Vec2> ThinPath(const std::vector<Vec2>& path, double step_m) {
  std::vector<Vec2> out;
  for (size_t i = 0; i < path.size(); ++i)
    if (out.empty() || (path[i] - out.back()).norm() >= step_m || i + 1 == path.size()) out.push_back(path[i]);
  return out;
}

namespace {

// Items (points or boxes) bucketed on a uniform grid for range queries; the
// cell grows so that the grid stays under 4M cells whatever the extent.
class BoxGrid {
 public:
  BoxGrid(const Vec2& lo, const Vec2& hi, double cell_m) : lo_(lo) {
    const double wx = std::max(hi.x() - lo.x(), 1e-9), wy = std::max(hi.y() - lo.y(), 1e-9);
    cell_ = std::max({cell_m, 1e-3, std::sqrt(wx * wy / 4e6), wx / 4e6, wy / 4e6});
    w_ = static_cast<int>(wx / cell_) + 1;
    h_ = static_cast<int>(wy / cell_) + 1;
    buckets_.resize(static_cast<size_t>(w_) * h_);
  }
  void Add(const Vec2& a, const Vec2& b, int item) {
    ForCells(a.cwiseMin(b), a.cwiseMax(b), [&](std::vector<int>& c) { c.push_back(item); });
  }
  // Every item whose box meets [lo, hi] (each once, in ascending order).
  void Query(const Vec2& lo, const Vec2& hi, std::vector<int>* out) {
    out->clear();
    ForCells(lo, hi, [&](std::vector<int>& c) { out->insert(out->end(), c.begin(), c.end()); });
    std::sort(out->begin(), out->end());
    out->erase(std::unique(out->begin(), out->end()), out->end());
  }
  // Whether f(item) holds for an item listed in a cell that meets [lo, hi]:
  // cell by cell, stopping at the first that does (an item listed in several
  // cells may be tried more than once; for points, each is listed once).
  template <class F>
  bool AnyIn(const Vec2& lo, const Vec2& hi, F&& f) const {
    const int x0 = std::clamp(static_cast<int>(std::floor((lo.x() - lo_.x()) / cell_)), 0, w_ - 1);
    const int x1 = std::clamp(static_cast<int>(std::floor((hi.x() - lo_.x()) / cell_)), 0, w_ - 1);
    const int y0 = std::clamp(static_cast<int>(std::floor((lo.y() - lo_.y()) / cell_)), 0, h_ - 1);
    const int y1 = std::clamp(static_cast<int>(std::floor((hi.y() - lo_.y()) / cell_)), 0, h_ - 1);
    for (int y = y0; y <= y1; ++y)
      for (int x = x0; x <= x1; ++x)
        for (int item : buckets_[static_cast<size_t>(y) * w_ + x])
          if (f(item)) return true;
    return false;
  }

 private:
  template <class F>
  void ForCells(const Vec2& lo, const Vec2& hi, F&& f) {
    const int x0 = std::clamp(static_cast<int>(std::floor((lo.x() - lo_.x()) / cell_)), 0, w_ - 1);
    const int x1 = std::clamp(static_cast<int>(std::floor((hi.x() - lo_.x()) / cell_)), 0, w_ - 1);
    const int y0 = std::clamp(static_cast<int>(std::floor((lo.y() - lo_.y()) / cell_)), 0, h_ - 1);
    const int y1 = std::clamp(static_cast<int>(std::floor((hi.y() - lo_.y()) / cell_)), 0, h_ - 1);
    for (int y = y0; y <= y1; ++y)
      for (int x = x0; x <= x1; ++x) f(buckets_[static_cast<size_t>(y) * w_ + x]);
  }
  Vec2 lo_;
  double cell_ = 1.0;
  int w_ = 1, h_ = 1;
  std::vector<std::vector<int>> buckets_;
};

}  // namespace

RecallStats WallRecall(const std::vector<Polyline>& map_walls, const std::vector<Segment2>& true_walls,
                       const std::vector<Vec2>& true_path, const WallMetricsOptions& options) {
  RecallStats st;
  const auto map_segs = ToSegments(map_walls);
  // Single-vertex polylines count as points.
  std::vector<Segment2> map_all = map_segs;
  for (const auto& l : map_walls)
    if (l.size() == 1) map_all.push_back({l[0], l[0]});
  const NearestSegment map_index(map_all);
  const auto path = ThinPath(true_path, options.path_step_m);
  const double range2 = options.sensor_range_m * options.sensor_range_m;
  // Grids of the true walls and of the path: the candidates of each test
  // below are found in their cells, so the cost grows with the map, not with
  // its square (the tests themselves are unchanged).
  Vec2 lo(std::numeric_limits<double>::max(), std::numeric_limits<double>::max()), hi = -lo;
  for (const auto& w : true_walls) lo = lo.cwiseMin(w.a).cwiseMin(w.b), hi = hi.cwiseMax(w.a).cwiseMax(w.b);
  for (const auto& q : path) lo = lo.cwiseMin(q), hi = hi.cwiseMax(q);
  if (true_walls.empty()) return st;
  BoxGrid wall_grid(lo, hi, std::max(options.sensor_range_m, 0.5));
  for (size_t k = 0; k < true_walls.size(); ++k) wall_grid.Add(true_walls[k].a, true_walls[k].b, static_cast<int>(k));
  BoxGrid path_grid(lo, hi, std::max(options.sensor_range_m, 0.5));
  for (size_t k = 0; k < path.size(); ++k) path_grid.Add(path[k], path[k], static_cast<int>(k));
  std::vector<int> candidates;
  std::vector<Segment2> nearby;
  const Vec2 r(options.sensor_range_m, options.sensor_range_m);
  for (const auto& w : true_walls) {
    const auto pts = SampleSegment(w, options.sample_step_m);
    const double len = w.length();
    const double each = pts.size() > 1 ? len / (pts.size() - 1) : 0.0;
    // Walls that can block a sight line onto this one: within range of it.
    const double reach = 2 * options.sensor_range_m + len;
    wall_grid.Query(w.a.cwiseMin(w.b) - Vec2(reach, reach), w.a.cwiseMax(w.b) + Vec2(reach, reach), &candidates);
    nearby.clear();
    for (int k : candidates) {
      const auto& o = true_walls[k];
      if (PointSegmentDistance(o.a, w.a, w.b) <= reach || PointSegmentDistance(o.b, w.a, w.b) <= reach)
        nearby.push_back(o);
    }
    for (size_t i = 0; i < pts.size(); ++i) {
      const double weight = pts.size() == 1 ? 0.0 : ((i == 0 || i + 1 == pts.size()) ? each / 2 : each);
      ++st.samples;
      // Any path point in range with a clear sight line (which one does not matter).
      const bool seen = path_grid.AnyIn(pts[i] - r, pts[i] + r, [&](int k) {
        const Vec2& q = path[k];
        return (q - pts[i]).squaredNorm() <= range2 && ClearLineOfSight(q, pts[i], nearby, options.sight_tolerance_m);
      });
      if (!seen) continue;
      ++st.seeable_samples;
      st.seeable_length_m += weight;
      if (map_index.Distance(pts[i]) <= options.recall_within_m) st.found_length_m += weight;
    }
  }
  return st;
}

}  // namespace cogmap::eval
