#include "cogmap/localize/em.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace cogmap::localize {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

double LogGauss(double x, double mu, double sigma2) {
  const double d = x - mu;
  return -0.5 * std::log(2.0 * kPi * sigma2) - d * d / (2.0 * sigma2);
}

// log(exp(a) + exp(b)), safe for -inf.
double LogAddExp(double a, double b) {
  if (a == -kInf) return b;
  if (b == -kInf) return a;
  const double hi = std::max(a, b), lo = std::min(a, b);
  return hi + std::log1p(std::exp(lo - hi));
}

double Mean(const std::vector<double>& x) {
  double s = 0.0;
  for (double v : x) s += v;
  return s / static_cast<double>(x.size());
}

// Var(X) of fig. A.6 (|X|-1 denominator); 0 for one value.
double Var(const std::vector<double>& x) {
  if (x.size() < 2) return 0.0;
  const double mu = Mean(x);
  double s = 0.0;
  for (double v : x) s += (v - mu) * (v - mu);
  return s / static_cast<double>(x.size() - 1);
}

// log I0(kappa), finite for any kappa >= 0.
double LogBesselI0(double kappa) {
  if (kappa < 500.0) return std::log(std::cyl_bessel_i(0.0, kappa));
  const double k = kappa;
  return k - 0.5 * std::log(2.0 * kPi * k) + std::log1p(1.0 / (8.0 * k) + 9.0 / (128.0 * k * k));
}

// A1(kappa) = I1(kappa) / I0(kappa): the mean resultant length of a von Mises.
double A1(double kappa) {
  if (kappa <= 0.0) return 0.0;
  if (kappa < 500.0) return std::cyl_bessel_i(1.0, kappa) / std::cyl_bessel_i(0.0, kappa);
  return 1.0 - 1.0 / (2.0 * kappa) - 1.0 / (8.0 * kappa * kappa);
}

// Inverse of A1 (Best and Fisher 1981; Fisher 1993, eq. 4.40).
double A1Inverse(double r) {
  if (r <= 0.0) return 0.0;
  if (r < 0.53) return 2.0 * r + r * r * r + 5.0 * std::pow(r, 5) / 6.0;
  if (r < 0.85) return -0.4 + 1.39 * r + 0.43 / (1.0 - r);
  if (r >= 1.0) return kInf;
  return 1.0 / (r * r * r - 4.0 * r * r + 3.0 * r);
}

// The concentration of a von Mises fitted to n samples, corrected for the
// maximum-likelihood estimate's upward bias in small samples (Best and Fisher
// 1981; Fisher 1993, eq. 4.41): two edges 4 degrees apart make A1Inverse
// read a spread of 4 degrees as the whole truth, and the mean's standard
// error below 1.5 degrees. n <= 1 cannot estimate a spread at all.
double KappaSmallSample(double kappa, double n) {
  if (!(n > 1.0)) return 0.0;
  if (kappa < 2.0) return std::max(kappa - 2.0 / (n * kappa), 0.0);
  return kappa * std::pow(n - 1.0, 3) / (n * n * n + n);
}

}  // namespace

const char* DeclineName(Decline d) {
  switch (d) {
    case Decline::kNone: return "accepted";
    case Decline::kNoWalls: return "no_walls";
    case Decline::kTooLittleWall: return "too_little_wall";
    case Decline::kTooFewEdges: return "too_few_edges";
    case Decline::kNotManhattan: return "not_manhattan";
    case Decline::kTooUncertain: return "too_uncertain";
    case Decline::kDriftOutlier: return "drift_outlier";
    case Decline::kGridDisagrees: return "grid_disagrees";
  }
  return "unknown";
}

