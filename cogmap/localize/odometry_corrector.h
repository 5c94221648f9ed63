#pragma once
#include <deque>
#include <optional>
#include <vector>

#include "cogmap/asr/asr.h"
#include "cogmap/core/pose2.h"
#include "cogmap/localize/heading_corrector.h"

namespace cogmap::localize {

// Drift-rate estimation with odometry pre-correction (default mode; not in
// the thesis, which corrects one rotation per ASR: docs/heading-correction.md).
//
// Odometry heading drift is mostly systematic: so many degrees per metre
// driven. A Kalman filter tracks the heading error of the raw odometry
// e(s) = raw heading - true heading (up to one constant) as a function of the
// distance s driven, with state [e, rate]: e(s + ds) = e(s) + rate ds + a
// random walk. Each ASR whose walls give an accepted EM estimate is one
// measurement of e at the ASR's mean distance. Between ASRs the rate is used
// to correct the odometry as it comes in (heading -= rate x ds, position
// re-integrated with the corrected heading), so the next ASR's grid is built
// from odometry that drifts only by the residual rate: its walls stay sharp.
struct DriftFilterOptions {
  // Prior 1-sigma of the drift rate (rad per metre), mean 0.
  double rate_prior_sigma_rad_per_m = DegToRad(3.0);
  // Prior 1-sigma of the heading error before the first measurement.
  double heading_prior_sigma_rad = DegToRad(10.0);
  // Random walk of the heading error (odometry noise): rad per sqrt(metre).
  // 0.6, not the simulator's 0.17: the true heading error of simulated sonar
  // runs wanders by several degrees over tens of metres (hundreds of radians of
  // turning), and a stiffer model bends the ASRs between measurements.
  double heading_walk_rad_per_sqrt_m = DegToRad(0.6);
  // At the end of a run (DriftHeadingCorrector::Smooth), before smoothing,
  // the heading walk and a factor on every measurement sigma are chosen again,
  // jointly, among these candidates by maximum likelihood of the filter's
  // innovations (OdometryCorrector::FitNoise), when the run has at least
  // min_measurements_to_fit_noise measurements. How much the odometry wanders
  // and how good the walls are differ by robot and sensor: a fixed walk of 0.6
  // suits simulated sonar, 0.3 the CARMEN logs with added drift (docs).
  // Empty candidates: keep the values above.
  std::vector<double> walk_candidates_rad_per_sqrt_m = {DegToRad(0.15), DegToRad(0.3), DegToRad(0.45),
                                                        DegToRad(0.6),  DegToRad(0.9), DegToRad(1.2)};
  std::vector<double> sigma_scale_candidates = {0.35, 0.5, 0.7, 1.0, 1.4, 2.0};
  int min_measurements_to_fit_noise = 15;
  // Random walk of the rate (drift that changes along the run): rad/m per sqrt(m).
  double rate_walk_rad_per_m_per_sqrt_m = DegToRad(0.01);
  // Measurement 1-sigma of one ASR's estimate = max(floor, scale x the EM
  // uncertainty): the EM uncertainty is an asymptotic standard error and is
  // optimistic on sonar walls.
  double measurement_sigma_scale = 2.0;
  double measurement_sigma_floor_rad = DegToRad(0.5);
  // The walls of an ASR mapped while the rate is still uncertain are smeared:
  // the residual heading changes by (rate error) x (distance) across it. Its
  // measurement sigma grows by rate_sigma x span / sqrt(12) (a uniform spread
  // over the span), so the first, smeared ASRs count little once later ones
  // pin the rate (the smoother then extrapolates the line back to them).
  bool smear_inflation = false;  // off: on simulated sonar runs it did not help (docs)
  // Innovation gate: a measurement farther than max(gate_min, gate_sigmas x
  // sqrt(innovation variance)) from the prediction is a gross error (clutter
  // taken for walls) and is not used. After max_consecutive_rejects rejections
  // in a row the heading variance is widened, so a filter that lost track
  // re-locks instead of rejecting for ever.
  double gate_sigmas = 4.0;
  double gate_min_rad = DegToRad(3.0);
  int max_consecutive_rejects = 3;
  // Warm-up: until this many ASRs have accepted estimates, the filter is not
  // trusted (one confident but wrong estimate would set a wrong rate, and the
  // pre-correction would then smear the next ASRs and slip a quarter turn):
  // each ASR is corrected on its own as HeadingCorrector does (with its drift
  // gate), and its measurement is kept. Then a Theil-Sen line through them (the
  // median of pairwise slopes) picks the inliers (within max(3 robust sigmas,
  // warmup_min_band_rad) of it), the filter is run over those, and
  // pre-correction starts.
  int warmup_measurements = 4;
  double warmup_min_band_rad = DegToRad(5.0);
  // DriftHeadingCorrector::Smooth: RobustSmoothedHeadings (true) or the plain
  // RTS smoother.
  bool robust_smoothing = false;  // off: no gain on the simulated sonar runs (docs)
  // Pre-correct odometry with the estimated rate (false: estimate only).
  bool precorrect = true;
};

// The Kalman filter on [e, rate] and the odometry pre-correction.
class OdometryCorrector {
 public:
  explicit OdometryCorrector(const DriftFilterOptions& options = {});

