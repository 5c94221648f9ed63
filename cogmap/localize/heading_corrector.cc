#include "cogmap/localize/heading_corrector.h"

#include <algorithm>
#include <cmath>

namespace cogmap::localize {

Pose2 RotationAbout(const Vec2& pivot, double angle_rad) {
  const Vec2 t = RotateAbout(Vec2(0.0, 0.0), pivot, angle_rad);
  return {t.x(), t.y(), NormalizeAngle(angle_rad)};
}

Pose2 CorrectionOf(const asr::Asr& asr) {
  return asr.world_from_local_corrected * asr.world_from_local_raw.inverse();
}

DirectionEstimate HeadingCorrector::Estimate(const asr::Asr& raw) const {
  const std::vector<WallDirection> s = WallDirectionsWorldRaw(raw);
  if (options_.mode == HeadingMode::kPaper) {
    return EstimateDirectionPaper(s, MotorDirections(raw, options_.min_motor_chord_m), options_.paper);
  }
  DirectionEstimate e = EstimateDirectionRobust(s, options_.robust);
  e.em_direction_rad = e.direction_rad;
  const asr::GridOrientation& g = raw.grid_orientation;
  const bool uncertain = options_.grid_refine_uncertain && !e.accepted && e.decline == Decline::kTooUncertain;
  if (options_.grid_refine && (e.accepted || uncertain) && g.valid && g.contrast >= options_.min_grid_contrast) {
    const double grid = FoldToQuarterTurn(g.angle_rad + raw.world_from_local_raw.theta);
    // The window is where the EM's edges point (their own spread, as the
    // EM measured it): the small-sample correction says how far the truth
    // may lie from them, not where they point, and would widen the window
    // until any grid orientation, however faint, confirmed them.
    const double pointed = e.uncertainty_asymptotic_rad >= 0.0 ? e.uncertainty_asymptotic_rad : e.uncertainty_rad;
    const double sigma = std::isfinite(pointed) ? pointed : kPi / 4.0;
    const double window = std::max(options_.refine_window_sigmas * sigma, options_.refine_window_min_rad);
    if (std::abs(FoldToQuarterTurn(grid - e.direction_rad)) <= window) {
      e.direction_rad = grid;
      e.uncertainty_rad =
          options_.grid_sigma_rad * std::sqrt(std::max(1.0, options_.grid_reference_cells / std::max(1, g.cells)));
      e.grid_refined = true;
      e.accepted = true;
      e.decline = Decline::kNone;
    } else if (e.accepted && options_.grid_disagreement_declines) {
      e.accepted = false;
      e.decline = Decline::kGridDisagrees;
    }
  }
  return e;
}

asr::Asr HeadingCorrector::Close(asr::Asr raw) {
  last_ = Estimate(raw);
  for (size_t i = 1; i < raw.path.size(); ++i)
    distance_since_accepted_m_ += (raw.path[i].translation() - raw.path[i - 1].translation()).norm();
  if (last_.accepted) {
    // Direction in the corrected frame before this ASR's own rotation.
    const double d = FoldToQuarterTurn(last_.direction_rad + world_corrected_from_raw_.theta);
    // Wrapped into (-45, 45]: FoldToQuarterTurn gives [-45, 45).
    double drift = reference_rad_ ? FoldToQuarterTurn(d - *reference_rad_) : 0.0;
    if (drift == -kPi / 4.0) drift = kPi / 4.0;
    const bool gate = options_.mode == HeadingMode::kDefault && options_.drift_gate;
    if (gate && std::abs(drift) > options_.max_drift_base_rad +
                                      options_.max_drift_rad_per_m * distance_since_accepted_m_) {
      last_.accepted = false;
      last_.decline = Decline::kDriftOutlier;
    }
  }
  if (last_.accepted) {
    distance_since_accepted_m_ = 0.0;
    const double d = FoldToQuarterTurn(last_.direction_rad + world_corrected_from_raw_.theta);
    if (!reference_rad_) {
      reference_rad_ = d;
    } else {
      double drift = FoldToQuarterTurn(d - *reference_rad_);
      if (drift == -kPi / 4.0) drift = kPi / 4.0;
      const Vec2 pivot = world_corrected_from_raw_ * raw.entry_pivot_m;
      world_corrected_from_raw_ = RotationAbout(pivot, -drift) * world_corrected_from_raw_;
      // After the rotation this ASR's direction equals the reference (mod 90),
      // so the reference stays.
    }
  }
  raw.world_from_local_corrected = world_corrected_from_raw_ * raw.world_from_local_raw;
  raw.heading_correction_rad = world_corrected_from_raw_.theta;
  raw.heading_uncertainty_rad =
      last_.valid ? (std::isfinite(last_.uncertainty_rad) ? last_.uncertainty_rad : kPi / 4.0) : -1.0;
  return raw;
}

void HeadingCorrector::Restore(const Pose2& correction, std::optional<double> reference_rad) {
  world_corrected_from_raw_ = correction;
  reference_rad_ = reference_rad;
  distance_since_accepted_m_ = 0.0;
  if (reference_rad_) reference_rad_ = FoldToQuarterTurn(*reference_rad_);
}

std::optional<double> ReferenceDirection(const std::vector<asr::Asr>& corrected,
                                         const HeadingCorrectionOptions& options) {
  const HeadingCorrector estimator(options);
  for (const auto& a : corrected) {
    // Estimate on the corrected walls: a copy whose raw pose is the corrected one.
    asr::Asr view = a;
    view.world_from_local_raw = a.world_from_local_corrected;
    const Pose2 c = CorrectionOf(a);
    view.entry_pivot_m = c * a.entry_pivot_m;
    for (auto& e : view.exits) e.center_m = c * e.center_m;
    for (auto& p : view.path) p = c * p;
    const DirectionEstimate e = estimator.Estimate(view);
    if (e.accepted) return e.direction_rad;
  }
  return std::nullopt;
}

std::vector<asr::Asr> CorrectHeadings(std::vector<asr::Asr> asrs,
                                      const HeadingCorrectionOptions& options) {
  HeadingCorrector corrector(options);
  for (auto& a : asrs) a = corrector.Close(std::move(a));
  return asrs;
}

}  // namespace cogmap::localize
