#include "cogmap/graph/map_optimizer.h"

#include <Eigen/Dense>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <numeric>

#include "cogmap/core/parallel.h"
#include "cogmap/core/text.h"
#include "cogmap/localize/wall_directions.h"

namespace cogmap::graph {
namespace {

// The kinds of factor with a sigma factor of their own (fitted by
// FitVarianceComponents, all but the closures; kept by a Trial).
constexpr FactorKind kSigmaKinds[] = {FactorKind::kOdometry, FactorKind::kOdometryHeading, FactorKind::kDirection,
                                      FactorKind::kRegistration, FactorKind::kLoopClosure};

// Variance along the walls of a closure held across them only (100 m
// squared: nothing the odometry's metres cannot outweigh).
constexpr double kUnknownAlongWalls = 1e4;

double Seconds(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

std::vector<FacedPoint> TransformPoints(const Pose2& T, const std::vector<FacedPoint>& pts) {
  std::vector<FacedPoint> out;
  out.reserve(pts.size());
  const double c = std::cos(T.theta), s = std::sin(T.theta);
  for (const auto& p : pts)
    out.push_back({Vec2(T.x + c * p.p.x() - s * p.p.y(), T.y + s * p.p.x() + c * p.p.y()),
                   Vec2(c * p.normal.x() - s * p.normal.y(), s * p.normal.x() + c * p.normal.y())});
  return out;
}

std::vector<FacedSegment> TransformFaces(const Pose2& T, const std::vector<FacedSegment>& faces) {
  std::vector<FacedSegment> out;
  out.reserve(faces.size());
  const double c = std::cos(T.theta), s = std::sin(T.theta);
  for (const auto& f : faces)
    out.push_back({T * f.a, T * f.b, Vec2(c * f.normal.x() - s * f.normal.y(), s * f.normal.x() + c * f.normal.y())});
  return out;
}

std::vector<Vec2> TransformPath(const Pose2& T, const std::vector<Vec2>& path) {
  std::vector<Vec2> out;
  out.reserve(path.size());
  for (const auto& p : path) out.push_back(T * p);
  return out;
}

// Residual of 'b' against 'a' as a 3-vector (translation in a's frame, angle).
Eigen::Vector3d Difference(const Pose2& a, const Pose2& b) {
  const Pose2 d = a.inverse() * b;
  return {d.x, d.y, NormalizeAngle(d.theta)};
}

// Every step-th point of 'pts' (at most 'most' points).
std::vector<Vec2> Thin(const std::vector<Vec2>& pts, size_t most) {
  if (pts.size() <= most) return pts;
  std::vector<Vec2> out;
  const double step = static_cast<double>(pts.size()) / static_cast<double>(most);
  for (size_t k = 0; k < most; ++k) out.push_back(pts[static_cast<size_t>(k * step)]);
  return out;
}

// Whether the straight line from p to q crosses one of 'faces'. A point
// within 'margin_m' of a face's line is not behind it: a robot's centre
// keeps its radius from every wall, so a path that close to one runs along
// it or through its door.
bool Blocked(const Vec2& p, const Vec2& q, const std::vector<FacedSegment>& faces, double margin_m) {
  for (const FacedSegment& f : faces) {
    const double len = f.length();
    if (len <= 0.0) continue;
    // Distances of p and q from the face's line.
    const double dp = std::abs(Cross(f.b - f.a, p - f.a)) / len, dq = std::abs(Cross(f.b - f.a, q - f.a)) / len;
    if (dp > margin_m && dq > margin_m && SegmentsCross(p, q, f.a, f.b)) return true;
  }
  return false;
}

}  // namespace

double TurnRange(const std::vector<Pose2>& placed, const std::vector<Pose2>& odometry) {
  const size_t n = std::min(placed.size(), odometry.size());
  if (n == 0) return 0.0;
  double prev = 0.0, unwrapped = 0.0, lo = 0.0, hi = 0.0;
  for (size_t i = 0; i < n; ++i) {
    const double c = NormalizeAngle(placed[i].theta - odometry[i].theta);
    unwrapped = i == 0 ? c : unwrapped + NormalizeAngle(c - prev);
    prev = c;
    lo = i == 0 ? unwrapped : std::min(lo, unwrapped);
    hi = i == 0 ? unwrapped : std::max(hi, unwrapped);
  }
  return hi - lo;
}

double SameSpaceShare(const std::vector<Vec2>& stored_path, const std::vector<FacedSegment>& stored_faces,
                      const std::vector<Vec2>& new_path, const std::vector<FacedSegment>& new_faces,
                      const Pose2& stored_from_new, const SameSpaceOptions& o) {
  if (stored_path.empty() || new_path.empty()) return 1.0;  // nothing to tell them apart: the walls decide
  // Each face lengthened at both ends by half the widest door: a doorway
  // between two faces is closed, a room's walls surround it.
  auto closed = [&](const std::vector<FacedSegment>& faces, const Pose2& T) {
    std::vector<FacedSegment> out;
    for (const FacedSegment& f : faces) {
      const double len = f.length();
      if (len <= 0.0) continue;
      const Vec2 u = (f.b - f.a) / len;
      out.push_back({T * Vec2(f.a - 0.5 * o.door_m * u), T * Vec2(f.b + 0.5 * o.door_m * u), f.normal});
    }
    return out;
  };
  // The path but its first and last end_m (where it crossed the doorways it
  // was cut at), every 40th part at most.
  auto inner = [&](const std::vector<Vec2>& path) {
    double total = 0.0;
    std::vector<double> at(path.size(), 0.0);
    for (size_t k = 1; k < path.size(); ++k) at[k] = total += (path[k] - path[k - 1]).norm();
    std::vector<Vec2> out;
    for (size_t k = 0; k < path.size(); ++k)
      if (at[k] >= o.end_m && at[k] <= total - o.end_m) out.push_back(path[k]);
    return Thin(out.empty() ? path : out, 40);
  };
  const std::vector<Vec2> a = inner(stored_path);
  const std::vector<Vec2> b = inner(TransformPath(stored_from_new, new_path));
  // The share of 'to' in sight of some point of 'from', through 'faces'.
  auto share_seen = [&](const std::vector<Vec2>& from, const std::vector<Vec2>& to,
                        const std::vector<FacedSegment>& faces) {
    int seen = 0;
    for (const Vec2& q : to)
      for (const Vec2& p : from)
        if (!Blocked(p, q, faces, o.margin_m)) {
          ++seen;
          break;
        }
    return static_cast<double>(seen) / static_cast<double>(to.size());
  };
  // Both ASRs' walls: each sees the wall between two rooms, with its own gaps.
  std::vector<FacedSegment> walls = closed(stored_faces, Pose2{});
  for (const FacedSegment& f : closed(new_faces, stored_from_new)) walls.push_back(f);
  return std::max(share_seen(a, b, walls), share_seen(b, a, walls));
}

bool SameSpace(const std::vector<Vec2>& stored_path, const std::vector<FacedSegment>& stored_faces,
               const std::vector<Vec2>& new_path, const std::vector<FacedSegment>& new_faces,
               const Pose2& stored_from_new, const SameSpaceOptions& o) {
  return SameSpaceShare(stored_path, stored_faces, new_path, new_faces, stored_from_new, o) >= o.min_share;
}

MapOptimizer::MapOptimizer(const MapOptimizerOptions& options)
    : options_(options), estimator_(options.heading) {
  graph_.SetRatesHeldAtOffsets(options_.drift_known);
}

// The walls the ASR keeps when they differ from those matched (the cone
// grid's: asr::MapperOptions::cone_output_walls), bent with the drift found as
// the matched ones are. A fresh ASR holds them as walls_local and
// output_walls_local; a stored one as matched_walls_local and walls_local.
void MapOptimizer::SetOutputWalls(Node* n, const asr::Asr& a) {
  n->output_walls.reset();
  n->output_walls_seen_s.clear();
  if (a.has_output_walls) n->output_walls = a.output_walls_local;
  else if (a.has_matched_walls) n->output_walls = a.walls_local;
  if (!a.has_matched_walls && a.has_output_walls) n->output_walls_seen_s = a.output_walls_seen_s;
}

MapOptimizer::Node MapOptimizer::MakeNode(const asr::Asr& a) const {
  Node n;
  n.asr_id = a.id;
  n.raw = a.world_from_local_raw;
  n.path_raw = a.path;
  n.path_turn = a.path_turn_rad;
  n.turn_after = a.turn_after_path_rad;
  n.pre_rate = a.pre_bend_rad_per_m;
  const Pose2 local_from_world = a.world_from_local_raw.inverse();
  // The path in the frame its walls were mapped in.
  std::vector<Pose2> scratch;
  const std::vector<Pose2>& mapped = MappedPath(n, &scratch);
  Vec2 last(1e18, 1e18);
  for (const Pose2& p : mapped) {
    const Vec2 q = local_from_world * p.translation();
    if ((q - last).norm() >= 0.2 || n.path_local.empty()) {
      n.path_local.push_back(q);
      last = q;
    }
  }
  if (!mapped.empty() && n.path_local.back() != local_from_world * mapped.back().translation())
    n.path_local.push_back(local_from_world * mapped.back().translation());
  // The walls matched (registration, loop closure, consistency); the walls
  // the ASR keeps, when they differ, are its callers' (SetOutputWalls).
  n.walls = a.has_matched_walls ? a.matched_walls_local : a.walls_local;
  for (const asr::Exit& e : a.exits)
    n.exits_local.emplace_back(a.world_from_local_raw.inverse() * e.center_m, 0.5 * e.width_m);
  // Where each vertex was seen from: known for the ASRs of this run as
  // mapped (walls_local, output_walls_local), not for stored ones.
  if (!a.has_matched_walls) n.walls_seen_s = a.walls_seen_s;
  n.faces = FaceWalls(n.walls, n.path_local);
  // The samples and the face index are made again when a loop closure needs
  // them (TryLoopClosures, a few candidates per ASR) rather than kept for
  // every ASR of the run.
  n.sample_count = static_cast<int>(SampleFaces(n.faces, options_.registration.sample_step_m).size());
  // Centre and radius of everything the ASR holds (walls and path).
  Vec2 lo(1e18, 1e18), hi(-1e18, -1e18);
  auto grow = [&](const Vec2& p) {
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
  };
  for (const auto& f : n.faces) {
    grow(f.a);
    grow(f.b);
  }
  for (const auto& p : n.path_local) grow(p);
  if (lo.x() > hi.x()) lo = hi = Vec2(0, 0);
  n.centre_local = 0.5 * (lo + hi);
  n.box_lo = lo;
  n.box_hi = hi;
  n.radius_m = 0.5 * (hi - lo).norm();
  return n;
}

void MapOptimizer::AddStored(const asr::Asr& stored, int room_id) {
  Node n = MakeNode(stored);
  SetOutputWalls(&n, stored);
  n.stored = true;
  n.room_id = room_id >= 0 ? room_id : stored.id;
  graph_.AddNode(stored.world_from_local_corrected, /*fixed=*/true, n.pre_rate);
  node_of_asr_[stored.id] = static_cast<int>(nodes_.size());
  nodes_.push_back(std::move(n));
  searched_at_.push_back(stored.world_from_local_corrected);
}

class MapOptimizer::Prepared : public asr::PlacementWork {
 public:
  Node node;
  localize::DirectionEstimate estimate;
  std::vector<SplitDirection> split;
  double seconds = 0.0;
};

std::unique_ptr<asr::PlacementWork> MapOptimizer::Prepare(const asr::Asr& a) const {
  const auto t0 = std::chrono::steady_clock::now();
  auto p = std::make_unique<Prepared>();
  Node& node = p->node;
  node = MakeNode(a);
  node.room_id = a.id;
  // Wall direction (raw world frame) -> local frame.
  p->estimate = estimator_.Estimate(a);
  const localize::DirectionEstimate& est = p->estimate;
  if (est.accepted && std::isfinite(est.uncertainty_rad)) {
    node.direction = true;
    node.direction_local = est.direction_rad - a.world_from_local_raw.theta;
    node.direction_sigma_measured = options_.direction_sigma_scale * est.uncertainty_rad;
    p->split = SplitDirections(node, a);
  }
  p->seconds = Seconds(t0);
  return p;
}

asr::Asr MapOptimizer::Place(asr::Asr a, std::unique_ptr<asr::PlacementWork> work) {
  const auto t0 = std::chrono::steady_clock::now();
  if (!dynamic_cast<Prepared*>(work.get())) work = Prepare(a);
  Prepared* prepared = static_cast<Prepared*>(work.get());
  solve_seconds_ += prepared->seconds;
  Node node = std::move(prepared->node);
  // The walls the ASR keeps, as it is now (a sonar's cone grid is
  // vectorised after Prepare).
  SetOutputWalls(&node, a);
  const int idx = static_cast<int>(nodes_.size());
  last_estimate_ = std::move(prepared->estimate);
  const localize::DirectionEstimate& est = last_estimate_;
  if (idx == 0) {
    graph_.AddNode(a.world_from_local_raw, /*fixed=*/true, node.pre_rate);
  } else {
    const Node& prev = nodes_[idx - 1];
    // Odometry from the previous ASR's origin to this one's, through its
    // path, as the previous ASR was mapped (its pre-bend removed: the graph
    // bends it by the rest of the drift, rate - pre_rate).
    std::vector<Pose2> path;
    path.reserve(prev.path_raw.size() + 1);
    path.assign(prev.path_raw.begin(), prev.path_raw.end());
    path.push_back(a.world_from_local_raw);
    // The turns between the poses (on the spot too), where the previous ASR
    // knows them; taken from its node, which needs them for this factor only.
    std::vector<double> turns;
    turns.swap(nodes_[idx - 1].path_turn);
    if (turns.size() == prev.path_raw.size() && !turns.empty()) turns.push_back(prev.turn_after);
    else turns.clear();
    const OdometryMeasurement m = MeasureOdometry(asr::CorrectedPath(path, prev.raw, Pose2{}, prev.pre_rate),
                                                  options_.odometry, 24, turns.empty() ? nullptr : &turns);
    driven_m_ += m.distance_m;
    // Prediction with the previous node's drift rate.
    const double r = graph_.rate(idx - 1) - prev.pre_rate;
    Vec2 t(0, 0);
    for (const auto& st : m.steps) t += RotateAbout(Vec2(st.x(), st.y()), Vec2(0, 0), -r * st.z());
    const Pose2 predicted = graph_.pose(idx - 1) * Pose2{t.x(), t.y(), m.delta.theta - r * m.distance_m};
    graph_.AddNode(predicted, /*fixed=*/false, node.pre_rate);
    graph_.AddOdometry(idx - 1, idx, m, options_.odometry);
    // d(delta)/d(rate) at rate 0: each step turned by -rate x the distance before it.
    for (const auto& st : m.steps) node.odo_by_rate.head<2>() += st.z() * Eigen::Vector2d(st.y(), -st.x());
    node.odo_by_rate.z() = -m.distance_m;
    // Uncertainty accumulated for the candidate search: the translation
    // variance of the odometry plus the heading uncertainty turned lateral.
    const double prev_sigma = DirectionSigma(prev.direction_sigma_measured);
    const double heading_sigma2 =
        prev.direction ? prev_sigma * prev_sigma : std::min(prev.heading_var, kPi * kPi / 16.0);
    node.heading_var = heading_sigma2 + m.covariance(2, 2);
    node.var_prefix = prev.var_prefix + m.covariance(0, 0) + m.covariance(1, 1) +
                      heading_sigma2 * m.distance_m * m.distance_m;
    // Registration against the previous ASR (across the exit).
    if (!prev.faces.empty() && !node.faces.empty()) {
      // The walls are raw: so is the registration, and its guess is the raw
      // odometry (the graph's prediction without the drift's bend).
      const Pose2 guess = graph_.Bend(idx - 1, m).inverse() * graph_.pose(idx - 1).inverse() * graph_.pose(idx);
      // The odometry's covariance of the guess (with the drift rate's
      // uncertainty in the heading, as in the gate below), turned from the
      // end pose's frame into the previous ASR's. With it the registration
      // keeps the guess along what the walls cannot tell better than the
      // odometry; without it, ICP slid a corridor's walls along their
      // length to wherever they overlapped most (hallway_loop: 2-19 m, up
      // to three door periods, all rejected by the gate below). Only a
      // registration that determines all three directions better than the
      // odometry is a factor.
      Eigen::Matrix3d prior = m.covariance;
      prior(2, 2) += std::pow(options_.odometry.rate_prior_sigma_rad_per_m * m.distance_m, 2);
      prior = TurnedCovariance(prior, m.delta.theta);
      Registration reg = RegisterWalls(prev.faces, node.faces, guess, options_.registration, &prior);
      if (reg.converged && reg.match_fraction >= options_.min_match_fraction && reg.matches >= options_.min_matches &&
          reg.degenerate_directions == 0) {
        // Gate against the odometry: both can be wrong, the test uses both
        // covariances (drift-rate uncertainty folded into the heading).
        // Both in the end pose's frame (the registration's covariance turned
        // from the previous ASR's: across a turn a corridor's weak axis is
        // another axis there), as the difference and the factor take them.
        const Eigen::Matrix3d reg_cov = CovarianceInSourceFrame(reg);
        Eigen::Matrix3d S = reg_cov + m.covariance;
        S(2, 2) += std::pow(options_.odometry.rate_prior_sigma_rad_per_m * m.distance_m, 2);
        const Eigen::Vector3d d = Difference(guess, reg.target_from_source);
        const double d2 = d.dot(S.ldlt().solve(d));
        if (d2 <= ChiSquareQuantile(options_.gate_probability, 3)) {
          graph_.AddRelative(idx - 1, idx, reg.target_from_source, reg_cov, FactorKind::kRegistration, 2.0, &m);
          ++registrations_;
        }
      }
    }
  }
  if (node.direction) {
    const std::vector<SplitDirection>& split = prepared->split;
    // The walls were seen along the whole path: on average half-way.
    double len = 0.0;
    for (size_t k = 1; k < node.path_raw.size(); ++k)
      len += (node.path_raw[k].translation() - node.path_raw[k - 1].translation()).norm();
    // Where along the path the direction was seen: each of its walls
    // somewhere on it (spread L / sqrt(12)), the direction a mean over
    // about effective_edges of them.
    const int whole = graph_.AddDirection(
        idx, node.direction_local, node.direction_sigma_measured, 0.5 * len, options_.direction_sigma_floor_rad, 2.0,
        len / std::sqrt(12.0 * std::max(1.0, est.effective_edges)));
    const double sigma = DirectionSigma(node.direction_sigma_measured);
    const double w = 1.0 / (sigma * sigma), s_seen = driven_m_ + 0.5 * len;
    pre_w_ += w;
    pre_ws_ += w * s_seen;
    pre_wss_ += w * s_seen * s_seen;
    ++pre_n_;
    if (split.size() >= 2) {
      // The groups are tried in Finish in place of the whole; until then
      // they wait, disabled.
      Split sp{whole, {}};
      for (const SplitDirection& d : split) {
        sp.groups.push_back(
            graph_.AddDirection(idx, d.direction_local, d.sigma_measured, d.s_mean_m, options_.direction_sigma_floor_rad,
                                2.0, options_.direction_split_m / std::sqrt(12.0 * std::max(1.0, d.effective_edges))));
        graph_.SetFactorEnabled(sp.groups.back(), false);
      }
      splits_.push_back(std::move(sp));
    }
  }
  node_of_asr_[a.id] = idx;
  nodes_.push_back(std::move(node));
  searched_at_.push_back(graph_.pose(idx));

  const size_t closures_before = closures_.size();
  if (idx > 0) TryLoopClosures(idx);
  // A closure frees the whole loop: every node from the oldest stored ASR it
  // reaches to the new one (at least the local window), the nodes before it
  // held as the anchor; a full solve when one is due (full_solve_growth) or
  // at the end of the run.
  int first_free = std::max(1, idx - options_.window + 1);
  bool closed_loop = false;
  for (size_t k = closures_before; k < closures_.size(); ++k) {
    if (!closures_[k].accepted) continue;
    closed_loop = true;
    first_free = std::min(first_free, std::max(1, node_of_asr_.at(closures_[k].from_asr)));
  }
  const bool full_due = idx - last_full_solve_ >= std::max<double>(options_.window, options_.full_solve_growth * idx);
  if (idx > 0 && full_due) {
    graph_.Solve(0, options_.full_iterations);
    last_full_solve_ = idx;
  } else if (idx > 0) {
    graph_.Solve(first_free, closed_loop ? options_.full_iterations : options_.local_iterations);
  }
  const Pose2 T = graph_.pose(idx);
  a.world_from_local_corrected = T;
  a.heading_correction_rad = NormalizeAngle(T.theta - a.world_from_local_raw.theta);
  a.heading_uncertainty_rad = nodes_[idx].direction ? DirectionSigma(nodes_[idx].direction_sigma_measured) : -1.0;
  solve_seconds_ += Seconds(t0);
  return a;
}

std::vector<MapOptimizer::SplitDirection> MapOptimizer::SplitDirections(const Node& n, const asr::Asr& a) const {
  std::vector<SplitDirection> out;
  if (!(options_.direction_split_m > 0.0) || n.path_local.size() < 2) return out;
  // The groups' directions come from the EM on their walls alone. Where the
  // heading estimate needs the room's grid (sonar, whose polylines wobble:
  // HeadingCorrectionOptions::grid_refine), a few metres of walls alone give
  // no trustworthy direction: no split (measured on nine_rooms with 16
  // sonars: wall p95 0.36 -> 0.85 m with split sonar walls).
  if (estimator_.options().grid_refine) return out;
  std::vector<double> s(n.path_local.size(), 0.0);
  for (size_t k = 1; k < n.path_local.size(); ++k) s[k] = s[k - 1] + (n.path_local[k] - n.path_local[k - 1]).norm();
  const double length = s.back();
  const int bins = static_cast<int>(std::floor(length / options_.direction_split_m));
  if (bins < 2) return out;
  struct Edge {
    localize::WallDirection d;
    double s;
  };
  std::vector<std::vector<Edge>> by_bin(bins);
  for (const Polyline& line : a.has_matched_walls ? a.matched_walls_local : a.walls_local) {
    for (size_t i = 1; i < line.size(); ++i) {
      const Vec2 e = line[i] - line[i - 1];
      const double len = e.norm();
      if (!(len > 1e-6) || !std::isfinite(len)) continue;
      // Where along the path the edge was seen from: the grid holds every
      // reading of it, so its direction is the mean of the headings of all
      // the path points within sight (split_sight_m), not of the nearest
      // one (a wall passed twice, or seen while driving towards it, was
      // drawn from several; the nearest alone compressed the slope: 2 deg/m
      // read as 0.6-1.6). None within sight: the nearest.
      const Vec2 mid = 0.5 * (line[i] + line[i - 1]);
      size_t best = 0;
      double best_d2 = std::numeric_limits<double>::infinity(), s_sum = 0.0;
      int seen = 0;
      const double sight2 = options_.split_sight_m * options_.split_sight_m;
      for (size_t k = 0; k < n.path_local.size(); ++k) {
        const double d2 = (n.path_local[k] - mid).squaredNorm();
        if (d2 < best_d2) {
          best_d2 = d2;
          best = k;
        }
        if (d2 <= sight2) {
          s_sum += s[k];
          ++seen;
        }
      }
      const double s_edge = seen > 0 ? s_sum / seen : s[best];
      const int b = std::clamp(static_cast<int>(s_edge / (length / bins)), 0, bins - 1);
      by_bin[b].push_back({{localize::FoldToQuarterTurn(std::atan2(e.y(), e.x())), len}, s_edge});
    }
  }
  // Walls in local raw coordinates: the local frame's axes are the raw
  // world's (theta of world_from_local_raw), as for the whole-ASR factor.
  // The groups' standard errors stay asymptotic: a group holds few edges by
  // construction, and the slope test below, not each group's own gate, keeps
  // noise out. Neither the small-sample correction nor the run's pooled
  // spread fits them: the whole ASRs' spread holds the very drift the groups
  // measure (cluttered_lab laser at 1 deg/m: with them no group passed, the
  // drift went uncorrected, heading error 0.3 -> 5 degrees).
  localize::RobustEmOptions split_em = estimator_.options().robust;
  split_em.small_sample_correction = false;
  for (const auto& edges : by_bin) {
    std::vector<localize::WallDirection> dirs;
    double sw = 0.0, w = 0.0;
    for (const Edge& e : edges) {
      localize::WallDirection d = e.d;
      d.folded_rad = localize::FoldToQuarterTurn(d.folded_rad + a.world_from_local_raw.theta);
      dirs.push_back(d);
      sw += e.s * e.d.length_m;
      w += e.d.length_m;
    }
    if (dirs.empty()) continue;
    const localize::DirectionEstimate est = localize::EstimateDirectionRobust(dirs, split_em);
    if (!est.accepted || !std::isfinite(est.uncertainty_rad)) continue;
    out.push_back({est.direction_rad - a.world_from_local_raw.theta, sw / w,
                   options_.direction_sigma_scale * est.uncertainty_rad, est.effective_edges});
  }
  // Only when the groups' directions turn with the distance driven beyond
  // their uncertainties: the weighted least-squares slope of direction over
  // s (a drift rate seen inside the ASR) must differ from zero at the drift
  // test's level. Walls that agree are better read as one factor, and noise
  // in small groups must not bend a good room.
  if (out.size() < 2) return {};
  const double ref = out.front().direction_local;
  double W = 0.0, Ws = 0.0, Wss = 0.0, Wy = 0.0, Wsy = 0.0;
  for (const SplitDirection& d : out) {
    const double sigma = DirectionSigma(d.sigma_measured);
    const double w = 1.0 / (sigma * sigma);
    const double y = localize::FoldToQuarterTurn(d.direction_local - ref);
    W += w;
    Ws += w * d.s_mean_m;
    Wss += w * d.s_mean_m * d.s_mean_m;
    Wy += w * y;
    Wsy += w * d.s_mean_m * y;
  }
  const double det = W * Wss - Ws * Ws;
  if (!(det > 0.0)) return {};
  const double slope = (W * Wsy - Ws * Wy) / det;
  const double chi2 = slope * slope / (W / det);
  if (chi2 <= ChiSquareQuantile(options_.drift_test_probability, 1)) return {};
  return out;
}

OdometryMeasurement MapOptimizer::PathTo(const Node& n, const Vec2& local_point) const {
  const Pose2 local_from_world = n.raw.inverse();
  std::vector<Pose2> scratch;
  const std::vector<Pose2>& mapped = MappedPath(n, &scratch);
  size_t best = 0;
  double best_d2 = std::numeric_limits<double>::infinity();
  for (size_t t = 0; t < mapped.size(); ++t) {
    const double d2 = (local_from_world * mapped[t].translation() - local_point).squaredNorm();
    if (d2 < best_d2) {
      best_d2 = d2;
      best = t;
    }
  }
  std::vector<Pose2> path;
  path.reserve(best + 1);
  for (size_t t = 0; t <= best && t < mapped.size(); ++t) path.push_back(local_from_world * mapped[t]);
  return MeasureOdometry(path, options_.odometry);
}

namespace {
Vec2 Centroid(const std::vector<FacedPoint>& pts) {
  Vec2 c(0, 0);
  for (const auto& p : pts) c += p.p;
  return pts.empty() ? c : Vec2(c / static_cast<double>(pts.size()));
}
}  // namespace

std::vector<FacedPoint> MapOptimizer::InBox(const std::vector<FacedPoint>& pts, const Node& n) const {
  std::vector<FacedPoint> out;
  const double m = 0.5;
  for (const auto& p : pts)
    if (p.p.x() >= n.box_lo.x() - m && p.p.x() <= n.box_hi.x() + m && p.p.y() >= n.box_lo.y() - m &&
        p.p.y() <= n.box_hi.y() + m)
      out.push_back(p);
  return out;
}

MapOptimizer::CandidateEval MapOptimizer::EvaluateCandidate(int n, int k,
                                                           const std::vector<FacedPoint>& cur_samples) const {
  const Node& cur = nodes_[n];
  const Node& o = nodes_[k];
  const std::vector<FacedPoint> o_samples = SampleFaces(o.faces, options_.registration.sample_step_m);
  const double cos_max = options_.registration.max_normal_angle_rad;
  CandidateEval ev;
  // The graph's pose of the new ASR in the stored one's frame, and the
  // same for the raw walls: each node's walls bent back by its drift rate
  // where they may overlap (the path pose nearest the other's centre).
  ev.rate_k = graph_.rate(k) - o.pre_rate;
  ev.rate_n = graph_.rate(n - 1) - cur.pre_rate;
  ev.placed = graph_.pose(k).inverse() * graph_.pose(n);
  const Pose2 guess = BendAt(PathTo(o, ev.placed * cur.centre_local), ev.rate_k).inverse() * ev.placed *
                      BendAt(PathTo(cur, ev.placed.inverse() * o.centre_local), ev.rate_n);
  // Correlative search over the pose uncertainty (positions and headings
  // within the gate), scored by how many of the new ASR's wall samples land
  // on a matching face; ICP from the best distinct starts. Distinct good
  // solutions mean the walls cannot tell the places apart.
  const double var_here = std::max(0.0, cur.var_prefix - o.var_prefix) + 0.01;
  const double radius = std::min(options_.candidate_sigmas * std::sqrt(var_here), options_.max_search_m);
  const double hsig = std::sqrt(cur.heading_var + o.heading_var) + DegToRad(1.0);
  const double hrange = std::min(options_.candidate_sigmas * hsig, options_.max_search_rad);
  std::vector<FacedPoint> coarse;
  for (size_t i = 0; i < cur_samples.size(); i += 3) coarse.push_back(cur_samples[i]);
  struct Start {
    Pose2 pose;
    double score;
  };
  std::vector<Start> starts;
  const double step = options_.search_step_m, hstep = options_.search_step_rad;
  std::vector<double> shifts;
  for (double d = -radius; d <= radius + 1e-9; d += step) shifts.push_back(d);
  const Vec2 centre = guess * cur.centre_local;
  for (double dth = -hrange; dth <= hrange + 1e-9; dth += hstep) {
    // Rotate about the new ASR's centre; every shift of the rotated samples
    // scored at once. Matched samples (not a fraction): two long ASRs
    // overlap only in part.
    const Pose2 rotated = Pose2{centre.x(), centre.y(), dth} * Pose2{-centre.x(), -centre.y(), 0.0} * guess;
    const std::vector<int> matched = AgreementOverShifts(o.faces, TransformPoints(rotated, coarse), shifts, shifts,
                                                         options_.loop_tolerance_m, cos_max);
    for (size_t i = 0; i < shifts.size(); ++i) {
      for (size_t j = 0; j < shifts.size(); ++j) {
        const double dx = shifts[i], dy = shifts[j];
        if (dx * dx + dy * dy > radius * radius + 1e-9) continue;
        starts.push_back({Pose2{dx, dy, 0.0} * rotated, static_cast<double>(matched[i * shifts.size() + j])});
      }
    }
  }
  std::sort(starts.begin(), starts.end(), [](const Start& a, const Start& b) { return a.score > b.score; });
  std::vector<Pose2> chosen;
  for (const Start& st : starts) {
    if (chosen.size() >= 3 || st.score <= 0.0) break;
    bool distinct = true;
    for (const Pose2& p : chosen) {
      const Eigen::Vector3d dd = Difference(p, st.pose);
      if (dd.head<2>().norm() < 0.5 && std::abs(dd(2)) < DegToRad(5.0)) distinct = false;
    }
    if (distinct) chosen.push_back(st.pose);
  }
  int best_matches = 0, best_overlap = 0;  // why nothing came of them, if nothing did
  for (const Pose2& start : chosen) {
    Registration reg = RegisterWalls(o.faces, cur.faces, start, options_.registration);
    best_matches = std::max(best_matches, reg.matches);
    if (!reg.converged || reg.matches < options_.min_matches) continue;
    // Agreement where the two overlap: the samples of each that fall in the
    // other's box (walls the other could have seen).
    const auto pts_in_o = InBox(TransformPoints(reg.target_from_source, cur_samples), o);
    const auto o_in_cur = InBox(TransformPoints(reg.target_from_source.inverse(), o_samples), cur);
    const int overlap = static_cast<int>(std::min(pts_in_o.size(), o_in_cur.size()));
    best_overlap = std::max(best_overlap, overlap);
    if (overlap < options_.min_matches) continue;
    const double a1 = AgreementFraction(o.faces, pts_in_o, options_.loop_tolerance_m, cos_max);
    const double a2 = AgreementFraction(cur.faces, o_in_cur, options_.loop_tolerance_m, cos_max);
    ev.sols.push_back({reg, std::min(a1, a2), Centroid(pts_in_o), Centroid(o_in_cur)});
  }
  std::sort(ev.sols.begin(), ev.sols.end(),
            [](const CandidateSolution& a, const CandidateSolution& b) { return a.agreement > b.agreement; });
  if (ev.sols.empty()) {
    const std::string need = " (at least " + std::to_string(options_.min_matches) + ")";
    ev.reason = chosen.empty() ? "no placement within the search range puts a wall sample on a matching face"
                : best_matches < options_.min_matches
                    ? "too few wall samples matched after ICP: " + std::to_string(best_matches) + need
                    : "too little overlap: " + std::to_string(best_overlap) + " wall samples in each other's box" +
                          need;
  }
  return ev;
}

std::optional<Vec2> MapOptimizer::AlongTheWalls(const std::vector<Eigen::Vector3d>& alternatives,
                                                const Eigen::Matrix3d& cov,
                                                const std::vector<FacedSegment>& faces) const {
  // The heading: each alternative within three sigmas of the best (both
  // registrations' sigma, taken as the best's), a degree at least.
  const double heading_tol = std::max(DegToRad(1.0), 3.0 * std::sqrt(2.0 * std::max(0.0, cov(2, 2))));
  const Eigen::Vector3d* far = nullptr;
  for (const Eigen::Vector3d& a : alternatives) {
    if (std::abs(a(2)) > heading_tol) return std::nullopt;
    if (!far || a.head<2>().norm() > far->head<2>().norm()) far = &a;
  }
  if (!far || far->head<2>().norm() < 0.3) return std::nullopt;
  const Vec2 u = far->head<2>().normalized(), across(-u.y(), u.x());
  // On one line through the best: across it within three sigmas of the
  // walls' covariance and the agreement's tolerance.
  const double sigma_across = std::sqrt(std::max(0.0, across.dot(cov.topLeftCorner<2, 2>() * across)));
  for (const Eigen::Vector3d& a : alternatives)
    if (std::abs(across.dot(a.head<2>())) > options_.loop_tolerance_m + 3.0 * std::sqrt(2.0) * sigma_across)
      return std::nullopt;
  // The walls run along it: a corridor repeats along its length, not across.
  double along = 0.0, total = 0.0;
  const double cos_tol = std::cos(options_.walls_along_rad);
  for (const FacedSegment& f : faces) {
    const Vec2 e = f.b - f.a;
    const double len = e.norm();
    if (!(len > 0.0)) continue;
    total += len;
    if (std::abs(e.dot(u)) >= cos_tol * len) along += len;
  }
  if (!(total > 0.0) || along < options_.walls_along_share * total) return std::nullopt;
  return u;
}

namespace {

// Wall samples against the walls of another ASR (its frame), each face seen
// from either side: on a wall (within 'tolerance_m' of one), in front of the
// nearest wall (in the free space it was seen from: the other ASR saw no
// wall there), or behind it (space the other did not see: counted in
// neither).
struct SeenSamples {
  int on_walls = 0;
  int in_front = 0;
};
SeenSamples SeenBy(const std::vector<FacedSegment>& faces, const std::vector<FacedPoint>& pts, double tolerance_m) {
  SeenSamples out;
  for (const FacedPoint& q : pts) {
    double residual = 0.0;
    const int f = NearestFaceByScan(faces, q.p, q.normal, std::numeric_limits<double>::infinity(), -2.0, &residual);
    if (f < 0) continue;
    if (PointSegmentDistance(q.p, faces[f].a, faces[f].b) <= tolerance_m) ++out.on_walls;
    else if (residual > tolerance_m) ++out.in_front;
  }
  return out;
}

}  // namespace

std::optional<MapOptimizer::NextDoor> MapOptimizer::NextDoorWithinGate(
    int n, int k, const Pose2& best, const Pose2& predicted, const Eigen::Matrix3d& S, double gate,
    const OdometryMeasurement& to_k, const OdometryMeasurement& to_n, double rate_k, double rate_n,
    const std::vector<FacedPoint>& cur_samples) const {
  const Node& cur = nodes_[n];
  // The new ASR's walls' directions (modulo a quarter turn, by length) and
  // its extent along each: a room beside it lies at least that far over.
  double c4 = 0.0, s4 = 0.0;
  for (const FacedSegment& f : cur.faces) {
    const Vec2 e = f.b - f.a;
    const double a4 = 4.0 * std::atan2(e.y(), e.x()), len = e.norm();
    c4 += len * std::cos(a4);
    s4 += len * std::sin(a4);
  }
  if (cur.faces.empty()) return std::nullopt;
  const double dir = 0.25 * std::atan2(s4, c4);
  const Vec2 axes[2] = {Vec2(std::cos(dir), std::sin(dir)), Vec2(-std::sin(dir), std::cos(dir))};
  const Eigen::LDLT<Eigen::Matrix3d> solver(S);
  std::optional<NextDoor> out;
  for (const Vec2& u : axes) {
    double lo = std::numeric_limits<double>::infinity(), hi = -lo;
    for (const FacedSegment& f : cur.faces) {
      lo = std::min({lo, f.a.dot(u), f.b.dot(u)});
      hi = std::max({hi, f.a.dot(u), f.b.dot(u)});
    }
    for (const double sign : {-1.0, 1.0}) {
      const Vec2 shift = sign * (hi - lo) * u;
      const Pose2 beside = best * Pose2{shift.x(), shift.y(), 0.0};
      const Eigen::Vector3d d = Difference(predicted, beside);
      const double m2 = d.dot(solver.solve(d));
      if (!(m2 <= gate)) continue;
      // Ruled out where the stored map shows otherwise (each stored ASR as
      // the graph holds it): the new ASR's path through a stored ASR's walls
      // there, a stored path through its walls, or walls where the other saw
      // none: of the wall samples of each that fall in the other's box, fewer
      // than loop_min_agreement lie on a wall of the other, seen from either
      // side (the wall between two rooms is seen from both). Space nobody
      // mapped rules nothing out.
      const Pose2 world = graph_.pose(k) * BendAt(to_k, rate_k) * beside * BendAt(to_n, rate_n).inverse();
      const Vec2 centre = world * cur.centre_local;
      bool ruled_out = false;
      for (int j = 0; j + 1 < n && !ruled_out; ++j) {
        const Node& o = nodes_[j];
        if ((graph_.pose(j) * o.centre_local - centre).norm() > o.radius_m + cur.radius_m) continue;
        const Pose2 rel = graph_.pose(j).inverse() * world;
        if (PathWallCrossings(o.faces, TransformPath(rel, cur.path_local)) +
                PathWallCrossings(cur.faces, TransformPath(rel.inverse(), o.path_local)) >
            0) {
          ruled_out = true;
          break;
        }
        const auto cur_in_o = InBox(TransformPoints(rel, cur_samples), o);
        const auto o_in_cur =
            InBox(TransformPoints(rel.inverse(), SampleFaces(o.faces, options_.registration.sample_step_m)), cur);
        const SeenSamples a = SeenBy(o.faces, cur_in_o, options_.loop_tolerance_m);
        const SeenSamples b = SeenBy(cur.faces, o_in_cur, options_.loop_tolerance_m);
        const int seen = a.on_walls + a.in_front + b.on_walls + b.in_front;
        ruled_out = seen >= options_.min_matches && a.on_walls + b.on_walls < options_.loop_min_agreement * seen;
      }
      if (ruled_out) continue;
      if (!out) out = NextDoor{shift, m2, 0.0};
      else if (m2 < out->mahalanobis2) out->shift = shift, out->mahalanobis2 = m2;
      out->likelihood += std::exp(-0.5 * m2);
    }
  }
  return out;
}

int MapOptimizer::TryLoopClosures(int n, SearchAgain* again) {
  Node& cur = nodes_[n];
  if (cur.sample_count < options_.min_matches) return 0;
  const std::vector<FacedPoint> cur_samples = SampleFaces(cur.faces, options_.registration.sample_step_m);
  const Vec2 cn = graph_.pose(n) * cur.centre_local;
  struct Cand {
    int k;
    double score;
  };
  std::vector<Cand> cands;
  for (int k = 0; k + 1 < n; ++k) {
    const Node& o = nodes_[k];
    if (o.sample_count < options_.min_matches) continue;
    if (again) {
      if (again->skip.count({k, n})) continue;
      // The graph's prediction of n in k's frame against the one n's search
      // had (k's pose then taken as the one k had when it was new): one that
      // moved by less than a step of the correlative search is searched as
      // before.
      const Eigen::Vector3d moved =
          Difference(searched_at_[k].inverse() * searched_at_[n], graph_.pose(k).inverse() * graph_.pose(n));
      if (moved.head<2>().norm() < options_.search_step_m && std::abs(moved(2)) < options_.search_step_rad) continue;
    }
    const double var = std::max(0.0, cur.var_prefix - o.var_prefix) + 0.01;
    const double gate = options_.candidate_sigmas * std::sqrt(var);
    const double dist = (graph_.pose(k) * o.centre_local - cn).norm();
    const double reach = o.radius_m + cur.radius_m + gate;
    if (dist > reach) continue;
    cands.push_back({k, dist / reach});
  }
  std::sort(cands.begin(), cands.end(), [](const Cand& a, const Cand& b) { return a.score < b.score; });
  if (cands.size() > static_cast<size_t>(options_.max_candidates)) cands.resize(options_.max_candidates);
  // Each candidate's search and ICP read the graph and the nodes only: with
  // two threads the candidates are shared out (the same results, decided in
  // the same order below).
  std::vector<CandidateEval> evals(cands.size());
  ForEachShared(cands.size(), options_.threads,
                [&](size_t i) { evals[i] = EvaluateCandidate(n, cands[i].k, cur_samples); });
  std::vector<Implied> implied;
  int accepted = 0;
  // Where the candidate's record goes: a new one, or (searched again) the
  // pair's earlier record, replaced.
  auto record = [&](const LoopClosure& lc, int k) -> size_t {
    if (again) {
      const auto it = again->record.find({k, n});
      if (it != again->record.end()) {
        closures_[it->second] = lc;
        return it->second;
      }
    }
    closures_.push_back(lc);
    return closures_.size() - 1;
  };
  for (size_t ci = 0; ci < cands.size(); ++ci) {
    const int k = cands[ci].k;
    const CandidateEval& ev = evals[ci];
    const Node& o = nodes_[k];
    LoopClosure lc;
    lc.from_asr = o.asr_id;
    lc.to_asr = cur.asr_id;
    if (ev.sols.empty()) {
      lc.reason = ev.reason;
      record(lc, k);
      continue;
    }
    const std::vector<CandidateSolution>& sols = ev.sols;
    const CandidateSolution& best = sols.front();
    const double rate_k = ev.rate_k, rate_n = ev.rate_n;
    const Pose2& placed = ev.placed;
    lc.relative = best.reg.target_from_source;
    lc.agreement = best.agreement;
    lc.rmse_m = best.reg.rmse_m;
    // Gate against the prediction and its uncertainty.
    const double var = std::max(0.0, cur.var_prefix - o.var_prefix) + 0.01;
    // Distinct placements that fit about as well: the walls cannot tell
    // them apart. When they all lie along the new ASR's walls (a corridor),
    // the closure holds across the walls only.
    std::vector<Eigen::Vector3d> alternatives;  // each in the best's frame
    for (size_t s = 1; s < sols.size(); ++s) {
      const Eigen::Vector3d dd = Difference(best.reg.target_from_source, sols[s].reg.target_from_source);
      if ((dd.head<2>().norm() > 0.3 || std::abs(dd(2)) > DegToRad(5.0)) &&
          sols[s].agreement >= options_.ambiguity_ratio * best.agreement)
        alternatives.push_back(dd);
    }
    bool ambiguous = !alternatives.empty();
    // The walls' covariance in the new ASR's frame, as the difference below
    // and the closure factor take it.
    Eigen::Matrix3d reg_cov = CovarianceInSourceFrame(best.reg);
    if (ambiguous && options_.closures_across_walls) {
      if (const std::optional<Vec2> along = AlongTheWalls(alternatives, reg_cov, cur.faces)) {
        const Eigen::Vector3d u(along->x(), along->y(), 0.0);
        reg_cov += kUnknownAlongWalls * u * u.transpose();
        ambiguous = false;
        lc.across_walls_only = true;
      }
    }
    Eigen::Matrix3d S = reg_cov;
    S(0, 0) += var;
    S(1, 1) += var;
    S(2, 2) += cur.heading_var + o.heading_var + DegToRad(1.0) * DegToRad(1.0);
    // Where the walls overlap: each node's raw path to there, for the bend.
    const OdometryMeasurement to_k = PathTo(o, best.overlap_in_o);
    const OdometryMeasurement to_n = PathTo(cur, best.overlap_in_cur);
    const Pose2 predicted_raw = BendAt(to_k, rate_k).inverse() * placed * BendAt(to_n, rate_n);
    const Eigen::Vector3d d = Difference(predicted_raw, best.reg.target_from_source);
    lc.mahalanobis2 = d.dot(S.ldlt().solve(d));
    // Free space: neither ASR's path may cross the other's walls.
    const int cross = PathWallCrossings(o.faces, TransformPath(best.reg.target_from_source, cur.path_local)) +
                      PathWallCrossings(cur.faces, TransformPath(best.reg.target_from_source.inverse(), o.path_local));
    // On one wall of the stored ASR (a line: two constraints on three
    // unknowns) every pose sliding along it, with the heading its line
    // gives, fits exactly: no residual, so nothing checks the closure, and
    // the sigma of its heading is the residual floor's, not the line's
    // (bench/never_worse: 30 of 265 accepted closures were such; one of
    // their runs came out worse than its odometry without a warning).
    // Two collinear pieces of one wall count as two faces: not caught here.
    if (best.agreement < options_.loop_min_agreement) lc.reason = "walls disagree";
    else if (best.reg.faces_matched < 2)
      lc.reason = "the walls meet on one wall only (every pose along it fits exactly: nothing checks the closure)";
    else if (ambiguous) lc.reason = "ambiguous: another placement fits as well";
    else if (cross > 0) lc.reason = "a path crosses the other's walls";
    else if (lc.mahalanobis2 > ChiSquareQuantile(options_.gate_probability, 3)) lc.reason = "too far from the prediction";
    else if (options_.closure_next_door && !lc.across_walls_only) {
      if (const std::optional<NextDoor> nd =
              NextDoorWithinGate(n, k, best.reg.target_from_source, predicted_raw, S,
                                 ChiSquareQuantile(options_.gate_probability, 3), to_k, to_n, rate_k, rate_n,
                                 cur_samples))
        if (std::exp(-0.5 * lc.mahalanobis2) < options_.next_door_min_odds * nd->likelihood)
          lc.reason = "ambiguous: the room next door (" + std::to_string(nd->shift.norm()).substr(0, 4) +
                      " m over) is about as likely (Mahalanobis^2 " + std::to_string(nd->mahalanobis2).substr(0, 4) +
                      " against " + std::to_string(lc.mahalanobis2).substr(0, 4) + ")";
    }
    if (!lc.reason.empty()) {
      record(lc, k);
      continue;
    }
    lc.accepted = true;
    lc.reason = lc.across_walls_only ? "accepted across the walls only (along them another placement fits as well)"
                                     : "accepted";
    if (again) lc.reason += " (searched again at the end of the run)";
    if (best.agreement >= options_.same_room_agreement && !lc.across_walls_only)
      lc.same_space = SameSpaceShare(o.path_local, o.faces, cur.path_local, cur.faces, best.reg.target_from_source,
                                     options_.same_space);
    lc.same_room = lc.same_space >= options_.same_space.min_share;
    if (lc.same_room) cur.room_id = o.room_id;
    closure_factor_.push_back(
        graph_.AddRelative(k, n, best.reg.target_from_source, reg_cov, FactorKind::kLoopClosure, 2.0, &to_k, &to_n));
    const size_t at = record(lc, k);
    closure_index_.push_back(static_cast<int>(at));
    const Pose2 implied_pose =
        graph_.pose(k) * BendAt(to_k, rate_k) * best.reg.target_from_source * BendAt(to_n, rate_n).inverse();
    implied.push_back({at, closure_factor_.size() - 1, k, implied_pose, TurnedCovariance(reg_cov, implied_pose.theta)});
    ++accepted;
  }
  // Two closures of the new ASR must place it alike: the stored ASRs they
  // reach are held to each other by the graph (closely, when they are
  // neighbours), so the two places they imply differ by no more than their
  // covariances and the odometry between the two stored ASRs allow. When
  // they differ more, one of them is wrong and the walls cannot say which
  // (hallway_loop driven twice: its new corridor piece closed on the two
  // stored pieces it overlaps, 2-5 m apart along the corridor, both wrong);
  // neither is kept. The closures of the ASR before it count too, carried
  // to this one by the graph's odometry between the two.
  const size_t own = implied.size();
  if (prev_implied_node_ == n - 1) {
    const Pose2 step = graph_.pose(n - 1).inverse() * graph_.pose(n);
    const double var_step = std::max(0.0, cur.var_prefix - nodes_[n - 1].var_prefix);
    const double heading_step = std::max(0.0, cur.heading_var - nodes_[n - 1].heading_var);
    for (Implied im : prev_implied_) {
      if (!closures_[im.closure].accepted) continue;
      im.world = im.world * step;
      im.cov(0, 0) += var_step;
      im.cov(1, 1) += var_step;
      im.cov(2, 2) += heading_step;
      implied.push_back(im);
    }
  }
  const double gate3 = ChiSquareQuantile(options_.gate_probability, 3);
  std::vector<int> disagrees(implied.size(), -1);
  for (size_t a = 0; a < implied.size(); ++a)
    for (size_t b = a + 1; b < implied.size(); ++b) {
      const Implied &A = implied[a], &B = implied[b];
      Eigen::Matrix3d C = A.cov + B.cov;
      const double between = std::abs(nodes_[A.k].var_prefix - nodes_[B.k].var_prefix) + 0.01;
      C(0, 0) += between;
      C(1, 1) += between;
      C(2, 2) += std::abs(nodes_[A.k].heading_var - nodes_[B.k].heading_var) + DegToRad(1.0) * DegToRad(1.0);
      // C is along the map's axes, the difference along A's.
      const Eigen::Vector3d d = Difference(A.world, B.world);
      C = TurnedCovariance(C, -A.world.theta);
      if (d.dot(C.ldlt().solve(d)) > gate3) {
        if (disagrees[a] < 0) disagrees[a] = static_cast<int>(b);
        if (disagrees[b] < 0) disagrees[b] = static_cast<int>(a);
      }
    }
  bool dropped = false;
  for (size_t a = 0; a < implied.size(); ++a) {
    if (disagrees[a] < 0) continue;
    const Implied& other = implied[disagrees[a]];
    LoopClosure& lc = closures_[implied[a].closure];
    lc.accepted = false;
    lc.same_room = false;
    lc.reason = "disagrees with the closure to ASR " + std::to_string(nodes_[other.k].asr_id) + " (places it " +
                std::to_string((implied[a].world.translation() - other.world.translation()).norm()).substr(0, 4) +
                " m apart)";
    graph_.SetRelativeEnabled(closure_factor_[implied[a].factor], false);
    dropped = true;
    if (a < own) --accepted;
  }
  if (dropped) AssignRoomIds();
  implied.resize(own);
  prev_implied_ = std::move(implied);
  prev_implied_node_ = n;
  return accepted;
}

int MapOptimizer::SearchClosuresAgain() {
  SearchAgain again;
  // A pair once accepted keeps its factor and its record (standing, or
  // dropped as contradicted or disagreeing: the graph and the other
  // closures that judged it still do), and is not searched again.
  for (size_t k = 0; k < closure_factor_.size(); ++k) {
    const LoopClosure& lc = closures_[closure_index_[k]];
    again.skip.insert({node_of_asr_.at(lc.from_asr), node_of_asr_.at(lc.to_asr)});
  }
  for (size_t i = 0; i < closures_.size(); ++i) {
    const std::pair<int, int> pair{node_of_asr_.at(closures_[i].from_asr), node_of_asr_.at(closures_[i].to_asr)};
    if (!again.skip.count(pair)) again.record[pair] = i;
  }
  prev_implied_node_ = -1;
  prev_implied_.clear();
  int accepted = 0;
  for (int n = 1; n < size(); ++n)
    if (!nodes_[n].stored) accepted += TryLoopClosures(n, &again);
  return accepted;
}

void MapOptimizer::AssignRoomIds() {
  // Room identities from the closures that stand (a dropped closure no
  // longer makes its ASR a revisit).
  for (auto& n : nodes_)
    if (!n.stored) n.room_id = n.asr_id;
  for (const LoopClosure& lc : closures_)
    if (lc.accepted && lc.same_room) nodes_[node_of_asr_[lc.to_asr]].room_id = nodes_[node_of_asr_[lc.from_asr]].room_id;
}

MapOptimizer::Consistency MapOptimizer::MapConsistency(const std::vector<Pose2>& poses,
                                                       const std::vector<double>& rates) const {
  // World walls and paths; pairs tested only where their boxes overlap (a
  // uniform grid of the boxes keeps this linear in the map's size).
  const size_t N = nodes_.size();
  std::vector<std::vector<FacedSegment>> walls(N);
  std::vector<std::vector<Vec2>> paths(N);
  std::vector<Eigen::Vector4d> box(N);  // of the walls
  for (size_t i = 0; i < N; ++i) {
    // With a drift rate, the walls and path as the placement has them
    // (re-integrated inside the ASR); the faces keep the sides they had.
    const double r = rates.empty() ? 0.0 : rates[i];
    if (r != nodes_[i].pre_rate && !nodes_[i].stored) {
      const std::vector<Vec2> path_local = LocalCorrectedPath(nodes_[i], r);
      walls[i] = TransformFaces(poses[i], FaceWalls(BendWalls(nodes_[i], r), path_local));
      paths[i] = TransformPath(poses[i], path_local);
    } else {
      walls[i] = TransformFaces(poses[i], nodes_[i].faces);
      paths[i] = TransformPath(poses[i], nodes_[i].path_local);
    }
    Eigen::Vector4d b(1e18, 1e18, -1e18, -1e18);
    for (const auto& f : walls[i])
      for (const Vec2& p : {f.a, f.b}) b = Eigen::Vector4d(std::min(b(0), p.x()), std::min(b(1), p.y()),
                                                           std::max(b(2), p.x()), std::max(b(3), p.y()));
    for (const auto& p : paths[i]) b = Eigen::Vector4d(std::min(b(0), p.x()), std::min(b(1), p.y()),
                                                       std::max(b(2), p.x()), std::max(b(3), p.y()));
    box[i] = b;
  }
  const double cell = 5.0;
  auto cells = [&](const Eigen::Vector4d& b, auto&& f) {
    for (long gx = static_cast<long>(std::floor(b(0) / cell)); gx <= static_cast<long>(std::floor(b(2) / cell)); ++gx)
      for (long gy = static_cast<long>(std::floor(b(1) / cell)); gy <= static_cast<long>(std::floor(b(3) / cell)); ++gy)
        f(gx, gy);
  };
  std::map<std::pair<long, long>, std::vector<int>> grid;
  for (size_t i = 0; i < N; ++i)
    if (box[i](0) <= box[i](2)) cells(box[i], [&](long x, long y) { grid[{x, y}].push_back(static_cast<int>(i)); });
  // Each ASR's doorways as placed: centre and the radius around it where no
  // crossing counts (none when the margin is 0).
  std::vector<std::vector<std::pair<Vec2, double>>> doors(N);
  if (options_.consistency_door_margin_m > 0.0)
    for (size_t i = 0; i < N; ++i)
      for (const auto& [c, half] : nodes_[i].exits_local)
        doors[i].emplace_back(poses[i] * c, half + options_.consistency_door_margin_m);
  auto near_door = [&](const Vec2& m, size_t of) {
    for (const auto& [c, r] : doors[of])
      if ((m - c).norm() <= r) return true;
    return false;
  };
  Consistency out;
  for (size_t i = 0; i < N; ++i) {
    if (box[i](0) > box[i](2)) continue;
    std::vector<int> others;
    cells(box[i], [&](long x, long y) {
      if (auto it = grid.find({x, y}); it != grid.end()) others.insert(others.end(), it->second.begin(), it->second.end());
    });
    std::sort(others.begin(), others.end());
    others.erase(std::unique(others.begin(), others.end()), others.end());
    others.erase(std::remove(others.begin(), others.end(), static_cast<int>(i)), others.end());
    // The path away from the doorways of i and of each other ASR j: its
    // pieces between them (consistency_door_margin_m).
    std::vector<char> at_own_door(paths[i].size(), 0);
    for (size_t k = 1; k < paths[i].size(); ++k) at_own_door[k] = near_door(0.5 * (paths[i][k] + paths[i][k - 1]), i);
    for (int j : others) {
      std::vector<Vec2> piece;
      auto flush = [&] {
        out.crossings += PathWallCrossings(walls[j], piece);
        piece.clear();
      };
      for (size_t k = 1; k < paths[i].size(); ++k) {
        const Vec2 m = 0.5 * (paths[i][k] + paths[i][k - 1]);
        if (at_own_door[k] || near_door(m, static_cast<size_t>(j))) {
          flush();
          continue;
        }
        if (piece.empty()) piece.push_back(paths[i][k - 1]);
        piece.push_back(paths[i][k]);
      }
      flush();
    }
    // Path inside another ASR's box: where its walls could contradict it.
    for (size_t k = 1; k < paths[i].size(); ++k) {
      const Vec2 m = 0.5 * (paths[i][k] + paths[i][k - 1]);
      if (at_own_door[k]) continue;
      for (int j : others)
        if (m.x() >= box[j](0) && m.x() <= box[j](2) && m.y() >= box[j](1) && m.y() <= box[j](3) &&
            !near_door(m, static_cast<size_t>(j))) {
          out.overlap_m += (paths[i][k] - paths[i][k - 1]).norm();
          break;
        }
    }
  }
  return out;
}

std::vector<Vec2> MapOptimizer::LocalCorrectedPath(const Node& n, double rate) const {
  std::vector<Vec2> out;
  Vec2 last(1e18, 1e18);
  for (const Pose2& p : asr::CorrectedPath(n.path_raw, n.raw, Pose2{}, rate))
    if ((p.translation() - last).norm() >= 0.2) {
      out.push_back(p.translation());
      last = p.translation();
    }
  return out;
}

bool MapOptimizer::LessConsistent(const Consistency& a, const Consistency& b) {
  // Crossings per metre of path that overlaps another ASR: a map spread out
  // by drift overlaps little and crosses little, a compact one overlaps much.
  // 'a' is worse when its count exceeds b's rate over a's overlap by more
  // than 3 Poisson sigmas.
  const double rate = (b.crossings + 1.0) / std::max(b.overlap_m, 1.0);
  const double expected = rate * std::max(a.overlap_m, 1.0);
  return a.crossings > expected + 3.0 * std::sqrt(expected);
}

MapOptimizer::DriftDecision MapOptimizer::TestDrift(bool likelihood_ratio_only) {
  DriftDecision out;
  graph_.SetRatesFixedAtZero(false);
  PoseGraph::SolveSummary with_drift = graph_.Solve(0, options_.full_iterations);
  // Is there drift at all? The graph with every rate held at zero is the
  // nested model; the rates stay only if they lower the (robust) cost by
  // more than the 99 % chi-square quantile of one degree of freedom
  // (likelihood-ratio test). A few wall directions far apart, each known
  // modulo a quarter turn, can otherwise fit a confident wrong drift.
  PoseGraph::State drift_state = graph_.Save();
  graph_.SetRatesFixedAtZero(true);
  PoseGraph::SolveSummary no_drift = graph_.Solve(0, options_.full_iterations);
  PoseGraph::State no_drift_state = graph_.Save();
  // A likelihood ratio compares the two models at their own best fits, and
  // the wall directions' quarter-turn branches give each model many local
  // ones. The nested model solved from the drift's solution keeps that
  // solution's branches: it is solved again from the odometry (the
  // dead-reckoned poses; the stored nodes where they are), and the better
  // of the two is its fit. When that fits better than the drift's own, the
  // drift's solve had stopped in a worse basin (the nested model lies inside
  // it): it is solved again from there. (CARMEN fhw as a 16-sonar ring, no
  // drift: from the drift's solution the nested model's cost was 57.7,
  // from the odometry 7.4, against the drift's 26.1; the test had found a
  // drift of 2.26 deg/m, ATE 35.7 m against its exact input.)
  {
    const std::vector<Pose2> now = CurrentPoses();
    for (int i = 0; i < static_cast<int>(nodes_.size()); ++i)
      graph_.set_pose(i, nodes_[i].stored ? now[i] : nodes_[i].raw);
    const PoseGraph::SolveSummary from_odometry = graph_.Solve(0, options_.full_iterations);
    if (from_odometry.final_cost < no_drift.final_cost) {
      no_drift = from_odometry;
      no_drift_state = graph_.Save();
    }
    graph_.Restore(no_drift_state);
    if (no_drift.final_cost < with_drift.final_cost) {
      graph_.SetRatesFixedAtZero(false);
      const PoseGraph::SolveSummary again = graph_.Solve(0, options_.full_iterations);
      if (again.final_cost < with_drift.final_cost) {
        with_drift = again;
        drift_state = graph_.Save();
      }
      graph_.SetRatesFixedAtZero(true);
      graph_.Restore(no_drift_state);
    }
  }
  graph_.SetRatesFixedAtZero(false);
  graph_.Restore(drift_state);
  const double rate = MeanRate();
  graph_.SetRatesFixedAtZero(true);
  graph_.Restore(no_drift_state);
  out.free_state = drift_state;
  out.held_state = no_drift_state;
  out.chi2 = 2.0 * (no_drift.final_cost - with_drift.final_cost);
  const double quantile = ChiSquareQuantile(options_.drift_test_probability, 1);
  out.detected = out.chi2 > quantile;
  if (likelihood_ratio_only) return out;
  // The minima of the rates: the drift's own and its aliases.
  int solved = 0;
  double gap = 0.0;
  std::vector<RateMinimum> minima = FindRateMinima(rate, with_drift.final_cost, drift_state, quantile, &solved, &gap);
  size_t best = 0;
  for (size_t k = 1; k < minima.size(); ++k)
    if (minima[k].cost < minima[best].cost) best = k;
  // The drift model at its best fit: the likeliest of its minima (its solve
  // may have stopped in a basin near no drift, the drift's own lying a few
  // aliases away: CARMEN fhw as a 16-sonar ring at 1 deg/m, the solve from
  // the nested model's fit at -0.11 deg/m, the scan's best at 1.0).
  out.chi2 = 2.0 * (no_drift.final_cost - minima[best].cost);
  out.detected = out.chi2 > quantile;
  // Each minimum is a hypothesis of the map, weighed by its likelihood
  // relative to the best: the covariances (Finish) hold them all, whichever
  // is kept, since a Gaussian about the kept one alone says nothing of a
  // quarter-turn alias that fits almost as well (aria/triangle with 8
  // sonars at 2 deg/m: no drift found, the truth on an alias 90 degrees
  // away, 0 of 3 ASRs within 3 sigma).
  // (The graph is restored to the hypothesis kept below.)
  for (const RateMinimum& m : minima) {
    graph_.Restore(m.state);
    out.hypotheses.push_back({m.rate, std::exp(-(m.cost - minima[best].cost)), CurrentPoses()});
  }
  if (!out.detected) {
    // Aliases that fit about as well as the drift's own basin: the drift is
    // left at zero (the test found none), and the user is told.
    int close = 0;
    size_t nearest = 0, likeliest = 0;
    for (size_t k = 1; k < minima.size(); ++k)
      if (2.0 * (minima[k].cost - minima[0].cost) < quantile) {
        if (close == 0 || std::abs(minima[k].rate) < std::abs(minima[nearest].rate)) nearest = k;
        if (close == 0 || minima[k].cost < minima[likeliest].cost) likeliest = k;
        ++close;
      }
    // The nearest rate, and the likeliest when that is another (a sparse
    // ring on a real building: the nearest -1.6 deg/m, the likeliest 2.3
    // with three quarters of the likelihood).
    auto deg = [](double rad) { return std::to_string(RadToDeg(rad)).substr(0, 5); };
    std::string which = deg(minima[nearest].rate) + " deg/m the nearest";
    if (likeliest != nearest && minima[likeliest].cost < minima[0].cost)
      which += ", " + deg(minima[likeliest].rate) + " the likeliest";
    if (close > 0)
      out.warning = "no drift found, but " + std::to_string(close) + (close == 1 ? " other rate" : " other rates") +
                    " (" + which + ") fit the wall directions about as well; the uncertainties hold them";
    graph_.SetRatesFixedAtZero(true);
    graph_.Restore(no_drift_state);
    if (options_.drift_known) out.detected = true;  // held at the drift removed (SetRatesHeldAtOffsets)
    return out;
  }
  // The most likely of the minima is the drift; the others its aliases,
  // weighed together: the drift's odds are its likelihood over theirs summed.
  if (best != 0) out.chi2 = 2.0 * (no_drift.final_cost - minima[best].cost);
  double alias_weight = 0.0;
  int close = 0;
  for (size_t k = 0; k < minima.size(); ++k) {
    if (k == best) continue;
    const double d = 2.0 * (minima[k].cost - minima[best].cost);
    out.alias_chi2 = std::min(out.alias_chi2, d);
    alias_weight += std::exp(-0.5 * d);
    if (d < quantile) {
      out.alias_risk = true;
      ++close;
    }
  }
  const double found_rate = minima[best].rate;
  // With aliases, more hypotheses were tried: the drift must beat no drift
  // at the test's level divided among them (Bonferroni), and its aliases
  // together by the odds asked for.
  const double strict = ChiSquareQuantile(1.0 - (1.0 - options_.drift_test_probability) / (1 + std::max(2, solved)), 1);
  const double odds = alias_weight > 0.0 ? 1.0 / alias_weight : std::numeric_limits<double>::infinity();
  const bool beats_alias = odds >= std::max(1.0, options_.alias_min_odds);
  const bool keep = !out.alias_risk || (out.chi2 > strict && beats_alias);
  if (keep) {
    graph_.SetRatesFixedAtZero(false);
    graph_.Restore(minima[best].state);
  } else {
    graph_.SetRatesFixedAtZero(true);
    graph_.Restore(no_drift_state);
  }
  if (out.alias_risk)
    out.warning = "the drift rate is ambiguous: " + std::to_string(RadToDeg(found_rate)).substr(0, 5) + " deg/m and " +
                  std::to_string(close) + (close == 1 ? " other rate" : " other rates") +
                  " fit the wall directions about as well (" + std::to_string(static_cast<int>(gap)) +
                  " m without one); " +
                  (keep          ? "kept the most likely"
                   : beats_alias ? "not corrected (no drift is about as likely)"
                                 : "not corrected (odds " + std::to_string(odds).substr(0, 4) +
                                       ":1 against its aliases: a coin toss)");
  out.detected = keep || options_.drift_known;
  return out;
}

std::vector<MapOptimizer::RateMinimum> MapOptimizer::FindRateMinima(double rate, double cost,
                                                                    const PoseGraph::State& state, double quantile,
                                                                    int* solved, double* gap_m) {
  const int N = static_cast<int>(nodes_.size());
  // Aliasing: wall directions known modulo 90 degrees and far apart are
  // fitted as well by a rate that turns the heading by a quarter turn
  // more between them (the start of the run counts as a direction: its
  // heading is known).
  double s = 0.0, last = 0.0, gap = 0.0;
  for (int i = 0; i < N; ++i) {
    if (nodes_[i].stored) continue;
    if (nodes_[i].direction) {
      gap = std::max(gap, s - last);
      last = s;
    }
    for (size_t t = 1; t < nodes_[i].path_local.size(); ++t)
      s += (nodes_[i].path_local[t] - nodes_[i].path_local[t - 1]).norm();
  }
  gap = std::max(gap, s - last);
  *gap_m = gap;
  // The aliases: other rates the wall directions may fit about as well. The
  // direction factors' cost over a common change of every rate
  // (PoseGraph::DirectionProfile: the odometry does not resist such a
  // change, the loop closures do) is sampled at a sixteenth of its finest
  // period (a quarter turn over the whole path) for every rate within the
  // prior's 3 sigma; its lowest local minima outside the drift's own basin
  // are each solved from their own dead-reckoned start (at most
  // max_drift_aliases). A quarter turn more over the longest stretch
  // without a wall direction is one such rate; on a long sonar run with few
  // directions there are many (CARMEN intel as a 16-sonar ring, 1 deg/m
  // added: minima every 0.2-0.4 deg/m, five of them within the test's
  // quantile of the best).
  std::vector<RateMinimum> minima{{rate, cost, state}};
  if (gap > 1.0 && s > 0.0) {
    const double period = (kPi / 2.0) / s;
    const double step = period / 16.0;
    const double limit = 3.0 * options_.odometry.rate_prior_sigma_rad_per_m;
    // On a long run, as much of that range around the drift as some 4
    // million factor evaluations reach (the nearest aliases first).
    const double factors = static_cast<double>(std::max<size_t>(1, nodes_.size() + closure_factor_.size()));
    const double budget = std::max(2000.0, 4e6 / factors);
    double lo = -limit, hi = limit;
    if ((hi - lo) / step > budget) {
      lo = std::max(-limit, rate - 0.5 * budget * step);
      hi = std::min(limit, rate + 0.5 * budget * step);
    }
    std::vector<double> deltas;
    for (double r = lo; r <= hi; r += step) deltas.push_back(r - rate);
    graph_.SetRatesFixedAtZero(false);
    graph_.Restore(state);  // the profile is taken about the drift's solution
    const std::vector<double> profile = graph_.DirectionProfile(deltas);
    const size_t n_d = profile.size();
    if (n_d >= 3) {
      // The drift's own basin: downhill from delta = 0.
      size_t home = 0;
      for (size_t k = 1; k < n_d; ++k)
        if (std::abs(deltas[k]) < std::abs(deltas[home])) home = k;
      while (home > 0 && profile[home - 1] < profile[home]) --home;
      while (home + 1 < n_d && profile[home + 1] < profile[home]) ++home;
      std::vector<size_t> cands;
      for (size_t k = 1; k + 1 < n_d; ++k)
        if (k != home && profile[k] <= profile[k - 1] && profile[k] <= profile[k + 1] &&
            2.0 * (profile[k] - profile[home]) < 2.0 * quantile)
          cands.push_back(k);
      std::sort(cands.begin(), cands.end(), [&](size_t a, size_t b) { return profile[a] < profile[b]; });
      if (cands.size() > static_cast<size_t>(options_.max_drift_aliases)) cands.resize(options_.max_drift_aliases);
      for (size_t k : cands) {
        graph_.ChainWithRate(rate + deltas[k]);
        const PoseGraph::SolveSummary a = graph_.Solve(0, options_.full_iterations);
        ++*solved;
        const double found = MeanRate();
        // A solve that went back nearer a minimum already found than a
        // quarter of the profile's period found the same map.
        bool same = false;
        for (const RateMinimum& m : minima) same = same || std::abs(found - m.rate) < 0.25 * period;
        if (!same) minima.push_back({found, a.final_cost, graph_.Save()});
      }
    }
  }
  return minima;
}

void MapOptimizer::SetSplitsEnabled(bool on) {
  for (const Split& sp : splits_) {
    graph_.SetFactorEnabled(sp.whole, !on);
    for (int g : sp.groups) {
      graph_.SetFactorEnabled(g, on);
      graph_.SetDirectionFamily(g, graph_.DirectionFamily(sp.whole));  // the ASR's building direction
    }
  }
}

constexpr double kQuarterTurn = kPi / 2.0;
// A change of building direction is judged on the mean of up to this many
// wall directions either side (a sparse ring's single room reads its walls
// a few degrees off).
constexpr int kWingStepRun = 3;
// SplitAtOneStep: the factors left out either side of the split (the rooms
// and corridor where the wings meet read between them), and so the least
// on each side (they and a run of kWingStepRun).
constexpr int kClear = 2;
constexpr int kWingSplitLeast = kClear + kWingStepRun;
// How many standard errors of their separation two groups of wall
// directions may lie under building_direction_min_rad and still be apart:
// the one-sided 99 % point of the normal.
constexpr double kApartZ = 2.326;

namespace {
// The window a group of wall directions is gathered in: as given, between
// half of min_rad and min_rad (0: half).
double GroupWidth(double min_rad, double width_rad) {
  return width_rad > 0.0 ? std::clamp(width_rad, 0.5 * min_rad, min_rad) : 0.5 * min_rad;
}

// The least separation two groups of wall directions 'd' apart (standard
// deviations sd_a and sd_b, n_a and n_b members) need to be apart: min_rad,
// or z standard errors of their separation under it when they are two
// clusters (every member nearer its own mean than the midpoint by two
// standard deviations: d at least four pooled deviations). A wing at
// min_rad is measured under it half the time (a laser's 15-degree wing at
// 14.9); a sparse ring's groups, a few degrees wide each, are not resolved
// so, and stay min_rad apart. z 0: min_rad.
double AllowedSeparation(double d, double min_rad, double sd_a, int n_a, double sd_b, int n_b, double z) {
  if (!(z > 0.0) || n_a < 2 || n_b < 2) return min_rad;
  const double pooled = std::sqrt(0.5 * (sd_a * sd_a + sd_b * sd_b));
  if (d < 4.0 * pooled) return min_rad;
  return min_rad - z * std::sqrt(sd_a * sd_a / n_a + sd_b * sd_b / n_b);
}

// The least separation the directions 'dirs' may keep when each of
// 'world' is tied to family[k]: for each pair, min_rad, or less within
// their standard errors when the two groups are clusters (AllowedSeparation).
double LeastApart(const std::vector<double>& world, const std::vector<int>& family, const std::vector<double>& dirs,
                  double min_rad) {
  std::vector<double> sd(dirs.size(), 0.0);
  std::vector<int> n(dirs.size(), 0);
  for (size_t f = 0; f < world.size(); ++f) {
    sd[family[f]] += std::pow(FoldQuarter(world[f] - dirs[family[f]]), 2);
    ++n[family[f]];
  }
  for (size_t k = 0; k < dirs.size(); ++k) sd[k] = std::sqrt(sd[k] / std::max(1, n[k] - 1));
  double least = min_rad;
  for (size_t k = 0; k < dirs.size(); ++k)
    for (size_t j = 0; j < k; ++j)
      least = std::min(least, AllowedSeparation(std::abs(FoldQuarter(dirs[k] - dirs[j])), min_rad, sd[k], n[k], sd[j],
                                                n[j], kApartZ));
  return least;
}

// Greedily: the widest group of angles (folded into a quarter turn) within
// a window 'width' wide (of equal counts, the narrowest), by a sliding
// window over them sorted (n log n); then the same among the rest, a group
// whose direction lies nearer than min_rad to one taken dropped, while a
// group of min_count or more is left. Each direction is its group's mean
// weighted by 'weights' (none: equal); a group takes the angles within
// min_rad less the window's half-width of it, so that one min_rad away
// keeps its own. The total count and squared spread are what the scan
// ranks by.
struct Gathering {
  int count = 0;
  double spread = 0.0;
  std::vector<double> directions;
  std::vector<double> deviations;  // each group's standard deviation, from its scatter
  std::vector<int> counts;         // and its size
};
Gathering Gather(const std::vector<double>& angles, const std::vector<double>* weights, double min_rad,
                 int min_count, int most, double width, double apart_z) {
  const double reach = min_rad - 0.5 * width;
  Gathering g;
  std::vector<std::pair<double, double>> u;  // (folded angle, weight)
  for (size_t k = 0; k < angles.size(); ++k) u.emplace_back(FoldQuarter(angles[k]), weights ? (*weights)[k] : 1.0);
  std::vector<std::pair<double, double>> ring;
  while (static_cast<int>(g.directions.size()) < most && static_cast<int>(u.size()) >= min_count) {
    std::sort(u.begin(), u.end());
    const size_t n = u.size();
    ring.assign(u.begin(), u.end());
    for (size_t k = 0; k < n; ++k) ring.emplace_back(u[k].first + kQuarterTurn, u[k].second);  // once round
    size_t best_first = 0, best_count = 0;
    double best_span = 0.0;
    for (size_t a = 0, b = 0; a < n; ++a) {
      b = std::max(b, a);
      while (b + 1 < a + n && ring[b + 1].first - ring[a].first <= width) ++b;
      const size_t count = b - a + 1;
      const double span = ring[b].first - ring[a].first;
      if (count > best_count || (count == best_count && span < best_span)) {
        best_count = count;
        best_first = a;
        best_span = span;
      }
    }
    if (static_cast<int>(best_count) < min_count) break;
    double sum = 0.0, wsum = 0.0;
    for (size_t k = best_first; k < best_first + best_count; ++k) {
      sum += ring[k].second * ring[k].first;
      wsum += ring[k].second;
    }
    const double mean = wsum > 0.0 ? sum / wsum : ring[best_first].first;
    double scatter = 0.0;
    for (size_t k = best_first; k < best_first + best_count; ++k)
      scatter += (ring[k].first - mean) * (ring[k].first - mean);
    const double sd = best_count > 1 ? std::sqrt(scatter / static_cast<double>(best_count - 1)) : 0.5 * width;
    bool apart = true;
    for (size_t j = 0; j < g.directions.size(); ++j) {
      const double d = std::abs(FoldQuarter(mean - g.directions[j]));
      apart = apart && d >= AllowedSeparation(d, min_rad, sd, static_cast<int>(best_count), g.deviations[j],
                                              g.counts[j], apart_z);
    }
    std::vector<std::pair<double, double>> rest;
    if (!apart) {
      // The tail of a group taken: its window's angles go, nothing is kept.
      const double lo = ring[best_first].first, hi = ring[best_first + best_count - 1].first;
      for (const auto& x : u) {
        const double e = FoldQuarter(x.first - lo);
        if (e < 0.0 || e > hi - lo) rest.push_back(x);
      }
      u.swap(rest);
      continue;
    }
    g.spread += scatter;
    g.count += static_cast<int>(best_count);
    g.directions.push_back(FoldQuarter(mean));
    g.deviations.push_back(sd);
    g.counts.push_back(static_cast<int>(best_count));
    for (const auto& x : u)
      if (std::abs(FoldQuarter(x.first - mean)) >= reach) rest.push_back(x);
    u.swap(rest);
  }
  return g;
}
}  // namespace

std::vector<double> BuildingDirections(const std::vector<double>& directions, const std::vector<double>& weights,
                                       double min_rad, int min_count, int most, double width_rad) {
  return Gather(directions, &weights, min_rad, min_count, most, GroupWidth(min_rad, width_rad), kApartZ).directions;
}

std::optional<WingScan> ScanBuildingDirections(const std::vector<PoseGraph::DirectionTerm>& terms, double lo,
                                               double hi, double step, double min_rad, int min_count, int most,
                                               const std::vector<double>& reference_rates, double width_rad) {
  const double width = GroupWidth(min_rad, width_rad);
  if (terms.empty() || !(step > 0.0) || !(hi >= lo)) return std::nullopt;
  std::vector<double> u(terms.size());
  auto at = [&](double r) {
    for (size_t t = 0; t < terms.size(); ++t) u[t] = FoldQuarter(terms[t].world + r * terms[t].slope);
  };
  // What one direction gathers at the rates found with one.
  int single = 0;
  for (double r : reference_rates) {
    at(r);
    single = std::max(single, Gather(u, nullptr, min_rad, 1, 1, width, 0.0).count);
  }
  Gathering best;
  double best_rate = 0.0;
  const int samples = static_cast<int>(std::floor((hi - lo) / step)) + 1;
  for (int k = 0; k < samples; ++k) {
    const double r = lo + k * step;
    at(r);
    Gathering g = Gather(u, nullptr, min_rad, min_count, most, width, 0.0);
    if (g.directions.size() >= 2 && (g.count > best.count || (g.count == best.count && g.spread < best.spread))) {
      best = std::move(g);
      best_rate = r;
    }
  }
  if (best.directions.size() < 2 || best.count < single + min_count) return std::nullopt;
  return WingScan{best_rate, best.count, single, best.directions};
}

namespace {
// Angles in the order given, on the circle of a quarter turn (times 4),
// as prefix sums: any run's circular scatter and mean in constant time.
class QuarterRuns {
 public:
  explicit QuarterRuns(const std::vector<double>& angles) : c_(angles.size() + 1, 0.0), s_(angles.size() + 1, 0.0) {
    for (size_t k = 0; k < angles.size(); ++k) {
      c_[k + 1] = c_[k] + std::cos(4.0 * angles[k]);
      s_[k + 1] = s_[k] + std::sin(4.0 * angles[k]);
    }
  }
  int size() const { return static_cast<int>(c_.size()) - 1; }
  // Run [a, b)'s scatter: its count less the length of its resultant.
  double Scatter(int a, int b) const { return (b - a) - std::hypot(c_[b] - c_[a], s_[b] - s_[a]); }
  double Mean(int a, int b) const { return 0.25 * std::atan2(s_[b] - s_[a], c_[b] - c_[a]); }
  // The split into [0, k) and [k, n), each 'least' or more, with the
  // least scatter summed: (k, that scatter), k -1 when there is none.
  std::pair<int, double> BestSplit(int least) const {
    std::pair<int, double> best{-1, std::numeric_limits<double>::infinity()};
    const int n = size();
    for (int k = least; k <= n - least; ++k) {
      const double cost = Scatter(0, k) + Scatter(k, n);
      if (cost < best.second) best = {k, cost};
    }
    return best;
  }

