#include "cogmap/vectorize/line_extract.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>

#include "cogmap/core/angles.h"
#include "cogmap/vectorize/line_fit.h"

namespace cogmap::vectorize {
namespace {

Vec2 Perp(const Vec2& v) { return {-v.y(), v.x()}; }

// Sequential Hough: an accumulator that points can leave.
class Hough {
 public:
  Hough(const std::vector<Vec2>& points, int width, int height, const LineExtractOptions& o)
      : points_(points), bins_(std::max(8, o.theta_bins)), rho_bin_(std::max(0.1, o.rho_bin_cells)) {
    reach_ = std::hypot(width, height) + 2.0;
    rhos_ = static_cast<int>(std::ceil(2.0 * reach_ / rho_bin_)) + 1;
    cos_.resize(bins_);
    sin_.resize(bins_);
    for (int k = 0; k < bins_; ++k) {
      const double t = kPi * k / bins_;
      cos_[k] = std::cos(t);
      sin_[k] = std::sin(t);
    }
    acc_.assign(static_cast<size_t>(bins_) * rhos_, 0);
    for (size_t i = 0; i < points_.size(); ++i) Vote(static_cast<int>(i), +1);
  }

  void Vote(int i, int sign) {
    const Vec2& p = points_[i];
    for (int k = 0; k < bins_; ++k) {
      const double rho = p.x() * cos_[k] + p.y() * sin_[k];
      const int r = std::clamp(static_cast<int>(std::floor((rho + reach_) / rho_bin_)), 0, rhos_ - 1);
      acc_[static_cast<size_t>(k) * rhos_ + r] += sign;
    }
  }

  // The strongest bin: its votes, its unit normal and distance.
  int Peak(Vec2* normal, double* rho) const {
    const auto it = std::max_element(acc_.begin(), acc_.end());
    const size_t at = static_cast<size_t>(it - acc_.begin());
    const int k = static_cast<int>(at / rhos_), r = static_cast<int>(at % rhos_);
    *normal = Vec2(cos_[k], sin_[k]);
    *rho = (r + 0.5) * rho_bin_ - reach_;
    return *it;
  }

 private:
  const std::vector<Vec2>& points_;
  int bins_;
  double rho_bin_;
  double reach_ = 0.0;
  int rhos_ = 0;
  std::vector<double> cos_, sin_;
  std::vector<int> acc_;
};

struct Seg {
  Vec2 end[2];
  Vec2 dir{1, 0};  // unit, end[0] -> end[1]
  int points = 0;
  double rms = 0.0;
  bool dropped = false;
  int link_seg[2] = {-1, -1};  // the segment joined at each end (a corner)
  int link_end[2] = {-1, -1};
  bool moved[2] = {false, false};
  double length() const { return (end[1] - end[0]).norm(); }
  Vec2 mid() const { return 0.5 * (end[0] + end[1]); }
};

// The crossing of the lines of two segments; false when they are closer to
// parallel than min_sin.
bool Crossing(const Seg& a, const Seg& b, double min_sin, Vec2* x) {
  const double c = Cross(a.dir, b.dir);
  if (std::abs(c) < min_sin) return false;
  const double s = Cross(b.end[0] - a.end[0], b.dir) / c;
  *x = a.end[0] + s * a.dir;
  return true;
}

// X lies on the side of end e of s (moving e to X keeps at least half of s).
bool Toward(const Seg& s, int e, const Vec2& x) { return (x - s.mid()).dot(s.end[e] - s.mid()) > 0.0; }

}  // namespace

LineExtractResult ExtractWallLines(const grid::Grid2D<float>& cleaned, const grid::Grid2D<float>& raw,
                                   const LineExtractOptions& options) {
  LineExtractResult out;
  LineExtractStats& st = out.stats;
  const auto& lim = cleaned.limits();
  const int w = lim.width(), h = lim.height();
  if (w <= 0 || h <= 0) return out;
  const CellClasses& cls = options.classes;
  const bool raw_ok = raw.limits().width() == w && raw.limits().height() == h;

  std::vector<Vec2> points;
  std::vector<Vec2> path;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      if (cls.IsOccupied((options.all_occupied && raw_ok ? raw : cleaned).at(x, y))) points.push_back(Vec2(x + 0.5, y + 0.5));
      if (raw_ok && cls.IsPath(raw.at(x, y))) path.push_back(Vec2(x + 0.5, y + 0.5));
    }
  st.points = static_cast<int64_t>(points.size());
  if (points.empty()) return out;

