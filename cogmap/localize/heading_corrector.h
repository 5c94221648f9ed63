#pragma once
#include <optional>
#include <vector>

#include "cogmap/asr/asr.h"
#include "cogmap/localize/em.h"

namespace cogmap::localize {

enum class HeadingMode {
  kPaper,    // thesis §3.1.9-3.1.10: Gaussian mixture over s U m, always corrects
  kDefault,  // length-weighted von Mises + clutter on 4 theta, declines without evidence
};

struct HeadingCorrectionOptions {
  HeadingMode mode = HeadingMode::kDefault;
  PaperEmOptions paper;    // used in kPaper mode
  RobustEmOptions robust;  // used in kDefault mode
  double min_motor_chord_m = 0.2;  // m data (paper mode): shortest chord used
  // Drift gate (default mode only; not in the thesis): an accepted estimate
  // whose drift exceeds max_drift_base_rad + max_drift_rad_per_m x (distance
  // travelled since the last accepted ASR, its path included) is a gross
  // error (clutter taken for walls) and is declined, so that it can neither
  // rotate the ASR wildly nor push the next ASR's drift across the +-45 degree
  // wrap (a quarter-turn slip that would rotate every later ASR by 90).
  bool drift_gate = true;
  double max_drift_base_rad = DegToRad(10.0);
  double max_drift_rad_per_m = DegToRad(3.0);
  // Grid refinement (default mode only; not in the thesis): the polylines of a
  // sonar room wobble (edges of a metre or two at 10-20 degrees off their
  // wall), so the EM direction is off by a few degrees; the projection profile
  // of the room's occupied cells (Asr::grid_orientation) weighs every wall cell
  // and is off by about one (measured, docs/heading-correction.md). When the EM
  // accepts (or declines only as too uncertain, grid_refine_uncertain) and the
  // two agree within max(refine_window_sigmas x EM sigma, refine_window_min_rad)
  // (the EM sigma of its edges' own spread: uncertainty_asymptotic_rad),
  // the ASR is accepted with the grid's direction and 1-sigma grid_sigma_rad
  // (x sqrt(grid_reference_cells / cells) for an ASR with fewer occupied cells
  // than a room of nine_rooms, on which the 1 degree was measured).
  // When the grid has a clear orientation (contrast >= min_grid_contrast) that
  // an accepted EM direction misses, the two evidences contradict each other
  // and the ASR is declined (grid_disagreement_declines). Without a clear grid
  // orientation the EM decides alone.
  bool grid_refine = true;
  bool grid_refine_uncertain = true;
  bool grid_disagreement_declines = true;
  double refine_window_sigmas = 3.0;
  double refine_window_min_rad = DegToRad(4.0);
  double min_grid_contrast = 1.2;
  double grid_sigma_rad = DegToRad(1.0);
  double grid_reference_cells = 600.0;
};

// Heading correction of a sequence of ASRs by EM over wall directions (SPEC 5,
// thesis §3.1.9, §3.1.10, fig. 5.1). Rotation only.
//
// For each ASR, in the order the robot visited them:
//  1. its dominant wall direction d is measured in the raw world frame
//     (walls_local through world_from_local_raw), then carried into the
//     corrected frame by the rotation accumulated so far: d' = d + C;
//  2. drift = d' - reference, wrapped into (-45, 45] degrees, where reference is
//     the corrected direction of the previous ASR that had an accepted estimate
//     (the first such ASR sets it and is not rotated); in default mode a drift
//     larger than odometry can plausibly have drifted is declined (drift gate);
//  3. the ASR is rotated by -drift about its entry pivot (in the corrected
//     frame) and that rotation is composed into the accumulated correction, so
//     it carries to every later ASR pose, pivot and path.
// An ASR whose estimate is declined (default mode) or that has no walls gets
// only the accumulated correction of those before it.
//
// Output fields of each Asr: world_from_local_corrected = Correction() *
// world_from_local_raw, heading_correction_rad = its rotation angle (corrected -
// raw heading), heading_uncertainty_rad = 1-sigma of this ASR's own direction
// estimate (-1 when there was no wall to estimate from). Raw fields are kept.
class HeadingCorrector {
 public:
  explicit HeadingCorrector(const HeadingCorrectionOptions& options = {}) : options_(options) {}
  const HeadingCorrectionOptions& options() const { return options_; }

  // Corrects one ASR that has just closed; call in visiting order.
  asr::Asr Close(asr::Asr raw);

  // Continues a stored run (cogmap map --resume), before the first Close:
  // 'correction' is the raw -> corrected transform in force at the end of the
  // stored run (CorrectionOf(its last ASR)), 'reference_rad' the reference
  // direction in the corrected frame (ReferenceDirection of the stored ASRs;
  // nullopt: the next accepted ASR sets it).
  void Restore(const Pose2& correction, std::optional<double> reference_rad);

  // The rigid transform from the raw world frame to the corrected one after the
  // ASRs closed so far (identity at start). The corrected pose of any raw pose
  // p recorded after the last closed ASR's entry is Correction() * p.
  const Pose2& Correction() const { return world_corrected_from_raw_; }
  // The reference wall direction (folded, corrected frame), if one was set.
  std::optional<double> Reference() const { return reference_rad_; }
  // The estimate of the last ASR passed to Close.
  const DirectionEstimate& LastEstimate() const { return last_; }

  // The dominant wall direction of an ASR in the raw world frame, per mode.
  DirectionEstimate Estimate(const asr::Asr& raw) const;

 private:
  HeadingCorrectionOptions options_;
  Pose2 world_corrected_from_raw_;
  std::optional<double> reference_rad_;
  double distance_since_accepted_m_ = 0.0;
  DirectionEstimate last_;
};

// The reference direction (folded, corrected frame) of already corrected ASRs:
// the direction of the first one, in visiting order, whose estimate on its
// corrected walls is accepted. nullopt when none is.
std::optional<double> ReferenceDirection(const std::vector<asr::Asr>& corrected,
                                         const HeadingCorrectionOptions& options = {});

// Batch form: the same result as closing the ASRs one by one.
std::vector<asr::Asr> CorrectHeadings(std::vector<asr::Asr> asrs,
                                      const HeadingCorrectionOptions& options = {});

// The raw-to-corrected transform of an ASR: world_from_local_corrected *
// world_from_local_raw^-1. Apply it to the ASR's raw path poses.
Pose2 CorrectionOf(const asr::Asr& asr);

// Rotation by 'angle_rad' about 'pivot' as a rigid transform.
Pose2 RotationAbout(const Vec2& pivot, double angle_rad);

}  // namespace cogmap::localize
