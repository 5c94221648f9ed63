// ROS 2 sqlite3 bags written here with SQLite and a CDR encoder, read back.
#include "cogmap/io/ros2_bag.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <sqlite3.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "cogmap/core/angles.h"
#include "cogmap/io/cdr.h"
#include "cogmap/io/log_test_util.h"
#include "cogmap/io/ros1_bag.h"
#include "cogmap/io/world_io.h"
#include "cogmap/sensors/robot.h"
#include "cogmap/sim/simulator.h"

namespace cogmap::io {
namespace {

using namespace testing_util;
using ::testing::HasSubstr;
namespace fs = std::filesystem;

// XCDR1 as rmw writes it: 4-byte encapsulation header, then each primitive
// aligned to its size relative to the end of the header.
class CdrWriter {
 public:
  explicit CdrWriter(bool big_endian = false) : big_(big_endian) {
    buf_ = {0, static_cast<char>(big_endian ? 0 : 1), 0, 0};
  }
  void U8(uint8_t v) { Put(&v, 1); }
  void U32(uint32_t v) { Put(&v, 4); }
  void I32(int32_t v) { Put(&v, 4); }
  void F32(float v) { Put(&v, 4); }
  void F64(double v) { Put(&v, 8); }
  void String(const std::string& s) {
    U32(static_cast<uint32_t>(s.size() + 1));
    buf_ += s;
    buf_.push_back('\0');
  }
  void Header(int64_t ns, const std::string& frame) {
    I32(static_cast<int32_t>(ns / 1000000000));
    U32(static_cast<uint32_t>(ns % 1000000000));
    String(frame);
  }
  void Pose(double x, double y, double yaw) {
    for (double v : {x, y, 0.0, 0.0, 0.0, std::sin(yaw / 2), std::cos(yaw / 2)}) F64(v);
  }
  const std::string& bytes() const { return buf_; }

