#include "cogmap/plan/plan.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <deque>
#include <functional>
#include <limits>
#include <memory>
#include <numeric>
#include <optional>
#include <queue>
#include <set>
#include <unordered_map>

#include <Eigen/Eigenvalues>
#include <boost/geometry.hpp>
#include <boost/geometry/geometries/point_xy.hpp>
#include <boost/geometry/geometries/polygon.hpp>

#include "cogmap/core/angles.h"
#include "cogmap/core/parallel.h"
#include "cogmap/graph/registration.h"

namespace cogmap::plan {

double FaceBehindForBeam(double beam_rad, double reach_m, double cell_m) {
  if (!(beam_rad > 0.0)) return 0.0;
  // Unknown reach: the thesis's window (3 m).
  return beam_rad * (reach_m > 0.0 ? reach_m : 3.0) >= cell_m ? -0.025 : 0.03;
}

namespace {

namespace bg = boost::geometry;
using BPoint = bg::model::d2::point_xy<double>;
using BPoly = bg::model::polygon<BPoint, false, false>;  // counter-clockwise, open
using BMulti = bg::model::multi_polygon<BPoly>;

constexpr double kPi = 3.14159265358979323846;
double Deg(double d) { return d * kPi / 180.0; }
Vec2 Perp(const Vec2& v) { return {-v.y(), v.x()}; }

// Wraps an angle into [-pi/4, pi/4): its offset from the nearest quarter turn.
double QuarterOffset(double a) {
  const double q = kPi / 2.0;
  return a - q * std::floor(a / q + 0.5);
}

// ------------------------------------------------------------------ spatial hash
// Cells of 'cell' metres keyed in one 64-bit integer; lists of ids per cell.
class CellHash {
 public:
  explicit CellHash(double cell) : cell_(cell) {}
  void Add(const Vec2& lo, const Vec2& hi, int id) {
    ForCells(lo, hi, [&](int64_t k) {
      auto& v = cells_[k];
      if (v.empty() || v.back() != id) v.push_back(id);
    });
  }
  // Distinct ids listed in the cells of the box (order of first sight).
  std::vector<int> Query(const Vec2& lo, const Vec2& hi) const {
    std::vector<int> out;
    ForCells(lo, hi, [&](int64_t k) {
      auto it = cells_.find(k);
      if (it == cells_.end()) return;
      for (int id : it->second)
        if (seen_.insert(id).second) out.push_back(id);
    });
    seen_.clear();
    return out;
  }

 private:
  template <class F>
  void ForCells(const Vec2& lo, const Vec2& hi, F&& f) const {
    const int64_t x0 = static_cast<int64_t>(std::floor(lo.x() / cell_)), x1 = static_cast<int64_t>(std::floor(hi.x() / cell_));
    const int64_t y0 = static_cast<int64_t>(std::floor(lo.y() / cell_)), y1 = static_cast<int64_t>(std::floor(hi.y() / cell_));
    for (int64_t y = y0; y <= y1; ++y)
      for (int64_t x = x0; x <= x1; ++x) f((y << 32) ^ (x & 0xffffffffLL));
  }
  double cell_;
  std::unordered_map<int64_t, std::vector<int>> cells_;
  mutable std::set<int> seen_;
};

// ------------------------------------------------------------------ wall evidence
struct Evidence {
  Vec2 a, b, n;  // a faced ASR wall segment (world), n: free side
  int asr = -1;
  double length() const { return (b - a).norm(); }
};

// Second moments of a set of segments taken as uniform line densities.
struct Moments {
  double w = 0.0;
  Vec2 s{0, 0};
  Eigen::Matrix2d ss = Eigen::Matrix2d::Zero();
  void Add(const Vec2& a, const Vec2& b, double weight) {
    const double len = (b - a).norm();
    if (len <= 0.0) return;
    const double m = weight * len;
    const Vec2 c = 0.5 * (a + b), d = b - a;
    w += m;
    s += m * c;
    ss += m * (c * c.transpose() + d * d.transpose() / 12.0);
  }
  void Add(const Moments& o) {
    w += o.w;
    s += o.s;
    ss += o.ss;
  }
  Vec2 Mean() const { return s / w; }
  Eigen::Matrix2d Cov() const {
    const Vec2 c = Mean();
    return ss / w - c * c.transpose();
  }
};

// One wall face: the evidence of every ASR that saw it, fitted as one line.
struct Face {
  Vec2 c{0, 0};  // a point on the line (weighted centroid)
  Vec2 u{1, 0};  // direction
  Vec2 n{0, 1};  // free side, perpendicular to u
  Moments mom;  // the members, each ASR weighted by its quality
  Moments raw;  // the members unweighted (the spread along the face)
  std::vector<int> members;
  double tmin = 0.0, tmax = 0.0;  // extent along u from c
  double sigma_theta = 0.0;       // standard error of the direction
  bool squared = false;
  void Refit(const Vec2 seed_normal) {  // by value: callers pass n itself
    c = mom.Mean();
    Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> es(mom.Cov());
    u = es.eigenvectors().col(1).normalized();
    n = Perp(u);
    if (n.dot(seed_normal) < 0.0) n = -n;
  }
  double Offset(const Vec2& p) const { return n.dot(p - c); }
  double Along(const Vec2& p) const { return u.dot(p - c); }
};

// A straight wall piece: a line and the intervals of it that are wall.
struct Piece {
  Vec2 c, u, n;
  Moments mom, raw;  // the evidence it was fitted to (Face::mom, Face::raw)
  std::vector<std::pair<double, double>> spans;
  std::set<int> asrs;
  double weight = 0.0;  // metres seen, quality-weighted, per metre of extent
  bool squared = false;
  bool two_sided = false;
  // The point of this piece's line nearest q.
  Vec2 Foot(const Vec2& q) const { return c + u.dot(q - c) * u; }
};

// The standard error of a line's direction fitted to evidence: the
// residual variance across it (at least floor2) over the spread of the
// evidence along it, with residuals correlated over correlation_m.
double DirectionSigma(double residual2, double floor2, double spread, double correlation_m) {
  return std::sqrt(std::max(floor2, residual2) * correlation_m / std::max(spread, 1e-6));
}

// Squares direction 'u' to the building's direction phi (modulo a quarter
// turn) when it lies within square_z sigma of it, sigma the direction's own
// standard error and the scatter of the building's walls (floor_theta) in
// quadrature. Returns whether it did.
bool SquareTo(double phi, double floor_theta, double sigma_theta, double square_z, Vec2* u) {
  const double a = std::atan2(u->y(), u->x());
  const double d = QuarterOffset(a - phi);
  if (std::abs(d) > square_z * std::sqrt(sigma_theta * sigma_theta + floor_theta * floor_theta)) return false;
  *u = Vec2(std::cos(a - d), std::sin(a - d));
  return true;
}

// Intervals (any order) as sorted spans, those less than 'gap' apart joined.
std::vector<std::pair<double, double>> JoinSpans(std::vector<std::pair<double, double>> iv, double gap) {
  std::sort(iv.begin(), iv.end());
  std::vector<std::pair<double, double>> spans;
  for (const auto& s : iv) {
    if (!spans.empty() && s.first <= spans.back().second + gap)
      spans.back().second = std::max(spans.back().second, s.second);
    else
      spans.push_back(s);
  }
  return spans;
}

// Removes [lo, hi] from a sorted list of spans.
void SubtractSpan(std::vector<std::pair<double, double>>* spans, double lo, double hi) {
  std::vector<std::pair<double, double>> out;
  for (const auto& [a, b] : *spans) {
    if (b <= lo || a >= hi) {
      out.push_back({a, b});
      continue;
    }
    if (a < lo) out.push_back({a, lo});
    if (b > hi) out.push_back({hi, b});
  }
  *spans = std::move(out);
}

// ------------------------------------------------------------------ geometry helpers
bool InConvex(const std::vector<Vec2>& hull, const Vec2& p) {
  if (hull.size() < 3) return false;
  for (size_t i = 0; i < hull.size(); ++i)
    if (Cross(hull[(i + 1) % hull.size()] - hull[i], p - hull[i]) < -1e-9) return false;
  return true;
}

double RingArea(const std::vector<Vec2>& ring) {
  double a = 0.0;
  for (size_t i = 0; i < ring.size(); ++i) a += Cross(ring[i], ring[(i + 1) % ring.size()]);
  return 0.5 * a;
}

BPoly ToBoost(const std::vector<Vec2>& ring) {
  BPoly p;
  for (const Vec2& v : ring) p.outer().push_back(BPoint(v.x(), v.y()));
  bg::correct(p);
  return p;
}

std::vector<Vec2> FromBoost(const BPoly& p) {
  std::vector<Vec2> out;
  for (const auto& q : p.outer()) out.push_back(Vec2(q.x(), q.y()));
  // Open ring: drop a repeated closing point and consecutive duplicates.
  std::vector<Vec2> clean;
  for (const Vec2& v : out)
    if (clean.empty() || (v - clean.back()).norm() > 1e-9) clean.push_back(v);
  while (clean.size() > 1 && (clean.front() - clean.back()).norm() <= 1e-9) clean.pop_back();
  return clean;
}

// ------------------------------------------------------------------ tiled lattice
// A w x h lattice stored in square tiles of kSide x kSide cells, each allocated
// on the first write of a value other than 'fill'; unwritten cells read as
// 'fill'. The room grid's masks and labels cost what the walls and rooms on
// them cost, not the bounding box of the map (docs/floor-plan.md, "Memory").
template <class T>
class TiledLattice {
 public:
  static constexpr int kShift = 4;
  static constexpr int kSide = 1 << kShift;
  static constexpr int kMask = kSide - 1;

  TiledLattice(int w, int h, T fill)
      : w_(w), h_(h), tw_((w + kMask) >> kShift), th_((h + kMask) >> kShift), fill_(fill),
        tiles_(static_cast<size_t>(tw_) * th_) {}
  TiledLattice(const TiledLattice& o) : w_(o.w_), h_(o.h_), tw_(o.tw_), th_(o.th_), fill_(o.fill_), tiles_(o.tiles_.size()) {
    for (size_t t = 0; t < tiles_.size(); ++t)
      if (o.tiles_[t]) {
        tiles_[t] = std::make_unique<T[]>(kSide * kSide);
        std::copy_n(o.tiles_[t].get(), kSide * kSide, tiles_[t].get());
      }
  }
  TiledLattice(TiledLattice&&) = default;
  TiledLattice& operator=(TiledLattice&&) = default;
  TiledLattice& operator=(const TiledLattice&) = delete;

  // (x, y) inside the lattice.
  T Get(int x, int y) const {
    const auto& t = tiles_[Tile(x >> kShift, y >> kShift)];
    return t ? t[Within(x, y)] : fill_;
  }
  void Set(int x, int y, T v) {
    auto& t = tiles_[Tile(x >> kShift, y >> kShift)];
    if (!t) {
      if (v == fill_) return;
      t = std::make_unique<T[]>(kSide * kSide);
      std::fill_n(t.get(), kSide * kSide, fill_);
    }
    t[Within(x, y)] = v;
  }
  // f(x, y, value) for every cell of an allocated tile, in the lattice's
  // row-major order (y, then x): the order of a dense lattice, unwritten cells
  // left out.
  template <class F>
  void ForEachStored(F&& f) const {
    for (int y = 0; y < h_; ++y) {
      const int ty = y >> kShift;
      for (int tx = 0; tx < tw_; ++tx) {
        const auto& t = tiles_[Tile(tx, ty)];
        if (!t) continue;
        const int x0 = tx << kShift, x1 = std::min(w_, x0 + kSide);
        const T* row = t.get() + ((y & kMask) << kShift);
        for (int x = x0; x < x1; ++x) f(x, y, row[x - x0]);
      }
    }
  }
  // f(x, y) for every cell of a tile that is allocated or touches one (8
  // neighbours): every cell within kSide cells of a written one, tile by
  // tile (rows of tiles ty0 to ty1 - 1; by default all).
  template <class F>
  void ForEachNearStored(F&& f, int ty0 = 0, int ty1 = std::numeric_limits<int>::max()) const {
    for (int ty = std::max(0, ty0); ty < std::min(th_, ty1); ++ty)
      for (int tx = 0; tx < tw_; ++tx) {
        bool near = false;
        for (int dy = -1; dy <= 1 && !near; ++dy)
          for (int dx = -1; dx <= 1 && !near; ++dx) {
            const int ux = tx + dx, uy = ty + dy;
            near = ux >= 0 && uy >= 0 && ux < tw_ && uy < th_ && tiles_[Tile(ux, uy)];
          }
        if (!near) continue;
        const int x1 = std::min(w_, (tx + 1) << kShift), y1 = std::min(h_, (ty + 1) << kShift);
        for (int y = ty << kShift; y < y1; ++y)
          for (int x = tx << kShift; x < x1; ++x) f(x, y);
      }
  }

 private:
  size_t Tile(int tx, int ty) const { return static_cast<size_t>(ty) * tw_ + tx; }
  static int Within(int x, int y) { return ((y & kMask) << kShift) | (x & kMask); }
  int w_, h_, tw_, th_;
  T fill_;
  std::vector<std::unique_ptr<T[]>> tiles_;

 public:
  int tile_rows() const { return th_; }
};
// A w x h lattice of 2-bit values (0-3) in tiles of 16 x 16 cells, one
// 32-bit word per tile row, allocated on the first non-zero write; unwritten
// cells read 0. The room grid's masks: a quarter of a byte lattice's memory
// (at 1000 rooms the wall mask was the plan's largest structure, 10.8 MB).
class Mask {
 public:
  static constexpr int kShift = 4;
  static constexpr int kSide = 1 << kShift;
  static constexpr int kLow = kSide - 1;

  Mask(int w, int h) : w_(w), h_(h), tw_((w + kLow) >> kShift), tiles_(static_cast<size_t>(tw_) * ((h + kLow) >> kShift)) {}

  // (x, y) inside the lattice.
  uint8_t Get(int x, int y) const {
    const auto& t = tiles_[Tile(x, y)];
    return t ? static_cast<uint8_t>((t[y & kLow] >> (2 * (x & kLow))) & 3u) : 0;
  }
  void Set(int x, int y, uint8_t v) {  // v < 4
    auto& t = tiles_[Tile(x, y)];
    if (!t) {
      if (v == 0) return;
      t = std::make_unique<uint32_t[]>(kSide);  // zeroed
    }
    const int shift = 2 * (x & kLow);
    uint32_t& row = t[y & kLow];
    row = (row & ~(3u << shift)) | (static_cast<uint32_t>(v & 3u) << shift);
  }
  // f(x, y, value) for every cell of an allocated tile, row-major (y, then
  // x), unwritten cells left out.
  template <class F>
  void ForEachStored(F&& f) const {
    for (int y = 0; y < h_; ++y) {
      const int ty = y >> kShift;
      for (int tx = 0; tx < tw_; ++tx) {
        const auto& t = tiles_[static_cast<size_t>(ty) * tw_ + tx];
        if (!t) continue;
        const int x0 = tx << kShift, x1 = std::min(w_, x0 + kSide);
        const uint32_t row = t[y & kLow];
        for (int x = x0; x < x1; ++x) f(x, y, static_cast<uint8_t>((row >> (2 * (x - x0))) & 3u));
      }
    }
  }

 private:
  size_t Tile(int x, int y) const { return static_cast<size_t>(y >> kShift) * tw_ + (x >> kShift); }
  int w_, h_, tw_;
  std::vector<std::unique_ptr<uint32_t[]>> tiles_;
};

// Room per cell, -1: none, on tiles: 16-bit labels while the rooms number
// fewer than 32768 (half the memory of int labels: at 1000 rooms the labels
// are the plan's largest structure), 32-bit beyond.
class Labels {
 public:
  Labels(int w, int h, int n_labels) : wide_(n_labels > std::numeric_limits<int16_t>::max()) {
    if (wide_) wide_cells_.emplace(w, h, -1);
    else narrow_cells_.emplace(w, h, int16_t{-1});
  }
  bool wide() const { return wide_; }
  int Get(int x, int y) const { return wide_ ? wide_cells_->Get(x, y) : narrow_cells_->Get(x, y); }
  void Set(int x, int y, int v) {
    if (wide_) wide_cells_->Set(x, y, v);
    else narrow_cells_->Set(x, y, static_cast<int16_t>(v));  // v < n_labels
  }
  template <class F>
  void ForEachStored(F&& f) const {  // f(x, y, label)
    if (wide_) wide_cells_->ForEachStored([&](int x, int y, int v) { f(x, y, v); });
    else narrow_cells_->ForEachStored([&](int x, int y, int16_t v) { f(x, y, static_cast<int>(v)); });
  }
  template <class F>
  void ForEachNearStored(F&& f, int ty0 = 0, int ty1 = std::numeric_limits<int>::max()) const {
    if (wide_) wide_cells_->ForEachNearStored(f, ty0, ty1);
    else narrow_cells_->ForEachNearStored(f, ty0, ty1);
  }
  // Rows of 16-cell tiles (ForEachNearStored's ranges; QuarterTable's tiles are the same).
  int tile_rows() const { return wide_ ? wide_cells_->tile_rows() : narrow_cells_->tile_rows(); }

 private:
  bool wide_;
  std::optional<TiledLattice<int>> wide_cells_;
  std::optional<TiledLattice<int16_t>> narrow_cells_;
};

// ------------------------------------------------------------------ room grid
// A grid in the building frame (rotated by -phi so walls run along the axes).
struct RoomGrid {
  double cell = 0.1;
  double phi = 0.0;
  Vec2 lo{0, 0};
  int w = 0, h = 0;
  Vec2 ToFrame(const Vec2& p) const { return RotateAbout(p, Vec2(0, 0), -phi); }
  Vec2 FromFrame(const Vec2& p) const { return RotateAbout(p, Vec2(0, 0), phi); }
  bool Cell(const Vec2& world, int* cx, int* cy) const {
    const Vec2 f = ToFrame(world);
    *cx = static_cast<int>(std::floor((f.x() - lo.x()) / cell));
    *cy = static_cast<int>(std::floor((f.y() - lo.y()) / cell));
    return *cx >= 0 && *cy >= 0 && *cx < w && *cy < h;
  }
  Vec2 Center(int cx, int cy) const { return FromFrame(Vec2(lo.x() + (cx + 0.5) * cell, lo.y() + (cy + 0.5) * cell)); }
  size_t Idx(int cx, int cy) const { return static_cast<size_t>(cy) * w + cx; }
  // Marks the cells a segment crosses, 4-connected (a 4-connected flood cannot slip through).
  void Block(const Vec2& a, const Vec2& b, Mask* mask, uint8_t value = 1) const {
    const double len = (b - a).norm();
    const int steps = std::max(1, static_cast<int>(std::ceil(len / (0.25 * cell))));
    int px = 0, py = 0;
    bool have = false;
    for (int i = 0; i <= steps; ++i) {
      int cx, cy;
      if (!Cell(a + (b - a) * (static_cast<double>(i) / steps), &cx, &cy)) {
        have = false;
        continue;
      }
      if (have && cx != px && cy != py) mask->Set(px, cy, value);  // close the diagonal step
      mask->Set(cx, cy, value);
      px = cx, py = cy, have = true;
    }
  }
};

// Where a room may flood: convex hulls of the walls, the path and the floor
// the grid saw (Asr::free_hull_local). Pass 1 (the shapes that tell corridors
// from rooms) takes one hull per unit (a room with its revisits and absorbed
// slivers), not one for them all: the pieces of a corridor turning a corner
// would span the block it runs around. Pass 2 (the plan's footprints) takes
// one per ASR: a unit whose visits go round a corner (a corridor driven
// twice, a ring's revisits merged into one room) would span it too.
using RoomHulls = std::vector<std::vector<Vec2>>;

// Values of a room-grid mask.
constexpr uint8_t kBlocked = 1;  // a wall or a door line
constexpr uint8_t kTight = 2;    // free, but within the robot's radius of a wall (TightCells)

// The wall mask with the door lines of one split of the rooms drawn over it:
// the door lines on a lattice of their own (a few tiles), the walls read
// through, so that a split costs its doors and not a copy of every wall tile
// (at 1000 rooms the copy was 7 MB of the plan's peak).
class DoorMask {
 public:
  DoorMask(const Mask& walls, int w, int h) : walls_(&walls), doors_(w, h) {}
  uint8_t Get(int x, int y) const { return doors_.Get(x, y) == kBlocked ? kBlocked : walls_->Get(x, y); }
  Mask* doors() { return &doors_; }

