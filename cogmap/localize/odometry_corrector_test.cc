#include "cogmap/localize/odometry_corrector.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>

#include "cogmap/localize/heading_error.h"
#include "cogmap/localize/test_rooms.h"

namespace cogmap::localize {
namespace {

using testing::NoisyRoom;
using testing::WallNoise;

TEST(DriftFilterOptions, Defaults) {
  const DriftFilterOptions o;
  EXPECT_EQ(o.rate_prior_sigma_rad_per_m, DegToRad(3.0));
  EXPECT_EQ(o.heading_prior_sigma_rad, DegToRad(10.0));
  EXPECT_EQ(o.heading_walk_rad_per_sqrt_m, DegToRad(0.6));
  EXPECT_EQ(o.warmup_min_band_rad, DegToRad(5.0));
  EXPECT_EQ(o.min_measurements_to_fit_noise, 15);
  EXPECT_EQ(o.measurement_sigma_scale, 2.0);
  EXPECT_EQ(o.measurement_sigma_floor_rad, DegToRad(0.5));
  EXPECT_EQ(o.gate_sigmas, 4.0);
  EXPECT_EQ(o.max_consecutive_rejects, 3);
  EXPECT_TRUE(o.precorrect);
  EXPECT_EQ(o.warmup_measurements, 4);
  EXPECT_FALSE(o.smear_inflation);
  EXPECT_FALSE(o.robust_smoothing);
}

TEST(OdometryCorrector, WithoutMeasurementsReturnsTheRawPoses) {
  OdometryCorrector c;
  const std::vector<Pose2> raw = {{1, 2, 0.3}, {1.5, 2.2, 0.5}, {1.9, 2.9, 1.4}, {1.0, 3.5, -2.9}};
  for (size_t i = 0; i < raw.size(); ++i) {
    const Pose2 p = c.Correct(raw[i], double(i));
    EXPECT_NEAR(p.x, raw[i].x, 1e-12);
    EXPECT_NEAR(p.y, raw[i].y, 1e-12);
    EXPECT_NEAR(AngleDiff(p.theta, raw[i].theta), 0.0, 1e-12);
  }
  EXPECT_EQ(c.applied_rad(), 0.0);
}

TEST(OdometryCorrector, RecoversAConstantRateFromExactMeasurements) {
  OdometryCorrector c;
  const double rate = DegToRad(1.0);
  for (int k = 0; k < 15; ++k) {
    const double s = 2.25 + 4.5 * k;
    c.Predict(s);
    ASSERT_TRUE(c.Update(0.1 + rate * s, DegToRad(0.5)));
  }
  EXPECT_NEAR(RadToDeg(c.rate_rad_per_m()), 1.0, 0.01);
  EXPECT_NEAR(RadToDeg(c.heading_rad()), RadToDeg(0.1 + rate * (2.25 + 4.5 * 14)), 0.05);
  EXPECT_LT(c.rate_sigma_rad_per_m(), DegToRad(0.1));
}

TEST(OdometryCorrector, RecoversTheRateFromNoisyMeasurements) {
  OdometryCorrector c;
  const double rate = DegToRad(-0.7);
  std::mt19937 rng(3);
  std::normal_distribution<double> noise(0.0, DegToRad(1.0));
  for (int k = 0; k < 40; ++k) {
    const double s = 4.5 * k;
    c.Predict(s);
    c.Update(rate * s + noise(rng), DegToRad(1.0));
  }
  EXPECT_NEAR(RadToDeg(c.rate_rad_per_m()), -0.7, 0.02);
}

TEST(OdometryCorrector, PreCorrectionUndoesAKnownDrift) {
  OdometryCorrector c;
  const double rate = DegToRad(1.0);
  c.Predict(0.0);
  c.Update(0.0, DegToRad(0.01));
  c.Predict(10.0);
  c.Update(rate * 10.0, DegToRad(0.01));
  ASSERT_NEAR(c.rate_rad_per_m(), rate, DegToRad(0.005));
  // Raw odometry of a robot driving straight along x, its heading drifting.
  Pose2 raw;
  Pose2 last;
  const double step = 0.05;
  for (int i = 0; i <= 400; ++i) {
    last = c.Correct(raw, 0.1 * i);
    raw = raw * Pose2{step, 0.0, rate * step};
  }
  // 20 m driven: raw heading is 20 degrees off, corrected stays near 0.
  EXPECT_NEAR(RadToDeg(AngleDiff(raw.theta, 0.0)), 20.05, 0.01);
  EXPECT_NEAR(RadToDeg(last.theta), 0.0, 0.1);
  EXPECT_NEAR(last.x, 20.0, 0.02);
  EXPECT_NEAR(last.y, 0.0, 0.05);
  EXPECT_NEAR(c.distance_m(), 20.0, 1e-9);
  EXPECT_NEAR(c.applied_rad(), raw.theta - rate * step - last.theta, 1e-9);
}

// The synthetic heading errors below lie on a straight line, so the model is
// made as stiff as that line (the default walk allows for real wander).
DriftFilterOptions StiffModel() {
  DriftFilterOptions o;
  o.heading_walk_rad_per_sqrt_m = DegToRad(0.3);
  return o;
}

TEST(OdometryCorrector, SmoothingUsesLaterMeasurementsForEarlierSteps) {
  OdometryCorrector c(StiffModel());
  const double rate = DegToRad(1.0), offset = DegToRad(0.2);
  std::mt19937 rng(11);
  std::normal_distribution<double> noise(0.0, DegToRad(1.0));
  std::vector<double> filtered;
  for (int k = 0; k < 20; ++k) {
    const double s = 4.5 * k;
    c.Predict(s);
    c.Update(offset + rate * s + noise(rng), DegToRad(1.0));
    filtered.push_back(c.heading_rad());
  }
  const std::vector<double> smoothed = c.SmoothedHeadings();
  ASSERT_EQ(smoothed.size(), 20u);
  EXPECT_NEAR(smoothed.back(), c.heading_rad(), 1e-12);
  double err_f = 0.0, err_s = 0.0;
  for (int k = 0; k < 5; ++k) {
    const double truth = offset + rate * 4.5 * k;
    err_f += std::abs(filtered[k] - truth);
    err_s += std::abs(smoothed[k] - truth);
  }
  EXPECT_LT(err_s, 0.5 * err_f);
  EXPECT_LT(RadToDeg(err_s / 5.0), 0.5);
}

TEST(OdometryCorrector, RobustSmoothingResistsAnOutlierThatPassedTheGate) {
  DriftFilterOptions o = StiffModel();
  o.gate_sigmas = 100.0;  // let the outlier in
  OdometryCorrector c(o);
  const double rate = DegToRad(1.0);
  std::mt19937 rng(4);
  std::normal_distribution<double> noise(0.0, DegToRad(0.3));
  for (int k = 0; k < 20; ++k) {
    const double s = 4.5 * k;
    c.Predict(s);
    const double outlier = k == 10 ? DegToRad(12.0) : 0.0;
    ASSERT_TRUE(c.Update(rate * s + noise(rng) + outlier, DegToRad(1.0)));
  }
  const double truth = rate * 45.0;
  const double plain = std::abs(c.SmoothedHeadings()[10] - truth);
  const double robust = std::abs(c.RobustSmoothedHeadings()[10] - truth);
  EXPECT_GT(RadToDeg(plain), 1.0);
  EXPECT_LT(robust, 0.5 * plain);
}

// Measurements of a heading error that is a line (plus white noise of 'noise'
// rad), or that also random-walks by 'walk' rad per sqrt(metre).
OdometryCorrector::NoiseFit FitOn(double walk, double noise, uint32_t seed) {
  OdometryCorrector c(StiffModel());
  std::mt19937 rng(seed);
  std::normal_distribution<double> n01(0.0, 1.0);
  double e = 0.0;
  for (int k = 0; k < 60; ++k) {
    const double s = 4.0 * k;
    if (k > 0) e += DegToRad(1.0) * 4.0 + walk * std::sqrt(4.0) * n01(rng);
    c.Predict(s);
    c.Update(e + noise * n01(rng), DegToRad(1.0));
  }
  const DriftFilterOptions o;
  return c.FitNoise(o.walk_candidates_rad_per_sqrt_m, o.sigma_scale_candidates);
}

TEST(OdometryCorrector, FitNoiseTellsAWanderingHeadingFromNoisyWalls) {
  // A straight line measured with 1 degree of noise: little walk, scale ~1.
  const auto line = FitOn(0.0, DegToRad(1.0), 3);
  EXPECT_LE(line.walk_rad_per_sqrt_m, DegToRad(0.3));
  EXPECT_GE(line.sigma_scale, 0.7);
  EXPECT_LE(line.sigma_scale, 1.4);
  // A heading that wanders by 1 degree per sqrt(m), measured almost exactly.
  const auto wander = FitOn(DegToRad(1.0), DegToRad(0.1), 3);
  EXPECT_GE(wander.walk_rad_per_sqrt_m, DegToRad(0.9));
  EXPECT_LE(wander.sigma_scale, 0.5);
  EXPECT_GT(wander.log_likelihood, -1e300);
}

TEST(OdometryCorrector, AverageWeightsByDistanceInTheTimeWindow) {
  OdometryCorrector c;
  c.Correct({0, 0, 0}, 0.0);
  c.Correct({1, 0, 0}, 1.0);
  c.Correct({1, 0, 0}, 2.0);  // standing still: no weight
  c.Correct({4, 0, 0}, 3.0);
  const auto w = c.Average(0.5, 3.5);
  ASSERT_TRUE(w.has_value());
  EXPECT_NEAR(w->distance_m, (1.0 * 1.0 + 3.0 * 4.0) / 4.0, 1e-12);
  EXPECT_FALSE(c.Average(5.0, 6.0).has_value());
  c.Forget(2.5);
  const auto late = c.Average(0.0, 10.0);
  ASSERT_TRUE(late.has_value());
  EXPECT_NEAR(late->distance_m, 4.0, 1e-12);
}

TEST(OdometryCorrector, GatesAGrossMeasurementThenRelocks) {
  OdometryCorrector c;
  for (int k = 0; k < 10; ++k) {
    c.Predict(4.5 * k);
    ASSERT_TRUE(c.Update(0.0, DegToRad(0.5)));
  }
  c.Predict(50.0);
  EXPECT_FALSE(c.Update(DegToRad(20.0), DegToRad(0.5)));
  EXPECT_EQ(c.rejects(), 1);
  EXPECT_NEAR(c.heading_rad(), 0.0, 1e-9);
  // The heading truly jumped: after max_consecutive_rejects the filter lets it in.
  c.Predict(54.5);
  EXPECT_FALSE(c.Update(DegToRad(20.0), DegToRad(0.5)));
  c.Predict(59.0);
  EXPECT_FALSE(c.Update(DegToRad(20.0), DegToRad(0.5)));
  c.Predict(63.5);
  EXPECT_TRUE(c.Update(DegToRad(20.0), DegToRad(0.5)));
  EXPECT_GT(RadToDeg(c.heading_rad()), 15.0);
}

TEST(OdometryCorrector, UnwrapsMeasurementsToTheNearestQuarterTurn) {
  OdometryCorrector c;
  c.SetHeading(DegToRad(44.0), DegToRad(0.5));
  c.Predict(1.0);
  // 46 degrees and -44 are the same wall direction: the one near 44 is used.
  ASSERT_TRUE(c.Update(DegToRad(-44.0), DegToRad(0.5)));
  // Between the prediction (44) and the unwrapped measurement (46), not near -44.
  EXPECT_GT(RadToDeg(c.heading_rad()), 44.0);
  EXPECT_LE(RadToDeg(c.heading_rad()), 46.0 + 1e-9);
}

TEST(RawFromPrecorrected, RecoversARigidTransform) {
  const Pose2 t{1.5, -2.0, 0.4};
  std::vector<Pose2> pre = {{0, 0, 0}, {1, 0, 0.1}, {2, 0.5, 0.3}, {2.5, 1.5, 1.0}};
  std::vector<Pose2> raw;
  for (const auto& p : pre) raw.push_back(t * p);
  const Pose2 r = RawFromPrecorrected(pre, raw);
  EXPECT_NEAR(r.x, t.x, 1e-12);
  EXPECT_NEAR(r.y, t.y, 1e-12);
  EXPECT_NEAR(r.theta, t.theta, 1e-12);
  const Pose2 id = RawFromPrecorrected({}, {});
  EXPECT_EQ(id.x, 0.0);
  EXPECT_EQ(id.theta, 0.0);
}

// A run through a corridor of square rooms (5 m apart along x, true heading 0)
// whose odometry heading drifts by 'rate' per metre. Each room's walls are
// mapped from the pre-corrected pose at the room's centre, as the mapper does
// with the odometry the corrector hands it. Returns the ASRs as the mapper
// stores them (raw fields re-expressed in the raw frame).
std::vector<asr::Asr> MapDriftingCorridor(DriftHeadingCorrector* c, int rooms, double rate,
                                          const WallNoise& noise = {}, int bad_room = -1,
                                          double bad_rad = 0.0, const std::vector<int>& round_rooms = {}) {
  std::mt19937 rng(noise.seed);
  const double room_m = 5.0, step_m = 0.05;
  const int steps = static_cast<int>(std::lround(room_m / step_m));
  Pose2 truth{-room_m / 2.0, 0.0, 0.0};
  Pose2 raw = truth;
  double t = 0.0;
  std::vector<asr::Asr> out;
  for (int k = 0; k < rooms; ++k) {
    asr::Asr a;
    a.id = k;
    std::vector<Pose2> raw_path;
    Pose2 pre_centre, true_centre;
    a.start_time_s = t;
    for (int i = 0; i < steps; ++i) {
      const Pose2 pre = c->CorrectOdometry(raw, t);
      if (i == 0) {
        a.entry_pivot_m = pre.translation();
        a.world_from_local_raw = {pre.x, pre.y, 0.0};
      }
      if (i == steps / 2) {
        pre_centre = pre;
        true_centre = truth;
      }
      a.path.push_back(pre);
      raw_path.push_back(raw);
      a.true_path.push_back(truth);
      a.end_time_s = t;
      truth = truth * Pose2{step_m, 0.0, 0.0};
      raw = raw * Pose2{step_m, 0.0, rate * step_m};
      t += 0.1;
    }
    auto walls_true = NoisyRoom({k * room_m, 0.0}, 4.0, 4.0, noise, rng);
    // A room whose walls give a wrong but confident direction (clutter on
    // shelves); bad_rad = NaN: a round room (a 36-gon) instead.
    const bool round = (k == bad_room && std::isnan(bad_rad)) ||
                       std::find(round_rooms.begin(), round_rooms.end(), k) != round_rooms.end();
    if (round) {
      Polyline round = testing::RegularPolygon(36, 2.0, 0.1);
      for (auto& v : round) v += Vec2(k * room_m, 0.0);
      walls_true = {round};
    } else if (k == bad_room) {
      walls_true = Transform(RotationAbout({k * room_m, 0.0}, bad_rad), walls_true);
    }
    a.walls_local = Transform(a.world_from_local_raw.inverse() * pre_centre * true_centre.inverse(), walls_true);
    a.world_from_local_corrected = a.world_from_local_raw;
    asr::Asr closed = c->Close(a);
    const Pose2 raw_from_pre = RawFromPrecorrected(closed.path, raw_path);
    closed.world_from_local_raw = raw_from_pre * closed.world_from_local_raw;
    closed.entry_pivot_m = raw_from_pre * closed.entry_pivot_m;
    closed.path = raw_path;
    out.push_back(std::move(closed));
  }
  return out;
}

TEST(DriftHeadingCorrector, RemovesAConstantDriftRate) {
  DriftHeadingCorrector c;
  const auto asrs = MapDriftingCorridor(&c, 14, DegToRad(1.0));
  EXPECT_NEAR(RadToDeg(c.odometry().rate_rad_per_m()), 1.0, 0.02);
  const HeadingErrorStats st = ComputeHeadingErrors(asrs);
  ASSERT_EQ(st.asrs, 14);
  EXPECT_GT(st.max_raw_deg, 30.0);
  EXPECT_LT(st.max_deg, 0.5);
  EXPECT_LT(st.median_deg, 0.1);
}

TEST(DriftHeadingCorrector, NoisyWallsStillConverge) {
  DriftHeadingCorrector c;
  WallNoise noise;
  noise.pieces = 4;
  noise.vertex_sigma_m = 0.05;
  noise.clutter_edges = 8;
  noise.seed = 5;
  const auto asrs = MapDriftingCorridor(&c, 20, DegToRad(-1.0), noise);
  EXPECT_NEAR(RadToDeg(c.odometry().rate_rad_per_m()), -1.0, 0.1);
  const HeadingErrorStats st = ComputeHeadingErrors(asrs);
  EXPECT_GT(st.median_raw_deg, 15.0);
  EXPECT_LT(st.median_deg, 0.5);
  EXPECT_LT(st.max_deg, 2.0);
}

TEST(DriftHeadingCorrector, SmoothingRevisesTheStoredCorrections) {
  DriftHeadingCorrector c;
  WallNoise noise;
  noise.pieces = 4;
  noise.vertex_sigma_m = 0.08;
  noise.clutter_edges = 10;
  noise.seed = 9;
  auto asrs = MapDriftingCorridor(&c, 20, DegToRad(1.0), noise);
  const HeadingErrorStats before = ComputeHeadingErrors(asrs);
  const auto revisions = c.Smooth();
  ASSERT_EQ(revisions.size(), asrs.size());
  for (size_t i = 0; i < asrs.size(); ++i) {
    ASSERT_EQ(revisions[i].asr_id, asrs[i].id);
    asrs[i].world_from_local_corrected = revisions[i].delta * asrs[i].world_from_local_corrected;
  }
  const HeadingErrorStats after = ComputeHeadingErrors(asrs);
  EXPECT_LT(after.max_deg, before.max_deg);
  EXPECT_LT(after.median_deg, 0.5);
  // A second Smooth changes nothing more.
  for (const auto& r : c.Smooth()) EXPECT_NEAR(r.delta.theta, 0.0, 1e-12);
}

TEST(DriftHeadingCorrector, SmoothingTiesTheMapToTheStartingFrame) {
  // The reference is the first room's walls, mapped 2.5 m into the run: 2.5
  // degrees of drift. Online, every ASR carries that offset; after smoothing
  // the map is in the frame the odometry started in (no global rotation left).
  DriftHeadingCorrector c;
  auto asrs = MapDriftingCorridor(&c, 12, DegToRad(1.0));
  const HeadingErrorStats before = ComputeHeadingErrors(asrs);
  EXPECT_NEAR(RadToDeg(before.global_rotation_rad), 2.5, 0.3);
  const auto revisions = c.Smooth();
  for (size_t i = 0; i < asrs.size(); ++i)
    asrs[i].world_from_local_corrected = revisions[i].delta * asrs[i].world_from_local_corrected;
  const HeadingErrorStats after = ComputeHeadingErrors(asrs);
  EXPECT_NEAR(RadToDeg(after.global_rotation_rad), 0.0, 0.1);
  EXPECT_LT(after.max_deg, 0.5);
}

TEST(DriftHeadingCorrector, WarmupUnwrapsAGapOfMoreThan45Degrees) {
  // 2 degrees per metre, rooms 1-4 round (declined): the heading drifts 50
  // degrees between the first two measurements, which the walls alone read as
  // -40. The warm-up line through the later rooms puts it back.
  DriftHeadingCorrector c;
  auto asrs = MapDriftingCorridor(&c, 12, DegToRad(2.0), {}, -1, 0.0, {1, 2, 3, 4});
  EXPECT_NEAR(RadToDeg(c.odometry().rate_rad_per_m()), 2.0, 0.05);
  const auto revisions = c.Smooth();
  for (size_t i = 0; i < asrs.size(); ++i)
    asrs[i].world_from_local_corrected = revisions[i].delta * asrs[i].world_from_local_corrected;
  const HeadingErrorStats st = ComputeHeadingErrors(asrs);
  EXPECT_GT(st.max_raw_deg, 40.0);
  EXPECT_LT(st.max_deg, 1.0);
}

TEST(DriftHeadingCorrector, WarmupDropsAConfidentGrossEstimate) {
  DriftHeadingCorrector c;
  auto asrs = MapDriftingCorridor(&c, 14, DegToRad(1.0), {}, 1, DegToRad(20.0));
  // The rate was fitted without the bad room (declined by the drift gate or
  // dropped by the Theil-Sen band).
  EXPECT_NEAR(RadToDeg(c.odometry().rate_rad_per_m()), 1.0, 0.02);
  const HeadingErrorStats streaming = ComputeHeadingErrors(asrs);
  for (const auto& r : c.Smooth())
    for (auto& a : asrs)
      if (a.id == r.asr_id) a.world_from_local_corrected = r.delta * a.world_from_local_corrected;
  const HeadingErrorStats smoothed = ComputeHeadingErrors(asrs);
  EXPECT_LT(smoothed.max_deg, 0.5);
  EXPECT_LT(smoothed.max_deg, streaming.max_deg);
}

TEST(DriftHeadingCorrector, RoundRoomIsDeclinedAndFollowsTheModel) {
  DriftHeadingCorrector c;
  const auto asrs = MapDriftingCorridor(&c, 14, DegToRad(1.0), {}, 9, std::nan(""));
  const HeadingErrorStats st = ComputeHeadingErrors(asrs);
  ASSERT_EQ(st.per_asr.size(), 14u);
  // The round room gives no direction the gates accept; its heading comes from
  // the drift model, as good as its neighbours'.
  EXPECT_LT(std::abs(RadToDeg(st.per_asr[9].corrected_rad)), 0.5);
  EXPECT_LT(st.max_deg, 0.5);
}

TEST(DriftHeadingCorrector, ShortRunSmoothsWhatItHas) {
  DriftHeadingCorrector c;
  auto asrs = MapDriftingCorridor(&c, 3, DegToRad(1.0));  // still warming up
  const HeadingErrorStats before = ComputeHeadingErrors(asrs);
  for (const auto& r : c.Smooth())
    for (auto& a : asrs)
      if (a.id == r.asr_id) a.world_from_local_corrected = r.delta * a.world_from_local_corrected;
  const HeadingErrorStats after = ComputeHeadingErrors(asrs);
  EXPECT_LT(before.max_deg, 0.5);
  EXPECT_LT(after.max_deg, 0.5);
}

TEST(DriftHeadingCorrector, NoDriftMeansNoCorrection) {
  DriftHeadingCorrector c;
  const auto asrs = MapDriftingCorridor(&c, 6, 0.0);
  for (const auto& a : asrs) EXPECT_NEAR(a.heading_correction_rad, 0.0, 1e-9);
  EXPECT_NEAR(c.odometry().rate_rad_per_m(), 0.0, 1e-12);
}

TEST(DriftHeadingCorrector, AsrWithoutWallsFollowsThePrediction) {
  DriftHeadingCorrector c;
  auto asrs = MapDriftingCorridor(&c, 8, DegToRad(1.0));
  // Now a stretch with no walls: the model carries the correction.
  asr::Asr blind;
  blind.id = 99;
  const double t0 = asrs.back().end_time_s + 0.1;
  Pose2 raw = asrs.back().path.back();
  for (int i = 0; i < 100; ++i) {
    const Pose2 pre = c.CorrectOdometry(raw, t0 + 0.1 * i);
    if (i == 0) blind.entry_pivot_m = pre.translation();
    blind.path.push_back(pre);
    raw = raw * Pose2{0.05, 0.0, DegToRad(1.0) * 0.05};
  }
  blind.start_time_s = t0;
  blind.end_time_s = t0 + 9.9;
  const double before = c.Correction().theta;
  const asr::Asr out = c.Close(blind);
  EXPECT_FALSE(c.LastEstimate().valid);
  // The pre-correction already removed the drift: the rotation barely changes.
  EXPECT_NEAR(RadToDeg(AngleDiff(out.heading_correction_rad, before)), 0.0, 0.2);
}

}  // namespace
}  // namespace cogmap::localize
