#pragma once
#include <Eigen/Core>
#include <cmath>
#include <memory>
#include <string>
#include <vector>

#include "cogmap/core/angles.h"
#include "cogmap/core/pose2.h"

namespace cogmap::graph {

// Odometry noise between two ASR poses (default mode; not in the thesis).
// Wheel odometry errs in two ways: a random part that grows with the distance
// driven and the angle turned (this model: per step of length ds and turn
// dtheta, along-track variance trans^2 ds, heading variance heading^2 ds +
// rot^2 |dtheta|, propagated through the path so the heading error turns into
// lateral error), and a systematic heading drift (so many degrees per metre,
// SPEC 5) that the pose graph estimates as a variable of its own (a rate per
// ASR, a random walk from one to the next). The defaults are the simulator's
// random noise (docs/simulator.md) times two, for real robots whose wheels
// slip more than the simulated ones.
struct OdometryNoiseOptions {
  double trans_sigma_m_per_sqrt_m = 0.02;
  double heading_sigma_rad_per_sqrt_m = DegToRad(0.35);
  double rot_sigma_rad_per_sqrt_rad = DegToRad(0.6);
  double min_sigma_m = 0.01;
  double min_sigma_rad = DegToRad(0.1);
  // Drift rate: prior 1-sigma (mean 0) and random walk per sqrt(metre).
  double rate_prior_sigma_rad_per_m = DegToRad(3.0);
  double rate_walk_rad_per_m_per_sqrt_m = DegToRad(0.005);
};

// The odometry between two nodes: the raw relative pose of node j in node i's
// frame, its covariance from the noise model, and the path steps needed to
// re-integrate it under a drift rate r (each step's displacement turned by
// -r x the distance driven before it).
struct OdometryMeasurement {
  Pose2 delta;
  Eigen::Matrix3d covariance = Eigen::Matrix3d::Identity();
  double distance_m = 0.0;
  double turn_rad = 0.0;
  std::vector<Eigen::Vector3d> steps;  // (dx, dy, s at the step's middle), node i frame
};

// 'path_i' are the raw poses from node i's origin to node j's, in node i's
// frame (the first near the identity, the last = delta). Steps are merged to
// at most max_steps for the rate model (exact for the drift-free part).
// 'turns' (optional, one per path pose): the heading's summed absolute turn
// since the previous pose (asr::Asr::path_turn_rad), where it exceeds the
// net change between the two poses (a turn on the spot).
OdometryMeasurement MeasureOdometry(const std::vector<Pose2>& path_i, const OdometryNoiseOptions& options = {},
                                    int max_steps = 24, const std::vector<double>* turns = nullptr);

// The raw path's end of 'm' re-integrated under a drift rate, composed with
// the raw end's inverse: the rigid move that takes raw coordinates near the
// path's end to where that rate puts them (identity at rate 0).
Pose2 BendAt(const OdometryMeasurement& m, double rate_rad_per_m);

// kOdometryHeading names no factor of its own: it is the odometry factors'
// heading part, a variance component apart from their translation (SetSigmaFactor).
enum class FactorKind { kOdometry, kDirection, kRegistration, kLoopClosure, kRateWalk, kRatePrior, kOdometryHeading };
const char* FactorKindName(FactorKind k);

// A pose graph over ASR poses (x, y, theta), solved with Ceres:
//  - odometry factors between consecutive ASRs (Gaussian, with the node's
//    drift rate re-integrating the measured path);
//  - wall-direction factors: the dominant wall direction of an ASR is known
//    only modulo a quarter turn, so the factor ties theta_i + d_i (+ the
//    node's drift rate x the mean distance driven while the walls were seen) to a
//    building direction phi (a variable; one, unless a wing is turned
//    against the rest: AddBuildingDirection) modulo 90 degrees: a max-mixture over
//    the four branches (the nearest branch at every evaluation) with a Cauchy
//    tail for rooms whose walls are not the building's;
//  - relative-pose factors from registration (consecutive ASRs and loop
//    closures), Gaussian with a Cauchy tail;
//  - the drift-rate random walk and prior.
// Node 0 (or any node added as fixed) anchors the map.
class PoseGraph {
 public:
  PoseGraph();
  ~PoseGraph();
  PoseGraph(const PoseGraph&) = delete;
  PoseGraph& operator=(const PoseGraph&) = delete;

