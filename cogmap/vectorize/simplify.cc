#include "cogmap/vectorize/simplify.h"

#include <utility>

namespace cogmap::vectorize {

std::vector<int> VertexSimplifyIndices(const std::vector<Vec2>& line,
                                       const VertexSimplifyOptions& options) {
  std::vector<int> kept;
  const int n = static_cast<int>(line.size());
  if (n == 0) return kept;
  kept.push_back(0);
  for (int i = 1; i < n; ++i)
    if ((line[i] - line[kept.back()]).norm() >= options.tau_cells) kept.push_back(i);
  if (options.keep_end && n >= 2 && kept.back() != n - 1) {
    if (kept.size() >= 2) kept.back() = n - 1;
    else kept.push_back(n - 1);
  }
  return kept;
}

std::vector<int> DouglasPeuckerIndices(const std::vector<Vec2>& line,
                                       const DouglasPeuckerOptions& options) {
  const int n = static_cast<int>(line.size());
  std::vector<int> kept;
  if (n == 0) return kept;
  if (n <= 2) {
    for (int i = 0; i < n; ++i) kept.push_back(i);
    return kept;
  }
  std::vector<char> mark(n, 0);
  mark[0] = mark[n - 1] = 1;
  std::vector<std::pair<int, int>> stack;
  if ((line[0] - line[n - 1]).norm() == 0.0) {
    // Closed: the chord is a point; split at the vertex farthest from it.
    int far = 0;
    double best = -1.0;
    for (int i = 1; i < n - 1; ++i) {
      const double d = (line[i] - line[0]).norm();
      if (d > best) best = d, far = i;
    }
    if (far > 0) {
      mark[far] = 1;
      stack.push_back({0, far});
      stack.push_back({far, n - 1});
    }
  } else {
    stack.push_back({0, n - 1});
  }
  while (!stack.empty()) {
    const auto [j, k] = stack.back();
    stack.pop_back();
    if (k - j < 2) continue;
    int far = j;
    double best = 0.0;
    for (int i = j + 1; i < k; ++i) {
      const double d = PointSegmentDistance(line[i], line[j], line[k]);
      if (d > best) best = d, far = i;
    }
    if (best > options.eta_cells) {
      mark[far] = 1;
      stack.push_back({j, far});
      stack.push_back({far, k});
    }
  }
  for (int i = 0; i < n; ++i)
    if (mark[i]) kept.push_back(i);
  return kept;
}

std::vector<Vec2> Pick(const std::vector<Vec2>& line, const std::vector<int>& indices) {
  std::vector<Vec2> out;
  out.reserve(indices.size());
  for (int i : indices) out.push_back(line[i]);
  return out;
}

Polyline VertexSimplify(const Polyline& line, const VertexSimplifyOptions& options) {
  return Pick(line, VertexSimplifyIndices(line, options));
}

Polyline SimplifyDouglasPeucker(const Polyline& line, const DouglasPeuckerOptions& options) {
  return Pick(line, DouglasPeuckerIndices(line, options));
}

}  // namespace cogmap::vectorize
