#include "cogmap/asr/mapper.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <stdexcept>
#include <thread>

#include "cogmap/core/error.h"

namespace cogmap::asr {
namespace {

// Two 5 m x 4 m rooms side by side; the wall between them is 10 cm thick with
// a 1 m door at y in [1.5, 2.5].
std::vector<Segment2> TwoRooms() {
  std::vector<Segment2> w = {{{0, 0}, {10, 0}}, {{10, 0}, {10, 4}}, {{10, 4}, {0, 4}}, {{0, 4}, {0, 0}}};
  auto box = [&w](double x0, double y0, double x1, double y1) {
    w.push_back({{x0, y0}, {x1, y0}});
    w.push_back({{x1, y0}, {x1, y1}});
    w.push_back({{x1, y1}, {x0, y1}});
    w.push_back({{x0, y1}, {x0, y0}});
  };
  box(4.95, 0.0, 5.05, 1.5);
  box(4.95, 2.5, 5.05, 4.0);
  return w;
}

// Nearest wall along a ray, or max range.
double Cast(const std::vector<Segment2>& walls, const Vec2& o, double h, double max_m) {
  const Vec2 d(std::cos(h), std::sin(h));
  double best = max_m;
  for (const auto& s : walls) {
    const Vec2 e = s.b - s.a;
    const double den = d.x() * e.y() - d.y() * e.x();
    if (std::abs(den) < 1e-12) continue;
    const Vec2 ao = s.a - o;
    const double t = (ao.x() * e.y() - ao.y() * e.x()) / den;
    const double u = (ao.x() * d.y() - ao.y() * d.x()) / den;
    if (t > 0 && u >= 0 && u <= 1) best = std::min(best, t);
  }
  return best;
}

// A noise-free sonar sweep: each cone sampled by 5 rays, nearest echo.
sensors::LogRecord Sweep(const sensors::RobotDescription& robot, const std::vector<Segment2>& walls,
                         const Pose2& pose, double t) {
  sensors::LogRecord rec;
  rec.time_s = t;
  rec.odom = pose;
  rec.truth = pose;
  for (size_t i = 0; i < robot.sensors.size(); ++i) {
    const auto& s = robot.sensors[i];
    const Pose2 sp = sensors::SensorPose(pose, s);
    double r = s.max_range_m;
    for (int k = -2; k <= 2; ++k)
      r = std::min(r, Cast(walls, sp.translation(), sp.theta + k * s.beam_width_rad / 4, s.max_range_m));
    rec.ranges.push_back({static_cast<int>(i), r});
  }
  return rec;
}

std::vector<Pose2> Straight(Vec2 a, Vec2 b, double step = 0.05) {
  const double h = std::atan2(b.y() - a.y(), b.x() - a.x());
  const int n = static_cast<int>(std::lround((b - a).norm() / step));
  std::vector<Pose2> out;
  for (int i = 0; i <= n; ++i) {
    const Vec2 p = a + (b - a) * (static_cast<double>(i) / n);
    out.push_back({p.x(), p.y(), h});
  }
  return out;
}

struct Outcome {
  std::vector<Asr> closed;
  MemoryAsrStore store;
};

void Drive(CognitiveMapper* m, const std::vector<Pose2>& poses, double t0 = 0.0) {
  const auto robot = sensors::BuiltinRobot("pioneer16");
  const auto walls = TwoRooms();
  double t = t0;
  for (const auto& p : poses) {
    m->Push(Sweep(robot, walls, p, t));
    t += 0.1;
  }
}

// A 4 m x 4 m room of explored floor (walls 0.1 m thick all round) with a
// 0.8 m door in its right wall; beyond the door a 3 m x 6 m stretch of floor
// seen through it. The robot's path runs across the room.
grid::Grid2D<float> RoomSeenWithADoor() {
  grid::Grid2D<float> g(grid::MapLimits(0.1, Vec2(0, 0), 80, 60), 0.0f);  // 8 m x 6 m, unknown
  const vectorize::CellClasses cls;
  auto fill = [&](double x0, double y0, double x1, double y1, float v) {
    for (int y = static_cast<int>(std::lround(y0 * 10)); y < std::lround(y1 * 10); ++y)
      for (int x = static_cast<int>(std::lround(x0 * 10)); x < std::lround(x1 * 10); ++x) g.at(x, y) = v;
  };
  fill(1.0, 1.0, 5.2, 5.2, 20.0f);  // wall cells
  fill(1.1, 1.1, 5.1, 5.1, -5.0f);  // the room's floor: 4 m x 4 m
  fill(5.1, 2.7, 5.2, 3.5, -5.0f);  // the door (0.8 m) in the right wall
  fill(5.2, 0.0, 8.0, 6.0, -5.0f);  // the floor seen through it
  for (int x = 15; x < 45; ++x) g.at(x, 30) = cls.robot_path;
  return g;
}

TEST(FreeSpaceHull, IsTheRoomNotTheFloorSeenThroughItsDoor) {
  const auto hull = FreeSpaceHull(RoomSeenWithADoor(), vectorize::CellClasses{}, 0.5);
  // The room's floor: the door (0.8 m < 2 x 0.5 m) parts it from the floor
  // behind. Growing the core back by 0.5 m reaches the room's walls, and at
  // the door at most 0.5 m past it: the room (16 m2) and less than a 0.5 m
  // band beside it, not the 3 m of floor behind the door.
  EXPECT_GE(SignedArea(hull), 16.0 - 1e-9);
  EXPECT_LT(SignedArea(hull), 16.0 + 0.5 * 4.0);
  for (const Vec2& p : hull) {
    EXPECT_GE(p.x(), 1.1 - 1e-9);
    EXPECT_LE(p.x(), 5.2 + 0.5 + 1e-9);
    EXPECT_GE(p.y(), 1.1 - 1e-9);
    EXPECT_LE(p.y(), 5.1 + 1e-9);
  }
  // With no opening the floor seen through the door joins: the hull reaches
  // the far side (x = 8 m).
  const auto all = FreeSpaceHull(RoomSeenWithADoor(), vectorize::CellClasses{}, 0.0);
  double max_x = 0;
  for (const Vec2& p : all) max_x = std::max(max_x, p.x());
  EXPECT_NEAR(max_x, 8.0, 1e-9);
  // No path, no floor.
  grid::Grid2D<float> empty(grid::MapLimits(0.1, Vec2(0, 0), 10, 10), -5.0f);
  EXPECT_TRUE(FreeSpaceHull(empty, vectorize::CellClasses{}, 0.5).empty());
}

TEST(SimplifyConvex, DropsTheVerticesThatCostLeastArea) {
  // A 4 x 4 square with a vertex 0.01 m out in the middle of each side: each
  // costs 0.02 m2 (0.125 % of 16); the corners cost 8 m2 each.
  const std::vector<Vec2> poly{{0, 0}, {2, -0.01}, {4, 0}, {4.01, 2}, {4, 4}, {2, 4.01}, {0, 4}, {-0.01, 2}};
  const auto square = SimplifyConvex(poly, 0.01);
  ASSERT_EQ(square.size(), 4u);
  EXPECT_NEAR(SignedArea(square), 16.0, 1e-12);
  // A budget below one side vertex's cost keeps them all; none leaves a triangle.
  EXPECT_EQ(SimplifyConvex(poly, 0.001).size(), 8u);
  EXPECT_EQ(SimplifyConvex(poly, 1.0).size(), 3u);
}

TEST(MapperOptions, DefaultsAreThePapers) {
  const MapperOptions o;
  EXPECT_DOUBLE_EQ(o.cell_m, 0.1);
  EXPECT_DOUBLE_EQ(o.mhimm.window_m, 3.0);
  EXPECT_FLOAT_EQ(o.mhimm.min_value, -3.0f);
  EXPECT_DOUBLE_EQ(o.boundary.close_m, 0.7);
}

TEST(CognitiveMapper, DoorwaySplitsTwoRoomsIntoTwoAsrs) {
  Outcome run;
  CognitiveMapper m(sensors::BuiltinRobot("pioneer16"), {}, &run.store,
                    [&run](const Asr& a) { run.closed.push_back(a); });
  Drive(&m, Straight({1.0, 2.0}, {9.0, 2.0}));
  EXPECT_EQ(run.closed.size(), 1u);  // room A closed at the door, B still open
  EXPECT_EQ(m.current_id(), 1);
  m.Finish();
  ASSERT_EQ(run.closed.size(), 2u);
  EXPECT_EQ(m.current_id(), -1);
  const Asr& a = run.closed[0];
  const Asr& b = run.closed[1];
  EXPECT_EQ(a.id, 0);
  EXPECT_EQ(b.id, 1);
  ASSERT_EQ(a.exits.size(), 1u);
  const Exit& door = a.exits[0];
  EXPECT_EQ(door.from_asr, 0);
  EXPECT_EQ(door.to_asr, 1);
  EXPECT_NEAR(door.center_m.x(), 5.0, 0.3);
  EXPECT_NEAR(door.center_m.y(), 2.0, 1e-9);
  EXPECT_NEAR(door.width_m, 1.0, 0.35);
  // B was entered through the same exit, which is its pivot and local origin.
  ASSERT_EQ(b.exits.size(), 1u);
  EXPECT_EQ(b.exits[0].center_m, door.center_m);
  EXPECT_EQ(b.entry_pivot_m, door.center_m);
  EXPECT_NEAR(b.world_from_local_raw.x, door.center_m.x(), 0.05);
  EXPECT_EQ(b.world_from_local_raw.theta, 0.0);
  EXPECT_EQ(a.world_from_local_raw.x, 1.0);
  // Paths meet at the exit; both ASRs have walls and their sizes.
  EXPECT_LE(a.path.back().x, door.center_m.x() + 1e-9);
  EXPECT_GE(b.path.front().x, door.center_m.x() - 0.05);
  EXPECT_EQ(a.true_path.size(), a.path.size());
  EXPECT_FALSE(a.walls_local.empty());
  EXPECT_FALSE(b.walls_local.empty());
  EXPECT_GT(a.bytes.grid, a.bytes.polylines);
  EXPECT_GT(a.seconds.grid, 0.0);
  EXPECT_LE(a.end_time_s, b.start_time_s + 1e-9);
  // Stored, with the graph edge.
  EXPECT_EQ(run.store.Count(), 2);
  EXPECT_EQ(run.store.Neighbours(0), (std::vector<int>{1}));
  EXPECT_TRUE(run.store.GetMeta(kMetaLastRawPose).has_value());
  EXPECT_EQ(*run.store.GetMeta(kMetaNextId), "2");
}

TEST(CognitiveMapper, WallsOfTheFirstRoomOutlineIt) {
  Outcome run;
  CognitiveMapper m(sensors::BuiltinRobot("pioneer16"), {}, &run.store,
                    [&run](const Asr& a) { run.closed.push_back(a); });
  // A loop in room A, then through the door.
  auto poses = Straight({1.2, 1.2}, {3.8, 1.2});
  for (auto leg : {Straight({3.8, 1.2}, {3.8, 2.8}), Straight({3.8, 2.8}, {1.2, 2.8}),
                   Straight({1.2, 2.8}, {1.2, 2.0}), Straight({1.2, 2.0}, {8.0, 2.0})})
    poses.insert(poses.end(), leg.begin() + 1, leg.end());
  Drive(&m, poses);
  m.Finish();
  ASSERT_GE(run.closed.size(), 2u);
  const auto walls = run.closed[0].WallsWorldRaw();
  // Sonar rounds the room off (the nearest echo of a cone lies on its axis)
  // and sees a little of room B through the door: most vertices lie in room A
  // grown by the sonar's rounding.
  int near_wall = 0, total = 0;
  Vec2 lo(1e9, 1e9), hi(-1e9, -1e9);
  for (const auto& line : walls)
    for (const auto& p : line) {
      ++total;
      const bool in = p.x() > -0.7 && p.x() < 5.7 && p.y() > -0.7 && p.y() < 4.7;
      near_wall += in ? 1 : 0;
      if (in) {
        lo = lo.cwiseMin(p);
        hi = hi.cwiseMax(p);
      }
    }
  ASSERT_GT(total, 0);
  EXPECT_GE(hi.x() - lo.x(), 3.5);  // the outline spans the room
  EXPECT_GE(hi.y() - lo.y(), 2.5);
  EXPECT_GE(static_cast<double>(near_wall) / total, 0.6);
}

TEST(CognitiveMapper, TurningBackInTheDoorwayKeepsOneAsr) {
  Outcome run;
  CognitiveMapper m(sensors::BuiltinRobot("pioneer16"), {}, &run.store,
                    [&run](const Asr& a) { run.closed.push_back(a); });
  auto poses = Straight({1.0, 2.0}, {5.0, 2.0});
  const auto back = Straight({5.0, 2.0}, {1.0, 2.0});
  poses.insert(poses.end(), back.begin() + 1, back.end());
  Drive(&m, poses);
  m.Finish();
  EXPECT_EQ(run.closed.size(), 1u);
  EXPECT_EQ(m.stats().turn_backs, 1);
}

TEST(CognitiveMapper, LogEndingMidRoomIsClosedByFinish) {
  Outcome run;
  CognitiveMapper m(sensors::BuiltinRobot("pioneer16"), {}, &run.store);
  Drive(&m, Straight({1.0, 2.0}, {3.0, 2.0}));
  EXPECT_EQ(run.store.Count(), 0);
  m.Finish();
  m.Finish();  // idempotent
  EXPECT_EQ(run.store.Count(), 1);
  EXPECT_TRUE(run.store.Get(0)->exits.empty());
}

TEST(CognitiveMapper, ResumeContinuesIdsAndPose) {
  Outcome run;
  {
    CognitiveMapper m(sensors::BuiltinRobot("pioneer16"), {}, &run.store);
    Drive(&m, Straight({1.0, 2.0}, {3.0, 2.0}));
    m.Finish();
  }
  ASSERT_EQ(run.store.Count(), 1);
  MapperResume r;
  r.next_id = run.store.MaxId() + 1;
  r.previous_asr = run.store.MaxId();
  r.last_raw_pose = Pose2{3.0, 2.0, 0.0};
  CognitiveMapper m(sensors::BuiltinRobot("pioneer16"), {}, &run.store);
  m.Resume(r);
  // The new log's odometry starts at zero; its readings are those of x = 3..4.
  const auto robot = sensors::BuiltinRobot("pioneer16");
  const auto walls = TwoRooms();
  for (int i = 0; i <= 20; ++i) {
    auto rec = Sweep(robot, walls, {3.0 + i * 0.05, 2.0, 0.0}, 100 + i * 0.1);
    rec.odom = {i * 0.05, 0.0, 0.0};
    m.Push(rec);
  }
  m.Finish();
  ASSERT_EQ(run.store.Count(), 2);
  const Asr b = *run.store.Get(1);
  EXPECT_NEAR(b.world_from_local_raw.x, 3.0, 1e-12);
  EXPECT_NEAR(b.world_from_local_raw.y, 2.0, 1e-12);
  EXPECT_NEAR(b.path.back().x, 4.0, 1e-9);
  ASSERT_EQ(b.exits.size(), 1u);
  EXPECT_EQ(b.exits[0].from_asr, 0);
  EXPECT_EQ(b.exits[0].width_m, 0.0);
  EXPECT_EQ(run.store.Neighbours(0), (std::vector<int>{1}));
}

TEST(CognitiveMapper, FixedLengthModeCutsAsrsOfTheSetLength) {
  MapperOptions o;
  o.boundary.mode = BoundaryMode::kFixedLength;
  o.boundary.asr_length_m = 2.0;
  Outcome run;
  CognitiveMapper m(sensors::BuiltinRobot("pioneer16"), o, &run.store,
                    [&run](const Asr& a) { run.closed.push_back(a); });
  Drive(&m, Straight({1.0, 2.0}, {8.95, 2.0}));
  m.Finish();
  ASSERT_EQ(run.closed.size(), 4u);  // cuts at 3, 5, 7; the last ends at 8.95
  for (const auto& a : run.closed) {
    const double length = a.path.back().x - a.world_from_local_raw.x;
    EXPECT_NEAR(length, 2.0, 0.05 + 1e-9) << a.id;
  }
}

TEST(CognitiveMapper, CorrectorSeesEveryAsrBeforeTheStore) {
  Outcome run;
  CognitiveMapper m(sensors::BuiltinRobot("pioneer16"), {}, &run.store);
  int calls = 0;
  m.SetCorrector([&calls](Asr a) {
    ++calls;
    a.world_from_local_corrected.theta = 0.1;
    a.heading_correction_rad = 0.1;
    return a;
  });
  Drive(&m, Straight({1.0, 2.0}, {9.0, 2.0}));
  m.Finish();
  EXPECT_EQ(calls, 2);
  EXPECT_DOUBLE_EQ(run.store.Get(1)->heading_correction_rad, 0.1);
}

// Closing in the background: the same ASRs, stored and handed over in order
// on the caller's thread; an error on the worker comes out of the caller's
// next Push or Finish, after the ASRs closed before it.
TEST(CognitiveMapper, BackgroundClosingHandsOverInOrderAndRaisesItsErrors) {
  MapperOptions o;
  o.close_in_background = true;
  Outcome run;
  const std::thread::id caller = std::this_thread::get_id();
  CognitiveMapper m(sensors::BuiltinRobot("pioneer16"), o, &run.store, [&](const Asr& a) {
    EXPECT_EQ(std::this_thread::get_id(), caller);
    run.closed.push_back(a);
  });
  Drive(&m, Straight({1.0, 2.0}, {9.0, 2.0}));
  m.Finish();
  ASSERT_EQ(run.closed.size(), 2u);
  EXPECT_EQ(run.closed[0].id, 0);
  EXPECT_EQ(run.closed[1].id, 1);
  EXPECT_FALSE(run.closed[0].walls_local.empty());
  EXPECT_EQ(run.store.Count(), 2);
  EXPECT_EQ(*run.store.GetMeta(kMetaNextId), "2");

  Outcome failing;
  CognitiveMapper f(sensors::BuiltinRobot("pioneer16"), o, &failing.store,
                    [&](const Asr& a) { failing.closed.push_back(a); });
  f.SetCorrector([](Asr a) {
    if (a.id == 1) throw std::runtime_error("corrector failed on ASR 1");
    return a;
  });
  Drive(&f, Straight({1.0, 2.0}, {9.0, 2.0}));
  try {
    f.Finish();
    FAIL() << "the worker's error was not raised";
  } catch (const std::runtime_error& e) {
    EXPECT_STREQ(e.what(), "corrector failed on ASR 1");
  }
  ASSERT_EQ(failing.closed.size(), 1u);
  EXPECT_EQ(failing.closed[0].id, 0);
  EXPECT_EQ(failing.store.Count(), 1);
}

TEST(CognitiveMapper, OdometryFilterKeepsTheRawOdometryInTheStore) {
  // The "pre-corrected" odometry is the raw one moved by a fixed rigid F: the
  // ASR is mapped in F's frame, then its raw fields go back to the raw frame.
  const Pose2 f{0.5, -0.3, 0.2};
  Outcome run;
  CognitiveMapper m(sensors::BuiltinRobot("pioneer16"), {}, &run.store,
                    [&run](const Asr& a) { run.closed.push_back(a); });
  m.SetOdometryFilter([f](const Pose2& raw, double) { return f * raw; });
  Drive(&m, Straight({1.0, 2.0}, {4.0, 2.0}));
  m.Finish();
  ASSERT_EQ(run.closed.size(), 1u);
  const Asr& a = run.closed[0];
  ASSERT_FALSE(a.path.empty());
  for (const auto& p : a.path) {  // the raw odometry, as driven
    EXPECT_NEAR(p.y, 2.0, 1e-9);
    EXPECT_NEAR(p.theta, 0.0, 1e-9);
  }
  EXPECT_NEAR(a.path.front().x, 1.0, 1e-9);
  EXPECT_NEAR(a.entry_pivot_m.x(), 1.0, 1e-9);
  EXPECT_NEAR(a.entry_pivot_m.y(), 2.0, 1e-9);
  // raw -> corrected (no corrector: the pre-corrected placement) is F.
  const Pose2 c = a.world_from_local_corrected * a.world_from_local_raw.inverse();
  EXPECT_NEAR(c.x, f.x, 1e-9);
  EXPECT_NEAR(c.y, f.y, 1e-9);
  EXPECT_NEAR(c.theta, f.theta, 1e-9);
  EXPECT_NEAR(a.heading_correction_rad, f.theta, 1e-9);
  EXPECT_EQ(run.store.Get(0)->path.size(), a.path.size());
  EXPECT_EQ(a.true_path.size(), a.path.size());
}

TEST(BestRigidFit, RecoversARigidTransform) {
  const Pose2 t{1.5, -2.0, 0.4};
  const std::vector<Pose2> from = {{0, 0, 0}, {1, 0, 0.1}, {2, 0.5, 0.3}};
  std::vector<Pose2> to;
  for (const auto& p : from) to.push_back(t * p);
  const Pose2 r = BestRigidFit(from, to);
  EXPECT_NEAR(r.x, t.x, 1e-12);
  EXPECT_NEAR(r.y, t.y, 1e-12);
  EXPECT_NEAR(r.theta, t.theta, 1e-12);
  EXPECT_EQ(BestRigidFit({}, {}).theta, 0.0);
}

// The positive numbers of the store's meta (the robot radius, the sensor
// reach, the sensor beam), each under its own key, written in shortest
// round-trip form and read back exactly; junk is a damaged store, an error
// naming the store and the key (it read as none: the floor plan then fell
// back to its defaults without a word).
TEST(PositiveMeta, RoundTripsAndRefusesJunk) {
  struct Key {
    const char* key;
    void (*set)(AsrStore*, double);
    std::optional<double> (*get)(const AsrStore&);
    double value;
  };
  for (const Key& k : {Key{kMetaRobotRadius, SetRobotRadius, RobotRadius, 0.1234567890123},
                       Key{kMetaSensorReach, SetSensorReach, SensorReach, 3.0000000001},
                       Key{kMetaSensorBeam, SetSensorBeam, SensorBeam, 0.4363323129985824}}) {
    SCOPED_TRACE(k.key);
    MemoryAsrStore store;
    EXPECT_FALSE(k.get(store));
    k.set(&store, k.value);
    ASSERT_TRUE(k.get(store));
    EXPECT_EQ(*k.get(store), k.value);
    EXPECT_EQ(store.GetMeta(k.key == kMetaRobotRadius ? kMetaSensorReach : kMetaRobotRadius), std::nullopt);
    for (const char* bad : {"", "abc", "0.2x", "3 m", "-0.3", "0", "nan", "inf"}) {
      store.SetMeta(k.key, bad);
      try {
        k.get(store);
        ADD_FAILURE() << "'" << bad << "' read without an error";
      } catch (const InputError& e) {
        EXPECT_EQ(std::string(e.what()), std::string("memory store: a damaged store: meta ") + k.key + " is '" + bad +
                                             "', not a positive number");
      }
    }
  }
}

}  // namespace
}  // namespace cogmap::asr