  // 'rate_offset': a drift rate already removed from everything measured of
  // node i (its walls and path were mapped on odometry re-integrated under
  // that rate, asr::Asr::pre_bend_rad_per_m). The node's rate stays the
  // odometry's whole drift; its factors bend their measurements by the rest,
  // rate - rate_offset (Bend and ChainWithRate too).
  int AddNode(const Pose2& initial, bool fixed = false, double rate_offset = 0.0);
  int size() const;
  void AddOdometry(int i, int j, const OdometryMeasurement& m, const OdometryNoiseOptions& noise = {});
  // 's_mean_m': mean distance driven from the node's origin while its walls
  // were seen (the node's drift rate times it leans them).
  // Returns the factor's handle for SetFactorEnabled.
  // 'floor_rad': the least sigma of the factor whatever SetSigmaFactor says.
  // The sigma has two parts: the measurement's (sigma_rad, which variance
  // components scale) and how square real buildings are (the floor: walls a
  // few tenths of a degree off the building's grid, seen alike by
  // neighbouring ASRs, an error their residuals cannot reveal).
  // 's_spread_m': the 1-sigma spread of where along the path the direction
  // was seen (a path of length L seen evenly: L / sqrt(12); a mean over n
  // walls each seen somewhere on it: L / sqrt(12 n)); with SetDirectionBend
  // the drift bends it over that by rate x that much more than the mean
  // corrects, an error added to the factor's sigma.
  int AddDirection(int i, double local_direction_rad, double sigma_rad, double s_mean_m = 0.0,
                   double floor_rad = 0.0, double cauchy_scale = 2.0, double s_spread_m = 0.0);
  // The marginal variance of every node's drift rate (rad/m)^2, with the
  // rates free; 0 where a rate is held (or all are); -1 for every node when
  // the information is singular (a rate nothing measures).
  std::vector<double> RateVariances() const;
  // Every direction factor's bend error from its node's current drift rate
  // and, when the rates are free, the rate's marginal variance:
  // s_spread x sqrt(rate^2 + var) (held until the next call; false: none).
  // 'rate_variances': RateVariances() already taken without any bend (one
  // per node), or empty to take them here.
  void SetDirectionBend(bool on, const std::vector<double>& rate_variances = {});
  // Any factor by the handle AddDirection returned (disabled factors are left
  // out of solves, residuals and covariances).
  void SetFactorEnabled(int handle, bool enabled);
  // Pose of node j in node i's frame, with its covariance. With 'bend_i'
  // and/or 'bend_j' (each node's raw path from its origin to where the walls
  // were seen: MeasureOdometry), j_in_i is a registration of raw walls: it is
  // bent by each node's drift rate as the odometry is, so that it constrains
  // the odometry's random error and not the drift. Across an exit: bend_i =
  // node i's odometry to node j, no bend_j.
  int AddRelative(int i, int j, const Pose2& j_in_i, const Eigen::Matrix3d& covariance, FactorKind kind,
                  double cauchy_scale = 2.0, const OdometryMeasurement* bend_i = nullptr,
                  const OdometryMeasurement* bend_j = nullptr);
  // Node i's path end under its current drift rate, given the raw one:
  // bent_end * m.delta^-1 (identity at rate 0).
  Pose2 Bend(int i, const OdometryMeasurement& m) const;
  void SetRelativeEnabled(int factor, bool enabled);
  // Multiplies every sigma of one kind of factor (variance components: the
  // prior sigmas fitted to a run's residuals). 1 = as given. The odometry
  // has two: its heading noise (kOdometryHeading: the heading error and the
  // lateral error it causes) and the translation noise given the heading
  // (kOdometry), so that wall directions can check the one and
  // registrations the other without one component absorbing both.
  void SetSigmaFactor(FactorKind kind, double factor);
  double SigmaFactor(FactorKind kind) const;

