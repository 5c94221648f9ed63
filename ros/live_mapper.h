#pragma once
// The ROS node's mapping side (C++20, no ROS headers): messages as the bag
// readers decode them (cogmap/io/ros_messages.h) go in from the subscriber
// callbacks; a mapping thread turns them into records with the same reader as
// `cogmap map BAG` (so a live run maps exactly like the bag of it) and maps
// them through mapping::MappingPipeline into OUTPUT/map.sqlite, one ASR per
// transaction as it closes (a crash loses at most the open room).
// This header compiles as C++17 too: the node's ROS code includes it.
#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "cogmap/io/ros_messages.h"

namespace cogmap::rosnode {

struct LiveTopic {
  std::string name;  // "/RosAria/sonar"
  std::string type;  // ROS 1 type name: "sensor_msgs/PointCloud", "nav_msgs/Odometry", ...
};

struct LiveOptions {
  std::string output_dir;            // map.sqlite and, on request, every output
  std::string robot;                 // a built-in robot or robot JSON ("" = from the messages and tf_static)
  std::string mode = "default";      // or "paper"
  std::vector<LiveTopic> topics;     // every subscribed topic, tf_static included
  // Each message waits this long (wall time) after it arrives before the
  // reader sees it, so that messages of one moment on different topics, which
  // arrive over separate connections in any order, are put back in stamp order.
  double reorder_window_s = 0.5;
  std::string scan_match = "auto";  // a laser's scans correct the odometry first (`cogmap map --scan-match`)
  std::string distance_scale = "auto";  // the odometry's distance scale (`cogmap map --distance-scale`)
};

// What the node publishes, in the map frame (metres).
struct WallSegment {
  double x0, y0, x1, y1;
  int asr;
};
struct RoomMark {
  int asr, room;
  double x, y;  // label point (mean of the ASR's path as placed)
};
struct GraphEdge {
  double x0, y0, x1, y1;  // room label -> exit centre -> room label, as two halves
};
struct MapSnapshot {
  std::vector<WallSegment> walls;
  std::vector<RoomMark> rooms;
  std::vector<GraphEdge> graph;
  int asrs = 0;
};
// An occupancy grid as nav_msgs/OccupancyGrid wants it: row-major from the
// origin cell, 0 free, 100 occupied, -1 unknown.
struct GridSnapshot {
  double resolution_m = 0.1;
  double origin_x = 0, origin_y = 0, origin_yaw = 0;
  int width = 0, height = 0;
  std::vector<int8_t> data;
};

class LiveMapper {
 public:
  explicit LiveMapper(const LiveOptions& options);
  ~LiveMapper();
  LiveMapper(const LiveMapper&) = delete;
  LiveMapper& operator=(const LiveMapper&) = delete;

  // From the subscriber callbacks (any thread). 'topic' indexes options.topics.
  void Receive(int topic, int64_t receive_ns, io::ros::Message message);
  // Starts mapping as soon as every range and odometry topic has had a message
  // (the robot is built from them, as a bag reader does). 'on_asr' is called
  // from the mapping thread after each ASR closes.
  void Start(std::function<void()> on_asr);
  // Ends the input, waits for the mapping thread, places every ASR (the pose
  // graph's final solve) and writes every output into the output folder.
  // Returns a one-line summary; throws what mapping threw (an InputError
  // naming the topic and message for bad data).
  std::string Finish();
  // Writes the outputs of the map so far (ASRs closed until now, at their
  // current placements) without ending the run. Returns the files written.
  std::vector<std::string> WriteFloorPlan();

  MapSnapshot Snapshot() const;
  // The room being mapped (raw odometry frame), and the whole map: free where
  // a closed room's grid saw free space (its last snapshot, placed as the map
  // places that room), occupied on every wall, unknown elsewhere.
  GridSnapshot CurrentRoomGrid() const;
  GridSnapshot WholeMapGrid(double cell_m = 0.05) const;
  // A mapping error, once the thread has stopped on one ("" while fine).
  std::string error() const;
  bool finished() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace cogmap::rosnode
