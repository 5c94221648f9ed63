#include "cogmap/sim/nav_grid.h"

#include <algorithm>
#include <cmath>
#include <deque>
#include <string>

#include "cogmap/core/error.h"

namespace cogmap::sim {
namespace {
// 2^26 cells (10 bytes each): an 800 m square at 10 cm.
constexpr double kMaxNavCells = 67108864.0;
}  // namespace

grid::MapLimits LimitsAround(const World& world, const std::vector<Vec2>& extra, double cell_m,
                             double margin_m) {
  Vec2 lo = world.min(), hi = world.max();
  if (world.walls().empty() && !extra.empty()) lo = hi = extra.front();
  for (const auto& p : extra) {
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
  }
  lo -= Vec2(margin_m, margin_m);
  hi += Vec2(margin_m, margin_m);
  // Sizes in floating point first: a world far too large (or not finite) must
  // not reach the conversion to int, nor the allocation.
  const double wd = std::ceil((hi.x() - lo.x()) / cell_m), hd = std::ceil((hi.y() - lo.y()) / cell_m);
  if (!(std::isfinite(wd) && std::isfinite(hd)) || std::max(wd, 1.0) * std::max(hd, 1.0) > kMaxNavCells)
    throw InputError("world: " + std::to_string(hi.x() - lo.x()) + " x " + std::to_string(hi.y() - lo.y()) +
                     " m needs more than " + std::to_string(static_cast<long>(kMaxNavCells)) +
                     " navigation cells of " + std::to_string(cell_m) + " m");
  const int w = std::max(1, static_cast<int>(wd));
  const int h = std::max(1, static_cast<int>(hd));
  return grid::MapLimits(cell_m, lo, w, h);
}

NavGrid::NavGrid(const World& world, const grid::MapLimits& limits, double robot_radius_m,
                 double margin_m)
    : limits_(limits) {
  const long n = limits_.cell_count();
  passable_.assign(n, 0);
  wall_.assign(n, 0);
  parent_.assign(n, -1);
  stamp_.assign(n, 0);
  const double need = robot_radius_m + margin_m;
  for (int y = 0; y < limits_.height(); ++y)
    for (int x = 0; x < limits_.width(); ++x) {
      const Vec2 c = limits_.CenterOf({x, y});
      passable_[limits_.Flat(x, y)] = world.Clearance(c, need + 1e-9) >= need ? 1 : 0;
    }
  const double step = limits_.cell_m() * 0.25;
  for (const auto& w : world.walls()) {
    const int k = std::max(1, static_cast<int>(std::ceil(w.length() / step)));
    for (int i = 0; i <= k; ++i) {
      const auto c = limits_.CellOf(w.a + (w.b - w.a) * (static_cast<double>(i) / k));
      if (limits_.Contains(c)) wall_[limits_.Flat(c)] = 1;
    }
  }
}

bool NavGrid::Passable(const Vec2& p) const {
  const auto c = limits_.CellOf(p);
  return limits_.Contains(c) && passable_[limits_.Flat(c)];
}

long NavGrid::NearestPassable(const Vec2& p, double within_m) const {
  const auto c0 = limits_.CellOf(p);
  const int r = static_cast<int>(std::ceil(within_m / limits_.cell_m()));
  long best = -1;
  double best_d = within_m;
  for (int dy = -r; dy <= r; ++dy)
    for (int dx = -r; dx <= r; ++dx) {
      const grid::CellIndex c(c0.x() + dx, c0.y() + dy);
      if (!limits_.Contains(c) || !passable_[limits_.Flat(c)]) continue;
      const double d = (limits_.CenterOf(c) - p).norm();
      if (d <= best_d) {
        best_d = d;
        best = limits_.Flat(c);
      }
    }
  return best;
}

std::vector<long> NavGrid::FindPath(long start, const std::function<bool(long)>& is_goal) const {
  if (start < 0 || start >= limits_.cell_count() || !passable_[start]) return {};
  if (++generation_ == 0) {
    std::fill(stamp_.begin(), stamp_.end(), 0);
    generation_ = 1;
  }
  const int w = limits_.width(), h = limits_.height();
  std::deque<long> queue{start};
  stamp_[start] = generation_;
  parent_[start] = -1;
  static constexpr int kDx[8] = {1, -1, 0, 0, 1, 1, -1, -1};
  static constexpr int kDy[8] = {0, 0, 1, -1, 1, -1, 1, -1};
  while (!queue.empty()) {
    const long cur = queue.front();
    queue.pop_front();
    if (is_goal(cur)) {
      std::vector<long> path;
      for (long c = cur; c >= 0; c = parent_[c]) path.push_back(c);
      std::reverse(path.begin(), path.end());
      return path;
    }
    const int cx = static_cast<int>(cur % w), cy = static_cast<int>(cur / w);
    for (int k = 0; k < 8; ++k) {
      const int nx = cx + kDx[k], ny = cy + kDy[k];
      if (nx < 0 || ny < 0 || nx >= w || ny >= h) continue;
      const long nf = limits_.Flat(nx, ny);
      if (stamp_[nf] == generation_ || !passable_[nf]) continue;
      // Diagonal moves only when both side cells are passable (no corner cutting).
      if (k >= 4 && (!passable_[limits_.Flat(nx, cy)] || !passable_[limits_.Flat(cx, ny)])) continue;
      stamp_[nf] = generation_;
      parent_[nf] = static_cast<int32_t>(cur);
      queue.push_back(nf);
    }
  }
  return {};
}

bool NavGrid::PassableLine(const Vec2& a, const Vec2& b) const {
  const double len = (b - a).norm();
  const int k = std::max(1, static_cast<int>(std::ceil(len / (0.5 * limits_.cell_m()))));
  for (int i = 0; i <= k; ++i)
    if (!Passable(a + (b - a) * (static_cast<double>(i) / k))) return false;
  return true;
}

}  // namespace cogmap::sim
