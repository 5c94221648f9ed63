#include "cogmap/vectorize/vectorize.h"

#include <chrono>

namespace cogmap::vectorize {
namespace {

double Since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

}  // namespace

VectorizeResult Vectorize(const grid::Grid2D<float>& grid, const VectorizeOptions& options) {
  VectorizeResult r;
  const auto& lim = grid.limits();
  r.bytes.grid = lim.cell_count();

  auto t0 = std::chrono::steady_clock::now();
  r.cleaned = CleanMap(grid, options.clean, &r.clean_stats);
  r.seconds.clean = Since(t0);

  t0 = std::chrono::steady_clock::now();
  r.chains = ExtractPoints(r.cleaned, options.extract, &r.extract_stats);
  r.seconds.extract = Since(t0);
  r.bytes.vertices = 4 * r.extract_stats.points;

  if (options.wall_lines) {
    // Walls as lines in the cleaned cells; the timing goes to 'fit'.
    t0 = std::chrono::steady_clock::now();
    LineExtractResult lines = ExtractWallLines(r.cleaned, grid, options.lines);
    r.line_stats = lines.stats;
    for (const auto& s : lines.segments) r.simplified.push_back({s.a, s.b});
    for (auto& wall : lines.walls) {
      Polyline world;
      world.reserve(wall.size());
      for (const auto& p : wall) world.push_back(lim.FromCellCoords(p));
      r.vertex_count += static_cast<int64_t>(world.size());
      r.polylines.push_back(std::move(world));
      r.fitted.push_back(std::move(wall));
    }
    r.seconds.fit = Since(t0);
    r.bytes.polylines = static_cast<int64_t>(EncodePolylines(r.polylines, options.codec).size());
    return r;
  }

  t0 = std::chrono::steady_clock::now();
  std::vector<std::vector<Vec2>> points;
  std::vector<std::vector<int>> kept;
  for (const auto& chain : r.chains) {
    if (static_cast<int>(chain.size()) < std::max(2, options.min_chain_points)) {
      ++r.dropped_chains;
      continue;
    }
    points.push_back(ChainToCellCoords(chain));
    if (options.smooth_half_window > 0) {
      const auto raw = points.back();
      const int n = static_cast<int>(raw.size()), k = options.smooth_half_window;
      for (int i = 0; i < n; ++i) {
        Vec2 sum(0, 0);
        int count = 0;
        for (int j = std::max(0, i - k); j <= std::min(n - 1, i + k); ++j) sum += raw[j], ++count;
        points.back()[i] = sum / count;
      }
      if (n >= 2 && chain.front() == chain.back()) points.back().back() = points.back().front();
    }
    const auto& pts = points.back();
    const std::vector<int> vs = VertexSimplifyIndices(pts, options.vertex_simplify);
    r.vertices_after_vertex_simplify += static_cast<int64_t>(vs.size());
    const std::vector<int> dp = DouglasPeuckerIndices(Pick(pts, vs), options.douglas_peucker);
    std::vector<int> idx;
    idx.reserve(dp.size());
    for (int i : dp) idx.push_back(vs[i]);
    r.simplified.push_back(Pick(pts, idx));
    kept.push_back(std::move(idx));
  }
  r.seconds.simplify = Since(t0);

  t0 = std::chrono::steady_clock::now();
  for (size_t c = 0; c < points.size(); ++c) {
    r.fitted.push_back(FitEdges(points[c], kept[c], options.fit, &r.fit_stats));
    Polyline world;
    world.reserve(r.fitted.back().size());
    for (const auto& p : r.fitted.back()) world.push_back(lim.FromCellCoords(p));
    r.vertex_count += static_cast<int64_t>(world.size());
    r.polylines.push_back(std::move(world));
  }
  r.seconds.fit = Since(t0);
  r.bytes.polylines = static_cast<int64_t>(EncodePolylines(r.polylines, options.codec).size());
  return r;
}

}  // namespace cogmap::vectorize
