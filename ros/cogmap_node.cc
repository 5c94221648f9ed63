// cogmap_node: maps live from ROS 1 topics (what RosAria-driven Pioneers
// publish) through cogmap's mapping API and publishes the map as it grows.
// docs/ros.md describes its parameters, topics and services.
//
// Compiled as C++17 (the ROS 1 message headers need it); the mapping itself
// is in live_mapper.cc.
#include <nav_msgs/OccupancyGrid.h>
#include <nav_msgs/Odometry.h>
#include <ros/ros.h>
#include <sensor_msgs/LaserScan.h>
#include <sensor_msgs/PointCloud.h>
#include <sensor_msgs/PointCloud2.h>
#include <sensor_msgs/Range.h>
#include <std_srvs/Trigger.h>
#include <tf2_msgs/TFMessage.h>
#include <visualization_msgs/MarkerArray.h>

#include <cmath>
#include <sstream>
#include <string>
#include <vector>

#include "cogmap/io/ros1_messages.h"
#include "ros/live_mapper.h"

namespace {

namespace cm = cogmap::io::ros;
using cogmap::rosnode::LiveMapper;

template <class M>
cm::Message Convert(const M& m) {
  return cm::FromRos1(m);
}
cm::Message Convert(const sensor_msgs::PointCloud2& p) {
  std::string err;
  cm::PointCloud c = cm::FromRos1(p, &err);
  if (!err.empty()) ROS_WARN_THROTTLE(10, "cogmap: PointCloud2 skipped: %s", err.c_str());
  return c;
}

// "name:type,name:type"
std::vector<cogmap::rosnode::LiveTopic> ParseTopics(const std::string& text) {
  std::vector<cogmap::rosnode::LiveTopic> out;
  std::stringstream in(text);
  std::string item;
  while (std::getline(in, item, ',')) {
    const auto colon = item.find(':');
    if (colon == std::string::npos) throw std::runtime_error("~topics: '" + item + "' is not NAME:TYPE");
    out.push_back({item.substr(0, colon), item.substr(colon + 1)});
  }
  return out;
}

nav_msgs::OccupancyGrid Grid(const cogmap::rosnode::GridSnapshot& g, const std::string& frame) {
  nav_msgs::OccupancyGrid m;
  m.header.stamp = ros::Time::now();
  m.header.frame_id = frame;
  m.info.resolution = static_cast<float>(g.resolution_m);
  m.info.width = g.width;
  m.info.height = g.height;
  m.info.origin.position.x = g.origin_x;
  m.info.origin.position.y = g.origin_y;
  m.info.origin.orientation.z = std::sin(0.5 * g.origin_yaw);
  m.info.origin.orientation.w = std::cos(0.5 * g.origin_yaw);
  m.data = g.data;
  return m;
}

visualization_msgs::Marker Marker(const std::string& frame, const std::string& ns, int id, int type) {
  visualization_msgs::Marker m;
  m.header.stamp = ros::Time::now();
  m.header.frame_id = frame;
  m.ns = ns;
  m.id = id;
  m.type = type;
  m.action = visualization_msgs::Marker::ADD;
  m.pose.orientation.w = 1.0;
  m.color.a = 1.0;
  return m;
}

class Node {
 public:
  Node(ros::NodeHandle& nh, ros::NodeHandle& pnh) {
    cogmap::rosnode::LiveOptions o;
    if (!pnh.getParam("output", o.output_dir)) throw std::runtime_error("~output: the output folder is required");
    pnh.param<std::string>("robot", o.robot, "");
    pnh.param<std::string>("mode", o.mode, "default");
    pnh.param<std::string>("frame", frame_, "odom");
    pnh.param<double>("reorder_window", o.reorder_window_s, 0.5);
    pnh.param<std::string>("scan_match", o.scan_match, "auto");
    pnh.param<std::string>("distance_scale", o.distance_scale, "auto");
    std::string topics;
    pnh.param<std::string>("topics", topics,
                           "/RosAria/sonar:sensor_msgs/PointCloud,/RosAria/pose:nav_msgs/Odometry,"
                           "/scan:sensor_msgs/LaserScan,/tf:tf2_msgs/TFMessage,/tf_static:tf2_msgs/TFMessage,"
                           "/base_pose_ground_truth:nav_msgs/Odometry");
    o.topics = ParseTopics(topics);
    mapper_ = std::make_unique<LiveMapper>(o);
    const uint32_t queue = 100000;  // a bag played fast must not drop messages
    for (size_t i = 0; i < o.topics.size(); ++i) {
      const int k = static_cast<int>(i);
      const std::string& name = o.topics[i].name;
      const cm::MessageType t = cm::TypeOf(o.topics[i].type);
      auto now = [] { return cm::Ros1Ns(ros::Time::now()); };
      switch (t) {
        case cm::MessageType::kLaserScan:
          subs_.push_back(nh.subscribe<sensor_msgs::LaserScan>(name, queue, [this, k, now](const auto& m) {
            mapper_->Receive(k, now(), Convert(*m));
          }));
          break;
        case cm::MessageType::kRange:
          subs_.push_back(nh.subscribe<sensor_msgs::Range>(name, queue, [this, k, now](const auto& m) {
            mapper_->Receive(k, now(), Convert(*m));
          }));
          break;
        case cm::MessageType::kPointCloud:
          subs_.push_back(nh.subscribe<sensor_msgs::PointCloud>(name, queue, [this, k, now](const auto& m) {
            mapper_->Receive(k, now(), Convert(*m));
          }));
          break;
        case cm::MessageType::kPointCloud2:
          subs_.push_back(nh.subscribe<sensor_msgs::PointCloud2>(name, queue, [this, k, now](const auto& m) {
            mapper_->Receive(k, now(), Convert(*m));
          }));
          break;
        case cm::MessageType::kOdometry:
          subs_.push_back(nh.subscribe<nav_msgs::Odometry>(name, queue, [this, k, now](const auto& m) {
            mapper_->Receive(k, now(), Convert(*m));
          }));
          break;
        case cm::MessageType::kTf:
          subs_.push_back(nh.subscribe<tf2_msgs::TFMessage>(name, queue, [this, k, now](const auto& m) {
            mapper_->Receive(k, now(), Convert(*m));
          }));
          break;
        default:
          throw std::runtime_error("~topics: " + name + ": cogmap reads no " + o.topics[i].type + " (it reads " +
                                   cm::KnownTypesText() + ")");
      }
    }
    // Latched: a viewer that starts later still gets the map.
    room_grid_pub_ = pnh.advertise<nav_msgs::OccupancyGrid>("current_room", 1, true);
    map_pub_ = pnh.advertise<nav_msgs::OccupancyGrid>("map", 1, true);
    walls_pub_ = pnh.advertise<visualization_msgs::MarkerArray>("walls", 1, true);
    rooms_pub_ = pnh.advertise<visualization_msgs::MarkerArray>("rooms", 1, true);
    graph_pub_ = pnh.advertise<visualization_msgs::MarkerArray>("room_graph", 1, true);
    finish_srv_ = pnh.advertiseService("finish", &Node::OnFinish, this);
    write_srv_ = pnh.advertiseService("write_floor_plan", &Node::OnWrite, this);
    mapper_->Start([this] { Publish(); });
    ROS_INFO("cogmap: mapping %zu topics into %s", o.topics.size(), o.output_dir.c_str());
  }

