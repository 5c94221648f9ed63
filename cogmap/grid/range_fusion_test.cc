#include "cogmap/grid/range_fusion.h"

#include "cogmap/grid/cone_row.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <random>
#include <vector>

#include "cogmap/core/angles.h"
#include "cogmap/core/bresenham.h"
#include "cogmap/core/error.h"

namespace cogmap::grid {
namespace {

// An 80 x 80 grid of 0.1 m cells with its lower-left corner at (-4, -4): the
// robot at (0.05, 0.05) sits in cell (40, 40); a reading of 1 m straight ahead
// ends in cell (50, 40); the 3 m window boundary is cell (70, 40).
GridBounds Bounded() {
  GridBounds b;
  b.fixed = MapLimits(0.1, Vec2(-4, -4), 80, 80);
  return b;
}

sensors::RangeSensor Ahead() {
  sensors::RangeSensor s;  // at the robot centre, heading along the robot's x
  s.max_range_m = 5.0;
  s.min_range_m = 0.15;
  return s;
}

const Pose2 kRobot{0.05, 0.05, 0.0};

HimmFusion Mhimm(const GridBounds& b = Bounded()) { return HimmFusion(true, MhimmOptions{}, b); }
HimmFusion Himm(const GridBounds& b = Bounded()) {
  MhimmOptions o;
  static_cast<HimmOptions&>(o) = HimmOptions{};
  return HimmFusion(false, o, b);
}

TEST(FusionDefaults, MatchThePapers) {
  const HimmOptions h;
  EXPECT_EQ(h.window_m, 3.0);
  EXPECT_EQ(h.hit_increment, 3.0f);
  EXPECT_EQ(h.neighbour_increment, 1.5f);
  EXPECT_EQ(h.beam_decrement, 1.0f);
  EXPECT_EQ(h.min_value, 0.0f);
  EXPECT_EQ(h.max_value, 15.0f);
  EXPECT_EQ(h.occupied_threshold, 7.0f);
  const MhimmOptions m;
  EXPECT_EQ(m.min_value, -3.0f);
  EXPECT_EQ(m.max_value, 15.0f);
  EXPECT_EQ(m.robot_path, -100.0f);
  EXPECT_EQ(m.window_m, 3.0);
  EXPECT_EQ(m.hit_increment, 3.0f);
  EXPECT_EQ(m.neighbour_increment, 1.5f);
  const ConeOptions c;
  EXPECT_EQ(c.window_m, 3.0);
  EXPECT_EQ(c.max_occupied, 0.98);
  EXPECT_EQ(GridBounds{}.cell_m, 0.1);
}

TEST(Mhimm, HitAddsThreeToEndCell) {
  auto g = Mhimm();
  g.Insert(kRobot, Ahead(), 1.0);
  EXPECT_EQ(g.values().at(50, 40), 3.0f);
}

TEST(Mhimm, HitAddsOneAndHalfToEightNeighbours) {
  auto g = Mhimm();
  g.Insert(kRobot, Ahead(), 1.0);
  // (49, 40) is also the last beam cell: -1 then +1.5.
  EXPECT_EQ(g.values().at(49, 40), 0.5f);
  for (const auto& c : {CellIndex(49, 39), CellIndex(49, 41), CellIndex(50, 39), CellIndex(50, 41),
                        CellIndex(51, 39), CellIndex(51, 40), CellIndex(51, 41)})
    EXPECT_EQ(g.values().at(c), 1.5f) << c.transpose();
  EXPECT_EQ(g.values().at(52, 40), 0.0f);
  EXPECT_EQ(g.values().at(50, 42), 0.0f);
}

TEST(Mhimm, BeamLosesOneWithBothEndsExcluded) {
  auto g = Mhimm();
  g.Insert(kRobot, Ahead(), 1.0);
  EXPECT_EQ(g.values().at(40, 40), 0.0f);  // r0 excluded
  for (int x = 41; x <= 48; ++x) EXPECT_EQ(g.values().at(x, 40), -1.0f) << x;
  EXPECT_EQ(g.values().at(50, 40), 3.0f);  // t excluded from the beam
  EXPECT_EQ(g.values().at(45, 41), 0.0f);
}

TEST(Mhimm, BeamStartsAtRobotCellAndEndPointUsesSensorPose) {
  auto g = Mhimm();
  sensors::RangeSensor s = Ahead();
  s.robot_from_sensor = Pose2{0.5, 0.0, kPi / 2};  // 0.5 m ahead, looking left
  g.Insert(kRobot, s, 1.0);                         // ends at (0.55, 1.05): cell (45, 50)
  EXPECT_EQ(g.values().at(45, 50), 3.0f);
  EXPECT_EQ(g.values().at(40, 40), 0.0f);
  int beam = 0;
  WalkBresenham(40, 40, 45, 50, [&](int x, int y) {
    const bool end = (x == 40 && y == 40) || (x == 45 && y == 50);
    const bool neighbour = std::abs(x - 45) <= 1 && std::abs(y - 50) <= 1;
    if (!end) {
      EXPECT_EQ(g.values().at(x, y), neighbour ? 0.5f : -1.0f) << x << "," << y;
      ++beam;
    }
    return true;
  });
  EXPECT_EQ(beam, 9);
}

TEST(Mhimm, ManyHitsClampAtFifteen) {
  auto g = Mhimm();
  for (int i = 0; i < 10; ++i) g.Insert(kRobot, Ahead(), 1.0);
  EXPECT_EQ(g.values().at(50, 40), 15.0f);
  EXPECT_EQ(g.values().at(50, 41), 15.0f);  // 10 x 1.5
}

// Each echo is tagged with the distance the robot had driven when it came;
// a wall point reads the mean over the hits near it, each weighted by the
// evidence it added (the mapper bends the walls by the drift there).
TEST(Mhimm, HitsRememberTheDistanceTheyWereHeardFrom) {
  auto g = Mhimm();
  g.Insert(kRobot, Ahead(), 1.0);
  EXPECT_FALSE(g.HitDistance(Vec2(1.05, 0.05), 0.05).has_value());  // not asked for
  g.SetDistance(1.0);
  g.Insert(kRobot, Ahead(), 1.0);
  g.SetDistance(4.0);
  g.Insert(kRobot, Ahead(), 1.0);
  g.Insert(kRobot, Ahead(), 1.0);
  g.Insert(Pose2{0.05, 0.05, kPi / 2}, Ahead(), 1.0);  // a hit at (0.05, 1.05)
  ASSERT_TRUE(g.HitDistance(Vec2(1.05, 0.05), 0.05).has_value());
  EXPECT_DOUBLE_EQ(*g.HitDistance(Vec2(1.05, 0.05), 0.05), 3.0);
  EXPECT_DOUBLE_EQ(*g.HitDistance(Vec2(0.05, 1.05), 0.05), 4.0);
  EXPECT_FALSE(g.HitDistance(Vec2(0.55, 0.55), 0.2).has_value());  // no hit there
}

TEST(Mhimm, ManyMissesClampAtMinusThree) {
  auto g = Mhimm();
  for (int i = 0; i < 10; ++i) g.Insert(kRobot, Ahead(), 1.0);
  EXPECT_EQ(g.values().at(45, 40), -3.0f);
}

// The sonar cone (MhimmOptions::cone_hits). An echo whose axis cell is known
// empty goes on its arc, at the cell nearest the axis that is not: a 30-degree
// sonar at (0.05, 0.05) looking along +x, its axis row (y in [0, 0.1)) cleared
// by a narrow beam; its echo at 1 m lands 5 degrees to the left (arc cells one
// cell apart: n = ceil(15 deg x 1 m / 0.1 m) = 3), at (0.046 + 1, 0.137).
TEST(Mhimm, ConeHitGoesOnTheArcWhereTheAxisIsKnownEmpty) {
  MhimmOptions o;
  o.cone_hits = true;
  HimmFusion f(true, o, Bounded());
  sensors::RangeSensor ray = Ahead();
  ray.beam_width_rad = DegToRad(0.5);  // a ray: the cone is narrower than a cell
  for (int i = 0; i < 3; ++i) f.Insert(kRobot, ray, 5.0);  // no echo: the row is cleared to the window
  ASSERT_LT(f.Values().at(50, 40), 0.0f);
  sensors::RangeSensor sonar = Ahead();
  sonar.beam_width_rad = DegToRad(30.0);
  f.Insert(kRobot, sonar, 1.0);
  const auto v = f.Values();
  const double a = DegToRad(5.0);
  const int cx = static_cast<int>(std::floor((0.05 + std::cos(a) + 4.0) / 0.1));
  const int cy = static_cast<int>(std::floor((0.05 + std::sin(a) + 4.0) / 0.1));
  EXPECT_EQ(cy, 41);
  EXPECT_FLOAT_EQ(v.at(cx, cy), 3.0f);    // the hit
  EXPECT_FLOAT_EQ(v.at(50, 40), -1.5f);   // the axis cell: -3, and +1.5 as the hit's neighbour
  // The cone nearer than the echo lost evidence off the axis too: the cell
  // 0.5 m ahead and 0.1 m left is 11 degrees off the axis (weight 0.25).
  EXPECT_LT(v.at(45, 40 + 1), 0.0f);
  // Without cone_hits the same readings put the echo on the axis.
  HimmFusion axis(true, MhimmOptions{}, Bounded());
  for (int i = 0; i < 3; ++i) axis.Insert(kRobot, ray, 5.0);
  axis.Insert(kRobot, sonar, 1.0);
  EXPECT_FLOAT_EQ(axis.Values().at(50, 40), 0.0f);  // -3 + 3
}

// A laser's beam is a ray: cone_hits changes nothing for it.
TEST(Mhimm, ConeHitsLeaveARayAlone) {
  MhimmOptions o;
  o.cone_hits = true;
  HimmFusion with(true, o, Bounded()), without(true, MhimmOptions{}, Bounded());
  sensors::RangeSensor laser = Ahead();
  laser.beam_width_rad = DegToRad(1.0);
  for (double r : {0.7, 1.0, 1.33, 2.5, 4.0})
    for (double th : {0.0, 0.4, -1.1}) {
      with.Insert(Pose2{0.05, 0.05, th}, laser, r);
      without.Insert(Pose2{0.05, 0.05, th}, laser, r);
    }
  EXPECT_EQ(with.Values().cells(), without.Values().cells());
}

TEST(Himm, ManyMissesClampAtZero) {
  auto g = Himm();
  for (int i = 0; i < 10; ++i) g.Insert(kRobot, Ahead(), 1.0);
  EXPECT_EQ(g.values().at(45, 40), 0.0f);
  EXPECT_EQ(g.values().at(50, 40), 15.0f);
  EXPECT_EQ(g.values().at(49, 40), 6.0f);  // beam -1 then +1.5: 1.5 + 9 x 0.5
}

TEST(Himm, SingleHitValues) {
  auto g = Himm();
  g.Insert(kRobot, Ahead(), 1.0);
  EXPECT_EQ(g.values().at(50, 40), 3.0f);
  EXPECT_EQ(g.values().at(49, 40), 1.5f);  // max(0 - 1, 0) + 1.5
  EXPECT_EQ(g.values().at(51, 40), 1.5f);
  EXPECT_EQ(g.values().at(45, 40), 0.0f);
}

TEST(Himm, IgnoresNoEchoAndReadingsBeyondWindow) {
  auto g = Himm();
  g.Insert(kRobot, Ahead(), 5.0);
  g.Insert(kRobot, Ahead(), 4.0);
  for (float v : g.values().cells()) EXPECT_EQ(v, 0.0f);
  EXPECT_EQ(g.stats().misses, 2);
}

TEST(Himm, HasNoRobotPath) {
  auto g = Himm();
  g.MarkRobot(kRobot);
  EXPECT_EQ(g.values().at(40, 40), 0.0f);
}

TEST(Mhimm, RobotCellBecomesPath) {
  auto g = Mhimm();
  g.MarkRobot(kRobot);
  EXPECT_EQ(g.values().at(40, 40), -100.0f);
  EXPECT_EQ(g.Classify(40, 40), CellClass::kRobotPath);
}

TEST(Mhimm, PathCellNeverChangedByBeams) {
  auto g = Mhimm();
  g.MarkRobot(kRobot);
  const Pose2 behind{-0.95, 0.05, 0.0};  // cell (30, 40)
  for (int i = 0; i < 5; ++i) g.Insert(behind, Ahead(), 2.0);  // beam through (40, 40)
  EXPECT_EQ(g.values().at(40, 40), -100.0f);
  EXPECT_EQ(g.values().at(39, 40), -3.0f);
}

TEST(Mhimm, PathCellNeverChangedByHitsOrNeighbours) {
  auto g = Mhimm();
  g.MarkRobot(kRobot);
  const Pose2 behind{-0.95, 0.05, 0.0};
  g.Insert(behind, Ahead(), 1.0);  // hit on (40, 40)
  g.Insert(behind, Ahead(), 1.1);  // hit on (41, 40): (40, 40) is a neighbour
  EXPECT_EQ(g.values().at(40, 40), -100.0f);
  EXPECT_EQ(g.values().at(41, 40), 3.0f + 1.5f);
}

TEST(Mhimm, NoEchoClearsUpToWindowWithoutHit) {
  auto g = Mhimm();
  g.Insert(kRobot, Ahead(), 5.0);  // max range: no echo
  EXPECT_EQ(g.values().at(40, 40), 0.0f);
  for (int x = 41; x <= 70; ++x) EXPECT_EQ(g.values().at(x, 40), -1.0f) << x;
  EXPECT_EQ(g.values().at(71, 40), 0.0f);
  float max = 0;
  for (float v : g.values().cells()) max = std::max(max, v);
  EXPECT_EQ(max, 0.0f);
  EXPECT_EQ(g.stats().misses, 1);
  EXPECT_EQ(g.stats().hits, 0);
}

TEST(Mhimm, ReadingBeyondWindowClearsUpToWindow) {
  auto g = Mhimm();
  g.Insert(kRobot, Ahead(), 4.0);
  EXPECT_EQ(g.values().at(70, 40), -1.0f);
  EXPECT_EQ(g.values().at(71, 40), 0.0f);
  EXPECT_EQ(g.values().at(80 - 1, 40), 0.0f);
}

TEST(Mhimm, ReadingBelowMinRangeIgnored) {
  auto g = Mhimm();
  g.Insert(kRobot, Ahead(), 0.1);
  g.Insert(kRobot, Ahead(), std::nan(""));
  for (float v : g.values().cells()) EXPECT_EQ(v, 0.0f);
  EXPECT_EQ(g.stats().ignored, 2);
}

TEST(Mhimm, ClassifiesByEpsilon) {
  auto g = Mhimm();
  g.MarkRobot(kRobot);
  for (int i = 0; i < 3; ++i) g.Insert(kRobot, Ahead(), 1.0);
  EXPECT_EQ(g.values().at(50, 40), 9.0f);
  EXPECT_EQ(g.Classify(50, 40), CellClass::kOccupied);   // 9 > 7
  EXPECT_EQ(g.Classify(50, 41), CellClass::kUnknown);    // 4.5 <= 7
  EXPECT_EQ(g.Classify(45, 40), CellClass::kEmpty);      // -3
  EXPECT_EQ(g.Classify(40, 40), CellClass::kRobotPath);
  EXPECT_EQ(g.Classify(10, 10), CellClass::kUnknown);
  const auto classes = g.Classes();
  EXPECT_EQ(classes.at(50, 40), CellClass::kOccupied);
}

TEST(Mhimm, BoundedGridIgnoresCellsOutside) {
  GridBounds b;
  b.fixed = MapLimits(0.1, Vec2(-1, -1), 20, 20);  // robot cell (10, 10)
  auto g = Mhimm(b);
  g.Insert(kRobot, Ahead(), 1.5);  // ends outside
  EXPECT_EQ(g.limits().width(), 20);
  for (int x = 11; x < 20; ++x) EXPECT_EQ(g.values().at(x, 10), -1.0f);
}

TEST(Mhimm, GrowthKeepsWorldPositionOfCells) {
  GridBounds b;
  b.grow_chunk_cells = 16;
  auto g = Mhimm(b);
  g.MarkRobot(kRobot);
  g.Insert(kRobot, Ahead(), 1.0);
  const Vec2 hit(1.05, 0.05);
  ASSERT_EQ(g.values().at(g.limits().CellOf(hit)), 3.0f);
  const int width0 = g.limits().width();
  const Pose2 far{-20.0, 30.0, 1.0};
  g.MarkRobot(far);
  g.Insert(far, Ahead(), 2.0);
  EXPECT_GT(g.limits().width(), width0);
  EXPECT_EQ(g.values().at(g.limits().CellOf(hit)), 3.0f);
  EXPECT_EQ(g.values().at(g.limits().CellOf(kRobot.translation())), -100.0f);
  EXPECT_EQ(g.values().at(g.limits().CellOf(far.translation())), -100.0f);
  // The origin stays on the 0.1 m lattice through (0, 0).
  const double ox = g.limits().origin().x() / 0.1;
  EXPECT_NEAR(ox, std::round(ox), 1e-9);
}

TEST(Mhimm, GrowingPastMaxCellsIsInputError) {
  GridBounds b;
  b.cell_m = 0.001;
  b.max_cells = 1'000'000;
  auto g = Mhimm(b);
  g.MarkRobot(kRobot);
  EXPECT_THROW(g.MarkRobot(Pose2{50.0, 50.0, 0.0}), InputError);
}

// A count beyond every integer type is printed as the double it is (it was
// cast to long long: undefined, "-9223372036854775808 cells of 0.000000 m").
TEST(Mhimm, AGridTooLargeForAnyIntegerSaysHowLarge) {
  GridBounds b;
  b.cell_m = 1e-9;
  auto g = Mhimm(b);
  g.MarkRobot(kRobot);
  try {
    g.MarkRobot(Pose2{50.0, 50.0, 0.0});
    FAIL() << "no error";
  } catch (const InputError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("e+21 cells of 1e-09 m"), std::string::npos) << what;
  }
}

TEST(Mhimm, GrownGridMatchesBoundedGrid) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> range(0.2, 5.0), turn(-kPi, kPi);
  GridBounds grow;
  grow.grow_chunk_cells = 8;
  auto a = Mhimm(grow);
  GridBounds big;
  big.fixed = MapLimits(0.1, Vec2(-20, -20), 400, 400);
  auto b = Mhimm(big);
  Pose2 pose{0.05, 0.05, 0};
  for (int i = 0; i < 300; ++i) {
    pose = Pose2{pose.x + 0.05 * std::cos(pose.theta), pose.y + 0.05 * std::sin(pose.theta),
                 NormalizeAngle(pose.theta + 0.02)};
    sensors::RangeSensor s = Ahead();
    s.robot_from_sensor.theta = turn(rng);
    const double r = range(rng);
    a.MarkRobot(pose);
    b.MarkRobot(pose);
    a.Insert(pose, s, r);
    b.Insert(pose, s, r);
  }
  int compared = 0;
  for (int y = 0; y < a.limits().height(); ++y)
    for (int x = 0; x < a.limits().width(); ++x) {
      const CellIndex cb = b.limits().CellOf(a.limits().CenterOf(CellIndex(x, y)));
      ASSERT_EQ(a.values().at(x, y), b.values().get(cb.x(), cb.y())) << x << "," << y;
      ++compared;
    }
  EXPECT_GT(compared, 100);
}

