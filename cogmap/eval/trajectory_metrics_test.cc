#include "cogmap/eval/trajectory_metrics.h"

#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <random>

#include "cogmap/asr/store.h"
#include "cogmap/core/test_temp.h"

namespace cogmap::eval {
namespace {

// A straight run along x: n poses 'step_m' apart, heading 0.
std::vector<Pose2> StraightLine(int n, double step_m) {
  std::vector<Pose2> p;
  for (int i = 0; i < n; ++i) p.push_back({i * step_m, 0.0, 0.0});
  return p;
}

// A wandering run with a fixed seed: heading changes, steps of 0.1 m.
std::vector<Pose2> Wander(int n, unsigned seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> turn(0.0, 0.08);
  std::vector<Pose2> p{{0.0, 0.0, 0.0}};
  for (int i = 1; i < n; ++i) {
    const Pose2 step{0.1, 0.0, turn(rng)};
    p.push_back(p.back() * step);
  }
  return p;
}

std::vector<Pose2> Transformed(const Pose2& t, const std::vector<Pose2>& poses) {
  std::vector<Pose2> out;
  for (const auto& p : poses) out.push_back(t * p);
  return out;
}

TEST(AlignPositions, RecoversARigidMotion) {
  const auto ref = Wander(200, 3);
  const Pose2 t{3.5, -2.0, 0.7};
  const Pose2 fit = AlignPositions(ref, Transformed(t, ref));
  EXPECT_NEAR(fit.x, t.x, 1e-9);
  EXPECT_NEAR(fit.y, t.y, 1e-9);
  EXPECT_NEAR(fit.theta, t.theta, 1e-12);
}

TEST(AlignPositions, EmptyIsIdentity) {
  const Pose2 fit = AlignPositions({}, {});
  EXPECT_EQ(fit.x, 0.0);
  EXPECT_EQ(fit.theta, 0.0);
}

TEST(AbsoluteTrajectoryError, IdenticalTrajectoriesGiveZero) {
  const auto ref = Wander(300, 1);
  const AteStats st = AbsoluteTrajectoryError(ref, ref);
  EXPECT_EQ(st.poses, 300);
  EXPECT_NEAR(st.rmse_m, 0.0, 1e-12);
  EXPECT_NEAR(st.max_m, 0.0, 1e-12);
}

TEST(AbsoluteTrajectoryError, RigidlyMovedTrajectoryGivesZeroAfterAlignment) {
  const auto ref = Wander(300, 2);
  const auto est = Transformed({-12.0, 40.0, 2.9}, ref);
  const AteStats st = AbsoluteTrajectoryError(est, ref);
  EXPECT_NEAR(st.rmse_m, 0.0, 1e-9);
  EXPECT_NEAR(st.max_m, 0.0, 1e-9);
  EXPECT_NEAR(st.reference_from_estimate.inverse().theta, 2.9, 1e-12);
}

TEST(AbsoluteTrajectoryError, ConstantOffsetOnOneHalf) {
  // A straight line of 2n poses along x; the estimate's second half is 2c
  // further along (a slipped wheel). All positions lie on one line, so the
  // summed cross product is 0: the fit does not rotate, it shifts by -c, and
  // every pose is exactly c off.
  const int n = 50;
  const double c = 0.3;
  const auto ref = StraightLine(2 * n, 0.1);
  auto est = ref;
  for (int i = n; i < 2 * n; ++i) est[i].x += 2 * c;
  const AteStats st = AbsoluteTrajectoryError(est, ref);
  EXPECT_EQ(st.reference_from_estimate.theta, 0.0);
  EXPECT_NEAR(st.reference_from_estimate.x, -c, 1e-12);
  EXPECT_NEAR(st.rmse_m, c, 1e-12);
  EXPECT_NEAR(st.mean_m, c, 1e-12);
  EXPECT_NEAR(st.median_m, c, 1e-12);
  EXPECT_NEAR(st.max_m, c, 1e-12);
}

TEST(AbsoluteTrajectoryError, OffsetAcrossTheLineIsPartlyRotatedAway) {
  // The second half 2c to the side: tilting the line does better than the
  // shift alone, so the RMSE is below c (and above 0).
  const auto ref = StraightLine(100, 0.1);
  auto est = ref;
  for (int i = 50; i < 100; ++i) est[i].y += 0.6;
  const AteStats st = AbsoluteTrajectoryError(est, ref);
  EXPECT_GT(st.rmse_m, 0.05);
  EXPECT_LT(st.rmse_m, 0.3);
  EXPECT_NE(st.reference_from_estimate.theta, 0.0);
}

TEST(AbsoluteTrajectoryError, OffsetHalvesOfAStandingRobotGiveExactlyHalfTheOffset) {
  // Positions without spread along any direction but the offset: n poses at
  // the origin and n at (0, 2c) vs all 2n at the origin. Best fit: shift by
  // -c; every error exactly c.
  const int n = 20;
  const double c = 0.25;
  std::vector<Pose2> ref(2 * n), est(2 * n);
  for (int i = n; i < 2 * n; ++i) est[i].y = 2 * c;
  const AteStats st = AbsoluteTrajectoryError(est, ref);
  EXPECT_NEAR(st.rmse_m, c, 1e-12);
  EXPECT_NEAR(st.mean_m, c, 1e-12);
  EXPECT_NEAR(st.median_m, c, 1e-12);
  EXPECT_NEAR(st.max_m, c, 1e-12);
}

TEST(AbsoluteTrajectoryError, ScaledTrajectoryIsNotExplainedAway) {
  // No scale in the fit: 10% longer steps leave an error.
  const auto ref = StraightLine(101, 0.1);
  auto est = ref;
  for (auto& p : est) p.x *= 1.1;
  // Centred: est = 1.1 * ref, error after the centroid shift 0.1 * |x - 5|.
  const AteStats st = AbsoluteTrajectoryError(est, ref);
  double sq = 0.0, mx = 0.0;
  for (const auto& p : ref) sq += std::pow(0.1 * (p.x - 5.0), 2), mx = std::max(mx, 0.1 * std::abs(p.x - 5.0));
  EXPECT_NEAR(st.rmse_m, std::sqrt(sq / 101), 1e-12);
  EXPECT_NEAR(st.max_m, mx, 1e-12);
}

TEST(RelativePoseError, IdenticalTrajectoriesGiveZero) {
  const auto ref = Wander(400, 4);
  const auto st = RelativePoseError(ref, ref, 5.0);
  ASSERT_TRUE(st);
  EXPECT_GT(st->pairs, 0);
  EXPECT_NEAR(st->trans_rmse_m, 0.0, 1e-12);
  EXPECT_NEAR(st->rot_rmse_deg, 0.0, 1e-12);
}

TEST(RelativePoseError, InvariantToARigidMotionOfTheEstimate) {
  const auto ref = Wander(400, 5);
  const auto st = RelativePoseError(Transformed({5.0, 1.0, -1.2}, ref), ref, 1.0);
  ASSERT_TRUE(st);
  EXPECT_NEAR(st->trans_rmse_m, 0.0, 1e-9);
  EXPECT_NEAR(st->rot_rmse_deg, 0.0, 1e-9);
}

TEST(RelativePoseError, HeadingDriftGivesDriftTimesDistance) {
  // Odometry that turns k deg per metre while the truth drives straight: every
  // pair d metres apart is k*d degrees off, whatever d.
  const double k_deg_per_m = 1.5, step = 0.1;
  const auto ref = StraightLine(301, step);  // 30 m
  std::vector<Pose2> est{{0.0, 0.0, 0.0}};
  for (size_t i = 1; i < ref.size(); ++i) est.push_back(est.back() * Pose2{step, 0.0, DegToRad(k_deg_per_m * step)});
  for (double d : {1.0, 5.0, 20.0}) {
    const auto st = RelativePoseError(est, ref, d);
    ASSERT_TRUE(st) << d;
    EXPECT_EQ(st->pairs, static_cast<int>(ref.size()) - static_cast<int>(std::lround(d / step))) << d;
    EXPECT_NEAR(st->rot_rmse_deg, k_deg_per_m * d, 1e-9) << d;
    EXPECT_NEAR(st->rot_mean_deg, k_deg_per_m * d, 1e-9) << d;
    // The drifting run ends on an arc of the same length d with the turn
    // k*d spread evenly over d/step steps (chord geometry): the end point of
    // est_i^-1 est_j vs (d, 0).
    const int steps = static_cast<int>(std::lround(d / step));
    Pose2 arc;
    for (int s = 0; s < steps; ++s) arc = arc * Pose2{step, 0.0, DegToRad(k_deg_per_m * step)};
    const double expected = (arc.translation() - Vec2(d, 0.0)).norm();
    EXPECT_NEAR(st->trans_rmse_m, expected, 1e-9) << d;
  }
}

TEST(RelativePoseError, ConstantOffsetOnOneHalfOnlyHurtsPairsAcrossTheStep) {
  // Straight line, 0.1 m steps; the second half 0.3 m to the side. A pair
  // (i, j) is off by exactly 0.3 m when it straddles the step, else 0.
  const int n = 100;
  const auto ref = StraightLine(n, 0.1);
  auto est = ref;
  for (int i = n / 2; i < n; ++i) est[i].y += 0.3;
  const auto st = RelativePoseError(est, ref, 1.0);  // j = i + 10
  ASSERT_TRUE(st);
  EXPECT_EQ(st->pairs, n - 10);
  // Straddling pairs: i in [40, 49]: 10 of 90.
  EXPECT_NEAR(st->trans_mean_m, 0.3 * 10 / 90, 1e-12);
  EXPECT_NEAR(st->trans_rmse_m, 0.3 * std::sqrt(10.0 / 90), 1e-12);
  EXPECT_NEAR(st->rot_rmse_deg, 0.0, 1e-12);
}

TEST(RelativePoseError, NoPairWhenTheRunIsShorter) {
  const auto ref = StraightLine(50, 0.1);  // 4.9 m
  EXPECT_FALSE(RelativePoseError(ref, ref, 5.0));
  EXPECT_TRUE(RelativePoseError(ref, ref, 1.0));
  EXPECT_FALSE(RelativePoseError({}, {}, 1.0));
}

TEST(RelativePoseError, PathLengthIsTheReferences) {
  // The estimate drives twice as far; pairs are picked by the reference's
  // travel (j = i + 10 for 1 m), so the translation error is 1 m each.
  const auto ref = StraightLine(41, 0.1);
  const auto est = StraightLine(41, 0.2);
  const auto st = RelativePoseError(est, ref, 1.0);
  ASSERT_TRUE(st);
  EXPECT_EQ(st->pairs, 31);
  EXPECT_NEAR(st->trans_rmse_m, 1.0, 1e-12);
}

// --- From ASRs: a store whose corrected poses equal the truth. ---

// ASR i: a 4 m stretch of a straight corridor along x, sampled every 0.1 m;
// the truth is the corridor; the raw odometry has turned by a growing angle
// (drift) about the ASR's entry; the correction puts it back exactly.
asr::Asr CorridorAsr(int id, double drift_rad_per_asr) {
  asr::Asr a;
  a.id = id;
  const Vec2 entry(4.0 * id, 0.0);
  const double drift = drift_rad_per_asr * id;
  // raw = R(drift about entry) * truth: world_from_local_raw is the local
  // frame in the raw world, world_from_local_corrected the same frame in the
  // truth's world.
  const Pose2 raw_from_true = Pose2{entry.x(), entry.y(), drift} * Pose2{-entry.x(), -entry.y(), 0.0};
  a.world_from_local_corrected = {entry.x(), entry.y(), 0.0};
  a.world_from_local_raw = raw_from_true * a.world_from_local_corrected;
  for (int k = 0; k < 40; ++k) {
    const Pose2 truth{entry.x() + 0.1 * k, 0.0, 0.0};
    a.true_path.push_back(truth);
    a.path.push_back(raw_from_true * truth);
  }
  return a;
}

void ExpectPerfectCorrection(const asr::AsrStore& store) {
  std::vector<asr::Asr> asrs;
  for (int id : store.Ids()) asrs.push_back(*store.Get(id));
  const AsrTrajectories t = PairAsrTrajectories(asrs);
  EXPECT_EQ(t.asrs, 6);
  ASSERT_EQ(t.reference.size(), 240u);
  const TrajectoryMetrics m = ComputeTrajectoryMetrics(t);
  EXPECT_NEAR(m.ate.rmse_m, 0.0, 1e-9);
  EXPECT_GT(m.ate_raw.rmse_m, 0.1);
  ASSERT_EQ(m.rpe.size(), 3u);
  for (size_t k = 0; k < 3; ++k) {
    ASSERT_TRUE(m.rpe[k]) << k;
    EXPECT_NEAR(m.rpe[k]->trans_rmse_m, 0.0, 1e-9);
    EXPECT_NEAR(m.rpe[k]->rot_rmse_deg, 0.0, 1e-9);
    ASSERT_TRUE(m.rpe_raw[k]) << k;
  }
  // Within an ASR the raw path is rigidly moved, so only pairs that cross an
  // ASR boundary see the drift step of 2 degrees.
  EXPECT_GT(m.rpe_raw[0]->rot_rmse_deg, 0.1);
  EXPECT_NEAR(m.rpe_raw[2]->rot_mean_deg, 10.0, 1e-6);  // 20 m spans exactly five steps of 2 degrees
}

TEST(PairAsrTrajectories, MemoryStoreWithPerfectCorrection) {
  asr::MemoryAsrStore store;
  for (int id = 0; id < 6; ++id) store.Put(CorridorAsr(id, DegToRad(2.0)));
  ExpectPerfectCorrection(store);
}

TEST(PairAsrTrajectories, SqliteStoreWithPerfectCorrection) {
  const std::string path = testing_util::TestTempPath("trajectory_metrics.sqlite");
  {
    auto store = asr::SqliteAsrStore::Open(path, asr::SqliteAsrStore::OpenMode::kReplace);
    // Stored out of order: the metrics follow the ids.
    for (int id : {3, 0, 5, 1, 4, 2}) store->Put(CorridorAsr(id, DegToRad(2.0)));
  }
  auto store = asr::SqliteAsrStore::Open(path, asr::SqliteAsrStore::OpenMode::kOpenExisting);
  ExpectPerfectCorrection(*store);
}

TEST(PairAsrTrajectories, LeadingPosesWithoutTruthArePairedFromTheEnd) {
  asr::Asr a = CorridorAsr(0, 0.0);
  // Two odometry poses before the first true pose (CARMEN's leading ODOM).
  a.path.insert(a.path.begin(), {Pose2{-0.2, 0.0, 0.0}, Pose2{-0.1, 0.0, 0.0}});
  asr::Asr no_truth = CorridorAsr(1, 0.0);
  no_truth.true_path.clear();
  const AsrTrajectories t = PairAsrTrajectories({a, no_truth});
  EXPECT_EQ(t.asrs, 1);
  EXPECT_EQ(t.unpaired_poses, 2);
  ASSERT_EQ(t.raw.size(), 40u);
  EXPECT_EQ(t.raw.front().x, 0.0);
  EXPECT_NEAR(ComputeTrajectoryMetrics(t).ate_raw.rmse_m, 0.0, 1e-12);
}

TEST(TrajectoryEvalKeys, NamesAndNulls) {
  AsrTrajectories t;
  t.reference = StraightLine(31, 0.1);  // 3 m: 1 m pairs only
  t.raw = t.reference;
  t.corrected = t.reference;
  std::map<std::string, std::optional<double>> keys;
  for (const auto& [k, v] : TrajectoryEvalKeys(ComputeTrajectoryMetrics(t))) keys[k] = v;
  for (const char* k : {"ate_rmse_m", "ate_rmse_m_raw", "rpe_1m_trans_m", "rpe_1m_rot_deg", "rpe_5m_trans_m",
                        "rpe_5m_rot_deg", "rpe_20m_trans_m", "rpe_20m_rot_deg", "rpe_1m_trans_m_raw",
                        "rpe_1m_rot_deg_raw", "rpe_5m_trans_m_raw", "rpe_5m_rot_deg_raw", "rpe_20m_trans_m_raw",
                        "rpe_20m_rot_deg_raw"})
    EXPECT_TRUE(keys.count(k)) << k;
  EXPECT_EQ(keys["ate_rmse_m"], 0.0);
  EXPECT_EQ(keys["rpe_1m_trans_m"], 0.0);
  EXPECT_FALSE(keys["rpe_5m_trans_m"]);
  EXPECT_FALSE(keys["rpe_20m_rot_deg_raw"]);
  EXPECT_EQ(keys["trajectory_poses"], 31.0);

  keys.clear();
  for (const auto& [k, v] : TrajectoryEvalKeys(ComputeTrajectoryMetrics({}))) keys[k] = v;
  EXPECT_FALSE(keys["ate_rmse_m"]);
  EXPECT_FALSE(keys["rpe_1m_trans_m_raw"]);
}

// --- Calibration of the placements (issue 10). ---

// An ASR whose true frame is 'true_frame' and whose raw frame is 'raw_frame'
// (odometry's error), with five path poses along its local x axis; the map
// placed it at 'map_from_truth' * true_frame moved by (ex, ey, eth) in the
// map's world frame. No truth when 'with_truth' is false.
asr::Asr PlacedAsr(int id, const Pose2& true_frame, const Pose2& raw_frame, const Pose2& map_from_truth, double ex,
                   double ey, double eth, bool with_truth = true) {
  asr::Asr a;
  a.id = id;
  a.world_from_local_raw = raw_frame;
  for (int k = 0; k < 5; ++k) {
    const Pose2 local{0.3 * k, 0.1 * k, 0.05 * k};
    a.path.push_back(raw_frame * local);
    if (with_truth) a.true_path.push_back(true_frame * local);
  }
  const Pose2 placed = map_from_truth * true_frame;
  a.world_from_local_corrected = {placed.x + ex, placed.y + ey, NormalizeAngle(placed.theta + eth)};
  return a;
}

Eigen::Matrix3d Cov(double var_x, double var_y, double sigma_theta_deg) {
  Eigen::Matrix3d c = Eigen::Matrix3d::Zero();
  c(0, 0) = var_x;
  c(1, 1) = var_y;
  c(2, 2) = std::pow(DegToRad(sigma_theta_deg), 2);
  c(0, 1) = c(1, 0) = 0.001;  // off-diagonal terms do not enter the bounds
  return c;
}

// Five ASRs in a map whose frame differs from the truth's by a rigid motion
// (the anchor, ASR 0, was placed at its raw pose), with known errors:
//   1: 0.5 m off, 3 sigma = 0.45 m       -> position out; 1 deg off, 3 sigma 3 deg -> in
//   2: 0.5 m off, 3 sigma = 0.6 m        -> in;          -2 deg off, 3 sigma 3 deg -> in
//   3: 0.1 m off, 3 sigma = 0.6 m        -> in;           5 deg off, 3 sigma 3 deg -> out
//   4: no truth, 5: zero covariance (not placed), 0: no covariance (the anchor) -> not checked
std::vector<asr::Asr> CalibrationAsrs(std::map<int, Eigen::Matrix3d>* covariances) {
  const Pose2 map_from_truth{2.0, -1.0, DegToRad(30.0)};
  std::vector<asr::Asr> asrs;
  const double d = DegToRad(1.0);
  asrs.push_back(PlacedAsr(0, {1.0, 1.0, 0.2}, {1.5, 0.8, 0.1}, map_from_truth, 0, 0, 0));
  asrs.push_back(PlacedAsr(1, {5.0, 1.0, 0.3}, {5.4, 1.9, 0.5}, map_from_truth, 0.3, 0.4, 1.0 * d));
  asrs.push_back(PlacedAsr(2, {9.0, 2.0, -0.4}, {9.8, 3.1, 0.1}, map_from_truth, -0.3, 0.4, -2.0 * d));
  asrs.push_back(PlacedAsr(3, {9.0, 7.0, 1.6}, {11.0, 8.0, 2.0}, map_from_truth, 0.0, -0.1, 5.0 * d));
  asrs.push_back(PlacedAsr(4, {5.0, 7.0, 3.0}, {6.0, 9.0, 3.1}, map_from_truth, 3.0, 3.0, 0.0, false));
  asrs.push_back(PlacedAsr(5, {1.0, 7.0, -3.0}, {2.0, 9.0, 3.1}, map_from_truth, 3.0, 3.0, 0.0));
  (*covariances)[1] = Cov(0.01, 0.0125, 1.0);
  (*covariances)[2] = Cov(0.02, 0.02, 1.0);
  (*covariances)[3] = Cov(0.02, 0.02, 1.0);
  (*covariances)[4] = Cov(0.02, 0.02, 1.0);
  (*covariances)[5] = Eigen::Matrix3d::Zero();
  return asrs;
}

void ExpectCalibrationCase(const PoseCalibration& c) {
  EXPECT_EQ(c.reference_asr, 0);
  ASSERT_EQ(c.checked(), 3);
  EXPECT_EQ(c.items[0].asr_id, 1);
  EXPECT_EQ(c.items[1].asr_id, 2);
  EXPECT_EQ(c.items[2].asr_id, 3);
  EXPECT_NEAR(c.items[0].position_error_m, 0.5, 1e-9);
  EXPECT_NEAR(c.items[1].position_error_m, 0.5, 1e-9);
  EXPECT_NEAR(c.items[2].position_error_m, 0.1, 1e-9);
  EXPECT_NEAR(RadToDeg(c.items[0].heading_error_rad), 1.0, 1e-9);
  EXPECT_NEAR(RadToDeg(c.items[1].heading_error_rad), -2.0, 1e-9);
  EXPECT_NEAR(RadToDeg(c.items[2].heading_error_rad), 5.0, 1e-9);
  EXPECT_NEAR(c.items[0].sigma_position_m, 0.15, 1e-12);
  EXPECT_NEAR(c.items[1].sigma_position_m, 0.2, 1e-12);
  EXPECT_FALSE(c.items[0].position_within);
  EXPECT_TRUE(c.items[0].heading_within);
  EXPECT_TRUE(c.items[1].within());
  EXPECT_TRUE(c.items[2].position_within);
  EXPECT_FALSE(c.items[2].heading_within);
  EXPECT_EQ(c.within(), 1);
  EXPECT_EQ(c.position_within(), 2);
  EXPECT_EQ(c.heading_within(), 2);
  std::map<std::string, std::optional<double>> keys;
  for (const auto& [k, v] : PoseCalibrationEvalKeys(c)) keys[k] = v;
  EXPECT_NEAR(keys["pose_calibration_3sigma"].value(), 1.0 / 3.0, 1e-12);
  EXPECT_NEAR(keys["pose_calibration_position_3sigma"].value(), 2.0 / 3.0, 1e-12);
  EXPECT_NEAR(keys["pose_calibration_heading_3sigma"].value(), 2.0 / 3.0, 1e-12);
  EXPECT_EQ(keys["pose_calibration_asrs"], 3.0);
}

TEST(PoseCalibration, KnownErrorsAndCovariances) {
  std::map<int, Eigen::Matrix3d> cov;
  const auto asrs = CalibrationAsrs(&cov);
  ExpectCalibrationCase(ComputePoseCalibration(asrs, cov));
}

TEST(PoseCalibration, CovariancesReadBackFromAStore) {
  std::map<int, Eigen::Matrix3d> cov;
  const auto asrs = CalibrationAsrs(&cov);
  const std::string path = testing_util::TestTempPath("calibration.sqlite");
  {
    auto store = asr::SqliteAsrStore::Open(path, asr::SqliteAsrStore::OpenMode::kReplace);
    std::vector<asr::Placement> placements;
    for (const auto& a : asrs) {
      store->Put(a);
      if (!cov.count(a.id)) continue;
      asr::Placement p;
      p.asr_id = a.id;
      p.room_id = a.id;
      p.covariance = cov[a.id];
      placements.push_back(p);
    }
    store->PutPlacements(asrs, placements, {});
  }
  auto store = asr::SqliteAsrStore::Open(path, asr::SqliteAsrStore::OpenMode::kOpenExisting);
  std::vector<asr::Asr> back;
  std::map<int, Eigen::Matrix3d> cov_back;
  for (int id : store->Ids()) {
    back.push_back(*store->Get(id));
    if (const auto p = store->GetPlacement(id)) cov_back[id] = p->covariance;
  }
  EXPECT_FALSE(cov_back.count(0));
  ExpectCalibrationCase(ComputePoseCalibration(back, cov_back));
}

TEST(PoseCalibration, NoTruthOrNoCovarianceChecksNothing) {
  std::map<int, Eigen::Matrix3d> cov;
  auto asrs = CalibrationAsrs(&cov);
  const PoseCalibration none = ComputePoseCalibration(asrs, {});
  EXPECT_EQ(none.checked(), 0);
  EXPECT_EQ(none.reference_asr, 0);
  std::map<std::string, std::optional<double>> keys;
  for (const auto& [k, v] : PoseCalibrationEvalKeys(none)) keys[k] = v;
  EXPECT_FALSE(keys["pose_calibration_3sigma"]);
  EXPECT_EQ(keys["pose_calibration_asrs"], 0.0);
  for (auto& a : asrs) a.true_path.clear();
  const PoseCalibration no_truth = ComputePoseCalibration(asrs, cov);
  EXPECT_EQ(no_truth.checked(), 0);
  EXPECT_EQ(no_truth.reference_asr, -1);
}

TEST(PoseCalibration, AnchorWithoutTruthMakesTheFirstWithTruthTheReference) {
  std::map<int, Eigen::Matrix3d> cov;
  auto asrs = CalibrationAsrs(&cov);
  asrs[0].true_path.clear();
  // ASR 1 is now the reference: its own error is removed and moves the others'.
  const PoseCalibration c = ComputePoseCalibration(asrs, cov);
  EXPECT_EQ(c.reference_asr, 1);
  ASSERT_EQ(c.checked(), 3);
  EXPECT_NEAR(c.items[0].position_error_m, 0.0, 1e-9);
  EXPECT_NEAR(c.items[0].heading_error_rad, 0.0, 1e-12);
  EXPECT_NEAR(RadToDeg(c.items[1].heading_error_rad), -3.0, 1e-9);
}

TEST(PoseCalibration, KSigmaNamesTheKeys) {
  std::map<int, Eigen::Matrix3d> cov;
  const auto asrs = CalibrationAsrs(&cov);
  const PoseCalibration c = ComputePoseCalibration(asrs, cov, 2.0);
  // 2 sigma: ASR 2's 0.5 m against 0.4 m is out too.
  EXPECT_EQ(c.within(), 0);
  std::map<std::string, std::optional<double>> keys;
  for (const auto& [k, v] : PoseCalibrationEvalKeys(c)) keys[k] = v;
  EXPECT_TRUE(keys.count("pose_calibration_2sigma"));
  EXPECT_EQ(keys["pose_calibration_2sigma"], 0.0);
}

}  // namespace
}  // namespace cogmap::eval
