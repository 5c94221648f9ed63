#pragma once
#include <map>
#include <string>
#include <utility>
#include <vector>

#include "cogmap/asr/asr.h"

namespace cogmap::localize {

// Heading error of one ASR: the circular mean, over the poses of its path, of
// (estimated heading - true heading). path[i] pairs with true_path[i] when both
// have the same length; a path longer by poses before its first one with truth
// (the mapper's sampling: a CARMEN log's odometry before its first laser
// record) pairs from the end, those poses without a partner, as the trajectory
// metrics pair them; else (a store whose path was sampled without regard to
// the truth) each pose of the shorter one pairs with the pose of the longer
// one at the nearest fraction of the distance driven through the ASR.
struct AsrHeadingError {
  int asr_id = -1;
  int poses = 0;
  double raw_rad = 0.0;        // odometry heading - truth, global rotation removed
  double corrected_rad = 0.0;  // corrected heading - truth, global rotation removed
};

struct HeadingErrorStats {
  int asrs = 0;  // ASRs with ground truth (0: the other fields mean nothing)
  double median_deg = 0.0;      // median |corrected error|
  double max_deg = 0.0;         // max |corrected error|
  double median_raw_deg = 0.0;  // median |raw error|
  double max_raw_deg = 0.0;     // max |raw error|
  double global_rotation_rad = 0.0;      // removed from the corrected errors
  double global_rotation_raw_rad = 0.0;  // removed from the raw errors
  std::vector<AsrHeadingError> per_asr;  // in input order
  // The odometry's heading drift against the truth: the least-squares slope
  // of the ASRs' raw heading errors (unwrapped in input order) over the
  // distance the odometry drove to the middle of each ASR's path, rad per
  // metre. What a drift rate the map reports can be checked against (the
  // drift a simulation or `--add-drift-deg-per-m` put in, plus what the
  // odometry's own noise added). Known when drift_asrs >= 3 and the ASRs'
  // middles are apart.
  int drift_asrs = 0;
  double odometry_drift_rad_per_m = 0.0;
};

// Heading errors of ASRs that have true_path (and a path). The corrected pose
// of a raw pose p is CorrectionOf(asr) * p. One global rotation (the circular
// mean of the per-ASR errors) is removed separately from the raw and the
// corrected errors, since neither map is tied to the true frame.
// 'corrected_paths' (ASR id -> the path as the pose graph placed it, one pose
// per Asr::path pose; the store's placements): the corrected headings of those
// ASRs come from it (the drift inside the ASR removed), the others' from
// CorrectionOf(asr) applied to the raw path.
HeadingErrorStats ComputeHeadingErrors(const std::vector<asr::Asr>& asrs,
                                       const std::map<int, std::vector<Pose2>>& corrected_paths = {});

// `cogmap eval` keys: heading_error_deg_median, heading_error_deg_max,
// heading_error_deg_median_raw, heading_error_deg_max_raw, and
// odometry_drift_deg_per_m when it is known. Empty when no ASR has ground
// truth.
std::vector<std::pair<std::string, double>> HeadingErrorEvalKeys(const HeadingErrorStats& stats);

}  // namespace cogmap::localize