TEST(Mhimm, SweepMatchesSingleInserts) {
  const auto robot = sensors::BuiltinRobot("pioneer16");
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> range(0.2, 5.0);
  GridBounds b;
  auto a = Mhimm(b), c = Mhimm(b);
  for (int k = 0; k < 20; ++k) {
    const Pose2 pose{0.013 * k, -0.021 * k, 0.1 * k};
    std::vector<sensors::RangeReading> sweep;
    for (int i = 0; i < 16; ++i) sweep.push_back({i, range(rng)});
    a.InsertSweep(pose, robot, sweep);
    c.MarkRobot(pose);
    for (const auto& r : sweep) c.Insert(pose, robot.sensors[r.sensor], r.range_m);
  }
  int differ = 0, nonzero = 0;
  for (int y = 0; y < a.limits().height(); ++y)
    for (int x = 0; x < a.limits().width(); ++x) {
      const CellIndex cc = c.limits().CellOf(a.limits().CenterOf(CellIndex(x, y)));
      differ += a.values().at(x, y) != c.values().get(cc.x(), cc.y());
      nonzero += a.values().at(x, y) != 0.0f;
    }
  EXPECT_EQ(differ, 0);
  EXPECT_GT(nonzero, 100);
  EXPECT_EQ(a.stats().readings, 320);
}

