#include "cogmap/vectorize/line_fit.h"

#include <cmath>

#include "cogmap/core/angles.h"

namespace cogmap::vectorize {
namespace {

Vec2 Project(const FittedLine& l, const Vec2& p) {
  return l.point + l.direction * (p - l.point).dot(l.direction);
}

}  // namespace

FittedLine FitLine(const std::vector<Vec2>& points, const LineFitOptions& options) {
  FittedLine line;
  const size_t n = points.size();
  if (n < 2) return line;
  Vec2 mean(0, 0);
  for (const auto& p : points) mean += p;
  mean /= static_cast<double>(n);
  double sxx = 0, syy = 0, sxy = 0;
  for (const auto& p : points) {
    const Vec2 d = p - mean;
    sxx += d.x() * d.x();
    syy += d.y() * d.y();
    sxy += d.x() * d.y();
  }
  line.point = mean;
  if (sxx <= 0.0 && syy <= 0.0) return line;  // all points equal
  if (options.mode == FitMode::kPaper) {
    // Eq. 3.8/3.9 on the axis of larger spread (y on x, or x on y).
    if (sxx >= syy)
      line.direction = Vec2(1.0, sxy / sxx).normalized();
    else
      line.direction = Vec2(sxy / syy, 1.0).normalized();
    // Eq. 3.10; exact when there is no spread across the line.
    const double rho = (sxx > 0.0 && syy > 0.0) ? sxy / std::sqrt(sxx * syy) : 1.0;
    line.quality = std::abs(rho);
    line.accepted = line.quality >= options.min_abs_pearson;
  } else {
    // Principal axis of the scatter matrix.
    const double tr = sxx + syy, det = sxx * syy - sxy * sxy;
    const double disc = std::sqrt(std::max(0.0, tr * tr / 4.0 - det));
    const double l_max = tr / 2.0 + disc, l_min = std::max(0.0, tr / 2.0 - disc);
    const double angle = 0.5 * std::atan2(2.0 * sxy, sxx - syy);
    line.direction = Vec2(std::cos(angle), std::sin(angle));
    (void)l_max;
    line.quality = std::sqrt(l_min / static_cast<double>(n));
    line.accepted = line.quality <= options.max_rms_cells;
  }
  return line;
}

std::vector<Vec2> FitEdges(const std::vector<Vec2>& points, const std::vector<int>& vertices,
                           const LineFitOptions& options, LineFitStats* stats) {
  LineFitStats local;
  LineFitStats& st = stats ? *stats : local;
  const int k = static_cast<int>(vertices.size());
  std::vector<Vec2> out;
  for (int v : vertices) out.push_back(points[v]);
  if (k < 2) return out;
  const int edges = k - 1;
  std::vector<FittedLine> lines(edges);
  std::vector<Vec2> span;
  for (int e = 0; e < edges; ++e) {
    ++st.edges;
    span.assign(points.begin() + vertices[e], points.begin() + vertices[e + 1] + 1);
    if (static_cast<int>(span.size()) < std::max(2, options.min_points)) {
      ++st.too_few_points;
      continue;
    }
    lines[e] = FitLine(span, options);
    if (lines[e].accepted)
      ++st.fitted;
    else
      ++st.rejected;
  }
  const bool closed = k >= 4 && points[vertices.front()] == points[vertices.back()];
  const double min_sin = std::sin(DegToRad(options.min_corner_deg));
  for (int i = 0; i < k; ++i) {
    if (closed && i == k - 1) break;  // same vertex as 0
    int before = i - 1, after = i < edges ? i : -1;
    if (closed && i == 0) before = edges - 1;
    if (closed && i == k - 1) after = 0;
    const FittedLine* a = before >= 0 && lines[before].accepted ? &lines[before] : nullptr;
    const FittedLine* b = after >= 0 && lines[after].accepted ? &lines[after] : nullptr;
    const Vec2 v = points[vertices[i]];
    if (a && b) {
      const double cross = a->direction.x() * b->direction.y() - a->direction.y() * b->direction.x();
      bool joined = false;
      if (options.mode == FitMode::kDefault && std::abs(cross) >= min_sin) {
        // a.point + s a.dir = b.point + t b.dir
        const Vec2 d = b->point - a->point;
        const double s = (d.x() * b->direction.y() - d.y() * b->direction.x()) / cross;
        const Vec2 x = a->point + s * a->direction;
        if ((x - v).norm() <= options.max_corner_shift_cells) {
          out[i] = x;
          joined = true;
          ++st.corners_joined;
        }
      }
      if (!joined) out[i] = 0.5 * (Project(*a, v) + Project(*b, v));
    } else if (a) {
      out[i] = Project(*a, v);
    } else if (b) {
      out[i] = Project(*b, v);
    }
  }
  if (closed) out.back() = out.front();
  if (options.mode == FitMode::kDefault && options.max_chamfer_cells > 0.0 && edges >= 3) {
    auto line_of = [&](int e) -> const FittedLine* {
      if (closed) e = (e % edges + edges) % edges;
      return e >= 0 && e < edges && lines[e].accepted ? &lines[e] : nullptr;
    };
    std::vector<char> chamfer(edges, 0);
    std::vector<Vec2> corner(edges);
    for (int e = 0; e < edges; ++e) {
      const FittedLine* a = line_of(e - 1);
      const FittedLine* b = line_of(e + 1);
      if (!a || !b || a == b) continue;
      if ((out[e + 1] - out[e]).norm() >= options.max_chamfer_cells) continue;
      const double cross = a->direction.x() * b->direction.y() - a->direction.y() * b->direction.x();
      if (std::abs(cross) < min_sin) continue;
      const Vec2 d = b->point - a->point;
      const double s = (d.x() * b->direction.y() - d.y() * b->direction.x()) / cross;
      const Vec2 x = a->point + s * a->direction;
      if ((x - 0.5 * (out[e] + out[e + 1])).norm() > options.max_chamfer_cells) continue;
      // Neighbouring chamfers would fight over a vertex: take the first.
      if (e > 0 && chamfer[e - 1]) continue;
      chamfer[e] = 1;
      corner[e] = x;
    }
    if (closed && chamfer[0] && chamfer[edges - 1]) chamfer[edges - 1] = 0;
    for (int e = 0; e < edges; ++e)
      if (chamfer[e]) {
        out[e] = out[e + 1] = corner[e];
        ++st.chamfers_removed;
      }
    if (closed) {
      if (chamfer[0]) out.back() = out.front();
      if (chamfer[edges - 1]) out.front() = out.back();
    }
    std::vector<Vec2> dedup;
    for (const auto& v : out)
      if (dedup.empty() || (v - dedup.back()).norm() > 1e-9) dedup.push_back(v);
    if (closed && dedup.size() >= 2 && (dedup.front() - dedup.back()).norm() > 1e-9) dedup.push_back(dedup.front());
    out = std::move(dedup);
  }
  return out;
}

}  // namespace cogmap::vectorize
