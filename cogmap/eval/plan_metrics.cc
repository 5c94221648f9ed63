#include "cogmap/eval/plan_metrics.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <unordered_map>

#include <boost/geometry.hpp>
#include <boost/geometry/geometries/point_xy.hpp>
#include <boost/geometry/geometries/polygon.hpp>

#include "cogmap/eval/nearest_segment.h"
#include "cogmap/eval/wall_metrics.h"

namespace cogmap::eval {
namespace {

namespace bg = boost::geometry;
using BPoint = bg::model::d2::point_xy<double>;
using BPoly = bg::model::polygon<BPoint, false, false>;

constexpr double kPi = 3.14159265358979323846;

// Uniform hash grid of segments (each listed in every cell its box touches).
class SegGrid {
 public:
  SegGrid(const std::vector<Segment2>& segs, double cell) : segs_(segs), cell_(cell) {
    for (size_t i = 0; i < segs.size(); ++i) {
      const Vec2 lo = segs[i].a.cwiseMin(segs[i].b), hi = segs[i].a.cwiseMax(segs[i].b);
      for (int64_t y = C(lo.y()); y <= C(hi.y()); ++y)
        for (int64_t x = C(lo.x()); x <= C(hi.x()); ++x) cells_[Key(x, y)].push_back(static_cast<int>(i));
    }
  }
  // The nearest segment within 'radius' (<= cell) whose direction agrees with
  // 'dir' (unit; zero vector: any direction) within cos_angle; -1 when none.
  int Nearest(const Vec2& p, double radius, const Vec2& dir, double cos_angle, double* dist) const {
    int best = -1;
    double bd = radius;
    for (int64_t y = C(p.y() - radius); y <= C(p.y() + radius); ++y)
      for (int64_t x = C(p.x() - radius); x <= C(p.x() + radius); ++x) {
        auto it = cells_.find(Key(x, y));
        if (it == cells_.end()) continue;
        for (int i : it->second) {
          const Segment2& s = segs_[i];
          if (dir.squaredNorm() > 0) {
            const double len = s.length();
            if (len <= 0 || std::abs((s.b - s.a).dot(dir)) / len < cos_angle) continue;
          }
          const double d = PointSegmentDistance(p, s.a, s.b);
          if (d <= bd) bd = d, best = i;
        }
      }
    if (dist) *dist = bd;
    return best;
  }