 private:
  const Mask* walls_;
  Mask doors_;
};

// Marks kTight the free cells of 'walls' within radius_m of a wall (walls
// only: door lines are openings the robot took), except within radius_m of
// the robot's 'paths' (map frame): where the robot's centre cannot be. A gap
// narrower than the robot (a window, a jamb's return, two wall pieces that do
// not meet) is all tight cells. Kept in the wall mask
// itself (and so in the door masks copied from it): no second lattice.
// Returns the 4-connected steps that reach every tight cell from the open
// floor beside it (0: nothing marked, the cells are larger than the radius).
int TightCells(const RoomGrid& g, Mask* walls, double radius_m, const std::vector<std::vector<Vec2>>& paths) {
  const int k = static_cast<int>(std::floor(radius_m / g.cell));
  if (k < 1) return 0;
  std::vector<std::pair<int, int>> disk;
  for (int dy = -k; dy <= k; ++dy)
    for (int dx = -k; dx <= k; ++dx)
      if (dx * dx + dy * dy <= k * k && (dx || dy)) disk.push_back({dx, dy});
  // 'from' -> 'to' on the cells of the disk around (x, y).
  auto around = [&](int x, int y, uint8_t from, uint8_t to) {
    for (const auto& [dx, dy] : disk) {
      const int nx = x + dx, ny = y + dy;
      if (nx >= 0 && ny >= 0 && nx < g.w && ny < g.h && walls->Get(nx, ny) == from) walls->Set(nx, ny, to);
    }
  };
  // Marked while the walls are visited: a cell marked before its visit reads
  // kTight, not kBlocked, and a tile allocated on the way holds no wall.
  walls->ForEachStored([&](int x, int y, uint8_t v) {
    if (v == kBlocked) around(x, y, 0, kTight);
  });
  // Where the robot drove, its body was: the cells within its radius of the
  // path are not tight, whatever walls the map put beside them (sonar walls
  // pulled in by a wide cone, a wall drawn across the path by a pose error),
  // so no room is walled in around its own path.
  for (const auto& pts : paths)
    for (size_t j = 0; j < pts.size(); ++j) {
      const Vec2 a = j ? pts[j - 1] : pts[j], b = pts[j];
      const int steps = std::max(1, static_cast<int>(std::ceil((b - a).norm() / g.cell)));
      for (int t = 1; t <= steps; ++t) {
        int cx, cy;
        if (!g.Cell(a + (b - a) * (static_cast<double>(t) / steps), &cx, &cy)) continue;
        if (walls->Get(cx, cy) == kTight) walls->Set(cx, cy, 0);
        around(cx, cy, kTight, 0);
      }
    }
  // A tight cell is within k cells (Euclidean) of the open floor beside its
  // wall, so within ceil(sqrt(2) k) 4-connected steps.
  return static_cast<int>(std::ceil(std::sqrt(2.0) * k));
}

// Multi-source breadth-first flood: each seed cell's label spreads through free
// cells its region allows, first come first served (a geodesic Voronoi split).
// With grow_steps > 0 (TightCells marked the mask), the rooms first split
// the floor the robot's centre can reach, then each fills the tight cells
// beside its own floor (at most grow_steps deep): a room spreads through a
// gap in its walls only if the robot could have driven through it, instead
// of flooding whatever lies behind it within its hull.
Labels Flood(const RoomGrid& g, const DoorMask& blocked, const std::vector<std::vector<uint32_t>>& seeds,
             const std::vector<RoomHulls>& hulls_frame, int grow_steps = 0, int max_depth = 0) {
  Labels label(g.w, g.h, static_cast<int>(seeds.size()));
  std::deque<std::pair<int32_t, int32_t>> q;  // cells (x, y): no division per step
  // A region of many hulls (a corridor of hundreds of ASRs) is not tested
  // hull by hull: the hulls are listed by the 32 x 32-cell blocks their boxes
  // cover, and a cell tests its block's hulls of its region only.
  constexpr int kBlockShift = 5;
  const int bw = (g.w >> kBlockShift) + 1, bh = (g.h >> kBlockShift) + 1;
  std::vector<std::vector<std::pair<int, const std::vector<Vec2>*>>> in_block(static_cast<size_t>(bw) * bh);
  for (size_t r = 0; r < hulls_frame.size(); ++r)
    for (const auto& hull : hulls_frame[r]) {
      if (hull.size() < 3) continue;
      Vec2 lo = hull[0], hi = hull[0];
      for (const Vec2& v : hull) lo = lo.cwiseMin(v), hi = hi.cwiseMax(v);
      if (!lo.allFinite() || !hi.allFinite()) continue;  // no block of the lattice (readers refuse such input)
      auto block = [&](double v, double origin, int n) {
        const double c = std::floor((v - origin) / g.cell);
        return static_cast<int>(std::clamp(c, 0.0, static_cast<double>(n - 1) * (1 << kBlockShift))) >> kBlockShift;
      };
      // One cell of margin: InConvex's tolerance reaches past the box by far less.
      const int x0 = block(lo.x() - g.cell, g.lo.x(), bw), x1 = block(hi.x() + g.cell, g.lo.x(), bw);
      const int y0 = block(lo.y() - g.cell, g.lo.y(), bh), y1 = block(hi.y() + g.cell, g.lo.y(), bh);
      for (int by = y0; by <= y1; ++by)
        for (int bx = x0; bx <= x1; ++bx) in_block[static_cast<size_t>(by) * bw + bx].push_back({static_cast<int>(r), &hull});
    }
  auto allowed = [&](int r, int cx, int cy) {
    const Vec2 p(g.lo.x() + (cx + 0.5) * g.cell, g.lo.y() + (cy + 0.5) * g.cell);
    for (const auto& [hr, hull] : in_block[static_cast<size_t>(cy >> kBlockShift) * bw + (cx >> kBlockShift)])
      if (hr == r && InConvex(*hull, p)) return true;
    return false;
  };
  const bool two_phases = grow_steps > 0 && static_cast<uint64_t>(g.w) * static_cast<uint64_t>(g.h) <= UINT32_MAX;
  for (size_t r = 0; r < seeds.size(); ++r)
    for (size_t idx : seeds[r]) {
      const int cx = static_cast<int>(idx % g.w), cy = static_cast<int>(idx / g.w);
      if (blocked.Get(cx, cy) != kBlocked && label.Get(cx, cy) < 0) {
        label.Set(cx, cy, static_cast<int>(r));
        q.push_back({cx, cy});
      }
    }
  // Phase 2 starts from the labelled cells beside a tight one (the rim of
  // each room's open floor, and tight seeds), not from every labelled cell.
  std::vector<uint32_t> rim;  // cell indices: the grid holds at most max_cells (3e7)
  size_t left_in_level = q.size();
  int depth = 0;
  while (!q.empty()) {
    if (left_in_level == 0) {
      ++depth;
      left_in_level = q.size();
    }
    --left_in_level;
    const auto [cx, cy] = q.front();
    q.pop_front();
    if (max_depth > 0 && depth >= max_depth) continue;
    const int r = label.Get(cx, cy);
    const int nx[4] = {cx + 1, cx - 1, cx, cx}, ny[4] = {cy, cy, cy + 1, cy - 1};
    bool rim_cell = false;
    for (int k = 0; k < 4; ++k) {
      if (nx[k] < 0 || ny[k] < 0 || nx[k] >= g.w || ny[k] >= g.h) continue;
      const uint8_t m = blocked.Get(nx[k], ny[k]);
      if (m == kBlocked || label.Get(nx[k], ny[k]) >= 0 || !allowed(r, nx[k], ny[k])) continue;
      if (m == kTight && two_phases) {
        rim_cell = true;
        continue;
      }
      label.Set(nx[k], ny[k], r);
      q.push_back({nx[k], ny[k]});
    }
    if (rim_cell) rim.push_back(static_cast<uint32_t>(g.Idx(cx, cy)));
  }
  if (!two_phases) return label;
  // Phase 2: the tight cells, breadth first from the rims, at most
  // grow_steps deep (one frontier per step).
  std::deque<std::pair<int32_t, int32_t>>().swap(q);
  std::vector<uint32_t> next;
  for (int depth = 0; depth < grow_steps && !rim.empty(); ++depth) {
    next.clear();
    for (uint32_t idx : rim) {
      const int cx = static_cast<int>(idx % g.w), cy = static_cast<int>(idx / g.w);
      const int r = label.Get(cx, cy);
      const int nx[4] = {cx + 1, cx - 1, cx, cx}, ny[4] = {cy, cy, cy + 1, cy - 1};
      for (int k = 0; k < 4; ++k) {
        if (nx[k] < 0 || ny[k] < 0 || nx[k] >= g.w || ny[k] >= g.h) continue;
        if (blocked.Get(nx[k], ny[k]) != kTight || label.Get(nx[k], ny[k]) >= 0 || !allowed(r, nx[k], ny[k]))
          continue;
        label.Set(nx[k], ny[k], r);
        next.push_back(static_cast<uint32_t>(g.Idx(nx[k], ny[k])));
      }
    }
    rim.swap(next);
  }
  return label;
}

// The cells of one label span this box (x1 < 0: none).
struct CellBox {
  int x0 = std::numeric_limits<int>::max(), y0 = std::numeric_limits<int>::max(), x1 = -1, y1 = -1;
};

// The cell box of every label, in one pass.
std::vector<CellBox> LabelBoxes(const Labels& label, int n) {
  std::vector<CellBox> b(n);
  label.ForEachStored([&](int x, int y, int r) {
    if (r < 0) return;
    b[r].x0 = std::min(b[r].x0, x), b[r].x1 = std::max(b[r].x1, x);
    b[r].y0 = std::min(b[r].y0, y), b[r].y1 = std::max(b[r].y1, y);
  });
  return b;
}

// The quarters (HalfCells) of the unlabelled cells beside a room, by tile of
// 16 x 16 cells: per tile, a list of (cell in the tile, its four quarters)
// sorted by cell. About 10 bytes a cell with 16-bit labels (20 with 32-bit),
// where a hash map took some 56.
template <class T>
class QuarterTableOf {
  struct Entry {
    uint8_t at;  // (y & 15) * 16 + (x & 15)
    std::array<T, 4> q;
  };
  template <class V>
  static auto Lower(V& t, uint8_t at) {
    return std::lower_bound(t.begin(), t.end(), at, [](const Entry& e, uint8_t a) { return e.at < a; });
  }
  // The cell's entry, added with four -1 when it has none.
  std::array<T, 4>& Get(int cx, int cy) {
    std::vector<Entry>& t = tiles_[Tile(cx, cy)];
    const uint8_t at = At(cx, cy);
    auto it = Lower(t, at);
    if (it == t.end() || it->at != at) it = t.insert(it, Entry{at, {T(-1), T(-1), T(-1), T(-1)}});
    return it->q;
  }

 public:
  QuarterTableOf(int w, int h) : tw_((w + 15) >> 4), tiles_(static_cast<size_t>(tw_) * ((h + 15) >> 4)) {}
  // The cell's quarters into 'q'; false when it has none.
  bool Find(int cx, int cy, std::array<int, 4>* q) const {
    const std::vector<Entry>& t = tiles_[Tile(cx, cy)];
    const auto it = Lower(t, At(cx, cy));
    if (it == t.end() || it->at != At(cx, cy)) return false;
    for (int k = 0; k < 4; ++k) (*q)[k] = it->q[k];
    return true;
  }
  void Set(int cx, int cy, const std::array<int, 4>& q) {
    std::array<T, 4>& e = Get(cx, cy);
    for (int k = 0; k < 4; ++k) e[k] = static_cast<T>(q[k]);
  }
  void SetQuarter(int cx, int cy, int k, int r) { Get(cx, cy)[k] = static_cast<T>(r); }
  void ShrinkToFit() {
    for (auto& t : tiles_) t.shrink_to_fit();
  }

 private:
  size_t Tile(int cx, int cy) const { return static_cast<size_t>(cy >> 4) * tw_ + (cx >> 4); }
  static uint8_t At(int cx, int cy) { return static_cast<uint8_t>(((cy & 15) << 4) | (cx & 15)); }
  int tw_;
  std::vector<std::vector<Entry>> tiles_;
};

// The quarter table in the labels' width (Labels).
class QuarterTable {
 public:
  QuarterTable(int w, int h, bool wide) {
    if (wide) wide_.emplace(w, h);
    else narrow_.emplace(w, h);
  }
  bool Find(int cx, int cy, std::array<int, 4>* q) const {
    return wide_ ? wide_->Find(cx, cy, q) : narrow_->Find(cx, cy, q);
  }
  void Set(int cx, int cy, const std::array<int, 4>& q) { wide_ ? wide_->Set(cx, cy, q) : narrow_->Set(cx, cy, q); }
  void SetQuarter(int cx, int cy, int k, int r) {
    wide_ ? wide_->SetQuarter(cx, cy, k, r) : narrow_->SetQuarter(cx, cy, k, r);
  }
  void ShrinkToFit() { wide_ ? wide_->ShrinkToFit() : narrow_->ShrinkToFit(); }

 private:
  std::optional<QuarterTableOf<int>> wide_;
  std::optional<QuarterTableOf<int16_t>> narrow_;
};

// The rooms on a lattice of half cells (site (i, j) is quarter (i & 1, j & 1)
// of cell (i >> 1, j >> 1)): a labelled cell's four quarters carry its label;
// a cell the flood left unlabelled (walls and door lines run through it, or no
// room reached it) gives each quarter the label of the cell beside it across
// the quarter's outer sides (the lower label when both sides are rooms); a
// quarter at a room's outer corner, when the quarters beside it both took that
// room. So each room grows by half a cell, onto the middle
// of the wall cells it stopped at, and every site has one label: the rooms'
// site sets are disjoint by construction.
class HalfCells {
 public:
  // With threads >= 2 the tiles' rows are shared out in two halves: each
  // cell writes its own tile's quarters only, and the corners found are set
  // in the order one thread would (the same lattice).
  HalfCells(const RoomGrid& g, Labels* label, int threads = 1)
      : g_(g), label_(*label), w_(2 * g.w), h_(2 * g.h), quarters_(g.w, g.h, label->wide()) {
    auto cell = [&](int x, int y) { return x < 0 || y < 0 || x >= g.w || y >= g.h ? -1 : label_.Get(x, y); };
    const int rows = label_.tile_rows(), mid = threads >= 2 ? rows / 2 : rows;
    auto half_rows = [&](size_t part, auto&& f) {
      label_.ForEachNearStored(f, part == 0 ? 0 : mid, part == 0 ? mid : rows);
    };
    // Only cells within a tile of a labelled one can border a room.
    ForEachShared(2, threads, [&](size_t part) {
      half_rows(part, [&](int cx, int cy) {
        if (label_.Get(cx, cy) >= 0) return;
        std::array<int, 4> q{-1, -1, -1, -1};
        bool any = false;
        for (int k = 0; k < 4; ++k) {
          const int dx = (k & 1) ? 1 : -1, dy = (k & 2) ? 1 : -1;
          const int h = cell(cx + dx, cy), v = cell(cx, cy + dy);
          q[k] = h >= 0 && v >= 0 ? std::min(h, v) : h >= 0 ? h : v;
          any = any || q[k] >= 0;
        }
        if (any) quarters_.Set(cx, cy, q);
      });
    });
    // A quarter at a room's outer corner: both its outer neighbours took the
    // same room (so the room grows by a square, as a mitred buffer would).
    // Such a cell lies within two cells of a labelled one.
    struct Corner {
      int cx, cy, k, r;
    };
    std::vector<Corner> corners[2];
    ForEachShared(2, threads, [&](size_t part) {
      half_rows(part, [&](int cx, int cy) {
        if (label_.Get(cx, cy) >= 0) return;
        for (int k = 0; k < 4; ++k) {
          if (Quarter(cx, cy, k) >= 0) continue;
          const int dx = (k & 1) ? 1 : -1, dy = (k & 2) ? 1 : -1;
          const int h = Quarter(cx + dx, cy, (k & 2) | (dx > 0 ? 0 : 1));
          const int v = Quarter(cx, cy + dy, (k & 1) | (dy > 0 ? 0 : 2));
          if (h >= 0 && h == v) corners[part].push_back({cx, cy, k, h});
        }
      });
    });
    for (const auto& part : corners)
      for (const Corner& c : part) quarters_.SetQuarter(c.cx, c.cy, c.k, c.r);
    quarters_.ShrinkToFit();
  }
  int w() const { return w_; }
  int h() const { return h_; }
  // Marks 1 in 'mask' (row stride W; lattice site (x0, y0) at (1, 1)) the
  // sites of [x0, x1] x [y0, y1] whose label is r, as Get would tell, each
  // cell looked up once for its four quarters.
  void MaskOf(int r, int x0, int y0, int x1, int y1, std::vector<uint8_t>* mask, int W) const {
    for (int cy = y0 >> 1; cy <= (y1 >> 1); ++cy)
      for (int cx = x0 >> 1; cx <= (x1 >> 1); ++cx) {
        std::array<int, 4> q{-1, -1, -1, -1};
        if (cx >= 0 && cy >= 0 && cx < g_.w && cy < g_.h) {
          const int l = label_.Get(cx, cy);
          if (l >= 0) q = {l, l, l, l};
          else if (!quarters_.Find(cx, cy, &q)) q = {-1, -1, -1, -1};
        }
        for (int k = 0; k < 4; ++k) {
          if (q[k] != r) continue;
          const int i = 2 * cx + (k & 1), j = 2 * cy + (k >> 1);
          if (i < x0 || i > x1 || j < y0 || j > y1 || i >= w_ || j >= h_) continue;
          (*mask)[static_cast<size_t>(j - y0 + 1) * W + (i - x0 + 1)] = 1;
        }
      }
  }
  int Get(int i, int j) const {
    if (i < 0 || j < 0 || i >= w_ || j >= h_) return -1;
    return Quarter(i >> 1, j >> 1, (j & 1) * 2 + (i & 1));
  }
  // A labelled cell moves whole (its four quarters are 4-connected and share
  // one label, so every region that holds one of them holds all four).
  void Set(int i, int j, int r) {
    if (label_.Get(i >> 1, j >> 1) >= 0) {
      label_.Set(i >> 1, j >> 1, r);
      return;
    }
    quarters_.SetQuarter(i >> 1, j >> 1, (j & 1) * 2 + (i & 1), r);
  }