 private:
  std::vector<double> c_, s_;
};
}  // namespace

std::optional<double> ScanWingSplit(const std::vector<PoseGraph::DirectionTerm>& terms, double lo, double hi,
                                    double step, int least) {
  const int n = static_cast<int>(terms.size());
  if (least < 1 || n < 2 * least || !(step > 0.0) || !(hi >= lo)) return std::nullopt;
  std::vector<int> order(n);
  for (int k = 0; k < n; ++k) order[k] = k;
  std::stable_sort(order.begin(), order.end(), [&](int a, int b) { return terms[a].node < terms[b].node; });
  std::optional<double> best;
  double best_cost = std::numeric_limits<double>::infinity();
  std::vector<double> u(n);
  const int samples = static_cast<int>(std::floor((hi - lo) / step)) + 1;
  for (int i = 0; i < samples; ++i) {
    const double r = lo + i * step;
    for (int k = 0; k < n; ++k) u[k] = terms[order[k]].world + r * terms[order[k]].slope;
    const double cost = QuarterRuns(u).BestSplit(least).second;
    if (cost < best_cost) best_cost = cost, best = r;
  }
  return best;
}

WingSteps CountWingSteps(const std::vector<double>& world, const std::vector<int>& node,
                         const std::vector<int>& family, const std::vector<double>& directions, double tol_rad,
                         int run) {
  std::vector<size_t> order(world.size());
  for (size_t k = 0; k < order.size(); ++k) order[k] = k;
  std::stable_sort(order.begin(), order.end(), [&](size_t a, size_t b) { return node[a] < node[b]; });
  // Each factor's walls less its building direction.
  std::vector<double> off(order.size());
  for (size_t k = 0; k < order.size(); ++k) off[k] = FoldQuarter(world[order[k]] - directions[family[order[k]]]);
  auto fam = [&](size_t k) { return family[order[k]]; };
  // Whether the change into factor k (from k - 1) is a step.
  std::vector<int> step(order.size(), -1);  // -1: no change; 0: unsupported; 1: supported
  for (size_t k = 1; k < order.size(); ++k) {
    if (fam(k - 1) == fam(k)) continue;
    // The mean offset of up to 'run' factors either side of the change,
    // each side its own building direction's.
    double before = 0.0, after = 0.0;
    int nb = 0, na = 0;
    for (size_t i = k; i-- > 0 && nb < run && fam(i) == fam(k - 1);) before += off[i], ++nb;
    for (size_t j = k; j < order.size() && na < run && fam(j) == fam(k); ++j) after += off[j], ++na;
    step[k] = std::abs(after / na - before / nb) <= tol_rad ? 1 : 0;
  }
  WingSteps out;
  for (size_t k = 1; k < order.size(); ++k) {
    if (step[k] < 0) continue;
    // A room misread: tied to another direction than both its neighbours,
    // which share one and agree with each other within tol_rad, its walls
    // more than tol_rad off both of theirs, and neither change beside it a
    // step. Its two changes are not counted (a room's walls read 12
    // degrees off in a 20-degree wing, 16 sonars: two unsupported changes
    // beside the wing's one step). A room that reads the other building
    // direction is evidence of it and counts. A room where the odometry's
    // heading wanders across the half-way mark reads its walls as its
    // neighbours do, and under a drift read at the wrong rate the walls
    // turn from room to room (8 sonars at 2 deg/m read without drift:
    // 10-20 degrees): their changes count.
    auto misread = [&](size_t m) {
      return m > 0 && m + 1 < order.size() && fam(m - 1) == fam(m + 1) && fam(m) != fam(m - 1) && step[m] == 0 &&
             step[m + 1] == 0 && std::abs(FoldQuarter(world[order[m + 1]] - world[order[m - 1]])) <= tol_rad &&
             std::abs(FoldQuarter(world[order[m]] - world[order[m - 1]])) > tol_rad &&
             std::abs(FoldQuarter(world[order[m]] - world[order[m + 1]])) > tol_rad;
    };
    // So too the first or the last room of the run, which has one
    // neighbour: tied to another direction than the two rooms beside it,
    // which share one, its walls more than tol_rad off its neighbour's, and
    // the change beside it no step (rand40-5, 8 sonars, no drift, a
    // 30-degree wing: the first ASR read 44 degrees, its factor's sigma 15;
    // counted, its change left one step against one change that was none,
    // and the wing was squared onto the rest, heading median 12.3 degrees
    // against the odometry's 0.8).
    auto end_misread = [&](size_t m) {
      const size_t l = order.size() - 1;
      if (order.size() < 3 || (m != 0 && m != l)) return false;
      const size_t a = m == 0 ? 1 : l - 1, b = m == 0 ? 2 : l - 2;  // its neighbour, and the next
      const size_t change = m == 0 ? 1 : l;                         // between it and its neighbour
      return fam(a) == fam(b) && fam(m) != fam(a) && step[change] == 0 &&
             std::abs(FoldQuarter(world[order[m]] - world[order[a]])) > tol_rad;
    };
    if (misread(k) || misread(k - 1) || end_misread(k) || end_misread(k - 1)) continue;
    ++(step[k] ? out.supported : out.unsupported);
  }
  return out;
}

std::optional<WingSplit> SplitAtOneStep(const std::vector<double>& world, const std::vector<int>& node,
                                        double min_rad, int min_count, double tol_rad) {
  const int n = static_cast<int>(world.size());
  const int least = std::max(min_count, kWingSplitLeast);
  if (n < 2 * least) return std::nullopt;
  std::vector<int> order(n);
  for (int k = 0; k < n; ++k) order[k] = k;
  std::stable_sort(order.begin(), order.end(), [&](int a, int b) { return node[a] < node[b]; });
  std::vector<double> seen(n);
  for (int k = 0; k < n; ++k) seen[k] = world[order[k]];
  const QuarterRuns runs(seen);
  const int best = runs.BestSplit(least).first;
  if (best < 0) return std::nullopt;
  const double a = runs.Mean(0, best), b = runs.Mean(best, n);
  WingSplit out;
  out.directions = {FoldQuarter(a), FoldQuarter(b)};
  out.family.assign(n, 0);
  for (int k = best; k < n; ++k) out.family[order[k]] = 1;
  if (std::abs(FoldQuarter(b - a)) < LeastApart(world, out.family, out.directions, min_rad)) return std::nullopt;
  // The mean offset from side mean m of the three factors from 'from' on.
  auto offset = [&](int from, double m) {
    double sum = 0.0;
    for (int k = from; k < from + kWingStepRun; ++k) sum += FoldQuarter(world[order[k]] - m);
    return sum / kWingStepRun;
  };
  // The step: three factors either side, kClear clear of the split, each
  // less its side's mean.
  const double before = offset(best - kClear - kWingStepRun, a), after = offset(best + kClear, b);
  if (std::abs(after - before) > tol_rad) return std::nullopt;
  // And each side is level: the three factors at its far end read as the
  // three next to the split (kClear clear of it) do, within tol_rad or
  // half the step between the sides' means, whichever is more. A ramp (a
  // drift read at the held rates, or a wander) split in two has sides that
  // turn as much as the step between them; a wing's sides turn by what the
  // odometry's heading wanders along them, which grows with their length
  // and not with the step (rand44-37, 8 sonars, no drift, a 20-degree wing
  // of 114 ASRs: a step of 19.1 degrees, the first side 7.8 off level
  // after a wander of +-4 degrees and one room read 15 degrees; held to
  // tol_rad's 7.5 the wing was squared onto the rest, ATE 1.28 m against
  // the odometry's 0.29).
  const double level_tol = std::max(tol_rad, 0.5 * std::abs(FoldQuarter(b - a)));
  if (std::abs(offset(0, a) - before) > level_tol || std::abs(offset(n - kWingStepRun, b) - after) > level_tol)
    return std::nullopt;
  return out;
}

std::vector<double> BuildingDirectionsDeg(const OptimizerResult& r) {
  std::vector<double> out;
  for (double a : r.building_directions_rad) {
    const double deg = RadToDeg(a);
    out.push_back(deg - 90.0 * std::floor(deg / 90.0));
  }
  return out;
}

int MapOptimizer::TryBuildingDirections(DriftDecision* drift, double* chi2_out) {
  if (options_.max_building_directions < 2 || graph_.building_directions() != 1) return 0;
  // The one building direction, with the rates free: the cost more must
  // lower; and the map as decided: the consistency they must keep.
  const PoseGraph::State decided = graph_.Save();
  const bool decided_held = graph_.RatesFixedAtZero();
  graph_.SetRatesFixedAtZero(false);
  graph_.Restore(drift->free_state);
  const double cost_before = graph_.Cost();
  // The likelihood ratio is also taken with each model at its own
  // wall-direction variance component (a profile likelihood: -log L = cost
  // + the log of the directions' sigma scale, one per factor). A wing read
  // with one building direction is a misfit that component takes up: a
  // laser's 20-degree wing without drift put the wall directions' sigma
  // factor at 3.05, and at that sigma the wing lowered the cost by chi2 7.6
  // only (under the test's 10.8); at its own sigma (0.1) the wing explains
  // that excess, which the log term counts. A grouping that explains no
  // excess changes neither. The other
  // kinds' components stay as fitted: refitted too, the odometry headings'
  // (a row per ASR) shrank under any extra freedom (a 16-sonar run at 2
  // deg/m on a building without a wing: 0.61 -> 0.34, which alone passed
  // a false wing that took its wall p95 from 0.84 to 2.05 m).
  int direction_rows = 0;  // the same factors under every model, only their families differ
  for (const PoseGraph::FactorResidual& r : graph_.Residuals())
    if (r.enabled && r.kind == FactorKind::kDirection) direction_rows += r.dof;
  auto neg_log_l = [&]() {
    return graph_.Cost() + direction_rows * std::log(graph_.SigmaFactor(FactorKind::kDirection));
  };
  const double direction_sigma_before = graph_.SigmaFactor(FactorKind::kDirection);
  const double neg_log_l_before = neg_log_l();
  // The walls' directions along the odometry, dead-reckoned at the held
  // rates (no drift; with a second pass the drift removed while mapping)
  // and at the drift the rates found: a wing's step stands out there, while
  // a solved graph has already spread it over the odometry's heading noise
  // (a 30-degree wing, 16 sonars: every residual within 10 degrees). Each
  // grouping of two or more directions is a candidate, solved with the
  // rates free from there, each factor tied to its nearest direction.
  struct Candidate {
    double cost = std::numeric_limits<double>::infinity();
    std::vector<double> directions;
    std::vector<std::pair<int, int>> family;  // (factor handle, building direction)
    PoseGraph::State state;
    std::vector<Pose2> poses;  // the map it solved to, and its mean rate
    double rate = 0.0;
    double neg_log_l = std::numeric_limits<double>::infinity();  // at its own variance components
    // Solved, the least and the most its directions lie apart.
    double least_rad = std::numeric_limits<double>::infinity(), most_rad = 0.0;
    bool held = false;  // solved with the rates held at zero (a wing that needs no drift)
    // Solved with the rates held at zero: its cost, and whether the rates
    // lower it by more than the drift test's quantile (the walls need a
    // drift under this grouping).
    double held_cost = std::numeric_limits<double>::infinity();
    bool needs_drift = true;
    // The least separation its directions may keep, solved: min_rad, or
    // less within its groups' standard errors (AllowedSeparation).
    double apart_rad = 0.0;
  };
  graph_.Restore(drift->held_state);
  std::vector<std::pair<const PoseGraph::State*, double>> sources = {{&drift->held_state, MeanRate()}};
  graph_.Restore(drift->free_state);
  sources.emplace_back(&drift->free_state, MeanRate());
  graph_.Restore(drift->held_state);
  graph_.ChainWithRate(0.0);
  const std::vector<PoseGraph::DirectionTerm> terms = graph_.DirectionTerms();
  // How far apart the walls of one direction are read: within two of their
  // measured sigmas either way (the median factor's, before the variance
  // components, which a wing's misfit inflates), a quarter and a half of
  // the least separation at least and at most (a laser's rooms: 7.5 degrees
  // wide; a sonar ring's: 10-15).
  double width = 0.0;
  if (!terms.empty()) {
    std::vector<double> measured;
    for (const PoseGraph::DirectionTerm& t : terms) measured.push_back(t.measured_sigma);
    std::nth_element(measured.begin(), measured.begin() + measured.size() / 2, measured.end());
    width = GroupWidth(options_.building_direction_min_rad, 4.0 * measured[measured.size() / 2]);
  }
  // And at the rate at which the walls, dead-reckoned, gather best into
  // two or more directions (ScanBuildingDirections, over the rates within
  // the prior's 3 sigma every sixteenth of a quarter turn over the path):
  // a wing on top of a drift, which pulls the rates found with one
  // direction away from the truth (a 30-degree wing at 1 deg/m, 16 sonars:
  // 1.27 deg/m found).
  double s = 0.0;
  for (const PoseGraph::DirectionTerm& t : terms) s = std::max(s, std::abs(t.slope));
  if (s > 0.0 && static_cast<int>(terms.size()) >= 2 * options_.building_direction_min_asrs) {
    const double limit = 3.0 * options_.odometry.rate_prior_sigma_rad_per_m;
    // Some 4 million angle evaluations at most (the finest step kept).
    const double budget = std::max(2000.0, 4e6 / static_cast<double>(terms.size()));
    const double step = std::max((kQuarterTurn / s) / 16.0, 2.0 * limit / budget);
    const std::optional<WingScan> scan = ScanBuildingDirections(
        terms, -limit, limit, step, options_.building_direction_min_rad, options_.building_direction_min_asrs,
        options_.max_building_directions, {sources[0].second, sources[1].second}, width);
    if (scan) sources.emplace_back(&drift->held_state, scan->rate_rad_per_m);
    // And at the rate at which they split best into two level runs, one
    // before the robot passed into a wing and one after (ScanWingSplit): a
    // sonar ring's walls, read 5-10 degrees off now and then, do not gather
    // into groups 15-20 degrees apart by their directions alone, but they
    // do by where along the run they were seen (SplitAtOneStep, below).
    if (const std::optional<double> rate = ScanWingSplit(
            terms, -limit, limit, step, std::max(options_.building_direction_min_asrs, kWingSplitLeast)))
      sources.emplace_back(&drift->held_state, *rate);
  }
  // The least and the most the building directions lie apart, as solved.
  const auto spread = [&](double* least, double* most) {
    *least = std::numeric_limits<double>::infinity();
    *most = 0.0;
    for (int k = 0; k < graph_.building_directions(); ++k)
      for (int j = 0; j < k; ++j) {
        const double d = std::abs(FoldQuarter(graph_.building_direction(k) - graph_.building_direction(j)));
        *least = std::min(*least, d);
        *most = std::max(*most, d);
      }
  };
  std::vector<Candidate> candidates;
  for (const auto& [source, rate] : sources) {
    graph_.Restore(*source);
    graph_.ChainWithRate(rate);
    const std::vector<PoseGraph::DirectionTerm> rs = graph_.DirectionTerms();
    std::vector<double> world, weight;
    for (const PoseGraph::DirectionTerm& r : rs) {
      world.push_back(r.world);
      weight.push_back(1.0 / std::max(1e-12, r.sigma * r.sigma));
    }
    std::vector<double> dirs =
        BuildingDirections(world, weight, options_.building_direction_min_rad, options_.building_direction_min_asrs,
                           options_.max_building_directions, width);
    std::vector<int> family(rs.size(), 0), node(rs.size());
    for (size_t f = 0; f < rs.size(); ++f) {
      for (size_t k = 1; k < dirs.size(); ++k)
        if (std::abs(FoldQuarter(world[f] - dirs[k])) < std::abs(FoldQuarter(world[f] - dirs[family[f]])))
          family[f] = static_cast<int>(k);
      node[f] = rs[f].node;
    }
    // A wing begins where the robot passes into it: the walls of the ASRs
    // either side of each change of building direction turn by the step
    // between the two directions. A slow wander of the odometry's heading
    // over a long run gathers into groups too, split where it happens to
    // cross half-way between them (a generated 1000-room building, no wing:
    // 1 change of 227 at a step), and so does a drift read at another rate.
    // At most one change in five may be off (a room's direction misread).
    bool grouped = dirs.size() >= 2;
    if (grouped) {
      const WingSteps steps =
          CountWingSteps(world, node, family, dirs, 0.5 * options_.building_direction_min_rad, kWingStepRun);
      grouped = steps.supported >= 1 && steps.unsupported <= steps.supported / 4;
    }
    // Walls the groups miss may still split once along the run at a step
    // (SplitAtOneStep): each factor tied by where it was seen, not by its
    // direction. At every reading of the odometry, not only without drift:
    // under a drift a wing's rooms read level at the drift's rate, and a
    // sonar ring's rooms, each read 5-10 degrees off now and then, are
    // tied to the wrong group by their directions (8 sonars at 2 deg/m,
    // a 15-degree wing: 3 unsupported changes against 1 step).
    if (!grouped) {
      const std::optional<WingSplit> split = SplitAtOneStep(
          world, node, options_.building_direction_min_rad, options_.building_direction_min_asrs,
          0.5 * options_.building_direction_min_rad);
      if (split) {
        dirs = split->directions;
        family = split->family;
        grouped = true;
      }
    }
    if (!grouped) continue;
    Candidate c;
    c.directions = dirs;
    c.apart_rad = LeastApart(world, family, dirs, options_.building_direction_min_rad);
    graph_.SetBuildingDirection(0, dirs[0]);
    for (size_t k = 1; k < dirs.size(); ++k) graph_.AddBuildingDirection(dirs[k]);
    for (size_t f = 0; f < rs.size(); ++f) {
      c.family.emplace_back(rs[f].handle, family[f]);
      graph_.SetDirectionFamily(rs[f].handle, family[f]);
    }
    graph_.SetRatesFixedAtZero(false);
    graph_.Solve(0, options_.full_iterations);
    // Solved, the directions must still be a wing's apart to be kept: a
    // grouping of a drift's spread whose directions drew together is no
    // wing the model allows (a 16-sonar run at 2 deg/m on a building
    // without a wing: grouped 15 degrees apart, solved 11, and kept it
    // took the wall p95 from 0.84 to 2.05 m). It is still a map the walls
    // allow, held by the covariances when no wing is kept.
    spread(&c.least_rad, &c.most_rad);
    c.cost = graph_.Cost();
    c.state = graph_.Save();
    // Directions that drew together with the rates free may be a wing's
    // step shared between the directions and a drift: solved again with
    // the rates held at zero, when the walls need no drift under the wing
    // (the rates lower its cost by less than the drift test's quantile)
    // and its directions stay farther apart there than a group of them is
    // wide, the wing without drift is the candidate (apart, below). A
    // 16-sonar run without drift on a building whose wing turns 15
    // degrees: 11.3 degrees apart with the rates free (at 0.03 deg/m),
    // under the 15 a wing needs; the one direction kept straightened the
    // wing and its wall p95 went from the odometry's 0.79 to 5.76 m. A
    // drift read as a wing (2 deg/m on a building without one) needs its
    // rates under any grouping and is not taken this way.
    // Every candidate is also solved with the rates held at zero: whether
    // the walls need a drift under its grouping (the drift test's
    // likelihood ratio, c.needs_drift) is what ranks it against a grouping
    // that needs none (below).
    if (!options_.drift_known) {
      graph_.SetRatesFixedAtZero(true);
      graph_.Solve(0, options_.full_iterations);
      double least = 0.0, most = 0.0;
      spread(&least, &most);
      c.held_cost = graph_.Cost();
      c.needs_drift = 2.0 * (c.held_cost - c.cost) > ChiSquareQuantile(options_.drift_test_probability, 1);
      if (c.least_rad < options_.building_direction_min_rad && least >= std::min(width, c.apart_rad) &&
          !c.needs_drift) {
        c.least_rad = least;
        c.most_rad = most;
        c.held = true;
        c.cost = c.held_cost;
        c.state = graph_.Save();
      } else {
        graph_.Restore(c.state);
      }
      graph_.SetRatesFixedAtZero(false);
    }
    c.poses = CurrentPoses();
    c.rate = MeanRate();
    FitVarianceComponents(/*directions_only=*/true);
    c.neg_log_l = neg_log_l();
    graph_.SetSigmaFactor(FactorKind::kDirection, direction_sigma_before);
    graph_.RemoveBuildingDirections();
    candidates.push_back(std::move(c));
  }
  // Groupings that tie every factor to the same direction are one model
  // however many readings of the odometry found them: the test's level is
  // divided among the distinct ones (the same grouping found at the held
  // rates and at the scan's, counted twice, raised a 15-degree wing's
  // quantile from 12.1 to 12.9, past its 12.8).
  int tried = 0;
  for (size_t k = 0; k < candidates.size(); ++k) {
    bool seen = false;
    for (size_t j = 0; j < k && !seen; ++j) seen = candidates[j].family == candidates[k].family;
    tried += !seen;
  }
  // Of the candidates, the one whose likelihood ratio clears its quantile
  // (its directions beyond the first are parameters of their own) by the
  // most, at building_direction_test_probability divided among those tried.
  double chi2 = 0.0, margin = -std::numeric_limits<double>::infinity();
  const Candidate* chosen = nullptr;
  // Either likelihood ratio may clear it: at the variance components as
  // fitted with one direction (the test before the thirty-ninth session),
  // or at each model's own wall-direction variance when, solved, the
  // wing's directions are still a wing's apart: by
  // building_direction_min_rad, or, for a wing that needs no drift, by
  // more than a group of directions is wide (the drift's spread, which the
  // minimum guards against, is not there).
  const auto wing_apart = [&](const Candidate& c) { return c.held ? std::min(width, c.apart_rad) : c.apart_rad; };
  const auto apart = [&](const Candidate& c) { return c.least_rad >= wing_apart(c); };
  // A candidate's statistic and the quantile it must clear.
  const auto test = [&](const Candidate& c) {
    const int extra = static_cast<int>(c.directions.size()) - 1;
    const double q = ChiSquareQuantile(1.0 - (1.0 - options_.building_direction_test_probability) / tried, extra);
    const double profile =
        apart(c) ? 2.0 * (neg_log_l_before - c.neg_log_l) : -std::numeric_limits<double>::infinity();
    return std::pair{std::max(2.0 * (cost_before - c.cost), profile), q};
  };
  for (const Candidate& c : candidates) {
    const auto [x, q] = test(c);
    if (x - q > margin) {
      margin = x - q;
      chi2 = x;
      chosen = &c;
    }
  }
  // A direction more must earn its place against the grouping with fewer:
  // of the candidates that clear the test, those with the fewest
  // directions are ranked by their margin, and one with more replaces the
  // choice only when its likelihood ratio against it clears the test too
  // (the same level, degrees of freedom the directions it adds). Ranked by
  // margin alone, a grouping of three directions at a drift found with
  // one (a 55-degree wing without drift, 8 sonars: -7, -27 and 12 degrees
  // at 0.22 deg/m) beat the true two by 81.0 to 80.8 while its likelihood
  // was better by a chi2 of 3.2 only, and kept it turned the map 19
  // degrees.
  //
  // Of two groupings with as many directions, one that needs a drift
  // (Candidate::needs_drift) and one that does not, the drift is a
  // parameter more: the one with it is ranked first only when its
  // likelihood ratio against the other without drift clears the drift
  // test's quantile. Ranked by margin alone, a sonar ring's 35-degree wing
  // without drift (8 sonars, 27 ASRs) lost to a grouping 18 degrees apart
  // at a drift of -0.28 deg/m by a chi2 of 1.2 (30.6 against 29.4), and
  // kept it the map's heading median went from the odometry's 0.7 to 17
  // degrees and its ATE from 0.22 to 3.5 m.
  const double drift_quantile = ChiSquareQuantile(options_.drift_test_probability, 1);
  const auto ranks_first = [&](const Candidate& c, double c_margin) {
    if (c.needs_drift != chosen->needs_drift) {
      const Candidate& with = c.needs_drift ? c : *chosen;
      const Candidate& without = c.needs_drift ? *chosen : c;
      const bool earned = 2.0 * (without.held_cost - with.cost) > drift_quantile;
      return c.needs_drift ? earned : !earned;
    }
    return c_margin > margin;
  };
  if (chosen && margin > 0.0) {
    for (const Candidate& c : candidates) {
      const auto [x, q] = test(c);
      if (x - q > 0.0 && (c.directions.size() < chosen->directions.size() ||
                          (c.directions.size() == chosen->directions.size() && ranks_first(c, x - q)))) {
        margin = x - q;
        chi2 = x;
        chosen = &c;
      }
    }
    for (const Candidate& c : candidates) {
      if (c.directions.size() <= chosen->directions.size()) continue;
      const auto [x, q] = test(c);
      if (!(x - q > 0.0)) continue;
      // A grouping that needs a drift where the one chosen needs none
      // adds the drift too, a parameter more.
      const int extra = static_cast<int>(c.directions.size() - chosen->directions.size()) +
                        (c.needs_drift && !chosen->needs_drift ? 1 : 0);
      const double q_more =
          ChiSquareQuantile(1.0 - (1.0 - options_.building_direction_test_probability) / tried, extra);
      const double profile = apart(c) && apart(*chosen) ? 2.0 * (chosen->neg_log_l - c.neg_log_l)
                                                         : -std::numeric_limits<double>::infinity();
      if (std::max(2.0 * (chosen->cost - c.cost), profile) > q_more) {
        margin = x - q;
        chi2 = x;
        chosen = &c;
      }
    }
  }
  // The graph as decided, to keep or go back to.
  graph_.Restore(decided);
  graph_.SetRatesFixedAtZero(decided_held);
  // A wing kept under the test's margin (below), and its odds against one
  // building direction.
  const Candidate* likelier = nullptr;
  double likelier_odds = 0.0;
  if (!chosen || !(margin > 0.0) || !options_.keep_building_directions) {
    // No wing cleared the test: the map keeps one direction. But a wing
    // that fits the walls better than the map kept is a map the walls
    // allow, and the covariances hold it as they hold the drift's aliases
    // (Finish: the mixture's second moment about the poses kept): each
    // candidate weighs its likelihood relative to the one-direction graph
    // with the rates free (the first of the drift's hypotheses), less one
    // e-fold per direction it adds (Akaike weights: a direction more always
    // fits a little better). Without it, a 35-degree wing of eight rooms
    // seen by 16 sonars at 1 deg/m, under the test's chi-square (6.8
    // against 10.8), left 10 of 21 placed ASRs outside 3 sigma with no
    // word of the wing.
    if (!drift->hypotheses.empty()) {
      const double base = drift->hypotheses.front().weight;
      double total = 0.0, held = 0.0;
      for (const auto& h : drift->hypotheses) total += h.weight;
      const Candidate* best = nullptr;
      // The wings that need no drift: with a drift found, the other map.
      double undrifted = 0.0;
      const Candidate* best_undrifted = nullptr;
      for (const Candidate& c : candidates) {
        const int extra = static_cast<int>(c.directions.size()) - 1;
        const double w = base * std::exp(neg_log_l_before - c.neg_log_l - extra);
        if (!std::isfinite(w) || !(w > 0.0) || c.poses.size() != nodes_.size()) continue;
        drift->hypotheses.push_back({c.rate, w, c.poses, static_cast<int>(c.directions.size())});
        held += w;
        if (!best || c.neg_log_l < best->neg_log_l) best = &c;
        if (c.needs_drift) continue;
        undrifted += w;
        if (!best_undrifted || c.neg_log_l < best_undrifted->neg_log_l) best_undrifted = &c;
      }
      if (best && held >= total) {
        const double step = best->most_rad;
        const bool two = best->directions.size() > 2;
        char why[160];
        if (!apart(*best))
          std::snprintf(why, sizeof why, "but solved, %s drew to %.1f degrees apart, under the %.0f a wing needs",
                        two ? "two of their directions" : "its directions", RadToDeg(best->least_rad),
                        RadToDeg(wing_apart(*best)));
        else if (margin > 0.0)
          std::snprintf(why, sizeof why, "wings are not kept (MapOptimizerOptions::keep_building_directions)");
        else {
          // The figures of the wing named, which need not be the one the
          // test ranked first (that one's margin is the largest, this one's
          // likelihood).
          const auto [x, q] = test(*best);
          std::snprintf(why, sizeof why, "but not by the test's margin (chi2 %.1f, needed %.1f)", x, q);
        }
        char text[480];
        std::snprintf(text, sizeof text,
                      "%s %.0f degrees against the rest fit%s the walls better than one building direction "
                      "(%.3g:1 after %s), %s: the map keeps one direction, the uncertainties hold both",
                      two ? "wings turned up to" : "a wing turned", RadToDeg(step), two ? "" : "s", held / total,
                      two ? "their extra directions" : "its extra direction", why);
        drift->wing_warning = text;
        // With no drift found, the wing that outweighs one building
        // direction is the map kept, under the test's margin too. The
        // margin guards against groupings searched for over the rates and
        // from the data; a drift's spread, which gathers into groups and
        // draws together when solved, is the one such grouping that is
        // wrong and likelier, and it is not there. Kept to the margin, a
        // sonar ring's 15-20 degree wing without drift was squared onto
        // the rest while the walls favoured it 191:1 to 2,770:1 (rand41-5,
        // 8 sonars, a 20-degree wing: ATE 2.00 m against the odometry's
        // 0.30; kept, 0.34). So too when a drift was found with one
        // direction but the wing was solved with the rates held at zero
        // (Candidate::held: under the wing the rates lower the cost by less
        // than the drift test's quantile): with the wing no drift is found,
        // and the drift was the wing read as a ramp, whose one-direction
        // hypotheses the wing outweighs (rand41-33, 8 sonars, no drift, a
        // 15-degree wing: a drift of 0.26 deg/m found with one direction,
        // the wing 15:1 against it; ATE 0.57 m against the odometry's 0.12;
        // kept, 0.17).
        if ((!drift->detected || best->held) && options_.keep_building_directions) {
          likelier = best;
          likelier_odds = held / total;
        }
      } else if (const double margin_odds = std::exp(0.5 * drift_quantile);
                 best_undrifted && drift->detected && total < undrifted * margin_odds) {
        // A drift found, and a wing that needs none fitting the walls less
        // well but not by the margin the drift itself had to clear against
        // none (its likelihood ratio at the drift test's quantile, 27.6:1):
        // a wing read as a ramp looks so (rand45-37, 8 sonars, no drift, a
        // 15-degree wing: a drift of 0.23 deg/m kept at 0.54 against the
        // wing's 0.46 without drift, heading median 10.3 degrees against
        // the odometry's 0.51, warned only of uncertain ASRs). The map and
        // its covariances stay as they are (the mixture holds both); the
        // user is told which two maps the walls cannot tell apart.
        char text[480];
        std::snprintf(text, sizeof text,
                      "a drift of %+.3f deg/m was found, but a wing turned %.0f degrees against the rest without "
                      "drift fits the walls nearly as well (the drift only %.3g:1 against it, under the drift test's "
                      "%.3g:1): the map keeps the drift, the uncertainties hold both; compare with --no-correct",
                      RadToDeg(drift->hypotheses.front().rate), RadToDeg(best_undrifted->most_rad), total / undrifted,
                      margin_odds);
        drift->wing_warning = text;
      }
    }
    if (!likelier) return 0;
    chosen = likelier;
    chi2 = test(*likelier).first;
  }
  const Trial before = StartTrial();
  const DriftDecision before_drift = *drift;
  const Consistency c_before = MapConsistency(CurrentPoses(), CurrentRates());
  for (size_t k = 1; k < chosen->directions.size(); ++k) graph_.AddBuildingDirection(chosen->directions[k]);
  for (const auto& [handle, family] : chosen->family) graph_.SetDirectionFamily(handle, family);
  graph_.Restore(chosen->state);
  graph_.SetRatesFixedAtZero(false);
  FitVarianceComponents();
  *drift = TestDrift();
  DropContradictedClosures();
  if (LessConsistent(MapConsistency(CurrentPoses(), CurrentRates()), c_before)) {
    graph_.RemoveBuildingDirections();
    TakeBack(before);
    *drift = before_drift;
    return 0;
  }
  if (likelier) {
    const auto [x, q] = test(*likelier);
    // The wing as the map keeps it: solved again with the variance
    // components refitted and the drift tested, its directions may draw
    // together (a CARMEN museum read by a 16-sonar ring without drift: a
    // wing solved 35.7 degrees apart, kept at 2.2, while this warning named
    // the 35.7 only). When they drew under a wing's separation the warning
    // says so; the map is still the likelier (one direction there: ATE 1.41
    // m against the kept map's 0.24).
    double least = 0.0, most = 0.0;
    spread(&least, &most);
    const char* why = !before_drift.detected ? "no drift was found"
                      : drift->detected      ? "a drift is found with it as with one direction"
                                             : "with it no drift is found (the drift found with one direction was the wing)";
    char text[640];
    if (least < wing_apart(*likelier))
      std::snprintf(text, sizeof text,
                    "a wing turned %.0f degrees against the rest fits the walls %.3g:1 better than one building "
                    "direction and is kept under the test's margin (chi2 %.1f, needed %.1f): %s; but solved with the "
                    "whole map its directions drew to %.1f degrees apart, under the %.0f a wing needs: the map keeps "
                    "two near directions (the walls of some rooms held a little off the rest), not a wing",
                    RadToDeg(likelier->most_rad), likelier_odds, x, q, why, RadToDeg(least),
                    RadToDeg(wing_apart(*likelier)));
    else
      std::snprintf(text, sizeof text,
                    "a wing turned %.0f degrees against the rest is kept under the test's margin (chi2 %.1f, needed "
                    "%.1f): %s, and it fits the walls %.3g:1 better than one building direction",
                    RadToDeg(most), x, q, why, likelier_odds);
    drift->wing_warning = text;
  }
  *chi2_out = chi2;
  return graph_.building_directions() - 1;
}

std::vector<Pose2> MapOptimizer::CurrentPoses() const {
  std::vector<Pose2> out(nodes_.size());
  for (size_t i = 0; i < nodes_.size(); ++i) out[i] = graph_.pose(static_cast<int>(i));
  return out;
}

double MapOptimizer::MeanRate() const {
  double sum = 0.0;
  int n = 0;
  for (int i = 0; i < size(); ++i)
    if (!nodes_[i].stored) {
      sum += graph_.rate(i);
      ++n;
    }
  return n > 0 ? sum / n : 0.0;
}

std::vector<double> MapOptimizer::CurrentRates() const {
  std::vector<double> out(nodes_.size());
  for (size_t i = 0; i < nodes_.size(); ++i) out[i] = graph_.rate(static_cast<int>(i));
  return out;
}

MapOptimizer::Trial MapOptimizer::StartTrial() const {
  Trial t;
  t.state = graph_.Save();
  t.rates_fixed = graph_.RatesFixedAtZero();
  for (FactorKind k : kSigmaKinds) t.sigma.push_back(graph_.SigmaFactor(k));
  t.closures = closures_;
  t.closure_factors = closure_factor_.size();
  return t;
}

void MapOptimizer::TakeBack(const Trial& t) {
  // Closures accepted since: their factors disabled and forgotten.
  for (size_t k = t.closure_factors; k < closure_factor_.size(); ++k) graph_.SetRelativeEnabled(closure_factor_[k], false);
  closure_factor_.resize(t.closure_factors);
  closure_index_.resize(t.closure_factors);
  closures_ = t.closures;
  for (size_t k = 0; k < closure_factor_.size(); ++k)
    graph_.SetRelativeEnabled(closure_factor_[k], closures_[closure_index_[k]].accepted);
  for (size_t k = 0; k < t.sigma.size(); ++k) graph_.SetSigmaFactor(kSigmaKinds[k], t.sigma[k]);
  graph_.SetRatesFixedAtZero(t.rates_fixed);
  graph_.Restore(t.state);
}

void MapOptimizer::DropContradictedClosures() {
  // A closure the whole graph contradicts is dropped and the graph re-solved.
  const double gate3 = ChiSquareQuantile(options_.gate_probability, 3);
  for (int round = 0; round < 3; ++round) {
    bool dropped = false;
    const auto rs = graph_.Residuals();
    for (const auto& r : rs) {
      if (r.kind != FactorKind::kLoopClosure || !r.enabled || r.chi2 <= gate3) continue;
      graph_.SetRelativeEnabled(r.factor, false);
      for (size_t k = 0; k < closure_factor_.size(); ++k)
        if (closure_factor_[k] == r.factor) {
          LoopClosure& lc = closures_[closure_index_[k]];
          lc.accepted = false;
          lc.reason = "contradicted by the solved graph (chi2 " + std::to_string(r.chi2) + ")";
        }
      dropped = true;
    }
    if (!dropped) break;
    graph_.Solve(0, options_.full_iterations);
  }
}

double DriftSpreadSigma(double kept, double own, const std::vector<OptimizerResult::DriftHypothesis>& fits) {
  if (!(own >= 0.0)) return -1.0;
  double var = own * own;
  for (const auto& h : fits)
    if (std::isfinite(h.rate_rad_per_m) && std::isfinite(h.weight) && h.weight > 0.0)
      var += h.weight * (h.rate_rad_per_m - kept) * (h.rate_rad_per_m - kept);
  return std::sqrt(var);
}

OptimizerResult MapOptimizer::Finish() {
  OptimizerResult res;
  const int N = static_cast<int>(nodes_.size());
  if (N == 0) return res;
  auto t0 = std::chrono::steady_clock::now();
  const Trial at_start = StartTrial();
  FitVarianceComponents();
  DriftDecision drift = TestDrift();
  DropContradictedClosures();
  // No drift found, but the odometry's heading fitted far noisier than its
  // model: the wall directions pull the headings away from the odometry by
  // more than either model allows (a wing's walls read as the building's,
  // walls misread by a sparse ring: a wing turned 45 degrees, eight sonars,
  // no drift: the whole map turned 22 degrees with the odometry's heading
  // factor at 9.2, the robot's path through 18 walls). Fitted again with
  // the odometry's heading held at its model; the heading as fitted stands
  // unless its map is the less consistent of the two (a fitted heading
  // 1.5-3 times its model, as wall directions of a sparse ring or a laser
  // often fit it, and a map as consistent either way: the held fit as
  // often worse as better, bench/never_worse --random 40).
  if (!drift.detected && HeadingAboveItsModel()) {
    res.odometry_heading_fitted_factor = graph_.SigmaFactor(FactorKind::kOdometryHeading);
    const Trial fitted = StartTrial();
    const DriftDecision fitted_drift = drift;
    const Consistency c_fitted = MapConsistency(CurrentPoses(), CurrentRates());
    TakeBack(at_start);
    hold_odometry_heading_ = true;
    graph_.SetSigmaFactor(FactorKind::kOdometryHeading, 1.0);
    FitVarianceComponents();
    drift = TestDrift();
    DropContradictedClosures();
    if (!LessConsistent(c_fitted, MapConsistency(CurrentPoses(), CurrentRates()))) {
      hold_odometry_heading_ = false;
      TakeBack(fitted);
      drift = fitted_drift;
    } else {
      res.odometry_heading_held = true;
    }
  }
  // With search_again, the candidates are searched again against the
  // solved graph; when none of the closures found so stands, the graph is
  // left as it was (a wrong one, accepted and dropped again, would still
  // have weighed on the variance components and the drift test).
  if (options_.search_again) {
    const Trial before = StartTrial();
    const DriftDecision before_drift = drift;
    if (SearchClosuresAgain() > 0) {
      graph_.Solve(0, options_.full_iterations);
      FitVarianceComponents();
      drift = TestDrift();
      DropContradictedClosures();
      bool stands = false;
      for (size_t k = before.closure_factors; k < closure_factor_.size(); ++k)
        stands = stands || closures_[closure_index_[k]].accepted;
      if (!stands) {
        TakeBack(before);
        drift = before_drift;
      }
    }
  }
  // A wing turned against the rest of the building: a building direction
  // of its own, when the walls say so.
  TryBuildingDirections(&drift, &res.building_direction_chi2);
  // Drift inside long ASRs (direction_split_m): the walls grouped along the
  // path replace each such ASR's one direction, tried from the solution
  // with one direction per ASR (a good start: the groups of 3 m are bent by
  // the very drift they measure and, solved on their own, settled in wrong
  // minima at 2 deg/m). They are kept when they find a drift and leave the
  // map at least as consistent (robot path through walls) as without them.
  res.split_asrs = static_cast<int>(splits_.size());
  if (!splits_.empty()) {
    const Trial whole = StartTrial();
    const Consistency c_whole = MapConsistency(CurrentPoses(), CurrentRates());
    SetSplitsEnabled(true);
    graph_.SetRatesFixedAtZero(false);
    // First the groups at the whole solution's sigmas (the likelihood-ratio
    // test alone, two solves): when they find no drift there, the trial
    // ends (its variance components, a dozen solves, would re-weigh factors
    // that show none).
    const PoseGraph::State split_start = graph_.Save();
    bool split_kept = false;
    DriftDecision split;
    if (TestDrift(true).detected) {
      graph_.Restore(split_start);
      graph_.SetRatesFixedAtZero(false);
      FitVarianceComponents();
      split = TestDrift();
      DropContradictedClosures();
      const Consistency c_split = MapConsistency(CurrentPoses(), CurrentRates());
      split_kept = split.detected && !LessConsistent(c_split, c_whole);
    }
    if (split_kept) {
      // A wing held by the covariances (TryBuildingDirections) stays held:
      // weighed against the split's drift basin as it was against the
      // whole ASRs' (a 20-degree wing read as drift by both, a laser
      // without drift: the wing's hypothesis was dropped with the decision).
      const double was = drift.hypotheses.empty() ? 1.0 : drift.hypotheses.front().weight;
      const double now = split.hypotheses.empty() ? 1.0 : split.hypotheses.front().weight;
      for (const DriftDecision::Hypothesis& h : drift.hypotheses)
        if (h.building_directions > 1 && !split.hypotheses.empty()) {
          split.hypotheses.push_back(h);
          split.hypotheses.back().weight *= now / was;
        }
      if (split.wing_warning.empty()) split.wing_warning = drift.wing_warning;
      drift = split;
      res.split_used = true;
    } else {
      SetSplitsEnabled(false);
      TakeBack(whole);
    }
  }
  for (int k = 0; k < graph_.building_directions(); ++k) res.building_directions_rad.push_back(graph_.building_direction(k));
  res.drift_test_chi2 = drift.chi2;
  res.drift_detected = drift.detected;
  res.drift_alias_risk = drift.alias_risk;
  if (!drift.warning.empty()) res.warnings.push_back(drift.warning);
  if (!drift.wing_warning.empty()) res.warnings.push_back(drift.wing_warning);
  res.odometry_sigma_factor = graph_.SigmaFactor(FactorKind::kOdometry);
  res.odometry_heading_sigma_factor = graph_.SigmaFactor(FactorKind::kOdometryHeading);
  res.direction_sigma_factor = graph_.SigmaFactor(FactorKind::kDirection);
  res.registration_sigma_factor = graph_.SigmaFactor(FactorKind::kRegistration);
  const std::vector<Pose2> graph_poses = CurrentPoses();
  std::vector<Pose2> odo_poses(N);
  // Odometry: stored nodes stay where they were; new ones by dead reckoning
  // from the first new node's anchor.
  for (int i = 0; i < N; ++i) odo_poses[i] = nodes_[i].stored ? graph_poses[i] : nodes_[i].raw;
  // Consistency: how often the robot's path runs through another ASR's
  // walls. Counts are noisy (sonar walls, door jambs): the graph is rejected
  // only when its count exceeds odometry's by more than 3 Poisson sigmas.
  std::vector<double> rates = CurrentRates();
  const Consistency c_graph = MapConsistency(graph_poses, rates);
  const Consistency c_odo = MapConsistency(odo_poses, {});
  res.crossings_graph = c_graph.crossings;
  res.crossings_odometry = c_odo.crossings;
  res.overlap_graph_m = c_graph.overlap_m;
  res.overlap_odometry_m = c_odo.overlap_m;
  std::vector<Pose2> chosen = graph_poses;
  res.solution = "pose_graph";
  res.crossings_chosen = res.crossings_graph;
  if (LessConsistent(c_graph, c_odo)) {
    // Without the closures (the likeliest wrong factors), then odometry.
    for (size_t k = 0; k < closure_factor_.size(); ++k)
      if (closures_[closure_index_[k]].accepted) graph_.SetRelativeEnabled(closure_factor_[k], false);
    graph_.Solve(0, options_.full_iterations);
    const std::vector<Pose2> no_loop = CurrentPoses();
    rates = CurrentRates();
    const Consistency c_nl = MapConsistency(no_loop, rates);
    const int total_nl = c_nl.crossings;
    if (!LessConsistent(c_nl, c_odo)) {
      chosen = no_loop;
      res.solution = "pose_graph_without_closures";
      res.crossings_chosen = total_nl;
      for (size_t k = 0; k < closure_factor_.size(); ++k) {
        LoopClosure& lc = closures_[closure_index_[k]];
        if (lc.accepted) {
          lc.accepted = false;
          lc.reason = "dropped: the map with closures was less consistent than odometry";
        }
      }
    } else {
      chosen = odo_poses;
      res.solution = "odometry";
      res.crossings_chosen = res.crossings_odometry;
      for (int i = 0; i < N; ++i) graph_.set_pose(i, odo_poses[i]);
    }
    res.warnings.push_back("the pose graph made the map less consistent than odometry (robot path through walls: " +
                           std::to_string(res.crossings_graph) + " vs " + std::to_string(res.crossings_odometry) +
                           "); using " + res.solution);
  }
  // A drift left uncorrected because its quarter-turn alias fits about as
  // well (TestDrift: a coin toss) may still be chosen by the wall
  // directions alone, known modulo a quarter turn: the graph then turns the
  // run away from its odometry, ASR after ASR, by more than half a quarter
  // turn, the choice the drift test declined to make (fhw at 1 deg/m cut
  // every 8 m: turned 837 degrees, ATE 56.5 m against the odometry's 34.8).
  // The odometry stands instead. Without that ambiguity, a run turned far
  // from its odometry is the walls correcting a drift the rate test did not
  // keep (nine_rooms at 1 deg/m cut every 8 m: 113 degrees, ATE 0.16 m
  // against 2.94), and stays.
  if (res.solution != "odometry" && !res.drift_detected && res.drift_alias_risk) {
    const double turned = TurnRange(chosen, odo_poses);
    if (turned > options_.max_turn_without_drift_rad) {
      chosen = odo_poses;
      res.solution = "odometry";
      res.crossings_chosen = res.crossings_odometry;
      for (int i = 0; i < N; ++i) graph_.set_pose(i, odo_poses[i]);
      res.warnings.push_back("the drift was left uncorrected as ambiguous, but the pose graph turned the run " +
                             std::to_string(static_cast<int>(std::lround(RadToDeg(turned)))) +
                             " degrees away from its odometry (a quarter-turn branch of the walls chosen): using "
                             "the odometry");
    }
  }
  AssignRoomIds();
  res.solve_seconds = solve_seconds_ + Seconds(t0);
  // Chi-square of the solved graph.
  const std::vector<PoseGraph::FactorResidual> final_residuals = graph_.Residuals();
  // The weighted chi-square and what it is worth (Finish's covariances too).
  auto weighted = [N](const std::vector<PoseGraph::FactorResidual>& rs) {
    double chi2 = 0.0, dof = 0.0;
    for (const auto& r : rs)
      if (r.enabled) chi2 += r.weight * r.chi2, dof += r.consistency * r.dof;
    return std::make_pair(chi2, std::max(1.0, dof - 3.0 * (N - 1)));
  };
  for (const auto& r : final_residuals) {
    if (!r.enabled) continue;
    res.chi2 += r.chi2;
    res.chi2_dof += r.dof;
    if (r.kind == FactorKind::kDirection) ++res.direction_factors;
  }
  res.chi2_dof = std::max(1, res.chi2_dof - 3 * (N - 1));
  res.chi2_p999 = ChiSquareQuantile(0.999, res.chi2_dof);
  std::tie(res.chi2_weighted, res.chi2_weighted_dof) = weighted(final_residuals);
  const int weighted_dof = std::max(1, static_cast<int>(std::lround(res.chi2_weighted_dof)));
  if (res.chi2_weighted > ChiSquareQuantile(0.999, weighted_dof))
    res.warnings.push_back("the factors disagree more than their covariances allow (weighted chi2 " +
                           std::to_string(static_cast<int>(res.chi2_weighted)) + " for " +
                           std::to_string(weighted_dof) + " dof): the uncertainties are optimistic");
  res.registrations = registrations_;
  res.drift_rate_rad_per_m = MeanRate();
  // Covariances scaled by the a-posteriori variance factor chi2 / dof (the
  // variance of unit weight of least-squares adjustment) when it exceeds 1:
  // the factors disagree more than their sigmas allow. Below 1 they are kept
  // (by default; min_variance_factor): small residuals say the random part
  // of the noise was small, not that a systematic one (the wheels' distance
  // scale) was, which no residual of a graph without loops can see.
  t0 = std::chrono::steady_clock::now();
  std::vector<Eigen::Matrix3d> cov;
  std::vector<Eigen::Matrix3d> aligned_cov;  // after the map's best rigid alignment
  double cov_chi2 = res.chi2_weighted;  // (weighted) chi-square of the model the covariances come from
  if (res.solution != "odometry") {
    // With the rates free even when the test kept them at zero: an
    // undetected drift is still a possible one, and the sigmas must say so.
    const bool zero = graph_.RatesFixedAtZero();  // held (at zero, or at a drift known before the run)
    if (zero) graph_.SetRatesFixedAtZero(false);
    // The fitted sigma factors may shrink a kind of factor below its noise
    // model for the estimate; for the covariance they only inflate it. A
    // group's residuals are small where nothing else measures the same
    // relative pose (a chain without loops, a corridor's length), which says
    // nothing about the noise there (the global redundancy share cannot tell).
    std::map<FactorKind, double> fitted;
    if (options_.covariance_sigma_floor) {
      for (FactorKind k : kSigmaKinds) {
        fitted[k] = graph_.SigmaFactor(k);
        graph_.SetSigmaFactor(k, std::max(1.0, fitted[k]));
      }
      // The variance factor below then belongs to the same (floored) model.
      cov_chi2 = weighted(graph_.Residuals()).first;
    }
    // The run's drift rate's uncertainty: the root mean square of its
    // nodes' marginal sigmas (the rate reported is their mean; strongly
    // correlated through the random walk, its sigma is at most this).
    const std::vector<double> rate_var = graph_.RateVariances();
    double sum = 0.0;
    int n = 0;
    bool known = N > 1;  // one room: no odometry, no drift to speak of
    for (int i = 0; i < N; ++i)
      if (!nodes_[i].stored) sum += rate_var[i], ++n, known = known && rate_var[i] >= 0.0;
    res.drift_rate_sigma_rad_per_m = known && n > 0 ? std::sqrt(sum / n) : -1.0;
    // A room's walls were seen all along its path, each bent by the drift
    // so far; the direction factor corrects them by the mean, and the rest
    // (the rate x the spread of where they were seen) is an error the
    // covariance must hold (covariance_direction_bend).
    if (options_.covariance_direction_bend) graph_.SetDirectionBend(true, rate_var);
    cov = graph_.Covariances(&aligned_cov);
    if (options_.covariance_direction_bend) graph_.SetDirectionBend(false);
    for (const auto& [k, f] : fitted) graph_.SetSigmaFactor(k, f);
    if (zero) graph_.SetRatesFixedAtZero(true);
  }
  // The minima of the rates TestDrift found (the drift's own basin with
  // the rates free, and its aliases), each a map the walls fit, as likely
  // as its weight: the covariance about the poses kept is the mixture's
  // second moment about them (each hypothesis's own covariance taken as the
  // one above, plus its offset from the poses kept, squared). Without it
  // the sigmas were those of the hypothesis kept alone: a run whose drift
  // the test left at zero while the truth was its alias (a quarter turn
  // more between two wall directions far apart), or a drift within the
  // test's quantile of none, was placed outside 3 sigma
  // (bench/never_worse: 5 of 120 runs, aria/triangle with 8 sonars at 2
  // deg/m with 0 of 3 ASRs within 3 sigma; docs/pose-graph.md).
  std::vector<Eigen::Matrix3d> spread(N, Eigen::Matrix3d::Zero());
  // A solve that failed (a cost not finite) is no hypothesis.
  auto usable = [](const DriftDecision::Hypothesis& h) {
    if (!std::isfinite(h.weight) || !std::isfinite(h.rate)) return false;
    for (const Pose2& p : h.poses)
      if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.theta)) return false;
    return true;
  };
  double total = 0.0;
  for (const auto& h : drift.hypotheses)
    if (usable(h)) total += h.weight;
  std::vector<double> aligned_spread(N, 0.0);  // the same for the position, each offset less its best rigid fit
  for (const auto& h : drift.hypotheses) {
    if (!usable(h) || !(total > 0.0)) continue;
    const double w = h.weight / total;
    res.drift_hypotheses.push_back({h.rate, w, h.building_directions});
    if (cov.empty()) continue;
    std::vector<Vec2> from, to;
    for (int i = 0; i < N && i < static_cast<int>(h.poses.size()); ++i) {
      from.emplace_back(h.poses[i].x, h.poses[i].y);
      to.emplace_back(chosen[i].x, chosen[i].y);
      if (nodes_[i].stored) continue;
      const Eigen::Vector3d d(h.poses[i].x - chosen[i].x, h.poses[i].y - chosen[i].y,
                              NormalizeAngle(h.poses[i].theta - chosen[i].theta));
      spread[i] += w * d * d.transpose();
    }
    const Pose2 fit = AlignPoints(from, to);
    for (size_t i = 0; i < from.size(); ++i)
      if (!nodes_[i].stored) aligned_spread[i] += w * (fit * from[i] - to[i]).squaredNorm();
  }
  res.drift_rate_spread_sigma_rad_per_m =
      DriftSpreadSigma(res.drift_rate_rad_per_m, res.drift_rate_sigma_rad_per_m, res.drift_hypotheses);
  res.covariance_seconds = Seconds(t0);
  const double factor = cov_chi2 / res.chi2_weighted_dof;
  const double inflate =
      res.chi2_dof >= options_.min_dof_to_shrink ? std::max(options_.min_variance_factor, factor) : std::max(1.0, factor);
  res.variance_factor = inflate;
  std::vector<double> dir_resid(N, 0.0);
  std::vector<int> family(N, 0);
  for (const PoseGraph::DirectionTerm& t : graph_.DirectionTerms()) family[t.node] = t.family;
  for (const auto& r : final_residuals)
    if (r.kind == FactorKind::kDirection && r.enabled) dir_resid[r.i] = std::max(dir_resid[r.i], std::sqrt(r.chi2));
  // How far the correction moved the map from its odometry, against how
  // sure it is: the share of placed ASRs whose odometry pose lies within 3
  // sigma of the pose kept (as the calibration against the truth is
  // counted, cogmap eval). A drift found moves them beyond it, as it
  // should. Without one, the odometry is a map the graph itself allows
  // only if it lies within those sigmas; a map moved beyond them is the
  // walls or closures against the odometry. On 720 runs of 120 random
  // buildings (bench/never_worse --random, seeds 39-41) it fired on 12,
  // each with the odometry the better map (8 of them counted worse than
  // it: sonar rings on winged buildings); but it also fires where the
  // walls rightly took out a drift under the test's reach (nine_rooms, 16
  // sonars, 0.1 deg/m, the simulator's default: ATE 0.33 -> 0.09 m). An
  // undetected drift moves the map as a ramp along the path, a room turned
  // by its walls alone as a step; a wing turned onto the rest reads as
  // either. So the warning says which: the odometry is bent by the one
  // drift rate that brings it nearest the map (least squares, the rate's
  // prior its sigma with the rates free: the drift the test could not rule
  // out), and when that brings 95 % within 3 sigma the warning names the
  // rate (the odometry drifts that much, or the building turns along the
  // way: nothing here tells which; docs/BENCHMARKS.md, "A map moved beyond
  // its sigmas: a ramp or a step"). The map is kept (the posterior sigmas
  // are narrower than the odometry's own noise allows about them, so a
  // fallback would need that covariance).
  // by_rate[i]: d(odometry pose i)/d(rate), world frame, from the frame
  // node (or the last stored one).
  std::vector<Eigen::Vector3d> by_rate(N, Eigen::Vector3d::Zero());
  for (int i = 1; i < N; ++i) {
    if (nodes_[i].stored) continue;
    const Pose2& a = odo_poses[i - 1];
    const Pose2& b = odo_poses[i];
    const Eigen::Vector3d before = nodes_[i - 1].stored ? Eigen::Vector3d::Zero() : by_rate[i - 1];
    const double c = std::cos(a.theta), sn = std::sin(a.theta);
    const Eigen::Vector3d& j = nodes_[i].odo_by_rate;
    by_rate[i] = before + Eigen::Vector3d(-(b.y - a.y) * before.z() + c * j.x() - sn * j.y(),
                                          (b.x - a.x) * before.z() + sn * j.x() + c * j.y(), j.z());
  }
  // Each placed ASR with a covariance: how far the pose kept lies from the
  // odometry's (x, y, theta), and that covariance.
  struct Moved {
    int node;
    Eigen::Vector3d by;
    Eigen::Matrix3d cov;
  };
  std::vector<Moved> moved;
  int uncertain = 0;
  int why_position = 0, why_heading = 0, why_walls = 0, why_other = 0;
  for (int i = 0; i < N; ++i) {
    if (nodes_[i].stored) continue;
    AsrEstimate e;
    e.asr_id = nodes_[i].asr_id;
    e.pose = chosen[i];
    e.room_id = nodes_[i].room_id;
    e.drift_rate_rad_per_m = res.solution == "odometry" ? 0.0 : graph_.rate(i);
    e.corrected_path = asr::CorrectedPath(nodes_[i].path_raw, nodes_[i].raw, chosen[i], e.drift_rate_rad_per_m);
    e.corrected_walls = BendWalls(nodes_[i], e.drift_rate_rad_per_m, /*output=*/true);
    e.direction_factor = nodes_[i].direction;
    e.direction_residual_sigmas = dir_resid[i];
    e.building_direction = family[i];
    if (!cov.empty()) {
      e.covariance = inflate * cov[i] + spread[i];
      e.has_covariance = true;
      // The position uncertain as the map is laid on the building (its best
      // rigid move), not against the first ASR's frame (docs/pose-graph.md,
      // "Uncertain ASRs"); against the first ASR when that fails.
      const bool laid = aligned_cov.size() == static_cast<size_t>(N);
      const double sp = laid ? std::sqrt(std::max(0.0, inflate * (aligned_cov[i](0, 0) + aligned_cov[i](1, 1)) +
                                                           aligned_spread[i]))
                             : std::sqrt(std::max(0.0, e.covariance(0, 0) + e.covariance(1, 1)));
      // The heading stays against the first ASR's frame: laid likewise, it
      // let a map worse than its odometry go without a warning (docs/pose-
      // graph.md, "Uncertain ASRs").
      const double st = std::sqrt(std::max(0.0, e.covariance(2, 2)));
      e.position_sigma_aligned_m = sp;
      if (i > 0) {  // the first node is the frame: fixed
        moved.push_back({i,
                         Eigen::Vector3d(chosen[i].x - odo_poses[i].x, chosen[i].y - odo_poses[i].y,
                                         NormalizeAngle(chosen[i].theta - odo_poses[i].theta)),
                         e.covariance});
      }
      if (sp > options_.uncertain_position_m) {
        e.why.push_back("position 1-sigma " + std::to_string(sp).substr(0, 5) + " m");
        ++why_position;
      }
      if (st > options_.uncertain_theta_rad) {
        e.why.push_back("heading 1-sigma " + std::to_string(RadToDeg(st)).substr(0, 5) + " deg");
        ++why_heading;
      }
    } else if (res.solution == "odometry") {
      e.why.push_back("placed by odometry (correction rejected)");
      ++why_other;
    } else {
      e.why.push_back("covariance not computable (graph rank deficient)");
      ++why_other;
    }
    if (nodes_[i].direction && dir_resid[i] > 3.0) {
      e.why.push_back("its walls disagree with the building direction (" + std::to_string(dir_resid[i]).substr(0, 4) +
                      " sigma)");
      ++why_walls;
    }
    e.uncertain = !e.why.empty();
    uncertain += e.uncertain ? 1 : 0;
    res.asrs.push_back(e);
  }
  // Within 3 sigma of the pose kept: as cogmap eval counts the calibration.
  auto within_3sigma = [](const Eigen::Vector3d& d, const Eigen::Matrix3d& C) {
    return d.head<2>().norm() <= 3.0 * std::sqrt(std::max(0.0, C(0, 0) + C(1, 1))) &&
           std::abs(NormalizeAngle(d.z())) <= 3.0 * std::sqrt(std::max(0.0, C(2, 2)));
  };
  int placed = static_cast<int>(moved.size()), within = 0, within_bent = 0;
  for (const Moved& m : moved) within += within_3sigma(m.by, m.cov);
  // The rate that bends the odometry nearest the map: least squares over the
  // placed ASRs (each weighed by its covariance), with the rate's prior.
  const double sigma_r = res.drift_rate_sigma_rad_per_m;
  double rate = 0.0;
  if (sigma_r > 0.0 && placed > 0) {
    double num = 0.0, den = 1.0 / (sigma_r * sigma_r);
    for (const Moved& m : moved) {
      const Eigen::Matrix3d W = (m.cov + 1e-9 * Eigen::Matrix3d::Identity()).inverse();
      const Eigen::Vector3d& g = by_rate[m.node];
      num += g.dot(W * m.by);
      den += g.dot(W * g);
    }
    rate = num / den;
  }
  for (const Moved& m : moved) within_bent += within_3sigma(m.by - rate * by_rate[m.node], m.cov);
  if (placed > 0) {
    res.odometry_within_3sigma = static_cast<double>(within) / placed;
    res.odometry_within_3sigma_bent = static_cast<double>(within_bent) / placed;
    res.moved_as_drift_rad_per_m = rate;
  }
  if (placed > 0 && res.solution != "odometry" && !res.drift_detected && !options_.drift_known &&
      within < 0.95 * placed) {
    std::string w = "with no drift found, the map moved " + std::to_string(placed - within) + " of " +
                    std::to_string(placed) + " placed ASRs beyond 3 sigma of their odometry";
    if (within_bent >= 0.95 * placed) {
      char what[160];
      std::snprintf(what, sizeof what, ", as a heading drift of %+.3f deg/m would (%.1f sigma of the drift the test "
                    "could not rule out)", RadToDeg(rate), std::abs(rate) / sigma_r);
      w += std::string(what) + ": the odometry drifts that much, or the building turns along the way (a wing)";
    } else {
      w += " by more than any one drift rate explains: the walls or closures disagree with the odometry, and one of "
           "them is wrong";
    }
    res.warnings.push_back(w + "; compare with --no-correct (report.json: pose_graph.odometry_within_3sigma)");
  }
  if (uncertain > 0) {
    // Why, in one line: how many for each reason (an ASR may have several).
    std::string why;
    auto reason = [&](int count, const std::string& text) {
      if (count > 0) why += (why.empty() ? "" : ", ") + std::to_string(count) + " " + text;
    };
    reason(why_position, "position 1-sigma over " + std::to_string(options_.uncertain_position_m).substr(0, 3) + " m");
    reason(why_heading,
           "heading 1-sigma over " + std::to_string(static_cast<int>(std::lround(RadToDeg(options_.uncertain_theta_rad)))) +
               " deg");
    reason(why_walls, "walls off the building direction");
    reason(why_other, res.solution == "odometry" ? "placed by odometry" : "without a covariance");
    // Where: the ASRs least sure of their position (as laid on the building)
    // and of their heading, with their 1-sigma, so that a long run flagged
    // all along says which part is worst.
    auto heading_sigma = [](const AsrEstimate& e) { return std::sqrt(std::max(0.0, e.covariance(2, 2))); };
    const AsrEstimate* worst_position = nullptr;
    const AsrEstimate* worst_heading = nullptr;
    for (const AsrEstimate& e : res.asrs) {
      if (!e.uncertain || !e.has_covariance) continue;
      if (e.position_sigma_aligned_m > options_.uncertain_position_m &&
          (!worst_position || e.position_sigma_aligned_m > worst_position->position_sigma_aligned_m))
        worst_position = &e;
      if (heading_sigma(e) > options_.uncertain_theta_rad &&
          (!worst_heading || heading_sigma(e) > heading_sigma(*worst_heading)))
        worst_heading = &e;
    }
    std::string where;
    if (worst_position) {
      AppendF(&where, "ASR %d (position 1-sigma %.2f m", worst_position->asr_id,
              worst_position->position_sigma_aligned_m);
      if (worst_heading == worst_position) {
        AppendF(&where, ", heading 1-sigma %.1f deg", RadToDeg(heading_sigma(*worst_heading)));
        worst_heading = nullptr;
      }
      where += ")";
    }
    if (worst_heading)
      AppendF(&where, "%sASR %d (heading 1-sigma %.1f deg)", where.empty() ? "" : ", ", worst_heading->asr_id,
              RadToDeg(heading_sigma(*worst_heading)));
    if (!where.empty()) where = "; least sure: " + where;
    res.warnings.push_back(std::to_string(uncertain) + " of " + std::to_string(res.asrs.size()) +
                           " ASRs are uncertain (" + why + where + "; report.json: pose_graph.uncertain_asrs)");
  }
  res.closures = closures_;
  return res;
}

