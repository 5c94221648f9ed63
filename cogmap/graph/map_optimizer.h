#pragma once
#include <Eigen/Core>
#include <limits>
#include <map>
#include <memory>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "cogmap/asr/asr.h"
#include "cogmap/asr/placement.h"
#include "cogmap/graph/pose_graph.h"
#include "cogmap/graph/registration.h"
#include "cogmap/localize/heading_corrector.h"

namespace cogmap::graph {

// Whether two ASRs matched by a loop closure lie in one space (a revisit):
// at least min_share of one's path (local frame; both thinned to 40 points,
// the first and last end_m left out: there the robot crossed the doorways it
// was cut at) is in sight of some point of the other's path, no face of
// either's walls crossing the line, each face lengthened by door_m / 2 at both
// ends so that doorways are closed (a point within margin_m of a face's line
// is not behind it: a robot's centre keeps its radius from every wall), with
// the new ASR at 'stored_from_new' in the stored one's frame. A revisit
// missed this way is a room of its own, as before revisits were recognised.
// True when either path is empty. SameSpaceShare: the larger of the two
// shares (1 when either path is empty).
struct SameSpaceOptions {
  double min_share = 0.5;
  double door_m = 1.5;
  double end_m = 0.5;
  double margin_m = 0.25;
};
bool SameSpace(const std::vector<Vec2>& stored_path, const std::vector<FacedSegment>& stored_faces,
               const std::vector<Vec2>& new_path, const std::vector<FacedSegment>& new_faces,
               const Pose2& stored_from_new, const SameSpaceOptions& options = {});
double SameSpaceShare(const std::vector<Vec2>& stored_path, const std::vector<FacedSegment>& stored_faces,
                      const std::vector<Vec2>& new_path, const std::vector<FacedSegment>& new_faces,
                      const Pose2& stored_from_new, const SameSpaceOptions& options = {});

// The pose graph over ASRs, built as they close (default mode of `cogmap map`;
// docs/pose-graph.md). Not in the thesis, which corrects one rotation per ASR;
// chapter V proposes matching ASRs against each other, which this does.
struct MapOptimizerOptions {
  OdometryNoiseOptions odometry;
  RegistrationOptions registration;
  // The wall-direction estimate of each ASR (EM + grid refinement).
  localize::HeadingCorrectionOptions heading;
  // The EM's 1-sigma is an asymptotic standard error, optimistic on sonar
  // walls (docs/heading-correction.md): the factor uses max(floor, scale x it).
  double direction_sigma_scale = 2.0;
  double direction_sigma_floor_rad = DegToRad(1.0);
  // Drift inside an ASR: an ASR whose path is at least twice this long has its
  // walls grouped by where along the path they were seen from (the mean
  // distance driven over the path points within split_sight_m), each
  // group's dominant direction a factor at its own mean distance driven.
  // Made when two or more groups give a direction and their directions turn
  // with the distance driven (the weighted slope differs from zero at
  // drift_test_probability); not for walls whose direction needs the grid
  // (sonar). The groups wait until Finish, which tries them in place of
  // their ASRs' whole directions from the solution with one direction per
  // ASR, and keeps them when they find a drift and the map stays as
  // consistent (docs/pose-graph.md). 0 = one factor per ASR.
  double direction_split_m = 3.0;
  // The drift to remove while the next rooms are mapped (PreBendRate,
  // asr::CognitiveMapper::SetPreBend): the graph's mean rate once the
  // least-squares slope of wall heading over distance driven has a 1-sigma
  // of at most this, from at least pre_bend_min_directions direction
  // factors, and the rate differs from zero at drift_test_probability;
  // else none. 0 = never.
  double pre_bend_max_sigma_rad_per_m = DegToRad(0.1);
  int pre_bend_min_directions = 3;
  // ... where along the path a wall edge was seen from: the mean distance
  // driven over the path points within this range of it (the MHIMM window:
  // the grid takes readings within 3 m of the robot).
  double split_sight_m = 3.0;
  // Local solve when an ASR closes: the last 'window' nodes move. A full
  // solve once the graph has grown by full_solve_growth (and at least
  // 'window' nodes) since the last one: the full solves cost O(N) each, so
  // spacing them geometrically keeps their cost per ASR flat, and they stop
  // the local windows (each anchored on a held node) from letting the heading
  // slip a quarter turn over a long stretch (docs/pose-graph.md).
  int window = 8;
  int local_iterations = 20;
  int full_iterations = 100;
  double full_solve_growth = 0.05;
  // Registration of each ASR against the previous one (across the exit).
  double min_match_fraction = 0.3;
  int min_matches = 20;
  // Loop closure: stored ASRs whose centre lies within their two radii plus
  // candidate_sigmas x the position uncertainty accumulated between them.
  double candidate_sigmas = 3.0;
  int max_candidates = 4;
  // 2: an ASR's loop-closure candidates are searched on two threads (the
  // same closures; MappingOptions::threads).
  int threads = 1;
  double loop_min_agreement = 0.5;  // of each ASR's walls on the other's, after ICP
  double loop_tolerance_m = 0.25;   // agreement distance
  // Correlative search of the starting pose: positions within
  // candidate_sigmas x the position uncertainty (at most max_search_m) every
  // search_step_m, headings likewise; ICP from the three best distinct starts.
  double max_search_m = 2.5;
  double search_step_m = 0.4;
  double max_search_rad = DegToRad(10.0);
  double search_step_rad = DegToRad(4.0);
  double ambiguity_ratio = 0.9;     // a distinct solution this close to the best: ambiguous
  // An ambiguous candidate whose alternatives all lie along the walls the
  // new ASR has (a corridor whose doors repeat along it), at the best's
  // heading, still fixes the heading and the position across those walls:
  // it is a closure across the walls only, its covariance along them
  // (100 m) leaving that direction to the odometry. Most of the new ASR's
  // walls (by length, walls_along_share) must run along the alternatives'
  // line (within walls_along_rad). Off by default: tried in the
  // thirty-third session, a sonar corridor's heading from ICP is no better
  // than its walls' lean, and on aria/office it made 3 of 80 bench maps
  // worse and 1 better (docs/pose-graph.md, "Closures across the walls
  // only"); false: every ambiguous candidate is rejected.
  bool closures_across_walls = false;
  // At the end of the run, the loop-closure candidates searched again
  // against the solved graph (the graph each was first judged against was
  // pulled by closures dropped later, and corrected less): a pair whose
  // predicted relative pose has moved by a search step or more since its
  // search, and that never held an accepted closure. Off by
  // default: on the CARMEN logs cut every 8-25 m (26 runs) ATE better in 10
  // and worse in 3, but on intel at the default cut 3 more closures for
  // 6-16 % more time, and on the bench's sonar runs of aria/office 1 map
  // better and 1 worse (docs/pose-graph.md, "Closures searched again").
  bool search_again = false;
  // A row of like rooms (offices along a corridor) matches a new room on
  // the stored room beside it as well as on itself: only the prediction
  // tells them apart. The room next door is the closure's best placement
  // moved by the new ASR's own extent along either of its walls'
  // directions; each such placement within the gate that no stored ASR's
  // walls or path rule out (space nobody mapped rules nothing out) is an
  // alternative, weighed by the prediction alone (exp(-Mahalanobis^2 / 2);
  // the walls fit both alike). A closure less than next_door_min_odds
  // times as likely as its alternatives together is rejected as ambiguous
  // (NextDoorWithinGate; docs/pose-graph.md, "The room next door"). At 1
  // the likelier wins; at 2 (the drift's alias_min_odds) CARMEN
  // freiburg-101 and intel lost right closures where the prediction's
  // covariance, which counts no closure before, is wide.
  bool closure_next_door = true;
  double next_door_min_odds = 1.0;
  double walls_along_share = 0.7;  // a room's walls run half one way, half the other
  double walls_along_rad = DegToRad(15.0);
  double gate_probability = 0.999;  // chi-square gate on the closure vs the prediction
  double drift_test_probability = 0.99;  // likelihood-ratio test of a drift rate (Finish)
  // A drift whose quarter-turn alias (a rate that turns the heading a quarter
  // turn more or less between two wall directions) fits nearly as well is
  // kept only when it is at least this many times as likely as its aliases together
  // (likelihood ratio exp(delta chi2 / 2)); at even odds the choice is a
  // coin toss between a corrected map and one far worse than the odometry,
  // so the drift is left uncorrected (TestDrift).
  double alias_min_odds = 2.0;
  // A drift known before the run and removed inside every room while it
  // was mapped (mapping::MappingOptions::remove_drift_rad_per_m, the second
  // pass): Finish's drift test weighs free rates against that drift (the
  // rates held at their offsets, PoseGraph::SetRatesHeldAtOffsets) instead
  // of against none, and the drift counts as found either way. The rooms
  // no longer lean with it, so a test against none would see less of it
  // than the run that found it (on cluttered_lab, 16 sonars, 1 deg/m, 2 of
  // 3 second passes held the rates at zero, putting the removed drift back:
  // ATE 0.06-0.14 -> 0.46-0.52 m, the odometry's); with the rates free and
  // untested, fhw at 1 deg/m cut every 8 m slid to an alias at -2.48 deg/m.
  bool drift_known = false;
  // A wing of the building turned against the rest (Finish,
  // TryBuildingDirections; docs/pose-graph.md, "Wings turned against the
  // rest"): the walls of at least building_direction_min_asrs ASRs, read
  // along the odometry, agree with each other (within two of their measured
  // sigmas either way, a quarter to a half of building_direction_min_rad)
  // and their direction lies at least building_direction_min_rad off every
  // other group's (modulo a quarter turn), and wherever the run passes from
  // one group to another the walls step between them. A drift rate fits
  // such a step badly, as a ramp that turns the rooms on both sides of it (a
  // 30-degree wing: 0.31 +- 0.05 deg/m "found" with no drift, heading
  // errors up to 19 degrees); a building direction per group fits it. They
  // are kept when they lower the graph's -log likelihood (the rates free on
  // both sides) by more than half the chi-square quantile of
  // building_direction_test_probability (Bonferroni over the candidates
  // tried), at the variance components as fitted or, when solved the
  // directions stay building_direction_min_rad apart, at each model's own
  // wall-direction variance, and leave the map at least as consistent; a
  // wing not kept is held by the covariances (and keep_building_directions
  // false keeps none: the covariances alone). The level is stricter
  // than the drift test's: the groups are searched for (over the drift
  // rate, and from the data), and at 99 % a 16-sonar run at 2 deg/m on a
  // building with no wing took one (chi2 7.9: wall p95 0.84 -> 2.05 m).
  // Wings meet at 15 degrees or more in real buildings; a room's direction
  // misread by a few degrees (sonar) is what the Cauchy tail is for. At most
  // max_building_directions in all (1: the first only, as before the
  // thirty-sixth session).
  int max_building_directions = 3;
  bool keep_building_directions = true;
  double building_direction_test_probability = 0.999;
  double building_direction_min_rad = DegToRad(15.0);
  int building_direction_min_asrs = 3;
  // The aliases tried (TestDrift): at most this many of the lowest minima
  // of the wall directions' cost over the drift rate, each a full solve.
  int max_drift_aliases = 6;
  // A revisit: both ASRs' walls agree on each other at least this much,
  // and the two paths lie in one space (SameSpace): two rooms side by side
  // share a wall, which both see and agree on (nine_rooms cut every 8 m: 45
  // of 45 revisits were of the room next door), but it stands between their
  // paths once its door is closed.
  double same_room_agreement = 0.6;
  SameSpaceOptions same_space;
  // With the drift left uncorrected as ambiguous (its quarter-turn alias
  // fits about as well), a solution that turns the run away from its
  // odometry by more than this (TurnRange) has chosen a quarter-turn branch
  // of the walls the drift test would not: the odometry is used instead.
  double max_turn_without_drift_rad = DegToRad(45.0);
  // Uncertain ASRs (named in report.json, warned about).
  double uncertain_theta_rad = DegToRad(3.0);
  double uncertain_position_m = 0.5;
  // Variance components (Finish): the sigmas of the odometry, wall-direction
  // and registration factors are priors for robots in general; at the end of
  // a run each kind's sigmas are scaled by the square root of its robustly
  // weighted chi^2 over its redundancy (the part of its dof the rest of the
  // graph checks: PoseGraph::Redundancies), re-solved and iterated this many
  // rounds, each factor within [1/10, 10] of the prior. A kind needs
  // min_factors_for_variance factors and min_redundancy_for_variance
  // redundancy to be fitted.
  int variance_rounds = 12;
  // The walls bent by the drift where each vertex was seen from (the hits'
  // distance driven, asr::Asr::walls_seen_s) rather than at its nearest path
  // pose (BendWalls).
  bool bend_where_seen = true;
  // The consistency check (MapConsistency) leaves out the robot's path
  // within this far of a doorway's jambs (half its width plus this from its
  // centre): there the walls of the two ASRs it joins end where each saw
  // them, and a placement a decimetre or two off (well within its sigma)
  // puts the path across the other's jamb. 0: every crossing counts.
  double consistency_door_margin_m = 0.5;
  int min_factors_for_variance = 10;
  double min_redundancy_for_variance = 3.0;
  // The odometry's heading noise against its motion model (Finish). With no
  // drift found, the odometry's heading error is the model's random walk;
  // its variance component fitted above the model beyond its sampling error
  // (its weighted chi^2 at the model over the kind's redundancy past this
  // quantile) means the wall directions pull the headings away from the
  // odometry by more than either model allows: a wing's walls read as the
  // building's, walls misread by a sparse ring. The fit is then tried again
  // with the odometry's heading held at its model, and that kept when the
  // map as fitted is the less consistent (MapConsistency: the robot's path
  // through walls). 0: never tried.
  double heading_model_test_probability = 0.999;
  // A-posteriori variance factor on the covariances (see Finish): it may
  // shrink them down to min_variance_factor (in variance) with at least
  // min_dof_to_shrink degrees of freedom. 1: never shrunk (the default; the
  // 100 bench runs: 97 with 95 % of the ASRs within 3 sigma, against 93 at
  // 0.25, docs/pose-graph.md "Uncertainty").
  int min_dof_to_shrink = 10;
  double min_variance_factor = 1.0;
  // Covariances with every fitted sigma factor at least 1 (see Finish()).
  bool covariance_sigma_floor = true;
  // Covariances with each wall-direction factor's bend error added: its
  // walls were seen all along its path (length L), each leaning by the
  // drift so far; the factor corrects them by the mean, which leaves the
  // rate x L / sqrt(12 n_eff) (n_eff: the EM's effective edges), the rate's
  // variance included (PoseGraph::SetDirectionBend). Only the covariance:
  // the estimate weighted so made the maps at 2 deg/m worse (bench/
  // never_worse: wall p95 +0.108 m, ATE +0.048 m on average); the
  // covariances alone: runs with 95 % of their ASRs within 3 sigma 229 ->
  // 230 of 240 (docs/pose-graph.md, "Uncertainty").
  bool covariance_direction_bend = true;
};

// How far the placed headings turn away from the odometry's over a run: the
// range (max - min) of placed[i].theta - odometry[i].theta, unwrapped along
// i (consecutive differences taken within half a turn).
double TurnRange(const std::vector<Pose2>& placed, const std::vector<Pose2>& odometry);

struct LoopClosure {
  int from_asr = -1;  // the stored ASR
  int to_asr = -1;    // the new one
  Pose2 relative;     // to_asr's pose in from_asr's frame
  double agreement = 0.0;
  double rmse_m = 0.0;
  double mahalanobis2 = 0.0;
  bool accepted = false;
  bool same_room = false;
  // Accepted across the walls only (MapOptimizerOptions::closures_across_walls):
  // along them other placements fit as well, and the factor leaves that
  // direction to the odometry. Never a revisit.
  bool across_walls_only = false;
  // SameSpaceShare of the two paths, measured for an accepted closure whose
  // walls agree enough for a revisit (same_room_agreement); -1 otherwise.
  double same_space = -1.0;
  std::string reason;  // why rejected, or "accepted"
};

struct AsrEstimate {
  int asr_id = -1;
  Pose2 pose;                      // world_from_local, optimised
  Eigen::Matrix3d covariance = Eigen::Matrix3d::Zero();
  bool has_covariance = false;
  // The position's 1-sigma once the whole map is laid on the building by
  // its best rigid move (PoseGraph::Covariances' aligned, the drift
  // hypotheses' spread likewise laid): what "uncertain" tests for the
  // position, since covariance holds the uncertainty of the frame the first
  // ASR fixes.
  double position_sigma_aligned_m = 0.0;
  int room_id = -1;                // the physical room (the first visit's ASR id)
  double drift_rate_rad_per_m = 0.0;  // estimated on the way out of it (0: odometry solution)
  // The robot's path through the ASR as the graph places it (world), the
  // drift rate removed inside the ASR (asr::CorrectedPath).
  std::vector<Pose2> corrected_path;
  // The ASR's walls (local frame) with the same drift removed: each vertex
  // moves with the path pose it was seen from (asr::Asr::walls_seen_s; the
  // nearest path pose where that is not known).
  std::vector<Polyline> corrected_walls;
  bool direction_factor = false;
  double direction_residual_sigmas = 0.0;
  int building_direction = 0;  // which of OptimizerResult::building_directions_rad its walls follow
  bool uncertain = false;
  std::vector<std::string> why;    // reasons it is uncertain
};

struct OptimizerResult {
  std::vector<AsrEstimate> asrs;  // in closing order
  std::vector<LoopClosure> closures;  // accepted and rejected candidates
  // Which placement the map uses: "pose_graph", "pose_graph_without_closures"
  // or "odometry" (every correction made the map less consistent).
  std::string solution = "odometry";
  int crossings_odometry = 0;  // robot path crossing another ASR's walls
  int crossings_graph = 0;
  int crossings_chosen = 0;
  double overlap_odometry_m = 0.0;  // path inside another ASR's box (the crossings' opportunity)
  double overlap_graph_m = 0.0;
  // Share of the placed ASRs whose odometry pose lies within 3 sigma of the
  // pose kept (position and heading, the covariances reported; -1 without
  // covariances): how far the correction moved the map, against how sure
  // it is. With no drift found, under 95 % is a warning.
  double odometry_within_3sigma = -1.0;
  // The same once the odometry is bent by the one drift rate that brings it
  // nearest the map (moved_as_drift_rad_per_m: least squares over the placed
  // ASRs, weighed by their covariances, the rate's prior its sigma with the
  // rates free). With no drift found and the first share under 95 %, the
  // warning says whether such a drift explains the move (this at 95 % or
  // more: a ramp along the path, an undetected drift or walls that lean
  // together) or not (a step: the walls or closures against the odometry).
  double odometry_within_3sigma_bent = -1.0;
  double moved_as_drift_rad_per_m = 0.0;
  double chi2 = 0.0;
  int chi2_dof = 0;
  double chi2_p999 = 0.0;      // the 99.9 % quantile for chi2_dof
  // The same as the solve weighs the factors (each chi2 times its robust
  // loss's weight, a factor the loss discounts as an outlier counting for
  // little), against what that sum is worth when every sigma is right (each
  // factor's consistency x its dof, less the parameters): what the
  // disagreement warning and the variance factor use. An outlier is named
  // with its ASR instead (its walls off the building direction).
  double chi2_weighted = 0.0;
  double chi2_weighted_dof = 1.0;
  double variance_factor = 1.0;  // applied to every covariance
  // Likelihood-ratio test of a drift rate against none (Finish).
  bool drift_detected = false;
  bool drift_alias_risk = false;  // detected, but the wall directions are too sparse to trust it
  // The minima of the graph's cost over the drift rate (TestDrift: the
  // drift's own basin, with the rates free, and its quarter-turn aliases),
  // each a map the walls fit, with its share of their likelihood; the
  // covariances hold their spread about the poses kept (Finish).
  struct DriftHypothesis {
    double rate_rad_per_m = 0.0;
    double weight = 0.0;          // shares sum to 1
    int building_directions = 1;  // more than 1: a wing the test did not keep
  };
  std::vector<DriftHypothesis> drift_hypotheses;
  // The building directions (radians, modulo a quarter turn, in the map
  // frame): the first, then any wing's (TryBuildingDirections); with the
  // chi-square each lowered the graph's cost by.
  std::vector<double> building_directions_rad;
  double building_direction_chi2 = 0.0;  // twice the robust cost the directions beyond the first lowered
  int split_asrs = 0;             // ASRs whose walls were grouped along the path (direction_split_m)
  bool split_used = false;        // ... and the groups kept (Finish)
  double drift_test_chi2 = 0.0;
  // Fitted sigma factors per kind of factor (variance components).
  double odometry_sigma_factor = 1.0, direction_sigma_factor = 1.0, registration_sigma_factor = 1.0;
  double odometry_heading_sigma_factor = 1.0;
  // The odometry's heading factor as first fitted, when it was above its
  // model with no drift found and the fit was tried again with it held at
  // the model (heading_model_test_probability); 0: not tried.
  double odometry_heading_fitted_factor = 0.0;
  // Whether that second fit was kept (the map as first fitted the less
  // consistent).
  bool odometry_heading_held = false;
  int registrations = 0;
  int direction_factors = 0;
  double drift_rate_rad_per_m = 0.0;      // mean of the estimated rates
  // Its 1-sigma (the rates free, even when the test held them at zero: the
  // drift it could not rule out); < 0: not known (the odometry solution, a
  // single room, a rate nothing measures).
  double drift_rate_sigma_rad_per_m = -1.0;
  // The rate's 1-sigma over every fit of the rates the covariances hold
  // (drift_hypotheses): the second moment of their mixture about the rate
  // kept, as the poses' covariances hold their spread about the poses kept
  // (DriftSpreadSigma). drift_rate_sigma_rad_per_m alone when there is one
  // fit; < 0 when that is not known.
  double drift_rate_spread_sigma_rad_per_m = -1.0;
  double solve_seconds = 0.0;
  double covariance_seconds = 0.0;
  std::vector<std::string> warnings;
};

// The sigma of a rate kept at 'kept' (its own 1-sigma 'own') when the data
// fit several rates, each with its share of the likelihood: the root of the
// mixture's second moment about the kept rate, own^2 + sum of share x
// (rate - kept)^2. One fit at the kept rate gives 'own' back; 'own' < 0
// (not known) gives -1.
double DriftSpreadSigma(double kept, double own, const std::vector<OptimizerResult::DriftHypothesis>& fits);

// The building directions (radians, modulo a quarter turn) that wall
// directions agree on: greedily, the widest group of 'directions' within a
// window 'width_rad' wide (between min_rad / 2 and min_rad; 0: min_rad / 2;
// their mean weighted by 'weights'), then the same among the rest, each at
// least min_rad from every direction taken, while min_count or more agree;
// at most 'most', largest first. Two or more: a wing of the building turned
// against the rest.
std::vector<double> BuildingDirections(const std::vector<double>& directions, const std::vector<double>& weights,
                                       double min_rad, int min_count, int most, double width_rad = 0.0);

// The common drift rate, among lo, lo + step, ... hi, at which the wall
// directions, each dead-reckoned as term.world + rate x term.slope, gather
// into two or more building directions (as BuildingDirections groups them)
// with the most of them (the tightest, of equal counts); none unless they
// gather at least min_count more there than one direction gathers at any
// of 'reference_rates' (the rates found with one building direction): a
// wing turned against the rest, on top of whatever drift. A drift alone
// gathers into one direction at its rate.
struct WingScan {
  double rate_rad_per_m = 0.0;
  int count = 0;         // directions gathered at that rate
  int single_count = 0;  // the most one direction gathers at the reference rates
  std::vector<double> directions;
};
std::optional<WingScan> ScanBuildingDirections(const std::vector<PoseGraph::DirectionTerm>& terms, double lo,
                                               double hi, double step, double min_rad, int min_count, int most,
                                               const std::vector<double>& reference_rates, double width_rad = 0.0);

// The common drift rate, among lo, lo + step, ... hi, at which the wall
// directions, dead-reckoned as term.world + rate x term.slope and taken in
// the order the robot saw them (by node), split once into two level runs
// best: the least circular scatter (modulo a quarter turn) about each
// side's mean, at the best split that leaves 'least' factors each side
// (the cost SplitAtOneStep minimises). A wing on top of a drift: read at
// the drift's rate, the walls before the robot passed into the wing lie
// about one direction and those after it about another; read at any other
// rate both runs ramp. Without a wing the best rate levels the walls
// around one direction, and SplitAtOneStep finds no step there. None with
// fewer than 2 x least factors.
std::optional<double> ScanWingSplit(const std::vector<PoseGraph::DirectionTerm>& terms, double lo, double hi,
                                    double step, int least);

// Where two wall directions that follow each other along the run (the
// ASRs by node order; 'world' each one's walls along the odometry, 'family'
// the building direction each is tied to) are tied to different building
// directions, the walls should turn by the step between those directions:
// a wing begins where the robot passes into it. Judged on the mean of up
// to 'run' wall directions either side of the change (those of the same
// building direction as the one next to it), each less its direction: the
// two means within tol_rad of each other. 'supported' counts the changes
// that are such a step, 'unsupported' those whose walls turned by less or
// more (a slow wander of the odometry's heading split at an arbitrary
// point: the walls either side of it lie half-way between the directions).
// A wall direction tied to another building direction than both its
// neighbours, which share one and agree within tol_rad, more than tol_rad
// off both of theirs and with neither change beside it a step, is a room
// misread (a sparse ring reads a room's walls 10 degrees off now and
// then): its two changes are not counted. Counted, one such room in a
// building of one wing made two unsupported changes against the wing's one
// step. One as near its neighbours as a wandering heading leaves it, or
// one that reads the other building direction, counts.
struct WingSteps {
  int supported = 0, unsupported = 0;
};
WingSteps CountWingSteps(const std::vector<double>& world, const std::vector<int>& node,
                         const std::vector<int>& family, const std::vector<double>& directions, double tol_rad,
                         int run = 3);

// The walls' directions ('world', each factor's along the odometry; 'node'
// its ASR) split once along the run where one building direction gives way
// to another: the split that leaves the least circular scatter about each
// side's mean (modulo a quarter turn), each side min_count or more. Kept
// when the two means lie building_direction_min_rad apart (or within their
// standard errors of it, as BuildingDirections allows) and the walls step
// there: the mean offsets of three factors either side, two factors clear
// of the split (the rooms and corridor where the wings meet read between
// them), within tol_rad of each other; and each side level: the three
// factors at its far end within tol_rad of those three, or within half the
// step between the means when that is more (a wing's sides turn by what
// the heading wanders along them, not with its step). A ramp (a drift
// read at the held rates, or a slow wander of the heading) splits too,
// but its sides turn as much as the step. 'family' is per input factor (0
// before the split, 1 after).
struct WingSplit {
  std::vector<double> directions;
  std::vector<int> family;
};
std::optional<WingSplit> SplitAtOneStep(const std::vector<double>& world, const std::vector<int>& node,
                                        double min_rad, int min_count, double tol_rad);

// r.building_directions_rad in degrees modulo a quarter turn, in [0, 90)
// (report.json, the terminal and Python give them so).
std::vector<double> BuildingDirectionsDeg(const OptimizerResult& r);

class MapOptimizer {
 public:
  explicit MapOptimizer(const MapOptimizerOptions& options = {});

