#include "cogmap/localize/heading_error.h"

#include <gtest/gtest.h>

#include "cogmap/core/angles.h"

namespace cogmap::localize {
namespace {

// An ASR whose raw path has a constant heading error of 'raw_deg' and whose
// correction rotates by 'correction_deg'.
asr::Asr WithError(int id, double raw_deg, double correction_deg) {
  asr::Asr a;
  a.id = id;
  a.world_from_local_raw = {0, 0, 0};
  a.world_from_local_corrected = {0, 0, DegToRad(correction_deg)};
  for (int i = 0; i < 5; ++i) {
    const double truth = 0.3 * i;
    a.true_path.push_back({double(i), 0, truth});
    a.path.push_back({double(i), 0.1, truth + DegToRad(raw_deg)});
  }
  return a;
}

TEST(HeadingError, RemovesOneGlobalRotation) {
  const HeadingErrorStats st = ComputeHeadingErrors({WithError(0, 5, 0), WithError(1, 5, 0), WithError(2, 5, 0)});
  EXPECT_EQ(st.asrs, 3);
  EXPECT_NEAR(st.max_raw_deg, 0.0, 1e-9);
  EXPECT_NEAR(st.max_deg, 0.0, 1e-9);
  EXPECT_NEAR(RadToDeg(st.global_rotation_raw_rad), 5.0, 1e-9);
}

TEST(HeadingError, MedianAndMaxOfRawAndCorrected) {
  // Raw errors 0, 2, 4, 6 deg -> circular mean 3 removed -> 3, 1, 1, 3.
  // Corrections -0, -2, -4, -6: corrected errors all 0.
  const HeadingErrorStats st = ComputeHeadingErrors(
      {WithError(0, 0, 0), WithError(1, 2, -2), WithError(2, 4, -4), WithError(3, 6, -6)});
  EXPECT_NEAR(st.median_raw_deg, 2.0, 1e-9);
  EXPECT_NEAR(st.max_raw_deg, 3.0, 1e-9);
  EXPECT_NEAR(st.median_deg, 0.0, 1e-9);
  EXPECT_NEAR(st.max_deg, 0.0, 1e-9);
  ASSERT_EQ(st.per_asr.size(), 4u);
  EXPECT_NEAR(RadToDeg(st.per_asr[3].raw_rad), 3.0, 1e-6);
  EXPECT_EQ(st.per_asr[3].poses, 5);
}

// ASRs along a straight road, each 4 m of path with a 1 m stretch between
// them (a path sampled at laser records), the odometry's heading off by
// rate x the distance driven: the rate back, whatever heading they start at
// and across the half turn.
TEST(HeadingError, TheOdometrysDriftIsTheSlopeOverTheDistanceDriven) {
  const double rate = DegToRad(1.5);  // per metre
  for (const double start : {0.0, DegToRad(178.0)}) {
    std::vector<asr::Asr> asrs;
    double s = 0.0;
    for (int id = 0; id < 6; ++id) {
      asr::Asr a;
      a.id = id;
      for (int i = 0; i <= 8; ++i) {
        const double x = s + 0.5 * i;
        a.true_path.push_back({x, 0, 0.0});
        a.path.push_back({x, 0, NormalizeAngle(start + rate * x)});
      }
      s += 4.0 + 1.0;
      asrs.push_back(a);
    }
    // An ASR without truth still counts in the distance.
    asrs.insert(asrs.begin() + 3, asr::Asr{});
    asrs[3].id = 99;
    asrs[3].path = {{14.0, 0, 0}, {14.5, 0, 0}};
    for (size_t k = 4; k < asrs.size(); ++k)
      for (auto* path : {&asrs[k].path, &asrs[k].true_path}) {
        for (auto& p : *path) p.x += 1.5;  // the stretch of ASR 99 and the way to it
      }
    for (size_t k = 4; k < asrs.size(); ++k)
      for (auto& p : asrs[k].path) p.theta = NormalizeAngle(start + rate * p.x);
    const HeadingErrorStats st = ComputeHeadingErrors(asrs);
    EXPECT_EQ(st.drift_asrs, 6);
    EXPECT_NEAR(st.odometry_drift_rad_per_m, rate, 1e-9) << start;
  }
  // Fewer than three ASRs with truth: not known.
  EXPECT_EQ(ComputeHeadingErrors({WithError(0, 0, 0), WithError(1, 2, 0)}).drift_asrs, 0);
}

TEST(HeadingError, WrapsAcrossPi) {
  asr::Asr a = WithError(0, 0, 0);
  for (auto& p : a.true_path) p.theta = DegToRad(179.5);
  for (auto& p : a.path) p.theta = DegToRad(-179.5);
  const HeadingErrorStats st = ComputeHeadingErrors({a, WithError(1, 0, 0)});
  EXPECT_NEAR(st.max_raw_deg, 0.5, 1e-6);
}

TEST(HeadingError, PairsPathsOfDifferentLengthByFraction) {
  asr::Asr a;
  for (int i = 0; i < 3; ++i) a.path.push_back({double(i), 0, DegToRad(10.0 * i + 1.0)});
  for (int i = 0; i < 5; ++i) a.true_path.push_back({0.5 * i, 0, DegToRad(5.0 * i)});
  asr::Asr b = a;
  for (auto& p : b.path) p.theta -= DegToRad(2.0);
  const HeadingErrorStats st = ComputeHeadingErrors({a, b});
  ASSERT_EQ(st.per_asr.size(), 2u);
  EXPECT_EQ(st.per_asr[0].poses, 3);
  EXPECT_NEAR(RadToDeg(st.global_rotation_raw_rad), 0.0, 1e-9);  // errors +1 and -1
  EXPECT_NEAR(st.max_raw_deg, 1.0, 1e-9);
}

TEST(HeadingError, SparseTruthPairsByDistanceNotByIndex) {
  // Odometry every 0.1 m along x with heading = x (rad); truth at x = 0, 0.2,
  // 0.3 and 2.0 only, with the same headings: no error, although index
  // fractions would pair truth 1 (at 0.2 m) with odometry at 0.67 m.
  asr::Asr a;
  for (int i = 0; i <= 20; ++i) a.path.push_back({0.1 * i, 0, 0.1 * i});
  for (double x : {0.0, 0.2, 0.3, 2.0}) a.true_path.push_back({x, 0, x});
  asr::Asr b = a;
  const HeadingErrorStats st = ComputeHeadingErrors({a, b});
  EXPECT_NEAR(st.max_raw_deg, 0.0, 1e-9);
  EXPECT_NEAR(RadToDeg(st.global_rotation_raw_rad), 0.0, 1e-9);
}

// A CARMEN log's first ASR: odometry poses before the first laser record
// (no truth) and then a turn on the spot, truth at every pose after those.
// Paired by distance driven, the spinning poses paired with truth taken
// while the robot faced elsewhere (the first ASRs of the five CARMEN logs
// read 2-7 degrees of error); paired from the end, none.
TEST(HeadingError, LeadingPosesWithoutTruthAreLeftUnpaired) {
  asr::Asr a;
  a.path = {{0.0, 0.0, 0.0}, {0.02, 0.0, 0.0}};  // before the first truth
  for (int i = 0; i < 8; ++i) a.path.push_back({0.03, 0.0, DegToRad(20.0 * i)});  // a turn on the spot
  for (int i = 1; i <= 10; ++i) a.path.push_back({0.03 + 0.1 * i, 0.0, DegToRad(140.0)});
  for (size_t k = 2; k < a.path.size(); ++k) a.true_path.push_back(a.path[k]);
  asr::Asr b = a;
  const HeadingErrorStats st = ComputeHeadingErrors({a, b});
  ASSERT_EQ(st.per_asr.size(), 2u);
  EXPECT_NEAR(st.max_raw_deg, 0.0, 1e-9);
  EXPECT_NEAR(RadToDeg(st.global_rotation_raw_rad), 0.0, 1e-9);
}

TEST(HeadingError, NoTruthGivesNoKeys) {
  asr::Asr a;
  a.path = {{0, 0, 0}};
  const HeadingErrorStats st = ComputeHeadingErrors({a});
  EXPECT_EQ(st.asrs, 0);
  EXPECT_TRUE(HeadingErrorEvalKeys(st).empty());
}

TEST(HeadingError, EvalKeys) {
  const auto keys = HeadingErrorEvalKeys(ComputeHeadingErrors({WithError(0, 0, 0), WithError(1, 2, 0)}));
  ASSERT_EQ(keys.size(), 4u);
  EXPECT_EQ(keys[0].first, "heading_error_deg_median");
  EXPECT_EQ(keys[1].first, "heading_error_deg_max");
  EXPECT_EQ(keys[2].first, "heading_error_deg_median_raw");
  EXPECT_EQ(keys[3].first, "heading_error_deg_max_raw");
  EXPECT_NEAR(keys[3].second, 1.0, 1e-6);
}

}  // namespace
}  // namespace cogmap::localize