PaperEmResult FitPaperEm(const std::vector<double>& s_raw, const std::vector<double>& m_raw,
                         const PaperEmOptions& options) {
  PaperEmResult r;
  // Non-finite values carry no direction.
  auto finite = [](const std::vector<double>& v) {
    std::vector<double> out;
    for (double a : v)
      if (std::isfinite(a)) out.push_back(a);
    return out;
  };
  const std::vector<double> s_in = finite(s_raw), m = finite(m_raw);
  const std::vector<double>& s = s_in;
  if (s.empty()) return r;
  const double floor2 = options.min_sigma_rad * options.min_sigma_rad;
  std::vector<double> x = s;
  x.insert(x.end(), m.begin(), m.end());
  const double n = static_cast<double>(x.size());

  GaussianComponent cs, cm;
  cs.mu = Mean(s);
  cs.sigma2 = std::max(Var(s), floor2);
  if (!m.empty()) {
    cm.mu = Mean(m);
    cm.sigma2 = std::max(Var(m), floor2);
    cs.pi = static_cast<double>(s.size()) / n;
    cm.pi = static_cast<double>(m.size()) / n;
  } else {
    cm.mu = cs.mu;
    cm.sigma2 = std::max({4.0 * Var(s), options.empty_m_sigma_rad * options.empty_m_sigma_rad, floor2});
    cs.pi = cm.pi = 0.5;
  }

  std::vector<double> qs(x.size());
  double sum_qs = 0.0;
  for (int it = 1; it <= options.max_iterations; ++it) {
    // E-step, eq. 3.13/3.14: <q_i^k> = pi_k p(x_i|phi_k) / sum_k pi_k p(x_i|phi_k).
    const double log_pi_s = cs.pi > 0.0 ? std::log(cs.pi) : -kInf;
    const double log_pi_m = cm.pi > 0.0 ? std::log(cm.pi) : -kInf;
    for (size_t i = 0; i < x.size(); ++i) {
      const double ls = log_pi_s + LogGauss(x[i], cs.mu, cs.sigma2);
      const double lm = log_pi_m + LogGauss(x[i], cm.mu, cm.sigma2);
      const double lz = LogAddExp(ls, lm);
      qs[i] = lz == -kInf ? 0.5 : std::exp(ls - lz);
    }
    // M-step, eq. 3.19-3.21.
    double sq_s = 0.0, sq_m = 0.0, sx_s = 0.0, sx_m = 0.0;
    for (size_t i = 0; i < x.size(); ++i) {
      sq_s += qs[i];
      sq_m += 1.0 - qs[i];
      sx_s += qs[i] * x[i];
      sx_m += (1.0 - qs[i]) * x[i];
    }
    GaussianComponent ns = cs, nm = cm;
    ns.pi = sq_s / n;
    nm.pi = sq_m / n;
    constexpr double kTiny = 1e-300;
    if (sq_s > kTiny) {  // a component that owns no data keeps its mean and variance
      ns.mu = sx_s / sq_s;
      double v = 0.0;
      for (size_t i = 0; i < x.size(); ++i) v += qs[i] * (x[i] - ns.mu) * (x[i] - ns.mu);
      ns.sigma2 = std::max(v / sq_s, floor2);
    }
    if (sq_m > kTiny) {
      nm.mu = sx_m / sq_m;
      double v = 0.0;
      for (size_t i = 0; i < x.size(); ++i) v += (1.0 - qs[i]) * (x[i] - nm.mu) * (x[i] - nm.mu);
      nm.sigma2 = std::max(v / sq_m, floor2);
    }
    const double error = std::abs(ns.mu - cs.mu) + std::abs(nm.mu - cm.mu);
    cs = ns;
    cm = nm;
    sum_qs = sq_s;
    r.iterations = it;
    if (error < options.epsilon_rad) {
      r.converged = true;
      break;
    }
  }
  r.valid = true;
  r.s = cs;
  r.m = cm;
  r.sum_q_s = sum_qs;
  return r;
}