 private:
  int64_t C(double v) const { return static_cast<int64_t>(std::floor(v / cell_)); }
  static int64_t Key(int64_t x, int64_t y) { return (y << 32) ^ (x & 0xffffffffLL); }
  const std::vector<Segment2>& segs_;
  double cell_;
  std::unordered_map<int64_t, std::vector<int>> cells_;
};

BPoly Poly(const std::vector<Vec2>& ring) {
  BPoly p;
  for (const Vec2& v : ring) p.outer().push_back(BPoint(v.x(), v.y()));
  bg::correct(p);
  return p;
}

// Area of the intersection of two polygons (rings; a self-crossing ring is
// read even-odd), by vertical slabs: between consecutive x of the vertices and
// of the edges' crossings no two edges cross, so the length of the vertical
// line inside both is linear in x there and its value at the slab's middle,
// times the slab's width, is the slab's area. Exact up to rounding, and
// continuous in the input: two rooms that share a wall (edges on one line,
// or nearly) add no area, where a polygon-clipping library may decide the
// topology wrongly and report one whole room as inside the other (Boost
// 1.74 did, on two valid rooms of a generated building).
double IntersectionArea(const BPoly& pa, const BPoly& pb) {
  struct Edge {
    double x0, y0, x1, y1;
  };
  bg::model::box<BPoint> ba, bb;
  bg::envelope(pa, ba);
  bg::envelope(pb, bb);
  const double lo_x = std::max(ba.min_corner().x(), bb.min_corner().x());
  const double hi_x = std::min(ba.max_corner().x(), bb.max_corner().x());
  const double lo_y = std::max(ba.min_corner().y(), bb.min_corner().y());
  const double hi_y = std::min(ba.max_corner().y(), bb.max_corner().y());
  if (!(lo_x < hi_x) || !(lo_y < hi_y)) return 0.0;
  // The edges that reach the common box's x range (only they bound the intersection there).
  auto edges_of = [&](const BPoly& p) {
    std::vector<Edge> out;
    const auto& r = p.outer();
    for (size_t i = 0; i < r.size(); ++i) {
      const BPoint& a = r[i];
      const BPoint& b = r[(i + 1) % r.size()];
      if (a.x() == b.x()) continue;  // vertical: no length across a slab
      if (std::max(a.x(), b.x()) <= lo_x || std::min(a.x(), b.x()) >= hi_x) continue;
      out.push_back(a.x() < b.x() ? Edge{a.x(), a.y(), b.x(), b.y()} : Edge{b.x(), b.y(), a.x(), a.y()});
    }
    return out;
  };
  const std::vector<Edge> ea = edges_of(pa), eb = edges_of(pb);
  std::vector<double> xs{lo_x, hi_x};
  for (const auto* es : {&ea, &eb})
    for (const Edge& e : *es)
      for (double x : {e.x0, e.x1})
        if (x > lo_x && x < hi_x) xs.push_back(x);
  // Crossings of any two edges (of either polygon) inside the range.
  std::vector<Edge> all = ea;
  all.insert(all.end(), eb.begin(), eb.end());
  for (size_t i = 0; i < all.size(); ++i)
    for (size_t j = i + 1; j < all.size(); ++j) {
      const Edge& e = all[i];
      const Edge& f = all[j];
      const double x0 = std::max(e.x0, f.x0), x1 = std::min(e.x1, f.x1);
      if (!(x0 < x1)) continue;
      auto y_at = [](const Edge& g, double x) { return g.y0 + (g.y1 - g.y0) * (x - g.x0) / (g.x1 - g.x0); };
      const double d0 = y_at(e, x0) - y_at(f, x0), d1 = y_at(e, x1) - y_at(f, x1);
      if ((d0 < 0 && d1 > 0) || (d0 > 0 && d1 < 0)) {
        const double x = x0 + (x1 - x0) * d0 / (d0 - d1);
        if (x > lo_x && x < hi_x) xs.push_back(x);
      }
    }
  std::sort(xs.begin(), xs.end());
  xs.erase(std::unique(xs.begin(), xs.end()), xs.end());
  // The y intervals inside a polygon on the vertical line at x (even-odd).
  auto intervals = [](const std::vector<Edge>& es, double x) {
    std::vector<double> ys;
    for (const Edge& e : es)
      if (e.x0 < x && x < e.x1) ys.push_back(e.y0 + (e.y1 - e.y0) * (x - e.x0) / (e.x1 - e.x0));
    std::sort(ys.begin(), ys.end());
    return ys;
  };
  double area = 0.0;
  for (size_t k = 0; k + 1 < xs.size(); ++k) {
    const double w = xs[k + 1] - xs[k];
    if (!(w > 0)) continue;
    const double xm = 0.5 * (xs[k] + xs[k + 1]);
    const std::vector<double> ya = intervals(ea, xm), yb = intervals(eb, xm);
    // Length of the intersection of the two interval sets.
    double len = 0.0;
    for (size_t i = 0; i + 1 < ya.size(); i += 2)
      for (size_t j = 0; j + 1 < yb.size(); j += 2) {
        const double l = std::min(ya[i + 1], yb[j + 1]) - std::max(ya[i], yb[j]);
        if (l > 0) len += l;
      }
    area += len * w;
  }
  return area;
}

double Percentile(std::vector<double> v, double q) {  // nearest rank
  std::sort(v.begin(), v.end());
  const size_t k = static_cast<size_t>(std::ceil(q * v.size()));
  return v[std::clamp<size_t>(k, 1, v.size()) - 1];
}

std::vector<Segment2> PlanSegments(const plan::Plan& plan) {
  std::vector<Segment2> out;
  for (const auto& w : plan.walls)
    for (size_t i = 1; i < w.points.size(); ++i) out.push_back({w.points[i - 1], w.points[i]});
  return out;
}

// Pairs of rooms whose boxes meet, through a grid of the boxes (linear for rooms of bounded size).
double OverlapArea(const std::vector<BPoly>& polys) {
  std::vector<bg::model::box<BPoint>> boxes(polys.size());
  double cell = 1.0;
  for (size_t i = 0; i < polys.size(); ++i) {
    bg::envelope(polys[i], boxes[i]);
    cell = std::max(cell, std::max(boxes[i].max_corner().x() - boxes[i].min_corner().x(),
                                   boxes[i].max_corner().y() - boxes[i].min_corner().y()) / 4.0);
  }
  cell = std::min(cell, 10.0);
  std::unordered_map<int64_t, std::vector<int>> grid;
  auto C = [&](double v) { return static_cast<int64_t>(std::floor(v / cell)); };
  double total = 0.0;
  for (size_t i = 0; i < polys.size(); ++i) {
    if (polys[i].outer().size() < 3) continue;
    std::vector<int> cand;
    const auto& b = boxes[i];
    for (int64_t y = C(b.min_corner().y()); y <= C(b.max_corner().y()); ++y)
      for (int64_t x = C(b.min_corner().x()); x <= C(b.max_corner().x()); ++x) {
        auto& v = grid[(y << 32) ^ (x & 0xffffffffLL)];
        cand.insert(cand.end(), v.begin(), v.end());
        v.push_back(static_cast<int>(i));
      }
    std::sort(cand.begin(), cand.end());
    cand.erase(std::unique(cand.begin(), cand.end()), cand.end());
    for (int j : cand)
      if (bg::intersects(boxes[i], boxes[j])) total += IntersectionArea(polys[i], polys[j]);
  }
  return total;
}

// The floor of a true room: the cells of its box (cell_m) that the robot
// could reach from its true path inside the box without crossing a world
// wall, with the wall cells bordering them. A room cairn is a box; a ring
// corridor's box also holds the block it runs around, which no plan covers.
// Empty (the box is the room) when no wall runs through the box's inside
// (farther than margin_m from its sides) or the robot never entered it.
struct RoomFloor {
  Vec2 origin{0, 0};
  double cell_m = 0.1;
  int w = 0, h = 0;
  std::vector<uint8_t> cells;  // 1: floor
  int64_t count = 0;
};

std::optional<RoomFloor> ReachableFloor(const NamedBox& t, const std::vector<Segment2>& walls,
                                        const std::vector<Vec2>& path, double cell_m, double margin_m) {
  const Vec2 lo = t.min, hi = t.max;
  // Does a wall cross the box shrunk by the margin? (Liang-Barsky clipping.)
  const Vec2 in_lo = lo + Vec2(margin_m, margin_m), in_hi = hi - Vec2(margin_m, margin_m);
  auto crosses = [&](const Segment2& s) {
    double t0 = 0.0, t1 = 1.0;
    const Vec2 d = s.b - s.a;
    for (int k = 0; k < 2; ++k) {
      const double p[2] = {-d[k], d[k]}, q[2] = {s.a[k] - in_lo[k], in_hi[k] - s.a[k]};
      for (int e = 0; e < 2; ++e) {
        if (p[e] == 0.0) {
          if (q[e] <= 0.0) return false;
        } else if (p[e] < 0.0) {
          t0 = std::max(t0, q[e] / p[e]);
        } else {
          t1 = std::min(t1, q[e] / p[e]);
        }
      }
    }
    return t0 < t1;
  };
  if (in_lo.x() >= in_hi.x() || in_lo.y() >= in_hi.y() || std::none_of(walls.begin(), walls.end(), crosses))
    return std::nullopt;
  RoomFloor f;
  f.origin = lo;
  f.cell_m = cell_m;
  f.w = static_cast<int>(std::ceil((hi.x() - lo.x()) / cell_m));
  f.h = static_cast<int>(std::ceil((hi.y() - lo.y()) / cell_m));
  if (f.w <= 0 || f.h <= 0) return std::nullopt;
  auto index = [&](const Vec2& p, int* x, int* y) {
    *x = static_cast<int>(std::floor((p.x() - lo.x()) / cell_m));
    *y = static_cast<int>(std::floor((p.y() - lo.y()) / cell_m));
    return *x >= 0 && *y >= 0 && *x < f.w && *y < f.h;
  };
  // 0 unknown, 1 floor, 2 wall. Walls drawn every half cell: a 4-connected
  // flood cannot pass a line drawn that densely.
  f.cells.assign(static_cast<size_t>(f.w) * f.h, 0);
  for (const Segment2& s : walls) {
    if (std::max(s.a.x(), s.b.x()) < lo.x() || std::min(s.a.x(), s.b.x()) > hi.x() ||
        std::max(s.a.y(), s.b.y()) < lo.y() || std::min(s.a.y(), s.b.y()) > hi.y())
      continue;
    const int n = std::max(1, static_cast<int>(std::ceil(2.0 * s.length() / cell_m)));
    for (int i = 0; i <= n; ++i) {
      int x, y;
      if (index(s.a + (s.b - s.a) * (static_cast<double>(i) / n), &x, &y))
        f.cells[static_cast<size_t>(y) * f.w + x] = 2;
    }
  }
  std::vector<int> stack;
  for (const Vec2& p : path) {
    int x, y;
    if (!index(p, &x, &y)) continue;
    const int c = y * f.w + x;
    if (f.cells[c] == 0) {
      f.cells[c] = 1;
      stack.push_back(c);
    }
  }
  if (stack.empty()) return std::nullopt;
  std::vector<uint8_t> border(f.cells.size(), 0);
  while (!stack.empty()) {
    const int c = stack.back();
    stack.pop_back();
    const int x = c % f.w, y = c / f.w;
    const int nb[4][2] = {{x + 1, y}, {x - 1, y}, {x, y + 1}, {x, y - 1}};
    for (const auto& q : nb) {
      if (q[0] < 0 || q[1] < 0 || q[0] >= f.w || q[1] >= f.h) continue;
      const int k = q[1] * f.w + q[0];
      if (f.cells[k] == 0) {
        f.cells[k] = 1;
        stack.push_back(k);
      } else if (f.cells[k] == 2) {
        border[k] = 1;
      }
    }
  }
  for (size_t c = 0; c < f.cells.size(); ++c) {
    f.cells[c] = f.cells[c] == 1 || border[c] ? 1 : 0;
    f.count += f.cells[c];
  }
  return f;
}

// IoU of a room floor (cells) with a plan room polygon: the cells whose
// centre lies inside it count as the intersection.
double FloorIou(const RoomFloor& f, const BPoly& poly, const bg::model::box<BPoint>& box) {
  const double a = f.cell_m * f.cell_m;
  int64_t inter = 0;
  const int x0 = std::max(0, static_cast<int>(std::floor((box.min_corner().x() - f.origin.x()) / f.cell_m)));
  const int x1 = std::min(f.w - 1, static_cast<int>(std::floor((box.max_corner().x() - f.origin.x()) / f.cell_m)));
  const int y0 = std::max(0, static_cast<int>(std::floor((box.min_corner().y() - f.origin.y()) / f.cell_m)));
  const int y1 = std::min(f.h - 1, static_cast<int>(std::floor((box.max_corner().y() - f.origin.y()) / f.cell_m)));
  for (int y = y0; y <= y1; ++y)
    for (int x = x0; x <= x1; ++x) {
      if (!f.cells[static_cast<size_t>(y) * f.w + x]) continue;
      const BPoint p(f.origin.x() + (x + 0.5) * f.cell_m, f.origin.y() + (y + 0.5) * f.cell_m);
      if (bg::within(p, poly)) ++inter;
    }
  const double uni = f.count * a + bg::area(poly) - inter * a;
  return uni > 0 ? inter * a / uni : 0.0;
}

}  // namespace

PlanMetrics DescribePlan(const plan::Plan& plan) {
  PlanMetrics m;
  m.walls = static_cast<int>(plan.walls.size());
  m.rooms = static_cast<int>(plan.rooms.size());
  m.doors = static_cast<int>(plan.doors.size());
  for (const auto& w : plan.walls) {
    m.wall_length_m += PolylineLength(w.points);
    m.vertices += static_cast<int64_t>(w.points.size());
  }
  m.vertices_per_m = m.wall_length_m > 0 ? m.vertices / m.wall_length_m : 0.0;
  std::vector<BPoly> polys;
  for (const auto& r : plan.rooms) polys.push_back(Poly(r.polygon));
  m.room_overlap_m2 = OverlapArea(polys);
  return m;
}

// Cells of each labelled room that each plan room's polygon covers (cell
// centres inside, even-odd rule, filled row by row): inter[label] maps a
// plan room index to its count.
std::vector<std::unordered_map<int, int64_t>> LabelCover(const plan::Plan& plan, const RoomLabels& L) {
  std::vector<std::unordered_map<int, int64_t>> inter(L.names.size());
  std::vector<double> xs;
  for (size_t j = 0; j < plan.rooms.size(); ++j) {
    const std::vector<Vec2>& ring = plan.rooms[j].polygon;
    if (ring.size() < 3) continue;
    double ymin = ring[0].y(), ymax = ymin;
    for (const Vec2& v : ring) {
      ymin = std::min(ymin, v.y());
      ymax = std::max(ymax, v.y());
    }
    // Rows whose centre lies within the polygon's span.
    const int r0 = std::max(0, static_cast<int>(std::ceil((ymin - L.origin.y()) / L.cell_m - 0.5)));
    const int r1 = std::min(L.height - 1, static_cast<int>(std::floor((ymax - L.origin.y()) / L.cell_m - 0.5)));
    for (int r = r0; r <= r1; ++r) {
      const double yc = L.origin.y() + (r + 0.5) * L.cell_m;
      xs.clear();
      for (size_t k = 0; k < ring.size(); ++k) {
        const Vec2& a = ring[k];
        const Vec2& b = ring[(k + 1) % ring.size()];
        if ((a.y() <= yc) != (b.y() <= yc)) xs.push_back(a.x() + (yc - a.y()) * (b.x() - a.x()) / (b.y() - a.y()));
      }
      std::sort(xs.begin(), xs.end());
      for (size_t k = 0; k + 1 < xs.size(); k += 2) {
        // Columns whose centre lies in [xs[k], xs[k + 1]).
        const int c0 = std::max(0, static_cast<int>(std::ceil((xs[k] - L.origin.x()) / L.cell_m - 0.5)));
        const int c1 = std::min(L.width - 1, static_cast<int>(std::ceil((xs[k + 1] - L.origin.x()) / L.cell_m - 0.5)) - 1);
        for (int c = c0; c <= c1; ++c) {
          const int l = L.label[static_cast<size_t>(r) * L.width + c];
          if (l >= 0) ++inter[l][static_cast<int>(j)];
        }
      }
    }
  }
  return inter;
}

PlanMetrics EvaluatePlan(const plan::Plan& plan, const FloorPlan& truth, const std::vector<Vec2>& true_path,
                         const PlanMetricsOptions& o, const RoomLabels* room_labels) {
  PlanMetrics m = DescribePlan(plan);
  const double cell = std::max(0.5, 2.0 * o.match_m);
  const SegGrid true_grid(truth.walls, cell);
  const NearestSegment true_nearest(truth.walls);
  const std::vector<Segment2> plan_segs = PlanSegments(plan);
  const SegGrid plan_grid(plan_segs, cell);
  const double cos_angle = std::cos(o.match_angle_deg * kPi / 180.0);

  // Precision and the plan side of duplication.
  std::vector<double> dist;
  for (const Segment2& s : plan_segs) {
    const double len = s.length();
    if (len <= 0) continue;
    const Vec2 dir = (s.b - s.a) / len;
    const int n = std::max(1, static_cast<int>(std::ceil(len / o.sample_step_m)));
    const double each = len / n;
    for (int i = 0; i < n; ++i) {
      const Vec2 p = s.a + (i + 0.5) * each * dir;
      dist.push_back(truth.walls.empty() ? std::numeric_limits<double>::infinity() : true_nearest.Distance(p));
      double d;
      if (true_grid.Nearest(p, o.match_m, dir, cos_angle, &d) >= 0) m.matched_plan_length_m += each;
    }
  }
  m.samples = static_cast<int64_t>(dist.size());
  if (!dist.empty()) {
    m.precision_p50_m = Percentile(dist, 0.50);
    m.precision_p95_m = Percentile(dist, 0.95);
  }
  // The true side: true wall length with a matching plan wall on it.
  for (const Segment2& s : truth.walls) {
    const double len = s.length();
    if (len <= 0) continue;
    const Vec2 dir = (s.b - s.a) / len;
    const int n = std::max(1, static_cast<int>(std::ceil(len / o.sample_step_m)));
    const double each = len / n;
    for (int i = 0; i < n; ++i) {
      const Vec2 p = s.a + (i + 0.5) * each * dir;
      double d;
      if (plan_grid.Nearest(p, o.match_m, dir, cos_angle, &d) >= 0) m.covered_true_length_m += each;
    }
  }
  if (m.covered_true_length_m > 0) m.duplication = m.matched_plan_length_m / m.covered_true_length_m;
  // Recall as the ASR walls' (eval::WallRecall).
  if (!plan.walls.empty() && !truth.walls.empty()) {
    std::vector<Polyline> lines;
    for (const auto& w : plan.walls) lines.push_back(w.points);
    WallMetricsOptions wo;
    wo.sample_step_m = o.sample_step_m;
    wo.recall_within_m = o.recall_within_m;
    wo.sensor_range_m = o.sensor_range_m;
    m.recall = WallRecall(lines, truth.walls, true_path, wo).recall();
  }

  auto median = [](std::vector<double> v) {
    std::sort(v.begin(), v.end());
    const size_t n = v.size();
    return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
  };
  if (room_labels && !room_labels->empty()) {
    // Rooms from a segmentation raster: each against its best plan room.
    const RoomLabels& L = *room_labels;
    const double cell_area = L.cell_m * L.cell_m;
    const auto inter = LabelCover(plan, L);
    std::vector<bool> entered(L.names.size(), false);
    for (const Vec2& p : true_path)
      if (const int l = L.At(p); l >= 0) entered[l] = true;
    std::vector<double> area(plan.rooms.size());
    for (size_t j = 0; j < plan.rooms.size(); ++j) area[j] = bg::area(Poly(plan.rooms[j].polygon));
    std::vector<double> entered_iou;
    for (size_t l = 0; l < L.names.size(); ++l) {
      double best = 0.0;
      for (const auto& [j, n] : inter[l]) {
        const double in = n * cell_area;
        const double uni = L.cells[l] * cell_area + area[j] - in;
        if (uni > 0) best = std::max(best, in / uni);
      }
      m.room_iou.push_back(best);
      m.room_entered.push_back(entered[l]);
      if (entered[l]) entered_iou.push_back(best);
    }
    m.room_iou_median = median(m.room_iou);
    m.rooms_entered = static_cast<int>(entered_iou.size());
    if (!entered_iou.empty()) m.room_iou_median_entered = median(entered_iou);
    return m;
  }
  // Rooms: each true room against its best plan room (candidates through a box grid).
  if (!truth.rooms.empty()) {
    std::vector<BPoly> polys;
    std::vector<bg::model::box<BPoint>> boxes;
    std::unordered_map<int64_t, std::vector<int>> grid;
    const double rc = 4.0;
    auto C = [&](double v) { return static_cast<int64_t>(std::floor(v / rc)); };
    auto Key = [](int64_t x, int64_t y) { return (y << 32) ^ (x & 0xffffffffLL); };
    // The true path's points binned in the same cells: each true room reads
    // the points near its box once, for its floor and for whether it was entered.
    std::unordered_map<int64_t, std::vector<Vec2>> path_cells;
    for (const Vec2& p : true_path) path_cells[Key(C(p.x()), C(p.y()))].push_back(p);
    std::vector<double> entered_iou;
    for (const auto& r : plan.rooms) {
      polys.push_back(Poly(r.polygon));
      boxes.emplace_back();
      bg::envelope(polys.back(), boxes.back());
      const auto& b = boxes.back();
      for (int64_t y = C(b.min_corner().y()); y <= C(b.max_corner().y()); ++y)
        for (int64_t x = C(b.min_corner().x()); x <= C(b.max_corner().x()); ++x)
          grid[Key(x, y)].push_back(static_cast<int>(polys.size()) - 1);
    }
    for (const NamedBox& t : truth.rooms) {
      const BPoly tp = Poly({t.min, {t.max.x(), t.min.y()}, t.max, {t.min.x(), t.max.y()}});
      const double ta = bg::area(tp);
      std::vector<int> cand;
      for (int64_t y = C(t.min.y()); y <= C(t.max.y()); ++y)
        for (int64_t x = C(t.min.x()); x <= C(t.max.x()); ++x) {
          auto it = grid.find(Key(x, y));
          if (it != grid.end()) cand.insert(cand.end(), it->second.begin(), it->second.end());
        }
      std::sort(cand.begin(), cand.end());
      cand.erase(std::unique(cand.begin(), cand.end()), cand.end());
      // The path's points in the box, and within a floor cell beyond its
      // upper sides (the floor's last cells reach that far).
      const NamedBox reach{"", t.min, t.max + Vec2(o.room_cell_m, o.room_cell_m)};
      std::vector<Vec2> near;
      for (int64_t y = C(reach.min.y()); y <= C(reach.max.y()); ++y)
        for (int64_t x = C(reach.min.x()); x <= C(reach.max.x()); ++x) {
          auto it = path_cells.find(Key(x, y));
          if (it == path_cells.end()) continue;
          for (const Vec2& p : it->second)
            if (reach.Contains(p)) near.push_back(p);
        }
      const bool entered = std::any_of(near.begin(), near.end(), [&](const Vec2& p) { return t.Contains(p); });
      // Its floor only when some plan room may overlap it (else the IoU is 0).
      const std::optional<RoomFloor> floor =
          cand.empty() ? std::nullopt : ReachableFloor(t, truth.walls, near, o.room_cell_m, o.room_margin_m);
      double best = 0.0;
      for (int j : cand) {
        if (floor) {
          best = std::max(best, FloorIou(*floor, polys[j], boxes[j]));
          continue;
        }
        const double inter = IntersectionArea(tp, polys[j]);
        const double uni = ta + bg::area(polys[j]) - inter;
        if (uni > 0) best = std::max(best, inter / uni);
      }
      m.room_iou.push_back(best);
      m.room_entered.push_back(entered);
      if (entered) entered_iou.push_back(best);
    }
    m.room_iou_median = median(m.room_iou);
    m.rooms_entered = static_cast<int>(entered_iou.size());
    if (!entered_iou.empty()) m.room_iou_median_entered = median(entered_iou);
  }
  return m;
}

std::vector<std::pair<std::string, std::optional<double>>> PlanEvalKeys(const PlanMetrics& m, bool with_truth) {
  std::vector<std::pair<std::string, std::optional<double>>> out = {
      {"plan_walls", m.walls},
      {"plan_rooms", m.rooms},
      {"plan_doors", m.doors},
      {"plan_wall_length_m", m.wall_length_m},
      {"plan_vertices_per_m", m.vertices_per_m},
      {"room_overlap_m2", m.room_overlap_m2},
  };
  if (with_truth) {
    out.push_back({"plan_wall_precision_p50_m", m.precision_p50_m});
    out.push_back({"plan_wall_precision_p95_m", m.precision_p95_m});
    out.push_back({"plan_wall_recall", m.recall});
    out.push_back({"plan_duplication", m.duplication});
    out.push_back({"room_iou_median", m.room_iou_median});
    out.push_back({"rooms_entered", m.rooms_entered});
    out.push_back({"room_iou_median_entered", m.room_iou_median_entered});
  }
  return out;
}

}  // namespace cogmap::eval