  // An ASR of an earlier run (--resume): held at its stored corrected pose.
  void AddStored(const asr::Asr& stored, int room_id = -1);
  // An ASR that has just closed, its raw fields in the odometry frame its walls
  // were built in (CognitiveMapper::SetPlacer): adds it
  // to the graph, registers it against the previous ASR and any stored ASR it
  // may overlap, solves locally (fully after a loop closure), and returns it
  // with world_from_local_corrected, heading_correction_rad and
  // heading_uncertainty_rad set.
  asr::Asr Place(asr::Asr a) { return Place(std::move(a), nullptr); }
  // The part of Place that reads the ASR alone (its node: the local path,
  // faces and extent; its wall direction; its walls' directions grouped
  // along the path), made ahead: const, safe on another thread while Place
  // runs (CognitiveMapper's walls stage makes it while the ASR before is
  // placed). The walls a sonar's ASR keeps (output_walls_local, vectorised
  // after it) Place takes from the ASR it is given.
  std::unique_ptr<asr::PlacementWork> Prepare(const asr::Asr& a) const;
  // 'prepared': Prepare(a) (a with other output walls at most), or null.
  asr::Asr Place(asr::Asr a, std::unique_ptr<asr::PlacementWork> prepared);
  // The odometry's noise model for the ASRs placed from now on (the
  // pipeline's laser odometry, once it has decided to match).
  void SetOdometryNoise(const OdometryNoiseOptions& noise) { options_.odometry = noise; }
  // Full solve, consistency check against odometry, covariances.
  OptimizerResult Finish();

