#pragma once
#include <map>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include <Eigen/Core>

#include "cogmap/asr/asr.h"
#include "cogmap/core/pose2.h"

namespace cogmap::eval {

// Trajectory metrics as SLAM papers publish them (Sturm et al. 2012, Kuemmerle
// et al. 2009): the absolute trajectory error after one rigid alignment and
// the relative pose error over fixed distances of travel. 'estimate' and
// 'reference' are the same instants, pose i with pose i.

// The rigid transform (rotation + translation, no scale) that maps the
// positions of 'from' onto those of 'to' with the least sum of squared
// distances (Umeyama/Horn in 2D; headings are not used). Identity when empty;
// a pure translation when the positions of 'from' all coincide.
Pose2 AlignPositions(const std::vector<Pose2>& from, const std::vector<Pose2>& to);

struct AteStats {
  int poses = 0;         // 0: no poses, the rest means nothing
  double rmse_m = 0.0;   // root mean square position error after alignment
  double mean_m = 0.0;
  double median_m = 0.0;
  double max_m = 0.0;
  Pose2 reference_from_estimate;  // the alignment applied to the estimate
};

// Absolute trajectory error: AlignPositions(estimate, reference) applied to
// the estimate once, then the distances between paired positions.
// Requires estimate.size() == reference.size().
AteStats AbsoluteTrajectoryError(const std::vector<Pose2>& estimate, const std::vector<Pose2>& reference);

struct RpeStats {
  double distance_m = 0.0;  // the travel d the pairs span
  int pairs = 0;
  double trans_rmse_m = 0.0;  // of |translation of (ref_i^-1 ref_j)^-1 (est_i^-1 est_j)|
  double trans_mean_m = 0.0;
  double rot_rmse_deg = 0.0;  // of |rotation of the same|, degrees
  double rot_mean_deg = 0.0;
};

// Relative pose error over 'distance_m' of travel: for every pose i, the first
// pose j > i whose reference path length from i is at least distance_m; the
// error of the relative motion est_i^-1 est_j against ref_i^-1 ref_j. nullopt
// when no such pair exists (the run is shorter than distance_m). Requires
// estimate.size() == reference.size().
std::optional<RpeStats> RelativePoseError(const std::vector<Pose2>& estimate, const std::vector<Pose2>& reference,
                                          double distance_m);

// A stored map's trajectories, paired pose for pose with the reference.
struct AsrTrajectories {
  std::vector<Pose2> reference;  // true_path
  std::vector<Pose2> raw;        // path: odometry, world raw frame
  std::vector<Pose2> corrected;  // world_from_local_corrected * world_from_local_raw^-1 * path
  int asrs = 0;                  // ASRs that contributed poses
  int unpaired_poses = 0;        // path poses left out (no true pose of the same instant)
};

// Concatenates, in the order given (the store's id order), the ASRs' paths
// with their true paths. The mapper samples both at the same records, so
// path[k] pairs with true_path[k]; the only path poses without a true pose are
// those taken before the log's first true pose (CARMEN's leading ODOM
// records), at the start of an ASR. So when an ASR's path is longer than its
// true path, the two are paired from their ends and the leading path poses are
// counted in unpaired_poses; when the true path is the longer (not written by
// this mapper), its leading extra poses are dropped likewise. ASRs without a
// true path add nothing.
// 'corrected_paths' (ASR id -> the store's placement path, one pose per path
// pose): the corrected trajectory of those ASRs as the pose graph placed it;
// the others' raw path moved rigidly with the ASR.
AsrTrajectories PairAsrTrajectories(const std::vector<asr::Asr>& asrs,
                                    const std::map<int, std::vector<Pose2>>& corrected_paths = {});

// The truth's world against the raw odometry frame an ASR's path is in, at
// its first path pose with truth (the two paired from their ends, as
// PairAsrTrajectories pairs them): truth pose x raw pose^-1. nullopt for an
// ASR without a true path.
std::optional<Pose2> TruthFromRaw(const asr::Asr& a);

struct TrajectoryMetrics {
  AteStats ate, ate_raw;
  // One per distance of TrajectoryDistances(), nullopt where no pair exists.
  std::vector<std::optional<RpeStats>> rpe, rpe_raw;
};

// The distances of travel the relative pose error is reported over: 1, 5, 20 m.
const std::vector<double>& TrajectoryDistances();

TrajectoryMetrics ComputeTrajectoryMetrics(const AsrTrajectories& t);

// `cogmap eval` keys: ate_rmse_m, ate_mean_m, ate_median_m, ate_max_m,
// rpe_<d>m_trans_m, rpe_<d>m_rot_deg, rpe_<d>m_trans_mean_m, rpe_<d>m_rot_mean_deg
// for d = 1, 5, 20, each also with the suffix _raw (the raw odometry), and
// trajectory_poses. nullopt (JSON null) where the metric does not exist: no
// paired poses, or no pair d metres apart.
std::vector<std::pair<std::string, std::optional<double>>> TrajectoryEvalKeys(const TrajectoryMetrics& m);

// Calibration of the pose graph's uncertainties (issue 10): is each ASR's
// true pose inside k sigma of where the map placed it?
//
// An ASR's true frame pose comes from its first paired path pose k:
// true_world_from_local = true_path_k * path_k^-1 * world_from_local_raw (the
// raw frame moved by the odometry's error at k). Both it and
// world_from_local_corrected are taken relative to the reference ASR, the
// first of 'asrs' with a paired true pose (the graph's fixed anchor, ASR 0,
// when it has truth), so that the reference's error is zero: the truth is
// moved rigidly onto the map's frame by est_ref * true_ref^-1.
//
// An ASR is checked when it has a paired true pose and a covariance in
// 'covariances' (of x, y, theta in the map's world frame; metres and
// radians) with a positive, finite trace of its position block and a
// non-negative, finite heading variance; zero covariances mean "not placed"
// and are skipped. It is within when its position error <= k sqrt(var_x +
// var_y) and its |heading error| <= k sigma_theta.
struct PoseCalibrationItem {
  int asr_id = -1;
  double position_error_m = 0.0;
  double heading_error_rad = 0.0;  // corrected - true, in (-pi, pi]
  double sigma_position_m = 0.0;   // sqrt(var_x + var_y)
  double sigma_heading_rad = 0.0;
  bool position_within = false, heading_within = false;
  bool within() const { return position_within && heading_within; }
};

struct PoseCalibration {
  double k_sigma = 3.0;
  int reference_asr = -1;  // -1: no ASR has a paired true pose
  std::vector<PoseCalibrationItem> items;  // the checked ASRs, in the order given
  int checked() const { return static_cast<int>(items.size()); }
  int within() const;           // both tests
  int position_within() const;
  int heading_within() const;
};

PoseCalibration ComputePoseCalibration(const std::vector<asr::Asr>& asrs,
                                       const std::map<int, Eigen::Matrix3d>& covariances, double k_sigma = 3.0);

// `cogmap eval` keys: pose_calibration_3sigma (share of checked ASRs within
// both bounds), pose_calibration_position_3sigma, pose_calibration_heading_3sigma
// (each bound alone), null when none was checked, and pose_calibration_asrs
// (how many were checked). "3sigma" follows k_sigma = 3.
std::vector<std::pair<std::string, std::optional<double>>> PoseCalibrationEvalKeys(const PoseCalibration& c);

}  // namespace cogmap::eval
