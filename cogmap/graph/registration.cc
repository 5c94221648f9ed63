#include "cogmap/graph/registration.h"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <limits>

namespace cogmap::graph {
namespace {

Vec2 Perp(const Vec2& v) { return {-v.y(), v.x()}; }

}  // namespace

int NearestFaceByScan(const std::vector<FacedSegment>& target, const Vec2& p, const Vec2& n, double max_d,
                      double cos_max, double* residual) {
  int best = -1;
  double best_d = max_d;
  for (size_t k = 0; k < target.size(); ++k) {
    const FacedSegment& f = target[k];
    if (f.normal.dot(n) < cos_max) continue;
    const double d = PointSegmentDistance(p, f.a, f.b);
    if (d < best_d) {
      best_d = d;
      best = static_cast<int>(k);
    }
  }
  if (best >= 0) *residual = target[best].normal.dot(p - target[best].a);
  return best;
}

FaceIndex::FaceIndex(const std::vector<FacedSegment>& faces, double cell_m, double reach_m) : faces_(&faces) {
  if (faces.empty()) return;
  Vec2 lo = faces[0].a, hi = faces[0].a;
  for (const FacedSegment& f : faces) {
    lo = lo.cwiseMin(f.a).cwiseMin(f.b);
    hi = hi.cwiseMax(f.a).cwiseMax(f.b);
    boxes_.push_back({std::min(f.a.x(), f.b.x()), std::min(f.a.y(), f.b.y()), std::max(f.a.x(), f.b.x()),
                      std::max(f.a.y(), f.b.y())});
  }
  // Cells no finer than the faces' extent allows: at most some 16 cells a face
  // (and 4096 in all for a handful of faces), whatever the coordinates.
  const double wx = hi.x() - lo.x(), wy = hi.y() - lo.y();
  const double max_cells = std::max(4096.0, 16.0 * static_cast<double>(faces.size()));
  const double cell = std::max({cell_m, std::sqrt(wx * wy / max_cells), std::max(wx, wy) / max_cells, 1e-9});
  lo_ = lo;
  inv_cell_ = 1.0 / cell;
  nx_ = static_cast<int>(wx * inv_cell_) + 1;
  ny_ = static_cast<int>(wy * inv_cell_) + 1;
  // The cells a face's box covers: counted, then filled (one flat array).
  auto cells_of = [&](const Box& box, int* i0, int* i1, int* j0, int* j1) {
    *i0 = CellOf((box.x0 - lo_.x()) * inv_cell_, nx_);
    *i1 = CellOf((box.x1 - lo_.x()) * inv_cell_, nx_);
    *j0 = CellOf((box.y0 - lo_.y()) * inv_cell_, ny_);
    *j1 = CellOf((box.y1 - lo_.y()) * inv_cell_, ny_);
  };
  // Each cell's list of the faces whose box, grown by 'grow', meets it:
  // counted, then filled face by face (one flat array, each list in index
  // order).
  auto bucket = [&](double grow, std::vector<int>* start, std::vector<int>* items) {
    start->assign(static_cast<size_t>(nx_) * ny_ + 1, 0);
    auto grown_cells = [&](const Box& box, int* i0, int* i1, int* j0, int* j1) {
      cells_of({box.x0 - grow, box.y0 - grow, box.x1 + grow, box.y1 + grow}, i0, i1, j0, j1);
    };
    for (const Box& box : boxes_) {
      int i0, i1, j0, j1;
      grown_cells(box, &i0, &i1, &j0, &j1);
      for (int i = i0; i <= i1; ++i)
        for (int j = j0; j <= j1; ++j) ++(*start)[static_cast<size_t>(i) * ny_ + j + 1];
    }
    for (size_t c = 1; c < start->size(); ++c) (*start)[c] += (*start)[c - 1];
    items->resize(start->back());
    std::vector<int> fill(start->begin(), start->end() - 1);
    for (size_t k = 0; k < boxes_.size(); ++k) {
      int i0, i1, j0, j1;
      grown_cells(boxes_[k], &i0, &i1, &j0, &j1);
      for (int i = i0; i <= i1; ++i)
        for (int j = j0; j <= j1; ++j) (*items)[fill[static_cast<size_t>(i) * ny_ + j]++] = static_cast<int>(k);
    }
  };
  bucket(0.0, &start_, &items_);
  if (!(reach_m > 0.0)) return;
  // The faces within reach of each cell: those whose box grown by reach (and
  // a margin for rounding) meets the cell. A point whose cell (CellOf,
  // clamped and never decreasing) is that of a point within reach of a face
  // lies in the face's grown box's cell range, so its cell's list holds
  // every face nearer than reach.
  reach_ = reach_m;
  bucket(reach_m + 1e-6, &near_start_, &near_);
}

int FaceIndex::Nearest(const Vec2& p, const Vec2& n, double max_d, double cos_max, double* residual,
                       double* distance) const {
  if (nx_ == 0) return -1;
  // A face closer than max_d has its nearest point, and so part of its box, in
  // the square of half-side max_d around p. CellOf never decreases as its
  // argument grows, so the cells of that point lie in the square's cell range.
  // The margin covers rounding; the faces it adds are measured like the others.
  const double r = max_d + 1e-6;
  const double ux0 = (p.x() - r - lo_.x()) * inv_cell_, ux1 = (p.x() + r - lo_.x()) * inv_cell_;
  const double uy0 = (p.y() - r - lo_.y()) * inv_cell_, uy1 = (p.y() + r - lo_.y()) * inv_cell_;
  if (!(ux1 >= 0.0 && uy1 >= 0.0 && ux0 < nx_ && uy0 < ny_)) return -1;  // also NaN
  const std::vector<FacedSegment>& faces = *faces_;
  int best = -1;
  double best_d = max_d;
  // One candidate face: a face whose box lies farther than the best so far
  // along x or y is farther (the margin covers rounding); then the normal;
  // then the distance. The scan's answer: the smallest distance, the lowest
  // index among equals.
  auto consider = [&](int k) {
    const Box& box = boxes_[k];
    const double reach = best_d + 1e-6;
    if (p.x() < box.x0 - reach || p.x() > box.x1 + reach || p.y() < box.y0 - reach || p.y() > box.y1 + reach)
      return;
    const FacedSegment& f = faces[k];
    if (f.normal.dot(n) < cos_max) return;
    const double d = PointSegmentDistance(p, f.a, f.b);
    if (d < best_d || (d == best_d && k < best)) {
      best_d = d;
      best = k;
    }
  };
  if (reach_ > 0.0 && max_d <= reach_) {
    // Every face nearer than max_d is in p's cell's list, once, in index order.
    const size_t c = static_cast<size_t>(CellOf((p.x() - lo_.x()) * inv_cell_, nx_)) * ny_ +
                     static_cast<size_t>(CellOf((p.y() - lo_.y()) * inv_cell_, ny_));
    for (const int* it = near_.data() + near_start_[c], *end = near_.data() + near_start_[c + 1]; it != end; ++it)
      consider(*it);
  } else {
    // The cells of the square of max_d around p; a face listed in several
    // cells is met again: same distance, no change.
    const int i0 = CellOf(ux0, nx_), i1 = CellOf(ux1, nx_), j0 = CellOf(uy0, ny_), j1 = CellOf(uy1, ny_);
    for (int i = i0; i <= i1; ++i) {
      const int* it = items_.data() + start_[static_cast<size_t>(i) * ny_ + j0];
      const int* end = items_.data() + start_[static_cast<size_t>(i) * ny_ + j1 + 1];
      for (; it != end; ++it) consider(*it);
    }
  }
  if (best >= 0) {
    *residual = faces[best].normal.dot(p - faces[best].a);
    if (distance) *distance = best_d;
  }
  return best;
}

std::vector<FacedSegment> FaceWalls(const std::vector<Polyline>& walls, const std::vector<Vec2>& free_points,
                                    double min_length_m) {
  std::vector<FacedSegment> out;
  for (const Polyline& line : walls) {
    for (size_t i = 1; i < line.size(); ++i) {
      const Vec2 a = line[i - 1], b = line[i];
      const double len = (b - a).norm();
      if (len < min_length_m) continue;
      Vec2 n = Perp((b - a) / len);
      const Vec2 mid = 0.5 * (a + b);
      // The free side: where the nearest path point is.
      double best = std::numeric_limits<double>::infinity();
      Vec2 nearest = mid + n;
      for (const Vec2& q : free_points) {
        const double d = PointSegmentDistance(q, a, b);
        if (d < best) {
          best = d;
          nearest = q;
        }
      }
      if (n.dot(nearest - mid) < 0.0) n = -n;
      out.push_back({a, b, n});
    }
  }
  return out;
}

std::vector<FacedPoint> SampleFaces(const std::vector<FacedSegment>& faces, double step_m) {
  std::vector<FacedPoint> out;
  for (size_t k = 0; k < faces.size(); ++k) {
    const FacedSegment& f = faces[k];
    const int n = std::max(1, static_cast<int>(std::floor(f.length() / step_m)));
    for (int i = 0; i < n; ++i) {
      const double t = (i + 0.5) / n;
      out.push_back({f.a + t * (f.b - f.a), f.normal, static_cast<int>(k)});
    }
  }
  return out;
}

namespace {

// The pseudo-inverse of a symmetric positive semi-definite matrix: its
// directions without weight (a corridor's length) stay without.
Eigen::Matrix3d PseudoInverse(const Eigen::Matrix3d& m) {
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> es(0.5 * (m + m.transpose()));
  const double top = std::max(es.eigenvalues()(2), 0.0);
  Eigen::Vector3d inv = Eigen::Vector3d::Zero();
  for (int i = 0; i < 3; ++i)
    if (top > 0.0 && es.eigenvalues()(i) > 1e-12 * top) inv(i) = 1.0 / es.eigenvalues()(i);
  return es.eigenvectors() * inv.asDiagonal() * es.eigenvectors().transpose();
}

// The information (inverse covariance) of the pose ICP found, from its
// matches at that pose. The estimate is x = H^-1 sum_i w_i J_i e_i; its
// errors are of two kinds.
// - Each sample's own noise, independent: variance s2 (the residuals', at
//   least min_sigma_m squared).
// - Each wall's place in its ASR, one error for all the samples along it:
//   its two ends each off by wall_end_sigma_m along its normal, so at the
//   middle of the samples matched on it an offset of variance sigma^2 / 2
//   and a tilt of variance 2 sigma^2 / L^2 (L its length), for the source's
//   wall and the target's alike. A matched pair of walls moves all its
//   samples together: its offset by a = sum w J, its tilt by
//   b = sum w J (t - t_mean), t along the target wall.
// Covariance C = H^-1 (s2 H + sum over pairs of var_offset a a^T +
// var_tilt b b^T) H^-1 (the sandwich; H = sum w J J^T); the information
// returned is C^+ = H M^+ H, singular where H is.
Eigen::Matrix3d PairedWallInformation(const std::vector<FacedSegment>& target, const std::vector<FacedSegment>& source,
                                      const std::vector<FacedPoint>& samples, const Pose2& T, double max_d,
                                      double cos_max, const FaceIndex& index, double s2,
                                      const RegistrationOptions& o) {
  struct Pair {
    int source = -1, target = -1;
    Eigen::Vector3d a = Eigen::Vector3d::Zero(), b = Eigen::Vector3d::Zero();  // sum w J, sum w J t
    double w = 0.0, wt = 0.0;                                                  // sum w, sum w t
  };
  std::vector<Pair> pairs;
  Eigen::Matrix3d H = Eigen::Matrix3d::Zero();
  const double c = std::cos(T.theta), s = std::sin(T.theta);
  for (const FacedPoint& fp : samples) {
    const Vec2 q = T * fp.p;
    const Vec2 n(c * fp.normal.x() - s * fp.normal.y(), s * fp.normal.x() + c * fp.normal.y());
    double e = 0.0, d = 0.0;
    const int k = index.Nearest(q, n, max_d, cos_max, &e, &d);
    if (k < 0) continue;
    const Vec2& nt = target[k].normal;
    const Vec2 dq(-(q.y() - T.y), q.x() - T.x);
    const Eigen::Vector3d J(nt.x(), nt.y(), nt.dot(dq));
    const double w = std::abs(e) <= o.huber_m ? 1.0 : o.huber_m / std::abs(e);
    H += w * J * J.transpose();
    const Vec2 along = target[k].b - target[k].a;
    const double len = along.norm();
    const double t = len > 0.0 ? (q - target[k].a).dot(along) / len : 0.0;
    auto it =
        std::find_if(pairs.begin(), pairs.end(), [&](const Pair& p) { return p.source == fp.face && p.target == k; });
    if (it == pairs.end()) {
      pairs.push_back({fp.face, k});
      it = pairs.end() - 1;
    }
    it->a += w * J;
    it->b += w * t * J;
    it->w += w;
    it->wt += w * t;
  }
  const double v = o.wall_end_sigma_m * o.wall_end_sigma_m;
  Eigen::Matrix3d M = s2 * H;
  for (const Pair& p : pairs) {
    const double ls = std::max(o.sample_step_m, source[p.source].length());
    const double lt = std::max(o.sample_step_m, target[p.target].length());
    const double var_offset = v;  // sigma^2 / 2 from each of the two walls
    const double var_tilt = 2.0 * v / (ls * ls) + 2.0 * v / (lt * lt);
    const Eigen::Vector3d b = p.b - (p.w > 0.0 ? p.wt / p.w : 0.0) * p.a;  // tilt about the samples' middle
    M += var_offset * p.a * p.a.transpose() + var_tilt * b * b.transpose();
  }
  return H * PseudoInverse(M) * H;
}

}  // namespace

Registration RegisterWalls(const std::vector<FacedSegment>& target, const std::vector<FacedSegment>& source,
                           const Pose2& initial, const RegistrationOptions& o, const Eigen::Matrix3d* prior) {
  Registration r;
  r.target_from_source = initial;
  const std::vector<FacedPoint> samples = SampleFaces(source, o.sample_step_m);
  r.samples = static_cast<int>(samples.size());
  if (target.empty() || samples.size() < static_cast<size_t>(o.min_matches)) return r;
  const double cos_max = std::cos(o.max_normal_angle_rad);
  // Every query is within the first iterations' radius: each reads one cell's
  // list of the faces within that radius of the cell (cells of the radius
  // itself: by callgrind on intel, RegisterWalls 607 M instructions with the
  // square of cells around each query, 412 M so; 449 M with cells of a
  // third of it, whose lists cost more to build).
  const double reach = std::max(o.max_correspondence_m, o.final_correspondence_m);
  const FaceIndex index(target, reach, reach);
  Pose2 T = initial;
  Eigen::Matrix3d H = Eigen::Matrix3d::Zero();
  double sum_w_e2 = 0.0, sum_w = 0.0;
  int matches = 0;
  std::vector<char> face_hit(target.size(), 0);
  // With a prior: its Cholesky factor L (prior = L L^T) whitens the pose.
  Eigen::Matrix3d L = Eigen::Matrix3d::Identity();
  if (prior) {
    Eigen::LLT<Eigen::Matrix3d> llt(0.5 * (*prior + prior->transpose()));
    if (llt.info() != Eigen::Success) prior = nullptr;
    else L = llt.matrixL();
  }
  // The data's information in the prior's whitened coordinates, and the
  // directions it determines (eigenvalue >= 1), at the last iteration.
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> whitened;
  // The residuals' variance inflated by the samples along correlation_length_m
  // (the older model's): what the iterations weigh the data by, and the
  // covariance without the walls' own errors (wall_end_sigma_m 0).
  const double inflate = std::max(1.0, o.correlation_length_m / o.sample_step_m);
  auto data_variance = [&](int m) {
    const double dof = std::max(1, m - 3);
    return std::max(o.min_sigma_m * o.min_sigma_m, sum_w_e2 / dof) * inflate;
  };
  // Iteration it's fraction of the run and its correspondence radius,
  // shrinking linearly from the first to the last.
  auto fraction = [&](int it) { return o.iterations > 1 ? static_cast<double>(it) / (o.iterations - 1) : 1.0; };
  auto radius = [&](int it) {
    return o.max_correspondence_m + fraction(it) * (o.final_correspondence_m - o.max_correspondence_m);
  };
  for (int it = 0; it < o.iterations; ++it) {
    const double frac = fraction(it);
    const double max_d = radius(it);
    const double c = std::cos(T.theta), s = std::sin(T.theta);
    H.setZero();
    Eigen::Vector3d g = Eigen::Vector3d::Zero();
    sum_w_e2 = sum_w = 0.0;
    matches = 0;
    std::fill(face_hit.begin(), face_hit.end(), 0);  // this iteration's matches only
    double farthest = 0.0;  // of this iteration's matches
    for (const FacedPoint& fp : samples) {
      const Vec2 q = T * fp.p;
      const Vec2 n(c * fp.normal.x() - s * fp.normal.y(), s * fp.normal.x() + c * fp.normal.y());
      double e = 0.0, d = 0.0;
      const int k = index.Nearest(q, n, max_d, cos_max, &e, &d);
      if (k < 0) continue;
      farthest = std::max(farthest, d);
      face_hit[k] = 1;
      const Vec2& nt = target[k].normal;
      const Vec2 dq(-(q.y() - T.y), q.x() - T.x);  // d(T p)/d theta
      const Eigen::Vector3d J(nt.x(), nt.y(), nt.dot(dq));
      const double w = std::abs(e) <= o.huber_m ? 1.0 : o.huber_m / std::abs(e);
      H += w * J * J.transpose();
      g += w * J * e;
      sum_w_e2 += w * e * e;
      sum_w += w;
      ++matches;
    }
    r.iterations = it + 1;
    if (matches < o.min_matches) {
      r.matches = matches;
      return r;
    }
    Eigen::Vector3d dx;
    if (prior) {
      // Gauss-Newton in the whitened coordinates u = L^-1 x, along the
      // eigenvectors the data determines better than the prior only.
      const double s2 = data_variance(matches);
      whitened.compute(L.transpose() * (H / s2) * L);
      const Eigen::Vector3d gu = L.transpose() * (g / s2);
      Eigen::Vector3d du = Eigen::Vector3d::Zero();
      for (int i = 0; i < 3; ++i) {
        const double lambda = whitened.eigenvalues()(i);
        if (lambda < 1.0) continue;
        const Eigen::Vector3d v = whitened.eigenvectors().col(i);
        du -= v * (v.dot(gu) / lambda);
      }
      dx = L * du;
    } else {
      // Levenberg damping keeps degenerate directions (a corridor) where they are.
      Eigen::Matrix3d A = H;
      for (int i = 0; i < 3; ++i) A(i, i) += 1e-6 + 1e-3 * H(i, i);
      dx = -A.ldlt().solve(g);
    }
    T = Pose2{T.x + dx(0), T.y + dx(1), NormalizeAngle(T.theta + dx(2))};
    const bool still = dx.head<2>().norm() < 1e-5 && std::abs(dx(2)) < 1e-6;
    if (still && frac >= 1.0) break;
    // Settled: the next iterations whose radius still exceeds the farthest
    // match shrink it without dropping a match (and a sample unmatched stays
    // so): the same matches at the same pose. The run goes on at the first
    // iteration whose radius drops a match, or at the last.
    if (still) {
      int next = it + 1;
      while (next < o.iterations - 1 && radius(next) > farthest) ++next;
      it = next - 1;
    }
  }
  r.target_from_source = T;
  r.matches = matches;
  r.faces_matched = static_cast<int>(std::count(face_hit.begin(), face_hit.end(), 1));
  r.match_fraction = r.samples > 0 ? static_cast<double>(matches) / r.samples : 0.0;
  r.rmse_m = sum_w > 0 ? std::sqrt(sum_w_e2 / sum_w) : 0.0;
  if (prior) {
    // The data's covariance along the directions it determines (information
    // at least the prior's); along the others as good as none: 10^4 times
    // the prior's. With the walls' own errors (wall_end_sigma_m > 0) the
    // information of the pose found, else the last iteration's (H / s2).
    if (o.wall_end_sigma_m > 0.0)
      whitened.compute(L.transpose() *
                       PairedWallInformation(target, source, samples, T, radius(r.iterations - 1), cos_max, index,
                                             data_variance(matches) / inflate, o) *
                       L);
    Eigen::Vector3d inv;
    for (int i = 0; i < 3; ++i) {
      const double lambda = whitened.eigenvalues()(i);
      const bool determined = lambda >= 1.0;
      r.degenerate_directions += determined ? 0 : 1;
      inv(i) = determined ? 1.0 / lambda : 1e4;
    }
    const Eigen::Matrix3d V = whitened.eigenvectors();
    r.covariance = L * V * inv.asDiagonal() * V.transpose() * L.transpose();
    r.converged = true;
    return r;
  }
  // Without a prior (a loop closure's search; its model of the walls'
  // errors is the older one, not changed with the registrations across
  // exits): sigma^2 H^-1, the residual variance inflated by the samples
  // along correlation_length_m. Pseudo-inverse on the eigen-decomposition:
  // a direction without information gets a large variance, not a NaN.
  const double s2 = data_variance(matches);
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> es(H);
  Eigen::Vector3d inv = Eigen::Vector3d::Zero();
  for (int i = 0; i < 3; ++i) inv(i) = es.eigenvalues()(i) > 1e-9 ? 1.0 / es.eigenvalues()(i) : 1e9;
  r.covariance = s2 * es.eigenvectors() * inv.asDiagonal() * es.eigenvectors().transpose();
  r.converged = true;
  return r;
}

Eigen::Matrix3d TurnedCovariance(const Eigen::Matrix3d& cov, double theta) {
  Eigen::Matrix3d R = Eigen::Matrix3d::Identity();
  R.topLeftCorner<2, 2>() = Eigen::Rotation2Dd(theta).toRotationMatrix();
  return R * cov * R.transpose();
}

Eigen::Matrix3d CovarianceInSourceFrame(const Registration& r) {
  // A move (dx, dy) of the target-frame translation is R(theta)^T (dx, dy)
  // along the source's axes; the heading is the same in both.
  return TurnedCovariance(r.covariance, -r.target_from_source.theta);
}

std::vector<int> AgreementOverShifts(const std::vector<FacedSegment>& target, const std::vector<FacedPoint>& points,
                                     const std::vector<double>& xs, const std::vector<double>& ys, double tolerance_m,
                                     double max_normal_angle_rad) {
  const size_t nx = xs.size(), ny = ys.size();
  std::vector<int> count(nx * ny, 0);
  if (nx == 0 || ny == 0) return count;
  std::vector<int> marked(nx * ny, -1);  // the last point that counted at each shift
  const double cos_max = std::cos(max_normal_angle_rad);
  // Indices of the axis values within [lo, hi].
  auto span = [](const std::vector<double>& axis, double lo, double hi) {
    const auto first = std::lower_bound(axis.begin(), axis.end(), lo);
    const auto last = std::upper_bound(first, axis.end(), hi);
    return std::pair<size_t, size_t>(first - axis.begin(), last - axis.begin());
  };
  for (size_t k = 0; k < points.size(); ++k) {
    const FacedPoint& q = points[k];
    for (const FacedSegment& f : target) {
      if (f.normal.dot(q.normal) < cos_max) continue;
      // Shifts that can bring the point within tolerance: the face's box
      // grown by it, less the point.
      const auto [i0, i1] = span(xs, std::min(f.a.x(), f.b.x()) - tolerance_m - q.p.x(),
                                 std::max(f.a.x(), f.b.x()) + tolerance_m - q.p.x());
      if (i0 >= i1) continue;
      const auto [j0, j1] = span(ys, std::min(f.a.y(), f.b.y()) - tolerance_m - q.p.y(),
                                 std::max(f.a.y(), f.b.y()) + tolerance_m - q.p.y());
      for (size_t i = i0; i < i1; ++i)
        for (size_t j = j0; j < j1; ++j) {
          const size_t c = i * ny + j;
          if (marked[c] == static_cast<int>(k)) continue;
          if (PointSegmentDistance(Vec2(q.p.x() + xs[i], q.p.y() + ys[j]), f.a, f.b) < tolerance_m) {
            marked[c] = static_cast<int>(k);
            ++count[c];
          }
        }
    }
  }
  return count;
}

double AgreementFraction(const std::vector<FacedSegment>& target, const std::vector<FacedPoint>& points,
                         double tolerance_m, double max_normal_angle_rad) {
  if (points.empty()) return 0.0;
  const double cos_max = std::cos(max_normal_angle_rad);
  const FaceIndex index(target, std::max(tolerance_m, 0.25));
  int ok = 0;
  for (const FacedPoint& p : points) {
    double e = 0.0;
    if (index.Nearest(p.p, p.normal, tolerance_m, cos_max, &e) >= 0) ++ok;
  }
  return static_cast<double>(ok) / points.size();
}

int PathWallCrossings(const std::vector<FacedSegment>& walls, const std::vector<Vec2>& path, double max_gap_m) {
  int n = 0;
  for (size_t i = 1; i < path.size(); ++i) {
    const Vec2 &p = path[i - 1], &q = path[i];
    if ((q - p).norm() > max_gap_m) continue;
    const double xmin = std::min(p.x(), q.x()), xmax = std::max(p.x(), q.x());
    const double ymin = std::min(p.y(), q.y()), ymax = std::max(p.y(), q.y());
    for (const FacedSegment& w : walls) {
      if (std::max(w.a.x(), w.b.x()) < xmin || std::min(w.a.x(), w.b.x()) > xmax ||
          std::max(w.a.y(), w.b.y()) < ymin || std::min(w.a.y(), w.b.y()) > ymax)
        continue;
      if (SegmentsCross(p, q, w.a, w.b)) ++n;
    }
  }
  return n;
}

}  // namespace cogmap::graph
