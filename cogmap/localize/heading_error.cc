#include "cogmap/localize/heading_error.h"

#include <algorithm>
#include <cmath>

#include "cogmap/core/angles.h"
#include "cogmap/localize/heading_corrector.h"

namespace cogmap::localize {
namespace {

double CircularMean(const std::vector<double>& a) {
  double c = 0.0, s = 0.0;
  for (double v : a) {
    c += std::cos(v);
    s += std::sin(v);
  }
  return (c == 0.0 && s == 0.0) ? 0.0 : std::atan2(s, c);
}

// Cumulative distance along the poses as a fraction of the total (index
// fraction when they do not move).
std::vector<double> DistanceFractions(const std::vector<Pose2>& poses) {
  const size_t n = poses.size();
  std::vector<double> f(n, 0.0);
  for (size_t i = 1; i < n; ++i) f[i] = f[i - 1] + (poses[i].translation() - poses[i - 1].translation()).norm();
  const double total = n ? f.back() : 0.0;
  for (size_t i = 0; i < n; ++i) f[i] = total > 1e-9 ? f[i] / total : (n > 1 ? double(i) / double(n - 1) : 0.5);
  return f;
}

// Index of the value of the sorted 'f' nearest to 'x'.
size_t Nearest(const std::vector<double>& f, double x) {
  const auto it = std::lower_bound(f.begin(), f.end(), x);
  if (it == f.begin()) return 0;
  if (it == f.end()) return f.size() - 1;
  const size_t j = static_cast<size_t>(it - f.begin());
  return (x - f[j - 1] <= f[j] - x) ? j - 1 : j;
}

// Whether path[n - m + k] and truth[k] (m = truth's length) are the same
// instants: the mapper samples the path only at records with truth once it
// has seen one, so a longer path has its extra poses first (a CARMEN log's
// odometry before its first laser record). Their steps then agree (the
// odometry's error aside): the summed step difference is within 10 % of the
// truth's way plus 5 cm. Paths of older stores, sampled without regard to
// the truth, do not.
bool PairsFromTheEnd(const std::vector<Pose2>& path, const std::vector<Pose2>& truth) {
  const size_t n = path.size(), m = truth.size();
  if (m == 0 || n < m) return false;
  double diff = 0.0, way = 0.0;
  for (size_t k = 1; k < m; ++k) {
    const double sp = (path[n - m + k].translation() - path[n - m + k - 1].translation()).norm();
    const double st = (truth[k].translation() - truth[k - 1].translation()).norm();
    diff += std::abs(sp - st);
    way += st;
  }
  return diff <= 0.1 * way + 0.05;
}

double Median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  const size_t n = v.size();
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

}  // namespace

HeadingErrorStats ComputeHeadingErrors(const std::vector<asr::Asr>& asrs,
                                       const std::map<int, std::vector<Pose2>>& corrected_paths) {
  HeadingErrorStats st;
  std::vector<double> raw, cor;
  for (const auto& a : asrs) {
    const size_t n = a.path.size(), nt = a.true_path.size();
    if (n == 0 || nt == 0) continue;
    const Pose2 correction = CorrectionOf(a);
    const auto placed = corrected_paths.find(a.id);
    const std::vector<Pose2>* path_placed =
        placed != corrected_paths.end() && placed->second.size() == n ? &placed->second : nullptr;
    std::vector<double> er, ec;
    auto add = [&](size_t k, const Pose2& t) {
      const Pose2& p = a.path[k];
      er.push_back(AngleDiff(p.theta, t.theta));
      ec.push_back(AngleDiff(path_placed ? (*path_placed)[k].theta : (correction * p).theta, t.theta));
    };
    if (n == nt) {
      for (size_t i = 0; i < n; ++i) add(i, a.true_path[i]);
    } else if (PairsFromTheEnd(a.path, a.true_path)) {
      // The leading poses without truth have no partner (as the trajectory
      // metrics pair them). By distance they paired with whatever truth was
      // nearest in way driven: during a turn on the spot (every CARMEN log
      // starts with some) a pose with one taken seconds later, 30-60 degrees
      // apart, and the first ASR's error read 2-7 degrees.
      for (size_t i = 0; i < nt; ++i) add(n - nt + i, a.true_path[i]);
    } else {
      // Different sampling (e.g. truth only on laser records): each pose of the
      // sparser sequence pairs with the pose of the denser one at the nearest
      // fraction of the distance driven through the ASR.
      const bool path_sparse = n < nt;
      const std::vector<Pose2>& sparse = path_sparse ? a.path : a.true_path;
      const std::vector<Pose2>& dense = path_sparse ? a.true_path : a.path;
      const std::vector<double> fs = DistanceFractions(sparse), fd = DistanceFractions(dense);
      for (size_t i = 0; i < sparse.size(); ++i) {
        const size_t j = Nearest(fd, fs[i]);
        if (path_sparse) add(i, dense[j]);
        else add(j, sparse[i]);
      }
    }
    AsrHeadingError e;
    e.asr_id = a.id;
    e.poses = static_cast<int>(n);
    e.raw_rad = CircularMean(er);
    e.corrected_rad = CircularMean(ec);
    st.per_asr.push_back(e);
    raw.push_back(e.raw_rad);
    cor.push_back(e.corrected_rad);
  }
  st.asrs = static_cast<int>(st.per_asr.size());
  if (st.asrs == 0) return st;
  st.global_rotation_raw_rad = CircularMean(raw);
  st.global_rotation_rad = CircularMean(cor);
  std::vector<double> abs_raw, abs_cor;
  for (auto& e : st.per_asr) {
    e.raw_rad = AngleDiff(e.raw_rad, st.global_rotation_raw_rad);
    e.corrected_rad = AngleDiff(e.corrected_rad, st.global_rotation_rad);
    abs_raw.push_back(RadToDeg(std::abs(e.raw_rad)));
    abs_cor.push_back(RadToDeg(std::abs(e.corrected_rad)));
  }
  st.median_deg = Median(abs_cor);
  st.max_deg = *std::max_element(abs_cor.begin(), abs_cor.end());
  st.median_raw_deg = Median(abs_raw);
  st.max_raw_deg = *std::max_element(abs_raw.begin(), abs_raw.end());
  // The drift: each ASR's raw error against the odometry's distance to the
  // middle of its path (every ASR's path counted, with truth or without, and
  // the way from one ASR's last pose to the next one's first: a path
  // sampled at a CARMEN log's laser records leaves a stretch between them).
  std::map<int, double> middle;
  double driven = 0.0;
  const Pose2* previous = nullptr;
  for (const auto& a : asrs) {
    if (a.path.empty()) continue;
    if (previous) driven += (a.path.front().translation() - previous->translation()).norm();
    double len = 0.0;
    for (size_t k = 1; k < a.path.size(); ++k) len += (a.path[k].translation() - a.path[k - 1].translation()).norm();
    middle[a.id] = driven + 0.5 * len;
    driven += len;
    previous = &a.path.back();
  }
  std::vector<double> xs, ys;
  double last = 0.0;
  for (const auto& e : st.per_asr) {
    // Unwrapped: each error within half a turn of the one before.
    const double y = xs.empty() ? e.raw_rad : last + AngleDiff(e.raw_rad, last);
    xs.push_back(middle[e.asr_id]);
    ys.push_back(y);
    last = y;
  }
  if (xs.size() >= 3) {
    double mx = 0.0, my = 0.0;
    for (size_t i = 0; i < xs.size(); ++i) mx += xs[i], my += ys[i];
    mx /= static_cast<double>(xs.size());
    my /= static_cast<double>(xs.size());
    double sxx = 0.0, sxy = 0.0;
    for (size_t i = 0; i < xs.size(); ++i) sxx += (xs[i] - mx) * (xs[i] - mx), sxy += (xs[i] - mx) * (ys[i] - my);
    if (sxx > 1e-9) {
      st.drift_asrs = static_cast<int>(xs.size());
      st.odometry_drift_rad_per_m = sxy / sxx;
    }
  }
  return st;
}

std::vector<std::pair<std::string, double>> HeadingErrorEvalKeys(const HeadingErrorStats& stats) {
  if (stats.asrs == 0) return {};
  std::vector<std::pair<std::string, double>> keys = {{"heading_error_deg_median", stats.median_deg},
                                                      {"heading_error_deg_max", stats.max_deg},
                                                      {"heading_error_deg_median_raw", stats.median_raw_deg},
                                                      {"heading_error_deg_max_raw", stats.max_raw_deg}};
  if (stats.drift_asrs >= 3) keys.emplace_back("odometry_drift_deg_per_m", RadToDeg(stats.odometry_drift_rad_per_m));
  return keys;
}

}  // namespace cogmap::localize