TEST(FusionRules, ParseNames) {
  EXPECT_EQ(ParseFusionRule("mhimm"), FusionRule::kMhimm);
  EXPECT_EQ(ParseFusionRule("ds"), FusionRule::kDempsterShafer);
  for (const auto& n : FusionRuleNames()) EXPECT_EQ(FusionRuleName(ParseFusionRule(n)), n);
  EXPECT_THROW(ParseFusionRule("magic"), InputError);
}

TEST(FusionRules, FactoryMakesEachRule) {
  for (const auto& n : FusionRuleNames()) {
    auto f = MakeFusion(ParseFusionRule(n));
    EXPECT_EQ(FusionRuleName(f->rule()), n);
    f->InsertSweep(kRobot, sensors::BuiltinRobot("pioneer16"),
                   std::vector<sensors::RangeReading>{{0, 1.0}, {4, 2.0}, {99, 1.0}});
    EXPECT_EQ(f->stats().readings, 3);
    EXPECT_EQ(f->stats().ignored, 1);
    EXPECT_EQ(f->Classify(f->limits().CellOf(kRobot.translation()).x(),
                          f->limits().CellOf(kRobot.translation()).y()),
              n == "himm" ? CellClass::kUnknown : CellClass::kRobotPath);
  }
}

// The cone rules: sensor at (0.05, 0.05) looking along +x, 30 degree beam,
// 5 m max range. The cell (50, 40) centre is 1 m ahead on the axis, (45, 40)
// 0.5 m ahead.
TEST(Bayes, ArcCellOnAxisBecomesOccupied) {
  ConeFusion g(false, ConeOptions{}, Bounded());
  g.Insert(kRobot, Ahead(), 1.0);
  const double f = ((5.0 - 1.0) / 5.0 + 1.0) / 2.0;  // table 2.2, alpha = 0
  EXPECT_NEAR(g.OccupancyAt(50, 40), f * 0.98, 1e-5);
  EXPECT_EQ(g.Classify(50, 40), CellClass::kOccupied);
}