  // Current room identity of an ASR (-1 unknown).
  int RoomOf(int asr_id) const;
  const std::vector<LoopClosure>& closures() const { return closures_; }
  int size() const { return static_cast<int>(nodes_.size()); }
  // The drift rate (rad per metre) to remove inside the ASRs mapped from now
  // on (asr::Asr::pre_bend_rad_per_m): the mean of the placed nodes' rates
  // when the direction factors placed so far pin it
  // (pre_bend_max_sigma_rad_per_m) and tell it from none (the drift test's
  // level), else 0. A wrong value costs sharpness, not consistency: each node's
  // factors know what was removed (PoseGraph::AddNode's rate_offset).
  double PreBendRate() const;
  // The wall-direction estimate of the ASR placed last.
  const localize::DirectionEstimate& LastEstimate() const { return last_estimate_; }

 private:
  struct Node {
    int asr_id;
    Pose2 raw;                       // world_from_local_raw
    std::vector<FacedSegment> faces; // local frame
    int sample_count = 0;            // SampleFaces(faces): made again when a loop closure needs them
    std::vector<Vec2> path_local;    // robot path, local frame, every ~0.2 m
    std::vector<Pose2> path_raw;     // raw path (world raw), for the odometry factor
    std::vector<double> path_turn;   // asr::Asr::path_turn_rad (empty: not known, or used)
    double turn_after = 0.0;         // asr::Asr::turn_after_path_rad
    double pre_rate = 0.0;           // drift removed while it was mapped (asr::Asr::pre_bend_rad_per_m)
    std::vector<Polyline> walls;     // local frame, as mapped
    std::optional<std::vector<Polyline>> output_walls;  // the walls the ASR keeps, when not 'walls'
    // Per vertex of walls / output_walls, the distance driven when it was
    // seen (asr::Asr::walls_seen_s; empty or NaN: not known).
    std::vector<std::vector<double>> walls_seen_s, output_walls_seen_s;
    // Its exits (doorways): centre (local frame) and the radius around it
    // where the consistency check counts no crossing (MapConsistency).
    std::vector<std::pair<Vec2, double>> exits_local;
    Vec2 centre_local{0, 0};
    Vec2 box_lo{0, 0}, box_hi{0, 0};  // of walls and path, local frame
    double radius_m = 0.0;
    bool stored = false;
    bool direction = false;
    double direction_local = 0.0;
    double direction_sigma_measured = 0.0;  // without the floor (the part variance components scale)
    double var_prefix = 0.0;         // accumulated position variance from the first node
    double heading_var = 0.0;        // heading variance since the last direction factor
    // The odometry from the previous node to this one (its frame): its
    // derivative by the drift rate, what an undetected drift would bend it
    // by (Finish: the map moved beyond its sigmas, as a drift would?).
    Eigen::Vector3d odo_by_rate = Eigen::Vector3d::Zero();
    int room_id = -1;
  };
  Node MakeNode(const asr::Asr& a) const;
  // n's path as its walls were mapped (world raw frame): the raw path itself
  // when n.pre_rate is 0, else that path re-integrated under it, made in
  // 'scratch'.
  const std::vector<Pose2>& MappedPath(const Node& n, std::vector<Pose2>* scratch) const;
  // n's walls with the drift 'rate' removed inside the ASR; 'output': the
  // walls it keeps (Node::output_walls) rather than those matched.
  std::vector<Polyline> BendWalls(const Node& n, double rate, bool output = false) const;
  // The raw odometry from n's origin to its path pose nearest 'local_point'
  // (where walls near that point were seen from).
  OdometryMeasurement PathTo(const Node& n, const Vec2& local_point) const;
  // Direction factors of an ASR's walls grouped along its path
  // (direction_split_m); fewer than two: use one for the whole ASR.
  struct SplitDirection {
    double direction_local;
    double s_mean_m;
    double sigma_measured;  // without the floor (the part variance components scale)
    double effective_edges = 1.0;  // the EM's Kish effective number of inlier edges
  };
  // A direction's sigma: its measured part, at least the floor (how square
  // real buildings are).
  double DirectionSigma(double measured) const { return std::max(options_.direction_sigma_floor_rad, measured); }
  std::vector<SplitDirection> SplitDirections(const Node& n, const asr::Asr& a) const;
  class Prepared;
  // The walls the ASR keeps (Node::output_walls) and where they were seen:
  // not MakeNode's, which Prepare calls before a sonar's are vectorised.
  static void SetOutputWalls(Node* n, const asr::Asr& a);
  struct Split {
    int whole;                // the whole-ASR direction factor (disabled while split)
    std::vector<int> groups;  // the groups' factors
  };
  std::vector<Split> splits_;
  // Finish's likelihood-ratio test of a drift rate against none; leaves the
  // graph solved under the hypothesis kept.
  struct DriftDecision {
    double chi2 = 0.0;
    bool detected = false;
    bool alias_risk = false;
    double alias_chi2 = std::numeric_limits<double>::infinity();  // the best distinct alias's chi2 above the drift's
    std::string warning;
    // Every minimum of the rates found (the drift's own basin among them),
    // its poses and its likelihood relative to the best (exp(-delta cost)):
    // the hypotheses the map's uncertainty must hold whichever was kept.
    struct Hypothesis {
      double rate = 0.0;
      double weight = 1.0;
      std::vector<Pose2> poses;
      int building_directions = 1;  // 2 or 3: a wing the test did not keep (TryBuildingDirections)
    };
    std::vector<Hypothesis> hypotheses;
    // A wing not kept that fits better than the map kept (TryBuildingDirections).
    std::string wing_warning;
    // The graph solved with the rates free and held.
    PoseGraph::State free_state, held_state;
  };
  // The minima of the graph's cost over a common change of every rate
  // (TestDrift): the one of 'rate' first (cost 'cost', state 'state'), then
  // its aliases, each solved; the graph is left in an unspecified state.
  struct RateMinimum {
    double rate, cost;
    PoseGraph::State state;
  };
  // '*gap_m': the longest stretch of the path without a wall direction.
  std::vector<RateMinimum> FindRateMinima(double rate, double cost, const PoseGraph::State& state, double quantile,
                                          int* solved, double* gap_m);
  // The drift test; with likelihood_ratio_only, the likelihood-ratio test
  // alone (detected: the rates lower the cost beyond the quantile), without
  // the aliases' search.
  DriftDecision TestDrift(bool likelihood_ratio_only = false);
  // Wings turned against the rest of the building: building directions
  // for groups of wall directions that agree with each other but not with
  // the first (BuildingDirections, along the odometry), kept when the
  // likelihood and the map's consistency say so
  // (MapOptimizerOptions::max_building_directions); '*drift' is decided
  // again under the directions kept, '*chi2' what they lowered the cost by.
  // Returns the number added.
  int TryBuildingDirections(DriftDecision* drift, double* chi2);
  // The groups in place of their ASRs' whole direction (true) or not.
  void SetSplitsEnabled(bool on);
  std::vector<Pose2> CurrentPoses() const;
  std::vector<double> CurrentRates() const;
  // The mean of the drift rates of the nodes this run placed (0: none): the
  // run's rate as Finish reports it.
  double MeanRate() const;
  // Closures the solved graph contradicts (chi-square over the gate) are
  // disabled and the graph re-solved, up to 3 rounds.
  void DropContradictedClosures();
  // What Finish tries and may take back (the split directions, the
  // closures searched again): the graph's poses and rates, whether the
  // rates are held, the sigma factors and the closures. TakeBack disables
  // and forgets the closure factors added since.
  struct Trial {
    PoseGraph::State state;
    bool rates_fixed = false;
    std::vector<double> sigma;  // per kSigmaKinds (map_optimizer.cc)
    std::vector<LoopClosure> closures;
    size_t closure_factors = 0;
  };
  Trial StartTrial() const;
  void TakeBack(const Trial& t);
  // The loop-closure candidates of node n: searched, gated and, when
  // accepted, added to the graph; the number accepted. With 'again' (the
  // end of the run, search_again) the pairs it holds are skipped, and so is
  // a pair whose prediction has not moved since it was searched; a pair
  // searched before has its record replaced rather than a second one added.
  struct SearchAgain {
    std::set<std::pair<int, int>> skip;            // (stored node, new node)
    std::map<std::pair<int, int>, size_t> record;  // pair -> index in closures_
  };
  int TryLoopClosures(int n, SearchAgain* again = nullptr);
  // search_again: every node's candidates searched again with the graph as
  // it stands at the end of the run; the number of closures accepted.
  int SearchClosuresAgain();
  // One loop-closure candidate k of node n (TryLoopClosures): the
  // correlative search, ICP from its best distinct starts and the agreement
  // of each solution, best first. Reads the graph and the nodes only.
  struct CandidateSolution {
    Registration reg;
    double agreement;
    Vec2 overlap_in_o, overlap_in_cur;  // centroids of the overlapping samples
  };
  struct CandidateEval {
    std::vector<CandidateSolution> sols;  // best agreement first
    std::string reason;                   // why there is none, when empty
    double rate_k = 0.0, rate_n = 0.0;    // each node's drift rate, less what was removed while mapped
    Pose2 placed;                         // the graph's pose of n in k's frame
  };
  CandidateEval EvaluateCandidate(int n, int k, const std::vector<FacedPoint>& cur_samples) const;
  // For an ambiguous closure: the direction (unit, in the new ASR's frame)
  // along which its alternatives lie (each a^-1 b from the best, 'cov' the
  // best's covariance in that frame), when they all keep the best's heading,
  // lie on one line through it and the new ASR's walls ('faces') run along
  // that line; nullopt otherwise.
  std::optional<Vec2> AlongTheWalls(const std::vector<Eigen::Vector3d>& alternatives, const Eigen::Matrix3d& cov,
                                    const std::vector<FacedSegment>& faces) const;
  // The room next door (closure_next_door): the new ASR n moved by its own
  // extent along either of its walls' two directions (modulo a quarter
  // turn, by length), from 'best' (n in k's frame), each such placement's
  // Mahalanobis distance from 'predicted' under S. Those within 'gate' that
  // no stored ASR rules out (a path crossing walls either way, or of the
  // wall samples of either that fall in the other's box and are not behind
  // its walls, fewer than loop_min_agreement on a wall of the other, seen
  // from either side; 'cur_samples': n's wall samples) are alternatives:
  // the likeliest's shift (n's frame) and distance, and their likelihoods
  // summed; nullopt when there is none.
  struct NextDoor {
    Vec2 shift{0, 0};            // the likeliest's
    double mahalanobis2 = 0.0;   // the likeliest's
    double likelihood = 0.0;     // sum of exp(-mahalanobis2 / 2) over all of them
  };
  std::optional<NextDoor> NextDoorWithinGate(int n, int k, const Pose2& best, const Pose2& predicted,
                                             const Eigen::Matrix3d& S, double gate,
                                             const OdometryMeasurement& to_k, const OdometryMeasurement& to_n,
                                             double rate_k, double rate_n,
                                             const std::vector<FacedPoint>& cur_samples) const;
  // The points (in n's local frame) inside n's box, 0.5 m margin.
  std::vector<FacedPoint> InBox(const std::vector<FacedPoint>& pts, const Node& n) const;
  struct Consistency {
    int crossings = 0;       // robot path segments crossing another ASR's walls
    double overlap_m = 0.0;  // path length inside another ASR's box
  };
  // 'rates': per node, the drift removed inside it (empty: none).
  Consistency MapConsistency(const std::vector<Pose2>& poses, const std::vector<double>& rates) const;
  std::vector<Vec2> LocalCorrectedPath(const Node& n, double rate) const;
  static bool LessConsistent(const Consistency& a, const Consistency& b);
  // directions_only: the wall directions' sigma factor alone, the others as
  // they are. The odometry's heading factor stays as it is while
  // hold_odometry_heading_.
  void FitVarianceComponents(bool directions_only = false);
  // Whether the odometry's heading factor, as fitted, is above its model
  // beyond its sampling error (heading_model_test_probability).
  bool HeadingAboveItsModel() const;
  // The odometry heading's redundancy at the last round of
  // FitVarianceComponents that fitted it (0: never fitted).
  double heading_redundancy_ = 0.0;
  bool hold_odometry_heading_ = false;