 private:
  void Put(const void* v, size_t n) {
    while ((buf_.size() - 4) % n) buf_.push_back('\0');
    char b[8];
    std::memcpy(b, v, n);
    if (big_) std::reverse(b, b + n);
    buf_.append(b, n);
  }
  bool big_;
  std::string buf_;
};

std::string Odometry(int64_t ns, double x, double y, double yaw, bool big = false) {
  CdrWriter w(big);
  w.Header(ns, "odom");
  w.String("base_link");
  w.Pose(x, y, yaw);
  for (int i = 0; i < 36; ++i) w.F64(0);  // pose covariance
  for (int i = 0; i < 6 + 36; ++i) w.F64(0);  // twist and its covariance
  return w.bytes();
}

std::string Tf(int64_t ns, const std::string& parent, const std::string& child, double x, double y, double yaw) {
  CdrWriter w;
  w.U32(1);
  w.Header(ns, parent);
  w.String(child);
  w.Pose(x, y, yaw);
  return w.bytes();
}

std::string Scan(int64_t ns, const std::string& frame, float angle_min, float inc, float max_m,
                 const std::vector<float>& ranges) {
  CdrWriter w;
  w.Header(ns, frame);
  w.F32(angle_min);
  w.F32(angle_min + inc * (ranges.size() - 1));
  w.F32(inc);
  w.F32(0);
  w.F32(0.1f);
  w.F32(0.05f);
  w.F32(max_m);
  w.U32(static_cast<uint32_t>(ranges.size()));
  for (float r : ranges) w.F32(r);
  w.U32(0);  // intensities
  return w.bytes();
}

std::string Range(int64_t ns, const std::string& frame, float range) {
  CdrWriter w;
  w.Header(ns, frame);
  w.U8(0);  // ULTRASOUND
  w.F32(0.5f);
  w.F32(0.2f);
  w.F32(4.0f);
  w.F32(range);
  return w.bytes();
}

std::string Cloud(int64_t ns, const std::vector<std::array<float, 3>>& points) {
  CdrWriter w;
  w.Header(ns, "sonar");
  w.U32(static_cast<uint32_t>(points.size()));
  for (const auto& p : points)
    for (float v : p) w.F32(v);
  w.U32(0);  // channels
  return w.bytes();
}

struct Row {
  std::string topic;
  int64_t ns;
  std::string data;
};

// A rosbag2 sqlite3 bag folder: metadata.yaml and one .db3 with rosbag2's schema.
std::string WriteRos2Bag(const std::string& name, const std::vector<std::pair<std::string, std::string>>& topics,
                         const std::vector<Row>& rows, const std::string& storage = "sqlite3") {
  const fs::path dir = ::cogmap::testing_util::TestTempPath(name);
  fs::remove_all(dir);
  fs::create_directories(dir);
  const std::string db3 = name + "_0.db3";
  std::ofstream(dir / "metadata.yaml") << "rosbag2_bagfile_information:\n  version: 5\n  storage_identifier: "
                                       << storage << "\n  relative_file_paths:\n    - " << db3
                                       << "\n  duration:\n    nanoseconds: 0\n";
  sqlite3* db = nullptr;
  EXPECT_EQ(sqlite3_open((dir / db3).string().c_str(), &db), SQLITE_OK);
  auto exec = [&](const std::string& sql) { EXPECT_EQ(sqlite3_exec(db, sql.c_str(), nullptr, nullptr, nullptr), SQLITE_OK) << sql; };
  exec("CREATE TABLE topics(id INTEGER PRIMARY KEY, name TEXT NOT NULL, type TEXT NOT NULL, "
       "serialization_format TEXT NOT NULL, offered_qos_profiles TEXT NOT NULL)");
  exec("CREATE TABLE messages(id INTEGER PRIMARY KEY, topic_id INTEGER NOT NULL, timestamp INTEGER NOT NULL, "
       "data BLOB NOT NULL)");
  exec("CREATE INDEX timestamp_idx ON messages (timestamp ASC)");
  exec("BEGIN");
  for (size_t i = 0; i < topics.size(); ++i)
    exec("INSERT INTO topics VALUES (" + std::to_string(i + 1) + ", '" + topics[i].first + "', '" + topics[i].second +
         "', 'cdr', '')");
  sqlite3_stmt* st = nullptr;
  sqlite3_prepare_v2(db, "INSERT INTO messages (topic_id, timestamp, data) VALUES (?, ?, ?)", -1, &st, nullptr);
  for (const auto& r : rows) {
    int id = 0;
    for (size_t i = 0; i < topics.size(); ++i)
      if (topics[i].first == r.topic) id = static_cast<int>(i + 1);
    EXPECT_GT(id, 0) << r.topic;
    sqlite3_bind_int(st, 1, id);
    sqlite3_bind_int64(st, 2, r.ns);
    sqlite3_bind_blob(st, 3, r.data.data(), static_cast<int>(r.data.size()), SQLITE_TRANSIENT);
    EXPECT_EQ(sqlite3_step(st), SQLITE_DONE);
    sqlite3_reset(st);
  }
  sqlite3_finalize(st);
  exec("COMMIT");
  sqlite3_close(db);
  return dir.string();
}

const std::vector<std::pair<std::string, std::string>> kTopics = {
    {"/odom", "nav_msgs/msg/Odometry"},     {"/scan", "sensor_msgs/msg/LaserScan"},
    {"/tf_static", "tf2_msgs/msg/TFMessage"}, {"/sonar_front", "sensor_msgs/msg/Range"},
    {"/chatter", "std_msgs/msg/String"}};

// Odometry at 1 s and 3 s; a 2-beam scan at 2 s from a laser 0.1 m ahead of
// base_link; a Range at 3 s in base_link.
std::vector<Row> ExactRows() {
  return {{"/tf_static", 500000000, Tf(500000000, "base_link", "laser", 0.1, 0.0, 0.0)},
          {"/odom", 1000000000, Odometry(1000000000, 0.0, 0.0, 0.0)},
          {"/scan", 2000000000, Scan(2000000000, "laser", -0.25f, 0.5f, 6.0f, {1.5f, 0.75f})},
          {"/chatter", 2500000000, std::string("\0\1\0\0\3\0\0\0hi\0", 11)},
          {"/odom", 3000000000, Odometry(3000000000, 2.0, 0.0, kPi / 2)},
          {"/sonar_front", 3000000000, Range(3000000000, "base_link", 2.0f)}};
}

TEST(Ros2Bag, ReadsExactRecordsFromCdr) {
  const std::string bag = WriteRos2Bag("ros2_exact", kTopics, ExactRows());
  EXPECT_EQ(DetectLogFormat(bag), "ros2bag");
  auto reader = OpenLog(bag);
  const auto robot = *reader->robot_hint();
  // Natural order of the range topics: /scan, then /sonar_front.
  ASSERT_EQ(robot.sensors.size(), 3u);
  EXPECT_EQ(robot.sensors[0].robot_from_sensor.x, 0.1);
  EXPECT_EQ(robot.sensors[0].robot_from_sensor.theta, -0.25);
  EXPECT_EQ(robot.sensors[1].robot_from_sensor.theta, 0.25);
  EXPECT_EQ(robot.sensors[0].max_range_m, 6.0);
  EXPECT_EQ(robot.sensors[2].kind, sensors::SensorKind::kSonar);
  EXPECT_NEAR(robot.sensors[2].beam_width_rad, 0.5, 1e-7);
  EXPECT_NEAR(robot.sensors[2].max_range_m, 4.0, 1e-7);
  const auto back = ReadAll(*reader);
  ASSERT_EQ(back.size(), 3u);
  EXPECT_EQ(back[0].time_s, 1.0);
  EXPECT_TRUE(back[0].ranges.empty());
  EXPECT_EQ(back[1].time_s, 2.0);
  EXPECT_DOUBLE_EQ(back[1].odom.x, 1.0);
  EXPECT_DOUBLE_EQ(back[1].odom.theta, kPi / 4);
  ASSERT_EQ(back[1].ranges.size(), 2u);
  EXPECT_EQ(back[1].ranges[0].range_m, 1.5);
  EXPECT_EQ(back[1].ranges[1].range_m, 0.75);
  EXPECT_EQ(back[2].time_s, 3.0);
  EXPECT_DOUBLE_EQ(back[2].odom.x, 2.0);
  ASSERT_EQ(back[2].ranges.size(), 1u);
  EXPECT_EQ(back[2].ranges[0].sensor, 2);
  EXPECT_EQ(back[2].ranges[0].range_m, 2.0);
  bool chatter_unused = false;
  for (const auto& c : reader->contents()) chatter_unused |= c.name == "/chatter" && c.use.empty() && c.count == 1;
  EXPECT_TRUE(chatter_unused);
}

TEST(Ros2Bag, BigEndianCdrDecodesTheSame) {
  const std::string le = Odometry(1500000000, 1.25, -2.5, 0.75, false);
  const std::string be = Odometry(1500000000, 1.25, -2.5, 0.75, true);
  ASSERT_NE(le, be);
  for (const std::string& bytes : {le, be}) {
    const auto m = cdr::Decode(ros::MessageType::kOdometry, reinterpret_cast<const uint8_t*>(bytes.data()), bytes.size());
    const auto& o = std::get<ros::Odometry>(m);
    EXPECT_EQ(o.header.stamp_ns, 1500000000);
    EXPECT_EQ(o.header.frame_id, "odom");
    EXPECT_EQ(o.child_frame_id, "base_link");
    EXPECT_EQ(o.pose.x, 1.25);
    EXPECT_EQ(o.pose.y, -2.5);
    EXPECT_DOUBLE_EQ(ros::YawOf(o.pose), 0.75);
  }
}

TEST(Ros2Bag, ShortCdrIsAnErrorNamingTheMessage) {
  auto rows = ExactRows();
  rows[2].data.resize(rows[2].data.size() - 6);  // no intensities, the last range cut in half
  const std::string bag = WriteRos2Bag("ros2_short", kTopics, rows);
  EXPECT_THAT(ErrorReading(bag, "auto"), HasSubstr("ros2_short_0.db3: /scan message 1: bad CDR"));
}

TEST(Ros2Bag, WrongTypeTopicIsAnError) {
  const std::string bag = WriteRos2Bag("ros2_wrong", kTopics, ExactRows());
  LogOpenOptions o;
  o.topics = {"/odom", "/chatter"};
  try {
    OpenLog(bag, o);
    FAIL();
  } catch (const InputError& e) {
    EXPECT_THAT(e.what(), HasSubstr("topic /chatter is a std_msgs/msg/String, which cogmap does not read"));
  }
}

TEST(Ros2Bag, TruncatedDb3IsAnErrorNamingTheFile) {
  std::vector<Row> rows = ExactRows();
  for (int k = 0; k < 400; ++k) {
    const int64_t ns = 4000000000 + k * 10000000LL;
    rows.push_back({"/odom", ns, Odometry(ns, 2.0 + k * 0.01, 0.0, 0.0)});
  }
  const std::string bag = WriteRos2Bag("ros2_truncated", kTopics, rows);
  const std::string db3 = bag + "/ros2_truncated_0.db3";
  fs::resize_file(db3, fs::file_size(db3) / 2);
  EXPECT_THAT(ErrorReading(bag, "auto"), HasSubstr(db3 + ": "));
}

TEST(Ros2Bag, McapStorageIsAClearError) {
  const std::string bag = WriteRos2Bag("ros2_mcap", kTopics, ExactRows(), "mcap");
  EXPECT_THAT(ErrorReading(bag, "auto"), HasSubstr("MCAP storage: cogmap reads the sqlite3 storage only"));
  const std::string mcap = ::cogmap::testing_util::TestTempPath("run.mcap");
  std::ofstream(mcap) << "\x89MCAP0\r\n";
  EXPECT_THAT(ErrorReading(mcap, "auto"), HasSubstr("MCAP storage"));
}

// A simulated Pioneer run as RosAria would have it in ROS 2: odometry, the
// sonar readings as sensor_msgs/msg/PointCloud points, truth.
TEST(Ros2Bag, SimulatedSonarRunReadsBackAsTheSameRecords) {
  const FloorPlan plan = ReadAriaMap(std::string(COGMAP_SHARED_DIR) + "/worlds/nine_rooms.map").plan;
  const auto robot = sensors::BuiltinRobot("pioneer16");
  sim::SimulatorOptions o;
  o.seed = 9;
  o.max_time_s = 10.0;
  o.sonar_bank_size = 1;  // the whole ring in every record, as RosAria publishes it
  std::vector<sensors::LogRecord> run;
  sim::Simulate(plan, robot, o, [&](const sensors::LogRecord& r) { run.push_back(r); });
  std::vector<Row> rows;
  for (const auto& r : run) {
    const int64_t ns = std::llround(r.time_s * 1e9) + 1000000000;  // ROS 2 bags start after 0
    rows.push_back({"/odom", ns, Odometry(ns, r.odom.x, r.odom.y, r.odom.theta)});
    if (r.ranges.empty()) continue;
    std::vector<std::array<float, 3>> points;
    for (const auto& q : r.ranges) {
      const Pose2& p = robot.sensors[q.sensor].robot_from_sensor;
      points.push_back({static_cast<float>(p.x + q.range_m * std::cos(p.theta)),
                        static_cast<float>(p.y + q.range_m * std::sin(p.theta)), 0.0f});
    }
    rows.push_back({"/sonar", ns, Cloud(ns, points)});
  }
  const std::string bag =
      WriteRos2Bag("ros2_sim", {{"/odom", "nav_msgs/msg/Odometry"}, {"/sonar", "sensor_msgs/msg/PointCloud"}}, rows);
  auto reader = OpenLog(bag + "/metadata.yaml");
  EXPECT_EQ(reader->robot_hint()->name, "pioneer16");  // 16 points per full sweep
  const auto back = ReadAll(*reader);
  ASSERT_EQ(back.size(), run.size());
  for (size_t k = 0; k < run.size(); ++k) {
    ASSERT_NEAR(back[k].time_s, run[k].time_s + 1.0, 1e-9);
    ASSERT_EQ(back[k].odom.x, run[k].odom.x);
    ASSERT_NEAR(back[k].odom.theta, run[k].odom.theta, 1e-12);
    ASSERT_EQ(back[k].ranges.size(), run[k].ranges.size());
    for (size_t i = 0; i < run[k].ranges.size(); ++i) {
      ASSERT_EQ(back[k].ranges[i].sensor, run[k].ranges[i].sensor);
      ASSERT_NEAR(back[k].ranges[i].range_m, run[k].ranges[i].range_m, 2e-6);
    }
  }
}

// WriteRosAriaBag2 (convert --to ros2bag): a simulated run with sonar and a
// laser, written as a ROS 2 bag, reads back as the same records as the ROS 1
// bag of the same run (both encode the same messages); the bag decodes with
// the tests' own CDR reading above (topic types, metadata).
TEST(Ros2BagWriter, SameRecordsAsTheRos1BagOfTheRun) {
  const FloorPlan plan = ReadAriaMap(std::string(COGMAP_SHARED_DIR) + "/worlds/nine_rooms.map").plan;
  for (const char* name : {"pioneer16", "laser"}) {
    const auto robot = sensors::BuiltinRobot(name);
    sim::SimulatorOptions o;
    o.seed = 4;
    o.max_time_s = 8.0;
    std::vector<sensors::LogRecord> run;
    sim::Simulate(plan, robot, o, [&](const sensors::LogRecord& r) { run.push_back(r); });
    auto source = [&run](size_t* k) {
      return [&run, k](sensors::LogRecord* r) {
        if (*k == run.size()) return false;
        *r = run[(*k)++];
        return true;
      };
    };
    size_t k1 = 0, k2 = 0;
    const std::string ros1 = ::cogmap::testing_util::TestTempPath(std::string(name) + ".bag");
    const std::string ros2 = ::cogmap::testing_util::TestTempPath(std::string(name) + "_ros2");
    fs::remove_all(ros2);
    EXPECT_EQ(WriteRosAriaBag(ros1, robot, source(&k1)), static_cast<long>(run.size()));
    EXPECT_EQ(WriteRosAriaBag2(ros2, robot, source(&k2)), static_cast<long>(run.size()));
    EXPECT_TRUE(fs::exists(fs::path(ros2) / (std::string(name) + "_ros2_0.db3")));
    EXPECT_EQ(DetectLogFormat(ros2), "ros2bag");
    const auto a = ReadAll(ros1, "rosbag"), b = ReadAll(ros2, "ros2bag");
    ASSERT_EQ(a.size(), b.size()) << name;
    ASSERT_GT(a.size(), 50u);
    for (size_t k = 0; k < a.size(); ++k) {
      ASSERT_NEAR(a[k].time_s, b[k].time_s, 1.5e-9);  // ROS 1 bag times are at least 1 ns
      ASSERT_EQ(a[k].odom.x, b[k].odom.x);
      ASSERT_EQ(a[k].odom.theta, b[k].odom.theta);
      ASSERT_EQ(a[k].truth.has_value(), b[k].truth.has_value());
      ASSERT_EQ(a[k].ranges.size(), b[k].ranges.size());
      for (size_t i = 0; i < a[k].ranges.size(); ++i) {
        ASSERT_EQ(a[k].ranges[i].sensor, b[k].ranges[i].sensor);
        ASSERT_EQ(a[k].ranges[i].range_m, b[k].ranges[i].range_m);
      }
    }
    // The topics as rosbag2 lists them.
    const std::string yaml = FileBytes((fs::path(ros2) / "metadata.yaml").string());
    EXPECT_THAT(yaml, HasSubstr("storage_identifier: sqlite3"));
    EXPECT_THAT(yaml, HasSubstr("type: nav_msgs/msg/Odometry"));
    EXPECT_THAT(yaml, HasSubstr(std::string("type: ") + (robot.sensors[0].kind == sensors::SensorKind::kSonar
                                                            ? "sensor_msgs/msg/PointCloud"
                                                            : "sensor_msgs/msg/LaserScan")));
    // Written whole or not at all: an existing folder is refused untouched.
    size_t k3 = 0;
    EXPECT_THROW(WriteRosAriaBag2(ros2, robot, source(&k3)), InputError);
    EXPECT_EQ(ReadAll(ros2, "ros2bag").size(), b.size());
  }
}

}  // namespace
}  // namespace cogmap::io