  auto raw_occupied = [&](const Vec2& q) {
    if (!raw_ok) return false;
    const int x = static_cast<int>(std::floor(q.x())), y = static_cast<int>(std::floor(q.y()));
    return x >= 0 && y >= 0 && x < w && y < h && cls.IsOccupied(raw.at(x, y));
  };
  const double door_cells = options.door_gap_m / lim.cell_m();
  const int min_points = std::max(2, options.min_points);

  // 1. Lines, strongest first.
  Hough hough(points, w, h, options);
  std::vector<char> alive(points.size(), 1);
  std::vector<Seg> segs;
  std::vector<int> in;
  std::vector<Vec2> pts;
  for (int iter = 0; iter < options.max_lines; ++iter) {
    Vec2 normal;
    double rho = 0.0;
    if (hough.Peak(&normal, &rho) < min_points) break;
    ++st.lines;
    // Inliers of the peak's line, then of its total-least-squares refits.
    auto collect = [&](const Vec2& n, double c, double band) {
      in.clear();
      for (size_t i = 0; i < points.size(); ++i)
        if (alive[i] && std::abs(points[i].dot(n) - c) <= band) in.push_back(static_cast<int>(i));
    };
    collect(normal, rho, std::max(options.first_band_cells, 0.5 * options.rho_bin_cells));
    Vec2 origin = normal * rho, dir = Perp(normal);
    double rms = 0.0;
    LineFitOptions tls;
    tls.mode = FitMode::kDefault;
    for (int r = 0; r < options.refits && in.size() >= 2; ++r) {
      pts.clear();
      for (int i : in) pts.push_back(points[i]);
      const FittedLine f = FitLine(pts, tls);
      if (f.direction.norm() < 0.5 || (f.quality == 0.0 && pts.size() < 2)) break;
      origin = f.point;
      dir = f.direction;
      rms = f.quality;
      const Vec2 n = Perp(dir);
      const double band = std::clamp(options.band_sigmas * rms, options.min_band_cells, options.max_band_cells);
      const std::vector<int> before = in;
      collect(n, origin.dot(n), band);
      if (in.size() < 2) {
        in = before;
        break;
      }
    }
    // Every inlier leaves the accumulator, whatever becomes of its run.
    for (int i : in) {
      alive[i] = 0;
      hough.Vote(i, -1);
    }
    const size_t first_seg = segs.size();
    // Runs along the line, split at gaps.
    std::vector<std::pair<double, int>> along;
    along.reserve(in.size());
    for (int i : in) along.push_back({(points[i] - origin).dot(dir), i});
    std::sort(along.begin(), along.end());
    const Vec2 n = Perp(dir);
    auto evidence = [&](double t0, double t1) {
      int samples = 0, hits = 0;
      for (double t = t0 + 0.5; t < t1; t += 0.5) {
        ++samples;
        const Vec2 q = origin + t * dir;
        if (raw_occupied(q) || raw_occupied(q + n) || raw_occupied(q - n)) ++hits;
      }
      return samples == 0 || 2 * hits >= samples;
    };
    size_t start = 0;
    for (size_t k = 1; k <= along.size(); ++k) {
      bool split = k == along.size();
      if (!split) {
        const double empty = along[k].first - along[k - 1].first - 1.0;
        split = empty >= door_cells ||
                (empty >= options.min_evidence_gap_cells && !evidence(along[k - 1].first, along[k].first));
      }
      if (!split) continue;
      const int count = static_cast<int>(k - start);
      const double t0 = along[start].first - 0.5, t1 = along[k - 1].first + 0.5;
      const double len = t1 - t0;
      if (count >= min_points && len >= options.min_length_cells && count >= options.min_density * len) {
        Seg s;
        s.end[0] = origin + t0 * dir;
        s.end[1] = origin + t1 * dir;
        s.dir = dir;
        s.points = count;
        double ss = 0.0;
        for (size_t j = start; j < k; ++j) {
          const double d = (points[along[j].second] - origin).dot(n);
          ss += d * d;
        }
        s.rms = std::sqrt(ss / count);
        segs.push_back(s);
      } else {
        ++st.rejected_runs;
      }
      start = k;
    }
    // The rest of the band along the kept segments.
    for (size_t q = first_seg; q < segs.size(); ++q) {
      const Seg& g = segs[q];
      const double len = g.length();
      for (size_t i = 0; i < points.size(); ++i) {
        if (!alive[i]) continue;
        const Vec2 d = points[i] - g.end[0];
        const double t = d.dot(g.dir);
        if (t < 0.0 || t > len || std::abs(Cross(g.dir, d)) > options.clear_band_cells) continue;
        alive[i] = 0;
        hough.Vote(static_cast<int>(i), -1);
      }
    }
  }
  // 1b. Cut where the robot drove.
  const double clear = std::max(0.0, options.path_clearance_m / lim.cell_m() - 0.5);
  auto near_path = [&](const Vec2& q) {
    if (clear <= 0.0) return false;
    for (const Vec2& p : path)
      if ((p - q).squaredNorm() < clear * clear) return true;
    return false;
  };
  if (clear > 0.0 && !path.empty()) {
    std::vector<Seg> kept;
    for (const Seg& g : segs) {
      const double len = g.length();
      const int steps = std::max(1, static_cast<int>(std::ceil(len / 0.5)));
      double run0 = -1.0;
      bool cut = false;
      auto emit = [&](double t0, double t1) {
        if (t1 - t0 < options.min_length_cells) return;
        Seg piece = g;
        piece.end[0] = g.end[0] + t0 * g.dir;
        piece.end[1] = g.end[0] + t1 * g.dir;
        piece.points = static_cast<int>(std::lround(g.points * (t1 - t0) / std::max(len, 1e-9)));
        kept.push_back(piece);
      };
      for (int k = 0; k <= steps; ++k) {
        const double t = len * k / steps;
        const bool blocked = near_path(g.end[0] + t * g.dir);
        if (!blocked && run0 < 0.0) run0 = t;
        if (blocked) {
          cut = true;
          if (run0 >= 0.0) emit(run0, std::max(run0, t - len / steps));
          run0 = -1.0;
        }
      }
      if (run0 >= 0.0) emit(run0, len);
      if (cut) ++st.path_cuts;
    }
    segs = std::move(kept);
  }
  for (const Seg& s : segs) out.segments.push_back({s.end[0], s.end[1], s.points, s.rms});