  struct SolveSummary {
    int iterations = 0;
    double initial_cost = 0.0;
    double final_cost = 0.0;
    double seconds = 0.0;
    int free_nodes = 0;
    bool usable = false;
  };
  // Optimises the nodes with index >= first_free (0: all), the others held.
  SolveSummary Solve(int first_free = 0, int max_iterations = 50);

  // Sets every drift rate to 'rate_rad_per_m' and re-chains the poses of the
  // nodes that are not fixed along the odometry factors (in the order they
  // were added) with it: a starting point for another drift hypothesis.
  void ChainWithRate(double rate_rad_per_m);
  // The wall-direction factors' robust cost (Ceres' convention: half the
  // robust chi^2) when every drift rate moves by the same 'delta' from its
  // current value and the free nodes follow by dead reckoning (as
  // ChainWithRate re-chains them: node j turns by -delta x the distance
  // driven to it), the building direction re-fitted for each delta, plus
  // the registrations' and loop closures' heading residuals (each with its
  // marginal heading sigma: a lower bound on what they add); one value per
  // delta. The odometry factors and the registrations across exits (bent by
  // the rate as the odometry is) do not change under such a move: a cheap
  // map of the other drift rates the wall directions, known modulo a quarter
  // turn, may fit about as well (MapOptimizer's drift test solves each it finds).
  std::vector<double> DirectionProfile(const std::vector<double>& deltas) const;
  // Holds every drift rate at zero (true) or lets them move again (false).
  void SetRatesFixedAtZero(bool fixed);
  bool RatesFixedAtZero() const;
  // Held rates (SetRatesFixedAtZero(true)) equal each node's rate offset
  // instead of zero: the nested hypothesis "no drift beyond what was
  // removed while mapping", for a run mapped with a drift known before it
  // (every node's offset that drift).
  void SetRatesHeldAtOffsets(bool on);
  // Snapshot of all poses and rates, and its restoration.
  struct State {
    std::vector<Pose2> poses;
    std::vector<double> rates;
    std::vector<double> phi;  // the building directions
  };
  State Save() const;
  void Restore(const State& s);

  Pose2 pose(int i) const;
  void set_pose(int i, const Pose2& p);
  double rate(int i) const;
  bool has_direction() const;
  double building_direction(int family = 0) const;
  int building_directions() const;

  // More than one building direction: a wing of the building turned
  // against the rest (by 30 or 45 degrees, say) has walls square among
  // themselves but not to the first direction's. AddBuildingDirection adds
  // one (a variable, started at 'initial_rad') and returns its index;
  // SetDirectionFamily ties a direction factor (AddDirection's handle) to
  // it (0: the first, where every factor starts); RemoveBuildingDirections
  // ties every factor back to the first and drops the others.
  int AddBuildingDirection(double initial_rad);
  void SetBuildingDirection(int family, double rad);
  void SetDirectionFamily(int handle, int family);
  int DirectionFamily(int handle) const;
  void RemoveBuildingDirections();
  // Every enabled direction factor's walls in the map frame (radians,
  // modulo a quarter turn: the node's heading plus the measured direction,
  // less the lean of its drift rate) at the current estimate, and how that
  // changes per unit of a common change of every drift rate with the nodes
  // following by dead reckoning (as in DirectionProfile); its sigma; its
  // building direction.
  struct DirectionTerm {
    int handle = -1, node = -1;
    double world = 0.0, slope = 0.0, sigma = 0.0;
    double measured_sigma = 0.0;  // its measurement's sigma, at least the floor (no variance components)
    int family = 0;
  };
  std::vector<DirectionTerm> DirectionTerms() const;
  // The robust cost of every enabled factor at the current estimate
  // (Ceres' convention: half the robust chi^2), held parameters included.
  double Cost() const;