 private:
  void Publish() {
    const auto s = mapper_->Snapshot();
    visualization_msgs::MarkerArray walls, rooms, graph;
    auto w = Marker(frame_, "walls", 0, visualization_msgs::Marker::LINE_LIST);
    w.scale.x = 0.05;
    w.color.r = w.color.g = w.color.b = 0.1f;
    for (const auto& seg : s.walls) {
      geometry_msgs::Point a, b;
      a.x = seg.x0, a.y = seg.y0, b.x = seg.x1, b.y = seg.y1;
      w.points.push_back(a);
      w.points.push_back(b);
    }
    walls.markers.push_back(w);
    for (const auto& r : s.rooms) {
      auto t = Marker(frame_, "rooms", r.asr, visualization_msgs::Marker::TEXT_VIEW_FACING);
      t.pose.position.x = r.x;
      t.pose.position.y = r.y;
      t.scale.z = 0.4;
      t.color.r = 0.1f, t.color.g = 0.3f, t.color.b = 0.8f;
      t.text = "A" + std::to_string(r.asr) + (r.room != r.asr ? " (room " + std::to_string(r.room) + ")" : "");
      rooms.markers.push_back(t);
    }
    auto g = Marker(frame_, "room_graph", 0, visualization_msgs::Marker::LINE_LIST);
    g.scale.x = 0.03;
    g.color.r = 0.9f, g.color.g = 0.4f;
    for (const auto& e : s.graph) {
      geometry_msgs::Point a, b;
      a.x = e.x0, a.y = e.y0, b.x = e.x1, b.y = e.y1;
      g.points.push_back(a);
      g.points.push_back(b);
    }
    graph.markers.push_back(g);
    walls_pub_.publish(walls);
    rooms_pub_.publish(rooms);
    graph_pub_.publish(graph);
    map_pub_.publish(Grid(mapper_->WholeMapGrid(), frame_));
    const auto room = mapper_->CurrentRoomGrid();
    if (room.width > 0) room_grid_pub_.publish(Grid(room, frame_));
  }

  bool OnFinish(std_srvs::Trigger::Request&, std_srvs::Trigger::Response& res) {
    try {
      res.message = mapper_->Finish();
      res.success = true;
      Publish();
    } catch (const std::exception& e) {
      res.success = false;
      res.message = e.what();
    }
    return true;
  }

  bool OnWrite(std_srvs::Trigger::Request&, std_srvs::Trigger::Response& res) {
    try {
      std::string files;
      for (const auto& f : mapper_->WriteFloorPlan()) files += (files.empty() ? "" : " ") + f;
      res.success = true;
      res.message = files;
    } catch (const std::exception& e) {
      res.success = false;
      res.message = e.what();
    }
    return true;
  }

  std::string frame_;
  std::unique_ptr<LiveMapper> mapper_;
  std::vector<ros::Subscriber> subs_;
  ros::Publisher room_grid_pub_, map_pub_, walls_pub_, rooms_pub_, graph_pub_;
  ros::ServiceServer finish_srv_, write_srv_;
};

}  // namespace

int main(int argc, char** argv) {
  ros::init(argc, argv, "cogmap_node");
  ros::NodeHandle nh, pnh("~");
  try {
    Node node(nh, pnh);
    // Callbacks on two threads: the services wait for the mapping thread
    // while subscriptions keep flowing.
    ros::AsyncSpinner spinner(2);
    spinner.start();
    ros::waitForShutdown();
  } catch (const std::exception& e) {
    ROS_FATAL("cogmap: %s", e.what());
    return 2;
  }
  return 0;
}