  // The pre-corrected pose of a raw odometry pose (raw world frame; call in
  // time order, one call per record). The first call returns its input; every
  // later pose follows from the previous corrected pose by the raw odometry
  // increment with its heading change reduced by rate x distance.
  Pose2 Correct(const Pose2& raw_odom, double time_s);

  // Mean distance driven and mean accumulated pre-correction D = raw heading -
  // corrected heading (radians, unwrapped) over the records with time in
  // [start_s, end_s], weighted by the distance of each step. nullopt when no
  // record falls in the window.
  struct Window {
    double distance_m = 0.0;  // mean distance driven since the start
    double applied_rad = 0.0; // mean D
    double span_m = 0.0;      // distance driven from the first record to the last
  };
  std::optional<Window> Average(double start_s, double end_s) const;
  // Forgets records older than 'time_s' (the window of the next ASR starts later).
  void Forget(double time_s);

  // Kalman filter. Predict to distance s; returns the predicted e(s).
  double Predict(double distance_m);
  // Measurement z of e at the distance of the last Predict, 1-sigma sigma_rad.
  // z is first unwrapped to the quarter turn nearest the prediction (walls fix
  // the heading modulo 90 degrees). Returns false when the innovation gate
  // rejects it.
  bool Update(double z_rad, double sigma_rad);
  // Sets the heading error state (a resumed run): mean, 1-sigma; rate untouched.
  void SetHeading(double e_rad, double sigma_rad);
  // Stores a measurement at the last Predict without updating the filter
  // (warm-up); Refilter uses it unless Drop(step) is called for it.
  void Record(double z_rad, double sigma_rad);
  // The same for an earlier step (its measurement replaced).
  void Record(size_t step, double z_rad, double sigma_rad);
  void Drop(size_t step);
  // Runs the filter again from its initial state over all the kept
  // measurements (no gate, no quarter-turn unwrapping: they must be unwrapped
  // already) and continues from the result. Returns the log-likelihood of the
  // measurements (sum over the innovations of log N(nu; 0, S)).
  double Refilter();
  // Refilters with each pair (heading walk, factor on every measurement
  // sigma) and keeps the most likely (returned; in force from then on).
  struct NoiseFit {
    double walk_rad_per_sqrt_m = 0.0;
    double sigma_scale = 1.0;
    double log_likelihood = 0.0;
  };
  NoiseFit FitNoise(const std::vector<double>& walks_rad_per_sqrt_m, const std::vector<double>& sigma_scales);
  double heading_walk_rad_per_sqrt_m() const { return options_.heading_walk_rad_per_sqrt_m; }
  double sigma_scale() const { return sigma_scale_; }
  size_t steps() const { return steps_.size(); }
  // Rauch-Tung-Striebel smoothing of the steps so far: the heading error e at
  // the distance of every Predict call, in order, given all the measurements
  // (earlier ones included: the rate learnt later corrects the first ASRs).
  // 'start_e' (optional) receives the smoothed heading error at distance 0, the
  // start of the run.
  std::vector<double> SmoothedHeadings(double* start_e = nullptr) const;
  // The same, robust (batch, not in the thesis): the forward filter is re-run
  // over the stored measurements that passed the gate, with their variances
  // rescaled by one factor estimated from the residuals (the EM uncertainty is
  // a poor absolute scale: too large on whole rooms, too small on short
  // stretches of sonar wall) and down-weighted beyond 'huber_k' robust sigmas
  // (Huber), iterated 'iterations' times.
  std::vector<double> RobustSmoothedHeadings(int iterations = 5, double huber_k = 2.0,
                                             double* start_e = nullptr) const;

  double heading_rad() const { return e_; }
  double rate_rad_per_m() const { return rate_; }
  double heading_sigma_rad() const;
  double rate_sigma_rad_per_m() const;
  double distance_m() const { return distance_m_; }
  // Raw heading - corrected heading of the last Correct (unwrapped).
  double applied_rad() const { return applied_rad_; }
  int measurements() const { return measurements_; }
  int rejects() const { return rejects_; }

