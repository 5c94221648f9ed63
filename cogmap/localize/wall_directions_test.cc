#include "cogmap/localize/wall_directions.h"

#include <gtest/gtest.h>

#include "cogmap/localize/test_rooms.h"

namespace cogmap::localize {
namespace {

constexpr double kTol = 1e-12;

TEST(FoldToQuarterTurn, KeepsAnglesInsideTheQuarter) {
  EXPECT_NEAR(FoldToQuarterTurn(0.0), 0.0, kTol);
  EXPECT_NEAR(FoldToQuarterTurn(DegToRad(10)), DegToRad(10), kTol);
  EXPECT_NEAR(FoldToQuarterTurn(DegToRad(44)), DegToRad(44), kTol);
  EXPECT_NEAR(FoldToQuarterTurn(DegToRad(-44)), DegToRad(-44), kTol);
}

TEST(FoldToQuarterTurn, FoldsWallAndItsNormalTogether) {
  for (double d : {10.0, 100.0, 190.0, 280.0, -80.0, -170.0, 370.0})
    EXPECT_NEAR(FoldToQuarterTurn(DegToRad(d)), DegToRad(10), 1e-9) << d;
}

TEST(FoldToQuarterTurn, SeamIsHalfOpenAtPlus45) {
  EXPECT_NEAR(FoldToQuarterTurn(DegToRad(45)), DegToRad(-45), 1e-12);
  EXPECT_NEAR(FoldToQuarterTurn(DegToRad(-45)), DegToRad(-45), 1e-12);
  EXPECT_NEAR(FoldToQuarterTurn(DegToRad(134)), DegToRad(44), 1e-9);
  EXPECT_NEAR(FoldToQuarterTurn(DegToRad(136)), DegToRad(-44), 1e-9);
  for (int i = -2000; i <= 2000; ++i) {
    const double f = FoldToQuarterTurn(i * 0.01);
    EXPECT_GE(f, -kPi / 4);
    EXPECT_LT(f, kPi / 4);
  }
}

TEST(WallDirections, OneEntryPerEdgeOfARotatedSquare) {
  const auto s = WallDirections({testing::Rectangle({1, 2}, 4, 3, DegToRad(30))});
  ASSERT_EQ(s.size(), 4u);
  for (const auto& w : s) EXPECT_NEAR(w.folded_rad, DegToRad(30), 1e-9);
  EXPECT_NEAR(s[0].length_m, 4.0, 1e-9);
  EXPECT_NEAR(s[1].length_m, 3.0, 1e-9);
}

TEST(WallDirections, SkipsRepeatedVertices) {
  const auto s = WallDirections({{{0, 0}, {0, 0}, {2, 0}}, {{5, 5}}});
  ASSERT_EQ(s.size(), 1u);
  EXPECT_NEAR(s[0].length_m, 2.0, kTol);
}

TEST(WallDirections, WorldRawUsesTheRawFramePose) {
  asr::Asr a;
  a.walls_local = {{{0, 0}, {3, 0}}};
  a.world_from_local_raw = {5, 5, DegToRad(12)};
  a.world_from_local_corrected = {0, 0, DegToRad(-30)};
  const auto s = WallDirectionsWorldRaw(a);
  ASSERT_EQ(s.size(), 1u);
  EXPECT_NEAR(s[0].folded_rad, DegToRad(12), 1e-9);
}

TEST(MotorDirections, ChordsFromEntryThroughExits) {
  asr::Asr a;
  a.entry_pivot_m = {0, 0};
  a.exits.push_back({{3, 1}, 0.9, 0, 1});
  a.exits.push_back({{3, 5}, 0.9, 0, 2});
  const auto m = MotorDirections(a);
  ASSERT_EQ(m.size(), 2u);
  EXPECT_NEAR(m[0], std::atan2(1.0, 3.0), 1e-12);
  EXPECT_NEAR(m[1], 0.0, 1e-12);  // straight up: 90 degrees folds to 0
}

TEST(MotorDirections, PathChordWhenNoExit) {
  asr::Asr a;
  a.path = {{0, 0, 0}, {1, 1, 0}, {2, 0.5, 0}};
  const auto m = MotorDirections(a);
  ASSERT_EQ(m.size(), 1u);
  EXPECT_NEAR(m[0], std::atan2(0.5, 2.0), 1e-12);
  EXPECT_TRUE(MotorDirections(asr::Asr{}).empty());
}

}  // namespace
}  // namespace cogmap::localize
