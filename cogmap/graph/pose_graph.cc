#include "cogmap/graph/pose_graph.h"

#include "cogmap/graph/pose_costs.h"

#include <ceres/ceres.h>

#include <Eigen/Dense>
#include <Eigen/SparseCholesky>
#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstring>
#include <deque>
#include <limits>
#include <map>
#include <unordered_map>

namespace cogmap::graph {
namespace {

using costs::kQuarter;

Eigen::Matrix3d SqrtInformation(const Eigen::Matrix3d& covariance) {
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> es(0.5 * (covariance + covariance.transpose()));
  Eigen::Vector3d inv_sqrt;
  for (int i = 0; i < 3; ++i) inv_sqrt(i) = 1.0 / std::sqrt(std::max(es.eigenvalues()(i), 1e-12));
  return inv_sqrt.asDiagonal() * es.eigenvectors().transpose();
}

// The odometry's whitening, heading first: row 2 is the heading error over
// its marginal sigma; rows 0 and 1 whiten the translation error less what the
// heading error explains of it (the conditional of translation given heading).
// So the chi^2 splits into a heading part and a translation part, and each
// can be scaled on its own: scaling row 2 scales the heading noise together
// with the lateral error it causes, scaling rows 0-1 the rest.
Eigen::Matrix3d HeadingFirstSqrtInformation(const Eigen::Matrix3d& covariance) {
  const Eigen::Matrix3d C = 0.5 * (covariance + covariance.transpose());
  const double var_h = std::max(C(2, 2), 1e-18);
  const Eigen::Vector2d K = C.block<2, 1>(0, 2) / var_h;  // translation per unit heading error
  const Eigen::Matrix2d cond = C.block<2, 2>(0, 0) - K * C.block<1, 2>(2, 0);
  // cond = L L^T: |L^-1 x|^2 = x^T cond^-1 x.
  const Eigen::Matrix2d L = Eigen::LLT<Eigen::Matrix2d>(cond).matrixL();
  const Eigen::Matrix2d A = L.inverse();
  Eigen::Matrix3d W = Eigen::Matrix3d::Zero();
  W.block<2, 2>(0, 0) = A;
  W.block<2, 1>(0, 2) = -A * K;
  W(2, 2) = 1.0 / std::sqrt(var_h);
  return W;
}

}  // namespace

const char* FactorKindName(FactorKind k) {
  switch (k) {
    case FactorKind::kOdometry: return "odometry";
    case FactorKind::kDirection: return "wall_direction";
    case FactorKind::kRegistration: return "registration";
    case FactorKind::kLoopClosure: return "loop_closure";
    case FactorKind::kRateWalk: return "rate_walk";
    case FactorKind::kRatePrior: return "rate_prior";
    case FactorKind::kOdometryHeading: return "odometry_heading";
  }
  return "?";
}

OdometryMeasurement MeasureOdometry(const std::vector<Pose2>& path, const OdometryNoiseOptions& o, int max_steps,
                                    const std::vector<double>* turns) {
  OdometryMeasurement m;
  if (path.empty()) {
    m.covariance = Eigen::Vector3d(o.min_sigma_m * o.min_sigma_m, o.min_sigma_m * o.min_sigma_m,
                                   o.min_sigma_rad * o.min_sigma_rad)
                       .asDiagonal();
    return m;
  }
  m.delta = path.back();
  // Covariance of the robot pose in node i's frame, propagated step by step.
  Eigen::Matrix3d P = Eigen::Matrix3d::Zero();
  Pose2 prev{0.0, 0.0, path.front().theta};
  std::vector<Eigen::Vector3d> fine;  // (dx, dy, s mid)
  double s = 0.0;
  auto step = [&](const Pose2& q, double turned) {
    const Vec2 d = q.translation() - prev.translation();
    const double ds = d.norm();
    const double dth = NormalizeAngle(q.theta - prev.theta);
    const double turn = std::max(std::abs(dth), turned);
    if (ds > 0.0) fine.emplace_back(d.x(), d.y(), s + 0.5 * ds);
    Eigen::Matrix3d F = Eigen::Matrix3d::Identity();
    F(0, 2) = -d.y();
    F(1, 2) = d.x();
    const Vec2 u = ds > 1e-9 ? Vec2(d / ds) : Vec2(std::cos(q.theta), std::sin(q.theta));
    Eigen::Matrix<double, 3, 2> G = Eigen::Matrix<double, 3, 2>::Zero();
    G(0, 0) = u.x();
    G(1, 0) = u.y();
    G(2, 1) = 1.0;
    Eigen::Matrix2d Q = Eigen::Matrix2d::Zero();
    Q(0, 0) = o.trans_sigma_m_per_sqrt_m * o.trans_sigma_m_per_sqrt_m * ds;
    Q(1, 1) = o.heading_sigma_rad_per_sqrt_m * o.heading_sigma_rad_per_sqrt_m * ds +
              o.rot_sigma_rad_per_sqrt_rad * o.rot_sigma_rad_per_sqrt_rad * turn;
    P = F * P * F.transpose() + G * Q * G.transpose();
    s += ds;
    m.turn_rad += turn;
    prev = q;
  };
  // (The first pose's turn came before node i's origin.)
  const bool with_turns = turns && turns->size() == path.size();
  for (size_t k = 0; k < path.size(); ++k) step(path[k], with_turns && k > 0 ? (*turns)[k] : 0.0);
  m.distance_m = s;
  // Merge the fine steps into at most max_steps (consecutive sums; the mid
  // distance is the length-weighted mean).
  const size_t n = fine.size();
  const size_t per = std::max<size_t>(1, (n + max_steps - 1) / std::max(1, max_steps));
  for (size_t i = 0; i < n; i += per) {
    Eigen::Vector3d acc = Eigen::Vector3d::Zero();
    double w = 0.0;
    for (size_t k = i; k < std::min(n, i + per); ++k) {
      acc.x() += fine[k].x();
      acc.y() += fine[k].y();
      const double len = std::hypot(fine[k].x(), fine[k].y());
      acc.z() += len * fine[k].z();
      w += len;
    }
    acc.z() = w > 0 ? acc.z() / w : 0.0;
    m.steps.push_back(acc);
  }
  // (The first path pose may sit off node i's origin: the first fine step
  // runs from the origin to it.)
  // Into the frame of the measured end pose.
  Eigen::Matrix3d R = Eigen::Matrix3d::Identity();
  const double c = std::cos(m.delta.theta), sn = std::sin(m.delta.theta);
  R(0, 0) = c;
  R(0, 1) = sn;
  R(1, 0) = -sn;
  R(1, 1) = c;
  m.covariance = R * P * R.transpose();
  m.covariance(0, 0) += o.min_sigma_m * o.min_sigma_m;
  m.covariance(1, 1) += o.min_sigma_m * o.min_sigma_m;
  m.covariance(2, 2) += o.min_sigma_rad * o.min_sigma_rad;
  return m;
}

struct PoseGraph::Impl {
  std::deque<std::array<double, 3>> nodes;
  std::deque<double> rates;
  std::vector<double> offsets;  // per node: the drift rate its measurements already had removed
  std::vector<bool> fixed;
  // The building directions: the first (phi[0]) and any turned wing's
  // (AddBuildingDirection); a deque, so that the factors' pointers stay.
  std::deque<double> phi{0.0};
  bool has_phi = false;
  struct Factor {
    FactorKind kind;
    int i = -1, j = -1;
    int dof = 0;
    std::unique_ptr<ceres::CostFunction> cost;
    std::unique_ptr<ceres::LossFunction> loss;  // may be null
    double cauchy_scale = 0.0;                  // the loss's scale (0: none)
    std::vector<double*> params;
    bool enabled = true;
    double* scale = nullptr;  // the functor's scale (variance components), when it has one
    // A part of the factor scaled as a component of its own (kOdometry: its
    // heading row, kOdometryHeading), when it has one.
    FactorKind part_kind = FactorKind::kOdometry;
    double* part_scale = nullptr;
    const OdometryMeasurement* odometry = nullptr;  // kOdometry: the measurement
    costs::DirectionCost* direction = nullptr;            // kDirection: the functor
    int family = 0;                                       // kDirection: its building direction
    // Relative factors (AddRelative), for DirectionProfile: the measured
    // heading (of the middle, between the bends), the marginal variance of
    // its heading, and each bent end's path length and rate offset (0: not bent).
    double rel_theta = 0.0, rel_heading_var = 0.0;
    double bend_s_i = 0.0, bend_s_j = 0.0, bend_off_i = 0.0, bend_off_j = 0.0;
  };
  std::vector<Factor> factors;
  std::vector<int> relative_index;  // AddRelative index -> factors index
  bool rates_zero = false;
  bool held_at_offsets = false;  // SetRatesHeldAtOffsets: held rates equal their offsets, not zero
  bool has_rate_prior = false;  // the first chain's rate has its prior
  // Redundancies(): the information matrix's symbolic factorisation (its
  // fill-reducing ordering and elimination tree), kept while its pattern
  // stays the same: the variance-component rounds ask again and again of
  // the same graph with other weights.
  struct Symbolic {
    std::vector<int> outer, inner;  // the pattern it was analysed for
    Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> ldlt;
  };
  std::unique_ptr<Symbolic> symbolic;

