#include "cogmap/localize/scan_odometry.h"

#include <gtest/gtest.h>

#include <cmath>
#include <iterator>
#include <random>

#include "cogmap/io/world_io.h"
#include "cogmap/sim/world.h"

namespace cogmap::localize {
namespace {

// A laser's readings at 'truth' in 'world' (range noise 'noise_m').
std::vector<sensors::RangeReading> Scan(const sim::World& world, const sensors::RobotDescription& robot,
                                        const Pose2& truth, double noise_m, std::mt19937_64* rng) {
  std::normal_distribution<double> n(0.0, noise_m);
  std::vector<sensors::RangeReading> out;
  for (int i = 0; i < static_cast<int>(robot.sensors.size()); ++i) {
    const sensors::RangeSensor& s = robot.sensors[i];
    const Pose2 sp = sensors::SensorPose(truth, s);
    const sim::RayHit hit = world.CastRay(sp.translation(), sp.theta, s.max_range_m);
    out.push_back({i, hit.hit() ? hit.distance_m + n(*rng) : s.max_range_m});
  }
  return out;
}

struct DriveResult {
  double truth_heading_err_deg = 0.0, odom_heading_err_deg = 0.0;
  double truth_pos_err_m = 0.0, odom_pos_err_m = 0.0;
  ScanOdometryStats stats;
};

// The robot drives 'path' (true poses, 5 cm apart); the wheels drift by
// 'drift_deg_per_m' and read 2 % long. Errors at the end, relative to the start.
DriveResult Drive(const sim::World& world, const std::vector<Pose2>& path, double drift_deg_per_m,
                  const sensors::RobotDescription& robot = sensors::BuiltinRobot("laser"), unsigned seed = 3) {
  ScanOdometry so(robot);
  std::mt19937_64 rng(seed);
  Pose2 odom = path[0], corrected;
  for (size_t k = 0; k < path.size(); ++k) {
    if (k > 0) {
      const Pose2 step = path[k - 1].inverse() * path[k];
      const double d = std::hypot(step.x, step.y);
      odom = odom * Pose2{1.02 * step.x, 1.02 * step.y, step.theta + DegToRad(drift_deg_per_m) * d};
    }
    corrected = so.Correct(odom, Scan(world, robot, path[k], 0.01, &rng));
  }
  DriveResult r;
  const Pose2 t = path.back();
  r.truth_heading_err_deg = RadToDeg(std::abs(NormalizeAngle(corrected.theta - t.theta)));
  r.odom_heading_err_deg = RadToDeg(std::abs(NormalizeAngle(odom.theta - t.theta)));
  r.truth_pos_err_m = (corrected.translation() - t.translation()).norm();
  r.odom_pos_err_m = (odom.translation() - t.translation()).norm();
  r.stats = so.stats();
  return r;
}

std::vector<Segment2> Box(double x0, double y0, double x1, double y1) {
  return {{Vec2(x0, y0), Vec2(x1, y0)}, {Vec2(x1, y0), Vec2(x1, y1)}, {Vec2(x1, y1), Vec2(x0, y1)},
          {Vec2(x0, y1), Vec2(x0, y0)}};
}

// A 6 x 4 m room with a cabinet, driven round a loop of 14 m at 3 deg/m of
// drift: the wheels end 40 degrees and metres off, the scans within tenths.
TEST(ScanOdometry, AScannedRoomCorrectsTheWheels) {
  std::vector<Segment2> walls = Box(0, 0, 6, 4);
  for (const Segment2& s : Box(2.5, 1.6, 3.5, 2.4)) walls.push_back(s);
  const sim::World world(walls);
  std::vector<Pose2> path;
  // Round the cabinet: four legs with quarter turns on the spot.
  const Vec2 corners[] = {Vec2(1, 0.8), Vec2(5, 0.8), Vec2(5, 3.2), Vec2(1, 3.2)};
  for (int leg = 0; leg < 4; ++leg) {
    const Vec2 a = corners[leg], b = corners[(leg + 1) % 4];
    const double h = std::atan2(b.y() - a.y(), b.x() - a.x());
    const int n = static_cast<int>(std::round((b - a).norm() / 0.05));
    for (int k = 0; k < n; ++k) path.push_back(Pose2{a.x() + (b.x() - a.x()) * k / n, a.y() + (b.y() - a.y()) * k / n, h});
    const double next = leg < 3 ? std::atan2(corners[(leg + 2) % 4].y() - b.y(), corners[(leg + 2) % 4].x() - b.x()) : h;
    for (int k = 1; k <= 9; ++k) path.push_back(Pose2{b.x(), b.y(), h + NormalizeAngle(next - h) * k / 9.0});
  }
  const DriveResult r = Drive(world, path, 3.0);
  EXPECT_GT(r.odom_heading_err_deg, 30.0);
  EXPECT_LT(r.truth_heading_err_deg, 0.5);
  EXPECT_GT(r.odom_pos_err_m, 1.0);
  EXPECT_LT(r.truth_pos_err_m, 0.05);
  EXPECT_GT(r.stats.matched, 0.95 * r.stats.scans);
}

// A corridor of two long walls tells the heading and the lateral position,
// not how far along: there the wheels are kept (their 2 % stays, no slide).
TEST(ScanOdometry, ACorridorKeepsTheWheelsAlongIt) {
  const sim::World world({{Vec2(-5, -1), Vec2(60, -1)}, {Vec2(-5, 1), Vec2(60, 1)}});
  std::vector<Pose2> path;
  for (int k = 0; k <= 400; ++k) path.push_back(Pose2{0.05 * k, 0.2 * std::sin(0.05 * k), 0.0});
  const DriveResult r = Drive(world, path, 2.0);
  EXPECT_GT(r.odom_heading_err_deg, 20.0);
  EXPECT_LT(r.truth_heading_err_deg, 0.5);
  const Pose2 t = path.back();
  // Along: the wheels' 2 % of 20 m, within a few centimetres either way.
  EXPECT_GT(r.truth_pos_err_m, 0.2);
  EXPECT_LT(r.truth_pos_err_m, 0.6);
  (void)t;
}

// Through a door into a room deeper than the laser reaches (gen-building
// --room-depth-m 8 with the 8 m laser): inside, the scans see the room's side
// walls only, which tell nothing of the way forward. The walls beside the
// robot must not be matched to the jamb seen at the edge of the reference's
// view (a surface facing the other way): that held the robot at the door while
// the wheels drove it 2.3 m in (gen30deep, laser: ATE 1.21 m, 0.13 m without).
TEST(ScanOdometry, ADeepRoomThroughADoorKeepsTheWheelsForward) {
  // gen30deep's room 36.56-41.50 m along the corridor, its door 38.02-39.22 m,
  // the robot through it at 38.55 m (walls of no thickness, as generated).
  const std::vector<Segment2> walls = {
      {Vec2(-20, 3), Vec2(20, 3)},                                              // the corridor's far wall
      {Vec2(-20, 0), Vec2(-0.535, 0)}, {Vec2(0.665, 0), Vec2(20, 0)},           // its near wall, the door in it
      {Vec2(-1.986, 0), Vec2(-1.986, -8)}, {Vec2(2.951, 0), Vec2(2.951, -8)},  // the room, 8 m deep
      {Vec2(-1.986, -8), Vec2(2.951, -8)}};
  const sim::World world(walls);
  std::vector<Pose2> path;
  for (int k = 0; k <= 100; ++k) path.push_back(Pose2{0.0, 1.5 - 0.05 * k, -M_PI / 2});
  const DriveResult r = Drive(world, path, 0.0);
  // The wheels' 2 % of 5 m, not metres.
  EXPECT_LT(r.truth_pos_err_m, 0.2);
  EXPECT_LT(r.truth_heading_err_deg, 0.5);
}

// A dense laser close to a corridor's wall in a building scanned by a robot
// (data/room-segmentation/lab_a_scan.png, 5 cm pixels: walls with a pixel's
// step here and there): a URG-04LX's 240 degrees in 341 beams, 4 m, 0.35 m
// from the wall. 15 beams either side of a return near the robot span a few
// centimetres of wall, the lines fitted to them lay along a step, tens of
// degrees off the wall, and they measured the way along the corridor as
// none (the robot held still for 3 m of its 4). The lines now take the
// returns within 0.3 m along the scan, however many beams that is.
TEST(ScanOdometry, ADenseLaserNearAScannedCorridorWallKeepsTheWheelsAlongIt) {
  const sim::World world(
      io::ReadWorld(std::string(COGMAP_SHARED_DIR) + "/data/room-segmentation/lab_a_scan.png").plan.walls);
  sensors::LaserOptions urg;
  urg.beams = 341;
  urg.fov_rad = DegToRad(240.0);
  urg.max_range_m = 4.0;
  // The simulated robot's true path there (every 0.2 s of the run that
  // showed it: x m, y m, heading degrees), halved into 5 cm steps: through a
  // doorway, turning into the corridor, 3.3 m along it.
  const double truth[][3] = {
      {26.00, 30.58, -121.3}, {25.94, 30.49, -120.4}, {25.89, 30.41, -119.8}, {25.84, 30.32, -119.6},
      {25.80, 30.23, -119.4}, {25.75, 30.15, -119.3}, {25.70, 30.06, -119.3}, {25.65, 29.97, -119.3},
      {25.60, 29.88, -119.2}, {25.55, 29.80, -119.2}, {25.50, 29.71, -119.2}, {25.45, 29.62, -119.2},
      {25.41, 29.54, -114.0}, {25.39, 29.49, -110.6}, {25.36, 29.40, -105.7}, {25.34, 29.30, -94.4}, {25.35, 29.21, -81.7},
      {25.37, 29.12, -67.2},  {25.42, 29.04, -52.3},  {25.48, 28.97, -40.0}, {25.56, 28.93, -24.2},
      {25.65, 28.90, -13.2},  {25.74, 28.88, -7.3},   {25.84, 28.87, -4.2},  {25.94, 28.87, -2.4},
      {26.04, 28.86, -1.5},   {26.14, 28.86, -1.0},   {26.24, 28.86, -0.7},  {26.34, 28.86, -0.5},
      {26.44, 28.86, -0.4},   {26.54, 28.86, -0.3},   {26.64, 28.86, -0.3},  {26.74, 28.86, -0.3},
      {26.84, 28.85, -0.2},   {26.94, 28.85, -0.2},   {27.04, 28.85, -0.2},  {27.14, 28.85, -0.2},
      {27.24, 28.85, -0.2},   {27.34, 28.85, -0.1},   {27.44, 28.85, -0.1},  {27.54, 28.85, -0.1},
      {27.64, 28.85, -0.1},   {27.74, 28.85, -0.1},   {27.84, 28.85, -0.1},  {27.94, 28.85, -0.1},
      {28.04, 28.85, -0.1},   {28.14, 28.85, 2.5},    {28.24, 28.86, 3.9},   {28.34, 28.87, 4.7},
      {28.44, 28.88, 5.1},    {28.54, 28.88, 5.4},    {28.64, 28.89, 5.5},   {28.74, 28.90, 5.6},
      {28.84, 28.91, 5.7},    {28.94, 28.92, 5.7}};
  std::vector<Pose2> path;
  for (size_t k = 0; k < std::size(truth); ++k) {
    const Pose2 a{truth[k][0], truth[k][1], DegToRad(truth[k][2])};
    path.push_back(a);
    if (k + 1 < std::size(truth)) {
      const Pose2 b{truth[k + 1][0], truth[k + 1][1], DegToRad(truth[k + 1][2])};
      path.push_back(Pose2{0.5 * (a.x + b.x), 0.5 * (a.y + b.y), a.theta + 0.5 * NormalizeAngle(b.theta - a.theta)});
    }
  }
  // Whether a line comes out tens of degrees off depends on the range noise:
  // before, one of these 15 noise draws (seed 11) held the robot still.
  for (unsigned seed = 1; seed <= 15; ++seed) {
    SCOPED_TRACE("noise seed " + std::to_string(seed));
    const DriveResult r = Drive(world, path, 0.0, sensors::MakeLaser(urg, "urg"), seed);
    // The wheels' 2 % of 4.2 m is 8 cm; standing still, 3.3 m.
    EXPECT_LT(r.truth_pos_err_m, 0.2);
    EXPECT_LT(r.truth_heading_err_deg, 0.5);
  }
}

TEST(ScanOdometry, ASonarRobotIsLeftAlone) {
  ScanOdometry so(sensors::BuiltinRobot("pioneer16"));
  const Pose2 odom{1.0, 2.0, 0.3};
  EXPECT_EQ(so.Correct(odom, {{0, 1.0}, {1, 2.0}}).x, 1.0);
  EXPECT_EQ(so.stats().scans, 0);
}

}  // namespace
}  // namespace cogmap::localize