 private:
  struct Sample {
    double time_s, distance_m, applied_rad, step_m;
  };
  DriftFilterOptions options_;
  // Odometry.
  std::optional<Pose2> last_raw_;
  Pose2 corrected_;
  double distance_m_ = 0.0;
  double applied_rad_ = 0.0;
  std::deque<Sample> samples_;
  // One entry per Predict: the state after it (pred) and after the update (filt).
  struct Step {
    double ds;
    bool measured = false;      // an update was applied at this step
    double z = 0.0, sigma = 0.0;  // the measurement (unwrapped) and its 1-sigma
    double pred_e, pred_r, pred_ee, pred_er, pred_rr;
    double filt_e, filt_r, filt_ee, filt_er, filt_rr;
  };
  std::vector<Step> steps_;
  double init_e_ = 0.0, init_r_ = 0.0, init_ee_ = 0.0, init_er_ = 0.0, init_rr_ = 0.0;
  void RecordFiltered();
  std::vector<double> Rts(const std::vector<Step>& steps, double* start_e = nullptr) const;
  // Filter.
  double filter_s_ = 0.0;
  double e_ = 0.0, rate_ = 0.0;
  double p_ee_, p_er_ = 0.0, p_rr_;
  int measurements_ = 0;
  double sigma_scale_ = 1.0;  // factor on every measurement sigma in Refilter (FitNoise)
  int rejects_ = 0;
  int consecutive_rejects_ = 0;
};

// Heading correction with drift-rate estimation (default mode): the EM of
// HeadingCorrector on each ASR's walls, fused with the drift model. Feed every
// raw odometry pose through CorrectOdometry and build the ASRs from the poses
// it returns ("pre-corrected"), then Close each ASR (all its fields in that
// pre-corrected frame) as it closes. Close measures the ASR's dominant wall
// direction against the reference (the first accepted ASR, as HeadingCorrector
// does), turns it into a measurement of the raw odometry heading error, and
// rotates the ASR about its entry pivot so that its heading matches the
// filter's estimate (the prediction alone when the estimate is declined or
// gated), carried to every later ASR.
//
// Output fields as HeadingCorrector::Close, in the pre-corrected frame:
// world_from_local_corrected = Correction() * world_from_local_raw (the raw
// pose being the pre-corrected one). Re-express the raw fields in the raw
// odometry frame afterwards (the mapper does: RawFromPrecorrected).
class DriftHeadingCorrector {
 public:
  explicit DriftHeadingCorrector(const HeadingCorrectionOptions& heading = {},
                                 const DriftFilterOptions& drift = {});

  Pose2 CorrectOdometry(const Pose2& raw_odom, double time_s) { return odometry_.Correct(raw_odom, time_s); }
  asr::Asr Close(asr::Asr precorrected);
  // Continues a stored run: see HeadingCorrector::Restore. The drift rate
  // starts again from its prior.
  void Restore(const Pose2& correction, std::optional<double> reference_rad);

  // Smoothing at the end of a run (or whenever): the corrections of all the
  // ASRs closed so far, recomputed from the smoothed heading errors (RTS) so
  // that the rate learnt later also corrects the first ASRs (closed before it
  // was known). Returns, per ASR id in closing order, the transform to apply on
  // the left of its world_from_local_corrected (new = delta * old); the
  // corrector's own state moves to the smoothed chain. Walls stay as mapped.
  struct Revision {
    int asr_id = -1;
    Pose2 delta;
  };
  std::vector<Revision> Smooth();

  const Pose2& Correction() const { return world_corrected_from_pre_; }
  std::optional<double> Reference() const { return reference_rad_; }
  const DirectionEstimate& LastEstimate() const { return last_; }
  const OdometryCorrector& odometry() const { return odometry_; }

 private:
  HeadingCorrector estimator_;  // its Estimate() only
  HeadingCorrectionOptions heading_options_;
  OdometryCorrector odometry_;
  DriftFilterOptions drift_options_;
  Pose2 world_corrected_from_pre_;
  std::optional<double> reference_rad_;
  DirectionEstimate last_;
  // What Smooth needs of each closed ASR.
  struct Closed {
    int id;
    double applied_rad;   // mean pre-correction D over the ASR
    Vec2 pivot_pre;       // entry pivot, pre-corrected frame
    bool rotated;         // a reference existed (it was rotated)
    Pose2 correction;     // pre -> corrected after it
  };
  std::vector<Closed> closed_;
  Pose2 start_correction_;  // pre -> corrected before the first Close
  bool restored_ = false;   // Restore was called (the run did not start here)
  // Warm-up (DriftFilterOptions::warmup_measurements).
  bool warming_ = true;
  struct WarmMeasurement {
    size_t step;
    double distance_m, z_rad, sigma_rad;
  };
  std::vector<WarmMeasurement> warm_;
  double distance_since_accepted_m_ = 0.0;
  void EndWarmup();
  double WarmupRate() const;  // provisional rate from the warm-up measurements
};

// The rigid transform that best maps a pre-corrected path onto the raw one
// (same length, pose i with pose i): rotation = circular mean of the heading
// differences, translation matching the centroids. Identity for empty paths.
Pose2 RawFromPrecorrected(const std::vector<Pose2>& precorrected, const std::vector<Pose2>& raw);

}  // namespace cogmap::localize
