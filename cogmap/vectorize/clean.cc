#include "cogmap/vectorize/clean.h"

#include <algorithm>
#include <cstdint>
#include <cstdlib>
#include <functional>
#include <vector>

#include "cogmap/core/bresenham.h"

namespace cogmap::vectorize {
namespace {

// True when the walk from a toward b meets a path cell before any occupied
// cell (a itself excluded). With 'stop_at_target', the walk ends at b.
template <typename Get>
bool RayReachesPath(int ax, int ay, int bx, int by, const CellClasses& cls, Get&& get,
                    int64_t* steps) {
  bool first = true, found = false;
  WalkBresenham(ax, ay, bx, by, [&](int x, int y) {
    if (first) {
      first = false;
      return true;
    }
    if (steps) ++*steps;
    const float v = get(x, y);
    if (cls.IsPath(v)) {
      found = true;
      return false;
    }
    return !cls.IsOccupied(v);
  });
  return found;
}

}  // namespace

grid::Grid2D<float> CleanMap(const grid::Grid2D<float>& grid, const CleanOptions& options,
                             CleanStats* stats) {
  CleanStats local;
  CleanStats& st = stats ? *stats : local;
  st = CleanStats{};
  grid::Grid2D<float> out = grid;
  const auto& lim = grid.limits();
  const int w = lim.width(), h = lim.height();
  const int m = std::max(0, options.max_dist_cells);
  const CellClasses& cls = options.classes;
  if (w <= 0 || h <= 0) return out;

  // Path cells in buckets of side B (cells are distinct by construction).
  const int bucket = std::max(4, std::min(16, m > 0 ? m / 2 : 4));
  const int bw = (w + bucket - 1) / bucket, bh = (h + bucket - 1) / bucket;
  std::vector<std::vector<std::pair<int, int>>> buckets(static_cast<size_t>(bw) * bh);
  const auto& cells = grid.cells();
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
      if (cls.IsPath(cells[lim.Flat(x, y)])) {
        buckets[static_cast<size_t>(y / bucket) * bw + x / bucket].push_back({x, y});
        ++st.path_cells;
      }
  auto get = [&](int x, int y) { return grid.get(x, y); };

  // (d2, x, y) of the path cells in range, as one 128-bit key per cell: sorted
  // as the triples are (all three are non-negative), without the triples'
  // branchy lexicographic comparison.
  using Key = unsigned __int128;
  std::vector<Key> candidates;
  std::vector<uint64_t> open_order;  // (nearest possible d2, bucket index)
  std::pair<int, int> witness(-1, -1);
  // Survivors with the path cell that sees them.
  std::vector<std::pair<grid::CellIndex, std::pair<int, int>>> survivors;
  auto occupied_at = [&](int x, int y) {
    return x >= 0 && y >= 0 && x < w && y < h && cls.IsOccupied(cells[lim.Flat(x, y)]);
  };
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) {
      const float v = cells[lim.Flat(x, y)];
      if (!cls.IsOccupied(v)) continue;
      ++st.occupied_in;
      out.at(x, y) = 0.0f;
      if (st.path_cells == 0) continue;
      // blocked[(dy + 1) * 3 + dx + 1]: the neighbour (x + dx, y + dy) is
      // occupied, so every ray whose first step lands there fails at once.
      bool blocked[9];
      int blocked_count = 0;
      for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx) {
          blocked[(dy + 1) * 3 + dx + 1] = (dx || dy) && occupied_at(x + dx, y + dy);
          blocked_count += blocked[(dy + 1) * 3 + dx + 1];
        }
      if (blocked_count == 8) {  // buried
        ++st.buried;
        continue;
      }
      bool found = false;
      auto in_range = [&](const std::pair<int, int>& p) {
        return std::abs(p.first - x) <= m && std::abs(p.second - y) <= m;
      };
      auto attempt = [&](const std::pair<int, int>& p) {
        ++st.rays_walked;
        return RayReachesPath(x, y, p.first, p.second, cls, get, &st.steps_walked);
      };
      // Nearest first: the first path cell that sees a is then about square
      // to the wall, which kRunMiddle uses as the direction through the band.
      // The buckets in range are opened in the order of their nearest
      // possible cell, their path cells kept in a min-heap of (d2, x, y)
      // keys; the heap's top is tried only when no unopened bucket can hold
      // a smaller key. Exactly the order of sorting every candidate, but the
      // first few nearest usually see the cell, so most are never sorted.
      candidates.clear();
      open_order.clear();
      const int bx0 = std::max(0, (x - m) / bucket), bx1 = std::min(bw - 1, (x + m) / bucket);
      const int by0 = std::max(0, (y - m) / bucket), by1 = std::min(bh - 1, (y + m) / bucket);
      for (int by = by0; by <= by1; ++by)
        for (int bx = bx0; bx <= bx1; ++bx) {
          if (buckets[static_cast<size_t>(by) * bw + bx].empty()) continue;
          const int gx = std::max({0, bx * bucket - x, x - (bx * bucket + bucket - 1)});
          const int gy = std::max({0, by * bucket - y, y - (by * bucket + bucket - 1)});
          open_order.push_back(static_cast<uint64_t>(gx * gx + gy * gy) << 32 |
                               static_cast<uint64_t>(by * bw + bx));
        }
      std::sort(open_order.begin(), open_order.end());
      const auto lower = std::greater<Key>();
      size_t next = 0;
      while (!found) {
        while (next < open_order.size() &&
               (candidates.empty() || static_cast<uint64_t>(candidates.front() >> 64) >= open_order[next] >> 32)) {
          for (const auto& p : buckets[static_cast<size_t>(open_order[next] & 0xffffffffu)])
            if (in_range(p)) {
              const int ddx = p.first - x, ddy = p.second - y;
              // A ray whose first step is occupied fails there; it is
              // neither queued nor walked (the same survivors and
              // witnesses, fewer rays_walked).
              int fx, fy;
              BresenhamFirstStep(ddx, ddy, &fx, &fy);
              if (blocked[(fy + 1) * 3 + fx + 1]) continue;
              candidates.push_back(static_cast<Key>(static_cast<uint64_t>(ddx * ddx + ddy * ddy)) << 64 |
                                   static_cast<uint64_t>(p.first) << 32 | static_cast<uint32_t>(p.second));
              std::push_heap(candidates.begin(), candidates.end(), lower);
            }
          ++next;
        }
        if (candidates.empty()) break;
        std::pop_heap(candidates.begin(), candidates.end(), lower);
        const Key c = candidates.back();
        candidates.pop_back();
        const std::pair<int, int> p(static_cast<int>(static_cast<uint64_t>(c) >> 32),
                                    static_cast<int>(static_cast<uint32_t>(c)));
        if (attempt(p)) {
          found = true;
          witness = p;
        }
      }
      if (found) survivors.push_back({grid::CellIndex(x, y), witness});
    }
  }
  for (const auto& [a, p] : survivors) {
    grid::CellIndex keep = a;
    if (options.keep == KeepCell::kRunMiddle) {
      // The run of occupied cells from a along p -> a.
      const int dx = a.x() - p.first, dy = a.y() - p.second;
      const double len = std::max(1e-9, std::sqrt(static_cast<double>(dx * dx + dy * dy)));
      const int reach = std::max(1, options.max_run_cells);
      const int ex = a.x() + static_cast<int>(std::lround(dx / len * reach));
      const int ey = a.y() + static_cast<int>(std::lround(dy / len * reach));
      std::vector<grid::CellIndex> run;
      WalkBresenham(a.x(), a.y(), ex, ey, [&](int cx, int cy) {
        if (!occupied_at(cx, cy) || static_cast<int>(run.size()) >= reach) return false;
        run.push_back({cx, cy});
        return true;
      });
      if (!run.empty()) keep = run[run.size() / 2];
    }
    out.at(keep) = grid.at(keep);
  }
  for (float v : out.cells()) st.kept += cls.IsOccupied(v);
  return out;
}