  // Marginal covariances of every node's (x, y, theta), the fixed nodes held
  // (zero for them). Empty when the computation fails (rank deficient).
  // With 'aligned', also from the same factorisation: the covariance of
  // every node's pose once the map is laid on the truth by the one rigid
  // move (SE(2)) that fits its node positions best, as the absolute
  // trajectory error lays a map: what the uncertainty of the frame the first
  // node fixes adds (growing with the distance driven from it) is taken
  // out. The move is the least-squares one over every node's position (the
  // fixed ones too; headings do not weigh in, but the move's turn turns
  // them); the covariance is the marginal one with the fit's own uncertainty
  // removed. 'aligned' is left empty when either fails (and with one node).
  std::vector<Eigen::Matrix3d> Covariances(std::vector<Eigen::Matrix3d>* aligned = nullptr) const;

  // Per factor: its whitened squared residual (chi^2 without the robust loss)
  // and its dimension, at the current estimate.
  struct FactorResidual {
    FactorKind kind;
    int i = -1, j = -1;
    int factor = -1;  // AddRelative index, else -1
    double chi2 = 0.0;
    int dof = 0;
    bool enabled = true;
    double chi2_heading = 0.0;  // kOdometry: the part of chi2 from the heading (1 of its 3 dof)
    // The robust loss's slope at chi2, rho'(chi2) (1 without a loss): what
    // the solve weighs the factor by; and what weight x chi2 is worth per
    // dof when the factor's sigma is right (Redundancy::consistency).
    double weight = 1.0, consistency = 1.0;
  };
  std::vector<FactorResidual> Residuals() const;

  // Per factor (aligned with Residuals()): its redundancy number and its
  // robust weight at the current estimate. The weight w is the robust loss's
  // slope rho'(chi2) (1 without a loss); the redundancy is the part of the
  // factor's dof that the other factors check, r = dof - w tr(J S J^T), J the
  // factor's whitened Jacobian over the free parameters and S the covariance
  // of all free parameters under the weighted information; sum(dof - r) over
  // the enabled factors = the number of free parameters. Variance component
  // estimation divides each kind's weighted chi^2 by its summed redundancy
  // (Foerstner): a kind whose residuals nothing checks (the translation of
  // an odometry chain without registrations) has none and is not shrunk by
  // them. Computed by sparse LDL^T and the selected inverse (Takahashi) on
  // its pattern. Empty when the information is singular.
  // 'consistency' is what the weighted chi^2 is worth per unit of redundancy
  // when the sigma is right: E[w chi2] / dof under chi^2(dof) (1 without a
  // loss; 0.629 for a 1-dof and 0.495 for a 3-dof factor under a Cauchy loss
  // of scale 2): the variance components divide by it, else a robust loss would
  // shrink every sigma it weighs below the truth.
  struct FactorRedundancy {
    double redundancy = 0.0;
    double weight = 1.0;
    double consistency = 1.0;
    double redundancy_heading = 0.0;  // kOdometry: the heading row's part of the redundancy
  };
  std::vector<FactorRedundancy> Redundancies() const;

 private:
  struct Impl;
  struct Linearized;
  struct SelectedInverse;
  // Covariances' 'aligned', from the marginal blocks, each free node's first
  // column (-1: held) and the factorisation Invert left in impl_.
  void LaidCovariances(const std::vector<Eigen::Matrix3d>& marginal, const std::vector<int>& node_col, int cols,
                       std::vector<Eigen::Matrix3d>* out) const;
  // The enabled factors' weighted whitened Jacobian and normal matrix over
  // the free parameters (the rates free or held).
  Linearized Linearize(bool rates_free) const;
  // H^-1 on the pattern of H's sparse factor; false when H is singular
  // (a pivot below min_pivot times H's largest diagonal entry; < 0: no test).
  bool Invert(const Linearized& lin, double min_pivot, SelectedInverse* out) const;
  // The least pivot Invert accepts before calling the information singular.
  double SingularPivot(const Linearized& lin) const;
  std::unique_ptr<Impl> impl_;
};

// An angle modulo a quarter turn, in [-45, 45] degrees (radians): wall
// directions, whose four branches are alike.
inline double FoldQuarter(double a) { return a - (kPi / 2.0) * std::round(a / (kPi / 2.0)); }

// Chi-square quantile (exact, by bisection on the regularised gamma), dof >= 1.
double ChiSquareQuantile(double p, int dof);

}  // namespace cogmap::graph