void MapOptimizer::FitVarianceComponents(bool directions_only) {
  const std::vector<FactorKind> kinds =
      directions_only ? std::vector<FactorKind>{FactorKind::kDirection}
                      : std::vector<FactorKind>{FactorKind::kOdometry, FactorKind::kOdometryHeading,
                                                FactorKind::kDirection, FactorKind::kRegistration};
  for (int round = 0; round < options_.variance_rounds; ++round) {
    graph_.Solve(0, options_.full_iterations);
    const auto rs = graph_.Residuals();
    const auto red = graph_.Redundancies();
    if (red.size() != rs.size()) break;  // singular information: the sigmas stay as they are
    bool changed = false;
    for (FactorKind kind : kinds) {
      if (kind == FactorKind::kOdometryHeading && hold_odometry_heading_) continue;
      // Foerstner's estimate: the kind's robustly weighted chi^2 over the
      // part of its dof that the rest of the graph checks, each part worth
      // what a weighted chi^2 is at the right sigma (the loss's consistency).
      double chi2 = 0.0, redundancy = 0.0;
      int count = 0;
      for (size_t k = 0; k < rs.size(); ++k) {
        const auto& r = rs[k];
        const bool match = r.kind == kind || (kind == FactorKind::kRegistration && r.kind == FactorKind::kLoopClosure) ||
                           (kind == FactorKind::kOdometryHeading && r.kind == FactorKind::kOdometry);
        if (!r.enabled || !match) continue;
        // The odometry's two components: its heading row, and the rest.
        double c = r.chi2, rd = red[k].redundancy;
        if (r.kind == FactorKind::kOdometry) {
          const bool heading = kind == FactorKind::kOdometryHeading;
          c = heading ? r.chi2_heading : r.chi2 - r.chi2_heading;
          rd = heading ? red[k].redundancy_heading : red[k].redundancy - red[k].redundancy_heading;
        }
        chi2 += red[k].weight * c;
        redundancy += red[k].consistency * rd;
        ++count;
      }
      if (count < options_.min_factors_for_variance || redundancy < options_.min_redundancy_for_variance) continue;
      const double s2 = std::max(1e-6, chi2 / redundancy);
      const double now = graph_.SigmaFactor(kind);
      const double next = std::clamp(now * std::sqrt(s2), 0.1, 10.0);
      if (kind == FactorKind::kOdometryHeading) heading_redundancy_ = redundancy;
      if (std::abs(next / now - 1.0) > 0.05) changed = true;
      graph_.SetSigmaFactor(kind, next);
      if (kind == FactorKind::kRegistration) graph_.SetSigmaFactor(FactorKind::kLoopClosure, next);
    }
    if (!changed) break;
  }
}