grid::Grid2D<float> CleanMapBruteForce(const grid::Grid2D<float>& grid,
                                       const CleanOptions& options) {
  grid::Grid2D<float> out = grid;
  const auto& lim = grid.limits();
  const int m = std::max(0, options.max_dist_cells);
  const CellClasses& cls = options.classes;
  auto get = [&](int x, int y) { return grid.get(x, y); };
  for (int y = 0; y < lim.height(); ++y) {
    for (int x = 0; x < lim.width(); ++x) {
      if (!cls.IsOccupied(grid.at(x, y))) continue;
      bool found = false;
      for (int j = -m; j <= m && !found; ++j)
        for (int i = -m; i <= m && !found; ++i) {
          if (i == 0 && j == 0) continue;
          found = RayReachesPath(x, y, x + i, y + j, cls, get, nullptr);
        }
      if (!found) out.at(x, y) = 0.0f;
    }
  }
  return out;
}

grid::Grid2D<float> CleanMapPathTargets(const grid::Grid2D<float>& grid,
                                        const CleanOptions& options) {
  grid::Grid2D<float> out = grid;
  const auto& lim = grid.limits();
  const int m = std::max(0, options.max_dist_cells);
  const CellClasses& cls = options.classes;
  auto get = [&](int x, int y) { return grid.get(x, y); };
  std::vector<std::pair<int, int>> path;
  for (int y = 0; y < lim.height(); ++y)
    for (int x = 0; x < lim.width(); ++x)
      if (cls.IsPath(grid.at(x, y))) path.push_back({x, y});
  for (int y = 0; y < lim.height(); ++y) {
    for (int x = 0; x < lim.width(); ++x) {
      if (!cls.IsOccupied(grid.at(x, y))) continue;
      bool found = false;
      for (const auto& p : path) {
        if (std::abs(p.first - x) > m || std::abs(p.second - y) > m) continue;
        if (RayReachesPath(x, y, p.first, p.second, cls, get, nullptr)) {
          found = true;
          break;
        }
      }
      if (!found) out.at(x, y) = 0.0f;
    }
  }
  return out;
}

}  // namespace cogmap::vectorize
