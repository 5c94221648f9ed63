#include "cogmap/grid/range_fusion.h"

#include "cogmap/core/bresenham.h"
#include "cogmap/grid/cone_row.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>

#include "cogmap/core/angles.h"
#include "cogmap/core/error.h"

namespace cogmap::grid {
namespace {

// Grows 'g' (or creates it, when empty) so that [lo, hi] lies inside. The
// first grid's origin sits on the cell lattice of 'cell_m' through (0, 0), so
// that every run of the same log puts cells at the same world positions.
template <typename T>
void ReachBox(Grid2D<T>* g, const Vec2& lo, const Vec2& hi, const GridBounds& bounds, T fill) {
  if (!lo.allFinite() || !hi.allFinite()) throw InputError("pose or range is not a finite number");
  {
    Vec2 a = lo, b = hi;
    if (g->limits().width() > 0) {
      a = a.cwiseMin(g->limits().origin());
      b = b.cwiseMax(g->limits().max());
    }
    const double pad = 2.0 * std::max(1, bounds.grow_chunk_cells);
    const double cells = ((b.x() - a.x()) / bounds.cell_m + pad) * ((b.y() - a.y()) / bounds.cell_m + pad);
    if (cells > static_cast<double>(bounds.max_cells)) {
      // Printed as a double: the count may be beyond any integer type.
      char text[160];
      std::snprintf(text, sizeof text, "the grid would need %.3g cells of %g m (limit %lld): use larger cells or a "
                    "bounded grid", cells, bounds.cell_m, static_cast<long long>(bounds.max_cells));
      throw InputError(text);
    }
  }
  if (g->limits().width() == 0) {
    const double c = bounds.cell_m;
    const int chunk = std::max(1, bounds.grow_chunk_cells);
    const int x0 = static_cast<int>(std::floor(lo.x() / c)) - chunk / 2;
    const int y0 = static_cast<int>(std::floor(lo.y() / c)) - chunk / 2;
    const int x1 = static_cast<int>(std::floor(hi.x() / c)) + chunk / 2;
    const int y1 = static_cast<int>(std::floor(hi.y() / c)) + chunk / 2;
    *g = Grid2D<T>(MapLimits(c, Vec2(x0 * c, y0 * c), x1 - x0 + 1, y1 - y0 + 1), fill);
    return;
  }
  g->EnsureContains(lo, hi, std::max(1, bounds.grow_chunk_cells));
}

bool ValidRange(double range_m) { return std::isfinite(range_m) && range_m >= 0.0; }

}  // namespace

FusionRule ParseFusionRule(const std::string& name) {
  if (name == "himm") return FusionRule::kHimm;
  if (name == "mhimm") return FusionRule::kMhimm;
  if (name == "bayes") return FusionRule::kBayes;
  if (name == "ds" || name == "dempster-shafer") return FusionRule::kDempsterShafer;
  throw InputError("unknown fusion rule '" + name + "' (known: himm, mhimm, bayes, ds)");
}

std::string FusionRuleName(FusionRule rule) {
  switch (rule) {
    case FusionRule::kHimm: return "himm";
    case FusionRule::kMhimm: return "mhimm";
    case FusionRule::kBayes: return "bayes";
    case FusionRule::kDempsterShafer: return "ds";
  }
  return "?";
}

std::vector<std::string> FusionRuleNames() { return {"himm", "mhimm", "bayes", "ds"}; }

void RangeFusion::InsertSweep(const Pose2& world_from_robot, const sensors::RobotDescription& robot,
                              std::span<const sensors::RangeReading> readings) {
  MarkRobot(world_from_robot);
  for (const auto& r : readings) {
    if (r.sensor < 0 || r.sensor >= static_cast<int>(robot.sensors.size())) {
      ++stats_.readings;
      ++stats_.ignored;
      continue;
    }
    Insert(world_from_robot, robot.sensors[r.sensor], r.range_m);
  }
}

Grid2D<CellClass> RangeFusion::Classes() const {
  Grid2D<CellClass> out(limits(), CellClass::kUnknown);
  for (int y = 0; y < limits().height(); ++y)
    for (int x = 0; x < limits().width(); ++x) out.at(x, y) = Classify(x, y);
  return out;
}

// ---------------------------------------------------------------- HIMM / MHIMM

HimmFusion::HimmFusion(bool modified, const MhimmOptions& options, const GridBounds& bounds)
    : modified_(modified), options_(options), bounds_(bounds), bounded_(bounds.fixed.has_value()) {
  if (bounded_) {
    grid_ = Grid2D<float>(*bounds.fixed, 0.0f);
    bounds_.cell_m = bounds.fixed->cell_m();
  }
}

void HimmFusion::Reach(const Vec2& lo, const Vec2& hi) {
  if (bounded_) return;
  const int w = grid_.limits().width(), h = grid_.limits().height();
  const Vec2 origin = grid_.limits().origin();
  ReachBox(&grid_, lo, hi, bounds_, 0.0f);
  // The hit distances grow alike (from the same limits, the same limits),
  // when the grid did.
  if (track_distance_ && (grid_.limits().width() != w || grid_.limits().height() != h ||
                          grid_.limits().origin() != origin)) {
    ReachBox(&hit_distance_sum_, lo, hi, bounds_, 0.0f);
    ReachBox(&hit_weight_, lo, hi, bounds_, 0.0f);
  }
}

void HimmFusion::SetDistance(double s_m) {
  if (!track_distance_) {
    hit_distance_sum_ = Grid2D<float>(grid_.limits(), 0.0f);
    hit_weight_ = Grid2D<float>(grid_.limits(), 0.0f);
    track_distance_ = true;
  }
  distance_ = s_m;
}

void HimmFusion::MarkRobot(const Pose2& world_from_robot) {
  ++stats_.robot_updates;
  if (!modified_) return;
  const Vec2 p = world_from_robot.translation();
  const bool join = last_path_point_ && options_.join_path_max_m > 0.0 &&
                    (p - *last_path_point_).norm() <= options_.join_path_max_m;
  if (join) {
    Reach(p.cwiseMin(*last_path_point_), p.cwiseMax(*last_path_point_));
  } else {
    Reach(p, p);
  }
  const CellIndex c = grid_.limits().CellOf(p);
  if (join) {
    const CellIndex a = grid_.limits().CellOf(*last_path_point_);
    WalkBresenham(a.x(), a.y(), c.x(), c.y(), [&](int x, int y) {
      if (grid_.limits().Contains(CellIndex(x, y))) grid_.at(x, y) = options_.robot_path;
      return true;
    });
  } else if (grid_.limits().Contains(c)) {
    grid_.at(c) = options_.robot_path;
  }
  last_path_point_ = p;
}

void HimmFusion::Insert(const Pose2& world_from_robot, const sensors::RangeSensor& sensor,
                        double range_m) {
  const Pose2 sp = sensors::SensorPose(world_from_robot, sensor);
  const Vec2 robot = world_from_robot.translation();
  Reach(robot, robot);
  InsertRay(grid_.limits().CellOf(robot), sp.x, sp.y, std::cos(sp.theta), std::sin(sp.theta),
            sensor, range_m);
}

void HimmFusion::InsertSweep(const Pose2& world_from_robot, const sensors::RobotDescription& robot,
                             std::span<const sensors::RangeReading> readings) {
  MarkRobot(world_from_robot);
  // One box for the whole sweep, so that no reading needs to grow the grid.
  double reach = 0.0;
  for (const auto& s : robot.sensors)
    reach = std::max(reach, s.robot_from_sensor.translation().norm() +
                                std::min(options_.window_m, s.max_range_m));
  const Vec2 p = world_from_robot.translation();
  const double margin = reach + 2.0 * bounds_.cell_m;
  Reach(p - Vec2(margin, margin), p + Vec2(margin, margin));
  CellIndex r0 = grid_.limits().CellOf(p);
  Vec2 origin = grid_.limits().origin();
  const double c = std::cos(world_from_robot.theta), s = std::sin(world_from_robot.theta);
  for (const auto& r : readings) {
    if (grid_.limits().origin() != origin) {  // a reading grew the grid
      origin = grid_.limits().origin();
      r0 = grid_.limits().CellOf(p);
    }
    if (r.sensor < 0 || r.sensor >= static_cast<int>(robot.sensors.size())) {
      ++stats_.readings;
      ++stats_.ignored;
      continue;
    }
    const sensors::RangeSensor& sensor = robot.sensors[r.sensor];
    const Pose2& m = sensor.robot_from_sensor;
    // Sensor pose by composing rotations (eq. 3.5); the mount's turn is
    // taken once per sensor.
    if (mount_turn_.size() <= static_cast<size_t>(r.sensor))
      mount_turn_.resize(robot.sensors.size(), {std::numeric_limits<double>::quiet_NaN(), 0.0, 0.0});
    MountTurn& turn = mount_turn_[r.sensor];
    if (!(turn.theta == m.theta)) turn = {m.theta, std::cos(m.theta), std::sin(m.theta)};
    const double cm = turn.c, sm = turn.s;
    const double sx = world_from_robot.x + c * m.x - s * m.y;
    const double sy = world_from_robot.y + s * m.x + c * m.y;
    InsertRay(r0, sx, sy, c * cm - s * sm, s * cm + c * sm, sensor, r.range_m);
  }
}

void HimmFusion::InsertRay(const CellIndex& r0, double sx, double sy, double cos_h, double sin_h,
                           const sensors::RangeSensor& sensor, double range_m) {
  ++stats_.readings;
  if (!ValidRange(range_m) || (options_.ignore_below_min_range && range_m < sensor.min_range_m)) {
    ++stats_.ignored;
    return;
  }
  const bool hit = range_m < sensor.max_range_m && range_m < options_.window_m;
  if (!hit) {
    ++stats_.misses;
    if (!modified_) return;  // HIMM fuses hits only (§2.2.3)
  } else {
    ++stats_.hits;
  }
  // Hit: the end point. Miss (MHIMM): the window boundary, or the max range
  // when that is nearer (SPEC 2).
  const double d = hit ? range_m : std::min(options_.window_m, sensor.max_range_m);
  const MapLimits* lim = &grid_.limits();
  const double inv = 1.0 / lim->cell_m();
  const double ex = sx + d * cos_h, ey = sy + d * sin_h;
  int tx = static_cast<int>(std::floor((ex - lim->origin().x()) * inv));
  int ty = static_cast<int>(std::floor((ey - lim->origin().y()) * inv));
  int x0 = r0.x(), y0 = r0.y();
  if (!bounded_ && (tx < 1 || ty < 1 || tx + 1 >= lim->width() || ty + 1 >= lim->height() ||
                    !lim->Contains(r0))) {
    // Only a lone Insert gets here: grow around both ends, then recompute.
    const Vec2 origin = lim->origin();
    const Vec2 r0w = lim->CenterOf(r0);
    const Vec2 e(ex, ey);
    const double pad = 2.0 * lim->cell_m();
    Reach(r0w.cwiseMin(e) - Vec2(pad, pad), r0w.cwiseMax(e) + Vec2(pad, pad));
    const Vec2 shift = (origin - lim->origin()) * inv;
    const int ddx = static_cast<int>(std::lround(shift.x())), ddy = static_cast<int>(std::lround(shift.y()));
    InsertRay(CellIndex(x0 + ddx, y0 + ddy), sx, sy, cos_h, sin_h, sensor, range_m);
    --stats_.readings;
    if (hit) --stats_.hits; else --stats_.misses;
    return;
  }

  float* cells = grid_.cells().data();
  const int w = lim->width(), h = lim->height();
  const float path = modified_ ? options_.robot_path : -std::numeric_limits<float>::infinity();
  const float lo = options_.min_value, hi = options_.max_value;
  const float dec = options_.beam_decrement;
  const bool checked = bounded_;
  auto decrement = [&](int x, int y) {
    if (checked && (static_cast<unsigned>(x) >= static_cast<unsigned>(w) ||
                    static_cast<unsigned>(y) >= static_cast<unsigned>(h)))
      return;
    float& v = cells[static_cast<long>(y) * w + x];
    if (v != path) v = std::max(v - dec, lo);
  };
  auto add = [&](int x, int y, float inc) {
    if (checked && (static_cast<unsigned>(x) >= static_cast<unsigned>(w) ||
                    static_cast<unsigned>(y) >= static_cast<unsigned>(h)))
      return;
    float& v = cells[static_cast<long>(y) * w + x];
    if (v != path) v = std::min(v + inc, hi);
  };

  // Integer Bresenham from r0 to t: r0 excluded; t excluded on a hit and
  // cleared on a miss.
  const int dx = std::abs(tx - x0), sxs = x0 < tx ? 1 : -1;
  const int dy = -std::abs(ty - y0), sys = y0 < ty ? 1 : -1;
  int err = dx + dy;
  while (x0 != tx || y0 != ty) {
    const int e2 = 2 * err;
    if (e2 >= dy) { err += dy; x0 += sxs; }
    if (e2 <= dx) { err += dx; y0 += sys; }
    if (x0 == tx && y0 == ty) break;
    decrement(x0, y0);
  }
  if (!hit) {
    if (tx != r0.x() || ty != r0.y()) decrement(tx, ty);
    return;
  }
  // The cone (default mode, MhimmOptions::cone_hits): free evidence over the
  // cone nearer than the echo, and the hit on the echo's arc.
  const double half = 0.5 * sensor.beam_width_rad;
  if (modified_ && options_.cone_hits && half * d >= lim->cell_m()) {
    const double cell = lim->cell_m();
    const double ox = lim->origin().x(), oy = lim->origin().y();
    const double reach = d - 1.5 * cell;
    if (reach > 0.0) {
      // The sector's box: its apex, the two ends of its arc and the arc's
      // point on the axis (the farthest along it).
      const double ca = std::cos(half), sa = std::sin(half);
      const double lx = cos_h * ca - sin_h * sa, ly = sin_h * ca + cos_h * sa;  // left edge
      const double rx = cos_h * ca + sin_h * sa, ry = sin_h * ca - cos_h * sa;  // right edge
      const double bx0 = std::min({0.0, reach * lx, reach * rx, reach * cos_h});
      const double bx1 = std::max({0.0, reach * lx, reach * rx, reach * cos_h});
      const double by0 = std::min({0.0, reach * ly, reach * ry, reach * sin_h});
      const double by1 = std::max({0.0, reach * ly, reach * ry, reach * sin_h});
      const int x_lo = std::max(0, static_cast<int>(std::floor((sx + bx0 - ox) * inv)));
      const int x_hi = std::min(w - 1, static_cast<int>(std::floor((sx + bx1 - ox) * inv)));
      const int y_lo = std::max(0, static_cast<int>(std::floor((sy + by0 - oy) * inv)));
      const int y_hi = std::min(h - 1, static_cast<int>(std::floor((sy + by1 - oy) * inv)));
      const double reach2 = reach * reach, cos2 = ca * ca, inv_half = 1.0 / half;
      for (int y = y_lo; y <= y_hi; ++y) {
        // The row's cells that can lie in the sector: within the disk and
        // between the two edges (each a half-plane through the apex; the
        // sector is their intersection with the disk, half-angle < 90
        // degrees). One cell of margin each side; the test below decides.
        const double py = oy + (y + 0.5) * cell - sy;
        const double disk2 = reach2 - py * py;
        if (disk2 <= 0.0) continue;
        double p_lo = -std::sqrt(disk2), p_hi = -p_lo;
        // Right edge: ry * px <= rx * py; left edge: ly * px >= lx * py.
        if (ry > 1e-9) p_hi = std::min(p_hi, rx * py / ry);
        else if (ry < -1e-9) p_lo = std::max(p_lo, rx * py / ry);
        if (ly > 1e-9) p_lo = std::max(p_lo, lx * py / ly);
        else if (ly < -1e-9) p_hi = std::min(p_hi, lx * py / ly);
        if (p_lo > p_hi + cell) continue;
        const int xa = std::max(x_lo, static_cast<int>(std::floor((sx + p_lo - ox) * inv - 0.5)) - 1);
        const int xb = std::min(x_hi, static_cast<int>(std::ceil((sx + p_hi - ox) * inv - 0.5)) + 1);
        // The row's cells (cone_row.h: two at a time where the CPU can).
        ConeRow row{ox, cell, sx, py, cos_h, sin_h, reach2, cos2, half, inv_half, dec, path, lo};
        row.Decrement(cells + static_cast<long>(y) * w, xa, xb);
      }
    }
    // The arc at d, one cell apart, from the axis outwards (0, +1, -1, +2, -2, ...).
    const int n = static_cast<int>(std::ceil(half * d * inv));
    const double heading = std::atan2(sin_h, cos_h);
    for (int j = 0; j <= 2 * n; ++j) {
      const int k = (j + 1) / 2 * (j % 2 ? 1 : -1);
      const double a = heading + half * k / n;
      const int cx = static_cast<int>(std::floor((sx + d * std::cos(a) - ox) * inv));
      const int cy = static_cast<int>(std::floor((sy + d * std::sin(a) - oy) * inv));
      if (static_cast<unsigned>(cx) >= static_cast<unsigned>(w) || static_cast<unsigned>(cy) >= static_cast<unsigned>(h))
        continue;
      const float v = cells[static_cast<long>(cy) * w + cx];
      if (v < 0.0f || v == path) continue;
      tx = cx, ty = cy;
      break;
    }
  }
  // Beam first, then the hit: t +3, its 8 neighbours +1.5 (SPEC 2).
  add(tx, ty, options_.hit_increment);
  if (track_distance_ && static_cast<unsigned>(tx) < static_cast<unsigned>(w) &&
      static_cast<unsigned>(ty) < static_cast<unsigned>(h)) {
    const long at = static_cast<long>(ty) * w + tx;
    hit_distance_sum_.cells()[at] += static_cast<float>(options_.hit_increment * distance_);
    hit_weight_.cells()[at] += options_.hit_increment;
  }
  const float n = options_.neighbour_increment;
  add(tx - 1, ty - 1, n); add(tx, ty - 1, n); add(tx + 1, ty - 1, n);
  add(tx - 1, ty, n);                         add(tx + 1, ty, n);
  add(tx - 1, ty + 1, n); add(tx, ty + 1, n); add(tx + 1, ty + 1, n);
}

std::optional<double> HimmFusion::HitDistance(const Vec2& p, double radius_m) const {
  if (!track_distance_) return std::nullopt;
  const MapLimits& lim = hit_weight_.limits();
  const double cell = lim.cell_m();
  const CellIndex c = lim.CellOf(p);
  const int r = std::max(0, static_cast<int>(std::ceil(radius_m / cell)));
  double sum = 0.0, weight = 0.0;
  for (int y = std::max(0, c.y() - r); y <= std::min(lim.height() - 1, c.y() + r); ++y)
    for (int x = std::max(0, c.x() - r); x <= std::min(lim.width() - 1, c.x() + r); ++x) {
      if ((lim.CenterOf(CellIndex(x, y)) - p).norm() > radius_m + 0.5 * cell) continue;
      sum += hit_distance_sum_.at(x, y);
      weight += hit_weight_.at(x, y);
    }
  if (!(weight > 0.0)) return std::nullopt;
  return sum / weight;
}

Grid2D<float> HimmFusion::Occupancy() const {
  Grid2D<float> out(grid_.limits(), 0.5f);
  const auto& v = grid_.cells();
  auto& o = out.cells();
  const float span = options_.max_value;
  for (size_t i = 0; i < v.size(); ++i) {
    if (modified_ && v[i] == options_.robot_path) o[i] = 0.0f;
    else if (v[i] > 0) o[i] = 0.5f + 0.5f * v[i] / span;
    else if (v[i] < 0) o[i] = 0.5f + 0.5f * v[i] / -options_.min_value;
  }
  return out;
}

CellClass HimmFusion::Classify(int x, int y) const {
  const float v = grid_.get(x, y);
  if (modified_ && v == options_.robot_path) return CellClass::kRobotPath;
  if (v > options_.occupied_threshold) return CellClass::kOccupied;
  if (v < 0) return CellClass::kEmpty;
  return CellClass::kUnknown;  // HIMM cannot tell empty from unknown
}

// ---------------------------------------------------------------- Bayes / DS

ConeFusion::ConeFusion(bool dempster_shafer, const ConeOptions& options, const GridBounds& bounds)
    : ds_(dempster_shafer), options_(options), bounds_(bounds), bounded_(bounds.fixed.has_value()) {
  if (bounded_) {
    occupied_ = Grid2D<float>(*bounds.fixed, 0.0f);
    empty_ = Grid2D<float>(*bounds.fixed, 0.0f);
    touched_ = Grid2D<uint8_t>(*bounds.fixed, 0);
    bounds_.cell_m = bounds.fixed->cell_m();
  }
}

void ConeFusion::Reach(const Vec2& lo, const Vec2& hi) {
  if (bounded_) return;
  ReachBox(&occupied_, lo, hi, bounds_, 0.0f);
  ReachBox(&empty_, lo, hi, bounds_, 0.0f);
  ReachBox(&touched_, lo, hi, bounds_, uint8_t{0});
}

void ConeFusion::MarkRobot(const Pose2& world_from_robot) {
  ++stats_.robot_updates;
  const Vec2 p = world_from_robot.translation();
  Reach(p, p);
  const CellIndex c = touched_.limits().CellOf(p);
  if (touched_.limits().Contains(c)) touched_.at(c) = 2;
}

void ConeFusion::Update(long flat, bool arc, double f) {
  f = std::clamp(f, 0.0, 1.0);
  float& o = occupied_.cells()[flat];
  if (!ds_) {
    // Table 2.2 and eq. 2.9 in log-odds: l += log(P(s|H) / P(s|not H)).
    constexpr double kEps = 1e-3;
    double p_occ = arc ? f * options_.max_occupied : 1.0 - f;
    if (!arc && options_.region2_never_occupied) p_occ = std::min(p_occ, 0.5);
    p_occ = std::clamp(p_occ, kEps, 1.0 - kEps);
    const float l = o + static_cast<float>(std::log(p_occ / (1.0 - p_occ)));
    o = std::clamp(l, -options_.log_odds_clamp, options_.log_odds_clamp);
  } else {
    // Table 2.3 masses combined by Dempster's rule (eq. 2.11-2.13).
    float& e = empty_.cells()[flat];
    const double m1o = o, m1e = e, m1u = std::max(0.0, 1.0 - m1o - m1e);
    const double m2o = arc ? f * options_.max_occupied : 0.0;
    const double m2e = arc ? 0.0 : f;
    const double m2u = 1.0 - m2o - m2e;
    const double conflict = m1o * m2e + m1e * m2o;
    const double norm = 1.0 - conflict;
    if (norm <= 1e-9) return;  // total conflict: Dempster's rule is undefined; keep the cell
    o = static_cast<float>((m1o * m2o + m1o * m2u + m1u * m2o) / norm);
    e = static_cast<float>((m1e * m2e + m1e * m2u + m1u * m2e) / norm);
  }
  if (touched_.cells()[flat] == 0) touched_.cells()[flat] = 1;
}

void ConeFusion::Insert(const Pose2& world_from_robot, const sensors::RangeSensor& sensor,
                        double range_m) {
  ++stats_.readings;
  if (!ValidRange(range_m) || (options_.ignore_below_min_range && range_m < sensor.min_range_m)) {
    ++stats_.ignored;
    return;
  }
  const bool hit = range_m < sensor.max_range_m && range_m < options_.window_m;
  if (hit) ++stats_.hits; else ++stats_.misses;
  const Pose2 sp = sensors::SensorPose(world_from_robot, sensor);
  const double beta = 0.5 * sensor.beam_width_rad;
  const double tol = options_.region_half_width_m;
  const double reach = hit ? range_m + tol : std::min(options_.window_m, sensor.max_range_m);
  const double big_r = sensor.max_range_m;
  const double c = std::cos(sp.theta), s = std::sin(sp.theta);

  // Bounding box of the sector: apex, both edge ends, and the axis extremes
  // the sector spans.
  Vec2 lo(sp.x, sp.y), hi = lo;
  auto include = [&](double angle) {
    const Vec2 q(sp.x + reach * std::cos(angle), sp.y + reach * std::sin(angle));
    lo = lo.cwiseMin(q);
    hi = hi.cwiseMax(q);
  };
  include(sp.theta - beta);
  include(sp.theta + beta);
  include(sp.theta);
  for (int k = 0; k < 4; ++k) {
    const double a = k * kPi / 2;
    if (std::abs(AngleDiff(a, sp.theta)) <= beta) include(a);
  }
  const Vec2 pad(bounds_.cell_m, bounds_.cell_m);
  Reach(lo - pad, hi + pad);
  const MapLimits& lim = occupied_.limits();
  CellIndex a = lim.CellOf(lo), b = lim.CellOf(hi);
  a = a.cwiseMax(CellIndex(0, 0));
  b = b.cwiseMin(CellIndex(lim.width() - 1, lim.height() - 1));
  const double reach2 = reach * reach, cos_beta = std::cos(beta);
  const bool narrow = beta < kPi / 2;
  for (int y = a.y(); y <= b.y(); ++y) {
    for (int x = a.x(); x <= b.x(); ++x) {
      const Vec2 ctr = lim.CenterOf(CellIndex(x, y));
      const double dx = ctr.x() - sp.x, dy = ctr.y() - sp.y;
      const double d2 = dx * dx + dy * dy;
      if (d2 > reach2 || d2 <= 0.0) continue;
      const double along = dx * c + dy * s;
      if (narrow && (along <= 0.0 || along * along < d2 * cos_beta * cos_beta)) continue;  // outside
      const double d = std::sqrt(d2);
      const double across = c * dy - s * dx;
      const double alpha = std::atan2(std::abs(across), along);
      if (alpha > beta) continue;
      const bool arc = hit && d >= range_m - tol;
      const double f = ((big_r - d) / big_r + (beta - alpha) / beta) / 2.0;
      Update(lim.Flat(x, y), arc, f);
    }
  }
}

float ConeFusion::OccupancyAt(int x, int y) const {
  if (!ds_) {
    const float l = occupied_.get(x, y);
    return 1.0f / (1.0f + std::exp(-l));
  }
  const float o = occupied_.get(x, y), e = empty_.get(x, y);
  return o + 0.5f * std::max(0.0f, 1.0f - o - e);  // pignistic probability
}

Grid2D<float> ConeFusion::Values() const {
  if (!ds_) return occupied_;
  return Occupancy();
}

Grid2D<float> ConeFusion::Occupancy() const {
  Grid2D<float> out(occupied_.limits(), 0.5f);
  for (int y = 0; y < out.limits().height(); ++y)
    for (int x = 0; x < out.limits().width(); ++x) out.at(x, y) = OccupancyAt(x, y);
  return out;
}

CellClass ConeFusion::Classify(int x, int y) const {
  const uint8_t t = touched_.get(x, y);
  if (t == 2) return CellClass::kRobotPath;
  if (t == 0) return CellClass::kUnknown;
  const float p = OccupancyAt(x, y);
  if (p > options_.occupied_probability) return CellClass::kOccupied;
  if (p < options_.free_probability) return CellClass::kEmpty;
  return CellClass::kUnknown;
}

std::unique_ptr<RangeFusion> MakeFusion(FusionRule rule, const FusionOptions& options) {
  switch (rule) {
    case FusionRule::kHimm: {
      MhimmOptions o;
      static_cast<HimmOptions&>(o) = options.himm;
      return std::make_unique<HimmFusion>(false, o, options.bounds);
    }
    case FusionRule::kMhimm:
      return std::make_unique<HimmFusion>(true, options.mhimm, options.bounds);
    case FusionRule::kBayes:
      return std::make_unique<ConeFusion>(false, options.cone, options.bounds);
    case FusionRule::kDempsterShafer:
      return std::make_unique<ConeFusion>(true, options.cone, options.bounds);
  }
  return nullptr;
}

}  // namespace cogmap::grid