 private:
  int Quarter(int cx, int cy, int k) const {
    if (cx < 0 || cy < 0 || cx >= g_.w || cy >= g_.h) return -1;
    const int l = label_.Get(cx, cy);
    if (l >= 0) return l;
    std::array<int, 4> q;
    return quarters_.Find(cx, cy, &q) ? q[k] : -1;
  }
  const RoomGrid& g_;
  Labels& label_;
  int w_, h_;
  QuarterTable quarters_;
};

// One room on a lattice box [x0, x1] x [y0, y1] (inclusive), with a frame of
// one site around it: local site (x, y) is lattice site (x0 - 1 + x, y0 - 1 + y).
// 'filled' holds the room's largest 4-connected component with its holes
// filled (every site not reachable from the frame without crossing it;
// without 'fill_holes', the component alone).
struct Region {
  int x0 = 0, y0 = 0, W = 0, H = 0;
  std::vector<uint8_t> filled;
  int64_t count = 0;  // filled sites
  bool at(int x, int y) const { return x >= 0 && y >= 0 && x < W && y < H && filled[static_cast<size_t>(y) * W + x]; }
};

// The same from a mask the caller fills: mask_of(&mask, W) marks 1 the
// room's sites (local site (x, y) at y * W + x, the frame left 0).
template <class MaskOf>
Region FillRegionMasked(int x0, int y0, int x1, int y1, MaskOf&& mask_of, bool fill_holes = true) {
  Region reg;
  reg.x0 = x0, reg.y0 = y0;
  if (x1 < x0 || y1 < y0) return reg;
  const int W = x1 - x0 + 3, H = y1 - y0 + 3;
  reg.W = W, reg.H = H;
  // Two bytes a site in all (a long corridor's box is large): the lattice's
  // answer for each site, asked once (the flood asks again for every
  // neighbour it meets, and a look-up in the lattice is not free), which
  // the flood marks as it goes and the hole filling below reuses; and the
  // room's piece, 'filled'.
  std::vector<uint8_t> mask(static_cast<size_t>(W) * H, 0);
  mask_of(&mask, W);
  constexpr uint8_t kSeen = 2;  // a site of the room a flood has reached
  // The 4-neighbours of a site off the frame (the room's sites, its holes:
  // the frame is never the room's, and always outside).
  const size_t row = static_cast<size_t>(W);
  auto neighbours = [&](size_t j, auto&& f) {
    f(j + 1);
    f(j - 1);
    f(j + row);
    f(j - row);
  };
  // Each 4-connected piece, flooded from its first site in row order; the
  // largest (the first of equal ones) is flooded again into 'filled'.
  auto flood = [&](size_t from, auto&& visit) {
    std::vector<size_t> st{from};
    visit(from);
    while (!st.empty()) {
      const size_t j = st.back();
      st.pop_back();
      neighbours(j, [&](size_t q) {
        if (mask[q] != 1) return;
        visit(q);
        st.push_back(q);
      });
    }
  };
  int64_t best_size = 0;
  size_t best_seed = 0;
  for (int y = 1; y < H - 1; ++y)
    for (int x = 1; x < W - 1; ++x) {
      const size_t j0 = static_cast<size_t>(y) * W + x;
      if (mask[j0] != 1) continue;
      int64_t size = 0;
      flood(j0, [&](size_t j) { mask[j] = kSeen, ++size; });
      if (size > best_size) best_size = size, best_seed = j0;
    }
  reg.filled.assign(static_cast<size_t>(W) * H, 0);
  if (best_size == 0) return reg;
  for (uint8_t& m : mask) m = m == kSeen ? 1 : m;
  flood(best_seed, [&](size_t j) { mask[j] = kSeen, reg.filled[j] = 1; });
  if (!fill_holes) {
    reg.count = best_size;
    return reg;
  }
  // Fill holes: sites not reachable from the frame without crossing the
  // piece (reg.filled, 1 while it is the piece alone). The mask is reused:
  // 1 outside, 2 in a hole (below), 0 neither.
  std::vector<uint8_t>& outside = mask;
  auto flood_outside = [&] {
    std::fill(outside.begin(), outside.end(), 0);
    std::vector<std::pair<int, int>> st{{0, 0}};
    outside[0] = 1;
    while (!st.empty()) {
      auto [cx, cy] = st.back();
      st.pop_back();
      const int nx[4] = {cx + 1, cx - 1, cx, cx}, ny[4] = {cy, cy, cy + 1, cy - 1};
      for (int k = 0; k < 4; ++k) {
        if (nx[k] < 0 || ny[k] < 0 || nx[k] >= W || ny[k] >= H) continue;
        const size_t q = static_cast<size_t>(ny[k]) * W + nx[k];
        if (outside[q] || reg.filled[q]) continue;
        outside[q] = 1;
        st.push_back({nx[k], ny[k]});
      }
    }
  };
  flood_outside();
  // A hole larger than the room itself is not part of it: it is what the
  // room runs round (a corridor ring round its block, closed once the loop
  // is: hallway_loop's ring filled to a 3,600 m2 square). A room is a
  // polygon without holes, so the ring is cut instead: the shortest way
  // across it from that hole to the outside is left to no room (a slit one
  // site wide), and the hole stays outside. Smaller holes (walls and
  // furniture inside a room, a room wholly inside it) are filled.
  constexpr uint8_t kHole = 2;
  bool cut = false;
  for (size_t j0 = 0; j0 < outside.size(); ++j0) {
    if (outside[j0] || reg.filled[j0]) continue;
    std::vector<size_t> sites{j0};
    outside[j0] = kHole;
    for (size_t i = 0; i < sites.size(); ++i)
      neighbours(sites[i], [&](size_t j) {
        if (outside[j] || reg.filled[j]) return;
        outside[j] = kHole;
        sites.push_back(j);
      });
    if (static_cast<int64_t>(sites.size()) <= best_size) continue;
    // Breadth first through the room from its sites beside this hole to the
    // first one beside the outside.
    std::vector<int64_t> parent(outside.size(), -2);
    std::vector<size_t> queue;
    for (size_t j : sites)
      neighbours(j, [&](size_t q) {
        if (reg.filled[q] && parent[q] == -2) parent[q] = -1, queue.push_back(q);
      });
    std::sort(queue.begin(), queue.end());  // a deterministic order whatever the hole's flood
    int64_t exit = -1;
    for (size_t i = 0; i < queue.size() && exit < 0; ++i) {
      const size_t j = queue[i];
      bool beside_outside = false;
      neighbours(j, [&](size_t q) { beside_outside = beside_outside || outside[q] == 1; });
      if (beside_outside) {
        exit = static_cast<int64_t>(j);
        break;
      }
      neighbours(j, [&](size_t q) {
        if (reg.filled[q] && parent[q] == -2) parent[q] = static_cast<int64_t>(j), queue.push_back(q);
      });
    }
    for (int64_t j = exit; j >= 0; j = parent[static_cast<size_t>(j)]) reg.filled[static_cast<size_t>(j)] = 0;
    cut = cut || exit >= 0;
  }
  if (cut) flood_outside();
  for (size_t j = 0; j < outside.size(); ++j) {
    reg.filled[j] = outside[j] == 1 ? 0 : 1;
    reg.count += reg.filled[j];
  }
  return reg;
}

template <class In>
Region FillRegion(int x0, int y0, int x1, int y1, In&& in_lattice, bool fill_holes = true) {
  return FillRegionMasked(
      x0, y0, x1, y1,
      [&](std::vector<uint8_t>* mask, int W) {
        const int H = y1 - y0 + 3;  // as FillRegionMasked frames the box
        for (int y = 1; y < H - 1; ++y)
          for (int x = 1; x < W - 1; ++x)
            (*mask)[static_cast<size_t>(y) * W + x] = in_lattice(x0 + x - 1, y0 + y - 1) ? 1 : 0;
      },
      fill_holes);
}

// Douglas-Peucker on 'chain' (its ends kept): the vertices kept.
void KeepFarthest(const std::vector<Vec2>& chain, size_t a, size_t b, double tol, std::vector<char>* keep) {
  double worst = 0.0;
  size_t at = a;
  for (size_t k = a + 1; k < b; ++k) {
    const double d = PointSegmentDistance(chain[k], chain[a], chain[b]);
    if (d > worst) worst = d, at = k;
  }
  if (worst <= tol) return;
  (*keep)[at] = 1;
  KeepFarthest(chain, a, at, tol, keep);
  KeepFarthest(chain, at, b, tol, keep);
}

// Straightens traced outlines (each a ring of lattice corners, counter-
// clockwise, with 'anchors' marking the corners where three or more labels
// meet): every stretch between two anchors (the whole ring from its least
// vertex when it has none) is simplified by Douglas-Peucker within
// 'tol_m', walked in one canonical direction (from its lesser end) so that
// a border two rooms share comes out the same in both and they neither
// overlap nor part. Both ends of an edge at least 'long_m' long are
// anchors too: a wall square to the lattice stays exactly so, and only the
// staircases of short steps between such edges are straightened (a notch
// of a cell at a corner no longer tilts the walls either side of it). A
// room whose outline would no longer be a simple polygon keeps its
// stretches as traced, and so do its neighbours' along them. tol_m <= 0:
// nothing changes.
void SimplifyOutlines(std::vector<std::vector<Vec2>>* rings, const std::vector<std::vector<char>>& anchors,
                      double tol_m, double long_m) {
  if (!(tol_m > 0.0)) return;
  using Key = std::pair<long long, long long>;
  auto key = [](const Vec2& v) { return Key{std::llround(v.x() * 1e6), std::llround(v.y() * 1e6)}; };
  // A stretch by its canonical first two vertices.
  std::set<std::pair<Key, Key>> traced;  // stretches left as traced
  auto simplified = [&](const std::vector<Vec2>& ring, const std::vector<char>& anchor,
                        std::vector<std::pair<Key, Key>>* stretches) {
    const size_t n = ring.size();
    std::vector<size_t> ends;
    for (size_t k = 0; k < n; ++k)
      if (anchor[k] || (ring[k] - ring[(k + 1) % n]).norm() >= long_m || (ring[k] - ring[(k + n - 1) % n]).norm() >= long_m)
        ends.push_back(k);
    if (ends.empty()) {
      size_t least = 0;
      for (size_t k = 1; k < n; ++k)
        if (key(ring[k]) < key(ring[least])) least = k;
      ends.push_back(least);
    }
    std::vector<char> keep(n, 0);
    for (size_t e : ends) keep[e] = 1;
    std::vector<Vec2> chain;
    std::vector<size_t> index;
    for (size_t s = 0; s < ends.size(); ++s) {
      const size_t a = ends[s], b = ends[(s + 1) % ends.size()];
      chain.clear();
      index.clear();
      for (size_t k = a;; k = (k + 1) % n) {
        chain.push_back(ring[k]);
        index.push_back(k);
        if (chain.size() > 1 && k == b) break;
      }
      if (chain.size() < 3) continue;
      const size_t m = chain.size();
      // Canonical direction: from the end whose first step is the lesser.
      const bool reverse = std::pair(key(chain[m - 1]), key(chain[m - 2])) < std::pair(key(chain[0]), key(chain[1]));
      if (reverse) {
        std::reverse(chain.begin(), chain.end());
        std::reverse(index.begin(), index.end());
      }
      const std::pair<Key, Key> id{key(chain[0]), key(chain[1])};
      stretches->push_back(id);
      if (traced.count(id)) {
        for (size_t k : index) keep[k] = 1;
        continue;
      }
      std::vector<char> kept(m, 0);
      KeepFarthest(chain, 0, m - 1, tol_m, &kept);
      for (size_t k = 0; k < m; ++k)
        if (kept[k]) keep[index[k]] = 1;
    }
    std::vector<Vec2> out;
    for (size_t k = 0; k < n; ++k)
      if (keep[k]) out.push_back(ring[k]);
    return out;
  };
  std::vector<std::vector<Vec2>> out(rings->size());
  bool again = true;
  for (int round = 0; again && round < 8; ++round) {
    again = false;
    for (size_t r = 0; r < rings->size(); ++r) {
      const std::vector<Vec2>& ring = (*rings)[r];
      if (ring.size() < 3) continue;
      std::vector<std::pair<Key, Key>> stretches;
      out[r] = simplified(ring, anchors[r], &stretches);
      bool simple = out[r].size() >= 3 && RingArea(out[r]) > 0.0;
      if (simple) {
        BPoly p;
        for (const Vec2& v : out[r]) p.outer().push_back(BPoint(v.x(), v.y()));
        simple = bg::is_valid(p);
      }
      if (!simple) {
        for (const auto& id : stretches) again = traced.insert(id).second || again;
        out[r] = ring;
      }
    }
  }
  if (again) return;  // (not settled: every outline as traced)
  for (size_t r = 0; r < rings->size(); ++r)
    if ((*rings)[r].size() >= 3) (*rings)[r] = std::move(out[r]);
}

// The outline of a filled region, counter-clockwise, collinear vertices merged,
// in the frame where lattice site (i, j) is the square origin + step * [i, i+1] x [j, j+1].
// 'inner_point': the centre of the site deepest inside (4-distance to the outline).
// A vertex on a straight stretch stays when 'keep(i, j)' says so for its
// lattice corner (i, j): where a neighbour's outline begins or ends, so that
// two rooms that meet have the same vertices along their common border.
template <class Keep>
std::vector<Vec2> TraceRegion(const Region& reg, const Vec2& origin, double step, Vec2* inner_point, Keep&& keep) {
  const int W = reg.W, H = reg.H;
  if (reg.count == 0) return {};
  auto filled = [&](int x, int y) { return reg.at(x, y); };
  const int x0 = reg.x0, y0 = reg.y0;
  // Boundary edges with the region on the left, from start vertex to end
  // vertex (vertices are cell corners, keyed (x, y) on the local lattice), in
  // scan order, then stably sorted by start vertex: a vertex's edges are
  // found by binary search, in the order they were found (a list as long as
  // the outline, not a table of the lattice's vertices).
  auto key = [&](int x, int y) { return static_cast<int64_t>(y) * (W + 1) + x; };
  struct Edge {
    int64_t from, to;
  };
  std::vector<Edge> edges;
  int64_t start = -1;
  for (int y = 0; y < H; ++y)
    for (int x = 0; x < W; ++x) {
      if (!filled(x, y)) continue;
      if (!filled(x, y - 1)) edges.push_back({key(x, y), key(x + 1, y)});          // bottom, left to right
      if (!filled(x + 1, y)) edges.push_back({key(x + 1, y), key(x + 1, y + 1)});  // right, upwards
      if (!filled(x, y + 1)) edges.push_back({key(x + 1, y + 1), key(x, y + 1)});  // top, right to left
      if (!filled(x - 1, y)) edges.push_back({key(x, y + 1), key(x, y)});          // left, downwards
      if (start < 0 && !filled(x, y - 1)) start = key(x, y);
    }
  std::stable_sort(edges.begin(), edges.end(), [](const Edge& a, const Edge& b) { return a.from < b.from; });
  std::vector<char> used(edges.size(), 0);
  size_t vertices = 0;  // distinct start vertices
  for (size_t k = 0; k < edges.size(); ++k) vertices += k == 0 || edges[k].from != edges[k - 1].from;
  // Walk the outer loop; at a pinch (two ways out) take the left turn, which
  // keeps the loop on the region's outline.
  std::vector<Vec2> ring;
  std::vector<std::pair<int, int>> corners;  // lattice corner of each ring vertex
  int64_t cur = start, prev = -1;
  const size_t limit = vertices * 2 + 8;
  std::vector<size_t> outs;  // the unused edges out of the current vertex, in order
  for (size_t guard = 0; guard < limit; ++guard) {
    const int cx = static_cast<int>(cur % (W + 1)), cy = static_cast<int>(cur / (W + 1));
    ring.push_back(Vec2(origin.x() + (x0 - 1 + cx) * step, origin.y() + (y0 - 1 + cy) * step));
    corners.push_back({x0 - 1 + cx, y0 - 1 + cy});
    outs.clear();
    auto it = std::lower_bound(edges.begin(), edges.end(), cur, [](const Edge& e, int64_t v) { return e.from < v; });
    for (; it != edges.end() && it->from == cur; ++it) {
      const size_t k = static_cast<size_t>(it - edges.begin());
      if (!used[k]) outs.push_back(k);
    }
    if (outs.empty()) break;
    size_t pick = 0;
    if (outs.size() > 1 && prev >= 0) {
      const Vec2 din(static_cast<double>(cx - prev % (W + 1)), static_cast<double>(cy - prev / (W + 1)));
      double best_turn = -10;
      for (size_t k = 0; k < outs.size(); ++k) {
        const int64_t to = edges[outs[k]].to;
        const Vec2 dout(static_cast<double>(to % (W + 1) - cx), static_cast<double>(to / (W + 1) - cy));
        const double turn = Cross(din, dout);  // > 0: left
        if (turn > best_turn) best_turn = turn, pick = k;
      }
    }
    const int64_t nxt = edges[outs[pick]].to;
    used[outs[pick]] = 1;
    prev = cur;
    cur = nxt;
    if (cur == start) break;
  }
  // Merge collinear vertices (but those 'keep' asks for).
  std::vector<Vec2> out;
  for (size_t i = 0; i < ring.size(); ++i) {
    const Vec2& p = ring[(i + ring.size() - 1) % ring.size()];
    const Vec2& c = ring[i];
    const Vec2& n = ring[(i + 1) % ring.size()];
    if (std::abs(Cross(c - p, n - c)) > 1e-12 || keep(corners[i].first, corners[i].second)) out.push_back(c);
  }
  // The cell deepest inside (farthest from the outline, 4-distance) for the label.
  if (inner_point) {
    // Breadth first from every site outside, in scan order: a queue of site
    // indices read from its front, the part read dropped once it is half
    // the queue (memory of the sites waiting, as a deque's, at half its).
    std::vector<int> dist(static_cast<size_t>(W) * H, -1);
    std::vector<int> q;
    for (int j = 0; j < W * H; ++j)
      if (!reg.filled[static_cast<size_t>(j)]) dist[static_cast<size_t>(j)] = 0, q.push_back(j);
    std::pair<int, int> deep{1, 1};
    int dmax = -1;
    for (size_t head = 0; head < q.size(); ++head) {
      if (head >= 4096 && 2 * head >= q.size()) {
        q.erase(q.begin(), q.begin() + static_cast<std::ptrdiff_t>(head));
        head = 0;
      }
      const int j0 = q[head];
      const int cx = j0 % W, cy = j0 / W;
      const int d = dist[static_cast<size_t>(j0)];
      if (d > dmax) dmax = d, deep = {cx, cy};
      const bool ok[4] = {cx + 1 < W, cx > 0, cy + 1 < H, cy > 0};
      const int nj[4] = {j0 + 1, j0 - 1, j0 + W, j0 - W};
      for (int k = 0; k < 4; ++k) {
        if (!ok[k] || dist[static_cast<size_t>(nj[k])] >= 0) continue;
        dist[static_cast<size_t>(nj[k])] = d + 1;
        q.push_back(nj[k]);
      }
    }
    *inner_point = Vec2(origin.x() + (x0 - 1 + deep.first + 0.5) * step, origin.y() + (y0 - 1 + deep.second + 0.5) * step);
  }
  return out;
}

// Principal lengths of a labelled region (a rectangle L x W has variances L^2/12, W^2/12).
struct Shape {
  double length_m = 0.0, width_m = 0.0, area_m2 = 0.0;
  Vec2 axis{1, 0};
  Vec2 centre{0, 0};                                   // of its area
  Eigen::Matrix2d cov = Eigen::Matrix2d::Zero();       // of its area (m^2)
  // Its extent along a unit direction: sqrt(12 x the variance along it), as
  // length_m and width_m are along the principal axes.
  double ExtentAlong(const Vec2& u) const { return std::sqrt(12.0 * std::max(0.0, u.dot(cov * u))); }
};

// The width of a convex polygon measured as RegionShapes measures a region's:
// sqrt(12 x the smaller principal variance of its area (exact polygon moments).
double PolygonWidth(const std::vector<Vec2>& poly) {
  double a = 0, cx = 0, cy = 0, ixx = 0, iyy = 0, ixy = 0;
  for (size_t i = 0; i < poly.size(); ++i) {
    const Vec2& p = poly[i];
    const Vec2& q = poly[(i + 1) % poly.size()];
    const double c = p.x() * q.y() - q.x() * p.y();
    a += c / 2;
    cx += c * (p.x() + q.x()) / 6;
    cy += c * (p.y() + q.y()) / 6;
    ixx += c * (p.x() * p.x() + p.x() * q.x() + q.x() * q.x()) / 12;
    iyy += c * (p.y() * p.y() + p.y() * q.y() + q.y() * q.y()) / 12;
    ixy += c * (p.x() * q.y() + 2 * p.x() * p.y() + 2 * q.x() * q.y() + q.x() * p.y()) / 24;
  }
  if (std::abs(a) < 1e-12) return 0.0;
  cx /= a, cy /= a;
  const double sxx = ixx / a - cx * cx, syy = iyy / a - cy * cy, sxy = ixy / a - cx * cy;
  const double mean = (sxx + syy) / 2, d = std::sqrt(std::max(0.0, (sxx - syy) * (sxx - syy) / 4 + sxy * sxy));
  return std::sqrt(12.0 * std::max(0.0, mean - d));
}

// A region's outline as its extreme points along kOutlineDirections
// directions (a half turn's worth), lattice frame: its convex hull is the
// hull of these points (exact for a box; for a room's shape within a few
// centimetres). Fixed size, so a building's regions take one allocation,
// and the outline of two regions together is the extremes of both.
constexpr int kOutlineDirections = 16;
struct Outline {
  // 2k: the farthest point along direction k, 2k + 1: against it; all
  // infinite while empty.
  std::array<Vec2, 2 * kOutlineDirections> point;
  Outline() { point.fill(Vec2::Constant(std::numeric_limits<double>::infinity())); }
  bool empty() const { return !std::isfinite(point[0].x()); }
  static const std::array<Vec2, kOutlineDirections>& Directions() {
    static const std::array<Vec2, kOutlineDirections> d = [] {
      std::array<Vec2, kOutlineDirections> out;
      for (int k = 0; k < kOutlineDirections; ++k)
        out[k] = Vec2(std::cos(kPi * k / kOutlineDirections), std::sin(kPi * k / kOutlineDirections));
      return out;
    }();
    return d;
  }
  void Add(const Vec2& q) {
    if (empty()) {
      point.fill(q);
      return;
    }
    const auto& dirs = Directions();
    for (int k = 0; k < kOutlineDirections; ++k) {
      const double d = dirs[k].dot(q);
      if (d > dirs[k].dot(point[2 * k])) point[2 * k] = q;
      if (d < dirs[k].dot(point[2 * k + 1])) point[2 * k + 1] = q;
    }
  }
  void Add(const Outline& o) {
    if (o.empty()) return;
    for (const Vec2& q : o.point) Add(q);
  }
  // The least width of the points' convex hull (the least, over its edges,
  // of the farthest point from the edge's line), its length across that
  // (its extent along that edge) and the direction the width is measured
  // along; 0, 0 (and x) when empty.
  struct Calipers {
    double width = 0.0, length = 0.0;
    Vec2 across{1, 0};
  };
  Calipers Measure() const {
    Calipers c;
    if (empty()) return c;
    const std::vector<Vec2> hull = ConvexHull(std::vector<Vec2>(point.begin(), point.end()));
    const int m = static_cast<int>(hull.size());
    double width = std::numeric_limits<double>::infinity();
    for (int i = 0; i < m; ++i) {
      const Vec2 a = hull[i], d = hull[(i + 1) % m] - a;
      const double len = d.norm();
      if (len < 1e-12) continue;
      const Vec2 u = d / len, nrm(-u.y(), u.x());
      double far = 0.0, lo = 0.0, hi = 0.0;
      for (int j = 0; j < m; ++j) {
        far = std::max(far, std::abs(nrm.dot(hull[j] - a)));
        lo = std::min(lo, u.dot(hull[j] - a));
        hi = std::max(hi, u.dot(hull[j] - a));
      }
      if (far < width) width = far, c.length = hi - lo, c.across = nrm;
    }
    c.width = std::isfinite(width) ? width : 0.0;
    return c;
  }
  std::pair<double, double> WidthAndLength() const {
    const Calipers c = Measure();
    return {c.width, c.length};
  }
  // The points' extent along unit direction u (0 when empty).
  double ExtentAlong(const Vec2& u) const {
    if (empty()) return 0.0;
    double lo = std::numeric_limits<double>::infinity(), hi = -lo;
    for (const Vec2& q : point) lo = std::min(lo, u.dot(q)), hi = std::max(hi, u.dot(q));
    return hi - lo;
  }
};

std::vector<Shape> RegionShapes(const RoomGrid& g, const Labels& label, int n,
                                std::vector<Outline>* outlines = nullptr) {
  std::vector<Moments> m(n);
  std::vector<double> cells(n, 0.0);
  // With 'outlines': each region's (lattice frame, not turned by phi),
  // from the corners of its first and last cell in every row it spans.
  if (outlines) outlines->assign(n, Outline());
  const int nd = outlines ? n : 0;
  std::vector<int> row(nd, -1), x0(nd, 0), x1(nd, 0);
  auto flush = [&](int r) {
    const double ya = g.lo.y() + row[r] * g.cell, yb = ya + g.cell;
    const double xa = g.lo.x() + x0[r] * g.cell, xb = g.lo.x() + (x1[r] + 1) * g.cell;
    for (const Vec2& q : {Vec2(xa, ya), Vec2(xa, yb), Vec2(xb, ya), Vec2(xb, yb)}) (*outlines)[r].Add(q);
  };
  label.ForEachStored([&](int x, int y, int r) {  // row-major: the sums' order is the dense lattice's
    if (r < 0) return;
    const Vec2 p(g.lo.x() + (x + 0.5) * g.cell, g.lo.y() + (y + 0.5) * g.cell);
    m[r].w += 1.0;
    m[r].s += p;
    m[r].ss += p * p.transpose();
    cells[r] += 1.0;
    if (!outlines) return;
    if (row[r] != y) {
      if (row[r] >= 0) flush(r);
      row[r] = y;
      x0[r] = x1[r] = x;
    } else {
      x1[r] = x;  // row-major: x grows along a row
    }
  });
  for (int r = 0; r < nd; ++r)
    if (row[r] >= 0) flush(r);
  std::vector<Shape> out(n);
  for (int r = 0; r < n; ++r) {
    if (m[r].w < 1.0) continue;
    Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> es(m[r].Cov());
    const double cell_var = g.cell * g.cell / 12.0;
    out[r].length_m = std::sqrt(12.0 * (std::max(0.0, es.eigenvalues()(1)) + cell_var));
    out[r].width_m = std::sqrt(12.0 * (std::max(0.0, es.eigenvalues()(0)) + cell_var));
    out[r].axis = g.FromFrame(es.eigenvectors().col(1));
    out[r].area_m2 = cells[r] * g.cell * g.cell;
    out[r].centre = g.FromFrame(m[r].Mean());
    const double c = std::cos(g.phi), sn = std::sin(g.phi);
    Eigen::Matrix2d rot;
    rot << c, -sn, sn, c;
    out[r].cov = rot * (m[r].Cov() + Eigen::Matrix2d::Identity() * (g.cell * g.cell / 12.0)) * rot.transpose();
  }
  return out;
}

struct UnionFind {
  std::vector<int> p;
  explicit UnionFind(int n) : p(n) { std::iota(p.begin(), p.end(), 0); }
  int Find(int x) { return p[x] == x ? x : p[x] = Find(p[x]); }
  bool Unite(int a, int b) {
    a = Find(a), b = Find(b);
    if (a == b) return false;
    p[std::max(a, b)] = std::min(a, b);
    return true;
  }
};

// A door found for an exit, before the plan rooms are known.
constexpr double kWayReach = 2.5;  // m: the path kept with a door (DoorCand::way)

struct DoorCand {
  Vec2 a, b;
  int from_asr = -1, to_asr = -1;
  bool in_wall = false;  // lies along walls: cut them
  bool jambs = false;    // in a wall, its ends at the faces beside the gap (else the exit's width)
  // The exit has no measured width (asr::Exit::width_m 0): the robot was
  // cut there by distance (BoundaryOptions::max_asr_m) or a resumed log
  // began there, not seen between two jambs. It may lie inside one space:
  // it does not part the rooms' first floods, and the open-plan rule
  // decides whether it is a door (BuildPlanFrom, "Open plan").
  bool unmeasured = false;
  // An unmeasured exit whose ASRs' paths went through a doorway the walls
  // show: a door the boundary detector missed, wherever the cut came.
  bool crossed_door = false;
  Vec2 centre{0, 0};  // the exit's placed centre (where the robot crossed)
  Vec2 line_c{0, 0}, line_u{1, 0};
  double lo = 0, hi = 0;  // the gap along line_u from line_c
  // The robot's way through it: each of the two ASRs' paths within
  // kWayReach of the exit (where a door that moves crosses the rooms' border).
  std::vector<std::vector<Vec2>> way;
  // How well it is placed: between jambs, then on a wall line, then across
  // the robot's way.
  int Rank() const { return jambs ? 2 : in_wall ? 1 : 0; }
};


// The plan; 'inputs_read' is called once the ASRs' walls, paths and floor and
// the placed paths have been read (after it only ids, poses, exits and times
// are), so a caller that hands them over can drop them before the floods.
Plan BuildPlanFrom(const std::vector<asr::Asr>& asrs, const std::map<int, int>& room_of_asr, const PlanOptions& o,
                   const std::map<int, std::vector<Pose2>>& placed_paths, const std::function<void()>& inputs_read) {
  Plan plan;
  if (asrs.empty()) return plan;

  // ---------------------------------------------------------------- inputs, placed
  std::map<int, size_t> index_of;
  for (size_t i = 0; i < asrs.size(); ++i) index_of[asrs[i].id] = i;
  std::vector<std::vector<Vec2>> path(asrs.size());
  std::vector<std::vector<Polyline>> walls(asrs.size());
  std::vector<std::vector<Vec2>> free_hull(asrs.size());  // the floor each ASR saw, placed
  std::vector<double> path_len(asrs.size(), 0.0);
  std::optional<Pose2> home;
  double first_time = std::numeric_limits<double>::infinity();
  for (size_t i = 0; i < asrs.size(); ++i) {
    const asr::Asr& x = asrs[i];
    std::vector<Pose2> poses;
    auto it = placed_paths.find(x.id);
    if (it != placed_paths.end() && !it->second.empty()) {
      poses = it->second;
    } else {
      const Pose2 carry = x.world_from_local_corrected * x.world_from_local_raw.inverse();
      for (const Pose2& p : x.path) poses.push_back(carry * p);
    }
    for (const Pose2& p : poses) path[i].push_back(p.translation());
    for (size_t k = 1; k < path[i].size(); ++k) path_len[i] += (path[i][k] - path[i][k - 1]).norm();
    walls[i] = x.WallsWorldCorrected();
    free_hull[i] = Transform(x.world_from_local_corrected, x.free_hull_local);
    if (!poses.empty() && (x.start_time_s < first_time || (!home && x.start_time_s == first_time))) {
      first_time = x.start_time_s;
      home = poses.front();
    }
  }
  plan.home = home;
  inputs_read();

  // ---------------------------------------------------------------- faces
  std::vector<Evidence> ev;
  for (size_t i = 0; i < asrs.size(); ++i)
    for (const auto& f : graph::FaceWalls(walls[i], path[i], o.min_segment_m))
      if (!path[i].empty()) ev.push_back({f.a, f.b, f.normal, static_cast<int>(i)});
  std::sort(ev.begin(), ev.end(), [](const Evidence& a, const Evidence& b) { return a.length() > b.length(); });

  const double cos_face = std::cos(Deg(o.face_angle_deg));
  std::vector<Face> faces;
  CellHash face_hash(2.0);
  const Vec2 reach(o.same_face_m + o.join_gap_m, o.same_face_m + o.join_gap_m);
  for (size_t e = 0; e < ev.size(); ++e) {
    const Evidence& s = ev[e];
    const Vec2 lo = s.a.cwiseMin(s.b), hi = s.a.cwiseMax(s.b);
    int best = -1;
    double best_d = std::numeric_limits<double>::infinity();
    for (int fi : face_hash.Query(lo - reach, hi + reach)) {
      const Face& f = faces[fi];
      if (f.n.dot(s.n) < cos_face) continue;
      const double da = std::abs(f.Offset(s.a)), db = std::abs(f.Offset(s.b));
      if (da > o.same_face_m || db > o.same_face_m) continue;
      const double ta = f.Along(s.a), tb = f.Along(s.b);
      if (std::max(ta, tb) < f.tmin - o.join_gap_m || std::min(ta, tb) > f.tmax + o.join_gap_m) continue;
      if (da + db < best_d) best_d = da + db, best = fi;
    }
    if (best < 0) {
      faces.emplace_back();
      best = static_cast<int>(faces.size()) - 1;
      faces[best].mom.Add(s.a, s.b, 1.0);
      faces[best].Refit(s.n);
      faces[best].tmin = std::min(faces[best].Along(s.a), faces[best].Along(s.b));
      faces[best].tmax = std::max(faces[best].Along(s.a), faces[best].Along(s.b));
    } else {
      Face& f = faces[best];
      f.mom.Add(s.a, s.b, 1.0);
      f.Refit(f.n);
      f.tmin = std::numeric_limits<double>::infinity(), f.tmax = -f.tmin;
    }
    Face& f = faces[best];
    f.members.push_back(static_cast<int>(e));
    if (f.members.size() > 1) {
      for (int m : f.members) {
        f.tmin = std::min({f.tmin, f.Along(ev[m].a), f.Along(ev[m].b)});
        f.tmax = std::max({f.tmax, f.Along(ev[m].a), f.Along(ev[m].b)});
      }
    }
    face_hash.Add(lo - Vec2(0.1, 0.1), hi + Vec2(0.1, 0.1), best);
  }

  // Refit each face with each ASR weighted by how well it saw it: the inverse
  // of (floor^2 + its mean squared residual to the fitted line).
  const double floor2 = o.residual_floor_m * o.residual_floor_m;
  std::vector<std::map<int, double>> face_quality(faces.size());  // asr index -> quality in (0, 1]
  for (size_t fi = 0; fi < faces.size(); ++fi) {
    Face& f = faces[fi];
    const Vec2 seed_n = f.n;
    std::map<int, double> q;
    for (int iter = 0; iter < 3; ++iter) {
      std::map<int, std::pair<double, double>> sq;  // asr -> (sum len * msd, sum len)
      for (int m : f.members) {
        const double d0 = f.Offset(ev[m].a), d1 = f.Offset(ev[m].b), len = ev[m].length();
        auto& acc = sq[ev[m].asr];
        acc.first += len * (d0 * d0 + d0 * d1 + d1 * d1) / 3.0;
        acc.second += len;
      }
      q.clear();
      for (const auto& [a, acc] : sq) q[a] = floor2 / (floor2 + acc.first / acc.second);
      Moments mom;
      for (int m : f.members) mom.Add(ev[m].a, ev[m].b, q[ev[m].asr]);
      f.mom = mom;
      f.Refit(seed_n);
    }
    face_quality[fi] = q;
    // Residual and direction standard error.
    double sum_len = 0, sum_sq = 0;
    Moments raw;
    for (int m : f.members) {
      const double d0 = f.Offset(ev[m].a), d1 = f.Offset(ev[m].b), len = ev[m].length();
      sum_sq += q[ev[m].asr] * len * (d0 * d0 + d0 * d1 + d1 * d1) / 3.0;
      sum_len += q[ev[m].asr] * len;
      raw.Add(ev[m].a, ev[m].b, 1.0);
    }
    const double spread = f.u.dot(raw.Cov() * f.u) * raw.w;  // integral of (t - tbar)^2
    f.sigma_theta = DirectionSigma(sum_sq / std::max(sum_len, 1e-9), floor2, spread, o.correlation_length_m);
    f.raw = raw;
    f.tmin = std::numeric_limits<double>::infinity(), f.tmax = -f.tmin;
    for (int m : f.members) {
      f.tmin = std::min({f.tmin, f.Along(ev[m].a), f.Along(ev[m].b)});
      f.tmax = std::max({f.tmax, f.Along(ev[m].a), f.Along(ev[m].b)});
    }
  }

  // ---------------------------------------------------------------- dominant direction and squaring
  {
    std::vector<double> hist(90, 0.0);
    for (const Face& f : faces) {
      const double a = std::atan2(f.u.y(), f.u.x());
      int bin = static_cast<int>(std::floor((QuarterOffset(a) + kPi / 4) / Deg(1.0)));
      bin = ((bin % 90) + 90) % 90;
      hist[bin] += f.mom.w > 0 ? (f.tmax - f.tmin) : 0.0;
    }
    int peak = 0;
    double peak_v = -1;
    for (int b = 0; b < 90; ++b) {
      double v = 0;
      for (int k = -2; k <= 2; ++k) v += hist[((b + k) % 90 + 90) % 90];
      if (v > peak_v) peak_v = v, peak = b;
    }
    const double peak_angle = -kPi / 4 + (peak + 0.5) * Deg(1.0);
    double sc = 0, ss = 0;
    for (const Face& f : faces) {
      const double a = std::atan2(f.u.y(), f.u.x());
      const double d = QuarterOffset(a - peak_angle);
      if (std::abs(d) > Deg(5.0)) continue;
      const double w = f.tmax - f.tmin;
      sc += w * std::cos(4 * a), ss += w * std::sin(4 * a);
    }
    double phi = sc == 0 && ss == 0 ? peak_angle : std::atan2(ss, sc) / 4.0;
    phi = std::fmod(phi + 2 * kPi, kPi / 2);
    plan.dominant_direction_rad = phi;
    // The scatter of the walls' directions that the fits do not explain (the
    // ASRs' heading errors, the vectorizer): 1.4826 x the length-weighted
    // median offset of the faces within 10 degrees of the building's
    // direction (a robust sigma), at least heading_floor_deg.
    std::vector<std::pair<double, double>> offs;  // |offset|, length
    double total = 0.0;
    for (const Face& f : faces) {
      const double d = std::abs(QuarterOffset(std::atan2(f.u.y(), f.u.x()) - phi));
      if (d < Deg(10.0)) offs.push_back({d, f.tmax - f.tmin}), total += f.tmax - f.tmin;
    }
    std::sort(offs.begin(), offs.end());
    double acc = 0.0, med = 0.0;
    for (const auto& [d, w] : offs) {
      acc += w;
      if (acc >= 0.5 * total) {
        med = d;
        break;
      }
    }
    const double floor_theta = std::max(Deg(o.heading_floor_deg), 1.4826 * med);
    plan.direction_scatter_rad = floor_theta;
    for (Face& f : faces) {
      if (SquareTo(phi, floor_theta, f.sigma_theta, o.square_z, &f.u)) {
        const Vec2 n_old = f.n;
        f.n = Perp(f.u);
        if (f.n.dot(n_old) < 0) f.n = -f.n;
        f.squared = true;
        f.tmin = std::numeric_limits<double>::infinity(), f.tmax = -f.tmin;
        for (int m : f.members) {
          f.tmin = std::min({f.tmin, f.Along(ev[m].a), f.Along(ev[m].b)});
          f.tmax = std::max({f.tmax, f.Along(ev[m].a), f.Along(ev[m].b)});
        }
      }
    }
  }

  // ---------------------------------------------------------------- pieces (spans of each face)
  std::vector<Piece> pieces;
  for (size_t fi = 0; fi < faces.size(); ++fi) {
    const Face& f = faces[fi];
    std::vector<std::pair<double, double>> iv;
    for (int m : f.members) {
      const double ta = f.Along(ev[m].a), tb = f.Along(ev[m].b);
      iv.push_back({std::min(ta, tb), std::max(ta, tb)});
    }
    const std::vector<std::pair<double, double>> spans = JoinSpans(std::move(iv), o.join_gap_m);
    Piece p;
    p.c = f.c, p.u = f.u, p.n = f.n, p.squared = f.squared;
    p.mom = f.mom, p.raw = f.raw;
    double ext = 0.0;
    for (const auto& s : spans)
      if (s.second - s.first >= o.min_wall_m) p.spans.push_back(s), ext += s.second - s.first;
    if (p.spans.empty()) continue;
    double seen = 0.0;
    for (int m : f.members) {
      p.asrs.insert(asrs[ev[m].asr].id);
      seen += ev[m].length() * face_quality[fi].at(ev[m].asr);
    }
    p.weight = seen;
    pieces.push_back(std::move(p));
  }
  // The pieces carry the faces on: the evidence and the faces go.
  std::vector<Evidence>().swap(ev);
  std::vector<Face>().swap(faces);
  std::vector<std::map<int, double>>().swap(face_quality);
  face_hash = CellHash(2.0);

  // Two pieces as one: the line fitted to the evidence of both (their
  // quality-weighted moments added, as one face's is fitted), squared to the
  // building's direction by the faces' test, free side A's; their ASRs and
  // weight together. The caller sets the spans.
  auto fit_both = [&](const Piece& A, const Piece& B) {
    Piece f;
    f.mom = A.mom;
    f.mom.Add(B.mom);
    f.raw = A.raw;
    f.raw.Add(B.raw);
    Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> es(f.mom.Cov());
    f.u = es.eigenvectors().col(1).normalized();
    const double sigma_theta =
        DirectionSigma(es.eigenvalues()(0), floor2, f.u.dot(f.raw.Cov() * f.u) * f.raw.w, o.correlation_length_m);
    f.squared = SquareTo(plan.dominant_direction_rad, plan.direction_scatter_rad, sigma_theta, o.square_z, &f.u);
    f.n = Perp(f.u);
    if (f.n.dot(A.n) < 0) f.n = -f.n;
    f.c = f.mom.Mean();
    f.asrs = A.asrs;
    f.asrs.insert(B.asrs.begin(), B.asrs.end());
    f.weight = A.weight + B.weight;
    return f;
  };

  // ---------------------------------------------------------------- one face found twice
  // Grouping tests each segment against a face's line as it stands when the
  // segment comes, so two faces of one wall can stay apart (each room placed
  // with its own error, each face fitted without the other). But two opaque
  // faces that face the same way cannot both be seen along the same stretch:
  // the nearer hides the farther. So same-facing pieces whose lines lie
  // within same_face_m of each other along an overlap of at least min_wall_m
  // are one face, refitted as one line with each weighted by its evidence
  // (test SameFaceFoundTwiceIsOneWall).
  {
    auto extent = [](const Piece& p) {
      return std::make_pair(p.spans.front().first, p.spans.back().second);
    };
    std::vector<bool> gone(pieces.size(), false);
    for (bool again = true; again;) {
      again = false;
      CellHash hash(2.0);
      auto box = [&](const Piece& p, Vec2* lo, Vec2* hi) {
        const auto [t0, t1] = extent(p);
        const Vec2 a = p.c + t0 * p.u, b = p.c + t1 * p.u;
        *lo = a.cwiseMin(b), *hi = a.cwiseMax(b);
      };
      for (size_t i = 0; i < pieces.size(); ++i) {
        if (gone[i]) continue;
        Vec2 lo, hi;
        box(pieces[i], &lo, &hi);
        hash.Add(lo, hi, static_cast<int>(i));
      }
      const Vec2 m(o.same_face_m, o.same_face_m);
      for (size_t i = 0; i < pieces.size(); ++i) {
        if (gone[i]) continue;
        Vec2 lo, hi;
        box(pieces[i], &lo, &hi);
        for (int j : hash.Query(lo - m, hi + m)) {
          if (j == static_cast<int>(i) || gone[j] || gone[i]) continue;
          Piece& A = pieces[i];
          const Piece& B = pieces[j];
          if (A.n.dot(B.n) < cos_face) continue;
          const auto [a0, a1] = extent(A);
          const auto [b0, b1] = extent(B);
          const Vec2 q0 = B.c + b0 * B.u, q1 = B.c + b1 * B.u;
          const double t0 = std::max(a0, std::min(A.u.dot(q0 - A.c), A.u.dot(q1 - A.c)));
          const double t1 = std::min(a1, std::max(A.u.dot(q0 - A.c), A.u.dot(q1 - A.c)));
          if (t1 - t0 < o.min_wall_m) continue;
          // B's line where A's overlap ends fall on it.
          const Vec2 pa0 = A.c + t0 * A.u, pa1 = A.c + t1 * A.u, pb0 = B.Foot(pa0), pb1 = B.Foot(pa1);
          if (std::abs(A.n.dot(pb0 - pa0)) >= o.same_face_m || std::abs(A.n.dot(pb1 - pa1)) >= o.same_face_m) continue;
          // One line fitted to the evidence of both, as one face's is
          // (each ASR weighted by its quality), and squared to the
          // building's direction by the same test. Not the two lines'
          // directions averaged about their overlap: a short piece a few
          // degrees off turned a long wall about the overlap's middle, its
          // far end half a metre off (aria/office, 16 sonars: an 11 m wall
          // turned 2.7 degrees by a 1 m piece 15 degrees off).
          Piece f = fit_both(A, B);
          std::vector<std::pair<double, double>> iv;
          for (const Piece* p : {static_cast<const Piece*>(&A), &B})
            for (const auto& sp : p->spans) {
              const double u0 = f.u.dot(p->c + sp.first * p->u - f.c), u1 = f.u.dot(p->c + sp.second * p->u - f.c);
              iv.push_back({std::min(u0, u1), std::max(u0, u1)});
            }
          f.spans = JoinSpans(std::move(iv), o.join_gap_m);
          A = std::move(f);
          gone[j] = true;
          again = true;
        }
      }
    }
    std::vector<Piece> kept;
    for (size_t i = 0; i < pieces.size(); ++i)
      if (!gone[i]) kept.push_back(std::move(pieces[i]));
    pieces = std::move(kept);
  }

  // ---------------------------------------------------------------- one wall seen tilted from both sides
  // Two faces that face away from each other and cross (an X or a narrow
  // V) cannot both be walls: each would put its free side inside the
  // other's wall. A sonar draws the wall between two rooms so beside a
  // doorway: each room's view of it leans, the echo at the jamb coming from
  // off the transducer's axis, anywhere across the cone, so its end is
  // pulled aside by up to the cone's half width at the range,
  // reach x sin(beam / 2), and a face of length L leans by up to
  // atan(reach sin(beam / 2) / L) (a 1.5 m stub seen by a 30-degree sonar
  // within 3 m: 27 degrees; the views cross near the wall's far end, where
  // both are right). Such a pair is one wall seen from both sides, fitted to
  // the evidence of both (the leans cancel) and squared by the faces' test.
  // Only faces whose directions differ by no more than their two leans
  // allow, and never more than kMaxLeans (PlanOptions::beam_width_rad and
  // reach_m; a laser's beam is a fraction of a degree, so its crossing
  // walls stay two; walls meeting at a corner or a T are 90 degrees apart).
  // Without a reach the beam itself bounds the difference, and the two must
  // cross between a fifth and four fifths of each other.
  if (o.beam_width_rad > 0.0) {
    constexpr double kMaxLeans = kPi / 3;
    const double cos_opposite = std::cos(std::min(o.beam_width_rad, kPi / 4));
    std::vector<bool> gone(pieces.size(), false);
    std::vector<Piece> merged;
    CellHash hash(2.0);
    auto ends = [](const Piece& p, Vec2* a, Vec2* b) {
      *a = p.c + p.spans.front().first * p.u;
      *b = p.c + p.spans.back().second * p.u;
    };
    for (size_t i = 0; i < pieces.size(); ++i) {
      if (pieces[i].spans.size() != 1) continue;
      Vec2 a, b;
      ends(pieces[i], &a, &b);
      hash.Add(a.cwiseMin(b), a.cwiseMax(b), static_cast<int>(i));
    }
    for (size_t i = 0; i < pieces.size(); ++i) {
      if (gone[i] || pieces[i].spans.size() != 1) continue;
      Vec2 a0, a1;
      ends(pieces[i], &a0, &a1);
      for (int j : hash.Query(a0.cwiseMin(a1), a0.cwiseMax(a1))) {
        if (j <= static_cast<int>(i) || gone[j] || gone[i]) continue;
        const Piece& A = pieces[i];
        const Piece& B = pieces[j];
        if (A.two_sided || B.two_sided) continue;
        Vec2 b0, b1;
        ends(B, &b0, &b1);
        if (!SegmentsCross(a0, a1, b0, b1)) continue;
        if (o.reach_m > 0.0) {
          // Each view leans by at most the angle under which the cone's half
          // width at the sensor's reach shows across the face's length.
          const double side = o.reach_m * std::sin(0.5 * o.beam_width_rad);
          const double allowed = std::atan(side / (a1 - a0).norm()) + std::atan(side / (b1 - b0).norm());
          if (std::acos(std::clamp(-A.n.dot(B.n), -1.0, 1.0)) > std::min(allowed, kMaxLeans)) continue;
        } else {
          // The beam alone, and an X well inside both (where they cross, as
          // fractions along each).
          if (A.n.dot(B.n) > -cos_opposite) continue;
          const Vec2 da = a1 - a0, db = b1 - b0;
          const double den = Cross(da, db);
          if (std::abs(den) < 1e-12) continue;
          const double ta = Cross(b0 - a0, db) / den, tb = Cross(b0 - a0, da) / den;
          if (ta < 0.2 || ta > 0.8 || tb < 0.2 || tb > 0.8) continue;
        }
        Piece f = fit_both(A, B);
        double t0 = std::numeric_limits<double>::infinity(), t1 = -t0;
        for (const Vec2& q : {a0, a1, b0, b1}) t0 = std::min(t0, f.u.dot(q - f.c)), t1 = std::max(t1, f.u.dot(q - f.c));
        f.spans = {{t0, t1}};
        f.two_sided = true;
        merged.push_back(std::move(f));
        gone[i] = gone[j] = true;
      }
    }
    std::vector<Piece> kept;
    for (size_t i = 0; i < pieces.size(); ++i)
      if (!gone[i]) kept.push_back(std::move(pieces[i]));
    for (auto& m : merged) kept.push_back(std::move(m));
    pieces = std::move(kept);
  }

  // ---------------------------------------------------------------- thin walls: opposite faces that coincide
  {
    const double thin_seen = o.thin_wall_m - 2.0 * o.face_behind_m;
    CellHash hash(2.0);
    auto box = [](const Piece& p, Vec2* lo, Vec2* hi) {
      *lo = Vec2(1e300, 1e300), *hi = -*lo;
      for (const auto& s : p.spans)
        for (double t : {s.first, s.second}) {
          const Vec2 q = p.c + t * p.u;
          *lo = lo->cwiseMin(q), *hi = hi->cwiseMax(q);
        }
    };
    for (size_t i = 0; i < pieces.size(); ++i) {
      Vec2 lo, hi;
      box(pieces[i], &lo, &hi);
      hash.Add(lo, hi, static_cast<int>(i));
    }
    std::vector<Piece> merged;
    const size_t n_pieces = pieces.size();
    for (size_t i = 0; i < n_pieces; ++i) {
      Vec2 lo, hi;
      box(pieces[i], &lo, &hi);
      const Vec2 m(std::max(0.0, thin_seen), std::max(0.0, thin_seen));
      for (int j : hash.Query(lo - m, hi + m)) {
        if (j <= static_cast<int>(i)) continue;
        Piece& A = pieces[i];
        Piece& B = pieces[j];
        if (A.n.dot(B.n) > -cos_face) continue;
        // B's spans in A's parameter; overlap with A's spans.
        for (const auto& sb : std::vector<std::pair<double, double>>(B.spans)) {
          const Vec2 q0 = B.c + sb.first * B.u, q1 = B.c + sb.second * B.u;
          const double t0 = std::min(A.u.dot(q0 - A.c), A.u.dot(q1 - A.c));
          const double t1 = std::max(A.u.dot(q0 - A.c), A.u.dot(q1 - A.c));
          for (const auto& sa : std::vector<std::pair<double, double>>(A.spans)) {
            const double o0 = std::max(t0, sa.first), o1 = std::min(t1, sa.second);
            if (o1 - o0 < 0.1) continue;
            // Separation at the overlap's two ends: B behind A (opposite A's
            // free side) by s. A real wall has s >= 0 (its thickness); faces
            // that cross (s < 0) put each room's floor beyond the other's
            // wall, which no wall does: they are one wall that placement
            // and sensor put apart, as far as two views of one face may lie
            // (same_face_m).
            const Vec2 a0 = A.c + o0 * A.u, a1 = A.c + o1 * A.u, b0 = B.Foot(a0), b1 = B.Foot(a1);
            const double s0 = -A.n.dot(b0 - a0), s1 = -A.n.dot(b1 - a1);
            // Seen closer than a thin wall's faces are (thin_wall_m less
            // the sensor's two face offsets, face_behind_m).
            if (s0 >= thin_seen || s1 >= thin_seen || s0 <= -o.same_face_m || s1 <= -o.same_face_m) continue;
            Piece t;
            const Vec2 m0 = 0.5 * (a0 + b0), m1 = 0.5 * (a1 + b1);
            t.c = m0;
            t.u = (m1 - m0).normalized();
            t.n = Perp(t.u);
            if (t.n.dot(A.n) < 0) t.n = -t.n;
            t.spans = {{0.0, (m1 - m0).norm()}};
            t.asrs = A.asrs;
            t.asrs.insert(B.asrs.begin(), B.asrs.end());
            t.weight = A.weight + B.weight;
            t.squared = A.squared && B.squared;
            t.two_sided = true;
            merged.push_back(t);
            SubtractSpan(&A.spans, o0, o1);
            const double u0 = B.u.dot(b0 - B.c), u1 = B.u.dot(b1 - B.c);
            SubtractSpan(&B.spans, std::min(u0, u1), std::max(u0, u1));
          }
        }
      }
    }
    for (auto& p : pieces) {
      std::vector<std::pair<double, double>> keep;
      for (const auto& s : p.spans)
        if (s.second - s.first >= 0.5 * o.min_wall_m) keep.push_back(s);
      p.spans = std::move(keep);
    }
    for (auto& m : merged) pieces.push_back(std::move(m));
  }

  // Straight walls: one per span.
  struct Seg {
    Vec2 a, b, n;
    size_t piece;
  };
  std::vector<Seg> segs;
  for (size_t i = 0; i < pieces.size(); ++i)
    for (const auto& s : pieces[i].spans)
      segs.push_back({pieces[i].c + s.first * pieces[i].u, pieces[i].c + s.second * pieces[i].u, pieces[i].n, i});

  // The walls by their boxes (the chamfers' T junctions, the doors, their
  // cuts, the walls beside doors).
  auto wall_boxes = [&] {
    CellHash h(2.0);
    for (size_t i = 0; i < segs.size(); ++i)
      h.Add(segs[i].a.cwiseMin(segs[i].b), segs[i].a.cwiseMax(segs[i].b), static_cast<int>(i));
    return h;
  };
  // The sensor's beam (the chamfers below, the jambs' diagonals after the
  // doors): a cone of half-width b seen from d metres smears a wall's end by
  // blur = 2 cells + tan(b) d, d at most the reach; blur_max from the reach.
  // Without a reach (a store from before it was kept), a sonar's own range:
  // 10 m for the Polaroid ranger. Laser or no beam known: tan_half 0.
  constexpr double kUnboundedReachM = 10.0;
  const double tan_half = o.beam_width_rad > 0.0 ? std::tan(0.5 * std::min(o.beam_width_rad, kPi / 2)) : 0.0;
  const double blur_max =
      tan_half > 0.0 ? 2.0 * o.cell_m + tan_half * (o.reach_m > 0.0 ? o.reach_m : kUnboundedReachM) : 0.0;
  // The blur at q as seen from the nearest point of 'paths' (one per ASR
  // index) of the ASRs behind piece p (Piece::asrs holds their ids; that
  // point returned in 'seen'); infinity when none has a path.
  auto blur_seen = [&](const auto& paths, const Piece& p, const Vec2& q, Vec2* seen) {
    double best = std::numeric_limits<double>::infinity();
    for (int id : p.asrs)
      for (const auto& pv : paths[index_of.at(id)]) {
        const Vec2 v(pv.x(), pv.y());
        const double d2 = (v - q).squaredNorm();
        if (d2 < best) best = d2, *seen = v;
      }
    if (!std::isfinite(best)) return best;
    double dist = std::sqrt(best);
    if (o.reach_m > 0.0) dist = std::min(dist, o.reach_m);
    return 2.0 * o.cell_m + tan_half * dist;
  };
  const double sin15 = std::sin(Deg(15.0)), sin60 = std::sin(Deg(60.0));

  // ---------------------------------------------------------------- corners
  {
    CellHash ends(std::max(o.corner_m, 0.2));
    for (size_t i = 0; i < segs.size(); ++i) {
      ends.Add(segs[i].a, segs[i].a, static_cast<int>(2 * i));
      ends.Add(segs[i].b, segs[i].b, static_cast<int>(2 * i + 1));
    }
    struct Cand {
      double cost;
      int e1, e2;
      Vec2 x;
    };
    std::vector<Cand> cands;
    const double min_sin = std::sin(Deg(o.corner_min_angle_deg));
    // Chamfers: a short diagonal wall between the ends of two walls that
    // meet at a corner is how a sonar sees that corner; it goes, and the
    // corner closes. Two tests, either suffices: the fixed one (at most
    // chamfer_max_m long, 30-60 degrees off the building's direction, the
    // walls' crossing within corner_m of their ends), and the beam's: a
    // cone of half-width b seen from d metres away smears a wall's end by
    // blur = 2 cells + tan(b) d (the walls' corner radius, docs/walls.md),
    // so a concave corner seen from d comes out cut by a diagonal up to
    // 2 blur long whose ends lie up to 1.5 blur from the crossing (its
    // rounding radius, and the chain's vertex on the arc) and within pi/4
    // blur (the rest of the arc) of the walls' ends, or of the interior of
    // a wall that goes on past the corner, on the far side of the diagonal
    // from where the robot was. A diagonal that the beam explains so (15
    // degrees or more off both walls) is that corner. For a laser (half a
    // degree) the blur is its 2-cell floor: the fixed test alone.
    std::vector<char> drop(segs.size(), 0);
    struct Join {
      int e1, e2;  // the two walls' ends (2 * seg + end), before the drop; -1: a wall going on past the corner
      Vec2 x;
    };
    std::vector<Join> joins;  // the corners the beam's test found, closed below
    // The walls by their boxes, for a diagonal's end on another wall's
    // interior (a T: the wall goes on past the corner).
    const CellHash seg_boxes = tan_half > 0.0 ? wall_boxes() : CellHash(2.0);
    struct Partner {
      size_t seg;
      int end;  // 2 * seg + end when the diagonal meets its end; -1: its interior
      Vec2 p;   // that end, or the foot on the wall
    };
    for (size_t i = 0; i < segs.size(); ++i) {
      const Vec2 d = segs[i].b - segs[i].a;
      const double len = d.norm();
      if (pieces[segs[i].piece].two_sided) continue;
      const double off = std::abs(QuarterOffset(std::atan2(d.y(), d.x()) - plan.dominant_direction_rad));
      const bool fixed_ok = len <= o.chamfer_max_m && off >= Deg(30.0);
      // The most the beam can blur (seen from its reach) bounds the search;
      // each corner's own blur below.
      const bool beam_ok = blur_max > 0.0 && len <= 2.0 * blur_max && off >= Deg(15.0);
      if (!fixed_ok && !beam_ok) continue;
      const double end_tol = std::max(o.chamfer_end_m, beam_ok ? kPi / 4 * blur_max : 0.0);
      const Vec2 ud = d / std::max(len, 1e-9);
      // The walls each end of the diagonal meets: their ends within end_tol,
      // and (beam's test) their interiors.
      auto partners = [&](const Vec2& q) {
        std::vector<Partner> out;
        const Vec2 e(end_tol, end_tol);
        for (int ea : ends.Query(q - e, q + e)) {
          const size_t j = static_cast<size_t>(ea / 2);
          const Vec2 pj = (ea % 2) ? segs[j].b : segs[j].a;
          if (j != i && !drop[j] && (pj - q).norm() <= end_tol) out.push_back({j, ea, pj});
        }
        if (!beam_ok) return out;
        for (int si : seg_boxes.Query(q - e, q + e)) {
          const size_t j = static_cast<size_t>(si);
          if (j == i || drop[j]) continue;
          const Vec2 w = segs[j].b - segs[j].a;
          const double t = w.dot(q - segs[j].a) / std::max(w.squaredNorm(), 1e-12);
          const Vec2 foot = segs[j].a + t * w;
          // Within the wall and clear of its ends (those are met above).
          if (t <= 0.0 || t >= 1.0 || (foot - q).norm() > end_tol) continue;
          if (std::min(t, 1.0 - t) * std::sqrt(w.squaredNorm()) <= end_tol) continue;
          out.push_back({j, -1, foot});
        }
        return out;
      };
      const std::vector<Partner> at_a = partners(segs[i].a), at_b = partners(segs[i].b);
      bool found = false;
      Join best{-1, -1, Vec2(0, 0)};
      double best_cost = std::numeric_limits<double>::infinity();
      for (const Partner& A : at_a)
        for (const Partner& B : at_b) {
          if (A.seg == B.seg || (A.end < 0 && B.end < 0)) continue;
          const Vec2 du = (segs[A.seg].b - segs[A.seg].a).normalized(), dv = (segs[B.seg].b - segs[B.seg].a).normalized();
          const double den = Cross(du, dv);
          if (std::abs(den) < sin60) continue;
          const Vec2 x = segs[A.seg].a + (Cross(segs[B.seg].a - segs[A.seg].a, dv) / den) * du;
          const double da = (x - A.p).norm(), db = (x - B.p).norm();
          if (fixed_ok && A.end >= 0 && B.end >= 0 && (A.p - segs[i].a).norm() <= o.chamfer_end_m &&
              (B.p - segs[i].b).norm() <= o.chamfer_end_m && da <= o.corner_m && db <= o.corner_m)
            found = true;
          // 15 degrees or more off both walls (a diagonal), and the beam's
          // blur of the corner: the corner was seen from no nearer than the
          // path comes to it.
          if (!beam_ok || std::abs(Cross(ud, du)) < sin15 || std::abs(Cross(ud, dv)) < sin15) continue;
          Vec2 seen_from(0, 0);
          const double blur = blur_seen(path, pieces[segs[i].piece], x, &seen_from);
          if (!std::isfinite(blur)) continue;
          const double tol = std::max(o.chamfer_end_m, kPi / 4 * blur);
          if (len > 2.0 * blur || da > 1.5 * blur || db > 1.5 * blur) continue;
          if ((A.p - segs[i].a).norm() > tol || (B.p - segs[i].b).norm() > tol) continue;
          // The corner beyond the diagonal as seen from the path (a concave
          // corner).
          const Vec2 nd = Perp(ud);
          if (nd.dot(x - segs[i].a) * nd.dot(seen_from - segs[i].a) >= 0.0) continue;
          if (da + db < best_cost) best_cost = da + db, best = {A.end, B.end, x};
        }
      if (best.e1 >= 0 || best.e2 >= 0) {
        found = true;
        joins.push_back(best);
      }
      if (found) drop[i] = 1;
    }
    {
      std::vector<Seg> kept;
      std::vector<int> new_index(segs.size(), -1);
      for (size_t i = 0; i < segs.size(); ++i)
        if (!drop[i]) new_index[i] = static_cast<int>(kept.size()), kept.push_back(segs[i]);
      if (kept.size() != segs.size()) {
        segs = std::move(kept);
        ends = CellHash(std::max(o.corner_m, 0.2));
        for (size_t i = 0; i < segs.size(); ++i) {
          ends.Add(segs[i].a, segs[i].a, static_cast<int>(2 * i));
          ends.Add(segs[i].b, segs[i].b, static_cast<int>(2 * i + 1));
        }
        // The beam's corners, in the kept walls' numbering (a wall another
        // chamfer's test dropped joins nothing).
        auto renumber = [&](int e) {  // -1 stays -1 (a wall's interior); -2: its wall was dropped
          if (e < 0) return -1;
          const int k = new_index[static_cast<size_t>(e / 2)];
          return k < 0 ? -2 : 2 * k + e % 2;
        };
        std::vector<Join> renumbered;
        for (const Join& j : joins) {
          const int e1 = renumber(j.e1), e2 = renumber(j.e2);
          if (e1 != -2 && e2 != -2) renumbered.push_back({e1, e2, j.x});
        }
        joins = std::move(renumbered);
      }
    }
    const Vec2 r(o.corner_m, o.corner_m);
    for (size_t i = 0; i < segs.size(); ++i)
      for (int end = 0; end < 2; ++end) {
        const Vec2 p = end ? segs[i].b : segs[i].a;
        for (int e2 : ends.Query(p - r, p + r)) {
          const size_t j = static_cast<size_t>(e2 / 2);
          if (j <= i) continue;
          const Vec2 q = (e2 % 2) ? segs[j].b : segs[j].a;
          const Vec2 du = (segs[i].b - segs[i].a).normalized(), dv = (segs[j].b - segs[j].a).normalized();
          const double den = Cross(du, dv);
          if (std::abs(den) < min_sin) continue;
          // Crossing of the two lines.
          const double t = Cross(segs[j].a - segs[i].a, dv) / den;
          const Vec2 x = segs[i].a + t * du;
          const double d1 = (x - p).norm(), d2 = (x - q).norm();
          if (d1 > o.corner_m || d2 > o.corner_m) continue;
          // Neither end may move farther than the two ends lie apart (a cell
          // at least): at a right angle each moves 0.71 of that gap, but two
          // walls at a shallow angle meet far beyond both ends, where
          // neither was seen (cluttered_lab: a 0.6 m box's bottom face and a
          // 31 degree diagonal of it, ends 0.33 m apart, met 0.55 m out: a
          // spur 0.6 m off every true wall).
          if (std::max(d1, d2) > std::max((p - q).norm(), o.cell_m)) continue;
          // The end must move along its wall by extending or trimming only a little:
          // a trim must not eat more than half the wall.
          if ((x - (end ? segs[i].a : segs[i].b)).norm() < 0.5 * (segs[i].b - segs[i].a).norm()) continue;
          if ((x - ((e2 % 2) ? segs[j].a : segs[j].b)).norm() < 0.5 * (segs[j].b - segs[j].a).norm()) continue;
          cands.push_back({d1 + d2, static_cast<int>(2 * i + end), e2, x});
        }
      }
    std::sort(cands.begin(), cands.end(), [](const Cand& a, const Cand& b) { return a.cost < b.cost; });
    std::vector<char> used(2 * segs.size(), 0);
    // The beam's corners first: their ends lie farther from the crossing
    // than corner_m, and the diagonal between them is gone.
    for (const Join& j : joins) {
      if ((j.e1 >= 0 && used[j.e1]) || (j.e2 >= 0 && used[j.e2])) continue;
      for (int e : {j.e1, j.e2})
        if (e >= 0) used[e] = 1, (e % 2 ? segs[e / 2].b : segs[e / 2].a) = j.x;
    }
    for (const Cand& c : cands) {
      if (used[c.e1] || used[c.e2]) continue;
      used[c.e1] = used[c.e2] = 1;
      for (int e : {c.e1, c.e2}) (e % 2 ? segs[e / 2].b : segs[e / 2].a) = c.x;
    }
  }

  // ---------------------------------------------------------------- doors from exits
  std::vector<DoorCand> door_cands;
  // The wall segments by their boxes (the doors below, the doorway gaps after them).
  const CellHash seg_hash = wall_boxes();
  {
    // One door per exit: an exit is listed by both of its ASRs; average its placed centres.
    struct ExitAcc {
      Vec2 sum{0, 0};
      int n = 0;
      double width = 0.0;
      int from = -1, to = -1;
    };
    std::vector<ExitAcc> exits;
    std::map<std::pair<int, int>, std::vector<size_t>> exits_of_pair;
    for (size_t i = 0; i < asrs.size(); ++i) {
      const Pose2 carry = asrs[i].world_from_local_corrected * asrs[i].world_from_local_raw.inverse();
      for (const asr::Exit& x : asrs[i].exits) {
        const Vec2 c = carry * x.center_m;
        bool found = false;
        auto& same = exits_of_pair[{x.from_asr, x.to_asr}];
        for (size_t k : same) {
          ExitAcc& e = exits[k];
          if ((e.sum / e.n - c).norm() < 1.5) {
            e.sum += c, ++e.n, found = true;
            break;
          }
        }
        if (!found) {
          same.push_back(exits.size());
          exits.push_back({c, 1, x.width_m, x.from_asr, x.to_asr});
        }
      }
    }
    for (const auto& e : exits) {
      DoorCand d;
      d.from_asr = e.from, d.to_asr = e.to;
      d.unmeasured = e.width <= 0.0;
      const Vec2 c = e.sum / e.n;
      d.centre = c;
      const double w = std::clamp(e.width, o.min_door_m, o.max_door_m);
      // The wall lines that pass the exit (their extent grown by a door
      // width), nearest first.
      const Vec2 r(o.door_search_m + o.max_door_m, o.door_search_m + o.max_door_m);
      std::vector<std::pair<double, int>> lines;
      for (int si : seg_hash.Query(c - r, c + r)) {
        const Seg& s = segs[si];
        const Vec2 u = (s.b - s.a).normalized();
        const double t = u.dot(c - s.a), len = (s.b - s.a).norm();
        if (t < -o.max_door_m || t > len + o.max_door_m) continue;
        const double dist = std::abs(Perp(u).dot(c - s.a));
        if (dist < o.door_search_m) lines.push_back({dist, si});
      }
      std::sort(lines.begin(), lines.end());
      // The faces along the line of segment si, within reach of the exit:
      // their covered spans on it, from the exit's foot p.
      auto faces_along = [&](int si, Vec2* foot, Vec2* dir) {
        const Seg& s = segs[si];
        const Vec2 u = (s.b - s.a).normalized();
        const Vec2 p = s.a + u.dot(c - s.a) * u;
        std::vector<std::pair<double, double>> cov;
        for (int ti : seg_hash.Query(p - r, p + r)) {
          const Seg& t = segs[ti];
          const Vec2 v = (t.b - t.a).normalized();
          if (std::abs(v.dot(u)) < std::cos(Deg(o.face_angle_deg))) continue;
          if (std::abs(Perp(u).dot(0.5 * (t.a + t.b) - p)) > o.wall_thickness_m &&
              std::abs(Perp(u).dot(t.a - p)) > o.wall_thickness_m)
            continue;
          const double ta = u.dot(t.a - p), tb = u.dot(t.b - p);
          cov.push_back({std::min(ta, tb), std::max(ta, tb)});
        }
        *foot = p, *dir = u;
        return cov;
      };
      // A door is a gap in a wall: the line holding it must hold at least as
      // much wall, within reach of the exit, as the door is wide, and each
      // end of the door must meet a wall (its jambs: the faces along the line,
      // or a wall across it at a corner). Less is an object beside the
      // robot's way (one 0.5 m face of a box in cluttered_lab took two exits
      // between it and the lab's walls for doors along its own line and cut
      // the lab into three rooms), or a wall's end with open floor beyond the
      // gap; the next line out is tried, and with none the exit is in no wall.
      auto near_wall = [&](const Vec2& q) {
        const Vec2 m(o.wall_thickness_m, o.wall_thickness_m);
        for (int ti : seg_hash.Query(q - m, q + m))
          if (PointSegmentDistance(q, segs[ti].a, segs[ti].b) <= o.wall_thickness_m) return true;
        return false;
      };
      bool found = false;
      for (const auto& [dist, si] : lines) {
        Vec2 p(0, 0), u(1, 0);
        const std::vector<std::pair<double, double>> cov = faces_along(si, &p, &u);
        double walled = 0.0;
        for (const auto& [a, b] : JoinSpans(cov, 0.0)) walled += std::max(0.0, std::min(b, r.x()) - std::max(a, -r.x()));
        if (walled < w) continue;
        double lo = -std::numeric_limits<double>::infinity(), hi = -lo;
        bool covered = false;
        for (const auto& [a, b] : cov) {
          if (a <= 0 && b >= 0) covered = true;
          if (b <= 0) lo = std::max(lo, b);
          if (a >= 0) hi = std::min(hi, a);
        }
        const bool jambs = !covered && hi - lo >= o.min_door_m && hi - lo <= o.max_door_m;
        if (!jambs) lo = -0.5 * w, hi = 0.5 * w;
        const Vec2 da = p + lo * u, db = p + hi * u;
        if (!jambs && !(near_wall(da) && near_wall(db))) continue;
        d.lo = lo, d.hi = hi;
        d.jambs = jambs;
        d.in_wall = true;
        d.line_c = p, d.line_u = u;
        d.a = da, d.b = db;
        found = true;
        break;
      }
      if (!found) {
        // No wall: an opening across the robot's way (a corridor cut). The
        // door line is across the heading at the path point nearest the exit.
        Vec2 dir(1, 0);
        double nd = std::numeric_limits<double>::infinity();
        for (int id : {e.from, e.to}) {
          auto it = index_of.find(id);
          if (it == index_of.end()) continue;
          const auto& pp = path[it->second];
          for (size_t k = 1; k < pp.size(); ++k) {
            const double dd = PointSegmentDistance(c, pp[k - 1], pp[k]);
            if (dd < nd && (pp[k] - pp[k - 1]).norm() > 1e-6) nd = dd, dir = (pp[k] - pp[k - 1]).normalized();
          }
        }
        const Vec2 u = Perp(dir);
        d.in_wall = false;
        d.line_c = c, d.line_u = u;
        d.lo = -0.5 * w, d.hi = 0.5 * w;
        d.a = c + d.lo * u, d.b = c + d.hi * u;
      }
      for (int id : {e.from, e.to}) {
        auto it = index_of.find(id);
        if (it == index_of.end()) continue;
        // Every 0.1 m or so (a cell): the poses come every few centimetres.
        std::vector<Vec2> piece;
        const auto& pp = path[it->second];
        for (size_t k = 0; k < pp.size(); ++k) {
          if ((pp[k] - c).norm() > kWayReach) continue;
          const bool last = k + 1 == pp.size() || (pp[k + 1] - c).norm() > kWayReach;
          if (piece.empty() || last || (pp[k] - piece.back()).norm() >= 0.1) piece.push_back(pp[k]);
        }
        if (piece.size() >= 2) d.way.push_back(std::move(piece));
      }
      door_cands.push_back(d);
    }
  }

  // ---------------------------------------------------------------- room grid
  RoomGrid g;
  g.phi = plan.dominant_direction_rad;
  {
    Vec2 lo(1e300, 1e300), hi = -lo;
    auto grow = [&](const Vec2& p) {
      const Vec2 f = g.ToFrame(p);
      lo = lo.cwiseMin(f), hi = hi.cwiseMax(f);
    };
    for (const auto& s : segs) grow(s.a), grow(s.b);
    for (const auto& pp : path)
      for (const auto& p : pp) grow(p);
    for (const auto& ww : walls)
      for (const auto& l : ww)
        for (const auto& p : l) grow(p);
    if (lo.x() > hi.x()) return plan;
    lo -= Vec2(1, 1), hi += Vec2(1, 1);
    g.cell = o.cell_m;
    const double cells = (hi.x() - lo.x()) * (hi.y() - lo.y()) / (g.cell * g.cell);
    if (cells > o.max_cells) g.cell *= std::sqrt(cells / o.max_cells);
    g.lo = lo;
    g.w = static_cast<int>(std::ceil((hi.x() - lo.x()) / g.cell));
    g.h = static_cast<int>(std::ceil((hi.y() - lo.y()) / g.cell));
  }
  Mask wall_mask(g.w, g.h);
  for (const auto& s : segs) g.Block(s.a, s.b, &wall_mask);
  const int grow_steps = TightCells(g, &wall_mask, o.gap_closing ? o.robot_radius_m : 0.0, path);
  const int reach_steps = o.reach_m > 0.0 ? static_cast<int>(std::ceil(std::sqrt(2.0) * o.reach_m / g.cell)) : 0;
  // A door across an open space reaches from wall to wall (up to 3 m each way).
  auto door_span = [&](DoorCand* d) {
    if (d->in_wall) return;
    for (int side : {-1, 1}) {
      double t = 0.0;
      for (; t < 3.0; t += 0.5 * g.cell) {
        int cx, cy;
        if (!g.Cell(d->line_c + side * t * d->line_u, &cx, &cy) || wall_mask.Get(cx, cy) == kBlocked) break;
      }
      if (side < 0) d->lo = -t; else d->hi = t;
    }
    d->a = d->line_c + d->lo * d->line_u, d->b = d->line_c + d->hi * d->line_u;
  };
  for (auto& d : door_cands) door_span(&d);
  // An unmeasured exit parts nothing only while neither of its ASRs' paths
  // went through a doorway the walls show (a gap of min_door_m to
  // max_door_m between the ends of two wall faces on one line): a space cut
  // by distance after the robot crossed a door it did not detect (off the
  // door's middle) holds two rooms, and its exit stays a door. A doorway
  // the ASR's own measured exits lie in was detected: it is their door, and
  // says nothing of the cut (a corridor piece entered from an office and cut
  // while the robot crossed the corridor to the office opposite was drawn
  // with a 6 m door along the corridor's middle: gen-building, a 3 m
  // corridor).
  if (std::any_of(door_cands.begin(), door_cands.end(), [](const DoorCand& d) { return d.unmeasured; })) {
    std::vector<std::pair<Vec2, Vec2>> gaps;
    const double cos_face = std::cos(Deg(o.face_angle_deg));
    const Vec2 r(o.max_door_m, o.max_door_m);
    for (size_t i = 0; i < segs.size(); ++i) {
      const Vec2 u = (segs[i].b - segs[i].a).normalized();
      for (const auto& [e, d] : {std::pair{segs[i].b, u}, std::pair{segs[i].a, Vec2(-u)}})
        for (int j : seg_hash.Query(e - r, e + r)) {
          if (static_cast<size_t>(j) <= i) continue;  // each pair once
          const Vec2 v = (segs[j].b - segs[j].a).normalized();
          if (std::abs(u.dot(v)) < cos_face) continue;
          for (const Vec2& f : {segs[j].a, segs[j].b}) {
            const double along = d.dot(f - e), across = std::abs(Perp(d).dot(f - e));
            if (along >= o.min_door_m && along <= o.max_door_m && across <= o.wall_thickness_m) gaps.push_back({e, f});
          }
        }
    }
    CellHash gap_hash(2.0);
    for (size_t k = 0; k < gaps.size(); ++k)
      gap_hash.Add(gaps[k].first.cwiseMin(gaps[k].second), gaps[k].first.cwiseMax(gaps[k].second), static_cast<int>(k));
    // Each ASR's measured exits, taken before any unmeasured one below turns
    // into a door (whose centre is where the cut fell, not a doorway).
    std::map<int, std::vector<Vec2>> measured_of_asr;
    for (const DoorCand& d : door_cands)
      if (!d.unmeasured) {
        measured_of_asr[d.from_asr].push_back(d.centre);
        if (d.to_asr != d.from_asr) measured_of_asr[d.to_asr].push_back(d.centre);
      }
    const std::vector<Vec2> none;
    auto through_door = [&](int asr_id) {
      auto it = index_of.find(asr_id);
      if (it == index_of.end()) return false;
      const auto m = measured_of_asr.find(asr_id);
      const std::vector<Vec2>& detected = m == measured_of_asr.end() ? none : m->second;
      auto detected_door = [&](const std::pair<Vec2, Vec2>& gap) {
        const Vec2 mid = 0.5 * (gap.first + gap.second);
        return std::any_of(detected.begin(), detected.end(),
                           [&](const Vec2& c) { return (c - mid).norm() <= o.max_door_m; });
      };
      const auto& pp = path[it->second];
      for (size_t k = 1; k < pp.size(); ++k)
        for (int gi : gap_hash.Query(pp[k - 1].cwiseMin(pp[k]), pp[k - 1].cwiseMax(pp[k])))
          if (SegmentsCross(pp[k - 1], pp[k], gaps[gi].first, gaps[gi].second) && !detected_door(gaps[gi]))
            return true;
      return false;
    };
    for (auto& d : door_cands)
      if (d.unmeasured && (through_door(d.from_asr) || through_door(d.to_asr))) d.unmeasured = false, d.crossed_door = true;
  }

  // Graph rooms (store ids), slivers absorbed into their neighbour.
  std::map<int, std::vector<size_t>> graph_members;  // store room id -> asr indices
  std::vector<int> graph_of(asrs.size());
  for (size_t i = 0; i < asrs.size(); ++i) {
    auto it = room_of_asr.find(asrs[i].id);
    graph_of[i] = it == room_of_asr.end() ? asrs[i].id : it->second;
    graph_members[graph_of[i]].push_back(i);
  }
  // Unit (working room) per ASR: starts as the graph room.
  std::vector<int> unit_of(asrs.size());
  std::vector<int> unit_ids;  // graph room id of each unit
  std::map<int, int> unit_of_graph;
  for (const auto& [gid, members] : graph_members) {
    unit_of_graph[gid] = static_cast<int>(unit_ids.size());
    unit_ids.push_back(gid);
  }
  for (size_t i = 0; i < asrs.size(); ++i) unit_of[i] = unit_of_graph[graph_of[i]];
  int n_units = static_cast<int>(unit_ids.size());
  std::vector<double> unit_path(n_units, 0.0);
  for (size_t i = 0; i < asrs.size(); ++i) unit_path[unit_of[i]] += path_len[i];
  // Exit adjacency between units.
  std::vector<std::set<int>> unit_adj(n_units);
  std::set<std::pair<int, int>> unmeasured_adj;  // units joined by an unmeasured exit
  std::set<std::pair<int, int>> unwalled_adj;    // ... by an exit that is no door between jambs
  for (const auto& d : door_cands) {
    auto a = index_of.find(d.from_asr), b = index_of.find(d.to_asr);
    if (a == index_of.end() || b == index_of.end()) continue;
    const int ua = unit_of[a->second], ub = unit_of[b->second];
    if (ua != ub) unit_adj[ua].insert(ub), unit_adj[ub].insert(ua);
    if (ua != ub && d.unmeasured) unmeasured_adj.insert({std::min(ua, ub), std::max(ua, ub)});
    if (ua != ub && !(d.jambs && !d.unmeasured)) unwalled_adj.insert({std::min(ua, ub), std::max(ua, ub)});
  }
  UnionFind absorb(n_units);
  for (int u = 0; u < n_units; ++u) {
    if (unit_path[u] >= o.sliver_path_m) continue;
    int best = -1;
    for (int v : unit_adj[u])
      if (unit_path[v] >= o.sliver_path_m && (best < 0 || unit_path[v] > unit_path[best])) best = v;
    if (best < 0) {  // no neighbour through an exit: the nearest ASR before it in time
      int first = -1, prev_id = std::numeric_limits<int>::min();
      for (size_t i = 0; i < asrs.size(); ++i)
        if (unit_of[i] == u && (first < 0 || asrs[i].id < first)) first = asrs[i].id;
      for (size_t k = 0; k < asrs.size(); ++k)
        if (asrs[k].id < first && asrs[k].id > prev_id && unit_path[unit_of[k]] >= o.sliver_path_m)
          prev_id = asrs[k].id, best = unit_of[k];
    }
    if (best >= 0) absorb.p[u] = best;  // slivers point at a non-sliver: one step
  }
  auto unit_root = [&](int u) { return absorb.Find(u); };

  // The paths, condensed for what follows (the floods' seeds and hulls, the
  // width of two strips, the walls beside doors): each ASR's path as the
  // cells it crossed, each tagged when within seed_door_clearance_m of one
  // of its own exits (a cell repeated with the same tag next in line adds
  // nothing to a flood's seeds), and its convex hull in the room grid's
  // frame (the hulls below are hulls of walls, path and floor: the path's
  // hull stands for the path).
  // The paths themselves go before the floods: at 1000 rooms they were
  // 5 MB of the plan's peak.
  constexpr uint32_t kNearDoor = 1u << 31;  // a cell index's tag (cells: at most max_cells, 3e7)
  std::vector<std::vector<uint32_t>> path_cells(asrs.size());
  std::vector<std::vector<Vec2>> path_hull_frame(asrs.size());
  {
    std::map<int, std::vector<const DoorCand*>> doors_of_asr;
    for (const auto& d : door_cands) {
      doors_of_asr[d.from_asr].push_back(&d);
      if (d.to_asr != d.from_asr) doors_of_asr[d.to_asr].push_back(&d);
    }
    for (size_t i = 0; i < asrs.size(); ++i) {
      const auto& own_doors = doors_of_asr[asrs[i].id];
      std::vector<uint32_t>& cells = path_cells[i];
      for (const auto& p : path[i]) {
        int cx, cy;
        if (!g.Cell(p, &cx, &cy)) continue;
        bool near_door = false;
        for (const DoorCand* d : own_doors)
          if (PointSegmentDistance(p, d->a, d->b) < o.seed_door_clearance_m) near_door = true;
        const uint32_t v = static_cast<uint32_t>(g.Idx(cx, cy)) | (near_door ? kNearDoor : 0u);
        if (cells.empty() || cells.back() != v) cells.push_back(v);
      }
      cells.shrink_to_fit();
      std::vector<Vec2> frame;
      frame.reserve(path[i].size());
      for (const auto& p : path[i]) frame.push_back(g.ToFrame(p));
      path_hull_frame[i] = ConvexHull(std::move(frame));
    }
  }
  // The walls beside doors, after the rooms, ask how near the robot came to
  // a corner: of the paths of the ASRs behind a diagonal wall (not squared,
  // 15 degrees or more off the building's direction), the only ones those
  // ask about in a squared building, a point every 2 cells is kept, in
  // single precision. A diagonal whose ASRs' paths are not kept is left as
  // it is.
  std::vector<std::vector<Eigen::Vector2f>> sparse_path(tan_half > 0.0 ? path.size() : 0);
  if (!sparse_path.empty())
    for (const Seg& sg : segs) {
      const Piece& pc = pieces[sg.piece];
      const Vec2 d = sg.b - sg.a;
      if (pc.squared || pc.two_sided ||
          std::abs(QuarterOffset(std::atan2(d.y(), d.x()) - plan.dominant_direction_rad)) < Deg(15.0))
        continue;
      for (int id : pc.asrs) {
        const size_t i = index_of.at(id);
        if (!sparse_path[i].empty()) continue;
        for (const Vec2& v : path[i])
          if (sparse_path[i].empty() || (v.cast<float>() - sparse_path[i].back()).norm() >= 2.0 * o.cell_m)
            sparse_path[i].push_back(v.cast<float>());
        sparse_path[i].shrink_to_fit();
      }
    }
  std::vector<std::vector<Vec2>>().swap(path);

  // Seeds and allowed regions per working room.
  // 'free_floor' (per room; empty: none) lets a room reach the floor its
  // ASRs' grids saw, not only the hull of its walls and path.
  // 'per_asr_hulls': one hull per ASR instead of one per unit.
  auto build_regions = [&](const std::vector<int>& room_of_unit, int n_rooms, const std::vector<char>& free_floor,
                           bool per_asr_hulls, std::vector<std::vector<uint32_t>>* seeds,
                           std::vector<RoomHulls>* hulls) {
    seeds->assign(n_rooms, {});
    hulls->assign(n_rooms, {});
    std::vector<std::vector<Vec2>> hull_pts(n_units);
    std::vector<RoomHulls> asr_hulls(n_units);  // per unit, one per ASR
    std::vector<std::vector<uint32_t>> all_path(n_rooms);
    for (size_t i = 0; i < asrs.size(); ++i) {
      const int u = unit_root(unit_of[i]);
      const int r = room_of_unit[u];
      std::vector<Vec2> pts;
      for (const auto& l : walls[i])
        for (const auto& p : l) pts.push_back(g.ToFrame(p));
      if (!free_floor.empty() && free_floor[r])
        for (const auto& p : free_hull[i]) pts.push_back(g.ToFrame(p));
      pts.insert(pts.end(), path_hull_frame[i].begin(), path_hull_frame[i].end());
      if (per_asr_hulls) {
        if (!pts.empty()) asr_hulls[u].push_back(ConvexHull(std::move(pts)));
      } else {
        hull_pts[u].insert(hull_pts[u].end(), pts.begin(), pts.end());
      }
      for (const uint32_t v : path_cells[i]) {
        // A cell repeated next in one room's list would flood nothing more: once.
        const uint32_t idx = v & ~kNearDoor;
        if (all_path[r].empty() || all_path[r].back() != idx) all_path[r].push_back(idx);
        if (!(v & kNearDoor) && ((*seeds)[r].empty() || (*seeds)[r].back() != idx)) (*seeds)[r].push_back(idx);
      }
    }
    for (int u = 0; u < n_units; ++u) {
      for (auto& h : asr_hulls[u]) (*hulls)[room_of_unit[u]].push_back(std::move(h));
      if (!hull_pts[u].empty()) (*hulls)[room_of_unit[u]].push_back(ConvexHull(hull_pts[u]));
    }
    for (int r = 0; r < n_rooms; ++r)
      if ((*seeds)[r].empty()) (*seeds)[r] = all_path[r];
  };
  // 'first': pass 1, where unmeasured exits and exits in no wall do not
  // block: either may lie inside one space (the rules after pass 1 decide).
  auto door_mask = [&](const std::vector<int>& room_of_unit, bool first = false) {
    DoorMask m(wall_mask, g.w, g.h);
    for (const auto& d : door_cands) {
      if (first && (d.unmeasured || (!d.in_wall && !d.crossed_door))) continue;
      auto a = index_of.find(d.from_asr), b = index_of.find(d.to_asr);
      if (a != index_of.end() && b != index_of.end() &&
          room_of_unit[unit_root(unit_of[a->second])] == room_of_unit[unit_root(unit_of[b->second])])
        continue;  // inside one room: no door
      g.Block(d.a, d.b, m.doors());
    }
    return m;
  };

  // Pass 1: the units (graph rooms with slivers absorbed) split the free space.
  std::vector<int> unit_room(n_units, -1);
  int n1 = 0;
  for (int u = 0; u < n_units; ++u)
    if (unit_root(u) == u) unit_room[u] = n1++;
  // The pass-1 rooms an exit joins ({-1, -1} when either ASR is not in the plan).
  auto rooms_of_exit = [&](const DoorCand& d) {
    auto a = index_of.find(d.from_asr), b = index_of.find(d.to_asr);
    if (a == index_of.end() || b == index_of.end()) return std::pair{-1, -1};
    return std::pair{unit_room[unit_root(unit_of[a->second])], unit_room[unit_root(unit_of[b->second])]};
  };
  std::vector<std::vector<uint32_t>> seeds;
  std::vector<RoomHulls> hulls;
  // Pass 1 bounds every unit by its walls and path: a corridor's grid sees
  // through doors and wall gaps into the rooms beside it, and the shapes
  // below tell corridors from rooms.
  build_regions(unit_room, n1, {}, false, &seeds, &hulls);
  std::vector<Shape> shapes;
  std::vector<Outline> outlines;  // pass 1's regions' outlines
  std::map<std::pair<int, int>, int> touching;  // pairs of units -> cell edges their regions share
  // The same contacts split by the direction of the step (x, y): a straight
  // border of slope dy/dx crosses about |dy| / cell x-steps and |dx| / cell
  // y-steps, so its length is about cell * hypot(x-steps, y-steps).
  std::map<std::pair<int, int>, std::pair<int, int>> touching_xy;
  {  // pass 1's labels go before pass 2 floods
    const DoorMask blocked1 = door_mask(unit_room, true);
    const Labels label1 = Flood(g, blocked1, seeds, hulls, grow_steps, reach_steps);
    shapes = RegionShapes(g, label1, n1, &outlines);
    // Two regions meet where a row or column of cells goes from one to the
    // other, directly or across unclaimed floor no wider than
    // corridor_touch_m (the hulls of two corridor pieces leave a wedge
    // between them where the robot turned into a room), never across a wall
    // or a door line.
    const int reach = std::max(1, static_cast<int>(std::lround(o.corridor_touch_m / g.cell)));
    label1.ForEachStored([&](int x, int y, int r) {
      if (r < 0) return;
      for (const auto& [dx, dy] : {std::pair{1, 0}, std::pair{0, 1}})
        for (int k = 1; k <= reach; ++k) {
          const int nx = x + k * dx, ny = y + k * dy;
          if (nx >= g.w || ny >= g.h || blocked1.Get(nx, ny) == kBlocked) break;
          const int q = label1.Get(nx, ny);
          if (q < 0) continue;
          if (q != r) {
            ++touching[{std::min(r, q), std::max(r, q)}];
            auto& xy = touching_xy[{std::min(r, q), std::max(r, q)}];
            ++(dx ? xy.first : xy.second);
          }
          break;
        }
    });
  }

  // Corridor pieces joined through exits are one corridor (a loop stays cut at one door).
  // A piece is narrow when at most corridor_max_width_m wide, elongated when
  // also corridor_min_aspect times longer; two narrow pieces joined through an
  // exit or meeting along corridor_touch_m of border, one of them elongated,
  // are one corridor.
  // A narrow piece that is not elongated and whose grids saw a floor wider
  // than a corridor is a room the robot only looked into (its walls and path
  // are a thin fan from the door), not a piece of the corridor it came from.
  std::vector<std::vector<Vec2>> floor_pts(n1);
  for (size_t i = 0; i < asrs.size(); ++i) {
    const int r = unit_room[unit_root(unit_of[i])];
    floor_pts[r].insert(floor_pts[r].end(), free_hull[i].begin(), free_hull[i].end());
  }
  // A piece the robot entered through a door and left through the same door
  // (every exit between its ASRs and the others' is a door between jambs the
  // robot went through, all in one doorway) is a room, whatever its shape: a
  // room the robot stepped into and backed out of is a strip of path and the
  // few walls near it, as narrow and elongated as a piece of corridor, and
  // across a corridor's line as a corridor's corner is (gen-building, a 1.4 m
  // corridor, a laser: three offices of 6 x 6 m entered 2.8 m deep went to the
  // corridor, by its corners and its pieces of one). A corridor is left at
  // its ends; a dead-end stub behind a door is a room of the room graph too.
  std::vector<char> behind_door(n1, 0);
  {
    std::vector<std::vector<const DoorCand*>> doors_of(n1);
    std::vector<char> other_exit(n1, 0), entered(n1, 0), left(n1, 0);
    for (const DoorCand& d : door_cands) {
      const auto [ra, rb] = rooms_of_exit(d);
      if (ra == rb) continue;
      const bool through = d.jambs && PointSegmentDistance(d.centre, d.a, d.b) <= o.robot_radius_m;
      for (const int r : {ra, rb}) {
        if (through) doors_of[r].push_back(&d);
        else other_exit[r] = 1;
      }
      left[ra] = entered[rb] = 1;
    }
    for (int r = 0; r < n1; ++r) {
      if (other_exit[r] || doors_of[r].empty() || !entered[r] || !left[r]) continue;
      const DoorCand& first = *doors_of[r].front();
      bool one = true;
      for (const DoorCand* d : doors_of[r])
        one = one && PointSegmentDistance(0.5 * (d->a + d->b), first.a, first.b) <= o.robot_radius_m &&
              PointSegmentDistance(0.5 * (first.a + first.b), d->a, d->b) <= o.robot_radius_m;
      behind_door[r] = one;
    }
  }
  std::vector<char> narrow(n1, 0), elongated(n1, 0);
  for (int r = 0; r < n1; ++r) {
    if (behind_door[r]) continue;
    narrow[r] = shapes[r].area_m2 > 0 && shapes[r].width_m <= o.corridor_max_width_m;
    elongated[r] = narrow[r] && shapes[r].length_m >= o.corridor_min_aspect * shapes[r].width_m;
    if (narrow[r] && !elongated[r] && PolygonWidth(ConvexHull(floor_pts[r])) > o.corridor_max_width_m)
      narrow[r] = 0;
  }
  UnionFind corr(n1);
  std::vector<char> in_corridor(n1, 0);
  // Two narrow pieces, both elongated (a corridor cut along its length or
  // at a corner), or one elongated and the two along one line (their hull
  // as narrow as a corridor): a room entered straight from a short piece of
  // corridor is a strip too, across the corridor's line.
  auto pieces_of_one = [&](int ru, int rv) {
    if (!narrow[ru] || !narrow[rv] || !(elongated[ru] || elongated[rv])) return false;
    if (elongated[ru] && elongated[rv]) return true;
    Outline both = outlines[ru];
    both.Add(outlines[rv]);
    return both.WidthAndLength().first <= o.corridor_max_width_m;
  };
  for (int u = 0; u < n_units; ++u) {
    if (unit_room[u] < 0) continue;
    for (int v : unit_adj[u]) {
      const int ru = unit_room[unit_root(u)], rv = unit_room[unit_root(v)];
      if (ru == rv || !pieces_of_one(ru, rv)) continue;
      if (corr.Unite(ru, rv)) in_corridor[ru] = in_corridor[rv] = 1;
    }
  }
  for (const auto& [pair, edges] : touching) {
    const auto [ru, rv] = pair;
    if (edges * g.cell < o.corridor_touch_m || !pieces_of_one(ru, rv)) continue;
    if (corr.Unite(ru, rv)) in_corridor[ru] = in_corridor[rv] = 1;
  }
  // Corners. A corridor turning a corner is an L, whose principal moments
  // read as wide, so the piece at the bend is neither narrow nor elongated
  // and would cut the corridor. Its floor per metre of the robot's path
  // through it is still about the corridor's (the robot drove along the L),
  // while a room the robot crossed has far more floor per metre of path. A
  // piece not in a corridor that meets two or more corridor pieces (narrow
  // and elongated, or already in a corridor; through an exit or along
  // corridor_touch_m of border) with at most corner_floor_ratio times their
  // mean floor per metre of path is a corner of the corridor and joins
  // them, also the one that closes a ring corridor (the polygon step cuts
  // a ring across rather than fill the block it runs round).
  {
    std::vector<double> piece_path(n1, 0.0);
    for (int u = 0; u < n_units; ++u)
      if (unit_room[unit_root(u)] >= 0) piece_path[unit_room[unit_root(u)]] += unit_path[u];
    auto floor_per_m = [&](int r) { return piece_path[r] > 0 ? shapes[r].area_m2 / piece_path[r] : 0.0; };
    // The band of the corridor pieces (their axes about parallel): across
    // their mean axis, from the lowest to the highest of their extents. Is
    // piece r's floor inside it, give or take corridor_touch_m / 2, and no
    // wider than a corridor?
    auto in_corridor_band = [&](int r, const std::vector<int>& pieces) {
      Vec2 u(0, 0);
      for (int q : pieces) u += shapes[q].axis.dot(shapes[pieces[0]].axis) < 0 ? Vec2(-shapes[q].axis) : shapes[q].axis;
      if (u.norm() < 1e-9) return false;
      u.normalize();
      const Vec2 n(-u.y(), u.x());
      double lo = std::numeric_limits<double>::infinity(), hi = -lo;
      for (int q : pieces) {
        const double c = n.dot(shapes[q].centre), half = 0.5 * shapes[q].ExtentAlong(n);
        lo = std::min(lo, c - half), hi = std::max(hi, c + half);
      }
      const double across = shapes[r].ExtentAlong(n), c = n.dot(shapes[r].centre);
      const double slack = 0.5 * o.corridor_touch_m;
      return across <= o.corridor_max_width_m && c - 0.5 * across >= lo - slack && c + 0.5 * across <= hi + slack;
    };
    std::vector<std::set<int>> nb(n1);
    for (int u = 0; u < n_units; ++u)
      if (unit_room[u] >= 0)
        for (int v : unit_adj[u]) {
          const int a = unit_room[unit_root(u)], b = unit_room[unit_root(v)];
          if (a != b) nb[a].insert(b), nb[b].insert(a);
        }
    for (const auto& [pair, edges] : touching)
      if (edges * g.cell >= o.corridor_touch_m) nb[pair.first].insert(pair.second), nb[pair.second].insert(pair.first);
    auto corridors_of = [&](const std::vector<int>& pieces) {
      std::set<int> groups;
      for (int q : pieces) groups.insert(corr.Find(q));
      return groups;
    };
    // First the corners.
    for (int r = 0; r < n1; ++r) {
      if (in_corridor[r] || (narrow[r] && elongated[r]) || piece_path[r] <= 0 || behind_door[r]) continue;
      std::vector<int> pieces;
      double sum = 0.0;
      for (int q : nb[r])
        if (in_corridor[q] || (narrow[q] && elongated[q])) pieces.push_back(q), sum += floor_per_m(q);
      if (pieces.size() < 2 || floor_per_m(r) > o.corner_floor_ratio * sum / pieces.size()) continue;
      // A corner turns: two of the pieces it joins run across each other
      // (axes more than 45 degrees apart). A room the robot crossed between
      // two pieces of one straight corridor joins nothing (a generated
      // building's rooms off a straight corridor read as corners otherwise).
      bool turns = false;
      for (size_t a = 0; a < pieces.size() && !turns; ++a)
        for (size_t b = a + 1; b < pieces.size() && !turns; ++b)
          turns = std::abs(shapes[pieces[a]].axis.dot(shapes[pieces[b]].axis)) < std::cos(Deg(45.0));
      if (!turns) continue;
      for (int q : pieces) corr.Unite(r, q), in_corridor[q] = 1;
      in_corridor[r] = 1;
    }
    // Then the pieces in a straight corridor's band: short pieces the boundary
    // detector cut out of the corridor itself (the robot stopped at a door
    // and looked in, every few metres along a corridor of offices), whose
    // floor spans the corridor's width and no more, centred on it. A room
    // off the corridor lies beside the band and reaches across it by its
    // depth. One corridor neighbour is enough, and the sweep is repeated
    // until nothing joins: a run of short pieces joins piece by piece from
    // the elongated one it starts at. Their floor per metre of path is
    // compared with the band's pieces' below, not with every neighbour's (a
    // sliver beside one, a few tenths of a square metre, made that mean
    // meaningless).
    for (bool joined = true; joined;) {
      joined = false;
      for (int r = 0; r < n1; ++r) {
        if (in_corridor[r] || (narrow[r] && elongated[r]) || piece_path[r] <= 0 || behind_door[r]) continue;
        std::vector<int> pieces;
        for (int q : nb[r])
          if (in_corridor[q] || (narrow[q] && elongated[q])) pieces.push_back(q);
        if (pieces.empty()) continue;
        const std::set<int> groups = corridors_of(pieces);
        // The band is drawn by the elongated pieces of the neighbours'
        // corridors (a short piece's axis says little: one 1.5 x 1.9 m piece
        // read across the corridor) at least as wide as the robot (a sliver
        // is no piece of a corridor it drove): the one nearest r and r's
        // neighbours among them that run along it; r joins nothing where its
        // neighbours run across each other (a corner or a junction: the
        // corners' rule above).
        std::vector<int> ref;
        for (int q = 0; q < n1; ++q)
          if (narrow[q] && elongated[q] && shapes[q].width_m >= 2.0 * o.robot_radius_m && groups.count(corr.Find(q)))
            ref.push_back(q);
        bool turns = false;
        for (int a : pieces)
          for (int b : pieces)
            turns |= a < b && elongated[a] && elongated[b] &&
                     std::abs(shapes[a].axis.dot(shapes[b].axis)) < std::cos(Deg(45.0));
        if (ref.empty() || turns) continue;
        const int nearest = *std::min_element(ref.begin(), ref.end(), [&](int a, int b) {
          return (shapes[a].centre - shapes[r].centre).squaredNorm() < (shapes[b].centre - shapes[r].centre).squaredNorm();
        });
        // Near r only: over tens of metres the pieces' centre lines part by
        // the map's small heading errors (2 degrees over 20 m is 0.7 m).
        std::vector<int> arm = {nearest};
        for (int q : pieces)
          if (q != nearest && std::find(ref.begin(), ref.end(), q) != ref.end() &&
              std::abs(shapes[q].axis.dot(shapes[nearest].axis)) >= std::cos(Deg(20.0)))
            arm.push_back(q);
        // And its floor per metre of the robot's path about a corridor's
        // (the corners' rule, against the pieces of the band): a room the
        // robot turned about in has more.
        double sum = 0.0;
        for (int q : arm) sum += floor_per_m(q);
        if (floor_per_m(r) > o.corner_floor_ratio * sum / arm.size() || !in_corridor_band(r, arm)) continue;
        for (int q : pieces) corr.Unite(r, q), in_corridor[q] = 1;
        in_corridor[r] = 1;
        joined = true;
      }
    }
  }
  // Chains. A corridor the robot left into a room every few metres is cut into
  // pieces no longer than a room is wide (2 x 2-3 m, and slivers between
  // them: none elongated), whose grids saw through the doors into the rooms
  // (floor wider than a corridor). They meet end to end without a wall or a
  // door line between them, and a chain of them stays as narrow as each
  // while it grows long: grown piece by piece along the borders they share
  // (as long as the chain stays at most corridor_max_width_m wide, or up to
  // corridor_chain_max_width_m while it grows no wider than its pieces), a
  // chain corridor_min_aspect times longer than wide is one corridor. Rooms
  // side by side meet across walls and door lines; a room beside a chain
  // widens it.
  {
    // Two rounds: the chains of corridors up to corridor_max_width_m, then,
    // among the regions no corridor holds yet, those of wider corridors.
    const std::vector<Outline> region_outline = std::move(outlines);
    for (const bool wide : {false, true}) {
      if (wide && o.corridor_chain_max_width_m <= o.corridor_max_width_m) break;
      UnionFind chain(n1);
      std::vector<Outline> chain_outline = region_outline;  // each chain's, at its root
      std::vector<int> members(n1, 1);
      std::vector<char> out(n1, 0);  // in no chain this round
      for (int r = 0; r < n1; ++r) out[r] = behind_door[r] || (wide && in_corridor[r]);
      // The joins that keep a chain narrowest first (a corridor's pieces end
      // to end before a room's strip across one): each candidate keyed by the
      // width of the two chains together, weighed again when either chain has
      // grown since.
      auto joined = [&](int a, int b) {
        Outline u = chain_outline[a];
        u.Add(chain_outline[b]);
        return u;
      };
      struct Join {
        double width;
        int a, b, size_a, size_b;
        bool operator>(const Join& o) const { return width > o.width; }
      };
      // A join keeps the chain a corridor's width: at most
      // corridor_max_width_m; in the second round, when the wider of the two
      // chains is already wider than that across the two together (a wide
      // corridor's piece, which may be shorter than the corridor is wide),
      // up to corridor_chain_max_width_m while the two together are no wider
      // than it by more than corridor_chain_slack (its pieces end to end are
      // as wide as each; a room beside it widens it). The width of the two
      // together, or -1 when they may not join.
      auto join_width = [&](const Outline& u, int a, int b) {
        const Outline::Calipers c = u.Measure();
        if (c.width <= o.corridor_max_width_m) return c.width;
        if (!wide || c.width > o.corridor_chain_max_width_m) return -1.0;
        const double wider = std::max(chain_outline[a].ExtentAlong(c.across), chain_outline[b].ExtentAlong(c.across));
        return wider > o.corridor_max_width_m && c.width <= (1.0 + o.corridor_chain_slack) * wider ? c.width : -1.0;
      };
      std::priority_queue<Join, std::vector<Join>, std::greater<Join>> joins;
      for (const auto& [pair, edges] : touching) {
        const auto [ru, rv] = pair;
        if (edges * g.cell < o.corridor_touch_m || chain_outline[ru].empty() || chain_outline[rv].empty() ||
            out[ru] || out[rv])
          continue;
        const double w = join_width(joined(ru, rv), ru, rv);
        if (w >= 0.0) joins.push({w, ru, rv, 1, 1});
      }
      while (!joins.empty()) {
        const Join j = joins.top();
        joins.pop();
        const int a = chain.Find(j.a), b = chain.Find(j.b);
        if (a == b) continue;
        const Outline u = joined(a, b);
        if (members[a] != j.size_a || members[b] != j.size_b) {  // grown since: weighed again
          const double w = join_width(u, a, b);
          if (w >= 0.0) joins.push({w, a, b, members[a], members[b]});
          continue;
        }
        chain.Unite(a, b);
        const int root = chain.Find(a);
        chain_outline[root] = u;
        members[root] = members[a] + members[b];
      }
      for (int r = 0; r < n1; ++r) {
        const int root = chain.Find(r);
        if (members[root] < 2) continue;
        const auto [width, length] = chain_outline[root].WidthAndLength();
        // Wider than corridor_max_width_m, twice as long again: two rooms
        // side by side whose wall the sensor missed are a short wide chain
        // (two 4 x 4 m offices: 8 x 4 m), a wide corridor is long.
        const double aspect = o.corridor_min_aspect * (width > o.corridor_max_width_m ? 2.0 : 1.0);
        if (length < aspect * width) continue;
        corr.Unite(r, root);
        in_corridor[r] = in_corridor[root] = 1;
      }
    }
  }
  // Open plan. Two rooms the robot drove between (an exit joins them),
  // neither a corridor (nor a lone corridor piece), whose pass-1 regions
  // meet across open floor (never across a wall or a door line) along more
  // than open_border_m are one space: a room's border is walls and doors,
  // and no doorway is that wide, so the exit was a narrowing, not a door.
  // Unless every exit between them is a door between jambs (measured, the
  // faces of its wall on both sides of it along one line: walls step 10):
  // then the two are on either side of that wall, and the open border is
  // the rest of it, which the sensor missed (16 sonars in a generated
  // corridor building, gen20wide: an office and the corridor piece it was
  // entered from were one room, and with the office across, 78 m2). A desk
  // or a box beside the robot's way holds a door on one side only.
  // The robot cut one room where clutter narrowed its way (cluttered_lab:
  // one 12 x 6 m lab, two ASRs meeting along 7 m of open floor); the room
  // graph keeps both. Rooms the robot entered each from elsewhere (offices
  // off a corridor) are not joined: between them an open border is more
  // likely a wall the sensor missed. Two pieces either side of an
  // unmeasured exit (a space cut by distance: DoorCand::unmeasured) are
  // joined so even when one looks like a corridor piece: cut from a hall,
  // its first region (the hull of its own walls and path) is a strip; a
  // piece that is a corridor's meets a room's piece only through the
  // room's door, far shorter than open_border_m.
  // The rooms' pairs of the units' pairs.
  auto room_pairs = [&](const std::set<std::pair<int, int>>& unit_pairs) {
    std::set<std::pair<int, int>> out;
    for (const auto& [u, v] : unit_pairs) {
      const int a = unit_room[unit_root(u)], b = unit_room[unit_root(v)];
      if (a >= 0 && b >= 0 && a != b) out.insert({std::min(a, b), std::max(a, b)});
    }
    return out;
  };
  // Driven between through an exit that is no door between jambs (those
  // driven between only through such doors stay apart).
  const std::set<std::pair<int, int>> driven = room_pairs(unwalled_adj);
  const std::set<std::pair<int, int>> driven_unmeasured = room_pairs(unmeasured_adj);
  for (const auto& [pair, xy] : touching_xy) {
    const auto [ru, rv] = pair;
    auto corridor_like = [&](int r) { return in_corridor[r] || (narrow[r] && elongated[r]); };
    if (!driven.count(pair)) continue;
    const bool unmeasured = driven_unmeasured.count(pair) > 0;
    if (!unmeasured && (corridor_like(ru) || corridor_like(rv))) continue;
    if (g.cell * std::hypot(xy.first, xy.second) <= o.open_border_m) continue;
    corr.Unite(ru, rv);
    if (!unmeasured || !(in_corridor[ru] || in_corridor[rv])) continue;
    // Two strips of a hall, taken for corridor pieces: together wider than a corridor.
    std::vector<Vec2> pts;
    for (size_t i = 0; i < asrs.size(); ++i) {
      const int r = unit_room[unit_root(unit_of[i])];
      if (r != ru && r != rv) continue;
      for (const Vec2& q : path_hull_frame[i]) pts.push_back(g.FromFrame(q));
      for (const auto& l : walls[i]) pts.insert(pts.end(), l.begin(), l.end());
    }
    if (PolygonWidth(ConvexHull(std::move(pts))) > o.corridor_max_width_m) in_corridor[ru] = in_corridor[rv] = 0;
  }
  // An exit in no wall, between two rooms (neither in a corridor nor a lone
  // corridor piece): a room's border is walls and doors, and a door is a gap
  // in a wall, so the robot was cut where its way narrowed inside one space
  // (between clutter and a wall, or two pieces of furniture). The two are one
  // room of the plan; the room graph keeps both. So is a cut by distance
  // (an unmeasured exit) through which no path went through a doorway the
  // walls show (DoorCand::crossed_door, above): it parts nothing, wherever
  // it fell and however short the border of open floor between the two
  // pieces (a real Pioneer's corridor cut at its corner, the two arms
  // meeting along 1.4 m of floor, was two rooms and a 6 m door). A
  // corridor cut into pieces is the corridors' rules', above. A lone piece
  // counts as a corridor's only if the robot fitted in it (at least its
  // diameter wide) and its grids saw no floor wider than a corridor: the
  // short way between two pieces of clutter is narrow and elongated too,
  // but its grids saw the room around it (cluttered_lab: 0.5-0.8 m wide
  // pieces between the lab's two halves).
  {
    auto corridor_piece = [&](int r) {
      return narrow[r] && elongated[r] && shapes[r].width_m >= 2.0 * o.robot_radius_m &&
             PolygonWidth(ConvexHull(floor_pts[r])) <= o.corridor_max_width_m;
    };
    // A group is a corridor's when the corridors' rules made it, or when it
    // is one lone corridor piece; a piece the open-plan rule joined to a room
    // is part of that room.
    std::vector<int> group_size(n1, 0);
    for (int r = 0; r < n1; ++r) ++group_size[corr.Find(r)];
    std::vector<char> corridor_group(n1, 0);
    for (int r = 0; r < n1; ++r)
      if (in_corridor[r] || (group_size[corr.Find(r)] == 1 && corridor_piece(r))) corridor_group[corr.Find(r)] = 1;
    for (const DoorCand& d : door_cands) {
      if (d.crossed_door || (d.in_wall && !d.unmeasured)) continue;
      const auto [ru, rv] = rooms_of_exit(d);
      if (ru < 0 || rv < 0 || corr.Find(ru) == corr.Find(rv)) continue;
      if (corridor_group[corr.Find(ru)] || corridor_group[corr.Find(rv)]) continue;
      corr.Unite(ru, rv);
    }
    // A lone corridor piece bypassed: the robot went through it from one
    // room to another on its other side (two exits whose lines run within
    // 45 degrees of each other, the two rooms on opposite sides of them),
    // neither a corridor's, and those two rooms meet each other along more
    // open floor than a door is wide (open_border_m). The floor goes round
    // the piece: the way through it was one way round an obstacle inside one
    // space, not a corridor between two, and the three are one room
    // (cluttered_lab: a sliver of an ASR in the gap between two boxes whose
    // sides line up like a doorway's jambs; the lab either side of it meets
    // below the lower box along 3.4 m of floor). Rooms entered from a
    // corridor through one side (offices) lie on the same side of their
    // doors: where two of those meet, a wall between them was missed
    // (RoomsEnteredEachFromTheCorridorStayTwoAcrossAMissedWall).
    struct End {
      int room;
      Vec2 at, u;  // the exit's centre and line
    };
    std::vector<std::vector<End>> ends(n1);  // a piece's exits to other rooms
    for (const DoorCand& d : door_cands) {
      if (d.unmeasured) continue;
      const auto [ru, rv] = rooms_of_exit(d);
      if (ru < 0 || rv < 0 || ru == rv) continue;
      ends[ru].push_back({rv, d.centre, d.line_u});
      ends[rv].push_back({ru, d.centre, d.line_u});
    }
    // The open border between two groups, as touching_xy.
    auto group_touch = [&](int a, int b) {
      std::pair<int, int> t{0, 0};
      for (const auto& [pair, xy] : touching_xy) {
        const int p = corr.Find(pair.first), q = corr.Find(pair.second);
        if ((p == a && q == b) || (p == b && q == a)) t.first += xy.first, t.second += xy.second;
      }
      return t;
    };
    for (int r = 0; r < n1; ++r) {
      const int root = corr.Find(r);
      if (in_corridor[r] || !corridor_group[root] || group_size[root] != 1) continue;
      std::set<int> sides;
      for (const End& ea : ends[r])
        for (const End& eb : ends[r]) {
          const int a = corr.Find(ea.room), b = corr.Find(eb.room);
          if (a >= b || corridor_group[a] || corridor_group[b]) continue;
          if (std::abs(ea.u.dot(eb.u)) < std::sqrt(0.5)) continue;
          const Vec2 n = Perp(ea.u);
          if (n.dot(shapes[ea.room].centre - ea.at) * n.dot(shapes[eb.room].centre - eb.at) >= 0.0) continue;
          const auto [nx, ny] = group_touch(a, b);
          if (g.cell * std::hypot(nx, ny) > o.open_border_m) sides.insert({a, b});
        }
      for (int a : sides) corr.Unite(r, a);
      if (!sides.empty()) corridor_group[corr.Find(r)] = 0;  // a room now, whichever root it kept
    }
  }
  // Plan rooms: one per corridor group or remaining unit, ordered by first ASR.
  std::vector<int> plan_of_r1(n1, -1);
  std::vector<int> order;
  for (size_t i = 0; i < asrs.size(); ++i) order.push_back(static_cast<int>(i));
  std::sort(order.begin(), order.end(), [&](int a, int b) { return asrs[a].id < asrs[b].id; });
  int n_plan = 0;
  std::vector<int> plan_of_unit(n_units, -1);
  std::vector<char> is_corridor, free_floor;
  auto number_plan_rooms = [&] {
    n_plan = 0;
    std::vector<int> root_plan(n1, -1);
    for (int i : order) {
      const int root = corr.Find(unit_room[unit_root(unit_of[i])]);
      if (root_plan[root] < 0) root_plan[root] = n_plan++;
    }
    for (int r = 0; r < n1; ++r) plan_of_r1[r] = root_plan[corr.Find(r)];
    for (int u = 0; u < n_units; ++u) plan_of_unit[u] = plan_of_r1[unit_room[unit_root(u)]];
    // Pass 2: the plan rooms; the rooms (not the corridors) reach the floor
    // their grids saw. A room the robot only looked into has few walls: the
    // hull of walls and path is a thin fan from the door, the floor seen is
    // most of the room (docs/floor-plan.md, "Rooms").
    is_corridor.assign(n_plan, 0);
    for (int r = 0; r < n1; ++r)
      if (in_corridor[r]) is_corridor[plan_of_r1[r]] = 1;
    free_floor.assign(n_plan, 0);
    for (int r = 0; r < n_plan; ++r) free_floor[r] = !is_corridor[r];
  };
  number_plan_rooms();
  build_regions(plan_of_unit, n_plan, free_floor, true, &seeds, &hulls);
  std::optional<Labels> label2 = Flood(g, door_mask(plan_of_unit), seeds, hulls, grow_steps, reach_steps);

  // Small rooms (small_room_radii) join the neighbour they meet along the
  // most border; then the plan rooms flood again. A merge can leave another
  // room small only by taking floor from it, so a few rounds settle it.
  const double small_m2 = std::pow(o.small_room_radii * o.robot_radius_m, 2);
  for (int round = 0; round < 3 && small_m2 > 0.0; ++round) {
    std::vector<long> cells(n_plan, 0);
    label2->ForEachStored([&](int, int, int r) {
      if (r >= 0) ++cells[r];
    });
    std::vector<char> small(n_plan, 0);
    bool any = false;
    for (int r = 0; r < n_plan; ++r)
      any |= (small[r] = cells[r] > 0 && cells[r] * g.cell * g.cell < small_m2) != 0;
    if (!any) break;
    // Contacts of each small room: cell pairs along a row or a column, next
    // to each other or across door-line cells (not wall cells) and unclaimed
    // floor, up to corridor_touch_m apart.
    const DoorMask doors = door_mask(plan_of_unit);
    const int reach = std::max(1, static_cast<int>(std::lround(o.corridor_touch_m / g.cell)));
    std::map<std::pair<int, int>, long> contact;  // (small room, neighbour) -> cell pairs
    label2->ForEachStored([&](int x, int y, int r) {
      if (r < 0) return;
      for (const auto& [dx, dy] : {std::pair{1, 0}, std::pair{0, 1}, std::pair{-1, 0}, std::pair{0, -1}})
        for (int k = 1; k <= reach; ++k) {
          const int nx = x + k * dx, ny = y + k * dy;
          if (nx < 0 || ny < 0 || nx >= g.w || ny >= g.h || wall_mask.Get(nx, ny) == kBlocked) break;
          if (doors.Get(nx, ny) == kBlocked) continue;
          const int q = label2->Get(nx, ny);
          if (q < 0) continue;
          if (q != r && small[r]) ++contact[{r, q}];
          break;
        }
    });
    std::vector<int> into(n_plan, -1);
    std::vector<long> best(n_plan, 0);
    for (const auto& [pair, n] : contact)
      if (n > best[pair.first]) best[pair.first] = n, into[pair.first] = pair.second;
    std::vector<int> r1_of_plan(n_plan, -1);
    for (int r = 0; r < n1; ++r) r1_of_plan[plan_of_r1[r]] = r;
    bool merged = false;
    for (int r = 0; r < n_plan; ++r)
      if (into[r] >= 0) {
        const int a = r1_of_plan[r], b = r1_of_plan[into[r]];
        // A small corridor piece joining a room stays a corridor only where
        // the room it joins is one.
        if (!is_corridor[into[r]])
          for (int q = 0; q < n1; ++q)
            if (corr.Find(q) == corr.Find(a)) in_corridor[q] = 0;
        merged |= corr.Unite(a, b);
      }
    if (!merged) break;
    number_plan_rooms();
    build_regions(plan_of_unit, n_plan, free_floor, true, &seeds, &hulls);
    label2.reset();
    label2 = Flood(g, door_mask(plan_of_unit), seeds, hulls, grow_steps, reach_steps);
  }
  // The walls, floor and condensed paths have served (the seeds and hulls
  // carry what the flood needs), then the seeds and hulls: freed before the
  // polygons are traced.
  std::vector<std::vector<Polyline>>().swap(walls);
  std::vector<std::vector<Vec2>>().swap(free_hull);
  std::vector<std::vector<uint32_t>>().swap(path_cells);
  std::vector<std::vector<Vec2>>().swap(path_hull_frame);

  // ---------------------------------------------------------------- room polygons
  std::vector<Room> rooms(n_plan);
  for (size_t i = 0; i < asrs.size(); ++i) {
    Room& room = rooms[plan_of_unit[unit_of[i]]];
    room.asr_ids.push_back(asrs[i].id);
    room.graph_rooms.push_back(graph_of[i]);
  }
  // The outlines, traced on the labels; the labels go once they are traced.
  std::vector<BPoly> polys(n_plan);
  std::vector<std::vector<Vec2>> rings(n_plan);  // traced outlines, world frame
  std::vector<std::vector<char>> anchors(n_plan);
  std::vector<Vec2> inner(n_plan, Vec2(0, 0));
  {
    Labels label = std::move(*label2);
    label2.reset();
    std::vector<std::vector<uint32_t>>().swap(seeds);
    std::vector<RoomHulls>().swap(hulls);
    // Each room is a set of sites of the half-cell lattice (HalfCells: disjoint
    // by construction). First every room, in order, becomes one piece without
    // holes: its largest 4-connected piece is kept (its other pieces are left
    // to no room) and whatever it encloses becomes its own (walls inside it,
    // and a room wholly inside it, which then disappears). A room is never
    // partly enclosed: it is one connected piece, so all of it lies in one
    // hole or none. Rooms smaller than min_room_area_m2 are left out. Then each
    // room's outline is traced along the lattice: the outlines of disjoint
    // sets, so no two rooms overlap, exactly (they share edges where they
    // meet). docs/floor-plan.md, "Polygons".
    std::vector<CellBox> boxes = LabelBoxes(label, n_plan);
    const int n_first = n_plan;
    for (int r = 0; r < n_first; ++r) {  // one piece of cells per room, before it grows onto the walls
      const CellBox b = boxes[r];
      if (b.x1 < 0) continue;
      const Region reg = FillRegion(b.x0, b.y0, b.x1, b.y1, [&](int x, int y) { return label.Get(x, y) == r; }, false);
      // Its other pieces are floor too, not to be lost (aria/office: up to
      // 55 m2 of a corridor the flood reached only round a door line, and
      // the start of a run, went to no room): each piece no smaller than a
      // small room (small_room_radii, as below) is a room of its own, with
      // the room's kind and no ASRs or doors of its own; a smaller one joins
      // the room it meets along the most border, or no room.
      for (int y = b.y0; y <= b.y1; ++y)
        for (int x = b.x0; x <= b.x1; ++x) {
          if (label.Get(x, y) != r || reg.at(x - b.x0 + 1, y - b.y0 + 1)) continue;
          // A new piece: flood it under a provisional label.
          const bool room_left = n_plan + 1 < std::numeric_limits<int16_t>::max();
          const int id = room_left ? n_plan : -1;
          std::vector<std::pair<int, int>> cells{{x, y}};
          label.Set(x, y, -2);
          for (size_t i = 0; i < cells.size(); ++i) {
            const auto [cx, cy] = cells[i];
            const int nx[4] = {cx + 1, cx - 1, cx, cx}, ny[4] = {cy, cy, cy + 1, cy - 1};
            for (int k = 0; k < 4; ++k) {
              if (nx[k] < b.x0 || ny[k] < b.y0 || nx[k] > b.x1 || ny[k] > b.y1) continue;
              if (label.Get(nx[k], ny[k]) != r || reg.at(nx[k] - b.x0 + 1, ny[k] - b.y0 + 1)) continue;
              label.Set(nx[k], ny[k], -2);
              cells.push_back({nx[k], ny[k]});
            }
          }
          const double piece_m2 = static_cast<double>(cells.size()) * g.cell * g.cell;
          const bool keep = id >= 0 && piece_m2 >= std::max(o.min_room_area_m2, small_m2);
          int into = keep ? id : -1;
          if (!keep) {
            std::map<int, long> border;
            for (const auto& [cx, cy] : cells) {
              const int nx[4] = {cx + 1, cx - 1, cx, cx}, ny[4] = {cy, cy, cy + 1, cy - 1};
              for (int k = 0; k < 4; ++k) {
                if (nx[k] < 0 || ny[k] < 0 || nx[k] >= g.w || ny[k] >= g.h) continue;
                const int q = label.Get(nx[k], ny[k]);
                if (q >= 0) ++border[q];
              }
            }
            long most = 0;
            for (const auto& [q, n] : border)
              if (n > most) most = n, into = q;
          }
          CellBox nb;
          for (const auto& [cx, cy] : cells) {
            label.Set(cx, cy, into);
            nb.x0 = std::min(nb.x0, cx), nb.y0 = std::min(nb.y0, cy), nb.x1 = std::max(nb.x1, cx), nb.y1 = std::max(nb.y1, cy);
          }
          if (!keep) {
            if (into >= 0) {
              CellBox& ib = boxes[into];
              ib.x0 = std::min(ib.x0, nb.x0), ib.y0 = std::min(ib.y0, nb.y0);
              ib.x1 = std::max(ib.x1, nb.x1), ib.y1 = std::max(ib.y1, nb.y1);
            }
            continue;
          }
          const char kind = is_corridor[r];
          ++n_plan;
          boxes.push_back(nb);
          rooms.push_back(Room{});
          is_corridor.push_back(kind);
          polys.emplace_back();
          rings.emplace_back();
          anchors.emplace_back();
          inner.push_back(Vec2(0, 0));
        }
    }
    HalfCells half(g, &label, o.threads);
    auto half_box = [&](int r, int* x0, int* y0, int* x1, int* y1) {
      *x0 = std::max(0, 2 * boxes[r].x0 - 1), *y0 = std::max(0, 2 * boxes[r].y0 - 1);
      *x1 = std::min(half.w() - 1, 2 * boxes[r].x1 + 2), *y1 = std::min(half.h() - 1, 2 * boxes[r].y1 + 2);
    };
    const double site_m2 = 0.25 * g.cell * g.cell;
    // A room's sites after its turn are its filled piece exactly; only a
    // later room taking some of them (one it encloses, or whose hole it
    // sits in) changes them. The pieces of rooms no later room touched are
    // kept for the tracing below instead of being filled again, up to
    // kKeptSites sites in all, a megabyte (a large building's corridor is
    // filled again).
    constexpr size_t kKeptSites = size_t{1} << 20;
    std::vector<Region> kept(n_plan);
    std::vector<char> touched(n_plan, 0);
    size_t kept_sites = 0;
    auto fill = [&](int r) {
      int x0, y0, x1, y1;
      half_box(r, &x0, &y0, &x1, &y1);
      return FillRegionMasked(
          x0, y0, x1, y1, [&](std::vector<uint8_t>* mask, int W) { half.MaskOf(r, x0, y0, x1, y1, mask, W); });
    };
    auto box_sites = [&](int r) {
      int x0, y0, x1, y1;
      half_box(r, &x0, &y0, &x1, &y1);
      return static_cast<size_t>(x1 - x0 + 3) * static_cast<size_t>(y1 - y0 + 3);
    };
    // With PlanOptions::threads >= 2 the rooms' fills are made ahead, two at
    // a time on two threads, from the labels as they stand before the pair:
    // a room's fill reads only the sites labelled with it, which a room
    // filled in turn meanwhile changes only by taking some (flagged in
    // 'taken': that fill is made again, in turn). So the same fills as one
    // after the other,
    // with one fill more held at a time. A room whose box is larger than
    // kAheadSites is filled in turn alone (the scratch of two large fills at
    // once is what a large building's plan cannot spare).
    constexpr size_t kAheadSites = size_t{1} << 19;
    std::vector<Region> ahead(n_plan);
    std::vector<char> taken(n_plan, 0);
    int batch_end = 0;  // rooms before it were considered for filling ahead
    for (int r = 0; r < n_plan; ++r) {
      if (boxes[r].x1 < 0) continue;
      if (o.threads >= 2 && r >= batch_end) {
        std::vector<int> batch;
        for (batch_end = r; batch_end < n_plan && batch.size() < 2; ++batch_end) {
          if (boxes[batch_end].x1 < 0) continue;
          if (box_sites(batch_end) > kAheadSites) {
            if (batch.empty()) continue;  // filled in turn below
            break;
          }
          batch.push_back(batch_end);
        }
        if (batch.size() >= 2) {
          for (int q : batch) taken[q] = 0;  // (what was taken before is in the labels they read)
          ForEachShared(batch.size(), o.threads, [&](size_t k) { ahead[batch[k]] = fill(batch[k]); });
        }
      }
      int x0, y0, x1, y1;
      half_box(r, &x0, &y0, &x1, &y1);
      Region reg = !ahead[r].filled.empty() && !taken[r] ? std::move(ahead[r]) : fill(r);
      std::vector<uint8_t>().swap(ahead[r].filled);
      const bool keep = reg.count * site_m2 >= o.min_room_area_m2;
      for (int y = 1; y < reg.H - 1; ++y)
        for (int x = 1; x < reg.W - 1; ++x) {
          const int i = x0 - 1 + x, j = y0 - 1 + y;
          const int cur = half.Get(i, j);
          const bool mine = keep && reg.at(x, y);
          if (mine && cur != r) {
            if (cur >= 0) touched[cur] = 1, taken[cur] = 1;
            half.Set(i, j, r);
          }
          if (!mine && cur == r) half.Set(i, j, -1);
        }
      if (keep && kept_sites + reg.filled.size() <= kKeptSites) {
        kept_sites += reg.filled.size();
        kept[r] = std::move(reg);
      }
    }
    std::vector<Region>().swap(ahead);
    // The labels are final from here on: each room's outline reads them
    // alone, and with PlanOptions::threads >= 2 the rooms are shared out
    // over two threads (the same outlines, each written to its own room).
    auto trace = [&](int r) {
      if (boxes[r].x1 < 0) return;
      int x0, y0, x1, y1;
      half_box(r, &x0, &y0, &x1, &y1);
      const Region reg = !touched[r] && !kept[r].filled.empty()
                             ? std::move(kept[r])
                             : FillRegionMasked(x0, y0, x1, y1, [&](std::vector<uint8_t>* mask, int W) {
                                 half.MaskOf(r, x0, y0, x1, y1, mask, W);
                               });
      std::vector<uint8_t>().swap(kept[r].filled);
      Vec2 in_frame(0, 0);
      // A corner of the lattice where three or more labels (rooms, or none) meet.
      auto junction = [&](int i, int j) {
        const int l[4] = {half.Get(i - 1, j - 1), half.Get(i, j - 1), half.Get(i - 1, j), half.Get(i, j)};
        int distinct = 0;
        for (int k = 0; k < 4; ++k) {
          bool seen = false;
          for (int m = 0; m < k; ++m) seen = seen || l[m] == l[k];
          distinct += seen ? 0 : 1;
        }
        return distinct >= 3;
      };
      const double step = 0.5 * g.cell;
      std::vector<Vec2> ring = TraceRegion(reg, g.lo, step, &in_frame, junction);
      if (ring.size() < 3) return;
      // Where the outline meets two other labels: the ends of the borders
      // it shares (SimplifyOutlines keeps them).
      anchors[r].resize(ring.size());
      for (size_t k = 0; k < ring.size(); ++k)
        anchors[r][k] = junction(static_cast<int>(std::lround((ring[k].x() - g.lo.x()) / step)),
                                 static_cast<int>(std::lround((ring[k].y() - g.lo.y()) / step)));
      for (auto& v : ring) v = g.FromFrame(v);
      rings[r] = std::move(ring);
      inner[r] = g.FromFrame(in_frame);
    };
    ForEachShared(static_cast<size_t>(n_plan), o.threads, [&](size_t r) { trace(static_cast<int>(r)); });
    // The lattice's staircases along walls that are not square to it (a
    // wing turned against the rest) straightened, each border alike for the
    // two rooms it divides.
    SimplifyOutlines(&rings, anchors, o.outline_tolerance_cells * g.cell, 5.0 * g.cell);
    for (int r = 0; r < n_plan; ++r)
      if (rings[r].size() >= 3) polys[r] = ToBoost(rings[r]);
    std::vector<std::vector<Vec2>>().swap(rings);
  }

  // ---------------------------------------------------------------- assemble rooms
  std::vector<int> room_index(n_plan, -1);  // plan room -> output index
  int n_corr = 0, n_room = 0;
  for (int r = 0; r < n_plan; ++r) {
    if (polys[r].outer().size() < 3) continue;
    Room room = rooms[r];
    room.id = static_cast<int>(plan.rooms.size());
    room.corridor = is_corridor[r];
    room.name = room.corridor ? "Corridor " + std::to_string(++n_corr) : "Room " + std::to_string(++n_room);
    room.polygon = FromBoost(polys[r]);
    if (RingArea(room.polygon) < 0) std::reverse(room.polygon.begin(), room.polygon.end());
    room.area_m2 = std::abs(RingArea(room.polygon));
    std::sort(room.asr_ids.begin(), room.asr_ids.end());
    std::sort(room.graph_rooms.begin(), room.graph_rooms.end());
    room.graph_rooms.erase(std::unique(room.graph_rooms.begin(), room.graph_rooms.end()), room.graph_rooms.end());
    room.label = inner[r];
    if (!bg::within(BPoint(room.label.x(), room.label.y()), polys[r])) {
      BPoint c;
      bg::centroid(polys[r], c);
      room.label = Vec2(c.x(), c.y());
      if (!bg::within(c, polys[r])) {
        // A point just inside the first edge.
        const Vec2 e0 = room.polygon[0], e1 = room.polygon[1];
        room.label = 0.5 * (e0 + e1) + 1e-3 * Perp((e1 - e0).normalized());
      }
    }
    polys[r] = BPoly();  // the room holds its polygon now
    room_index[r] = room.id;
    plan.rooms.push_back(std::move(room));
  }

  // ---------------------------------------------------------------- doors, cuts, edges
  auto plan_room_of_asr = [&](int asr_id) {
    auto it = index_of.find(asr_id);
    if (it == index_of.end()) return -1;
    return room_index[plan_of_unit[unit_of[it->second]]];
  };
  const CellHash cut_hash = wall_boxes();
  std::map<int, std::vector<std::pair<double, double>>> cuts;  // segment -> cut spans (0..1)
  // A door away from where its two rooms meet (the boundary detector fires
  // a metre or so inside a room; a sonar's stray wall by the door took it)
  // moves onto their shared border: to where the robot's way crossed it
  // (nearest the door), along the border there, with the door's width,
  // cutting the walls along it.
  // The rooms' outlines share their common edges exactly (traced on one
  // lattice, vertices kept where three labels meet).
  // The smaller outline's edges go in a sorted list, the larger's are looked
  // up in it: linear in the larger (a corridor's outline), per door.
  auto shared_border = [&](int ra, int rb) {
    using Key = std::array<long long, 4>;
    auto key = [](const Vec2& p, const Vec2& q) {
      const long long a[2] = {std::llround(p.x() * 1e6), std::llround(p.y() * 1e6)};
      const long long b[2] = {std::llround(q.x() * 1e6), std::llround(q.y() * 1e6)};
      return std::pair(a[0], a[1]) < std::pair(b[0], b[1]) ? Key{a[0], a[1], b[0], b[1]} : Key{b[0], b[1], a[0], a[1]};
    };
    const auto* small = &plan.rooms[ra].polygon;
    const auto* large = &plan.rooms[rb].polygon;
    if (small->size() > large->size()) std::swap(small, large);
    std::vector<Key> keys;
    for (size_t i = 0; i < small->size(); ++i) keys.push_back(key((*small)[i], (*small)[(i + 1) % small->size()]));
    std::sort(keys.begin(), keys.end());
    std::vector<std::pair<Vec2, Vec2>> out;
    for (size_t i = 0; i < large->size(); ++i) {
      const Vec2& p = (*large)[i];
      const Vec2& q = (*large)[(i + 1) % large->size()];
      if (std::binary_search(keys.begin(), keys.end(), key(p, q))) out.push_back({p, q});
    }
    return out;
  };
  for (DoorCand& m : door_cands) {
    const int ra = plan_room_of_asr(m.from_asr), rb = plan_room_of_asr(m.to_asr);
    if (ra < 0 || rb < 0 || ra == rb || m.jambs) continue;
    const std::vector<std::pair<Vec2, Vec2>> border = shared_border(ra, rb);
    const Vec2 c = 0.5 * (m.a + m.b);
    double best = std::numeric_limits<double>::infinity();
    for (const auto& [p, q] : border) best = std::min(best, PointSegmentDistance(c, p, q));
    if (!std::isfinite(best) || best <= o.door_border_m) continue;
    // Where the robot's way crosses the border, nearest the door; without a
    // crossing (the way ends short of it) the door stays.
    // The steps of the way: each ASR's path, and the step from the one's
    // last pose by the door to the other's first when under a metre (the
    // robot went from one ASR into the next there).
    std::vector<std::pair<Vec2, Vec2>> steps;
    for (const auto& piece : m.way)
      for (size_t k = 1; k < piece.size(); ++k) steps.push_back({piece[k - 1], piece[k]});
    if (m.way.size() == 2 && (m.way[1].front() - m.way[0].back()).norm() < 1.0)
      steps.push_back({m.way[0].back(), m.way[1].front()});
    double cross = std::numeric_limits<double>::infinity();
    Vec2 at(0, 0);
    for (const auto& [a0, a1] : steps)
      for (const auto& [p, q] : border) {
        const Vec2 r = a1 - a0, e = q - p;
        const double den = Cross(r, e);
        if (std::abs(den) < 1e-12) continue;
        const double t = Cross(p - a0, e) / den, v = Cross(p - a0, r) / den;
        if (t < 0.0 || t > 1.0 || v < 0.0 || v > 1.0) continue;
        const Vec2 x = a0 + t * r;
        if ((x - c).norm() < cross) cross = (x - c).norm(), at = x;
      }
    if (!std::isfinite(cross)) continue;
    // The border's direction there: its edges within a door width of the
    // point, by length (doubled angles: a lattice border is a staircase).
    const double w = std::clamp((m.b - m.a).norm(), o.min_door_m, o.max_door_m);
    double sc = 0.0, ss = 0.0;
    for (const auto& [p, q] : border) {
      const double len = (q - p).norm();
      if (len < 1e-9 || PointSegmentDistance(at, p, q) > w) continue;
      const double ang = 2.0 * std::atan2(q.y() - p.y(), q.x() - p.x());
      sc += len * std::cos(ang), ss += len * std::sin(ang);
    }
    const double half = 0.5 * std::atan2(ss, sc);
    const Vec2 along(std::cos(half), std::sin(half));
    m.line_c = at, m.line_u = along;
    m.lo = -0.5 * w, m.hi = 0.5 * w;
    m.a = at + m.lo * along, m.b = at + m.hi * along;
    m.in_wall = true;
  }
  // One door per doorway: the robot goes in and comes out through the same
  // door, two exits (and a revisit more). Two doors between the same two
  // plan rooms whose lines lie within wall_thickness_m of each other and
  // overlap along them are one: the better placed is kept (between jambs,
  // then on a wall line, then the first); on a wall line but not between
  // jambs, it spans both.
  std::vector<char> merged(door_cands.size(), 0);
  std::vector<std::vector<std::pair<int, int>>> also_joins(door_cands.size());  // more room pairs per kept door
  {
    auto rooms_of = [&](const DoorCand& d) {
      const int ra = plan_room_of_asr(d.from_asr), rb = plan_room_of_asr(d.to_asr);
      return std::pair<int, int>(std::min(ra, rb), std::max(ra, rb));
    };
    auto same_doorway = [&](const DoorCand& d, const DoorCand& e) {
      const Vec2 u = (d.b - d.a).normalized(), v = (e.b - e.a).normalized();
      if (std::abs(u.dot(v)) < std::cos(Deg(o.face_angle_deg))) return false;
      const double ea = u.dot(e.a - d.a), eb = u.dot(e.b - d.a), len = (d.b - d.a).norm();
      if (std::max(ea, eb) <= 0.0 || std::min(ea, eb) >= len) return false;  // no overlap along d
      const Vec2 n = Perp(u);
      return std::abs(n.dot(0.5 * (e.a + e.b) - d.a)) <= o.wall_thickness_m ||
             std::abs(n.dot(0.5 * (d.a + d.b) - e.a)) <= o.wall_thickness_m;
    };
    // Compared only within each pair of rooms (in index order): linear in
    // the doors of a building whose rooms have a door or two each.
    std::map<std::pair<int, int>, std::vector<size_t>> by_rooms;
    for (size_t i = 0; i < door_cands.size(); ++i) {
      const auto ri = rooms_of(door_cands[i]);
      if (ri.first != ri.second) by_rooms[ri].push_back(i);
    }
    auto merge_within = [&](const std::vector<size_t>& members) {
      for (size_t mi = 0; mi < members.size(); ++mi) {
        const size_t i = members[mi];
        if (merged[i]) continue;
        for (size_t mj = mi + 1; mj < members.size(); ++mj) {
          const size_t j = members[mj];
          if (merged[j] || !same_doorway(door_cands[i], door_cands[j])) continue;
          if (door_cands[j].Rank() > door_cands[i].Rank()) {
            std::swap(door_cands[i], door_cands[j]);  // the better one takes i's place, in i's order
          }
          DoorCand& keep = door_cands[i];
          const DoorCand& drop = door_cands[j];
          if (keep.in_wall && !keep.jambs && drop.in_wall) {
            // Neither gap was measured between jambs: the door spans both
            // exits' widths along its line (as both cut the wall before).
            const double ta = keep.line_u.dot(drop.a - keep.line_c), tb = keep.line_u.dot(drop.b - keep.line_c);
            keep.lo = std::min({keep.lo, ta, tb}), keep.hi = std::max({keep.hi, ta, tb});
            keep.a = keep.line_c + keep.lo * keep.line_u, keep.b = keep.line_c + keep.hi * keep.line_u;
          }
          // The dropped door's rooms stay joined, through the kept door.
          auto& also = also_joins[i];
          also.push_back(rooms_of(drop));
          also.insert(also.end(), also_joins[j].begin(), also_joins[j].end());
          merged[j] = 1;
        }
      }
    };
    for (const auto& [pair, members] : by_rooms) merge_within(members);
    // Then doors that share one room: the robot went into a room and back
    // out through the one doorway into another piece of the corridor (its
    // pieces 1 and 3 meet at the door of room 2): one door, both edges.
    std::map<int, std::vector<size_t>> by_room;
    for (size_t i = 0; i < door_cands.size(); ++i) {
      if (merged[i]) continue;
      const auto ri = rooms_of(door_cands[i]);
      if (ri.first == ri.second) continue;
      for (int r : {ri.first, ri.second})
        if (r >= 0) by_room[r].push_back(i);
    }
    for (const auto& [room, members] : by_room) merge_within(members);
  }
  for (size_t k = 0; k < door_cands.size(); ++k) {
    if (merged[k]) continue;
    const DoorCand& d = door_cands[k];
    const int ra = plan_room_of_asr(d.from_asr), rb = plan_room_of_asr(d.to_asr);
    auto ia = index_of.find(d.from_asr), ib = index_of.find(d.to_asr);
    if (ia != index_of.end() && ib != index_of.end() &&
        plan_of_unit[unit_of[ia->second]] == plan_of_unit[unit_of[ib->second]])
      continue;  // inside one plan room (corridor pieces, slivers, revisits)
    Door door;
    door.id = static_cast<int>(plan.doors.size());
    door.a = d.a, door.b = d.b;
    door.room_a = ra, door.room_b = rb;
    door.from_asr = d.from_asr, door.to_asr = d.to_asr;
    if (d.in_wall) {
      // The gap, to be cut out of every face along the door line.
      const Vec2 r(o.wall_thickness_m + o.max_door_m, o.wall_thickness_m + o.max_door_m);
      for (int si : cut_hash.Query(d.line_c - r, d.line_c + r)) {
        const Seg& s = segs[si];
        const Vec2 v = (s.b - s.a);
        const double len = v.norm();
        if (len <= 0) continue;
        const Vec2 vu = v / len;
        const bool along = std::abs(vu.dot(d.line_u)) >= std::cos(Deg(o.face_angle_deg));
        const bool near = std::abs(Perp(d.line_u).dot(s.a - d.line_c)) <= o.wall_thickness_m ||
                          std::abs(Perp(d.line_u).dot(s.b - d.line_c)) <= o.wall_thickness_m;
        const double ta = d.line_u.dot(s.a - d.line_c), tb = d.line_u.dot(s.b - d.line_c);
        if (!along || !near || std::max(ta, tb) <= d.lo || std::min(ta, tb) >= d.hi) continue;
        // Parameters along s of the door's ends.
        const double k_lo = (d.lo - ta) / (tb - ta), k_hi = (d.hi - ta) / (tb - ta);
        cuts[si].push_back({std::clamp(std::min(k_lo, k_hi), 0.0, 1.0), std::clamp(std::max(k_lo, k_hi), 0.0, 1.0)});
      }
    }
    if (ra >= 0) plan.rooms[ra].doors.push_back(door.id);
    if (rb >= 0 && rb != ra) plan.rooms[rb].doors.push_back(door.id);
    if (ra >= 0 && rb >= 0 && ra != rb) plan.edges.push_back({ra, rb, door.id});
    // The room pairs of the doors merged into this one (the same doorway).
    std::set<std::pair<int, int>> joined = {{std::min(ra, rb), std::max(ra, rb)}};
    for (const auto& [xa, xb] : also_joins[k]) {
      if (xa < 0 || xb < 0 || xa == xb || !joined.insert({xa, xb}).second) continue;
      for (int x : {xa, xb})
        if (std::find(plan.rooms[x].doors.begin(), plan.rooms[x].doors.end(), door.id) == plan.rooms[x].doors.end())
          plan.rooms[x].doors.push_back(door.id);
      plan.edges.push_back({xa, xb, door.id});
    }
    plan.doors.push_back(door);
  }

  // Cut the doors out of the walls.
  {
    std::vector<Seg> out;
    for (size_t i = 0; i < segs.size(); ++i) {
      auto it = cuts.find(static_cast<int>(i));
      if (it == cuts.end()) {
        out.push_back(segs[i]);
        continue;
      }
      const Seg& s = segs[i];
      const Vec2 v = s.b - s.a;
      const double len = v.norm();
      std::vector<std::pair<double, double>> keep = {{0.0, 1.0}};
      for (const auto& [k0, k1] : it->second) SubtractSpan(&keep, k0, k1);
      for (const auto& [k0, k1] : keep)
        if ((k1 - k0) * len >= 0.05) out.push_back({s.a + k0 * v, s.a + k1 * v, s.n, s.piece});
    }
    segs = std::move(out);
  }

  // ---------------------------------------------------------------- the walls beside doors
  // A door is a gap in a wall, and the wall goes on along the door's line to
  // the next wall across it. A sonar in the rooms sees that stretch edge-on
  // (specular: no echo) between two strong reflectors, the jamb and the
  // corner, and the chain walk joins the two by a diagonal: from the jamb to
  // the corner rounded by the beam's blur (the chamfers above). A diagonal,
  // 15 degrees or more off the door's line and off the wall it meets, with
  // one end within chamfer_end_m of a jamb and the other, ahead of the jamb
  // away from the gap, within 1.5 blurs of where the door's line meets a
  // wall across it (60 degrees or more), is that stretch: it goes, and the
  // wall from the jamb to the crossing is drawn, once per jamb. The plan's
  // doors are final here (the rooms are cut): a door the rooms did not keep
  // (an exit between two boxes in one lab) adds no wall. A laser's blur is
  // its 2-cell floor: a diagonal that close to the door's line is no
  // diagonal.
  if (tan_half > 0.0 && !plan.doors.empty()) {
    const CellHash boxes = wall_boxes();
    std::vector<char> gone(segs.size(), 0);
    std::vector<Seg> added;
    for (const Door& door : plan.doors) {
      if (door.width_m() < 1e-9) continue;
      for (int side : {-1, 1}) {
        const Vec2 jamb = side < 0 ? door.a : door.b;
        const Vec2 w = side < 0 ? Vec2((door.a - door.b).normalized()) : Vec2((door.b - door.a).normalized());  // away from the gap
        const Vec2 e(o.chamfer_end_m, o.chamfer_end_m);
        double best_s = std::numeric_limits<double>::infinity();
        Vec2 best_x(0, 0), best_n(0, 0);
        size_t best_piece = 0;
        std::vector<size_t> diagonals;
        for (int si : boxes.Query(jamb - e, jamb + e)) {
          const size_t i = static_cast<size_t>(si);
          if (gone[i] || pieces[segs[i].piece].two_sided || pieces[segs[i].piece].squared) continue;
          const Vec2 dv = segs[i].b - segs[i].a;
          const double len = dv.norm();
          if (len < 1e-9 || std::abs(Cross(dv / len, w)) < sin15) continue;
          // The end at the jamb, and the other one ahead of it.
          const bool a_at = (segs[i].a - jamb).norm() <= o.chamfer_end_m;
          const bool b_at = (segs[i].b - jamb).norm() <= o.chamfer_end_m;
          if (a_at == b_at) continue;
          const Vec2 far = a_at ? segs[i].b : segs[i].a;
          if (w.dot(far - jamb) <= 0.0) continue;
          // The wall across the line near the far end: where the line meets it.
          const Vec2 r(1.5 * blur_max, 1.5 * blur_max);
          bool found = false;
          for (int sk : boxes.Query(far - r, far + r)) {
            const size_t k = static_cast<size_t>(sk);
            if (k == i || gone[k]) continue;
            const Vec2 kv = segs[k].b - segs[k].a;
            const double lk = kv.norm();
            if (lk < 1e-9) continue;
            const double den = Cross(w, kv / lk);
            if (std::abs(den) < sin60 || std::abs(Cross(dv / len, kv / lk)) < sin15) continue;
            const double sdist = Cross(segs[k].a - jamb, kv / lk) / den;  // jamb + sdist w on wall k's line
            if (sdist <= 0.0 || len > sdist + blur_max) continue;
            const Vec2 x = jamb + sdist * w;
            Vec2 seen(0, 0);
            const double blur = blur_seen(sparse_path, pieces[segs[i].piece], x, &seen);
            if (!std::isfinite(blur)) continue;
            // On wall k (or within the blur of its ends), the diagonal's far
            // end on the rounded corner, and the diagonal no longer than the
            // stretch it stands for.
            const double t = (x - segs[k].a).dot(kv / lk);
            if (t < -blur || t > lk + blur || (far - x).norm() > 1.5 * blur || len > sdist + blur) continue;
            found = true;
            if (sdist < best_s) {
              best_s = sdist, best_x = x, best_piece = segs[i].piece;
              best_n = Perp(w);
              if (best_n.dot(segs[i].n) < 0.0) best_n = -best_n;
            }
          }
          if (found) diagonals.push_back(i);
        }
        if (diagonals.empty()) continue;
        for (size_t i : diagonals) gone[i] = 1;
        added.push_back({jamb, best_x, best_n, best_piece});
      }
    }
    if (!added.empty()) {
      std::vector<Seg> kept;
      for (size_t i = 0; i < segs.size(); ++i)
        if (!gone[i]) kept.push_back(segs[i]);
      for (auto& a : added) kept.push_back(a);
      segs = std::move(kept);
    }
  }

  // ---------------------------------------------------------------- walls out
  for (const Seg& s : segs) {
    if ((s.b - s.a).norm() < 0.05) continue;
    const Piece& p = pieces[s.piece];
    Wall w;
    w.points = {s.a, s.b};
    w.free_on_left = Perp(s.b - s.a).dot(s.n) > 0;
    const double ext = [&] {
      double e = 0;
      for (const auto& sp : p.spans) e += sp.second - sp.first;
      return e;
    }();
    w.weight = ext > 0 ? p.weight * (s.b - s.a).norm() / ext : 0.0;
    w.asr_ids.assign(p.asrs.begin(), p.asrs.end());
    w.squared = p.squared;
    w.two_sided = p.two_sided;
    plan.walls.push_back(std::move(w));
  }

  // Bounds.
  Vec2 lo(1e300, 1e300), hi = -lo;
  for (const auto& w : plan.walls)
    for (const auto& p : w.points) lo = lo.cwiseMin(p), hi = hi.cwiseMax(p);
  for (const auto& r : plan.rooms)
    for (const auto& p : r.polygon) lo = lo.cwiseMin(p), hi = hi.cwiseMax(p);
  if (lo.x() <= hi.x()) plan.min = lo, plan.max = hi;
  return plan;
}

}  // namespace

Plan BuildPlan(const std::vector<asr::Asr>& asrs, const std::map<int, int>& room_of_asr, const PlanOptions& options,
               const std::map<int, std::vector<Pose2>>& placed_paths) {
  return BuildPlanFrom(asrs, room_of_asr, options, placed_paths, [] {});
}

Plan BuildPlanReleasing(std::vector<asr::Asr>* asrs, const std::map<int, int>& room_of_asr, const PlanOptions& options,
                        std::map<int, std::vector<Pose2>>* placed_paths) {
  return BuildPlanFrom(*asrs, room_of_asr, options, *placed_paths, [&] {
    std::map<int, std::vector<Pose2>>().swap(*placed_paths);
    for (asr::Asr& x : *asrs) {
      std::vector<Polyline>().swap(x.walls_local);
      std::vector<Pose2>().swap(x.path);
      std::vector<Pose2>().swap(x.true_path);
      std::vector<Vec2>().swap(x.free_hull_local);
    }
  });
}

Plan TransformPlan(const Pose2& pose, const Plan& plan) {
  Plan out = plan;
  for (auto& w : out.walls)
    for (auto& p : w.points) p = pose * p;
  for (auto& d : out.doors) d.a = pose * d.a, d.b = pose * d.b;
  for (auto& r : out.rooms) {
    for (auto& p : r.polygon) p = pose * p;
    r.label = pose * r.label;
  }
  if (out.home) out.home = pose * *out.home;
  out.dominant_direction_rad = std::fmod(std::fmod(plan.dominant_direction_rad + pose.theta, kPi / 2) + kPi / 2, kPi / 2);
  Vec2 lo(1e300, 1e300), hi = -lo;
  for (const auto& w : out.walls)
    for (const auto& p : w.points) lo = lo.cwiseMin(p), hi = hi.cwiseMax(p);
  for (const auto& r : out.rooms)
    for (const auto& p : r.polygon) lo = lo.cwiseMin(p), hi = hi.cwiseMax(p);
  if (lo.x() <= hi.x()) out.min = lo, out.max = hi;
  return out;
}

}  // namespace cogmap::plan
