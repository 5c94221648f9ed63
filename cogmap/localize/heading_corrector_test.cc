#include "cogmap/localize/heading_corrector.h"

#include <gtest/gtest.h>

#include "cogmap/localize/heading_error.h"
#include "cogmap/localize/test_rooms.h"

namespace cogmap::localize {
namespace {

using testing::AsrWithWorldWalls;
using testing::DriftingCorridor;
using testing::Rectangle;

TEST(HeadingCorrectionOptions, DefaultModeIsTheRobustOne) {
  const HeadingCorrectionOptions o;
  EXPECT_EQ(o.mode, HeadingMode::kDefault);
  EXPECT_EQ(o.min_motor_chord_m, 0.2);
  EXPECT_TRUE(o.drift_gate);
  EXPECT_EQ(o.max_drift_base_rad, DegToRad(10.0));
  EXPECT_EQ(o.max_drift_rad_per_m, DegToRad(3.0));
}

TEST(RotationAbout, KeepsThePivotFixed) {
  const Pose2 r = RotationAbout({2, 3}, 0.7);
  const Vec2 p = r * Vec2(2, 3);
  EXPECT_NEAR(p.x(), 2, 1e-12);
  EXPECT_NEAR(p.y(), 3, 1e-12);
  EXPECT_NEAR(r.theta, 0.7, 1e-12);
}

TEST(HeadingCorrector, FirstAsrSetsTheReferenceAndIsNotRotated) {
  HeadingCorrector c;
  asr::Asr a = AsrWithWorldWalls({Rectangle({0, 0}, 4, 4, DegToRad(8))});
  a.world_from_local_raw = {1, 2, 0.3};
  a.walls_local = Transform(a.world_from_local_raw.inverse(), a.walls_local);
  const asr::Asr out = c.Close(a);
  EXPECT_EQ(out.heading_correction_rad, 0.0);
  EXPECT_NEAR(out.world_from_local_corrected.x, 1, 1e-12);
  EXPECT_NEAR(out.world_from_local_corrected.theta, 0.3, 1e-12);
  ASSERT_TRUE(c.Reference().has_value());
  EXPECT_NEAR(RadToDeg(*c.Reference()), 8.0, 1e-6);
  EXPECT_GE(out.heading_uncertainty_rad, 0.0);
}

TEST(HeadingCorrector, RotatesAboutTheEntryPivotAndCarriesTheRotation) {
  HeadingCorrector c;
  c.Close(AsrWithWorldWalls({Rectangle({0, 0}, 4, 4, 0.0)}));
  asr::Asr b = AsrWithWorldWalls({Rectangle({6, 0}, 4, 4, DegToRad(3))});
  b.entry_pivot_m = {3, 0};
  b.world_from_local_raw = {3, 0, DegToRad(3)};
  b.walls_local = Transform(b.world_from_local_raw.inverse(), b.walls_local);
  const asr::Asr bc = c.Close(b);
  EXPECT_NEAR(RadToDeg(bc.heading_correction_rad), -3.0, 1e-6);
  const Pose2 expected = RotateAbout(b.world_from_local_raw, b.entry_pivot_m, DegToRad(-3));
  EXPECT_NEAR(bc.world_from_local_corrected.x, expected.x, 1e-9);
  EXPECT_NEAR(bc.world_from_local_corrected.y, expected.y, 1e-9);
  EXPECT_NEAR(bc.world_from_local_corrected.theta, expected.theta, 1e-9);
  // A third ASR with no walls: the rotation carries, about pivot 2.
  asr::Asr d;
  d.world_from_local_raw = {9, 0.5, DegToRad(3)};
  const asr::Asr dc = c.Close(d);
  const Pose2 expected_d = RotateAbout(d.world_from_local_raw, b.entry_pivot_m, DegToRad(-3));
  EXPECT_NEAR(dc.world_from_local_corrected.x, expected_d.x, 1e-9);
  EXPECT_NEAR(dc.world_from_local_corrected.y, expected_d.y, 1e-9);
  EXPECT_NEAR(dc.heading_correction_rad, DegToRad(-3), 1e-9);
  EXPECT_EQ(dc.heading_uncertainty_rad, -1.0);
  EXPECT_FALSE(c.LastEstimate().valid);
}

TEST(HeadingCorrector, ComposesRotationsAboutSuccessivePivots) {
  HeadingCorrector c;
  c.Close(AsrWithWorldWalls({Rectangle({0, 0}, 4, 4, 0.0)}));
  asr::Asr b = AsrWithWorldWalls({Rectangle({6, 0}, 4, 4, DegToRad(2))});
  b.entry_pivot_m = {3, 0};
  c.Close(b);
  asr::Asr d = AsrWithWorldWalls({Rectangle({12, 1}, 4, 4, DegToRad(5))});
  d.entry_pivot_m = {9, 1};
  const asr::Asr dc = c.Close(d);
  // Rotation 1: -2 deg about (3, 0); rotation 2 about pivot (9, 1) carried by
  // rotation 1, by -(5 - 2) deg.
  const Pose2 r1 = RotationAbout({3, 0}, DegToRad(-2));
  const Pose2 r2 = RotationAbout(r1 * Vec2(9, 1), DegToRad(-3));
  const Pose2 expected = r2 * r1;
  EXPECT_NEAR(dc.world_from_local_corrected.x, expected.x, 1e-9);
  EXPECT_NEAR(dc.world_from_local_corrected.y, expected.y, 1e-9);
  EXPECT_NEAR(RadToDeg(dc.heading_correction_rad), -5.0, 1e-6);
}

TEST(HeadingCorrector, DriftWrapsModulo90Degrees) {
  HeadingCorrector c;
  c.Close(AsrWithWorldWalls({Rectangle({0, 0}, 4, 4, DegToRad(40))}));
  // 40 + 8 = 48 folds to -42: the drift is +8, not -82.
  const asr::Asr b = c.Close(AsrWithWorldWalls({Rectangle({0, 0}, 4, 4, DegToRad(48))}));
  EXPECT_NEAR(RadToDeg(b.heading_correction_rad), -8.0, 1e-6);
}

TEST(HeadingCorrector, DriftGateDeclinesAGrossError) {
  HeadingCorrector c;
  c.Close(AsrWithWorldWalls({Rectangle({0, 0}, 4, 4, 0.0)}));
  // 30 degrees of drift with no distance travelled: more than 10 + 3/m x 0.
  const asr::Asr b = c.Close(AsrWithWorldWalls({Rectangle({0, 0}, 4, 4, DegToRad(30))}));
  EXPECT_EQ(b.heading_correction_rad, 0.0);
  EXPECT_EQ(c.LastEstimate().decline, Decline::kDriftOutlier);
  // After 8 m of path the same drift is plausible (10 + 24 degrees).
  asr::Asr d = AsrWithWorldWalls({Rectangle({0, 0}, 4, 4, DegToRad(30))});
  d.path = {{0, 0, 0}, {8, 0, 0}};
  EXPECT_NEAR(RadToDeg(c.Close(d).heading_correction_rad), -30.0, 1e-6);
  // Paper mode has no gate.
  HeadingCorrectionOptions o;
  o.mode = HeadingMode::kPaper;
  HeadingCorrector p(o);
  p.Close(AsrWithWorldWalls({Rectangle({0, 0}, 4, 4, 0.0)}));
  EXPECT_NEAR(RadToDeg(p.Close(AsrWithWorldWalls({Rectangle({0, 0}, 4, 4, DegToRad(30))})).heading_correction_rad),
              -30.0, 1e-6);
}

TEST(HeadingCorrector, DeclinedAsrIsNotRotated) {
  HeadingCorrector c;
  c.Close(AsrWithWorldWalls({Rectangle({0, 0}, 4, 4, 0.0)}));
  const asr::Asr round = c.Close(AsrWithWorldWalls({testing::RegularPolygon(36, 3, DegToRad(5))}));
  EXPECT_EQ(round.heading_correction_rad, 0.0);
  EXPECT_FALSE(c.LastEstimate().accepted);
  EXPECT_GT(round.heading_uncertainty_rad, 0.0);
}

TEST(HeadingCorrector, StreamingEqualsBatch) {
  const auto raw = DriftingCorridor(6, DegToRad(1.0), 0.1);
  const auto batch = CorrectHeadings(raw);
  HeadingCorrector c;
  for (size_t k = 0; k < raw.size(); ++k) {
    const asr::Asr s = c.Close(raw[k]);
    EXPECT_EQ(s.world_from_local_corrected.x, batch[k].world_from_local_corrected.x);
    EXPECT_EQ(s.world_from_local_corrected.y, batch[k].world_from_local_corrected.y);
    EXPECT_EQ(s.heading_correction_rad, batch[k].heading_correction_rad);
  }
}

TEST(HeadingCorrector, RestoreContinuesAStoredRun) {
  const auto raw = DriftingCorridor(8, DegToRad(1.0), 0.1);
  const auto whole = CorrectHeadings(raw);
  const std::vector<asr::Asr> first(whole.begin(), whole.begin() + 5);
  HeadingCorrector resumed;
  const std::optional<double> ref = ReferenceDirection(first);
  ASSERT_TRUE(ref.has_value());
  resumed.Restore(CorrectionOf(first.back()), ref);
  for (size_t k = 5; k < raw.size(); ++k) {
    const asr::Asr a = resumed.Close(raw[k]);
    EXPECT_NEAR(a.heading_correction_rad, whole[k].heading_correction_rad, 1e-9) << k;
    EXPECT_NEAR(a.world_from_local_corrected.x, whole[k].world_from_local_corrected.x, 1e-9) << k;
  }
}

class CorridorTest : public ::testing::TestWithParam<HeadingMode> {};

TEST_P(CorridorTest, RecoversOneDegreeDriftPerAsr) {
  const auto raw = DriftingCorridor(12, DegToRad(1.0));
  HeadingCorrectionOptions o;
  o.mode = GetParam();
  const auto corrected = CorrectHeadings(raw, o);
  const HeadingErrorStats st = ComputeHeadingErrors(corrected);
  ASSERT_EQ(st.asrs, 12);
  EXPECT_LT(st.median_deg, 0.5);
  EXPECT_LT(st.max_deg, 0.5);
  EXPECT_GT(st.max_raw_deg, 5.0);
  // Each ASR's correction undoes the drift at its centre: k + 0.5 degrees,
  // less the first ASR's 0.5 that sets the reference.
  for (size_t k = 0; k < corrected.size(); ++k)
    EXPECT_NEAR(RadToDeg(corrected[k].heading_correction_rad), -static_cast<double>(k), 0.05) << k;
}

TEST_P(CorridorTest, CorrectedWallsLandNearTheTruth) {
  const auto raw = DriftingCorridor(12, DegToRad(1.0));
  HeadingCorrectionOptions o;
  o.mode = GetParam();
  const auto corrected = CorrectHeadings(raw, o);
  // The map is tied to the first room as mapped (its drift of 0.5 degrees at
  // its centre): compare the last room with the truth seen through that.
  const size_t mid = raw[0].path.size() / 2;
  const Pose2 raw_from_true = raw[0].path[mid] * raw[0].true_path[mid].inverse();
  const Polyline truth = Transform(raw_from_true, Rectangle({11 * 5.0, 0}, 4, 4, 0.0));
  const Polyline raw_walls = corrected.back().WallsWorldRaw()[0];
  const Polyline cor_walls = corrected.back().WallsWorldCorrected()[0];
  double raw_err = 0.0, cor_err = 0.0;
  for (size_t i = 0; i < truth.size(); ++i) {
    raw_err = std::max(raw_err, (raw_walls[i] - truth[i]).norm());
    cor_err = std::max(cor_err, (cor_walls[i] - truth[i]).norm());
  }
  EXPECT_GT(raw_err, 1.0);
  EXPECT_LT(cor_err, 0.05);
  RecordProperty("raw_err_m", std::to_string(raw_err));
  RecordProperty("cor_err_m", std::to_string(cor_err));
}

TEST(HeadingCorrector, DefaultModeIgnoresClutterThatBiasesPaperMode) {
  testing::WallNoise noise;
  noise.pieces = 4;             // each wall in four edges
  noise.vertex_sigma_m = 0.05;  // vertices jittered by 5 cm
  noise.clutter_edges = 8;      // 8 short edges at random angles per room
  noise.seed = 5;
  const auto raw = DriftingCorridor(12, DegToRad(1.0), 0.05, noise);
  HeadingCorrectionOptions o;
  const HeadingErrorStats robust = ComputeHeadingErrors(CorrectHeadings(raw, o));
  o.mode = HeadingMode::kPaper;
  const HeadingErrorStats paper = ComputeHeadingErrors(CorrectHeadings(raw, o));
  EXPECT_LT(robust.median_deg, 0.5);
  EXPECT_LT(robust.max_deg, 1.0);
  EXPECT_GT(robust.max_raw_deg, 5.0);
  EXPECT_LT(robust.median_deg, paper.median_deg);
  RecordProperty("paper_median_deg", std::to_string(paper.median_deg));
  RecordProperty("default_median_deg", std::to_string(robust.median_deg));
}

// A room whose walls give the EM 12.5 degrees, and a grid orientation as given
// (10 degrees: the grid agrees within the window and is taken).
asr::Asr RoomWithGrid(double grid_deg, double contrast, int cells = 700) {
  asr::Asr a = AsrWithWorldWalls({Rectangle({0, 0}, 5, 4, DegToRad(12.5))});
  a.grid_orientation = {true, DegToRad(grid_deg), contrast, cells};
  return a;
}

TEST(GridRefinement, AgreeingGridGivesTheDirectionAndItsSigma) {
  const HeadingCorrector c;
  const DirectionEstimate e = c.Estimate(RoomWithGrid(10.0, 1.6));
  EXPECT_TRUE(e.accepted);
  EXPECT_TRUE(e.grid_refined);
  EXPECT_NEAR(RadToDeg(e.direction_rad), 10.0, 1e-9);
  EXPECT_NEAR(RadToDeg(e.em_direction_rad), 12.5, 1e-3);
  EXPECT_NEAR(RadToDeg(e.uncertainty_rad), 1.0, 1e-9);
  // Fewer cells: a larger sigma (1 degree x sqrt(600 / 150) = 2).
  EXPECT_NEAR(RadToDeg(c.Estimate(RoomWithGrid(10.0, 1.6, 150)).uncertainty_rad), 2.0, 1e-9);
}

TEST(GridRefinement, ClearGridThatContradictsTheEmDeclines) {
  const HeadingCorrector c;
  const DirectionEstimate e = c.Estimate(RoomWithGrid(-20.0, 1.6));
  EXPECT_FALSE(e.accepted);
  EXPECT_EQ(e.decline, Decline::kGridDisagrees);
}

TEST(GridRefinement, GridWithoutAClearOrientationLeavesTheEmAlone) {
  const HeadingCorrector c;
  const DirectionEstimate e = c.Estimate(RoomWithGrid(-20.0, 1.05));
  EXPECT_TRUE(e.accepted);
  EXPECT_FALSE(e.grid_refined);
  EXPECT_NEAR(RadToDeg(e.direction_rad), 12.5, 1e-3);
}

TEST(GridRefinement, OffOrPaperModeIsTheEmAlone) {
  HeadingCorrectionOptions o;
  o.grid_refine = false;
  EXPECT_NEAR(RadToDeg(HeadingCorrector(o).Estimate(RoomWithGrid(10.0, 1.6)).direction_rad), 12.5, 1e-3);
  o = {};
  o.mode = HeadingMode::kPaper;
  EXPECT_FALSE(HeadingCorrector(o).Estimate(RoomWithGrid(10.0, 1.6)).grid_refined);
}

TEST(GridRefinement, RoundRoomStaysDeclinedWhateverTheGridSays) {
  asr::Asr a = AsrWithWorldWalls({testing::RegularPolygon(36, 2.0, 0.1)});
  a.grid_orientation = {true, 0.0, 1.6, 700};
  const DirectionEstimate e = HeadingCorrector().Estimate(a);
  EXPECT_FALSE(e.accepted);
  EXPECT_EQ(e.decline, Decline::kNotManhattan);
}

TEST(GridRefinement, UncertainEmConfirmedByTheGridIsAccepted) {
  // Two walls 16 degrees apart: the EM is too uncertain on its own.
  asr::Asr a =
      AsrWithWorldWalls({testing::Edge({0, 0}, DegToRad(0.0), 1.0), testing::Edge({0, 2}, DegToRad(16.0), 1.0)});
  HeadingCorrectionOptions o;
  o.grid_refine = false;
  const DirectionEstimate em = HeadingCorrector(o).Estimate(a);
  ASSERT_EQ(em.decline, Decline::kTooUncertain) << DeclineName(em.decline);
  a.grid_orientation = {true, DegToRad(8.0), 1.6, 700};
  const DirectionEstimate e = HeadingCorrector().Estimate(a);
  EXPECT_TRUE(e.accepted);
  EXPECT_TRUE(e.grid_refined);
  EXPECT_NEAR(RadToDeg(e.direction_rad), 8.0, 1e-9);
}

INSTANTIATE_TEST_SUITE_P(Modes, CorridorTest, ::testing::Values(HeadingMode::kPaper, HeadingMode::kDefault));

}  // namespace
}  // namespace cogmap::localize
