#include "cogmap/graph/pose_graph.h"

#include <gtest/gtest.h>

#include <array>

#include "cogmap/asr/asr.h"

#include <Eigen/Dense>
#include <cmath>
#include <thread>
#include <vector>


namespace cogmap::graph {
namespace {

std::vector<Pose2> Straight(double length_m, double step_m = 0.1) {
  std::vector<Pose2> p;
  for (double s = 0; s <= length_m + 1e-9; s += step_m) p.push_back({s, 0.0, 0.0});
  return p;
}

// The odometry of a raw path of 'length_m' turning left by 'rate' per metre.
OdometryMeasurement TurningOdometry(double length_m, double rate) {
  std::vector<Pose2> path;
  Pose2 p;
  for (double s = 0.0; s <= length_m + 1e-9; s += 0.1) {
    path.push_back(p);
    p = p * Pose2{0.1, 0.0, rate * 0.1};
  }
  return MeasureOdometry(path);
}

TEST(OdometryModel, VarianceGrowsWithDistanceAndHeadingTurnsLateral) {
  OdometryNoiseOptions o;
  const auto m2 = MeasureOdometry(Straight(2.0), o);
  const auto m8 = MeasureOdometry(Straight(8.0), o);
  EXPECT_NEAR(m8.distance_m, 8.0, 1e-9);
  EXPECT_GT(m8.covariance(0, 0), 3.0 * m2.covariance(0, 0));
  // Lateral variance grows with the cube of the distance (heading random walk).
  EXPECT_GT(m8.covariance(1, 1), 20.0 * m2.covariance(1, 1));
  EXPECT_NEAR(m8.covariance(2, 2),
              o.heading_sigma_rad_per_sqrt_m * o.heading_sigma_rad_per_sqrt_m * 8.0 + o.min_sigma_rad * o.min_sigma_rad,
              1e-9);
}

TEST(PoseGraph, DriftRateIsRecoveredFromWallDirections) {
  // A straight run of 10 rooms 4 m apart; the odometry turns 2 deg/m to the
  // left; every room's walls are axis-aligned in truth.
  const double rate = DegToRad(2.0);
  PoseGraph g;
  Pose2 raw;
  g.AddNode(raw, true);
  g.AddDirection(0, 0.0, DegToRad(1.0));
  for (int i = 1; i <= 10; ++i) {
    const auto m = TurningOdometry(4.0, rate);
    raw = raw * m.delta;
    g.AddNode(raw);
    g.AddOdometry(i - 1, i, m);
    // Each room's walls are axis-aligned in its own (true) local frame; its
    // raw pose carries the drift.
    g.AddDirection(i, 0.0, DegToRad(1.0));
    g.Solve(0);
  }
  for (int i = 0; i <= 10; ++i) {
    EXPECT_NEAR(g.pose(i).theta, 0.0, DegToRad(0.5)) << i;
    EXPECT_NEAR(g.pose(i).y, 0.0, 0.1) << i;
    EXPECT_NEAR(g.pose(i).x, 4.0 * i, 0.1) << i;
  }
  EXPECT_NEAR(g.rate(5), rate, DegToRad(0.2));
  const auto cov = g.Covariances();
  ASSERT_EQ(cov.size(), 11u);
  EXPECT_GT(cov[10](1, 1), cov[1](1, 1));
}

// The direction factors' profile over a common rate change: at 0 it is the
// factors' robust cost as solved (half the Cauchy-weighted chi^2 of
// Residuals()), and a change that turns the farthest room by a quarter turn
// relative to the nearest one fits as well when every room's walls were seen
// at the same distance from it; half-way it does not.
TEST(PoseGraph, DirectionProfileRepeatsEveryQuarterTurnOverThePath) {
  PoseGraph g;
  Pose2 raw;
  g.AddNode(raw, true);
  g.AddDirection(0, 0.0, DegToRad(1.0), 0.0);
  const auto m = TurningOdometry(10.0, DegToRad(1.0));
  raw = raw * m.delta;
  g.AddNode(raw);
  g.AddOdometry(0, 1, m);
  g.AddDirection(1, 0.0, DegToRad(1.0), 0.0);
  g.Solve(0);
  const double quarter = (kPi / 2.0) / m.distance_m;  // turns node 1 by a quarter turn
  const std::vector<double> p = g.DirectionProfile({0.0, quarter, -quarter, 0.5 * quarter});
  ASSERT_EQ(p.size(), 4u);
  double expected = 0.0;
  for (const auto& r : g.Residuals())
    if (r.kind == FactorKind::kDirection) expected += 0.5 * 4.0 * std::log1p(r.chi2 / 4.0);  // Cauchy scale 2
  EXPECT_NEAR(p[0], expected, 1e-6);
  EXPECT_NEAR(p[1], p[0], 1e-6);
  EXPECT_NEAR(p[2], p[0], 1e-6);
  // Half-way the two rooms' walls are 45 degrees apart: at best each is
  // 22.5 degrees (22.5 sigma) from the building direction.
  EXPECT_GT(p[3], p[0] + 10.0);
  // A loop closure between the two (node 1 seen from node 0, unbent, 1
  // degree sigma) holds their relative heading: the quarter turn that fits
  // the walls turns it by 90 degrees (Cauchy-weighted: 4 log(1 + (90/2)^2)
  // / 2 and more).
  Eigen::Matrix3d cov = Eigen::Matrix3d::Identity() * 0.01;
  cov(2, 2) = std::pow(DegToRad(1.0), 2);
  g.AddRelative(0, 1, g.pose(0).inverse() * g.pose(1), cov, FactorKind::kLoopClosure, 2.0);
  const std::vector<double> q = g.DirectionProfile({0.0, quarter});
  EXPECT_NEAR(q[0], p[0], 1e-6);  // the closure fits the current poses
  EXPECT_GT(q[1], q[0] + 0.5 * 4.0 * std::log1p(90.0 * 90.0 / 4.0) - 1e-6);
}

// A relative factor's covariance is along the measured pose's own axes (as
// the odometry's is along its end pose's). Node 1 is measured a quarter turn
// from node 0, tightly along its own x (the map's y) and in heading, loosely
// along its own y (the map's x); a second, isotropic measurement pulls it
// 0.5 m along the map's x and 0.3 m along the map's y. The loose axis gives
// way, the tight one holds.
TEST(PoseGraph, ARelativeFactorsCovarianceIsAlongTheMeasuredPosesAxes) {
  PoseGraph g;
  g.AddNode({0, 0, 0}, true);
  g.AddNode({1, 0, DegToRad(90.0)});
  g.SetRatesFixedAtZero(true);
  const Eigen::Matrix3d tight_x = Eigen::Vector3d(1e-4, 100.0, 1e-6).asDiagonal();
  g.AddRelative(0, 1, {1, 0, DegToRad(90.0)}, tight_x, FactorKind::kRegistration, 0.0);
  g.AddRelative(0, 1, {1.5, 0.3, DegToRad(90.0)}, Eigen::Matrix3d::Identity() * 0.01, FactorKind::kLoopClosure, 0.0);
  g.Solve();
  EXPECT_NEAR(g.pose(1).x, 1.5, 0.01);
  EXPECT_NEAR(g.pose(1).y, 0.0, 0.01);
  EXPECT_NEAR(g.pose(1).theta, DegToRad(90.0), 1e-3);
}

// Two nodes a measured 4 m apart: once the map is laid on the truth by its
// best rigid move, only the distance between them is uncertain, shared by
// the two (each moves half of it along the line): both positions' variance
// is the along-line variance / 4, whatever the across-line and heading
// variances (the move takes them), where the first ASR's frame puts all of
// it on the second.
TEST(PoseGraph, AlignedCovariancesKeepOnlyWhatARigidMoveCannotTake) {
  PoseGraph g;
  g.AddNode({0, 0, 0}, true);
  g.AddNode({4, 0, 0});
  g.SetRatesFixedAtZero(true);
  const Eigen::Matrix3d cov = Eigen::Vector3d(0.04, 0.09, 1e-3).asDiagonal();
  g.AddRelative(0, 1, {4, 0, 0}, cov, FactorKind::kRegistration, 0.0);
  g.Solve();
  std::vector<Eigen::Matrix3d> aligned;
  const auto anchored = g.Covariances(&aligned);
  ASSERT_EQ(aligned.size(), 2u);
  EXPECT_NEAR(anchored[1](0, 0) + anchored[1](1, 1), 0.13, 1e-9);
  EXPECT_NEAR(aligned[0](0, 0) + aligned[0](1, 1), 0.01, 1e-9);
  EXPECT_NEAR(aligned[1](0, 0) + aligned[1](1, 1), 0.01, 1e-9);
  // The move turns by the across-line error over the 4 m (a quarter of the
  // second's y), and so turns both headings: var 0.09 / 16 on the first,
  // that plus the measured 1e-3 on the second.
  EXPECT_NEAR(aligned[0](2, 2), 0.09 / 16.0, 1e-9);
  EXPECT_NEAR(aligned[1](2, 2), 1e-3 + 0.09 / 16.0, 1e-9);
}

// A chain driven straight: the anchored variance grows from the fixed first
// node to the last; laid on the truth by the best rigid move, both ends are
// the least sure and the middle the surest, every node somewhat unsure and
// the far end less unsure than against the first node.
TEST(PoseGraph, AlignedPositionsAreSurestAtTheMiddleOfAChain) {
  PoseGraph g;
  g.AddNode({0, 0, 0}, true);
  g.SetRatesFixedAtZero(true);
  const Eigen::Matrix3d step = Eigen::Vector3d(0.01, 0.01, DegToRad(1.0) * DegToRad(1.0)).asDiagonal();
  for (int i = 1; i <= 10; ++i) {
    g.AddNode({2.0 * i, 0, 0});
    g.AddRelative(i - 1, i, {2, 0, 0}, step, FactorKind::kRegistration, 0.0);
  }
  g.Solve();
  std::vector<Eigen::Matrix3d> laid;
  const auto anchored = g.Covariances(&laid);
  std::vector<double> aligned;
  for (const Eigen::Matrix3d& c : laid) aligned.push_back(c(0, 0) + c(1, 1));
  ASSERT_EQ(aligned.size(), 11u);
  const double far = anchored[10](0, 0) + anchored[10](1, 1);
  EXPECT_GT(aligned[0], aligned[5]);
  EXPECT_GT(aligned[10], aligned[5]);
  EXPECT_LT(aligned[10], far);
  for (double v : aligned) EXPECT_GT(v, 0.0);
  // Symmetric: the chain reversed is the same chain.
  EXPECT_NEAR(aligned[0], aligned[10], 0.05 * aligned[10]);
}

// The odometry of TurningOdometry's path as mapped with 'offset' removed:
// the path re-integrated under that rate (asr::CorrectedPath).
OdometryMeasurement PreBent(double length_m, double rate, double offset) {
  asr::Asr view;
  Pose2 p;
  for (double s = 0.0; s <= length_m + 1e-9; s += 0.1) {
    view.path.push_back(p);
    p = p * Pose2{0.1, 0.0, rate * 0.1};
  }
  return MeasureOdometry(asr::CorrectedPath(view, offset));
}

// A node's rate offset: the same run given as each room's odometry was
// mapped with 1.5 of the 2 deg/m already removed (the path turning by the
// rest), told so per node, solves to the poses and the whole drift rate of
// the raw odometry's graph.
TEST(PoseGraph, RateOffsetTurnsAPreBentPathBackIntoTheRawOne) {
  const double rate = DegToRad(2.0);
  auto solve = [&](double offset) {
    PoseGraph g;
    Pose2 raw;
    g.AddNode(raw, true, offset);
    g.AddDirection(0, 0.0, DegToRad(1.0));
    for (int i = 1; i <= 10; ++i) {
      raw = raw * TurningOdometry(4.0, rate).delta;
      g.AddNode(raw, false, offset);
      g.AddOdometry(i - 1, i, PreBent(4.0, rate, offset));
      // Walls seen 2 m into the room lean by the drift not yet removed there.
      g.AddDirection(i, (rate - offset) * 2.0, DegToRad(1.0), 2.0);
      g.Solve(0);
    }
    // The bend left to the graph: the rest of the drift.
    const OdometryMeasurement m = PreBent(4.0, rate, offset);
    EXPECT_NEAR(g.Bend(3, m).theta, -(g.rate(3) - offset) * m.distance_m, 1e-9);
    return g.Save();
  };
  const PoseGraph::State raw = solve(0.0), bent = solve(DegToRad(1.5));
  for (size_t i = 0; i < raw.poses.size(); ++i) {
    EXPECT_NEAR(bent.poses[i].x, raw.poses[i].x, 1e-4) << i;
    EXPECT_NEAR(bent.poses[i].y, raw.poses[i].y, 1e-4) << i;
    EXPECT_NEAR(bent.poses[i].theta, raw.poses[i].theta, DegToRad(1e-3)) << i;
    EXPECT_NEAR(bent.rates[i], raw.rates[i], DegToRad(1e-3)) << i;
  }
  EXPECT_NEAR(bent.rates[5], rate, DegToRad(0.2));
}

// A room's walls were seen all along its 4 m of path, each leaning by the
// drift so far; the direction factor corrects them by the mean, and the
// rest, rate x 4 / sqrt(12) m (2.3 degrees at 2 deg/m), is an error the
// covariances hold with SetDirectionBend. Without drift there is none.
TEST(PoseGraph, DirectionBendWidensTheCovariancesByTheDriftOverThePath) {
  auto heading_sigmas = [](double rate) {
    PoseGraph g;
    Pose2 raw;
    const double spread = 4.0 / std::sqrt(12.0);
    g.AddNode(raw, true);
    g.AddDirection(0, 0.0, DegToRad(1.0), 2.0, 0.0, 2.0, spread);
    for (int i = 1; i <= 10; ++i) {
      raw = raw * TurningOdometry(4.0, rate).delta;
      g.AddNode(raw, false);
      g.AddOdometry(i - 1, i, PreBent(4.0, rate, 0.0));
      g.AddDirection(i, rate * 2.0, DegToRad(1.0), 2.0, 0.0, 2.0, spread);
      g.Solve(0);
    }
    std::array<double, 3> out;
    out[0] = std::sqrt(g.Covariances()[10](2, 2));
    g.SetDirectionBend(true);
    out[1] = std::sqrt(g.Covariances()[10](2, 2));
    g.SetDirectionBend(false);
    out[2] = std::sqrt(g.Covariances()[10](2, 2));
    EXPECT_NEAR(g.rate(10), rate, DegToRad(0.2));
    // The rate's own sigma: pinned by eleven directions over 40 m to a few
    // hundredths of a degree per metre, and none while the rates are held.
    const double rate_sigma = std::sqrt(g.RateVariances()[10]);
    EXPECT_GT(rate_sigma, DegToRad(0.005));
    EXPECT_LT(rate_sigma, DegToRad(0.2));
    g.SetRatesFixedAtZero(true);
    EXPECT_EQ(g.RateVariances()[10], 0.0);
    g.SetRatesFixedAtZero(false);
    return out;
  };
  const auto drift = heading_sigmas(DegToRad(2.0));
  EXPECT_GT(drift[1], 1.5 * drift[0]);
  EXPECT_DOUBLE_EQ(drift[2], drift[0]);
  const auto none = heading_sigmas(0.0);
  EXPECT_NEAR(none[1], none[0], 0.05 * none[0]);
}

// One room, no odometry: nothing measures its drift rate, and its variance
// is not known rather than huge (a 1-room run printed a drift of 0 +- 9e8).
TEST(PoseGraph, ARateNothingMeasuresHasNoVariance) {
  PoseGraph g;
  g.AddNode(Pose2{}, true);
  g.AddDirection(0, 0.0, DegToRad(1.0), 2.0);
  g.Solve(0);
  ASSERT_EQ(g.RateVariances().size(), 1u);
  EXPECT_LT(g.RateVariances()[0], 0.0);
}

// The same run with a registration across every exit: each room's walls
// against the previous room's, both in their raw frames, so the measurement
// is the raw relative pose (the walls near the exit were seen with the heading
// drifted as far as the odometry's). Bent by the previous node's rate, the
// registrations leave the drift to the wall directions; taken as true
// relative poses they would hold the rate at zero and the rooms would keep
// the drift.
double MaxHeadingErrorWithExitRegistrations(bool bend) {
  const double rate = DegToRad(2.0);
  PoseGraph g;
  Pose2 raw;
  g.AddNode(raw, true);
  g.AddDirection(0, 0.0, DegToRad(1.0));
  Eigen::Matrix3d reg_cov = Eigen::Matrix3d::Zero();
  reg_cov.diagonal() << 0.02 * 0.02, 0.02 * 0.02, std::pow(DegToRad(0.3), 2);
  for (int i = 1; i <= 10; ++i) {
    const auto m = TurningOdometry(4.0, rate);
    raw = raw * m.delta;
    g.AddNode(raw);
    g.AddOdometry(i - 1, i, m);
    g.AddRelative(i - 1, i, m.delta, reg_cov, FactorKind::kRegistration, 2.0, bend ? &m : nullptr);
    g.AddDirection(i, 0.0, DegToRad(1.0));
    g.Solve(0);
  }
  double worst = 0.0;
  for (int i = 0; i <= 10; ++i) worst = std::max(worst, std::abs(NormalizeAngle(g.pose(i).theta)));
  return worst;
}

TEST(PoseGraph, RegistrationsAcrossExitsAreBentByTheDriftRate) {
  EXPECT_LT(MaxHeadingErrorWithExitRegistrations(true), DegToRad(0.5));
  EXPECT_GT(MaxHeadingErrorWithExitRegistrations(false), DegToRad(3.0));
}

// A closure measured on raw walls that overlap 6 m into node 0 and 3 m into
// node 1 (raw paths turning 1 deg/m left): with both rates at the drift the
// factor's prediction B_0 z B_1^-1 is exactly the true relative pose; at rate
// zero it is not.
TEST(PoseGraph, ClosureBentAtBothEndsIsExactAtTheTrueRate) {
  const double rate = DegToRad(1.0);
  const OdometryMeasurement to_0 = TurningOdometry(6.0, rate), to_1 = TurningOdometry(3.0, rate);
  const Pose2 t0{1.0, 2.0, 0.3}, t1{4.0, 7.0, 1.9};
  const Pose2 z = BendAt(to_0, rate).inverse() * (t0.inverse() * t1) * BendAt(to_1, rate);
  Eigen::Matrix3d cov = Eigen::Matrix3d::Identity() * 1e-4;
  auto chi2_at = [&](double r) {
    PoseGraph g;
    g.AddNode(t0, true);
    g.AddNode(t1);
    g.ChainWithRate(r);
    g.AddRelative(0, 1, z, cov, FactorKind::kLoopClosure, 2.0, &to_0, &to_1);
    return g.Residuals().back().chi2;
  };
  EXPECT_NEAR(chi2_at(rate), 0.0, 1e-12);
  EXPECT_GT(chi2_at(0.0), 100.0);
  // The bend at a path's end turns by the rate times its length.
  EXPECT_NEAR(BendAt(to_0, rate).theta, -rate * to_0.distance_m, 1e-12);
}

// The bends are kept between evaluations while the rate stays the same: a
// factor evaluated at one rate, another, then the first again gives each
// time what a new graph gives at that rate, to the bit.
TEST(PoseGraph, KeptBendsFollowTheRate) {
  const double rate = DegToRad(1.0);
  const OdometryMeasurement to_0 = TurningOdometry(6.0, rate), to_1 = TurningOdometry(3.0, rate);
  const Pose2 t0{1.0, 2.0, 0.3}, t1{4.0, 7.0, 1.9};
  const Pose2 z = BendAt(to_0, rate).inverse() * (t0.inverse() * t1) * BendAt(to_1, rate);
  const Eigen::Matrix3d cov = Eigen::Matrix3d::Identity() * 1e-4;
  auto make = [&](PoseGraph& g) {
    g.AddNode(t0, true);
    g.AddNode(t1);
    g.AddRelative(0, 1, z, cov, FactorKind::kLoopClosure, 2.0, &to_0, &to_1);
  };
  auto fresh = [&](double r) {
    PoseGraph g;
    make(g);
    g.ChainWithRate(r);
    return g.Residuals().back().chi2;
  };
  PoseGraph g;
  make(g);
  for (double r : {0.5 * rate, 0.0, 0.5 * rate, 0.5 * rate, rate, 0.0}) {
    g.ChainWithRate(r);
    EXPECT_EQ(g.Residuals().back().chi2, fresh(r)) << r;
  }
  EXPECT_NE(fresh(0.5 * rate), fresh(0.0));
}

TEST(PoseGraph, BendIsTheIdentityWithoutDrift) {
  PoseGraph g;
  g.AddNode(Pose2{}, true);
  const auto m = MeasureOdometry(Straight(4.0));
  const Pose2 b = g.Bend(0, m);
  EXPECT_NEAR(b.x, 0.0, 1e-12);
  EXPECT_NEAR(b.y, 0.0, 1e-12);
  EXPECT_NEAR(b.theta, 0.0, 1e-12);
}

// Node 1 measured twice from the fixed node 0, covariances 0.01 I and
// 0.04 I (sigmas 0.1 and 0.2), no robust loss.
void MeasureOnePoseTwice(PoseGraph* g) {
  g->AddNode({0, 0, 0}, true);
  g->AddNode({1.0, 0.5, 0.3});
  const Pose2 z{1.0, 0.5, 0.3};
  g->AddRelative(0, 1, z, 0.01 * Eigen::Matrix3d::Identity(), FactorKind::kRegistration, 0.0);
  g->AddRelative(0, 1, z, 0.04 * Eigen::Matrix3d::Identity(), FactorKind::kLoopClosure, 0.0);
}

TEST(PoseGraph, RedundancyOfTwoMeasurementsOfOnePoseIsSharedByTheirVariances) {
  // The three parameters take 3 of the 6 dof; each measurement keeps the
  // share of its own variance, 3 x 0.01 / 0.05 = 0.6 and 3 x 0.04 / 0.05 = 2.4.
  PoseGraph g;
  MeasureOnePoseTwice(&g);
  const auto red = g.Redundancies();
  ASSERT_EQ(red.size(), 2u);
  EXPECT_NEAR(red[0].redundancy, 0.6, 1e-6);
  EXPECT_NEAR(red[1].redundancy, 2.4, 1e-6);
  EXPECT_DOUBLE_EQ(red[0].weight, 1.0);
  EXPECT_NEAR(red[0].consistency, 1.0, 1e-9);  // no robust loss
}

TEST(PoseGraph, CovarianceOfTwoMeasurementsOfOnePoseIsTheirInformationSummed) {
  // Information 100 + 25: (125)^-1 = 0.008 on the diagonal, nothing off it.
  PoseGraph g;
  MeasureOnePoseTwice(&g);
  const auto cov = g.Covariances();
  ASSERT_EQ(cov.size(), 2u);
  EXPECT_TRUE(cov[0].isZero());  // the fixed node
  EXPECT_TRUE(cov[1].isApprox(0.008 * Eigen::Matrix3d::Identity(), 1e-9)) << cov[1];
}

TEST(PoseGraph, CovarianceAlongAChainIsTheFirstOrderPropagation) {
  // 0 (fixed) -> 1 -> 2, each 1 m straight ahead, translation variance
  // st2 and heading variance sh2 per step: node 2's x variance is 2 st2, its
  // y variance 2 st2 + 1 m^2 sh2 (node 1's heading error swings the second
  // step), its heading variance 2 sh2, and y and heading covary by sh2.
  const double st2 = 0.01, sh2 = 0.002;
  Eigen::Matrix3d c = Eigen::Matrix3d::Zero();
  c.diagonal() << st2, st2, sh2;
  PoseGraph g;
  g.AddNode({0, 0, 0}, true);
  g.AddNode({1, 0, 0});
  g.AddNode({2, 0, 0});
  g.AddRelative(0, 1, {1, 0, 0}, c, FactorKind::kRegistration, 0.0);
  g.AddRelative(1, 2, {1, 0, 0}, c, FactorKind::kRegistration, 0.0);
  const auto cov = g.Covariances();
  ASSERT_EQ(cov.size(), 3u);
  EXPECT_TRUE(cov[1].isApprox(c, 1e-9)) << cov[1];
  Eigen::Matrix3d want;
  want << 2 * st2, 0, 0,  //
      0, 2 * st2 + sh2, sh2,  //
      0, sh2, 2 * sh2;
  EXPECT_TRUE(cov[2].isApprox(want, 1e-9)) << cov[2];
}

TEST(PoseGraph, NoCovarianceForAPoseNothingDetermines) {
  // Node 1's heading is measured only by a direction factor and its
  // position by nothing: the graph is singular and says so (no numbers).
  PoseGraph g;
  g.AddNode({0, 0, 0}, true);
  g.AddNode({1, 0, 0});
  g.AddDirection(1, 0.0, 0.01);
  EXPECT_TRUE(g.Covariances().empty());
}

TEST(PoseGraph, RedundanciesSumToTheDofLeftOverByTheParameters) {
  // A chain of 8 rooms with wall directions and one loop closure, held
  // rates: the free parameters are 7 poses and the building direction.
  PoseGraph g;
  Pose2 raw;
  g.AddNode(raw, true);
  g.AddDirection(0, 0.01, DegToRad(1.0));
  for (int i = 1; i < 8; ++i) {
    const auto m = TurningOdometry(4.0, DegToRad(0.5));
    raw = raw * m.delta;
    g.AddNode(raw);
    g.AddOdometry(i - 1, i, m);
    g.AddDirection(i, 0.02 * (i % 3), DegToRad(1.0));
  }
  g.AddRelative(0, 7, Pose2{27.5, 1.0, 0.1}, 0.05 * Eigen::Matrix3d::Identity(), FactorKind::kLoopClosure);
  g.SetRatesFixedAtZero(true);
  g.Solve(0);
  const auto rs = g.Residuals();
  const auto red = g.Redundancies();
  ASSERT_EQ(red.size(), rs.size());
  double used = 0.0;
  for (size_t k = 0; k < rs.size(); ++k) {
    if (!rs[k].enabled) continue;
    EXPECT_GE(red[k].redundancy, 0.0);
    EXPECT_LE(red[k].redundancy, rs[k].dof);
    EXPECT_GT(red[k].weight, 0.0);
    EXPECT_LE(red[k].weight, 1.0);
    used += rs[k].dof - red[k].redundancy;
    // E[w chi2] / dof under chi^2(dof) with the Cauchy loss of scale 2 (by
    // an independent quadrature: 0.6290 for 1 dof, 0.4946 for 3).
    if (rs[k].kind == FactorKind::kDirection) { EXPECT_NEAR(red[k].consistency, 0.6290, 1e-3); }
    if (rs[k].kind == FactorKind::kLoopClosure) { EXPECT_NEAR(red[k].consistency, 0.4946, 1e-3); }
    if (rs[k].kind == FactorKind::kOdometry) { EXPECT_DOUBLE_EQ(red[k].consistency, 1.0); }
  }
  EXPECT_NEAR(used, 7 * 3 + 1, 1e-6);
}

// The odometry's chi^2 splits into its heading row (the heading error over
// its marginal sigma) and the translation given the heading, each scaled by
// its own variance component; together they are the full e^T C^-1 e.
TEST(PoseGraph, OdometryChiSquareSplitsIntoHeadingAndTranslationComponents) {
  const OdometryMeasurement m = MeasureOdometry(Straight(4.0));  // heading error turns lateral: C(1, 2) != 0
  ASSERT_GT(std::abs(m.covariance(1, 2)), 1e-6);
  PoseGraph g;
  g.AddNode({0, 0, 0}, true);
  const Eigen::Vector3d e(0.03, -0.05, DegToRad(1.5));  // in the measured end's frame (its theta is 0 here)
  g.AddNode({m.delta.x + e.x(), m.delta.y + e.y(), m.delta.theta + e.z()});
  g.AddOdometry(0, 1, m);
  g.SetRatesFixedAtZero(true);
  const double full = e.dot(m.covariance.inverse() * e);
  const double heading = e.z() * e.z() / m.covariance(2, 2);
  auto odometry = [&] {
    for (const auto& r : g.Residuals())
      if (r.kind == FactorKind::kOdometry) return r;
    return PoseGraph::FactorResidual{};
  };
  EXPECT_NEAR(odometry().chi2, full, 1e-9 * full);
  EXPECT_NEAR(odometry().chi2_heading, heading, 1e-9 * heading);
  // Heading sigma x2: its part / 4, the translation's part as it was.
  g.SetSigmaFactor(FactorKind::kOdometryHeading, 2.0);
  EXPECT_DOUBLE_EQ(g.SigmaFactor(FactorKind::kOdometryHeading), 2.0);
  EXPECT_DOUBLE_EQ(g.SigmaFactor(FactorKind::kOdometry), 1.0);
  EXPECT_NEAR(odometry().chi2_heading, heading / 4.0, 1e-9 * heading);
  EXPECT_NEAR(odometry().chi2 - odometry().chi2_heading, full - heading, 1e-9 * full);
}

// Node 1 measured by the odometry and by a registration of the same
// covariance: each keeps half of every dof, the odometry's heading row half
// of its one (1 - (1 / C_hh) (C_hh / 2)).
TEST(PoseGraph, OdometryHeadingRowKeepsItsShareOfTheRedundancy) {
  const OdometryMeasurement m = MeasureOdometry(Straight(4.0));
  PoseGraph g;
  g.AddNode({0, 0, 0}, true);
  g.AddNode(m.delta);
  g.AddOdometry(0, 1, m);
  g.AddRelative(0, 1, m.delta, m.covariance, FactorKind::kRegistration, 0.0);
  g.SetRatesFixedAtZero(true);
  const auto rs = g.Residuals();
  const auto red = g.Redundancies();
  ASSERT_EQ(red.size(), rs.size());
  for (size_t k = 0; k < rs.size(); ++k) {
    if (rs[k].kind == FactorKind::kOdometry) {
      EXPECT_NEAR(red[k].redundancy, 1.5, 1e-6);
      EXPECT_NEAR(red[k].redundancy_heading, 0.5, 1e-6);
    }
    if (rs[k].kind == FactorKind::kRegistration) { EXPECT_NEAR(red[k].redundancy, 1.5, 1e-6); }
  }
}

TEST(PoseGraph, ChiSquareQuantileMatchesTables) {
  EXPECT_NEAR(ChiSquareQuantile(0.999, 3), 16.27, 0.15);
  EXPECT_NEAR(ChiSquareQuantile(0.95, 1), 3.84, 0.15);
  EXPECT_NEAR(ChiSquareQuantile(0.999, 100), 149.4, 0.5);
  // Five-digit tables: 16.266, 3.8415, 0.45494 (the median of one dof).
  EXPECT_NEAR(ChiSquareQuantile(0.999, 3), 16.266, 1e-3);
  EXPECT_NEAR(ChiSquareQuantile(0.95, 1), 3.8415, 1e-4);
  EXPECT_NEAR(ChiSquareQuantile(0.5, 1), 0.45494, 1e-5);
}

TEST(PoseGraph, ChiSquareQuantileIsTheSameAskedAgainOrFromAnotherThread) {
  std::vector<double> first;
  for (int dof = 1; dof < 400; ++dof) first.push_back(ChiSquareQuantile(0.999, dof));
  for (int dof = 399; dof >= 1; --dof) EXPECT_EQ(ChiSquareQuantile(0.999, dof), first[dof - 1]) << dof;
  std::vector<double> other;
  std::thread([&] {
    for (int dof = 1; dof < 400; ++dof) other.push_back(ChiSquareQuantile(0.999, dof));
  }).join();
  EXPECT_EQ(other, first);
  EXPECT_LT(first[0], first[1]);
}


TEST(PoseGraph, OdometryCountsTurnsOnTheSpotBetweenPathPoses) {
  // The robot drives 1 m, spins a whole turn on the spot, and drives 1 m: the
  // path keeps poses by distance, so the spin falls between two poses whose
  // headings are equal. With the summed turns given, its heading noise
  // (rot^2 x 2 pi) is in the covariance; without, none of it is.
  OdometryNoiseOptions o;
  const std::vector<Pose2> path = {Pose2{0, 0, 0}, Pose2{1, 0, 0}, Pose2{2, 0, 0}};
  const std::vector<double> turns = {0.0, 0.0, 2.0 * kPi};
  const OdometryMeasurement plain = MeasureOdometry(path, o);
  const OdometryMeasurement spun = MeasureOdometry(path, o, 24, &turns);
  const double rot2 = o.rot_sigma_rad_per_sqrt_rad * o.rot_sigma_rad_per_sqrt_rad;
  EXPECT_NEAR(spun.covariance(2, 2) - plain.covariance(2, 2), rot2 * 2.0 * kPi, 1e-12);
  EXPECT_NEAR(spun.turn_rad, 2.0 * kPi, 1e-12);
  EXPECT_NEAR(plain.turn_rad, 0.0, 1e-12);
  // The first pose's turn came before the node's origin: not counted.
  const std::vector<double> before = {1.0, 0.0, 0.0};
  EXPECT_NEAR(MeasureOdometry(path, o, 24, &before).covariance(2, 2), plain.covariance(2, 2), 1e-15);
}

}  // namespace
}  // namespace cogmap::graph