bool MapOptimizer::HeadingAboveItsModel() const {
  // The fitted factor squared estimates the heading's variance over the
  // model's: under the model, its weighted chi^2 over the redundancy R is
  // about chi^2(R) / R.
  if (options_.heading_model_test_probability <= 0.0 || heading_redundancy_ <= 0.0) return false;
  const double f = graph_.SigmaFactor(FactorKind::kOdometryHeading);
  const int dof = std::max(1, static_cast<int>(std::lround(heading_redundancy_)));
  return f * f * heading_redundancy_ > ChiSquareQuantile(options_.heading_model_test_probability, dof);
}

std::vector<Polyline> MapOptimizer::BendWalls(const Node& n, double rate, bool output) const {
  const std::vector<Polyline>& walls = output && n.output_walls ? *n.output_walls : n.walls;
  if (rate == n.pre_rate || n.path_raw.empty()) return walls;
  // The path in the local frame, as mapped (q) and with the drift removed (c),
  // with the distance driven to each pose.
  const Pose2 local_from_world = n.raw.inverse();
  // (Placed at n.raw: back to the local frame below.)
  const std::vector<Pose2> c = asr::CorrectedPath(n.path_raw, n.raw, n.raw, rate);
  // The walls were mapped on the path re-integrated under n.pre_rate: what
  // is left to remove is rate - pre_rate, about that path's poses.
  std::vector<Pose2> scratch;
  const std::vector<Pose2>& mapped = MappedPath(n, &scratch);
  std::vector<Vec2> q(n.path_raw.size());
  std::vector<Pose2> cl(n.path_raw.size());
  std::vector<double> s(n.path_raw.size(), 0.0);
  for (size_t k = 0; k < n.path_raw.size(); ++k) {
    q[k] = local_from_world * mapped[k].translation();
    cl[k] = local_from_world * c[k];
    const Vec2 prev = k == 0 ? Vec2(0, 0) : q[k - 1];
    s[k] = (k == 0 ? 0.0 : s[k - 1]) + (q[k] - prev).norm();
  }
  // Each vertex moves as the pose it was seen from: by the drift at the
  // distance its echoes were heard (the path pose at that distance), or,
  // where that is not known, at the nearest path pose.
  const std::vector<std::vector<double>>& seen =
      output && n.output_walls ? n.output_walls_seen_s : n.walls_seen_s;
  const bool use_seen = options_.bend_where_seen && seen.size() == walls.size();
  std::vector<Polyline> out = walls;
  for (size_t i = 0; i < out.size(); ++i) {
    Polyline& line = out[i];
    for (size_t v = 0; v < line.size(); ++v) {
      Vec2& p = line[v];
      size_t best = 0;
      const double at = use_seen && v < seen[i].size() ? seen[i][v] : std::numeric_limits<double>::quiet_NaN();
      if (std::isfinite(at)) {
        best = static_cast<size_t>(std::lower_bound(s.begin(), s.end(), at) - s.begin());
        if (best == s.size() || (best > 0 && at - s[best - 1] < s[best] - at)) --best;
      } else {
        double bd = std::numeric_limits<double>::infinity();
        for (size_t k = 0; k < q.size(); ++k) {
          const double d = (q[k] - p).squaredNorm();
          if (d < bd) {
            bd = d;
            best = k;
          }
        }
      }
      p = cl[best].translation() + RotateAbout(p - q[best], Vec2(0, 0), -(rate - n.pre_rate) * s[best]);
    }
  }
  return out;
}