  bool Free(int node, int first_free) const { return node >= first_free && !fixed[node]; }

  // Each node's heading change per unit of a common change of every drift
  // rate, the nodes following by dead reckoning: the distance driven from
  // the chain's fixed start to it, negated (BentPathEnd turns a path's end
  // by -rate x its length).
  std::vector<double> TurnPerRate() const {
    std::vector<double> turn(nodes.size(), 0.0);
    for (const auto& f : factors)
      if (f.kind == FactorKind::kOdometry && f.odometry && !fixed[f.j]) turn[f.j] = turn[f.i] - f.odometry->distance_m;
    return turn;
  }

  void Build(ceres::Problem* problem, int first_free, bool all) {
    auto at = [](const double* block) { return const_cast<double*>(block); };  // Factor::params are const
    std::vector<double*> params;
    for (Factor& f : factors) {
      if (!f.enabled) continue;
      // The drift rate of node i belongs to the edge leaving it: the rates
      // from first_free - 1 on move (the edge into the window included),
      // fixed (anchor) nodes' too.
      const bool rate_factor = f.kind == FactorKind::kOdometry || f.kind == FactorKind::kRateWalk ||
                               f.kind == FactorKind::kRatePrior || f.kind == FactorKind::kDirection;
      const bool touches = all || (f.i >= 0 && Free(f.i, first_free)) || (f.j >= 0 && Free(f.j, first_free)) ||
                           (rate_factor && f.i >= first_free - 1);
      if (!touches) continue;
      params.clear();
      for (const double* p : f.params) params.push_back(at(p));
      problem->AddResidualBlock(f.cost.get(), f.loss.get(), params);
    }
    for (size_t n = 0; n < nodes.size(); ++n) {
      const bool free = Free(static_cast<int>(n), first_free);
      double* node = at(nodes[n].data());
      double* rate = at(&rates[n]);
      if (problem->HasParameterBlock(node) && !free) problem->SetParameterBlockConstant(node);
      if (problem->HasParameterBlock(rate) && (rates_zero || static_cast<int>(n) < first_free - 1))
        problem->SetParameterBlockConstant(rate);
    }
  }
};

PoseGraph::PoseGraph() : impl_(std::make_unique<Impl>()) {}
PoseGraph::~PoseGraph() = default;

int PoseGraph::AddNode(const Pose2& initial, bool fixed, double rate_offset) {
  impl_->nodes.push_back({initial.x, initial.y, initial.theta});
  // The drift already removed from its measurements is the best first guess
  // of its drift (0 when none was).
  impl_->rates.push_back(rate_offset);
  impl_->offsets.push_back(rate_offset);
  impl_->fixed.push_back(fixed);
  return static_cast<int>(impl_->nodes.size()) - 1;
}

int PoseGraph::size() const { return static_cast<int>(impl_->nodes.size()); }

void PoseGraph::AddOdometry(int i, int j, const OdometryMeasurement& m, const OdometryNoiseOptions& noise) {
  auto* c = new costs::OdometryCost{m, HeadingFirstSqrtInformation(m.covariance), impl_->offsets[i]};
  Impl::Factor f;
  f.scale = &c->scale;
  f.part_kind = FactorKind::kOdometryHeading;
  f.part_scale = &c->scale_heading;
  f.odometry = &c->m;
  f.kind = FactorKind::kOdometry;
  f.i = i;
  f.j = j;
  f.dof = 3;
  f.cost.reset(new costs::Analytic<costs::OdometryCost, 3, 3, 3, 1>(c));
  f.params = {impl_->nodes[i].data(), impl_->nodes[j].data(), &impl_->rates[i]};
  impl_->factors.push_back(std::move(f));
  // The drift rate: a random walk from node i to node j, and a prior on the
  // first rate of a chain.
  const double walk = noise.rate_walk_rad_per_m_per_sqrt_m * std::sqrt(std::max(m.distance_m, 0.1));
  Impl::Factor w;
  w.kind = FactorKind::kRateWalk;
  w.i = i;
  w.j = j;
  w.dof = 1;
  w.cost.reset(new costs::Analytic<costs::RateWalkCost, 1, 1, 1>(new costs::RateWalkCost{1.0 / walk}));
  w.params = {&impl_->rates[i], &impl_->rates[j]};
  impl_->factors.push_back(std::move(w));
  if (!impl_->has_rate_prior) {
    impl_->has_rate_prior = true;
    Impl::Factor p;
    p.kind = FactorKind::kRatePrior;
    p.i = i;
    p.dof = 1;
    p.cost.reset(new costs::Analytic<costs::RatePriorCost, 1, 1>(
        new costs::RatePriorCost{1.0 / noise.rate_prior_sigma_rad_per_m}));
    p.params = {&impl_->rates[i]};
    impl_->factors.push_back(std::move(p));
  }
}

void PoseGraph::SetFactorEnabled(int handle, bool enabled) { impl_->factors[handle].enabled = enabled; }

int PoseGraph::AddDirection(int i, double d, double sigma, double s_mean_m, double floor_rad, double cauchy_scale,
                            double s_spread_m) {
  if (!impl_->has_phi) {
    // The building direction starts at this first room's wall direction.
    impl_->phi[0] = impl_->nodes[i][2] + d;
    impl_->has_phi = true;
  }
  Impl::Factor f;
  f.kind = FactorKind::kDirection;
  f.i = i;
  f.dof = 1;
  auto* c = new costs::DirectionCost{d, sigma, s_mean_m, floor_rad, impl_->offsets[i]};
  c->s_spread = s_spread_m;
  f.scale = &c->scale;
  f.direction = c;
  f.cost.reset(new costs::Analytic<costs::DirectionCost, 1, 3, 1, 1>(c));
  f.loss.reset(new ceres::CauchyLoss(cauchy_scale));
  f.cauchy_scale = cauchy_scale;
  f.params = {impl_->nodes[i].data(), &impl_->phi[0], &impl_->rates[i]};
  impl_->factors.push_back(std::move(f));
  return static_cast<int>(impl_->factors.size()) - 1;
}

int PoseGraph::AddRelative(int i, int j, const Pose2& z, const Eigen::Matrix3d& cov, FactorKind kind,
                           double cauchy_scale, const OdometryMeasurement* bend_i,
                           const OdometryMeasurement* bend_j) {
  Impl::Factor f;
  f.kind = kind;
  f.i = i;
  f.j = j;
  f.dof = 3;
  f.rel_theta = z.theta;
  f.rel_heading_var = cov(2, 2);
  if (bend_i || bend_j) {
    const OdometryMeasurement none;
    const OdometryMeasurement& mi = bend_i ? *bend_i : none;
    const OdometryMeasurement& mj = bend_j ? *bend_j : none;
    auto* c = new costs::BentRelativeCost{mi, mj, mi.delta.inverse() * z * mj.delta, SqrtInformation(cov),
                                   bend_i ? impl_->offsets[i] : 0.0, bend_j ? impl_->offsets[j] : 0.0};
    f.rel_theta = c->middle.theta;
    f.bend_s_i = mi.distance_m;
    f.bend_s_j = mj.distance_m;
    f.bend_off_i = c->offset_i;
    f.bend_off_j = c->offset_j;
    f.scale = &c->scale;
    f.cost.reset(new costs::Analytic<costs::BentRelativeCost, 3, 3, 3, 1, 1>(c));
    f.params = {impl_->nodes[i].data(), impl_->nodes[j].data(), &impl_->rates[i], &impl_->rates[j]};
  } else {
    auto* c = new costs::RelativeCost{z, SqrtInformation(cov)};
    f.scale = &c->scale;
    f.cost.reset(new costs::Analytic<costs::RelativeCost, 3, 3, 3>(c));
    f.params = {impl_->nodes[i].data(), impl_->nodes[j].data()};
  }
  if (cauchy_scale > 0) {
    f.loss.reset(new ceres::CauchyLoss(cauchy_scale));
    f.cauchy_scale = cauchy_scale;
  }
  impl_->factors.push_back(std::move(f));
  impl_->relative_index.push_back(static_cast<int>(impl_->factors.size()) - 1);
  return static_cast<int>(impl_->relative_index.size()) - 1;
}

Pose2 PoseGraph::Bend(int i, const OdometryMeasurement& m) const {
  return BendAt(m, impl_->rates[i] - impl_->offsets[i]);
}

namespace {
// The path's end under drift rate 'rate' (m's steps re-integrated), in doubles.
Pose2 BentPathEnd(const OdometryMeasurement& m, double rate) {
  Vec2 t(0, 0);
  for (const Eigen::Vector3d& st : m.steps) t += RotateAbout(Vec2(st.x(), st.y()), Vec2(0.0, 0.0), -rate * st.z());
  return Pose2{t.x(), t.y(), m.delta.theta - rate * m.distance_m};
}
}  // namespace

Pose2 BendAt(const OdometryMeasurement& m, double rate) { return BentPathEnd(m, rate) * m.delta.inverse(); }

void PoseGraph::SetSigmaFactor(FactorKind kind, double factor) {
  for (auto& f : impl_->factors) {
    if (f.kind == kind && f.scale) *f.scale = 1.0 / factor;
    if (f.part_kind == kind && f.part_scale) *f.part_scale = 1.0 / factor;
  }
}

double PoseGraph::SigmaFactor(FactorKind kind) const {
  for (const auto& f : impl_->factors) {
    if (f.kind == kind && f.scale) return 1.0 / *f.scale;
    if (f.part_kind == kind && f.part_scale) return 1.0 / *f.part_scale;
  }
  return 1.0;
}

void PoseGraph::SetRelativeEnabled(int k, bool enabled) {
  impl_->factors[impl_->relative_index[k]].enabled = enabled;
}

PoseGraph::SolveSummary PoseGraph::Solve(int first_free, int max_iterations) {
  const auto t0 = std::chrono::steady_clock::now();
  SolveSummary out;
  ceres::Problem::Options po;
  po.cost_function_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
  po.loss_function_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
  ceres::Problem problem(po);
  impl_->Build(&problem, first_free, false);
  for (int n = first_free; n < size(); ++n) out.free_nodes += impl_->fixed[n] ? 0 : 1;
  if (problem.NumResidualBlocks() == 0) {
    out.usable = true;
    return out;
  }
  ceres::Solver::Options so;
  so.linear_solver_type = ceres::SPARSE_NORMAL_CHOLESKY;
  so.max_num_iterations = max_iterations;
  // Stop when an iteration lowers the cost by less than 1 part in 10^4: at a
  // chi^2 near its degrees of freedom (a few hundred) that is a change of a
  // few hundredths, far below the chi^2's own spread (its sd is sqrt(2 dof)),
  // and the poses move by millimetres (intel: at most 5 mm and 0.02 deg from
  // Ceres' default 10^-6, with 45 % fewer iterations).
  so.function_tolerance = 1e-4;
  so.num_threads = 1;
  so.logging_type = ceres::SILENT;
  so.minimizer_progress_to_stdout = false;
  ceres::Solver::Summary summary;
  ceres::Solve(so, &problem, &summary);
  for (auto& n : impl_->nodes) n[2] = NormalizeAngle(n[2]);
  out.iterations = static_cast<int>(summary.iterations.size());
  out.initial_cost = summary.initial_cost;
  out.final_cost = summary.final_cost;
  out.usable = summary.IsSolutionUsable();
  out.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return out;
}

void PoseGraph::ChainWithRate(double rate) {
  for (double& r : impl_->rates) r = rate;
  for (const auto& f : impl_->factors) {
    if (f.kind != FactorKind::kOdometry || !f.odometry || impl_->fixed[f.j]) continue;
    set_pose(f.j, pose(f.i) * BentPathEnd(*f.odometry, rate - impl_->offsets[f.i]));
  }
}

std::vector<double> PoseGraph::DirectionProfile(const std::vector<double>& deltas) const {
  std::vector<double> out(deltas.size(), 0.0);
  const Impl& m = *impl_;
  if (!m.has_phi) return out;
  const std::vector<double> turn = m.TurnPerRate();
  // Each enabled direction factor's residual angle at delta = 0 (before
  // the branch is chosen), its change per unit of delta, its sigma and loss.
  // A factor's Cauchy loss, evaluated here as ceres::CauchyLoss does (the
  // same operations, so the same values) without its virtual call, and the
  // weight without the logarithm the cost needs: the profile evaluates it
  // some ten times a term and rate (CARMEN intel: a million times).
  struct Cauchy {
    double b = 0.0, c = 0.0;  // scale squared and its inverse; b = 0: no loss
    explicit Cauchy(double scale) {
      if (scale > 0.0) {
        b = scale * scale;
        c = 1.0 / b;
      }
    }
    double Rho(double s) const { return b > 0.0 ? b * std::log(1.0 + s * c) : s; }
    double Weight(double s) const {
      return b > 0.0 ? std::max(std::numeric_limits<double>::min(), 1.0 / (1.0 + s * c)) : 1.0;
    }
  };
  struct Term {
    double v0, slope, inv_sigma2;
    Cauchy loss;
    int family = 0;
  };
  std::vector<Term> terms;
  for (const auto& f : m.factors) {
    if (!f.enabled || f.kind != FactorKind::kDirection || !f.direction) continue;
    const costs::DirectionCost& d = *f.direction;
    const double rate = m.rates[f.i] - d.offset;
    const double v0 = m.nodes[f.i][2] + d.d - rate * d.s_mean - m.phi[f.family];
    const double sigma = d.Sigma();
    terms.push_back({v0, turn[f.i] - d.s_mean, 1.0 / (sigma * sigma), Cauchy(f.loss ? f.cauchy_scale : 0.0), f.family});
  }
  // The registrations and loop closures: a common rate change turns node j
  // against node i by delta x the distance driven between them, and each
  // bent end's measurement by delta x its path; what is left turns the
  // measured heading against the poses (zero across an exit, whose
  // registration is bent by node i's path to node j). Their headings alone,
  // with their marginal sigma: a lower bound on what they add.
  struct Heading {
    double e0, slope, inv_sigma2;
    Cauchy loss;
  };
  std::vector<Heading> headings;
  for (const auto& f : m.factors) {
    if (!f.enabled || (f.kind != FactorKind::kRegistration && f.kind != FactorKind::kLoopClosure)) continue;
    const double slope = (turn[f.j] - turn[f.i]) - (f.bend_s_j - f.bend_s_i);
    if (std::abs(slope) < 1e-9 || f.rel_heading_var <= 0.0) continue;
    const double ri = m.rates[f.i] - f.bend_off_i, rj = m.rates[f.j] - f.bend_off_j;
    const double measured = f.rel_theta - ri * f.bend_s_i + rj * f.bend_s_j;
    const double e0 = NormalizeAngle(m.nodes[f.j][2] - m.nodes[f.i][2] - measured);
    const double scale = f.scale ? *f.scale : 1.0;
    headings.push_back({e0, slope, scale * scale / f.rel_heading_var, Cauchy(f.loss ? f.cauchy_scale : 0.0)});
  }
  if (terms.empty()) return out;
  const int families = static_cast<int>(m.phi.size());
  std::vector<double> a(terms.size());
  for (size_t k = 0; k < deltas.size(); ++k) {
    for (size_t t = 0; t < terms.size(); ++t) a[t] = terms[t].v0 + deltas[k] * terms[t].slope;
    // Each building direction: the weighted mean of its factors' angles on
    // the quarter-turn circle (4 x angle), then re-weighted least squares
    // on the nearest branches; the lower of that and the unmoved direction.
    double walls = 0.0;
    for (int family = 0; family < families; ++family) {
      double sx = 0.0, sy = 0.0;
      for (size_t t = 0; t < terms.size(); ++t) {
        if (terms[t].family != family) continue;
        sx += terms[t].inv_sigma2 * std::cos(4.0 * a[t]);
        sy += terms[t].inv_sigma2 * std::sin(4.0 * a[t]);
      }
      auto cost_at = [&](double phi) {
        double c = 0.0;
        for (size_t t = 0; t < terms.size(); ++t) {
          if (terms[t].family != family) continue;
          const double e = FoldQuarter(a[t] - phi);
          c += terms[t].loss.Rho(e * e * terms[t].inv_sigma2);
        }
        return 0.5 * c;
      };
      auto refit = [&](double phi) {
        for (int it = 0; it < 4; ++it) {
          double num = 0.0, den = 0.0;
          for (size_t t = 0; t < terms.size(); ++t) {
            if (terms[t].family != family) continue;
            const double e = FoldQuarter(a[t] - phi);
            const double w = terms[t].inv_sigma2 * terms[t].loss.Weight(e * e * terms[t].inv_sigma2);
            num += w * e;
            den += w;
          }
          if (den <= 0.0) break;
          phi += num / den;
        }
        return cost_at(phi);
      };
      walls += std::min(refit(0.0), refit(0.25 * std::atan2(sy, sx)));
    }
    double rest = 0.0;
    for (const Heading& h : headings) {
      const double e = NormalizeAngle(h.e0 + deltas[k] * h.slope);
      rest += h.loss.Rho(e * e * h.inv_sigma2);
    }
    out[k] = walls + 0.5 * rest;
  }
  return out;
}

void PoseGraph::SetRatesFixedAtZero(bool fixed) {
  impl_->rates_zero = fixed;
  if (fixed)
    for (size_t n = 0; n < impl_->rates.size(); ++n) impl_->rates[n] = impl_->held_at_offsets ? impl_->offsets[n] : 0.0;
}

void PoseGraph::SetRatesHeldAtOffsets(bool on) { impl_->held_at_offsets = on; }

bool PoseGraph::RatesFixedAtZero() const { return impl_->rates_zero; }

PoseGraph::State PoseGraph::Save() const {
  State s;
  for (int i = 0; i < size(); ++i) s.poses.push_back(pose(i));
  s.rates.assign(impl_->rates.begin(), impl_->rates.end());
  s.phi.assign(impl_->phi.begin(), impl_->phi.end());
  return s;
}

void PoseGraph::Restore(const State& s) {
  for (size_t i = 0; i < s.poses.size(); ++i) set_pose(static_cast<int>(i), s.poses[i]);
  for (size_t i = 0; i < s.rates.size(); ++i) impl_->rates[i] = s.rates[i];
  for (size_t k = 0; k < s.phi.size() && k < impl_->phi.size(); ++k) impl_->phi[k] = s.phi[k];
}

Pose2 PoseGraph::pose(int i) const {
  const auto& n = impl_->nodes[i];
  return {n[0], n[1], NormalizeAngle(n[2])};
}
void PoseGraph::set_pose(int i, const Pose2& p) { impl_->nodes[i] = {p.x, p.y, p.theta}; }
double PoseGraph::rate(int i) const { return impl_->rates[i]; }
bool PoseGraph::has_direction() const { return impl_->has_phi; }
double PoseGraph::building_direction(int family) const { return impl_->phi[family]; }
int PoseGraph::building_directions() const { return static_cast<int>(impl_->phi.size()); }

int PoseGraph::AddBuildingDirection(double initial_rad) {
  impl_->phi.push_back(initial_rad);
  return static_cast<int>(impl_->phi.size()) - 1;
}

void PoseGraph::SetBuildingDirection(int family, double rad) { impl_->phi[family] = rad; }

void PoseGraph::SetDirectionFamily(int handle, int family) {
  Impl::Factor& f = impl_->factors[handle];
  f.family = family;
  f.params[1] = &impl_->phi[family];
}

int PoseGraph::DirectionFamily(int handle) const { return impl_->factors[handle].family; }

void PoseGraph::RemoveBuildingDirections() {
  for (size_t k = 0; k < impl_->factors.size(); ++k)
    if (impl_->factors[k].kind == FactorKind::kDirection) SetDirectionFamily(static_cast<int>(k), 0);
  impl_->phi.resize(1);
}

std::vector<PoseGraph::DirectionTerm> PoseGraph::DirectionTerms() const {
  const Impl& m = *impl_;
  const std::vector<double> turn = m.TurnPerRate();
  std::vector<DirectionTerm> out;
  for (size_t k = 0; k < m.factors.size(); ++k) {
    const Impl::Factor& f = m.factors[k];
    if (!f.enabled || f.kind != FactorKind::kDirection || !f.direction) continue;
    const costs::DirectionCost& d = *f.direction;
    const double world = m.nodes[f.i][2] + d.d - (m.rates[f.i] - d.offset) * d.s_mean;
    out.push_back(
        {static_cast<int>(k), f.i, world, turn[f.i] - d.s_mean, d.Sigma(), std::max(d.floor, d.sigma), f.family});
  }
  return out;
}

double PoseGraph::Cost() const {
  double cost = 0.0;
  for (const Impl::Factor& f : impl_->factors) {
    if (!f.enabled) continue;
    double r[3] = {0, 0, 0};
    f.cost->Evaluate(f.params.data(), r, nullptr);
    double chi2 = 0.0;
    for (int a = 0; a < f.dof; ++a) chi2 += r[a] * r[a];
    if (f.loss) {
      double rho[3];
      f.loss->Evaluate(chi2, rho);
      chi2 = rho[0];
    }
    cost += 0.5 * chi2;
  }
  return cost;
}

// The enabled factors linearised at the graph's values: each factor's
// weighted whitened Jacobian over its free columns (the loss's weight
// rho'(s) as Ceres applies it for Cauchy and Huber losses, whose rho'' <= 0)
// and the normal matrix H = J^T J they add up to.
struct PoseGraph::Linearized {
  struct Rows {
    std::vector<int> col;  // global column of each free entry
    Eigen::MatrixXd J;     // dof x col.size()
  };
  std::vector<Rows> rows;       // per factor (empty for disabled ones)
  std::vector<double> weight;   // per factor
  std::unordered_map<const double*, int> first_col;
  int cols = 0;
  Eigen::SparseMatrix<double> H;
};

// The selected inverse S = (P H P^T)^-1 on the pattern of H's factor L:
// every entry of the inverse a covariance block or a redundancy number
// needs, at the cost of the factorisation (Takahashi's recurrences), where
// the whole inverse (or one solve per column) grows with the square of the
// graph.
struct PoseGraph::SelectedInverse {
  std::vector<double> sdiag, sval;
  const Eigen::SparseMatrix<double>* L = nullptr;
  Eigen::VectorXi perm;
  // Entry (a, b) of H^-1, in H's own column order.
  double operator()(int a, int b) const {
    const int i = perm(a), k = perm(b);
    if (i == k) return sdiag[i];
    const int c = std::min(i, k), r = std::max(i, k);
    const int* outer = L->outerIndexPtr();
    const int* inner = L->innerIndexPtr();
    const int* nnz = L->innerNonZeroPtr();
    const int* bgn = inner + outer[c];
    const int* end = inner + (nnz ? outer[c] + nnz[c] : outer[c + 1]);
    const int* q = std::lower_bound(bgn, end, r);
    return (q != end && *q == r) ? sval[q - inner] : 0.0;
  }
};

double PoseGraph::SingularPivot(const Linearized& lin) const {
  // Rank deficiency as SuiteSparseQR's default tolerance would find it:
  // a pivot of R below 20 (m + n) eps times the largest column norm, so a
  // pivot of D below its square times H's largest diagonal entry.
  size_t m = 0;
  for (size_t k = 0; k < impl_->factors.size(); ++k)
    if (impl_->factors[k].enabled) m += static_cast<size_t>(impl_->factors[k].dof);
  const double tol = 20.0 * static_cast<double>(m + static_cast<size_t>(lin.cols)) * std::numeric_limits<double>::epsilon();
  return tol * tol;
}

std::vector<Eigen::Matrix3d> PoseGraph::Covariances(std::vector<Eigen::Matrix3d>* aligned) const {
  // The marginal covariance of each free node: its 3 x 3 block of H^-1 for
  // the Jacobian Ceres would use (every enabled factor, its loss applied),
  // from the selected inverse. ceres::Covariance (SPARSE_QR) solved for every
  // column and took a time growing with the square of the graph (1.1 s of a
  // 1000-room building's 14 s).
  const size_t N = impl_->nodes.size();
  if (aligned) aligned->clear();
  std::vector<Eigen::Matrix3d> out(N, Eigen::Matrix3d::Zero());
  const Linearized lin = Linearize(!impl_->rates_zero);
  std::vector<int> node_col(N, -1);
  bool any = false;
  for (size_t n = 0; n < N; ++n) {
    if (impl_->fixed[n]) continue;
    auto it = lin.first_col.find(impl_->nodes[n].data());
    if (it == lin.first_col.end()) continue;
    node_col[n] = it->second;
    any = true;
  }
  if (!any) {
    if (aligned && N > 1) aligned->assign(N, Eigen::Matrix3d::Zero());
    return out;
  }
  SelectedInverse S;
  if (!Invert(lin, SingularPivot(lin), &S)) return {};
  for (size_t n = 0; n < N; ++n) {
    const int c = node_col[n];
    if (c < 0) continue;
    for (int a = 0; a < 3; ++a)
      for (int b = 0; b < 3; ++b) out[n](a, b) = S(c + a, c + b);
  }
  if (aligned) LaidCovariances(out, node_col, lin.cols, aligned);
  return out;
}

void PoseGraph::LaidCovariances(const std::vector<Eigen::Matrix3d>& marginal, const std::vector<int>& node_col,
                                int cols, std::vector<Eigen::Matrix3d>* out) const {
  // e' = e - G a, a = A sum_i G_i^T W e_i: node i's error less the rigid
  // move (translation, rotation about the centroid) fitted to the position
  // errors (W keeps x and y), A = (sum_i G_i^T W G_i)^-1. Its covariance
  // needs Sigma W G (three solves with H's factorisation, the one the
  // marginal blocks came from) besides those blocks:
  // Cov(e'_i) = S_ii - G_i A X_i^T - X_i A G_i^T + G_i A M A G_i^T,
  // X = Sigma W G, M = G^T W Sigma W G.
  const size_t N = impl_->nodes.size();
  Vec2 c(0.0, 0.0);
  for (size_t n = 0; n < N; ++n) c += Vec2(impl_->nodes[n][0], impl_->nodes[n][1]);
  c /= static_cast<double>(N);
  auto G = [&](size_t n) {
    Eigen::Matrix3d g = Eigen::Matrix3d::Identity();
    g(0, 2) = -(impl_->nodes[n][1] - c.y());
    g(1, 2) = impl_->nodes[n][0] - c.x();
    return g;
  };
  Eigen::Matrix3d W = Eigen::Matrix3d::Zero();
  W(0, 0) = W(1, 1) = 1.0;
  Eigen::Matrix3d info = Eigen::Matrix3d::Zero();
  for (size_t n = 0; n < N; ++n) info += G(n).transpose() * W * G(n);
  if (std::abs(info.determinant()) < 1e-12) return;  // one node, or all at one place: no move to fit
  const Eigen::Matrix3d A = info.inverse();
  Eigen::MatrixXd B = Eigen::MatrixXd::Zero(cols, 3);
  for (size_t n = 0; n < N; ++n)
    if (node_col[n] >= 0) B.block<3, 3>(node_col[n], 0) = W * G(n);
  const Eigen::MatrixXd X = impl_->symbolic->ldlt.solve(B);
  if (impl_->symbolic->ldlt.info() != Eigen::Success || !X.allFinite()) return;
  const Eigen::Matrix3d M = B.transpose() * X;
  out->assign(N, Eigen::Matrix3d::Zero());
  for (size_t n = 0; n < N; ++n) {
    const Eigen::Matrix3d Xi =
        node_col[n] >= 0 ? Eigen::Matrix3d(X.block<3, 3>(node_col[n], 0)) : Eigen::Matrix3d::Zero();
    const Eigen::Matrix3d g = G(n);
    (*out)[n] = marginal[n] - g * A * Xi.transpose() - Xi * A * g.transpose() + g * A * M * A * g.transpose();
  }
}

std::vector<double> PoseGraph::RateVariances() const {
  std::vector<double> var(impl_->nodes.size(), 0.0);
  if (impl_->rates_zero) return var;
  const Linearized lin = Linearize(true);
  SelectedInverse S;
  if (!Invert(lin, SingularPivot(lin), &S)) return std::vector<double>(impl_->nodes.size(), -1.0);
  for (size_t n = 0; n < impl_->nodes.size(); ++n) {
    auto it = lin.first_col.find(&impl_->rates[n]);
    if (it != lin.first_col.end()) var[n] = std::max(0.0, S(it->second, it->second));
  }
  return var;
}

void PoseGraph::SetDirectionBend(bool on, const std::vector<double>& rate_variances) {
  // The rate left to each factor's node, and how uncertain it is (the
  // marginal variance of its rate, when the rates are free and the graph
  // is invertible): E[(rate x spread)^2] = (rate^2 + var) x spread^2.
  std::vector<double> var(impl_->nodes.size(), 0.0);
  if (on && !impl_->rates_zero) {
    if (rate_variances.size() == var.size()) {
      var = rate_variances;
    } else {
      for (auto& f : impl_->factors)
        if (f.direction) f.direction->bend = 0.0;
      var = RateVariances();
    }
    for (double& v : var) v = std::max(0.0, v);  // singular: the solved rate alone
  }
  for (auto& f : impl_->factors) {
    if (!f.direction) continue;
    const double r = impl_->rates[f.i] - f.direction->offset;
    f.direction->bend = on ? f.direction->s_spread * std::sqrt(r * r + var[f.i]) : 0.0;
  }
}

namespace {
double CauchyConsistency(int dof, double a);
// CauchyConsistency for a factor, remembered per (dof, scale): a run asks for
// the same few pairs again and again (each thread keeps the ones it computed).
double Consistency(int dof, double cauchy_scale) {
  thread_local std::map<std::pair<int, double>, double> kappa;
  const std::pair<int, double> key{dof, cauchy_scale};
  auto it = kappa.find(key);
  if (it == kappa.end()) it = kappa.emplace(key, CauchyConsistency(dof, cauchy_scale)).first;
  return it->second;
}
}  // namespace

std::vector<PoseGraph::FactorResidual> PoseGraph::Residuals() const {
  std::vector<FactorResidual> out;
  std::vector<int> rel_of(impl_->factors.size(), -1);
  for (size_t k = 0; k < impl_->relative_index.size(); ++k) rel_of[impl_->relative_index[k]] = static_cast<int>(k);
  for (size_t k = 0; k < impl_->factors.size(); ++k) {
    const auto& f = impl_->factors[k];
    double r[3] = {0, 0, 0};
    f.cost->Evaluate(f.params.data(), r, nullptr);
    double chi2 = 0.0;
    for (int a = 0; a < f.dof; ++a) chi2 += r[a] * r[a];
    FactorResidual x{f.kind, f.i, f.j, rel_of[k], chi2, f.dof, f.enabled, f.part_scale ? r[2] * r[2] : 0.0};
    if (f.loss) {
      double rho[3];
      f.loss->Evaluate(chi2, rho);
      x.weight = rho[1];
      x.consistency = Consistency(f.dof, f.cauchy_scale);
    }
    out.push_back(x);
  }
  return out;
}

namespace {
// E[w(x) x] / dof for x ~ chi^2(dof) and the Cauchy weight w(x) = 1 / (1 + x /
// a^2): what a factor's weighted chi^2 is worth per unit of redundancy when
// its sigma is right (1 without a loss). By x = t^2 and Simpson's rule on
// t in [0, 12 + sqrt(dof)].
double CauchyConsistency(int dof, double a) {
  if (!(a > 0.0)) return 1.0;
  const double b = a * a, k = dof;
  const double norm = 2.0 / (std::pow(2.0, 0.5 * k) * std::tgamma(0.5 * k));
  const int n = 2000;
  const double hi = 12.0 + std::sqrt(k), h = hi / n;
  double sum = 0.0;
  for (int i = 0; i <= n; ++i) {
    const double t = i * h, x = t * t;
    const double f = norm * std::pow(t, k - 1.0) * std::exp(-0.5 * x) * x / (1.0 + x / b);
    sum += (i == 0 || i == n ? 1.0 : (i % 2 ? 4.0 : 2.0)) * f;
  }
  return sum * h / 3.0 / k;
}
}  // namespace

PoseGraph::Linearized PoseGraph::Linearize(bool rates_free) const {
  const auto& factors = impl_->factors;
  Linearized lin;
  // The free parameter blocks: nodes not held, rates unless held at zero, phi
  // (by address, sorted: one allocation, not one per block).
  std::vector<std::pair<const double*, bool>> is_free;
  is_free.reserve(2 * impl_->nodes.size() + impl_->phi.size());
  for (size_t n = 0; n < impl_->nodes.size(); ++n) {
    is_free.emplace_back(impl_->nodes[n].data(), !impl_->fixed[n]);
    is_free.emplace_back(&impl_->rates[n], rates_free);
  }
  for (const double& p : impl_->phi) is_free.emplace_back(&p, true);
  std::sort(is_free.begin(), is_free.end());
  auto free_block = [&](const double* p) {
    auto it = std::lower_bound(is_free.begin(), is_free.end(), p,
                               [](const std::pair<const double*, bool>& e, const double* q) { return e.first < q; });
    return it != is_free.end() && it->first == p && it->second;
  };
  auto& first_col = lin.first_col;
  first_col.reserve(is_free.size());
  int& cols = lin.cols;
  auto& rows = lin.rows;
  rows.resize(factors.size());
  lin.weight.assign(factors.size(), 0.0);
  std::vector<Eigen::Triplet<double>> triplets;
  size_t most_triplets = 0;  // (the sum of the blocks' sizes)^2 per factor: no regrowth below
  for (const auto& f : factors) {
    if (!f.enabled) continue;
    size_t n = 0;
    for (int32_t s : f.cost->parameter_block_sizes()) n += static_cast<size_t>(s);
    most_triplets += n * n;
  }
  triplets.reserve(most_triplets);
  // Per factor, reused: its Jacobian's blocks (one buffer), their addresses,
  // its free columns' (block, offset), its J^T J.
  std::vector<double> jac;
  std::vector<double*> jp;
  std::vector<size_t> at;  // each block's offset in jac
  std::vector<std::pair<size_t, int>> entries;
  Eigen::MatrixXd H;
  for (size_t k = 0; k < factors.size(); ++k) {
    const auto& f = factors[k];
    if (!f.enabled) continue;
    const std::vector<int32_t>& sizes = f.cost->parameter_block_sizes();
    size_t total = 0;
    for (int32_t b : sizes) total += static_cast<size_t>(b);
    jac.assign(static_cast<size_t>(f.dof) * total, 0.0);
    jp.resize(sizes.size());
    at.resize(sizes.size());
    for (size_t b = 0, offset = 0; b < sizes.size(); offset += static_cast<size_t>(f.dof) * sizes[b], ++b) {
      jp[b] = jac.data() + offset;
      at[b] = offset;
    }
    double r[3] = {0, 0, 0};
    if (!f.cost->Evaluate(f.params.data(), r, jp.data())) continue;
    double s = 0.0;
    for (int a = 0; a < f.dof; ++a) s += r[a] * r[a];
    double w = 1.0;
    if (f.loss) {
      double rho[3];
      f.loss->Evaluate(s, rho);
      w = rho[1];
    }
    lin.weight[k] = w;
    Linearized::Rows& R = rows[k];
    R.col.reserve(total);
    entries.clear();
    for (size_t b = 0; b < sizes.size(); ++b) {
      const double* p = f.params[b];
      if (!free_block(p)) continue;
      auto [c, added] = first_col.emplace(p, cols);
      if (added) cols += sizes[b];
      for (int o = 0; o < sizes[b]; ++o) {
        R.col.push_back(c->second + o);
        entries.emplace_back(b, o);
      }
    }
    R.J.resize(f.dof, static_cast<int>(R.col.size()));
    const double sw = std::sqrt(w);
    for (int a = 0; a < f.dof; ++a)
      for (size_t e = 0; e < entries.size(); ++e)
        R.J(a, static_cast<int>(e)) = sw * jac[at[entries[e].first] + a * sizes[entries[e].first] + entries[e].second];
    H.noalias() = R.J.transpose() * R.J;
    for (size_t a = 0; a < R.col.size(); ++a)
      for (size_t b = 0; b < R.col.size(); ++b) triplets.emplace_back(R.col[a], R.col[b], H(a, b));
  }
  if (cols == 0) return lin;
  lin.H.resize(cols, cols);
  lin.H.setFromTriplets(triplets.begin(), triplets.end());
  lin.H.makeCompressed();
  return lin;
}

bool PoseGraph::Invert(const Linearized& lin, double min_pivot, SelectedInverse* out) const {
  const Eigen::SparseMatrix<double>& H = lin.H;
  const int cols = static_cast<int>(H.cols());
  // The symbolic part again only when the pattern changed (the same
  // ordering and the same numbers as analysing it afresh).
  auto& sym = impl_->symbolic;
  const bool same_pattern = sym && static_cast<int>(sym->outer.size()) == cols + 1 &&
                            std::equal(sym->outer.begin(), sym->outer.end(), H.outerIndexPtr()) &&
                            static_cast<Eigen::Index>(sym->inner.size()) == H.nonZeros() &&
                            std::equal(sym->inner.begin(), sym->inner.end(), H.innerIndexPtr());
  if (!same_pattern) {
    sym = std::make_unique<Impl::Symbolic>();
    sym->outer.assign(H.outerIndexPtr(), H.outerIndexPtr() + cols + 1);
    sym->inner.assign(H.innerIndexPtr(), H.innerIndexPtr() + H.nonZeros());
    sym->ldlt.analyzePattern(H);
  }
  Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>>& ldlt = sym->ldlt;
  ldlt.factorize(H);
  if (ldlt.info() != Eigen::Success) return false;
  const Eigen::SparseMatrix<double>& L = ldlt.matrixL().nestedExpression();  // strictly lower, unit diagonal
  const Eigen::VectorXd D = ldlt.vectorD();
  // A pivot at or below min_pivot times H's largest diagonal entry: a
  // direction the factors do not determine (min_pivot < 0: no test).
  if (min_pivot >= 0.0) {
    double largest = 0.0;
    for (int c = 0; c < cols; ++c) largest = std::max(largest, H.coeff(c, c));
    for (int j = 0; j < cols; ++j)
      if (!(D(j) > min_pivot * largest)) return false;
  }
  // From the last column back, S_ij = -sum_k L_kj S_ik and
  // S_jj = 1/D_j - sum_k L_kj S_kj over the rows k of column j.
  std::vector<double>& sdiag = out->sdiag;
  std::vector<double>& sval = out->sval;
  sdiag.assign(cols, 0.0);
  sval.assign(L.nonZeros(), 0.0);
  const int* outer = L.outerIndexPtr();
  const int* inner = L.innerIndexPtr();
  const int* nnz = L.innerNonZeroPtr();
  auto col_end = [&](int c) { return nnz ? outer[c] + nnz[c] : outer[c + 1]; };
  const double* lval = L.valuePtr();
  // Column j needs S over its rows R_j (all after j, so already known):
  // gathered once into a dense block from the columns of R_j, which hold
  // every pair of R_j (a column's pattern holds its descendants' below it).
  std::vector<int> pos(cols, -1);  // row -> its place in R_j
  std::vector<double> block;
  for (int j = cols - 1; j >= 0; --j) {
    const int b = outer[j], e = col_end(j);
    const int m = e - b;
    for (int a = 0; a < m; ++a) pos[inner[b + a]] = a;
    block.assign(static_cast<size_t>(m) * m, 0.0);
    for (int a = 0; a < m; ++a) {
      const int c = inner[b + a];
      block[static_cast<size_t>(a) * m + a] = sdiag[c];
      for (int q = outer[c]; q < col_end(c); ++q) {
        const int at = pos[inner[q]];
        if (at < 0) continue;
        block[static_cast<size_t>(a) * m + at] = sval[q];
        block[static_cast<size_t>(at) * m + a] = sval[q];
      }
    }
    for (int a = 0; a < m; ++a) pos[inner[b + a]] = -1;
    for (int t = b; t < e; ++t) {
      const double* row = block.data() + static_cast<size_t>(t - b) * m;
      double z = 0.0;
      for (int u = b; u < e; ++u) z -= lval[u] * row[u - b];
      sval[t] = z;
    }
    double d = 1.0 / D(j);
    for (int t = b; t < e; ++t) d -= lval[t] * sval[t];
    sdiag[j] = d;
  }
  out->L = &L;
  out->perm = ldlt.permutationP().indices();
  return true;
}

std::vector<PoseGraph::FactorRedundancy> PoseGraph::Redundancies() const {
  const auto& factors = impl_->factors;
  std::vector<FactorRedundancy> out(factors.size(), FactorRedundancy{0.0, 0.0});
  Linearized lin = Linearize(!impl_->rates_zero);
  for (size_t k = 0; k < factors.size(); ++k) out[k].weight = lin.weight[k];
  const int cols = lin.cols;
  if (cols == 0) {
    for (size_t k = 0; k < factors.size(); ++k)
      if (factors[k].enabled) out[k].redundancy = factors[k].dof;
    return out;
  }
  Eigen::SparseMatrix<double>& H = lin.H;
  // A parameter nothing determines would make H singular: a relative
  // regularisation far below any factor's information keeps it invertible.
  double max_diag = 0.0;
  for (int c = 0; c < cols; ++c) max_diag = std::max(max_diag, H.coeff(c, c));
  for (int c = 0; c < cols; ++c) H.coeffRef(c, c) += 1e-12 * std::max(1.0, max_diag);
  SelectedInverse S;
  if (!Invert(lin, -1.0, &S)) return {};
  const auto& rows = lin.rows;
  Eigen::MatrixXd Sf, JS, JSJ;  // reused from factor to factor
  for (size_t k = 0; k < factors.size(); ++k) {
    if (!factors[k].enabled) continue;
    const Linearized::Rows& R = rows[k];
    const int m = static_cast<int>(R.col.size());
    if (m == 0) {
      JSJ.setZero(factors[k].dof, factors[k].dof);
    } else {
      Sf.resize(m, m);
      for (int a = 0; a < m; ++a)
        for (int b = 0; b < m; ++b) Sf(a, b) = S(R.col[a], R.col[b]);
      JS.noalias() = R.J * Sf;
      JSJ.noalias() = JS * R.J.transpose();
    }
    out[k].redundancy = std::clamp(factors[k].dof - JSJ.trace(), 0.0, static_cast<double>(factors[k].dof));
    if (factors[k].part_scale) out[k].redundancy_heading = std::clamp(1.0 - JSJ(2, 2), 0.0, 1.0);
  }
  for (size_t k = 0; k < factors.size(); ++k)
    if (factors[k].enabled) out[k].consistency = Consistency(factors[k].dof, factors[k].cauchy_scale);
  return out;
}

namespace {
// Regularised lower incomplete gamma P(a, x): the power series below a + 1,
// the continued fraction (modified Lentz) above.
double GammaP(double a, double x) {
  if (x <= 0.0) return 0.0;
  const double lg = std::lgamma(a);
  if (x < a + 1.0) {
    double term = 1.0 / a, sum = term;
    for (int n = 1; n < 500; ++n) {
      term *= x / (a + n);
      sum += term;
      if (std::abs(term) < std::abs(sum) * 1e-15) break;
    }
    return sum * std::exp(-x + a * std::log(x) - lg);
  }
  double b = x + 1.0 - a, c = 1e300, d = 1.0 / b, h = d;
  for (int i = 1; i < 500; ++i) {
    const double an = -i * (i - a);
    b += 2.0;
    d = an * d + b;
    if (std::abs(d) < 1e-300) d = 1e-300;
    c = b + an / c;
    if (std::abs(c) < 1e-300) c = 1e-300;
    d = 1.0 / d;
    const double del = d * c;
    h *= del;
    if (std::abs(del - 1.0) < 1e-15) break;
  }
  return 1.0 - std::exp(-x + a * std::log(x) - lg) * h;
}
}  // namespace

double ChiSquareQuantile(double p, int dof) {
  // A run asks for a few (p, dof) pairs thousands of times: each thread keeps
  // the ones it computed.
  struct Known {
    double p;
    int dof;
    double quantile;
  };
  thread_local std::vector<Known> known;
  for (const Known& q : known)
    if (q.p == p && q.dof == dof) return q.quantile;
  // Bisection on the chi-square CDF P(k/2, x/2), 200 halvings at most; once
  // a halving leaves (lo, hi) as they were, every later one does too (the
  // same midpoint, the same test), so stopping there gives the same value.
  const double k = std::max(1, dof);
  double lo = 0.0, hi = k + 50.0 * std::sqrt(2.0 * k) + 50.0;
  for (int it = 0; it < 200; ++it) {
    const double mid = 0.5 * (lo + hi);
    double& side = GammaP(0.5 * k, 0.5 * mid) < p ? lo : hi;
    if (side == mid) break;
    side = mid;
  }
  const double quantile = 0.5 * (lo + hi);
  if (known.size() >= 256) known.erase(known.begin());  // p and dof from outside: bounded
  known.push_back({p, dof, quantile});
  return quantile;
}

}  // namespace cogmap::graph