  // 2. Corners.
  const double tan_half = std::tan(std::clamp(options.beam_half_width_rad, 0.0, 1.5));
  auto blur = [&](const Vec2& x) {
    double d2 = std::numeric_limits<double>::infinity();
    for (const Vec2& p : path) d2 = std::min(d2, (p - x).squaredNorm());
    const double d = std::min(options.max_range_cells, std::sqrt(d2));
    return options.blur_floor_cells + tan_half * d;
  };
  const double min_sin = std::sin(DegToRad(options.min_corner_deg));
  const int n = static_cast<int>(segs.size());
  // A corner of a and b at X: ends ea, eb within radius r of X, each toward X.
  auto corner = [&](int a, int ea, int b, int eb, Vec2* x, double* r) {
    if (!Crossing(segs[a], segs[b], min_sin, x)) return false;
    if (!Toward(segs[a], ea, *x) || !Toward(segs[b], eb, *x)) return false;
    *r = blur(*x);
    if (near_path(*x)) return false;
    return (segs[a].end[ea] - *x).norm() <= *r && (segs[b].end[eb] - *x).norm() <= *r;
  };
  // 2a. Chamfers, shortest first.
  std::vector<int> by_length(n);
  std::iota(by_length.begin(), by_length.end(), 0);
  std::sort(by_length.begin(), by_length.end(), [&](int i, int j) { return segs[i].length() < segs[j].length(); });
  for (int s : by_length) {
    const Seg& c = segs[s];
    const double len = c.length();
    bool chamfer = false;
    for (int a = 0; a < n && !chamfer; ++a) {
      if (a == s || segs[a].dropped || segs[a].length() <= len) continue;
      for (int b = a + 1; b < n && !chamfer; ++b) {
        if (b == s || segs[b].dropped || segs[b].length() <= len) continue;
        for (int ea = 0; ea < 2 && !chamfer; ++ea)
          for (int eb = 0; eb < 2 && !chamfer; ++eb) {
            Vec2 x;
            double r = 0.0;
            if (!corner(a, ea, b, eb, &x, &r)) continue;
            chamfer = len <= 2.0 * r && (c.end[0] - x).norm() <= r && (c.end[1] - x).norm() <= r;
          }
      }
    }
    if (chamfer) {
      segs[s].dropped = true;
      ++st.chamfers_removed;
    }
  }
  // 2b. Corners, closest first.
  struct Candidate {
    double cost;
    int a, ea, b, eb;
    Vec2 x;
  };
  std::vector<Candidate> cands;
  for (int a = 0; a < n; ++a)
    for (int b = a + 1; b < n; ++b) {
      if (segs[a].dropped || segs[b].dropped) continue;
      for (int ea = 0; ea < 2; ++ea)
        for (int eb = 0; eb < 2; ++eb) {
          Vec2 x;
          double r = 0.0;
          if (!corner(a, ea, b, eb, &x, &r)) continue;
          const double cost = std::max((segs[a].end[ea] - x).norm(), (segs[b].end[eb] - x).norm());
          cands.push_back({cost, a, ea, b, eb, x});
        }
    }
  std::stable_sort(cands.begin(), cands.end(), [](const Candidate& p, const Candidate& q) { return p.cost < q.cost; });
  for (const Candidate& c : cands) {
    Seg &a = segs[c.a], &b = segs[c.b];
    if (a.link_seg[c.ea] >= 0 || b.link_seg[c.eb] >= 0) continue;
    // The other end of either may have moved: X must still be toward this one.
    if (!Toward(a, c.ea, c.x) || !Toward(b, c.eb, c.x)) continue;
    a.end[c.ea] = b.end[c.eb] = c.x;
    a.link_seg[c.ea] = c.b, a.link_end[c.ea] = c.eb;
    b.link_seg[c.eb] = c.a, b.link_end[c.eb] = c.ea;
    ++st.corners_joined;
  }
  // 2c. T junctions: a free end onto another segment's interior.
  for (int s = 0; s < n; ++s) {
    if (segs[s].dropped) continue;
    for (int e = 0; e < 2; ++e) {
      if (segs[s].link_seg[e] >= 0) continue;
      double best = std::numeric_limits<double>::infinity();
      Vec2 best_x(0, 0);
      for (int a = 0; a < n; ++a) {
        if (a == s || segs[a].dropped) continue;
        Vec2 x;
        if (!Crossing(segs[s], segs[a], min_sin, &x) || !Toward(segs[s], e, x)) continue;
        const double t = (x - segs[a].end[0]).dot(segs[a].dir);
        if (t < 0.0 || t > segs[a].length()) continue;
        const double d = (x - segs[s].end[e]).norm();
        if (d < best && d <= blur(x) && !near_path(x)) best = d, best_x = x;
      }
      if (std::isfinite(best)) {
        segs[s].end[e] = best_x;
        segs[s].moved[e] = true;
        ++st.t_joins;
      }
    }
  }