  MapOptimizerOptions options_;
  localize::HeadingCorrector estimator_;
  PoseGraph graph_;
  std::vector<Node> nodes_;
  std::map<int, int> node_of_asr_;
  std::vector<LoopClosure> closures_;
  std::vector<int> closure_factor_;  // per accepted closure: its AddRelative index
  std::vector<int> closure_index_;   // per accepted closure: index into closures_
  // The closures TryLoopClosures accepted for one new ASR, each with the
  // world pose of that ASR it implies and that pose's covariance (the
  // registration's, turned into the world frame): the last call's, for the
  // next one's consistency test.
  struct Implied {
    size_t closure;  // in closures_
    size_t factor;   // in closure_factor_
    int k;           // the stored ASR's node
    Pose2 world;
    Eigen::Matrix3d cov;
  };
  std::vector<Implied> prev_implied_;
  int prev_implied_node_ = -1;
  // Each node's pose when its candidates were searched (TryLoopClosures).
  std::vector<Pose2> searched_at_;
  // Each node's room: its own, or the room of the stored ASR an accepted
  // same-room closure revisits (in the closures' order).
  void AssignRoomIds();
  int registrations_ = 0;
  // Weighted sums over the placed ASRs' direction factors (weight 1 /
  // sigma^2, s the distance driven to where the walls were seen): the
  // least-squares slope of heading over s has variance 1 / Sxx, what
  // PreBendRate gates on.
  double pre_w_ = 0.0, pre_ws_ = 0.0, pre_wss_ = 0.0;
  int pre_n_ = 0;
  double driven_m_ = 0.0;  // distance driven to the newest node's origin
  localize::DirectionEstimate last_estimate_;
  double solve_seconds_ = 0.0;
  int last_full_solve_ = 0;
};

}  // namespace cogmap::graph
