// ROS 1 bags through rosbag_storage: the BagSource and the writer of
// ros_messages.h. Compiled as C++17 (the ROS 1 message headers use
// std::allocator<void>::rebind): includes no cogmap header that needs C++20.
#include <console_bridge/console.h>
#include <rosbag/bag.h>
#include <rosbag/view.h>

#include <algorithm>
#include <map>

#include "cogmap/core/error.h"
#include "cogmap/io/plugin_api.h"
#include "cogmap/io/ros1_messages.h"
#include "cogmap/io/ros_messages.h"

namespace cogmap::io::ros {
namespace {

::ros::Time RosTime(int64_t ns) {
  return ::ros::Time(static_cast<uint32_t>(ns / 1000000000), static_cast<uint32_t>(ns % 1000000000));
}
std_msgs::Header RosHeader(const ros::Header& h) {
  std_msgs::Header r;
  r.stamp = RosTime(h.stamp_ns);
  r.frame_id = h.frame_id;
  return r;
}

geometry_msgs::Transform RosTransform(const ros::Transform3& t) {
  geometry_msgs::Transform r;
  r.translation.x = t.x;
  r.translation.y = t.y;
  r.translation.z = t.z;
  r.rotation.x = t.qx;
  r.rotation.y = t.qy;
  r.rotation.z = t.qz;
  r.rotation.w = t.qw;
  return r;
}

class Ros1Source : public ros::BagSource {
 public:
  explicit Ros1Source(const std::string& path) : path_(path) {
    try {
      bag_.open(path, rosbag::bagmode::Read);
      rosbag::View all(bag_);
      std::map<std::string, std::string> types;
      for (const rosbag::ConnectionInfo* c : all.getConnections()) {
        auto it = types.find(c->topic);
        if (it != types.end() && it->second != c->datatype)
          throw InputError(path_ + ": topic " + c->topic + " carries two types (" + it->second + ", " + c->datatype + ")");
        types[c->topic] = c->datatype;
      }
      for (const auto& [name, type] : types) {
        rosbag::View one(bag_, rosbag::TopicQuery(name));
        by_name_[name] = static_cast<int>(topics_.size());
        topics_.push_back({name, type, static_cast<long>(one.size())});
      }
    } catch (const rosbag::BagUnindexedException&) {
      throw InputError(path_ + ": not a complete ROS 1 bag: its index is missing (a truncated bag, or one whose "
                               "recording was cut: 'rosbag reindex' can rebuild it)");
    } catch (const ::ros::Exception& e) {
      throw InputError(path_ + ": not a complete ROS 1 bag, or a damaged one (rosbag: " + std::string(e.what()) + ")");
    }
  }

  const std::vector<ros::TopicInfo>& topics() const override { return topics_; }

  void Start(const std::vector<int>& topics) override {
    std::vector<std::string> names;
    for (int t : topics) names.push_back(topics_[t].name);
    index_.assign(topics_.size(), 0);
    it_.reset();
    view_ = std::make_unique<rosbag::View>(bag_, rosbag::TopicQuery(names));
    total_ = view_->size();
    done_ = 0;
    it_ = std::make_unique<rosbag::View::iterator>(view_->begin());
  }

  bool Next(ros::BagMessage* out) override {
    if (!it_ || *it_ == view_->end()) return false;
    int topic = -1;
    long index = 0;
    try {
      const rosbag::MessageInstance& m = **it_;
      topic = by_name_.at(m.getTopic());
      index = ++index_[topic];
      out->topic = topic;
      out->index = index;
      out->time_ns = Ros1Ns(m.getTime());
      out->message = Decode(m, topic, index);
      ++*it_;
    } catch (const InputError&) {
      throw;
    } catch (const ::ros::Exception& e) {
      throw InputError(path_ + ": " + (topic >= 0 ? topics_[topic].name + " message " + std::to_string(index)
                                                  : "message after " + std::to_string(done_)) +
                       ": cannot read (" + e.what() + ")");
    }
    ++done_;
    return true;
  }

  double progress() const override { return total_ ? static_cast<double>(done_) / total_ : 1.0; }
  const std::string& path() const override { return path_; }
  std::string kind() const override { return "ROS 1 bag"; }

 private:
  template <class T>
  boost::shared_ptr<T> Get(const rosbag::MessageInstance& m, int topic, long index) const {
    auto p = m.instantiate<T>();
    if (!p)
      throw InputError(path_ + ": " + topics_[topic].name + " message " + std::to_string(index) + ": its " +
                       m.getDataType() + " definition (md5 " + m.getMD5Sum() + ") is not the one cogmap reads (md5 " +
                       ::ros::message_traits::MD5Sum<T>::value() + ")");
    return p;
  }

  ros::Message Decode(const rosbag::MessageInstance& m, int topic, long index) const {
    switch (ros::TypeOf(m.getDataType())) {
      case ros::MessageType::kLaserScan: return FromRos1(*Get<sensor_msgs::LaserScan>(m, topic, index));
      case ros::MessageType::kRange: return FromRos1(*Get<sensor_msgs::Range>(m, topic, index));
      case ros::MessageType::kPointCloud: return FromRos1(*Get<sensor_msgs::PointCloud>(m, topic, index));
      case ros::MessageType::kPointCloud2: {
        std::string err;
        ros::PointCloud c = FromRos1(*Get<sensor_msgs::PointCloud2>(m, topic, index), &err);
        if (!err.empty())
          throw InputError(path_ + ": " + topics_[topic].name + " message " + std::to_string(index) + ": " + err);
        return c;
      }
      case ros::MessageType::kOdometry: return FromRos1(*Get<nav_msgs::Odometry>(m, topic, index));
      case ros::MessageType::kTf: return FromRos1(*Get<tf2_msgs::TFMessage>(m, topic, index));
      case ros::MessageType::kOther: break;
    }
    return std::monostate{};
  }