  // 2d. Short segments joined to nothing.
  {
    std::vector<char> touched(n, 0);
    for (int s = 0; s < n; ++s)
      for (int e = 0; e < 2; ++e)
        if (segs[s].link_seg[e] >= 0 || segs[s].moved[e]) touched[s] = 1;
    const double min_iso = options.min_isolated_m / lim.cell_m();
    for (int s = 0; s < n; ++s)
      if (!segs[s].dropped && !touched[s] && segs[s].length() < min_iso) {
        segs[s].dropped = true;
        ++st.isolated_removed;
      }
  }

  // 3. Segments joined at corners into polylines.
  std::vector<char> used(n, 0);
  auto walk = [&](int s, int e) {
    std::vector<Vec2> line{segs[s].end[e]};
    while (s >= 0 && !used[s]) {
      used[s] = 1;
      const int other = 1 - e;
      line.push_back(segs[s].end[other]);
      const int next = segs[s].link_seg[other];
      e = segs[s].link_end[other];
      s = next;
    }
    return line;
  };
  for (int s = 0; s < n; ++s)
    if (!segs[s].dropped && !used[s])
      for (int e = 0; e < 2; ++e)
        if (segs[s].link_seg[e] < 0) {
          out.walls.push_back(walk(s, e));
          break;
        }
  for (int s = 0; s < n; ++s)  // closed loops: every end joined
    if (!segs[s].dropped && !used[s]) out.walls.push_back(walk(s, 0));
  st.segments = 0;
  for (const Seg& s : segs) st.segments += s.dropped ? 0 : 1;
  return out;
}

}  // namespace cogmap::vectorize
