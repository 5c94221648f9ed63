#include "cogmap/vectorize/synthetic_grid.h"

#include <algorithm>
#include <cmath>
#include <random>

#include "cogmap/core/bresenham.h"

namespace cogmap::vectorize {

grid::Grid2D<float> MakeSyntheticGrid(const std::vector<Segment2>& walls, const Polyline& path,
                                      const SyntheticGridOptions& options) {
  const double c = options.cell_m;
  Vec2 lo(1e300, 1e300), hi(-1e300, -1e300);
  auto grow = [&](const Vec2& p) {
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
  };
  for (const auto& w : walls) grow(w.a), grow(w.b);
  for (const auto& p : path) grow(p);
  if (walls.empty() && path.empty()) lo = hi = Vec2(0, 0);
  lo -= Vec2(options.margin_m, options.margin_m);
  hi += Vec2(options.margin_m, options.margin_m);
  lo = Vec2(std::floor(lo.x() / c) * c, std::floor(lo.y() / c) * c);
  const int w = std::max(1, static_cast<int>(std::ceil((hi.x() - lo.x()) / c)));
  const int h = std::max(1, static_cast<int>(std::ceil((hi.y() - lo.y()) / c)));
  grid::Grid2D<float> g(grid::MapLimits(c, lo, w, h), 0.0f);
  const auto& lim = g.limits();
  std::mt19937 rng(options.seed);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const Vec2 p = lim.CenterOf({x, y});
      bool occ = false;
      for (const auto& s : walls)
        if (PointSegmentDistance(p, s.a, s.b) <= options.wall_half_width_m + 1e-9) {
          occ = true;
          break;
        }
      if (occ) {
        g.at(x, y) = options.wall_value;
        continue;
      }
      if (options.see_m > 0.0) {
        for (size_t i = 0; i + 1 < path.size() || (i == 0 && path.size() == 1); ++i) {
          const Vec2& a = path[i];
          const Vec2& b = path.size() == 1 ? path[0] : path[i + 1];
          if (PointSegmentDistance(p, a, b) <= options.see_m) {
            g.at(x, y) = options.empty_value;
            break;
          }
        }
      }
      if (options.noise_fraction > 0.0 && u(rng) < options.noise_fraction) g.at(x, y) = options.wall_value;
    }
  for (size_t i = 0; i < path.size(); ++i) {
    const auto a = lim.CellOf(path[i]);
    const auto b = lim.CellOf(i + 1 < path.size() ? path[i + 1] : path[i]);
    WalkBresenham(a.x(), a.y(), b.x(), b.y(), [&](int x, int y) {
      if (lim.Contains({x, y})) g.at(x, y) = -100.0f;
      return true;
    });
  }
  return g;
}

std::vector<Segment2> RectangleWalls(const Vec2& min, const Vec2& max) {
  return {{min, Vec2(max.x(), min.y())},
          {Vec2(max.x(), min.y()), max},
          {max, Vec2(min.x(), max.y())},
          {Vec2(min.x(), max.y()), min}};
}

}  // namespace cogmap::vectorize