TEST(Bayes, CellInsideConeBecomesFree) {
  ConeFusion g(false, ConeOptions{}, Bounded());
  g.Insert(kRobot, Ahead(), 1.0);
  const double f = ((5.0 - 0.5) / 5.0 + 1.0) / 2.0;
  EXPECT_NEAR(g.OccupancyAt(45, 40), 1.0 - f, 1e-5);
  EXPECT_EQ(g.Classify(45, 40), CellClass::kEmpty);
  EXPECT_EQ(g.Classify(55, 40), CellClass::kUnknown);  // beyond the arc
  EXPECT_EQ(g.Classify(45, 50), CellClass::kUnknown);  // outside the cone
}

TEST(Bayes, RegionTwoEdgeFollowsTableOrIsCapped) {
  // A cell near the cone's edge, 2.5 m out: f < 0.5, so table 2.2 calls it
  // slightly occupied; the cap leaves it at 0.5.
  for (bool cap : {false, true}) {
    ConeOptions o;
    o.region2_never_occupied = cap;
    ConeFusion g(false, o, Bounded());
    g.Insert(kRobot, Ahead(), 2.9);
    const double alpha = std::atan2(0.6, 2.5);  // cell (65, 46): centre (2.55, 0.65)
    const double f = ((5.0 - std::hypot(2.5, 0.6)) / 5.0 + (kPi / 12 - alpha) / (kPi / 12)) / 2.0;
    ASSERT_LT(f, 0.5);
    EXPECT_NEAR(g.OccupancyAt(65, 46), cap ? 0.5 : 1.0 - f, 1e-5);
  }
}

