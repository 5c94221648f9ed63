#include "cogmap/vectorize/orientation.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <unordered_map>

namespace cogmap::vectorize {
namespace {

// Folds an angle into [-45, 45) degrees (orientation modulo a quarter turn).
double Fold(double a) {
  const double q = kPi / 2.0;
  double r = std::fmod(a + q / 2.0, q);
  if (r < 0) r += q;
  return r - q / 2.0;
}

// Sum of squares of the Gaussian-smoothed density of the projections of
// 'points' on 'normal': fine histogram (half a sigma per bin, linear
// interpolation), convolved with the Gaussian. The smoothing makes the score
// blind to the lattice of grid cell centres (whose projections line up at 0
// and 45 degrees whatever the walls do).
double ProfileScore(const std::vector<Vec2>& points, const Vec2& normal, double sigma) {
  if (points.empty()) return 0.0;
  constexpr int kBinsPerSigma = 4;
  const double bin = sigma / kBinsPerSigma;
  double lo = 1e300, hi = -1e300;
  std::vector<double> t(points.size());
  for (size_t i = 0; i < points.size(); ++i) {
    t[i] = points[i].dot(normal) / bin;
    lo = std::min(lo, t[i]);
    hi = std::max(hi, t[i]);
  }
  const int pad = 3 * kBinsPerSigma;  // 3 sigma
  lo -= pad;
  // Room for the kernel on both sides of the extreme points.
  const size_t n = static_cast<size_t>(std::floor(hi - lo)) + 2 * pad + 2;
  std::vector<double> h(n, 0.0);
  for (double v : t) {
    const double x = v - lo;
    const size_t b = static_cast<size_t>(x);
    const double f = x - static_cast<double>(b);
    h[b] += 1.0 - f;
    h[b + 1] += f;
  }
  static const std::vector<double> kernel = [] {
    std::vector<double> k(2 * pad + 1);
    for (int i = -pad; i <= pad; ++i) {
      const double u = static_cast<double>(i) / kBinsPerSigma;
      k[i + pad] = std::exp(-0.5 * u * u);
    }
    return k;
  }();
  // The smoothed density everywhere (its tails reach 'pad' bins beyond the
  // extreme points; clipping them would favour spread-out extremes):
  // v[b] = sum over i = -pad..pad, in that order, of kernel[i] h[b + i], h
  // being 0 outside [0, n). Eight bins at a time, each in its own lane of four
  // two-double vectors, every bin's sum still taken in tap order: the same
  // roundings as one bin after another, without one long chain of dependent
  // additions. The zero terms outside h add +0 to a sum that starts at +0 and
  // never goes negative, which changes nothing.
  std::vector<double> hp(n + 2 * pad + 8, 0.0);
  std::copy(h.begin(), h.end(), hp.begin() + pad);
  typedef double Pair __attribute__((vector_size(16)));
  auto load = [](const double* p) {
    Pair v;
    std::memcpy(&v, p, sizeof v);
    return v;
  };
  double s = 0.0;
  size_t b = 0;
  for (; b + 8 <= n; b += 8) {
    Pair a0 = {0.0, 0.0}, a1 = a0, a2 = a0, a3 = a0;  // bins b..b+1, b+2..b+3, ...
    for (int i = 0; i <= 2 * pad; ++i) {
      const Pair k = {kernel[i], kernel[i]};
      const double* src = hp.data() + b + i;
      a0 += k * load(src);
      a1 += k * load(src + 2);
      a2 += k * load(src + 4);
      a3 += k * load(src + 6);
    }
    for (const Pair& a : {a0, a1, a2, a3}) {
      s += a[0] * a[0];
      s += a[1] * a[1];
    }
  }
  for (; b < n; ++b) {
    double v = 0.0;
    for (int i = 0; i <= 2 * pad; ++i) v += kernel[i] * hp[b + i];
    s += v * v;
  }
  return s;
}

}  // namespace

double OrientationScore(const std::vector<Vec2>& points, double theta_rad, double bin_size) {
  const Vec2 n1(std::cos(theta_rad), std::sin(theta_rad));
  const Vec2 n2(-n1.y(), n1.x());
  return ProfileScore(points, n1, bin_size) + ProfileScore(points, n2, bin_size);
}

Orientation DominantOrientation(const std::vector<Vec2>& points, const OrientationOptions& options) {
  Orientation out;
  out.points = static_cast<int>(points.size());
  if (out.points < options.min_points || !(options.bin_size > 0.0)) return out;
  // Centre the points (keeps the projections small and well conditioned).
  Vec2 c(0.0, 0.0);
  for (const Vec2& p : points) c += p;
  c /= double(points.size());
  std::vector<Vec2> q;
  q.reserve(points.size());
  for (const Vec2& p : points) q.push_back(p - c);

  const double quarter = kPi / 2.0;
  const double fine = options.bin_size;
  const double coarse = fine * options.coarse_sigma_factor;
  auto score = [&](double theta, double sigma) { return OrientationScore(q, theta, sigma); };

  // 1. Coarse scan of the quarter turn with a wide kernel (a broad peak, so
  //    coarse steps do not miss it, and cheap: few bins).
  const int steps = std::max(8, static_cast<int>(std::lround(quarter / options.coarse_step_rad)));
  const double step = quarter / steps;
  int best = 0;
  double best_score = -1.0;
  for (int i = 0; i < steps; ++i) {
    const double v = score(-quarter / 2.0 + i * step, coarse);
    if (v > best_score) best_score = v, best = i;
  }
  // 2. Scan of [best - 2 steps, best + 2 steps] with the fine kernel. Long walls
  //    give narrow fine peaks (a fraction of a degree) that a scan can fall
  //    between, so the three highest local maxima of the scan are refined.
  const double centre = -quarter / 2.0 + best * step;
  // Two coarse steps either side: the wide kernel's peak can sit a step or
  // more from the fine one when clutter lies near the walls.
  const int per_step = std::max(2, static_cast<int>(std::ceil(step / options.fine_step_rad)));
  const double fstep = step / per_step;
  const int sub = 2 * per_step;
  std::vector<double> fs(2 * sub + 1);
  for (int k = -sub; k <= sub; ++k) fs[k + sub] = score(centre + k * fstep, fine);
  std::vector<int> maxima;
  for (int i = 0; i < static_cast<int>(fs.size()); ++i) {
    const bool left = i == 0 || fs[i] >= fs[i - 1];
    const bool right = i + 1 == static_cast<int>(fs.size()) || fs[i] >= fs[i + 1];
    if (left && right) maxima.push_back(i);
  }
  std::sort(maxima.begin(), maxima.end(), [&](int x, int y) { return fs[x] > fs[y]; });
  if (maxima.size() > 3) maxima.resize(3);
  // 3. Golden-section refinement of each in [t - fstep, t + fstep].
  const double g = (std::sqrt(5.0) - 1.0) / 2.0;
  double theta = centre, peak = -1.0;
  for (int i : maxima) {
    const double t = centre + (i - sub) * fstep;
    double a = t - fstep, b = t + fstep;
    double x1 = b - g * (b - a), x2 = a + g * (b - a);
    double f1 = score(x1, fine), f2 = score(x2, fine);
    while (b - a > options.tolerance_rad) {
      if (f1 < f2) {
        a = x1, x1 = x2, f1 = f2;
        x2 = a + g * (b - a);
        f2 = score(x2, fine);
      } else {
        b = x2, x2 = x1, f2 = f1;
        x1 = b - g * (b - a);
        f1 = score(x1, fine);
      }
    }
    const double tt = 0.5 * (a + b);
    double v = score(tt, fine);
    double best_t = tt;
    if (fs[i] > v) v = fs[i], best_t = t;
    if (v > peak) peak = v, theta = best_t;
  }
  // 4. Contrast: the peak over the median fine score at 8 angles spread over
  //    the rest of the quarter turn (10 degrees apart, none nearer the peak).
  std::vector<double> off;
  for (int k = 1; k <= 8; ++k) off.push_back(score(theta + k * quarter / 9.0, fine));
  std::nth_element(off.begin(), off.begin() + 4, off.end());
  const double median = 0.5 * (off[4] + *std::max_element(off.begin(), off.begin() + 4));
  out.valid = true;
  out.angle_rad = Fold(theta);
  out.contrast = median > 0.0 ? peak / median : 0.0;
  return out;
}

}  // namespace cogmap::vectorize
