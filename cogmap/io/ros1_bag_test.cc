// ROS 1 bags: written by rosbag (cogmap's RosAria-style writer, or messages
// built here), read back through OpenLog.
#include "cogmap/io/ros1_bag.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "cogmap/core/angles.h"
#include "cogmap/io/log_test_util.h"
#include "cogmap/io/ros1_bag_test_fixture.h"
#include "cogmap/io/world_io.h"
#include "cogmap/sensors/robot.h"
#include "cogmap/sim/simulator.h"

namespace cogmap::io {
namespace {

using namespace testing_util;
using ::testing::HasSubstr;
using M = FixtureMessage;

M Make(const std::string& topic, int64_t ns, M::Kind kind, const std::string& frame = "",
       const std::string& child = "", double x = 0, double y = 0, double yaw = 0) {
  M m;
  m.topic = topic;
  m.time_ns = ns;
  m.kind = kind;
  m.frame = frame;
  m.child = child;
  m.x = x;
  m.y = y;
  m.yaw = yaw;
  return m;
}

std::vector<sensors::LogRecord> SimulatedRun(const std::string& robot_name, double seconds) {
  const FloorPlan plan = ReadAriaMap(std::string(COGMAP_SHARED_DIR) + "/worlds/nine_rooms.map").plan;
  sim::SimulatorOptions o;
  o.seed = 5;
  o.max_time_s = seconds;
  std::vector<sensors::LogRecord> run;
  sim::Simulate(plan, sensors::BuiltinRobot(robot_name), o, [&](const sensors::LogRecord& r) { run.push_back(r); });
  return run;
}

std::string WriteBag(const std::string& name, const std::vector<sensors::LogRecord>& run,
                     const sensors::RobotDescription& robot) {
  const std::string path = ::cogmap::testing_util::TestTempPath(name);
  size_t k = 0;
  const long n = WriteRosAriaBag(path, robot, [&](sensors::LogRecord* r) {
    if (k == run.size()) return false;
    *r = run[k++];
    return true;
  });
  EXPECT_EQ(n, static_cast<long>(run.size()));
  return path;
}

// Times are nanoseconds in a bag, sonar points and laser ranges float32.
void ExpectSameRecords(const std::vector<sensors::LogRecord>& back, const std::vector<sensors::LogRecord>& run,
                       bool with_truth) {
  ASSERT_EQ(back.size(), run.size());
  for (size_t k = 0; k < run.size(); ++k) {
    const auto &a = back[k], &b = run[k];
    ASSERT_NEAR(a.time_s, b.time_s, 1e-9) << k;
    ASSERT_NEAR(a.odom.x, b.odom.x, 1e-12) << k;
    ASSERT_NEAR(a.odom.y, b.odom.y, 1e-12) << k;
    ASSERT_NEAR(NormalizeAngle(a.odom.theta - b.odom.theta), 0.0, 1e-12) << k;
    if (with_truth) {
      ASSERT_TRUE(a.truth.has_value()) << k;
      ASSERT_NEAR(a.truth->x, b.truth->x, 1e-12) << k;
      ASSERT_NEAR(NormalizeAngle(a.truth->theta - b.truth->theta), 0.0, 1e-12) << k;
    }
    ASSERT_EQ(a.ranges.size(), b.ranges.size()) << k;
    for (size_t i = 0; i < b.ranges.size(); ++i) {
      ASSERT_EQ(a.ranges[i].sensor, b.ranges[i].sensor) << k;
      ASSERT_NEAR(a.ranges[i].range_m, b.ranges[i].range_m, 2e-6) << k;
    }
  }
}

TEST(Ros1Bag, SimulatedSonarRunReadsBackAsTheSameRecords) {
  const auto run = SimulatedRun("pioneer16", 30.0);
  ASSERT_GT(run.size(), 500u);
  const auto robot = sensors::BuiltinRobot("pioneer16");
  const std::string bag = WriteBag("sonar_run.bag", run, robot);
  EXPECT_EQ(DetectLogFormat(bag), "rosbag");
  auto reader = OpenLog(bag);
  // The ring from the tf frames sonar_0..15 is the built-in Pioneer's.
  ASSERT_TRUE(reader->robot_hint());
  EXPECT_EQ(reader->robot_hint()->name, "pioneer16");
  const auto back = ReadAll(*reader);
  ExpectSameRecords(back, run, true);
  // No-echo readings stay no echo through float32.
  long no_echo_run = 0, no_echo_back = 0;
  for (const auto& r : run)
    for (const auto& q : r.ranges) no_echo_run += q.range_m >= 5.0;
  for (const auto& r : back)
    for (const auto& q : r.ranges) no_echo_back += q.range_m >= 5.0;
  EXPECT_EQ(no_echo_back, no_echo_run);
  EXPECT_TRUE(reader->skipped().empty());
  bool pose_used = false;
  for (const auto& c : reader->contents()) pose_used |= c.name == "/RosAria/pose" && c.use == "odometry";
  EXPECT_TRUE(pose_used);
}

TEST(Ros1Bag, SimulatedLaserRunReadsBackAsTheSameRecords) {
  const auto run = SimulatedRun("laser", 10.0);
  const auto robot = sensors::BuiltinRobot("laser");
  const std::string bag = WriteBag("laser_run.bag", run, robot);
  auto reader = OpenLog(bag, "rosbag");
  EXPECT_EQ(reader->robot_hint()->name, "laser");
  ExpectSameRecords(ReadAll(*reader), run, true);
}

TEST(Ros1Bag, OdometryFromTfWhenNoOdometryTopicIsChosen) {
  const auto run = SimulatedRun("pioneer16", 5.0);
  const std::string bag = WriteBag("tf_odom.bag", run, sensors::BuiltinRobot("pioneer16"));
  LogOpenOptions o;
  o.topics = {"/RosAria/sonar"};
  auto reader = OpenLog(bag, o);
  const auto back = ReadAll(*reader);
  std::vector<sensors::LogRecord> want = run;
  for (auto& r : want) r.truth.reset();
  ExpectSameRecords(back, want, false);
}

// Odometry at t = 1 s and 2 s; a 3-beam scan at 1.5 s from a laser that
// tf_static puts 0.2 m ahead of base_link, turned 90 degrees.
TEST(Ros1Bag, ScanTakesInterpolatedOdometryAndTfSensorPose) {
  const std::string bag = ::cogmap::testing_util::TestTempPath("interp.bag");
  M tf = Make("/tf_static", 500000000, M::kTf, "base_link", "laser", 0.2, 0.0, kPi / 2);
  M o1 = Make("/odom", 1000000000, M::kOdometry, "odom", "base_link", 0.0, 0.0, 0.0);
  M o2 = Make("/odom", 2000000000, M::kOdometry, "odom", "base_link", 1.0, 2.0, 0.5);
  M scan = Make("/scan", 1500000000, M::kLaserScan, "laser", "");
  scan.angle_min = -0.5;
  scan.angle_increment = 0.5;
  scan.range_min = 0.1;
  scan.range_max = 4.0;
  scan.values = {1.0f, std::numeric_limits<float>::infinity(), std::numeric_limits<float>::quiet_NaN()};
  WriteFixtureBag(bag, {tf, o1, scan, o2});
  auto reader = OpenLog(bag);
  const auto robot = *reader->robot_hint();
  EXPECT_EQ(robot.name, "bag-laser");
  ASSERT_EQ(robot.sensors.size(), 3u);
  EXPECT_NEAR(robot.sensors[0].robot_from_sensor.x, 0.2, 1e-12);
  EXPECT_NEAR(robot.sensors[0].robot_from_sensor.theta, kPi / 2 - 0.5, 1e-7);
  EXPECT_NEAR(robot.sensors[2].robot_from_sensor.theta, kPi / 2 + 0.5, 1e-7);
  EXPECT_EQ(robot.sensors[1].max_range_m, 4.0);
  EXPECT_NEAR(robot.sensors[1].min_range_m, 0.1, 1e-7);
  const auto back = ReadAll(*reader);
  ASSERT_EQ(back.size(), 3u);
  EXPECT_EQ(back[0].time_s, 1.0);
  EXPECT_TRUE(back[0].ranges.empty());
  EXPECT_EQ(back[1].time_s, 1.5);
  EXPECT_DOUBLE_EQ(back[1].odom.x, 0.5);
  EXPECT_DOUBLE_EQ(back[1].odom.y, 1.0);
  EXPECT_NEAR(back[1].odom.theta, 0.25, 1e-15);
  ASSERT_EQ(back[1].ranges.size(), 2u);  // the NaN is no reading, +inf is no echo
  EXPECT_EQ(back[1].ranges[0].sensor, 0);
  EXPECT_EQ(back[1].ranges[0].range_m, 1.0);
  EXPECT_EQ(back[1].ranges[1].sensor, 1);
  EXPECT_EQ(back[1].ranges[1].range_m, 4.0);
  EXPECT_EQ(back[2].time_s, 2.0);
}

// Two sonars as Range topics, placed by tf_static; odometry from /tf.
TEST(Ros1Bag, RangeTopicsAreOneSonarEach) {
  const std::string bag = ::cogmap::testing_util::TestTempPath("ranges.bag");
  M tf0 = Make("/tf_static", 1000000000, M::kTf, "base_link", "sonar_front", 0.1, 0.0, 0.0);
  M tf1 = Make("/tf_static", 1000000000, M::kTf, "base_link", "sonar_left", 0.0, 0.1, kPi / 2);
  M odom = Make("/tf", 1000000000, M::kTf, "odom", "base_link", 3.0, 4.0, 0.0);
  M r0 = Make("/sonar_10", 1000000000, M::kRange, "sonar_left");
  r0.field_of_view = 0.4;
  r0.range_min = 0.2;
  r0.range_max = 3.0;
  r0.values = {2.5f};
  M r1 = r0;
  r1.topic = "/sonar_2";
  r1.frame = "sonar_front";
  r1.values = {7.0f};  // beyond max range: no echo
  WriteFixtureBag(bag, {tf0, tf1, odom, r0, r1});
  auto reader = OpenLog(bag);
  const auto robot = *reader->robot_hint();
  ASSERT_EQ(robot.sensors.size(), 2u);
  // Natural order: /sonar_2 before /sonar_10.
  EXPECT_NEAR(robot.sensors[0].robot_from_sensor.x, 0.1, 1e-12);
  EXPECT_NEAR(robot.sensors[1].robot_from_sensor.theta, kPi / 2, 1e-12);
  EXPECT_NEAR(robot.sensors[1].beam_width_rad, 0.4, 1e-7);
  const auto back = ReadAll(*reader);
  ASSERT_EQ(back.size(), 1u);  // both readings join the odometry stamped like them
  EXPECT_EQ(back[0].odom.x, 3.0);
  ASSERT_EQ(back[0].ranges.size(), 2u);
  auto ranges = back[0].ranges;  // rosbag orders messages of one stamp by connection
  std::sort(ranges.begin(), ranges.end(), [](const auto& a, const auto& b) { return a.sensor < b.sensor; });
  EXPECT_EQ(ranges[0].sensor, 0);
  EXPECT_EQ(ranges[0].range_m, 3.0);  // 7 m is beyond max range: no echo
  EXPECT_EQ(ranges[1].sensor, 1);
  EXPECT_EQ(ranges[1].range_m, 2.5);
}

// A PointCloud2 sonar sweep of the pioneer8 (given as the robot): each point
// goes back to the sonar on whose axis it lies.
TEST(Ros1Bag, PointCloud2PointsBecomeSonarRanges) {
  const auto robot = sensors::BuiltinRobot("pioneer8");
  const std::string bag = ::cogmap::testing_util::TestTempPath("cloud2.bag");
  M odom = Make("/pose", 1000000000, M::kOdometry, "odom", "base_link");
  M cloud = Make("/sonar_pointcloud2", 1000000000, M::kPointCloud2, "base_link");
  const int sensors_hit[3] = {5, 0, 7};
  const float ranges[3] = {1.25f, 5.0f, 0.5f};
  for (int k = 0; k < 3; ++k) {
    const Pose2& p = robot.sensors[sensors_hit[k]].robot_from_sensor;
    cloud.values.push_back(static_cast<float>(p.x + ranges[k] * std::cos(p.theta)));
    cloud.values.push_back(static_cast<float>(p.y + ranges[k] * std::sin(p.theta)));
    cloud.values.push_back(0.0f);
  }
  WriteFixtureBag(bag, {odom, cloud});
  LogOpenOptions o;
  o.robot = robot;
  auto reader = OpenLog(bag, o);
  EXPECT_EQ(reader->robot_hint()->name, "pioneer8");
  const auto back = ReadAll(*reader);
  ASSERT_EQ(back.size(), 1u);
  ASSERT_EQ(back[0].ranges.size(), 3u);
  for (int k = 0; k < 3; ++k) {
    EXPECT_EQ(back[0].ranges[k].sensor, sensors_hit[k]);
    EXPECT_NEAR(back[0].ranges[k].range_m, ranges[k], 1e-6);
  }
  EXPECT_EQ(back[0].ranges[1].range_m, 5.0);  // no echo snapped to max range exactly
}

TEST(Ros1Bag, TruncatedBagIsOneErrorNamingTheFile) {
  const auto run = SimulatedRun("pioneer16", 3.0);
  const std::string bag = WriteBag("truncated.bag", run, sensors::BuiltinRobot("pioneer16"));
  std::filesystem::resize_file(bag, std::filesystem::file_size(bag) / 2);
  EXPECT_THAT(ErrorReading(bag, "auto"), HasSubstr(bag + ": not a complete ROS 1 bag"));
}

// roscpp sizes a PointCloud's points from the count in the message and
// librosbag reads a message at whatever offset and length the bag states: a
// damaged count or length costs gigabytes or a crash inside them. The bag is
// read first in a child process with bounded memory (child_check.h): one
// error naming the file, at once.
TEST(Ros1Bag, DamagedPointCountIsOneErrorNotGigabytes) {
  const auto run = SimulatedRun("pioneer16", 3.0);
  const std::string bag = WriteBag("count.bag", run, sensors::BuiltinRobot("pioneer16"));
  std::string bytes;
  {
    std::ifstream in(bag, std::ios::binary);
    bytes.assign(std::istreambuf_iterator<char>(in), {});
  }
  // The sonar clouds: each header's frame_id "sonar", then the point count
  // (every length-prefixed "sonar" is taken: the clouds are among them).
  const std::string sonar("\x05\x00\x00\x00sonar", 9);
  int changed = 0;
  for (size_t at = bytes.find(sonar); at != std::string::npos; at = bytes.find(sonar, at + 1), ++changed)
    bytes.replace(at + 9, 4, "\xF0\xFF\xFF\xFF");
  ASSERT_GT(changed, 0);
  std::ofstream(bag, std::ios::binary) << bytes;
  EXPECT_THAT(ErrorReading(bag, "auto"),
              HasSubstr(bag + ": a damaged ROS 1 bag: librosbag asked for more memory than such a file can need"));
}

TEST(Ros1Bag, RequestedTopicOfAnotherTypeIsAnError) {
  const std::string bag = ::cogmap::testing_util::TestTempPath("string.bag");
  M odom = Make("/odom", 1000000000, M::kOdometry, "odom", "base_link");
  M chat = Make("/chatter", 1000000000, M::kString);
  WriteFixtureBag(bag, {odom, chat});
  LogOpenOptions o;
  o.topics = {"/odom", "/chatter"};
  try {
    OpenLog(bag, o);
    FAIL();
  } catch (const InputError& e) {
    EXPECT_THAT(e.what(), HasSubstr(bag + ": topic /chatter is a std_msgs/String, which cogmap does not read"));
  }
  // Without --topics the bag has odometry but no range data.
  EXPECT_THAT(ErrorReading(bag, "auto"), HasSubstr(bag + ": odometry but no range data"));
}

TEST(Ros1Bag, LaserFrameNotConnectedToTheBaseIsAnError) {
  const std::string bag = ::cogmap::testing_util::TestTempPath("frames.bag");
  M tf = Make("/tf_static", 1000000000, M::kTf, "base_footprint", "laser", 0.2, 0.0, 0.0);
  M odom = Make("/odom", 1000000000, M::kOdometry, "odom", "base_link");
  M scan = Make("/scan", 1000000000, M::kLaserScan, "laser");
  scan.angle_increment = 0.1;
  scan.range_max = 4.0;
  scan.values = {1.0f, 2.0f};
  WriteFixtureBag(bag, {tf, odom, scan});
  EXPECT_THAT(ErrorReading(bag, "auto"), HasSubstr(bag + ": /scan message 1: mismatched tf frames"));
}

TEST(Ros1Bag, ScanWithAnotherBeamCountIsAnErrorNamingTheMessage) {
  const std::string bag = ::cogmap::testing_util::TestTempPath("beams.bag");
  M odom = Make("/odom", 1000000000, M::kOdometry, "odom", "base_link");
  M scan = Make("/scan", 1000000000, M::kLaserScan, "base_link");
  scan.angle_increment = 0.1;
  scan.range_max = 4.0;
  scan.values = {1.0f, 2.0f};
  M scan2 = scan;
  scan2.time_ns = 1100000000;
  scan2.values = {1.0f};
  WriteFixtureBag(bag, {odom, scan, scan2});
  EXPECT_THAT(ErrorReading(bag, "auto"), HasSubstr(bag + ": /scan message 2: LaserScan has 1 ranges, the first had 2"));
}

TEST(Ros1Bag, AbsurdOrNonFiniteOdometryIsAnErrorNamingTheMessage) {
  // A pose of 1e300 m (or NaN) failed later, in the grid, without naming the bag.
  for (const double x : {1e300, std::nan("")}) {
    const std::string bag = ::cogmap::testing_util::TestTempPath("far.bag");
    M odom = Make("/odom", 1000000000, M::kOdometry, "odom", "base_link");
    M far = Make("/odom", 1100000000, M::kOdometry, "odom", "base_link", x, 0.0);
    M scan = Make("/scan", 1050000000, M::kLaserScan, "base_link");
    scan.angle_increment = 0.1;
    scan.range_max = 4.0;
    scan.values = {1.0f, 2.0f};
    WriteFixtureBag(bag, {odom, scan, far});
    const std::string error = ErrorReading(bag, "auto");
    EXPECT_THAT(error, HasSubstr(bag + ": /odom message 2: "));
    EXPECT_THAT(error, HasSubstr(std::isnan(x) ? "is not finite" : "absurd position (1e+300, 0) m"));
  }
}

}  // namespace
}  // namespace cogmap::io