TEST(Bayes, RepeatedReadingsAddLogOdds) {
  ConeFusion g(false, ConeOptions{}, Bounded());
  g.Insert(kRobot, Ahead(), 1.0);
  const float once = g.Values().at(50, 40);
  g.Insert(kRobot, Ahead(), 1.0);
  EXPECT_NEAR(g.Values().at(50, 40), 2 * once, 1e-5);
  EXPECT_GT(g.OccupancyAt(50, 40), 0.98);
}

TEST(DempsterShafer, ArcAndInsideMasses) {
  ConeFusion g(true, ConeOptions{}, Bounded());
  g.Insert(kRobot, Ahead(), 1.0);
  const double f1 = 0.9, f05 = 0.95;
  EXPECT_NEAR(g.OccupiedMass(50, 40), f1 * 0.98, 1e-6);
  EXPECT_EQ(g.EmptyMass(50, 40), 0.0f);
  EXPECT_NEAR(g.EmptyMass(45, 40), f05, 1e-6);
  EXPECT_EQ(g.OccupiedMass(45, 40), 0.0f);
  EXPECT_NEAR(g.OccupancyAt(50, 40), f1 * 0.98 + 0.5 * (1 - f1 * 0.98), 1e-6);
  EXPECT_EQ(g.Classify(50, 40), CellClass::kOccupied);
  EXPECT_EQ(g.Classify(45, 40), CellClass::kEmpty);
}