DirectionEstimate EstimateDirectionPaper(const std::vector<WallDirection>& s,
                                         const std::vector<double>& m,
                                         const PaperEmOptions& options) {
  DirectionEstimate e;
  std::vector<double> sv;
  sv.reserve(s.size());
  for (const auto& w : s) {
    sv.push_back(w.folded_rad);
    e.total_length_m += w.length_m;
  }
  e.edges = static_cast<int>(s.size());
  const PaperEmResult r = FitPaperEm(sv, m, options);
  if (!r.valid) return e;
  e.valid = e.accepted = true;
  e.decline = Decline::kNone;
  // mu_s is a plain mean of folded values; fold again in case it left [-45, 45).
  e.direction_rad = FoldToQuarterTurn(r.s.mu);
  e.uncertainty_rad = std::sqrt(r.s.sigma2 / std::max(r.sum_q_s, 1.0));
  e.inlier_fraction = r.s.pi;
  e.effective_edges = r.sum_q_s;
  e.iterations = r.iterations;
  return e;
}

DirectionEstimate EstimateDirectionRobust(const std::vector<WallDirection>& s,
                                          const RobustEmOptions& options) {
  DirectionEstimate e;
  std::vector<double> phi, w;
  for (const auto& d : s) {
    const double weight = options.weight_by_length ? d.length_m : 1.0;
    if (!(weight > 0.0) || !std::isfinite(weight) || !std::isfinite(d.folded_rad)) continue;
    phi.push_back(NormalizeAngle(4.0 * d.folded_rad));
    w.push_back(weight);
    e.total_length_m += d.length_m;
  }
  e.edges = static_cast<int>(phi.size());
  if (phi.empty()) return e;
  const size_t n = phi.size();
  double wsum = 0.0;
  for (double v : w) wsum += v;

  // Start at the direction with the most weight nearby: a histogram of phi
  // (1 degree bins) smoothed by a circular Gaussian kernel, cost independent of
  // the number of edges. Deterministic, and inside the dominant cluster rather
  // than between clusters.
  const double ks = 4.0 * options.init_kernel_sigma_rad;
  const double kernel_kappa = 1.0 / std::max(ks * ks, 1e-12);
  constexpr int kBins = 360;
  constexpr double kBin = 2.0 * kPi / kBins;
  const int half = std::min(kBins / 2, static_cast<int>(std::ceil(3.0 * ks / kBin)));
  // hist[half + b] is bin b; the margins repeat the other end of the circle.
  std::vector<double> hist(kBins + 2 * half, 0.0);
  for (size_t i = 0; i < n; ++i) {
    const int b = std::clamp(static_cast<int>(std::floor((phi[i] + kPi) / kBin)), 0, kBins - 1);
    hist[half + b] += w[i];
  }
  for (int d = 0; d < half; ++d) {
    hist[d] = hist[kBins + d];                 // bins kBins-half .. kBins-1
    hist[half + kBins + d] = hist[half + d];   // bins 0 .. half-1
  }
  std::vector<double> kernel(half + 1);
  for (int d = 0; d <= half; ++d) kernel[d] = std::exp(-0.5 * (d * kBin) * (d * kBin) / (ks * ks));
  int best_bin = 0;
  double best = -1.0;
  std::vector<double> smooth(kBins);
  for (int b = 0; b < kBins; ++b) {
    const double* h = &hist[half + b];
    double dens = h[0] * kernel[0];
    for (int d = 1; d <= half; ++d) dens += (h[d] + h[-d]) * kernel[d];
    smooth[b] = dens;
    if (dens > best * (1.0 + 1e-12)) {
      best = dens;
      best_bin = b;
    }
  }
  double mu = -kPi + (best_bin + 0.5) * kBin;
  const double cap_s = 4.0 * options.min_edge_sigma_rad;
  const double kappa_max = 1.0 / std::max(cap_s * cap_s, 1e-12);
  double kappa = std::min(kernel_kappa, kappa_max);
  double pi_d = 1.0 - options.outlier_weight_init;
  const double log_uniform = -std::log(2.0 * kPi);

  std::vector<double> r(n);
  double resultant = 0.0;
  for (int it = 1; it <= options.max_iterations; ++it) {
    // E-step: responsibility of the von Mises (dominant) component.
    const double log_norm = -std::log(2.0 * kPi) - LogBesselI0(kappa);
    const double lpd = pi_d > 0.0 ? std::log(pi_d) : -kInf;
    const double lpo = pi_d < 1.0 ? std::log(1.0 - pi_d) : -kInf;
    for (size_t i = 0; i < n; ++i) {
      const double ld = lpd + log_norm + kappa * std::cos(phi[i] - mu);
      const double lo = lpo + log_uniform;
      const double lz = LogAddExp(ld, lo);
      r[i] = lz == -kInf ? 0.0 : std::exp(ld - lz);
    }
    // M-step (weighted): pi, circular mean, kappa from the mean resultant length.
    double sw = 0.0, sc = 0.0, ss = 0.0;
    for (size_t i = 0; i < n; ++i) {
      const double a = w[i] * r[i];
      sw += a;
      sc += a * std::cos(phi[i]);
      ss += a * std::sin(phi[i]);
    }
    pi_d = sw / wsum;
    double new_mu = mu;
    if (sw > 0.0) {
      resultant = std::hypot(sc, ss) / sw;
      if (resultant > 0.0) new_mu = std::atan2(ss, sc);
      kappa = std::min(A1Inverse(resultant), kappa_max);
    } else {
      resultant = 0.0;
      kappa = 0.0;
    }
    const double moved = std::abs(AngleDiff(new_mu, mu)) / 4.0;
    mu = new_mu;
    e.iterations = it;
    if (moved < options.epsilon_rad && it > 1) break;
  }

  // Kish effective number of inlier edges and the asymptotic standard error of
  // a von Mises mean direction, 1 / sqrt(n kappa A1(kappa)), divided by 4 to
  // go back from phi to theta; kappa corrected for the effective sample size
  // (small_sample_correction).
  double a1 = 0.0, a2 = 0.0;
  for (size_t i = 0; i < n; ++i) {
    a1 += w[i] * r[i];
    a2 += (w[i] * r[i]) * (w[i] * r[i]);
  }
  const double n_eff = a2 > 0.0 ? a1 * a1 / a2 : 0.0;
  const double kappa_se = options.small_sample_correction ? KappaSmallSample(kappa, n_eff) : kappa;
  const double info = n_eff * kappa_se * A1(kappa_se);
  const double info_asymptotic = n_eff * kappa * A1(kappa);
  e.uncertainty_asymptotic_rad = info_asymptotic > 0.0 ? 1.0 / (4.0 * std::sqrt(info_asymptotic)) : kInf;
  e.valid = true;
  e.direction_rad = FoldToQuarterTurn(mu / 4.0);
  e.uncertainty_rad = info > 0.0 ? 1.0 / (4.0 * std::sqrt(info)) : kInf;
  e.inlier_fraction = pi_d;
  e.concentration = kappa;
  e.effective_edges = n_eff;
  // Ambiguity: the highest other local maximum of the smoothed direction
  // histogram, farther than two kernel widths from its highest peak, over
  // that peak.
  {
    const int bmu = best_bin;
    const int sep = std::max(1, static_cast<int>(std::ceil(2.0 * ks / kBin)));
    double own = 0.0, other = 0.0;
    for (int b = 0; b < kBins; ++b) {
      int d = std::abs(b - bmu);
      d = std::min(d, kBins - d);
      const double v = smooth[b];
      if (d <= sep) {
        own = std::max(own, v);
      } else if (v >= smooth[(b + 1) % kBins] && v >= smooth[(b + kBins - 1) % kBins]) {
        other = std::max(other, v);
      }
    }
    e.ambiguity = own > 0.0 ? other / own : 1.0;
  }

  if (e.total_length_m < options.min_total_length_m) {
    e.decline = Decline::kTooLittleWall;
  } else if (e.edges < options.min_edges) {
    e.decline = Decline::kTooFewEdges;
  } else if (e.inlier_fraction < options.min_inlier_fraction || e.ambiguity > options.max_ambiguity) {
    e.decline = Decline::kNotManhattan;
  } else if (!(e.uncertainty_rad <= options.max_uncertainty_rad)) {
    e.decline = Decline::kTooUncertain;
  } else {
    e.decline = Decline::kNone;
    e.accepted = true;
  }
  return e;
}

}  // namespace cogmap::localize
