#include "cogmap/localize/odometry_corrector.h"

#include <algorithm>
#include <cmath>

namespace cogmap::localize {
namespace {

// Wraps into (-pi/4, pi/4]: walls fix a heading modulo a quarter turn.
double WrapQuarter(double a) {
  double w = FoldToQuarterTurn(a);
  if (w == -kPi / 4.0) w = kPi / 4.0;
  return w;
}

}  // namespace

OdometryCorrector::OdometryCorrector(const DriftFilterOptions& options)
    : options_(options),
      p_ee_(options.heading_prior_sigma_rad * options.heading_prior_sigma_rad),
      p_rr_(options.rate_prior_sigma_rad_per_m * options.rate_prior_sigma_rad_per_m) {}

Pose2 OdometryCorrector::Correct(const Pose2& raw_odom, double time_s) {
  if (!last_raw_) {
    last_raw_ = raw_odom;
    corrected_ = raw_odom;
    samples_.push_back({time_s, distance_m_, applied_rad_, 0.0});
    return corrected_;
  }
  Pose2 inc = last_raw_->inverse() * raw_odom;
  const double ds = std::hypot(inc.x, inc.y);
  const double dth = options_.precorrect && std::isfinite(rate_) ? rate_ * ds : 0.0;
  // The heading change of the step shrinks by dth; the step's translation
  // (along the mid heading) turns by half of it.
  const Vec2 t = RotateAbout(inc.translation(), Vec2(0.0, 0.0), -0.5 * dth);
  inc = {t.x(), t.y(), inc.theta - dth};
  corrected_ = corrected_ * inc;
  applied_rad_ += dth;
  distance_m_ += ds;
  last_raw_ = raw_odom;
  samples_.push_back({time_s, distance_m_, applied_rad_, ds});
  return corrected_;
}

std::optional<OdometryCorrector::Window> OdometryCorrector::Average(double start_s, double end_s) const {
  double w = 0.0, s = 0.0, d = 0.0;
  double s_plain = 0.0, d_plain = 0.0;
  double lo = 0.0, hi = 0.0;
  int n = 0;
  for (const auto& x : samples_) {
    if (x.time_s < start_s || x.time_s > end_s) continue;
    lo = n == 0 ? x.distance_m : std::min(lo, x.distance_m);
    hi = n == 0 ? x.distance_m : std::max(hi, x.distance_m);
    w += x.step_m;
    s += x.step_m * x.distance_m;
    d += x.step_m * x.applied_rad;
    s_plain += x.distance_m;
    d_plain += x.applied_rad;
    ++n;
  }
  if (n == 0) return std::nullopt;
  if (w > 0.0) return Window{s / w, d / w, hi - lo};
  return Window{s_plain / n, d_plain / n, hi - lo};
}

void OdometryCorrector::Forget(double time_s) {
  while (!samples_.empty() && samples_.front().time_s < time_s) samples_.pop_front();
}

double OdometryCorrector::Predict(double distance_m) {
  const double ds = std::max(0.0, distance_m - filter_s_);
  if (steps_.empty()) {
    init_e_ = e_;
    init_r_ = rate_;
    init_ee_ = p_ee_;
    init_er_ = p_er_;
    init_rr_ = p_rr_;
  }
  const double qe = options_.heading_walk_rad_per_sqrt_m * options_.heading_walk_rad_per_sqrt_m;
  const double qr = options_.rate_walk_rad_per_m_per_sqrt_m * options_.rate_walk_rad_per_m_per_sqrt_m;
  e_ += rate_ * ds;
  p_ee_ += 2.0 * ds * p_er_ + ds * ds * p_rr_ + qe * ds;
  p_er_ += ds * p_rr_;
  p_rr_ += qr * ds;
  filter_s_ = std::max(filter_s_, distance_m);
  steps_.push_back({ds, false, 0.0, 0.0, e_, rate_, p_ee_, p_er_, p_rr_, e_, rate_, p_ee_, p_er_, p_rr_});
  return e_;
}

void OdometryCorrector::RecordFiltered() {
  if (steps_.empty()) return;
  Step& st = steps_.back();
  st.filt_e = e_;
  st.filt_r = rate_;
  st.filt_ee = p_ee_;
  st.filt_er = p_er_;
  st.filt_rr = p_rr_;
}

std::vector<double> OdometryCorrector::SmoothedHeadings(double* start_e) const { return Rts(steps_, start_e); }

std::vector<double> OdometryCorrector::RobustSmoothedHeadings(int iterations, double huber_k, double* start_e) const {
  std::vector<Step> steps = steps_;
  const size_t n = steps.size();
  std::vector<double> weight(n, 1.0);
  double scale2 = 1.0;  // variance factor of the measurements
  std::vector<double> smoothed = Rts(steps);
  const double qe = options_.heading_walk_rad_per_sqrt_m * options_.heading_walk_rad_per_sqrt_m;
  const double qr = options_.rate_walk_rad_per_m_per_sqrt_m * options_.rate_walk_rad_per_m_per_sqrt_m;
  for (int it = 0; it < iterations; ++it) {
    // Forward with the current variance factor and weights; the normalised
    // squared innovations (one-step predictions do not see their own
    // measurement) say whether the factor is right: their median is 0.455
    // (chi-square, 1 degree of freedom) when it is.
    double e = init_e_, rate = init_r_, pee = init_ee_, per = init_er_, prr = init_rr_;
    std::vector<double> t;
    for (size_t k = 0; k < n; ++k) {
      Step& st = steps[k];
      const double ds = st.ds;
      e += rate * ds;
      pee += 2.0 * ds * per + ds * ds * prr + qe * ds;
      per += ds * prr;
      prr += qr * ds;
      st.pred_e = e, st.pred_r = rate, st.pred_ee = pee, st.pred_er = per, st.pred_rr = prr;
      if (st.measured && st.sigma > 0.0) {
        const double rvar = scale2 * st.sigma * st.sigma / weight[k];
        const double sv = pee + rvar;
        const double nu = st.z - e;
        // Only once the rate is pinned (two measurements) is the prediction informative.
        if (k > 0 && t.size() + 1 < 1000 && pee < rvar * 4.0) t.push_back(nu * nu / sv);
        const double ke = pee / sv, kr = per / sv;
        e += ke * nu;
        rate += kr * nu;
        const double a = pee, b = per;
        pee = a - ke * a;
        per = b - ke * b;
        prr = prr - kr * b;
      }
      st.filt_e = e, st.filt_r = rate, st.filt_ee = pee, st.filt_er = per, st.filt_rr = prr;
    }
    smoothed = Rts(steps, start_e);
    if (t.size() >= 3) {
      std::nth_element(t.begin(), t.begin() + t.size() / 2, t.end());
      scale2 = std::clamp(scale2 * t[t.size() / 2] / 0.455, 0.01, 100.0);
    }
    // Huber weights from the residuals to the smoothed headings.
    for (size_t k = 0; k < n; ++k) {
      if (!steps[k].measured || steps[k].sigma <= 0.0) continue;
      const double r = std::abs(steps[k].z - smoothed[k]) / (steps[k].sigma * std::sqrt(scale2));
      weight[k] = r <= huber_k ? 1.0 : huber_k / r;
    }
  }
  return smoothed;
}

std::vector<double> OdometryCorrector::Rts(const std::vector<Step>& steps, double* start_e) const {
  const size_t n = steps.size();
  std::vector<double> out(n);
  if (start_e) *start_e = init_e_;
  if (n == 0) return out;
  // The initial state (distance 0) as a step before the first: its filtered
  // state is the prior.
  Step start{};
  start.filt_e = init_e_, start.filt_r = init_r_;
  start.filt_ee = init_ee_, start.filt_er = init_er_, start.filt_rr = init_rr_;
  double se = steps.back().filt_e, sr = steps.back().filt_r;
  out[n - 1] = se;
  for (size_t k = n; k-- > 0;) {
    const Step& a = k == 0 ? start : steps[k - 1];
    const Step& b = steps[k];
    // G = P_filt(k) F^T P_pred(k+1)^-1 with F = [[1, ds], [0, 1]].
    const double ds = b.ds;
    const double pf00 = a.filt_ee, pf01 = a.filt_er, pf11 = a.filt_rr;
    // P_filt F^T: [[pf00 + ds pf01, pf01], [pf01 + ds pf11, pf11]]
    const double m00 = pf00 + ds * pf01, m01 = pf01, m10 = pf01 + ds * pf11, m11 = pf11;
    const double det = b.pred_ee * b.pred_rr - b.pred_er * b.pred_er;
    double ge = 0.0, gr = 0.0;  // first row of G applied to the difference below
    const double de = se - b.pred_e, dr = sr - b.pred_r;
    if (std::abs(det) > 1e-300) {
      const double i00 = b.pred_rr / det, i01 = -b.pred_er / det, i11 = b.pred_ee / det;
      const double g00 = m00 * i00 + m01 * i01, g01 = m00 * i01 + m01 * i11;
      const double g10 = m10 * i00 + m11 * i01, g11 = m10 * i01 + m11 * i11;
      ge = g00 * de + g01 * dr;
      gr = g10 * de + g11 * dr;
    }
    se = a.filt_e + ge;
    sr = a.filt_r + gr;
    if (k > 0) out[k - 1] = se;
    else if (start_e) *start_e = se;
  }
  return out;
}

bool OdometryCorrector::Update(double z_rad, double sigma_rad) {
  if (!std::isfinite(z_rad) || !std::isfinite(sigma_rad)) return false;
  const double nu = WrapQuarter(z_rad - e_);
  const double r = sigma_scale_ * sigma_scale_ * sigma_rad * sigma_rad;
  const double s = p_ee_ + r;
  const double gate = std::max(options_.gate_min_rad, options_.gate_sigmas * std::sqrt(s));
  if (std::abs(nu) > gate) {
    ++rejects_;
    if (++consecutive_rejects_ >= options_.max_consecutive_rejects) {
      // Lost track: let the next measurements in again.
      // The rate may be what is wrong: widen it too (a third of its prior).
      const double wide = options_.heading_prior_sigma_rad * options_.heading_prior_sigma_rad;
      const double wide_rate = options_.rate_prior_sigma_rad_per_m * options_.rate_prior_sigma_rad_per_m / 9.0;
      p_ee_ = std::max(p_ee_, wide);
      p_rr_ = std::max(p_rr_, wide_rate);
      p_er_ = 0.0;
      consecutive_rejects_ = 0;
      RecordFiltered();
    }
    return false;
  }
  consecutive_rejects_ = 0;
  if (!steps_.empty()) {
    steps_.back().measured = true;
    steps_.back().z = e_ + nu;
    steps_.back().sigma = sigma_rad;
  }
  const double ke = p_ee_ / s, kr = p_er_ / s;
  e_ += ke * nu;
  rate_ += kr * nu;
  const double pee = p_ee_, per = p_er_;
  p_ee_ = pee - ke * pee;
  p_er_ = per - ke * per;
  p_rr_ = p_rr_ - kr * per;
  ++measurements_;
  RecordFiltered();
  return true;
}

void OdometryCorrector::Record(double z_rad, double sigma_rad) {
  if (steps_.empty()) return;
  steps_.back().measured = true;
  steps_.back().z = z_rad;
  steps_.back().sigma = sigma_rad;
}

void OdometryCorrector::Record(size_t step, double z_rad, double sigma_rad) {
  if (step >= steps_.size()) return;
  steps_[step].measured = true;
  steps_[step].z = z_rad;
  steps_[step].sigma = sigma_rad;
}

void OdometryCorrector::Drop(size_t step) {
  if (step < steps_.size()) steps_[step].measured = false;
}

double OdometryCorrector::Refilter() {
  const double qe = options_.heading_walk_rad_per_sqrt_m * options_.heading_walk_rad_per_sqrt_m;
  const double qr = options_.rate_walk_rad_per_m_per_sqrt_m * options_.rate_walk_rad_per_m_per_sqrt_m;
  if (steps_.empty()) return 0.0;
  double e = init_e_, rate = init_r_, pee = init_ee_, per = init_er_, prr = init_rr_;
  double log_likelihood = 0.0;
  measurements_ = 0;
  for (Step& st : steps_) {
    const double ds = st.ds;
    e += rate * ds;
    pee += 2.0 * ds * per + ds * ds * prr + qe * ds;
    per += ds * prr;
    prr += qr * ds;
    st.pred_e = e, st.pred_r = rate, st.pred_ee = pee, st.pred_er = per, st.pred_rr = prr;
    if (st.measured && st.sigma > 0.0) {
      const double sv = pee + sigma_scale_ * sigma_scale_ * st.sigma * st.sigma;
      const double nu = st.z - e;  // z is unwrapped already (Update, EndWarmup)
      log_likelihood -= 0.5 * (nu * nu / sv + std::log(2.0 * kPi * sv));
      const double ke = pee / sv, kr = per / sv;
      e += ke * nu;
      rate += kr * nu;
      const double a = pee, b = per;
      pee = a - ke * a;
      per = b - ke * b;
      prr = prr - kr * b;
      ++measurements_;
    }
    st.filt_e = e, st.filt_r = rate, st.filt_ee = pee, st.filt_er = per, st.filt_rr = prr;
  }
  e_ = e, rate_ = rate, p_ee_ = pee, p_er_ = per, p_rr_ = prr;
  consecutive_rejects_ = 0;
  return log_likelihood;
}

OdometryCorrector::NoiseFit OdometryCorrector::FitNoise(const std::vector<double>& walks_rad_per_sqrt_m,
                                                        const std::vector<double>& sigma_scales) {
  NoiseFit best{options_.heading_walk_rad_per_sqrt_m, sigma_scale_, -1e300};
  if (walks_rad_per_sqrt_m.empty() || sigma_scales.empty()) return best;
  for (double scale : sigma_scales)
    for (double walk : walks_rad_per_sqrt_m) {
      options_.heading_walk_rad_per_sqrt_m = walk;
      sigma_scale_ = scale;
      const double ll = Refilter();
      if (ll > best.log_likelihood) best = {walk, scale, ll};
    }
  options_.heading_walk_rad_per_sqrt_m = best.walk_rad_per_sqrt_m;
  sigma_scale_ = best.sigma_scale;
  Refilter();
  return best;
}

void OdometryCorrector::SetHeading(double e_rad, double sigma_rad) {
  e_ = e_rad;
  p_ee_ = sigma_rad * sigma_rad;
  p_er_ = 0.0;
  RecordFiltered();
}

double OdometryCorrector::heading_sigma_rad() const { return std::sqrt(std::max(0.0, p_ee_)); }
double OdometryCorrector::rate_sigma_rad_per_m() const { return std::sqrt(std::max(0.0, p_rr_)); }

DriftHeadingCorrector::DriftHeadingCorrector(const HeadingCorrectionOptions& heading,
                                             const DriftFilterOptions& drift)
    : estimator_(heading), heading_options_(heading), odometry_(drift), drift_options_(drift) {
  warming_ = drift.warmup_measurements > 0;
}

double DriftHeadingCorrector::WarmupRate() const {
  // Least-squares slope of the warm-up measurements, within 3 prior sigmas.
  const size_t n = warm_.size();
  if (n < 2) return 0.0;
  double ms = 0.0, mz = 0.0;
  for (const auto& w : warm_) ms += w.distance_m, mz += w.z_rad;
  ms /= double(n), mz /= double(n);
  double sxx = 0.0, sxz = 0.0;
  for (const auto& w : warm_) {
    sxx += (w.distance_m - ms) * (w.distance_m - ms);
    sxz += (w.distance_m - ms) * (w.z_rad - mz);
  }
  if (sxx < 1e-9) return 0.0;
  const double limit = 3.0 * drift_options_.rate_prior_sigma_rad_per_m;
  return std::clamp(sxz / sxx, -limit, limit);
}

void DriftHeadingCorrector::EndWarmup() {
  warming_ = false;
  const size_t n = warm_.size();
  if (n >= 2) {
    // Theil-Sen: the median of the pairwise slopes, then the median intercept.
    std::vector<double> slopes;
    for (size_t i = 0; i < n; ++i)
      for (size_t j = i + 1; j < n; ++j) {
        const double ds = warm_[j].distance_m - warm_[i].distance_m;
        if (ds > 1e-6) slopes.push_back((warm_[j].z_rad - warm_[i].z_rad) / ds);
      }
    if (!slopes.empty()) {
      std::nth_element(slopes.begin(), slopes.begin() + slopes.size() / 2, slopes.end());
      const double slope = slopes[slopes.size() / 2];
      // Residuals modulo a quarter turn: when declined ASRs leave a gap over
      // which the heading drifted more than 45 degrees, the accumulated z of
      // the later ones is a quarter turn off the earlier ones; the line (from
      // the slopes of the close pairs) puts them back.
      std::vector<double> r;
      for (const auto& w : warm_) r.push_back(w.z_rad - slope * w.distance_m);
      std::vector<double> sorted = r;
      std::nth_element(sorted.begin(), sorted.begin() + n / 2, sorted.end());
      const double r0 = sorted[n / 2];
      for (double& v : r) v = r0 + WrapQuarter(v - r0);
      sorted = r;
      std::nth_element(sorted.begin(), sorted.begin() + n / 2, sorted.end());
      const double intercept = sorted[n / 2];
      std::vector<double> dev;
      for (double v : r) dev.push_back(std::abs(v - intercept));
      std::vector<double> ds = dev;
      std::nth_element(ds.begin(), ds.begin() + n / 2, ds.end());
      const double band = std::max(drift_options_.warmup_min_band_rad, 3.0 * 1.4826 * ds[n / 2]);
      for (size_t i = 0; i < n; ++i) {
        if (dev[i] > band) {
          odometry_.Drop(warm_[i].step);
        } else {
          // Unwrapped to the quarter turn of the line (the filter's prior
          // prediction is too vague to tell a 46 degree step from -44).
          odometry_.Record(warm_[i].step, r[i] + slope * warm_[i].distance_m, warm_[i].sigma_rad);
        }
      }
    }
  }
  odometry_.Refilter();
  warm_.clear();
}

asr::Asr DriftHeadingCorrector::Close(asr::Asr pre) {
  last_ = estimator_.Estimate(pre);
  const auto window = odometry_.Average(pre.start_time_s, pre.end_time_s);
  const double s = window ? window->distance_m : odometry_.distance_m();
  const double applied = window ? window->applied_rad : odometry_.applied_rad();
  const double span = window ? window->span_m : 0.0;
  // The rate's uncertainty while this ASR was mapped (before this update).
  const double rate_sigma = odometry_.rate_sigma_rad_per_m();
  odometry_.Forget(pre.end_time_s);
  odometry_.Predict(s);
  distance_since_accepted_m_ += span;
  Pose2& c = world_corrected_from_pre_;
  double warm_angle = 0.0;  // warm-up: this ASR's own rotation (-drift)
  if (last_.accepted) {
    // The ASR's direction in the corrected frame before its own rotation.
    const double d = FoldToQuarterTurn(last_.direction_rad + c.theta);
    const double drift = reference_rad_ ? WrapQuarter(d - *reference_rad_) : 0.0;
    if (!reference_rad_) reference_rad_ = d;
    // Corrected heading = raw - applied + c.theta; the walls say it is off the
    // reference by 'drift', so the raw heading error is:
    const double z = applied - c.theta + drift;
    double sigma =
        std::max(drift_options_.measurement_sigma_floor_rad,
                 drift_options_.measurement_sigma_scale *
                     (std::isfinite(last_.uncertainty_rad) ? last_.uncertainty_rad : kPi / 4.0));
    if (drift_options_.smear_inflation) sigma = std::hypot(sigma, rate_sigma * span / std::sqrt(12.0));
    if (warming_) {
      // Walls fix the heading modulo a quarter turn. The drift above is the
      // branch nearest the last accepted ASR (no drift in between); once two
      // warm-up measurements give a provisional rate, the branch nearest the
      // heading that rate predicts is taken instead, so that a gap of declined
      // rooms over which the heading drifted more than 45 degrees is not read
      // as drift the other way.
      double pred = z;
      if (!warm_.empty()) {
        const WarmMeasurement& last = warm_.back();
        pred = last.z_rad + WarmupRate() * (s - last.distance_m);
      }
      const double z_unwrapped = pred + WrapQuarter(z - pred);
      const double innovation = warm_.empty() ? drift : z_unwrapped - pred;
      // HeadingCorrector's drift gate, then this ASR is rotated on its own.
      if (heading_options_.drift_gate &&
          std::abs(innovation) > heading_options_.max_drift_base_rad +
                                     heading_options_.max_drift_rad_per_m * distance_since_accepted_m_) {
        last_.accepted = false;
        last_.decline = Decline::kDriftOutlier;
      } else {
        odometry_.Record(z_unwrapped, sigma);
        warm_.push_back({odometry_.steps() - 1, s, z_unwrapped, sigma});
        warm_angle = -(drift + (z_unwrapped - z));
        distance_since_accepted_m_ = 0.0;
      }
    } else if (!odometry_.Update(z, sigma)) {
      last_.accepted = false;
      last_.decline = Decline::kDriftOutlier;
    }
  }
  if (warming_ && static_cast<int>(warm_.size()) >= drift_options_.warmup_measurements) EndWarmup();
  if (reference_rad_) {
    // Rotate so that corrected heading = raw - e: c.theta = applied - e
    // (warm-up: by this ASR's own drift).
    const double angle =
        warming_ ? warm_angle : NormalizeAngle(applied - odometry_.heading_rad() - c.theta);
    const Vec2 pivot = c * pre.entry_pivot_m;
    c = RotationAbout(pivot, angle) * c;
  }
  closed_.push_back({pre.id, applied, pre.entry_pivot_m, reference_rad_.has_value(), c});
  pre.world_from_local_corrected = c * pre.world_from_local_raw;
  pre.heading_correction_rad = c.theta;
  pre.heading_uncertainty_rad =
      last_.valid ? (std::isfinite(last_.uncertainty_rad) ? last_.uncertainty_rad : kPi / 4.0) : -1.0;
  return pre;
}

void DriftHeadingCorrector::Restore(const Pose2& correction, std::optional<double> reference_rad) {
  world_corrected_from_pre_ = correction;
  start_correction_ = correction;
  restored_ = true;
  reference_rad_ = reference_rad;
  if (reference_rad_) reference_rad_ = FoldToQuarterTurn(*reference_rad_);
  // No pre-correction applied yet on the resumed log: e = -c.theta keeps the
  // stored correction until the walls say otherwise.
  odometry_.SetHeading(odometry_.applied_rad() - correction.theta, drift_options_.measurement_sigma_floor_rad * 4.0);
}

std::vector<DriftHeadingCorrector::Revision> DriftHeadingCorrector::Smooth() {
  if (warming_) EndWarmup();  // a short run: the filter over what there is
  // The heading walk and measurement noise that best explain the run's
  // measurements (maximum likelihood of the innovations), before smoothing.
  if (odometry_.measurements() >= drift_options_.min_measurements_to_fit_noise)
    odometry_.FitNoise(drift_options_.walk_candidates_rad_per_sqrt_m, drift_options_.sigma_scale_candidates);
  double start_e = 0.0;
  std::vector<double> e = drift_options_.robust_smoothing
                              ? odometry_.RobustSmoothedHeadings(5, 2.0, &start_e)
                              : odometry_.SmoothedHeadings(&start_e);
  std::vector<Revision> out;
  if (e.size() != closed_.size()) return out;  // Predict once per Close
  // The filter's heading errors are relative to the reference walls (the first
  // accepted ASR), which carry that ASR's own drift. On a run mapped from its
  // start the raw odometry has no heading error at distance 0: the smoothed
  // error there is that offset, and removing it ties the corrected map to the
  // odometry's starting frame instead of to the drifted reference. The ASRs
  // closed before the reference existed are then rotated too.
  const bool anchor = !restored_ && odometry_.measurements() > 0;
  if (anchor)
    for (double& v : e) v -= start_e;
  Pose2 c = start_correction_;
  for (size_t k = 0; k < closed_.size(); ++k) {
    Closed& x = closed_[k];
    if (x.rotated || anchor) {
      const double angle = NormalizeAngle(x.applied_rad - e[k] - c.theta);
      c = RotationAbout(c * x.pivot_pre, angle) * c;
    }
    out.push_back({x.id, c * x.correction.inverse()});
    x.correction = c;
  }
  world_corrected_from_pre_ = c;
  return out;
}

Pose2 RawFromPrecorrected(const std::vector<Pose2>& pre, const std::vector<Pose2>& raw) {
  const size_t n = std::min(pre.size(), raw.size());
  if (n == 0) return {};
  double c = 0.0, s = 0.0;
  Vec2 cp(0.0, 0.0), cr(0.0, 0.0);
  for (size_t i = 0; i < n; ++i) {
    const double d = AngleDiff(raw[i].theta, pre[i].theta);
    c += std::cos(d);
    s += std::sin(d);
    cp += pre[i].translation();
    cr += raw[i].translation();
  }
  const double theta = (c == 0.0 && s == 0.0) ? 0.0 : std::atan2(s, c);
  cp /= double(n);
  cr /= double(n);
  const Vec2 t = cr - RotateAbout(cp, Vec2(0.0, 0.0), theta);
  return {t.x(), t.y(), theta};
}

}  // namespace cogmap::localize