TEST(DempsterShafer, CombinesByDempstersRule) {
  ConeFusion g(true, ConeOptions{}, Bounded());
  g.Insert(kRobot, Ahead(), 1.0);  // (50, 40): m(occ) = a
  g.Insert(kRobot, Ahead(), 1.5);  // (50, 40) now in region II: m(empty) = b
  const double a = 0.9 * 0.98;
  const double b = ((5.0 - 1.0) / 5.0 + 1.0) / 2.0;
  const double norm = 1.0 - a * b;  // eq. 2.11-2.13: conflict occ x empty
  EXPECT_NEAR(g.OccupiedMass(50, 40), a * (1 - b) / norm, 1e-6);
  EXPECT_NEAR(g.EmptyMass(50, 40), (1 - a) * b / norm, 1e-6);
}

TEST(ConeRules, RobotPathAndNoEcho) {
  for (bool ds : {false, true}) {
    ConeFusion g(ds, ConeOptions{}, Bounded());
    g.MarkRobot(kRobot);
    g.Insert(kRobot, Ahead(), 5.0);  // no echo: region II up to the window
    EXPECT_EQ(g.Classify(40, 40), CellClass::kRobotPath);
    EXPECT_LT(g.OccupancyAt(60, 40), 0.5f);
    EXPECT_EQ(g.Classify(72, 40), CellClass::kUnknown);
    EXPECT_EQ(g.stats().misses, 1);
  }
}

}  // namespace
}  // namespace cogmap::grid

