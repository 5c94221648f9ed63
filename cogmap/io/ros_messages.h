#pragma once
// The few ROS messages cogmap reads, decoded into plain structs, and a bag as
// a source of them (each bag format decodes its own bytes). Plain C++17 with
// no cogmap types: the ROS 1 code that includes it compiles as C++17 (the ROS
// 1 message headers use std::allocator<void>::rebind, gone in C++20).
#include <array>
#include <cstdint>
#include <memory>
#include <string>
#include <variant>
#include <vector>

namespace cogmap::io::ros {

struct Header {
  int64_t stamp_ns = 0;
  std::string frame_id;
};

struct LaserScan {
  Header header;
  double angle_min_rad = 0, angle_increment_rad = 0;
  double range_min_m = 0, range_max_m = 0;
  std::vector<float> ranges;
};

struct Range {
  Header header;
  int radiation_type = 0;  // 0 ultrasound, 1 infrared
  double field_of_view_rad = 0, min_range_m = 0, max_range_m = 0;
  double range_m = 0;
};

// sensor_msgs/PointCloud, or PointCloud2's x, y, z fields.
struct PointCloud {
  Header header;
  std::vector<std::array<double, 3>> points;
};

// A rigid transform (geometry_msgs/Transform or Pose).
struct Transform3 {
  double x = 0, y = 0, z = 0;
  double qx = 0, qy = 0, qz = 0, qw = 1;
};

struct Odometry {
  Header header;
  std::string child_frame_id;
  Transform3 pose;
};

struct TransformStamped {
  Header header;
  std::string child_frame_id;
  Transform3 transform;
};

struct TfMessage {
  std::vector<TransformStamped> transforms;
};

using Message = std::variant<std::monostate, LaserScan, Range, PointCloud, Odometry, TfMessage>;

enum class MessageType { kLaserScan, kRange, kPointCloud, kPointCloud2, kOdometry, kTf, kOther };

// The type of a ROS 1 ("sensor_msgs/LaserScan") or ROS 2
// ("sensor_msgs/msg/LaserScan") type name; kOther for the rest.
MessageType TypeOf(const std::string& type_name);
// The types cogmap reads, for messages.
std::string KnownTypesText();

// sensor_msgs/PointField datatypes and the x, y, z of a PointCloud2's data.
struct PointField {
  std::string name;
  uint32_t offset = 0;
  uint8_t datatype = 0;  // 7 FLOAT32, 8 FLOAT64
  uint32_t count = 1;
};
// The points of a PointCloud2 (x, y, z must be FLOAT32 or FLOAT64). Returns
// an error text ("" when fine).
std::string DecodePointCloud2(const std::vector<PointField>& fields, bool big_endian, uint32_t point_step,
                              uint32_t width, uint32_t height, const uint8_t* data, size_t size,
                              std::vector<std::array<double, 3>>* points);

struct TopicInfo {
  std::string name;
  std::string type;
  long count = 0;
};

struct BagMessage {
  int topic = -1;      // index into BagSource::topics()
  long index = 0;      // 1-based index of the message on its topic
  int64_t time_ns = 0; // the bag's receive time
  Message message;     // decoded for the known types, monostate for others
};

// A bag's messages, decoded, one pass at a time. Throws InputError naming the
// file (and the topic and message) for unreadable content.
class BagSource {
 public:
  virtual ~BagSource() = default;
  virtual const std::vector<TopicInfo>& topics() const = 0;
  // Starts a pass over the messages of these topics (indices into topics())
  // in the bag's time order.
  virtual void Start(const std::vector<int>& topics) = 0;
  virtual bool Next(BagMessage* message) = 0;
  // Fraction of the current pass done.
  virtual double progress() const = 0;
  virtual const std::string& path() const = 0;
  // "ROS 1 bag", "ROS 2 bag" (for messages).
  virtual std::string kind() const = 0;
};

// Yaw of a quaternion (rotation about z), and the quaternion of a yaw.
double YawOf(const Transform3& t);
Transform3 FromPose2(double x, double y, double yaw_rad);

// ROS 1 bags through rosbag_storage (ros1_bag_source.cc, in the module
// plugin_api.h loads). Opening throws InputError naming the file for a bag
// rosbag cannot open.
std::unique_ptr<BagSource> OpenRos1BagSource(const std::string& path);

// A bag being written, message by message (ROS 1 or ROS 2).
class BagWriter {
 public:
  virtual ~BagWriter() = default;
  virtual void Write(const std::string& topic, int64_t time_ns, const Message& message) = 0;
  // Finishes the bag (indexes, metadata); the writer is unusable after.
  virtual void Close() = 0;
};

// Writes a ROS 1 bag (ros1_bag_source.cc, in the module plugin_api.h
// loads): LaserScan, PointCloud (as sensor_msgs/PointCloud), Odometry and
// TfMessage (as tf2_msgs/TFMessage). The bag time of a message is its time_ns,
// at least 1 ns (rosbag refuses 0).
std::unique_ptr<BagWriter> MakeRos1BagWriter(const std::string& path);

}  // namespace cogmap::io::ros
