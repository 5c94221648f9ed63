#include "cogmap/asr/boundary_detector.h"

#include <gtest/gtest.h>

#include <functional>
#include <vector>

namespace cogmap::asr {
namespace {

// A scripted drive: poses along a list, the two sides as functions of the pose.
struct Script {
  std::function<bool(const Pose2&)> left;
  std::function<bool(const Pose2&)> right;
  double half_width_m = 0.5;  // where the L / R obstacles sit across the robot
};

std::vector<BoundaryCut> RunScript(BoundaryDetector* d, const std::vector<Pose2>& poses, const Script& s) {
  std::vector<BoundaryCut> cuts;
  double t = 0.0;
  for (const Pose2& p : poses) {
    SideObservation l, r;
    l.observed = r.observed = true;
    l.close = s.left(p);
    r.close = s.right(p);
    const Vec2 n(-std::sin(p.theta), std::cos(p.theta));
    l.point_m = p.translation() + s.half_width_m * n;
    r.point_m = p.translation() - s.half_width_m * n;
    if (auto c = d->PushSides(t, p, l, r)) cuts.push_back(*c);
    t += 0.1;
  }
  return cuts;
}

// Poses along +x from x0 to x1 (inclusive) every 5 cm.
std::vector<Pose2> Line(double x0, double x1, double step = 0.05) {
  std::vector<Pose2> out;
  const int n = static_cast<int>(std::lround(std::abs(x1 - x0) / step));
  const double dir = x1 >= x0 ? 1.0 : -1.0;
  for (int i = 0; i <= n; ++i) out.push_back({x0 + dir * i * step, 0.0, dir > 0 ? 0.0 : kPi});
  return out;
}

bool Between(double x, double a, double b) { return x >= a - 1e-9 && x <= b + 1e-9; }

BoundaryDetector MakeDetector(const BoundaryOptions& o = {}) {
  return BoundaryDetector(sensors::BuiltinRobot("pioneer16"), o);
}

TEST(BoundaryOptions, DefaultsAreThePapers) {
  const BoundaryOptions o;
  EXPECT_EQ(o.mode, BoundaryMode::kDoorway);
  EXPECT_DOUBLE_EQ(o.close_m, 0.7);
  EXPECT_DOUBLE_EQ(o.corridor_m, 2.0);
  EXPECT_DOUBLE_EQ(o.asr_length_m, 4.5);
  EXPECT_DOUBLE_EQ(o.side_tolerance_rad, DegToRad(60.0));
  EXPECT_DOUBLE_EQ(o.release_confirm_m, 0.0);  // the access point ends at the first release
}

TEST(SideSensors, PioneerRingUsesTheSideAndDiagonalUnits) {
  const SideSensors s = FindSideSensors(sensors::BuiltinRobot("pioneer16"), BoundaryOptions{}.side_tolerance_rad);
  EXPECT_EQ(s.left, (std::vector<int>{0, 1, 2, 13, 14, 15}));
  EXPECT_EQ(s.right, (std::vector<int>{5, 6, 7, 8, 9, 10}));
}

TEST(SideSensors, LaserUsesBeamsNearNinetyDegrees) {
  sensors::LaserOptions lo;
  lo.beams = 181;
  const SideSensors s = FindSideSensors(sensors::MakeLaser(lo), BoundaryOptions{}.side_tolerance_rad);
  EXPECT_EQ(s.left.size(), 61u);   // 30..90 degrees, one beam per degree
  EXPECT_EQ(s.right.size(), 61u);  // -90..-30
  EXPECT_EQ(s.right.front(), 0);
  EXPECT_EQ(s.left.back(), 180);
}

TEST(BoundaryDetector, DoorwayCutsAtMidpointOfTheStretch) {
  auto d = MakeDetector();
  auto door = [](const Pose2& p) { return Between(p.x, 3.0, 3.4); };
  const auto cuts = RunScript(&d, Line(0.0, 6.0), {door, door});
  ASSERT_EQ(cuts.size(), 1u);
  EXPECT_EQ(cuts[0].kind, CutKind::kDoorway);
  // On at the 2nd close sweep (3.05), off at the 2nd open one (3.50).
  EXPECT_NEAR(cuts[0].center_m.x(), 0.5 * (3.05 + 3.50), 0.05 + 1e-9);
  EXPECT_NEAR(cuts[0].center_m.y(), 0.0, 1e-12);
  EXPECT_NEAR(cuts[0].width_m, 1.0, 1e-12);
  EXPECT_EQ(d.state(), BoundaryState::kInRoom);
  EXPECT_EQ(d.turn_backs(), 0);
}

TEST(BoundaryDetector, TurningBackInADoorwayCutsNothing) {
  auto d = MakeDetector();
  auto door = [](const Pose2& p) { return Between(p.x, 3.0, 3.4); };
  auto poses = Line(0.0, 3.3);
  const auto back = Line(3.3, 0.0);
  poses.insert(poses.end(), back.begin() + 1, back.end());
  const auto cuts = RunScript(&d, poses, {door, door});
  EXPECT_TRUE(cuts.empty());
  EXPECT_EQ(d.turn_backs(), 1);
  EXPECT_EQ(d.state(), BoundaryState::kInRoom);
}

TEST(BoundaryDetector, AWallAlongOneSideAfterTheDoorDoesNotHoldTheAccessPoint) {
  auto d = MakeDetector();
  auto left = [](const Pose2& p) { return Between(p.x, 3.0, 3.4); };
  auto right = [](const Pose2& p) { return Between(p.x, 3.0, 9.0); };  // hugging a wall
  const auto cuts = RunScript(&d, Line(0.0, 12.0), {left, right});
  ASSERT_EQ(cuts.size(), 1u);
  EXPECT_EQ(cuts[0].kind, CutKind::kDoorway);
  EXPECT_NEAR(cuts[0].center_m.x(), 0.5 * (3.05 + 3.50), 0.05 + 1e-9);
}

BoundaryOptions WithDoorRelease(double m) {
  BoundaryOptions o;
  o.release_confirm_m = m;
  return o;
}

// A 1.4 m corridor from x = 3 to 15 with a door on the right every 3 m (0.8 m
// open each): the thesis's rule ends the access point at every door; with a
// release confirmed over 1 m the doors are side openings and the corridor is
// cut at its mouth, every 4.5 m and where it ends.
TEST(BoundaryDetector, SideDoorsOfACorridorDoNotCutItWithDoorRelease) {
  auto left = [](const Pose2& p) { return Between(p.x, 3.0, 15.0); };
  auto right = [](const Pose2& p) {
    if (!Between(p.x, 3.0, 15.0)) return false;
    for (double door = 4.0; door < 15.0; door += 3.0)
      if (Between(p.x, door, door + 0.8)) return false;
    return true;
  };
  auto paper = MakeDetector();
  const auto paper_cuts = RunScript(&paper, Line(0.0, 20.0), {left, right});
  EXPECT_EQ(paper_cuts.size(), 6u);  // the doors end pieces of it

  auto d = MakeDetector(WithDoorRelease(1.0));
  const auto cuts = RunScript(&d, Line(0.0, 20.0), {left, right});
  ASSERT_EQ(cuts.size(), 4u);
  EXPECT_EQ(cuts[0].kind, CutKind::kCorridorEntry);
  EXPECT_NEAR(cuts[0].center_m.x(), 3.05, 1e-9);
  // 4.5 m from the mouth falls in the door at 7.0-7.8 (and the next in the
  // one at 10.0-10.8 + 0.2): each cut waits for both sides again.
  EXPECT_EQ(cuts[1].kind, CutKind::kCorridor);
  EXPECT_NEAR(cuts[1].center_m.x(), 7.90, 1e-9);
  EXPECT_EQ(cuts[2].kind, CutKind::kCorridor);
  EXPECT_NEAR(cuts[2].center_m.x(), 12.40, 1e-9);
  // The exit is where the release began (15.10), decided 1 m later.
  EXPECT_EQ(cuts[3].kind, CutKind::kCorridorExit);
  EXPECT_NEAR(cuts[3].center_m.x(), 15.10, 1e-9);
  EXPECT_NEAR(cuts[3].time_s, 15.10 / 0.05 * 0.1, 1e-9);
  EXPECT_EQ(d.state(), BoundaryState::kInRoom);
}

// Through a door, then along a wall on one side: the release is confirmed
// after 1 m and the cut is exactly the thesis rule's.
TEST(BoundaryDetector, DoorReleaseCutsADoorwayWhereTheThesisRuleDoes) {
  auto left = [](const Pose2& p) { return Between(p.x, 3.0, 3.4); };
  auto right = [](const Pose2& p) { return Between(p.x, 3.0, 9.0); };
  auto paper = MakeDetector();
  const auto expected = RunScript(&paper, Line(0.0, 12.0), {left, right});
  auto d = MakeDetector(WithDoorRelease(1.0));
  const auto cuts = RunScript(&d, Line(0.0, 12.0), {left, right});
  ASSERT_EQ(expected.size(), 1u);
  ASSERT_EQ(cuts.size(), 1u);
  EXPECT_EQ(cuts[0].kind, CutKind::kDoorway);
  EXPECT_DOUBLE_EQ(cuts[0].center_m.x(), expected[0].center_m.x());
  EXPECT_DOUBLE_EQ(cuts[0].time_s, expected[0].time_s);
  EXPECT_DOUBLE_EQ(cuts[0].width_m, expected[0].width_m);
  // Turning back still cuts nothing.
  auto back = MakeDetector(WithDoorRelease(1.0));
  auto door = [](const Pose2& p) { return Between(p.x, 3.0, 3.4); };
  auto poses = Line(0.0, 3.3);
  const auto ret = Line(3.3, 0.0);
  poses.insert(poses.end(), ret.begin() + 1, ret.end());
  EXPECT_TRUE(RunScript(&back, poses, {door, door}).empty());
  EXPECT_EQ(back.turn_backs(), 1);
}

TEST(BoundaryDetector, OneSideCloseIsNotAnAccessPoint) {
  auto d = MakeDetector();
  const auto cuts = RunScript(&d, Line(0.0, 10.0), {[](const Pose2&) { return true; },
                                               [](const Pose2&) { return false; }});
  EXPECT_TRUE(cuts.empty());
  EXPECT_EQ(d.state(), BoundaryState::kInRoom);
}

TEST(BoundaryDetector, ASingleNoisySweepIsDebounced) {
  auto d = MakeDetector();
  auto blip = [](const Pose2& p) { return std::abs(p.x - 2.0) < 0.01; };
  const auto cuts = RunScript(&d, Line(0.0, 5.0), {blip, blip});
  EXPECT_TRUE(cuts.empty());
  EXPECT_FALSE(d.left_on());
}

TEST(BoundaryDetector, SweepsWithoutSideReadingsKeepTheState) {
  auto d = MakeDetector();
  SideObservation close;
  close.observed = close.close = true;
  SideObservation none;  // not observed
  d.PushSides(0.0, {0, 0, 0}, close, close);
  d.PushSides(0.1, {0.05, 0, 0}, close, close);
  ASSERT_EQ(d.state(), BoundaryState::kAtAccessPoint);
  for (int i = 0; i < 10; ++i) d.PushSides(0.2 + i * 0.1, {0.1, 0, 0}, none, none);
  EXPECT_EQ(d.state(), BoundaryState::kAtAccessPoint);
}

TEST(BoundaryDetector, CorridorIsCutAtItsMouthThenEveryAsrLength) {
  auto d = MakeDetector();
  auto corridor = [](const Pose2& p) { return p.x >= 3.0; };
  const auto cuts = RunScript(&d, Line(0.0, 20.0), {corridor, corridor});
  ASSERT_GE(cuts.size(), 4u);
  EXPECT_EQ(cuts[0].kind, CutKind::kCorridorEntry);
  EXPECT_NEAR(cuts[0].center_m.x(), 3.05, 1e-9);  // the mouth (debounced by one sweep)
  for (size_t i = 1; i < cuts.size(); ++i) {
    EXPECT_EQ(cuts[i].kind, CutKind::kCorridor);
    EXPECT_NEAR(cuts[i].center_m.x() - cuts[i - 1].center_m.x(), 4.5, 0.05 + 1e-9);
    EXPECT_NEAR(cuts[i].width_m, 1.0, 1e-12);
  }
  EXPECT_EQ(cuts.size(), 4u);  // 3.05, 7.55, 12.05, 16.55
}

TEST(BoundaryDetector, LeavingACorridorCutsAtTheRelease) {
  auto d = MakeDetector();
  auto corridor = [](const Pose2& p) { return Between(p.x, 3.0, 7.0); };
  const auto cuts = RunScript(&d, Line(0.0, 12.0), {corridor, corridor});
  ASSERT_EQ(cuts.size(), 2u);
  EXPECT_EQ(cuts[0].kind, CutKind::kCorridorEntry);
  EXPECT_EQ(cuts[1].kind, CutKind::kCorridorExit);
  EXPECT_NEAR(cuts[1].center_m.x(), 7.10, 1e-9);  // off after the 2nd open sweep
}

TEST(BoundaryDetector, RobotStartingInACorridorKeepsItsFirstAsr) {
  auto d = MakeDetector();
  auto corridor = [](const Pose2&) { return true; };
  const auto cuts = RunScript(&d, Line(0.0, 10.0), {corridor, corridor});
  ASSERT_EQ(cuts.size(), 2u);  // no zero-length room at the start
  EXPECT_EQ(cuts[0].kind, CutKind::kCorridor);
  EXPECT_NEAR(cuts[0].center_m.x(), 4.5, 1e-9);
  EXPECT_NEAR(cuts[1].center_m.x(), 9.0, 1e-9);
}

TEST(BoundaryDetector, FixedLengthCutsEveryLengthOfTravelRoundCorners) {
  BoundaryOptions o;
  o.mode = BoundaryMode::kFixedLength;
  o.asr_length_m = 4.0;
  auto d = MakeDetector(o);
  std::vector<Pose2> poses = Line(0.0, 3.0);
  for (int i = 1; i <= 100; ++i) poses.push_back({3.0, i * 0.05, kPi / 2});  // up 5 m
  auto door = [](const Pose2&) { return true; };  // ignored in this mode
  const auto cuts = RunScript(&d, poses, {door, door});
  ASSERT_EQ(cuts.size(), 2u);
  EXPECT_EQ(cuts[0].kind, CutKind::kFixedLength);
  EXPECT_NEAR(cuts[0].center_m.x(), 3.0, 1e-9);
  EXPECT_NEAR(cuts[0].center_m.y(), 1.0, 1e-9);
  EXPECT_NEAR(cuts[1].center_m.y(), 5.0, 1e-9);
  EXPECT_DOUBLE_EQ(cuts[0].width_m, 0.0);
}

TEST(BoundaryDetector, ObservesSideSonarsOfARecord) {
  const auto robot = sensors::BuiltinRobot("pioneer16");
  auto d = MakeDetector();
  sensors::LogRecord rec;
  rec.odom = {1.0, 2.0, 0.0};
  rec.ranges = {{0, 0.4}, {15, 0.6}, {7, 2.0}, {3, 0.1}};
  const auto [l, r] = d.ObserveSides(rec, 0.0);
  EXPECT_TRUE(l.close);  // unit 0: 0.136 + 0.4 m to the left; unit 15 is 0.736 m away
  const Vec2 expect = sensors::ReadingEndPoint(rec.odom, robot.sensors[0], 0.4);
  EXPECT_NEAR((l.point_m - expect).norm(), 0.0, 1e-12);
  EXPECT_TRUE(r.observed);
  EXPECT_FALSE(r.close);
}

TEST(BoundaryDetector, DiagonalEchoIsRememberedUntilItIsBesideTheRobot) {
  // Unit 1 (50 degrees) sees a jamb ahead-left; 40 cm later, with no further
  // echo, the jamb is beside the robot and L is on.
  auto d = MakeDetector();
  sensors::LogRecord rec;
  rec.odom = {0.0, 0.0, 0.0};
  rec.ranges = {{1, 0.55}};
  const Vec2 jamb = sensors::ReadingEndPoint(rec.odom, sensors::BuiltinRobot("pioneer16").sensors[1], 0.55);
  EXPECT_FALSE(d.ObserveSides(rec, 0.0).first.close);  // still 0.47 m ahead
  rec.ranges.clear();
  rec.odom = {jamb.x(), 0.0, 0.0};
  const auto [l, r] = d.ObserveSides(rec, jamb.x());
  EXPECT_TRUE(l.close);
  EXPECT_NEAR((l.point_m - jamb).norm(), 0.0, 1e-12);
  EXPECT_FALSE(r.close);
  rec.odom = {jamb.x() + 0.5, 0.0, 0.0};  // passed it
  EXPECT_FALSE(d.ObserveSides(rec, jamb.x() + 0.5).first.close);
}

// A robot crossing a doorway off its middle: the side units see one jamb
// 'near_m' and the other 'far_m' across the robot (units 0 / 15 on the left,
// 7 / 8 on the right, each 0.136 m off the centre line) while x is in [2, 2.4].
// With 'far_wall' the far side is a wall along the way (seen all along).
int CutsThroughDoor(const BoundaryOptions& o, double near_m, double far_m, bool far_wall = false) {
  auto d = MakeDetector(o);
  int cuts = 0;
  for (int i = 0; i <= 100; ++i) {
    sensors::LogRecord rec;
    rec.time_s = i * 0.1;
    rec.odom = {i * 0.05, 0.0, 0.0};
    const bool jamb = rec.odom.x >= 2.0 && rec.odom.x <= 2.4;
    const double l = jamb ? near_m - 0.136 : 2.5, r = (jamb || far_wall) ? far_m - 0.136 : 2.5;
    rec.ranges = {{0, l}, {15, l}, {7, r}, {8, r}};
    if (d.Push(rec)) ++cuts;
  }
  return cuts;
}

TEST(BoundaryDetector, RecordsThroughADoorwayCutOnce) {
  // Two side sonars see jambs 0.36 m away while the robot crosses x in [2, 2.4].
  EXPECT_EQ(CutsThroughDoor(BoundaryOptions{}, 0.36 + 0.136, 0.36 + 0.136), 1);
}

BoundaryOptions WithGap(double m) {
  BoundaryOptions o;
  o.gap_m = m;
  return o;
}

TEST(BoundaryDetector, GapRuleFindsADoorCrossedOffItsMiddle) {
  // A 1.2 m door crossed 0.25 m off its middle: jambs 0.35 and 0.85 m across.
  EXPECT_EQ(CutsThroughDoor(BoundaryOptions{}, 0.35, 0.85), 0);  // the thesis: the far jamb is beyond close_m
  EXPECT_EQ(CutsThroughDoor(WithGap(1.4), 0.35, 0.85), 1);
  // Crossed in its middle, both rules agree.
  EXPECT_EQ(CutsThroughDoor(BoundaryOptions{}, 0.6, 0.6), 1);
  EXPECT_EQ(CutsThroughDoor(WithGap(1.4), 0.6, 0.6), 1);
}

TEST(BoundaryDetector, GapRuleWantsAJambNotAWallAlongTheWay) {
  // An obstacle 0.35 m to the left beside a wall 0.85 m to the right that
  // runs along the way (a 1.2 m corridor driven off its middle, a box
  // passed in a corridor): no door.
  EXPECT_EQ(CutsThroughDoor(WithGap(1.4), 0.35, 0.85, /*far_wall=*/true), 0);
  EXPECT_EQ(CutsThroughDoor(WithGap(1.4), 0.35, 0.85, /*far_wall=*/false), 1);
}

TEST(BoundaryDetector, GapRuleLeavesOpeningsWiderThanTheGapAlone) {
  // 0.3 m from a wall on the left, 1.3 m from one on the right: a 1.6 m
  // opening, wider than 2 close_m, is no access point under either rule.
  EXPECT_EQ(CutsThroughDoor(BoundaryOptions{}, 0.3, 1.3), 0);
  EXPECT_EQ(CutsThroughDoor(WithGap(1.4), 0.3, 1.3), 0);
  EXPECT_EQ(BoundaryOptions{}.gap_m, 0.0);  // off in the papers' defaults
}

TEST(BoundaryDetector, AWiderGapWantsBothSidesJambsWhenBothAreBeyondCloseM) {
  // A 2 m double door crossed in its middle: both jambs 1 m across, beyond
  // close_m. Under a 2.5 m gap both are jambs: a door.
  EXPECT_EQ(CutsThroughDoor(WithGap(1.4), 1.0, 1.0), 0);
  EXPECT_EQ(CutsThroughDoor(WithGap(2.5), 1.0, 1.0), 1);
  // The same widths beside a wall that runs along the way (a 2 m corridor,
  // its right wall): no door.
  EXPECT_EQ(CutsThroughDoor(WithGap(2.5), 1.0, 1.0, /*far_wall=*/true), 0);
}

}  // namespace
}  // namespace cogmap::asr

namespace cogmap::asr {
namespace {

// A wide hall: the sides never come on together, so only max_asr_m cuts it.
TEST(BoundaryDetector, MaxLengthCutsAWideSpace) {
  BoundaryOptions o;
  o.max_asr_m = 5.0;
  BoundaryDetector d(sensors::BuiltinRobot("pioneer16"), o);
  std::vector<BoundaryCut> cuts;
  const SideObservation none{true, false, Vec2(0, 0)};
  for (int i = 0; i <= 120; ++i) {  // 12 m in 0.1 m steps
    if (auto c = d.PushSides(i * 0.2, Pose2{i * 0.1, 0.0, 0.0}, none, none)) cuts.push_back(*c);
  }
  ASSERT_EQ(cuts.size(), 2u);
  EXPECT_EQ(cuts[0].kind, CutKind::kMaxLength);
  EXPECT_NEAR(cuts[0].pose.x, 5.0, 1e-9);
  EXPECT_NEAR(cuts[1].pose.x, 10.0, 1e-9);
}

TEST(BoundaryDetector, MaxLengthIsOffInThePapersDefaults) {
  EXPECT_EQ(BoundaryOptions{}.max_asr_m, 0.0);
}

}  // namespace
}  // namespace cogmap::asr
