#pragma once
#include <vector>

#include "cogmap/core/angles.h"
#include "cogmap/localize/wall_directions.h"

namespace cogmap::localize {

// ---------------------------------------------------------------------------
// Paper mode: the two-component 1-D Gaussian mixture of thesis §3.1.9.2 and
// fig. A.6, fitted to the pooled data x = s U m (folded directions, radians).
// ---------------------------------------------------------------------------

struct PaperEmOptions {
  // Stop when |mu_s - mu_s'| + |mu_m - mu_m'| < epsilon (fig. A.6). The thesis
  // gives no value.
  double epsilon_rad = 1e-7;
  int max_iterations = 500;  // the thesis loops until convergence; we cap it
  // Variance floor: a component never gets narrower than this (one wall, all
  // walls parallel, zero variance). Not in the thesis, which divides by zero.
  double min_sigma_rad = DegToRad(0.01);
  // Used when there is no m data: the m component starts at the s mean with a
  // variance of max(4 var(s), this^2), so the two components differ.
  double empty_m_sigma_rad = DegToRad(10.0);
};

struct GaussianComponent {
  double pi = 0.0;      // mixing weight, eq. 3.19
  double mu = 0.0;      // mean, eq. 3.20
  double sigma2 = 0.0;  // variance, eq. 3.21
};

struct PaperEmResult {
  bool valid = false;  // false when s is empty: no estimate
  GaussianComponent s;
  GaussianComponent m;
  int iterations = 0;
  bool converged = false;  // the stopping rule was met before max_iterations
  double sum_q_s = 0.0;    // sum_i <q_i^s>: the data mass of the s component
};

// Fits the mixture by EM. Initialisation (deterministic; fig. A.6 says "some
// random numbers" but defines Mean and Var helpers for it): mu_k = Mean(k data),
// sigma_k^2 = Var(k data) (|X|-1 denominator, floored), pi_k = |k data| / N.
// E-step eq. 3.13/3.14 (in log space, so far points never give 0/0), M-step
// eq. 3.19-3.21. Plain (non-circular) arithmetic on the values as the thesis
// does, so a cluster straddling the +-45 degree seam is split.
PaperEmResult FitPaperEm(const std::vector<double>& s, const std::vector<double>& m,
                         const PaperEmOptions& options = {});

// ---------------------------------------------------------------------------
// Default mode: length-weighted directions on the circle (phi = 4 theta) with
// a von Mises component for the dominant wall direction and a uniform outlier
// component for clutter; gates that decline to estimate without evidence.
// ---------------------------------------------------------------------------

struct RobustEmOptions {
  // Weight each edge by its length (the paper weighs every edge alike).
  bool weight_by_length = true;
  // Initial weight of the uniform clutter component.
  double outlier_weight_init = 0.3;
  // Kernel width (theta, 1 sigma) of the density used to pick the starting
  // direction: the data point with the most length nearby.
  double init_kernel_sigma_rad = DegToRad(10.0);
  double epsilon_rad = 1e-7;  // stop when the dominant direction moves less (theta)
  int max_iterations = 200;
  // A fitted wall is never trusted to better than this (1 sigma, theta): caps
  // the concentration, so perfect synthetic walls do not give zero uncertainty.
  double min_edge_sigma_rad = DegToRad(0.5);
  // Gates: below these the ASR is left uncorrected.
  double min_total_length_m = 1.5;   // total wall length
  int min_edges = 2;                 // number of edges with a direction
  double min_inlier_fraction = 0.25;  // share of wall length on the dominant direction
  // Largest allowed ratio of the second direction peak (smoothed histogram,
  // farther than two kernel widths) to the highest peak: a second
  // family of walls as strong as the first (non-Manhattan, round) is ambiguous.
  double max_ambiguity = 0.7;
  double max_uncertainty_rad = DegToRad(5.0);  // 1-sigma of the dominant direction
  // The standard error uses the concentration corrected for the Kish
  // effective number of inlier edges (Fisher 1993, eq. 4.41): two short edges
  // that happen to agree no longer claim a direction to 1.5 degrees, and a
  // single edge (no spread to measure) gives no standard error at all.
  bool small_sample_correction = true;
};

enum class Decline {
  kNone = 0,       // accepted
  kNoWalls,        // no edge with a direction (no estimate at all)
  kTooLittleWall,  // total wall length below min_total_length_m
  kTooFewEdges,    // fewer than min_edges
  kNotManhattan,   // too little wall length on the dominant direction, or a
                   // second direction nearly as strong (max_ambiguity)
  kTooUncertain,   // uncertainty above max_uncertainty_rad
  kDriftOutlier,   // HeadingCorrector: the implied drift is more than odometry can
                   // have drifted since the last accepted ASR (default mode)
  kGridDisagrees,  // HeadingCorrector: the ASR's grid cells have a clear orientation
                   // that the EM direction misses (default mode, grid refinement)
};
const char* DeclineName(Decline d);

struct DirectionEstimate {
  bool valid = false;     // a direction was computed (false: no data at all)
  bool accepted = false;  // passes the gates: use it to correct the heading
  Decline decline = Decline::kNoWalls;
  double direction_rad = 0.0;    // dominant wall direction, folded, [-pi/4, pi/4)
  double uncertainty_rad = -1.0; // 1-sigma of direction_rad (may be +inf)
  double inlier_fraction = 0.0;  // weight share of the dominant component
  double ambiguity = 0.0;        // second direction peak / dominant peak (default mode)
  double concentration = 0.0;    // von Mises kappa on phi = 4 theta (default mode)
  double effective_edges = 0.0;  // Kish effective sample size of the inliers
  // The standard error from the inliers' own spread as if it were known
  // (asymptotic, no small-sample correction): how closely the EM points, the
  // window in which the grid's direction confirms it (HeadingCorrector).
  double uncertainty_asymptotic_rad = -1.0;
  double total_length_m = 0.0;
  int edges = 0;
  int iterations = 0;
  bool grid_refined = false;     // direction and uncertainty from the ASR's grid cells
  double em_direction_rad = 0.0; // the EM's own direction (before any refinement)
};

// Default mode on the s data.
DirectionEstimate EstimateDirectionRobust(const std::vector<WallDirection>& s,
                                          const RobustEmOptions& options = {});

// Paper mode on the s and m data: direction = mu_s of FitPaperEm, accepted
// whenever s is not empty (the thesis never declines); uncertainty =
// sigma_s / sqrt(sum_i <q_i^s>), reported but not used as a gate.
DirectionEstimate EstimateDirectionPaper(const std::vector<WallDirection>& s,
                                         const std::vector<double>& m,
                                         const PaperEmOptions& options = {});

}  // namespace cogmap::localize