const std::vector<Pose2>& MapOptimizer::MappedPath(const Node& n, std::vector<Pose2>* scratch) const {
  if (n.pre_rate == 0.0) return n.path_raw;
  *scratch = asr::CorrectedPath(n.path_raw, n.raw, n.raw, n.pre_rate);
  return *scratch;
}

double MapOptimizer::PreBendRate() const {
  if (nodes_.empty() || !(options_.pre_bend_max_sigma_rad_per_m > 0.0) || pre_n_ < options_.pre_bend_min_directions)
    return 0.0;
  const double sxx = pre_wss_ - pre_ws_ * pre_ws_ / pre_w_;
  const double sigma = sxx > 0.0 ? 1.0 / std::sqrt(sxx) : std::numeric_limits<double>::infinity();
  if (!(sigma <= options_.pre_bend_max_sigma_rad_per_m)) return 0.0;
  // The run's rate, as Finish reports it: the mean of the nodes' rates (one
  // node's alone wanders with the heading noise between its neighbours'
  // walls: 0.96-1.41 deg/m on intel at 1 deg/m).
  const double r = MeanRate();
  // A rate the walls do not tell from none (the drift test's level, one
  // degree of freedom) is not removed: noise would bend good rooms.
  if (!std::isfinite(r) || r * r < ChiSquareQuantile(options_.drift_test_probability, 1) * sigma * sigma) return 0.0;
  return r;
}

int MapOptimizer::RoomOf(int asr_id) const {
  auto it = node_of_asr_.find(asr_id);
  return it == node_of_asr_.end() ? -1 : nodes_[it->second].room_id;
}

}  // namespace cogmap::graph
