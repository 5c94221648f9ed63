#include "cogmap/eval/trajectory_metrics.h"

#include <algorithm>
#include <cassert>
#include <cmath>

#include "cogmap/core/angles.h"

namespace cogmap::eval {
namespace {

double Median(std::vector<double> v) {
  if (v.empty()) return 0.0;
  std::sort(v.begin(), v.end());
  const size_t n = v.size();
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

// "1", "5", "20", "2.5": the distance as it appears in a key.
std::string DistanceName(double d) {
  std::string s = std::to_string(d);
  s.erase(s.find_last_not_of('0') + 1);
  if (!s.empty() && s.back() == '.') s.pop_back();
  return s;
}

}  // namespace

Pose2 AlignPositions(const std::vector<Pose2>& from, const std::vector<Pose2>& to) {
  assert(from.size() == to.size());
  const size_t n = std::min(from.size(), to.size());
  std::vector<Vec2> a(n), b(n);
  for (size_t i = 0; i < n; ++i) a[i] = from[i].translation(), b[i] = to[i].translation();
  return AlignPoints(a, b);
}

AteStats AbsoluteTrajectoryError(const std::vector<Pose2>& estimate, const std::vector<Pose2>& reference) {
  assert(estimate.size() == reference.size());
  AteStats st;
  const size_t n = std::min(estimate.size(), reference.size());
  if (n == 0) return st;
  st.reference_from_estimate = AlignPositions(estimate, reference);
  std::vector<double> e(n);
  double sum = 0.0, sum_sq = 0.0;
  for (size_t i = 0; i < n; ++i) {
    e[i] = (st.reference_from_estimate * estimate[i].translation() - reference[i].translation()).norm();
    sum += e[i];
    sum_sq += e[i] * e[i];
    st.max_m = std::max(st.max_m, e[i]);
  }
  st.poses = static_cast<int>(n);
  st.rmse_m = std::sqrt(sum_sq / n);
  st.mean_m = sum / n;
  st.median_m = Median(std::move(e));
  return st;
}

std::optional<RpeStats> RelativePoseError(const std::vector<Pose2>& estimate, const std::vector<Pose2>& reference,
                                          double distance_m) {
  assert(estimate.size() == reference.size());
  const size_t n = std::min(estimate.size(), reference.size());
  // Reference path length from the first pose.
  std::vector<double> s(n, 0.0);
  for (size_t k = 1; k < n; ++k) s[k] = s[k - 1] + (reference[k].translation() - reference[k - 1].translation()).norm();
  // Sums of 0.1 m steps are not exactly 1.0: a pair counts from a hair below d.
  const double reach = distance_m - 1e-9 * std::max(1.0, distance_m);
  RpeStats st;
  st.distance_m = distance_m;
  double t_sum = 0.0, t_sq = 0.0, r_sum = 0.0, r_sq = 0.0;
  size_t j = 1;
  for (size_t i = 0; i + 1 < n; ++i) {
    j = std::max(j, i + 1);
    while (j < n && s[j] - s[i] < reach) ++j;
    if (j >= n) break;  // no later i finds a pair either
    const Pose2 est_rel = estimate[i].inverse() * estimate[j];
    const Pose2 ref_rel = reference[i].inverse() * reference[j];
    const Pose2 err = ref_rel.inverse() * est_rel;
    const double t = err.translation().norm();
    const double r = std::abs(RadToDeg(NormalizeAngle(err.theta)));
    t_sum += t, t_sq += t * t, r_sum += r, r_sq += r * r;
    ++st.pairs;
  }
  if (st.pairs == 0) return std::nullopt;
  st.trans_rmse_m = std::sqrt(t_sq / st.pairs);
  st.trans_mean_m = t_sum / st.pairs;
  st.rot_rmse_deg = std::sqrt(r_sq / st.pairs);
  st.rot_mean_deg = r_sum / st.pairs;
  return st;
}

AsrTrajectories PairAsrTrajectories(const std::vector<asr::Asr>& asrs,
                                    const std::map<int, std::vector<Pose2>>& corrected_paths) {
  AsrTrajectories t;
  for (const auto& a : asrs) {
    const size_t n = a.path.size(), nt = a.true_path.size();
    const size_t m = std::min(n, nt);
    if (m == 0) continue;
    const auto placed = corrected_paths.find(a.id);
    const std::vector<Pose2> corrected = placed != corrected_paths.end() && placed->second.size() == n
                                             ? placed->second
                                             : asr::CorrectedPath(a, 0.0);
    // Paired from the ends: the leading extra poses have no partner.
    for (size_t k = 0; k < m; ++k) {
      const Pose2& p = a.path[n - m + k];
      t.raw.push_back(p);
      t.corrected.push_back(corrected[n - m + k]);
      t.reference.push_back(a.true_path[nt - m + k]);
    }
    t.unpaired_poses += static_cast<int>(n - m);
    ++t.asrs;
  }
  return t;
}

const std::vector<double>& TrajectoryDistances() {
  static const std::vector<double> d = {1.0, 5.0, 20.0};
  return d;
}

TrajectoryMetrics ComputeTrajectoryMetrics(const AsrTrajectories& t) {
  TrajectoryMetrics m;
  m.ate = AbsoluteTrajectoryError(t.corrected, t.reference);
  m.ate_raw = AbsoluteTrajectoryError(t.raw, t.reference);
  for (double d : TrajectoryDistances()) {
    m.rpe.push_back(RelativePoseError(t.corrected, t.reference, d));
    m.rpe_raw.push_back(RelativePoseError(t.raw, t.reference, d));
  }
  return m;
}

std::vector<std::pair<std::string, std::optional<double>>> TrajectoryEvalKeys(const TrajectoryMetrics& m) {
  std::vector<std::pair<std::string, std::optional<double>>> keys;
  keys.emplace_back("trajectory_poses", static_cast<double>(m.ate.poses));
  for (const bool raw : {false, true}) {
    const std::string sfx = raw ? "_raw" : "";
    const AteStats& a = raw ? m.ate_raw : m.ate;
    const bool has = a.poses > 0;
    keys.emplace_back("ate_rmse_m" + sfx, has ? std::optional(a.rmse_m) : std::nullopt);
    keys.emplace_back("ate_mean_m" + sfx, has ? std::optional(a.mean_m) : std::nullopt);
    keys.emplace_back("ate_median_m" + sfx, has ? std::optional(a.median_m) : std::nullopt);
    keys.emplace_back("ate_max_m" + sfx, has ? std::optional(a.max_m) : std::nullopt);
    const auto& rpe = raw ? m.rpe_raw : m.rpe;
    for (size_t k = 0; k < rpe.size() && k < TrajectoryDistances().size(); ++k) {
      const std::string p = "rpe_" + DistanceName(TrajectoryDistances()[k]) + "m_";
      const auto& r = rpe[k];
      keys.emplace_back(p + "trans_m" + sfx, r ? std::optional(r->trans_rmse_m) : std::nullopt);
      keys.emplace_back(p + "rot_deg" + sfx, r ? std::optional(r->rot_rmse_deg) : std::nullopt);
      keys.emplace_back(p + "trans_mean_m" + sfx, r ? std::optional(r->trans_mean_m) : std::nullopt);
      keys.emplace_back(p + "rot_mean_deg" + sfx, r ? std::optional(r->rot_mean_deg) : std::nullopt);
    }
  }
  return keys;
}

int PoseCalibration::within() const {
  return static_cast<int>(std::count_if(items.begin(), items.end(), [](const auto& i) { return i.within(); }));
}
int PoseCalibration::position_within() const {
  return static_cast<int>(std::count_if(items.begin(), items.end(), [](const auto& i) { return i.position_within; }));
}
int PoseCalibration::heading_within() const {
  return static_cast<int>(std::count_if(items.begin(), items.end(), [](const auto& i) { return i.heading_within; }));
}

std::optional<Pose2> TruthFromRaw(const asr::Asr& a) {
  const size_t n = a.path.size(), nt = a.true_path.size(), m = std::min(n, nt);
  if (m == 0) return std::nullopt;
  return a.true_path[nt - m] * a.path[n - m].inverse();
}

PoseCalibration ComputePoseCalibration(const std::vector<asr::Asr>& asrs,
                                       const std::map<int, Eigen::Matrix3d>& covariances, double k_sigma) {
  PoseCalibration c;
  c.k_sigma = k_sigma;
  // The true frame pose from the first paired path pose.
  auto true_frame = [](const asr::Asr& a) -> std::optional<Pose2> {
    const std::optional<Pose2> t = TruthFromRaw(a);
    if (!t) return std::nullopt;
    return *t * a.world_from_local_raw;
  };
  std::optional<Pose2> truth_to_map;  // maps the truth's world onto the map's
  for (const auto& a : asrs) {
    const std::optional<Pose2> t = true_frame(a);
    if (!t) continue;
    if (!truth_to_map) {
      truth_to_map = a.world_from_local_corrected * t->inverse();
      c.reference_asr = a.id;
    }
    const auto cov = covariances.find(a.id);
    if (cov == covariances.end()) continue;
    const Eigen::Matrix3d& s = cov->second;
    const double var_xy = s(0, 0) + s(1, 1), var_theta = s(2, 2);
    if (!std::isfinite(var_xy) || !std::isfinite(var_theta) || var_xy <= 0.0 || var_theta < 0.0 || s(0, 0) < 0.0 ||
        s(1, 1) < 0.0)
      continue;  // not placed (zero), or not a covariance
    const Pose2 truth = *truth_to_map * *t;
    PoseCalibrationItem it;
    it.asr_id = a.id;
    it.position_error_m = (a.world_from_local_corrected.translation() - truth.translation()).norm();
    it.heading_error_rad = NormalizeAngle(a.world_from_local_corrected.theta - truth.theta);
    it.sigma_position_m = std::sqrt(var_xy);
    it.sigma_heading_rad = std::sqrt(var_theta);
    it.position_within = it.position_error_m <= k_sigma * it.sigma_position_m;
    it.heading_within = std::abs(it.heading_error_rad) <= k_sigma * it.sigma_heading_rad;
    c.items.push_back(it);
  }
  return c;
}

std::vector<std::pair<std::string, std::optional<double>>> PoseCalibrationEvalKeys(const PoseCalibration& c) {
  const std::string k = DistanceName(c.k_sigma) + "sigma";
  const int n = c.checked();
  auto share = [n](int count) { return n > 0 ? std::optional(static_cast<double>(count) / n) : std::nullopt; };
  return {{"pose_calibration_" + k, share(c.within())},
          {"pose_calibration_position_" + k, share(c.position_within())},
          {"pose_calibration_heading_" + k, share(c.heading_within())},
          {"pose_calibration_asrs", static_cast<double>(n)}};
}

}  // namespace cogmap::eval
