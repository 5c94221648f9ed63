#include "cogmap/graph/pose_costs.h"

#include <gtest/gtest.h>

#include <random>
#include <string>
#include <vector>

namespace cogmap::graph::costs {
namespace {

// A raw path turning by 'rate' per metre, as MeasureOdometry sees it.
OdometryMeasurement Path(double length_m, double rate, double first_turn) {
  std::vector<Pose2> path;
  Pose2 p{0.0, 0.0, first_turn};
  for (double s = 0.0; s <= length_m + 1e-9; s += 0.1) {
    path.push_back(p);
    p = p * Pose2{0.1, 0.0, rate * 0.1};
  }
  return MeasureOdometry(path);
}

Eigen::Matrix3d RandomWhitening(std::mt19937& rng) {
  std::normal_distribution<double> n(0.0, 1.0);
  Eigen::Matrix3d W;
  for (int a = 0; a < 3; ++a)
    for (int b = 0; b < 3; ++b) W(a, b) = (a == b ? 5.0 : 0.0) + n(rng);
  return W;
}

// Evaluates 'analytic' and the same functor through ceres::AutoDiffCostFunction
// at 'params': the residuals must be the same to the bit (the solves'
// steps and costs come from them), each Jacobian entry the same to within
// rounding (relative to the block's largest), and a residual-only call the
// same residuals too. 'with_jacobian' per block: asked for or not.
template <typename F, int kRes, int... kBlocks>
void ExpectSameAsAutoDiff(const F& functor, std::vector<std::vector<double>> params, const std::string& what) {
  const Analytic<F, kRes, kBlocks...> analytic(new F(functor));
  const ceres::AutoDiffCostFunction<F, kRes, kBlocks...> automatic(new F(functor));
  const std::vector<int> sizes = {kBlocks...};
  std::vector<const double*> p;
  for (auto& b : params) p.push_back(b.data());
  for (int mask = 0; mask < (1 << sizes.size()); ++mask) {
    std::vector<std::vector<double>> ja(sizes.size()), jb(sizes.size());
    std::vector<double*> pa(sizes.size(), nullptr), pb(sizes.size(), nullptr);
    for (size_t b = 0; b < sizes.size(); ++b) {
      ja[b].assign(kRes * sizes[b], -7.0);
      jb[b].assign(kRes * sizes[b], 7.0);
      if (mask & (1 << b)) pa[b] = ja[b].data(), pb[b] = jb[b].data();
    }
    double ra[kRes], rb[kRes];
    ASSERT_TRUE(analytic.Evaluate(p.data(), ra, pa.data()));
    ASSERT_TRUE(automatic.Evaluate(p.data(), rb, pb.data()));
    for (int a = 0; a < kRes; ++a) EXPECT_EQ(ra[a], rb[a]) << what << " residual " << a << " mask " << mask;
    for (size_t b = 0; b < sizes.size(); ++b) {
      if (!(mask & (1 << b))) continue;
      double largest = 1e-12;
      for (double v : jb[b]) largest = std::max(largest, std::abs(v));
      for (size_t e = 0; e < jb[b].size(); ++e)
        EXPECT_NEAR(ja[b][e], jb[b][e], 1e-12 * largest) << what << " block " << b << " entry " << e;
    }
  }
  double ra[kRes], rb[kRes];
  ASSERT_TRUE(analytic.Evaluate(p.data(), ra, nullptr));
  ASSERT_TRUE(automatic.Evaluate(p.data(), rb, nullptr));
  for (int a = 0; a < kRes; ++a) EXPECT_EQ(ra[a], rb[a]) << what << " residual-only " << a;
}

std::vector<double> Pose(std::mt19937& rng, double spread) {
  std::uniform_real_distribution<double> u(-spread, spread), th(-3.1, 3.1);
  return {u(rng), u(rng), th(rng)};
}

TEST(AnalyticCosts, OdometryMatchesAutomaticDifferentiation) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> rate(-0.05, 0.05);
  for (int trial = 0; trial < 20; ++trial) {
    OdometryCost c{Path(3.0 + trial, 0.02 * (trial % 5) - 0.04, 0.1 * trial), RandomWhitening(rng), 0.003 * trial};
    c.scale = 0.7 + 0.05 * trial;
    c.scale_heading = 1.3 - 0.02 * trial;
    // The same rate twice in a row (the cache's path) and a new one.
    const double r = rate(rng);
    for (double each : {r, r, rate(rng)})
      ExpectSameAsAutoDiff<OdometryCost, 3, 3, 3, 1>(c, {Pose(rng, 10), Pose(rng, 10), {each}},
                                                      "odometry trial " + std::to_string(trial));
  }
}

TEST(AnalyticCosts, RelativeAndBentRelativeMatchAutomaticDifferentiation) {
  std::mt19937 rng(12);
  std::uniform_real_distribution<double> rate(-0.05, 0.05);
  for (int trial = 0; trial < 20; ++trial) {
    const std::vector<double> z = Pose(rng, 4);
    RelativeCost rel{Pose2{z[0], z[1], z[2]}, RandomWhitening(rng), 0.5 + 0.1 * trial};
    ExpectSameAsAutoDiff<RelativeCost, 3, 3, 3>(rel, {Pose(rng, 10), Pose(rng, 10)},
                                                "relative trial " + std::to_string(trial));
    // Bent at both ends, at one end (an exit: the other's path empty).
    const OdometryMeasurement mi = Path(2.0 + trial, 0.03, 0.2), none;
    const OdometryMeasurement mj = trial % 2 ? Path(1.0 + 0.5 * trial, -0.02, -0.1) : none;
    BentRelativeCost bent{mi, mj, Pose2{z[0], z[1], z[2]}, RandomWhitening(rng), 0.001 * trial, -0.002 * trial};
    bent.scale = 1.1;
    ExpectSameAsAutoDiff<BentRelativeCost, 3, 3, 3, 1, 1>(bent, {Pose(rng, 10), Pose(rng, 10), {rate(rng)}, {rate(rng)}},
                                                          "bent relative trial " + std::to_string(trial));
  }
}

TEST(AnalyticCosts, DirectionAndRateFactorsMatchAutomaticDifferentiation) {
  std::mt19937 rng(13);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (int trial = 0; trial < 20; ++trial) {
    DirectionCost d{u(rng), 0.02 + 0.01 * trial, 3.0 * std::abs(u(rng)), 0.01, 0.001 * trial};
    d.scale = 0.8;
    d.bend = 0.004 * trial;
    // Headings on every branch of the quarter turn.
    ExpectSameAsAutoDiff<DirectionCost, 1, 3, 1, 1>(d, {Pose(rng, 10), {u(rng) * 3.0}, {0.05 * u(rng)}},
                                                    "direction trial " + std::to_string(trial));
    ExpectSameAsAutoDiff<RateWalkCost, 1, 1, 1>(RateWalkCost{50.0 + trial}, {{0.01 * u(rng)}, {0.01 * u(rng)}},
                                                "rate walk");
    ExpectSameAsAutoDiff<RatePriorCost, 1, 1>(RatePriorCost{30.0 + trial}, {{0.01 * u(rng)}}, "rate prior");
  }
}

// The residual and Jacobian of one relative pose against central
// differences: the analytic derivatives are of the model, not of a copy
// of it (AutoDiff above shares the functor's templated code).
TEST(AnalyticCosts, RelativeJacobianMatchesCentralDifferences) {
  std::mt19937 rng(14);
  for (int trial = 0; trial < 10; ++trial) {
    const Eigen::Matrix3d W = RandomWhitening(rng);
    std::vector<double> in = Pose(rng, 5);
    const std::vector<double> pj = Pose(rng, 5), m = Pose(rng, 2);
    in.insert(in.end(), pj.begin(), pj.end());
    in.insert(in.end(), m.begin(), m.end());
    double r[3];
    Eigen::Matrix<double, 3, 9> J;
    RelativeResidualJ(&in[0], &in[3], &in[6], W, r, &J);
    for (int k = 0; k < 9; ++k) {
      const double h = 1e-6;
      std::vector<double> up = in, down = in;
      up[k] += h;
      down[k] -= h;
      double ru[3], rd[3];
      Eigen::Matrix<double, 3, 9> unused;
      RelativeResidualJ(&up[0], &up[3], &up[6], W, ru, &unused);
      RelativeResidualJ(&down[0], &down[3], &down[6], W, rd, &unused);
      for (int a = 0; a < 3; ++a) EXPECT_NEAR(J(a, k), (ru[a] - rd[a]) / (2 * h), 1e-6) << "column " << k;
    }
  }
}

}  // namespace
}  // namespace cogmap::graph::costs