  std::string path_;
  rosbag::Bag bag_;
  std::vector<ros::TopicInfo> topics_;
  std::map<std::string, int> by_name_;
  std::unique_ptr<rosbag::View> view_;
  std::unique_ptr<rosbag::View::iterator> it_;
  std::vector<long> index_;
  uint32_t total_ = 0, done_ = 0;
};

// Writes a ROS 1 bag: LaserScan, PointCloud (as sensor_msgs/PointCloud),
// Odometry and TfMessage (as tf2_msgs/TFMessage). The bag time of a message
// is its time_ns, at least 1 ns (rosbag refuses 0).
class Ros1BagWriter : public BagWriter {
 public:
  explicit Ros1BagWriter(const std::string& path);
  void Write(const std::string& topic, int64_t time_ns, const Message& message) override;
  void Close() override;

 private:
  struct Impl {
    std::string path;
    rosbag::Bag bag;
  };
  std::unique_ptr<Impl> impl_;
};

Ros1BagWriter::Ros1BagWriter(const std::string& path) : impl_(std::make_unique<Impl>()) {
  impl_->path = path;
  try {
    impl_->bag.open(path, rosbag::bagmode::Write);
  } catch (const ::ros::Exception& e) {
    throw InputError(path + ": cannot write the bag (" + std::string(e.what()) + ")");
  }
}

void Ros1BagWriter::Write(const std::string& topic, int64_t time_ns, const Message& message) {
  const ::ros::Time when = std::max(RosTime(time_ns), ::ros::TIME_MIN);
  try {
    if (const auto* s = std::get_if<LaserScan>(&message)) {
      sensor_msgs::LaserScan r;
      r.header = RosHeader(s->header);
      r.angle_min = static_cast<float>(s->angle_min_rad);
      r.angle_increment = static_cast<float>(s->angle_increment_rad);
      r.angle_max = static_cast<float>(s->angle_min_rad + (s->ranges.size() - 1) * s->angle_increment_rad);
      r.range_min = static_cast<float>(s->range_min_m);
      r.range_max = static_cast<float>(s->range_max_m);
      r.ranges = s->ranges;
      impl_->bag.write(topic, when, r);
    } else if (const auto* c = std::get_if<PointCloud>(&message)) {
      sensor_msgs::PointCloud r;
      r.header = RosHeader(c->header);
      for (const auto& p : c->points) {
        geometry_msgs::Point32 q;
        q.x = static_cast<float>(p[0]);
        q.y = static_cast<float>(p[1]);
        q.z = static_cast<float>(p[2]);
        r.points.push_back(q);
      }
      impl_->bag.write(topic, when, r);
    } else if (const auto* o = std::get_if<Odometry>(&message)) {
      nav_msgs::Odometry r;
      r.header = RosHeader(o->header);
      r.child_frame_id = o->child_frame_id;
      const auto t = RosTransform(o->pose);
      r.pose.pose.position.x = t.translation.x;
      r.pose.pose.position.y = t.translation.y;
      r.pose.pose.position.z = t.translation.z;
      r.pose.pose.orientation = t.rotation;
      impl_->bag.write(topic, when, r);
    } else if (const auto* tf = std::get_if<TfMessage>(&message)) {
      tf2_msgs::TFMessage r;
      for (const auto& t : tf->transforms) {
        geometry_msgs::TransformStamped s;
        s.header = RosHeader(t.header);
        s.child_frame_id = t.child_frame_id;
        s.transform = RosTransform(t.transform);
        r.transforms.push_back(s);
      }
      impl_->bag.write(topic, when, r);
    } else {
      throw InputError(impl_->path + ": cannot write this message type to " + topic);
    }
  } catch (const ::ros::Exception& e) {
    throw InputError(impl_->path + ": cannot write " + topic + " (" + std::string(e.what()) + ")");
  }
}

void Ros1BagWriter::Close() {
  try {
    impl_->bag.close();
  } catch (const ::ros::Exception& e) {
    throw InputError(impl_->path + ": cannot write the bag (" + std::string(e.what()) + ")");
  }
}

// librosbag's own messages (console_bridge) would print lines of their own
// beside cogmap's one-line error: off.
void Quiet() { console_bridge::setLogLevel(console_bridge::CONSOLE_BRIDGE_LOG_NONE); }

std::unique_ptr<BagSource> OpenSource(const std::string& path) {
  Quiet();
  return std::make_unique<Ros1Source>(path);
}

std::unique_ptr<BagWriter> MakeWriter(const std::string& path) { return std::make_unique<Ros1BagWriter>(path); }

}  // namespace
}  // namespace cogmap::io::ros

extern "C" __attribute__((visibility("default"))) const cogmap::io::plugin::Ros1Table* cogmap_io_ros1_table() {
  static const cogmap::io::plugin::Ros1Table table{cogmap::io::plugin::kPluginAbi, COGMAP_VERSION,
                                                   &cogmap::io::ros::OpenSource, &cogmap::io::ros::MakeWriter};
  return &table;
}