namespace cogmap::grid {
namespace {

// The cone's rows two cells at a time (SSE2) against one at a time: the same
// floats, to the bit, over rows of every kind (cells on the robot's path,
// cells at the floor, rows through the apex, both ends of odd and even
// lengths, cones of 5 to 60 degrees pointing every way).
TEST(ConeRow, PackedCellsMatchOneAtATime) {
  std::mt19937 rng(21);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  int rows_changed = 0, cells_changed = 0;
  const int trials = 2000;
  for (int trial = 0; trial < trials; ++trial) {
    const double heading = 2.0 * kPi * u(rng), half = DegToRad(2.5 + 27.5 * u(rng));
    const double reach = 0.5 + 4.0 * u(rng), cell = trial % 2 ? 0.1 : 0.055;
    // The sensor over the row's cells, the row on the side the cone points
    // to, within its reach.
    const int n = 40 + trial % 80;
    const double py = (std::sin(heading) < 0.0 ? -0.8 : 0.8) * reach * u(rng);
    const ConeRow c{0.0,  cell, n * cell * u(rng), py, std::cos(heading), std::sin(heading),
                    reach * reach, std::cos(half) * std::cos(half), half, 1.0 / half, 0.5 + u(rng), -4.0f, -3.0f};
    std::vector<float> a(n);
    for (auto& v : a) v = u(rng) < 0.1 ? c.path : u(rng) < 0.1 ? c.lo : static_cast<float>(-3.0 + 18.0 * u(rng));
    const std::vector<float> before = a;
    std::vector<float> b = a;
    const int xa = trial % 7, xb = n - 1 - trial % 5;
    c.Decrement(a.data(), xa, xb, /*packed=*/true);
    c.Decrement(b.data(), xa, xb, /*packed=*/false);
    ASSERT_EQ(0, std::memcmp(a.data(), b.data(), n * sizeof(float))) << "trial " << trial;
    int here = 0;
    for (int x = 0; x < n; ++x) here += a[x] != before[x] ? 1 : 0;
    rows_changed += here > 0 ? 1 : 0;
    cells_changed += here;
  }
  // The trials reach into the cone (else they compare nothing).
  EXPECT_GT(rows_changed, trials / 2);
  EXPECT_GT(cells_changed, 4 * trials);
}

}  // namespace
}  // namespace cogmap::grid
