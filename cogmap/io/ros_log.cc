#include "cogmap/io/ros_log.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <deque>
#include <limits>
#include <map>
#include <optional>
#include <queue>

#include "cogmap/core/angles.h"
#include "cogmap/core/error.h"
#include "cogmap/io/log_lines.h"
#include "cogmap/sensors/robot.h"

namespace cogmap::io::ros {

bool NaturalLess(const std::string& a, const std::string& b) {
  size_t i = 0, j = 0;
  while (i < a.size() && j < b.size()) {
    if (std::isdigit(static_cast<unsigned char>(a[i])) && std::isdigit(static_cast<unsigned char>(b[j]))) {
      size_t ie = i, je = j;
      while (ie < a.size() && std::isdigit(static_cast<unsigned char>(a[ie]))) ++ie;
      while (je < b.size() && std::isdigit(static_cast<unsigned char>(b[je]))) ++je;
      std::string na = a.substr(i, ie - i), nb = b.substr(j, je - j);
      na.erase(0, std::min(na.find_first_not_of('0'), na.size()));
      nb.erase(0, std::min(nb.find_first_not_of('0'), nb.size()));
      if (na.size() != nb.size()) return na.size() < nb.size();
      if (na != nb) return na < nb;
      i = ie;
      j = je;
    } else {
      if (a[i] != b[j]) return a[i] < b[j];
      ++i;
      ++j;
    }
  }
  return a.size() - i < b.size() - j;
}

namespace {

constexpr double kMaxOdomGapS = 1.0;          // a reading this far outside the odometry has no pose
constexpr double kCloudAxisToleranceM = 0.02; // a sonar point this far off every sonar's axis is an error
constexpr double kNoEchoSnapM = 1e-4;         // a range within this of max range is max range (float32)
constexpr long kTfPrescanMessages = 5000;     // /tf messages read at opening for odom -> base and frames
constexpr int kCloudPrescanMessages = 100;    // clouds read at opening for the ring's size

enum class Role { kUnused, kLaser, kRangeSonar, kCloudSonar, kOdometry, kTruth, kTf, kTfStatic };

std::string Frame(const std::string& f) { return !f.empty() && f[0] == '/' ? f.substr(1) : f; }

bool IsOdomFrame(const std::string& f) {
  return f == "odom" || (f.size() > 5 && f.compare(f.size() - 5, 5, "/odom") == 0);
}

Pose2 Planar(const Transform3& t) { return {t.x, t.y, YawOf(t)}; }

int64_t StampNs(const Header& h, int64_t receive_ns) { return h.stamp_ns != 0 ? h.stamp_ns : receive_ns; }

struct Stream {
  Role role = Role::kUnused;
  std::string use;  // for log-info
  int first_sensor = 0, n_sensors = 0;
  std::string frame;
  Pose2 base_from_frame;
  sensors::RobotDescription ring;  // kCloudSonar: the robot whose sonars the points belong to
};

struct Edge {
  std::string parent;
  Pose2 pose;  // parent_from_child
  std::string where;
};

class PoseTrack {
 public:
  void Add(double t, const Pose2& p) {
    if (s_.empty() || t >= s_.back().t) {
      s_.push_back({t, p});
    } else {
      auto it = std::upper_bound(s_.begin(), s_.end(), t, [](double v, const Sample& s) { return v < s.t; });
      s_.insert(it, {t, p});
    }
    latest_ = std::max(latest_, t);
    any_ = true;
  }
  bool any() const { return any_; }
  double latest() const { return latest_; }
  std::optional<Pose2> At(double t) const {
    if (s_.empty()) return std::nullopt;
    if (t <= s_.front().t) {
      if (s_.front().t - t <= kMaxOdomGapS) return s_.front().p;
      return std::nullopt;
    }
    if (t >= s_.back().t) {
      if (t - s_.back().t <= kMaxOdomGapS) return s_.back().p;
      return std::nullopt;
    }
    auto hi = std::lower_bound(s_.begin(), s_.end(), t, [](const Sample& s, double v) { return s.t < v; });
    if (hi->t == t) return hi->p;
    auto lo = hi - 1;
    const double f = (t - lo->t) / (hi->t - lo->t);
    const Pose2 &a = lo->p, &b = hi->p;
    return Pose2{a.x + f * (b.x - a.x), a.y + f * (b.y - a.y), NormalizeAngle(a.theta + f * NormalizeAngle(b.theta - a.theta))};
  }
  // Forgets samples no longer needed for stamps at or after 't'.
  void TrimBefore(double t) {
    while (s_.size() > 2 && s_[1].t <= t) s_.pop_front();
  }

 private:
  struct Sample {
    double t;
    Pose2 p;
  };
  std::deque<Sample> s_;
  double latest_ = -std::numeric_limits<double>::infinity();
  bool any_ = false;
};

struct Item {
  double t = 0;
  int order = 0;  // 0: an odometry record, 1: readings
  long seq = 0;
  sensors::LogRecord record;
};
struct ItemAfter {
  bool operator()(const Item& a, const Item& b) const {
    if (a.t != b.t) return a.t > b.t;
    if (a.order != b.order) return a.order > b.order;
    return a.seq > b.seq;
  }
};

bool Near(double a, double b, double tol) { return std::abs(a - b) <= tol; }

// Same sensors, within 'tol' (0: bit for bit).
bool SameSensors(const std::vector<sensors::RangeSensor>& a, const std::vector<sensors::RangeSensor>& b, double tol) {
  if (a.size() != b.size()) return false;
  for (size_t i = 0; i < a.size(); ++i) {
    const auto &p = a[i], &q = b[i];
    if (!Near(p.robot_from_sensor.x, q.robot_from_sensor.x, tol) ||
        !Near(p.robot_from_sensor.y, q.robot_from_sensor.y, tol) ||
        !Near(NormalizeAngle(p.robot_from_sensor.theta - q.robot_from_sensor.theta), 0.0, tol) ||
        !Near(p.beam_width_rad, q.beam_width_rad, tol) || !Near(p.min_range_m, q.min_range_m, tol) ||
        !Near(p.max_range_m, q.max_range_m, tol) || p.kind != q.kind)
      return false;
  }
  return true;
}

// Sensor geometry read back from a bag (float32 ranges and angles, poses
// through quaternions) matches a built-in robot within this.
constexpr double kBuiltinMatchTolerance = 1e-6;

class BagReader : public LogReader {
 public:
  BagReader(std::unique_ptr<BagSource> source, const LogOpenOptions& options)
      : src_(std::move(source)), options_(options) {
    const auto& topics = src_->topics();
    streams_.resize(topics.size());
    ChooseTopics();
    ReadStaticFrames();
    FindOdometry();
    BuildRobot();
    std::vector<int> pass;
    for (size_t i = 0; i < streams_.size(); ++i) {
      const Role r = streams_[i].role;
      if (r == Role::kLaser || r == Role::kRangeSonar || r == Role::kCloudSonar || r == Role::kOdometry ||
          r == Role::kTruth || (r == Role::kTf && odom_from_tf_))
        pass.push_back(static_cast<int>(i));
    }
    src_->Start(pass);
  }

  bool Next(sensors::LogRecord* out) override {
    while (true) {
      if (PopReady(out)) return true;
      if (done_) {
        if (readings_ == 0)
          throw InputError(src_->path() + ": no range readings with a pose: " + std::to_string(odometry_) +
                           " odometry messages; " + SkippedText());
        return false;
      }
      BagMessage m;
      if (!src_->Next(&m)) {
        done_ = true;
        continue;
      }
      Handle(m);
    }
  }

  std::optional<sensors::RobotDescription> robot_hint() const override { return robot_; }
  std::map<std::string, long> skipped() const override { return skipped_; }
  double progress() const override { return src_->progress(); }
  const std::string& path() const override { return src_->path(); }
  std::vector<LogContent> contents() const override {
    std::vector<LogContent> out;
    const auto& topics = src_->topics();
    for (size_t i = 0; i < topics.size(); ++i)
      out.push_back({topics[i].name, topics[i].type, topics[i].count, streams_[i].use});
    return out;
  }

 private:
  [[noreturn]] void Fail(int topic, long index, const std::string& problem) const {
    throw InputError(src_->path() + ": " + src_->topics()[topic].name + " message " + std::to_string(index) + ": " +
                     problem);
  }
  // 'pose' of message 'index' unless it is not finite or absurdly far (PoseProblem).
  Pose2 Checked(int topic, long index, const Pose2& pose) const {
    if (const std::string problem = PoseProblem(pose); !problem.empty()) Fail(topic, index, problem);
    return pose;
  }
  [[noreturn]] void FailFile(const std::string& problem) const {
    throw InputError(src_->path() + ": " + problem);
  }
  std::string TopicList(bool types) const {
    std::string s;
    for (const auto& t : src_->topics()) s += (s.empty() ? "" : ", ") + t.name + (types ? " (" + t.type + ")" : "");
    return s.empty() ? "none" : s;
  }
  std::string SkippedText() const {
    std::string s;
    for (const auto& [what, n] : skipped_) s += (s.empty() ? "" : "; ") + std::string("skipped ") + std::to_string(n) + " " + what;
    return s.empty() ? "nothing skipped" : s;
  }

  // Roles by type (or as chosen with --topics).
  void ChooseTopics() {
    const auto& topics = src_->topics();
    std::vector<bool> chosen(topics.size(), options_.topics.empty());
    for (const auto& want : options_.topics) {
      int found = -1;
      for (size_t i = 0; i < topics.size(); ++i)
        if (topics[i].name == want || Frame(topics[i].name) == Frame(want)) found = static_cast<int>(i);
      if (found < 0) FailFile("no topic '" + want + "' (topics: " + TopicList(false) + ")");
      if (TypeOf(topics[found].type) == MessageType::kOther)
        FailFile("topic " + want + " is a " + topics[found].type + ", which cogmap does not read (it reads " +
                 KnownTypesText() + ")");
      chosen[found] = true;
    }
    bool any_cloud = false;
    for (size_t i = 0; i < topics.size(); ++i)
      any_cloud |= chosen[i] && TypeOf(topics[i].type) == MessageType::kPointCloud;
    std::vector<int> odometry;
    for (size_t i = 0; i < topics.size(); ++i) {
      Stream& s = streams_[i];
      const MessageType type = TypeOf(topics[i].type);
      // tf is read for frames whatever --topics says.
      if (type == MessageType::kTf) {
        const bool is_static = Frame(topics[i].name).find("tf_static") != std::string::npos;
        s.role = is_static ? Role::kTfStatic : Role::kTf;
        if (is_static) {
          if (tf_static_ >= 0) FailFile("two tf_static topics: " + topics[tf_static_].name + ", " + topics[i].name);
          tf_static_ = static_cast<int>(i);
          s.use = "sensor frames";
        } else {
          if (tf_ >= 0) FailFile("two tf topics: " + topics[tf_].name + ", " + topics[i].name);
          tf_ = static_cast<int>(i);
        }
        continue;
      }
      if (!chosen[i]) continue;
      if (topics[i].count == 0) {
        s.use = "no messages";
        continue;
      }
      switch (type) {
        case MessageType::kLaserScan: s.role = Role::kLaser; break;
        case MessageType::kRange: s.role = Role::kRangeSonar; break;
        case MessageType::kPointCloud: s.role = Role::kCloudSonar; break;
        case MessageType::kPointCloud2:
          if (any_cloud) s.use = "";  // RosAria publishes the same sweep as PointCloud too
          else s.role = Role::kCloudSonar;
          break;
        case MessageType::kOdometry: {
          const std::string n = topics[i].name;
          if (n.find("ground_truth") != std::string::npos || n.find("truth") != std::string::npos) {
            if (truth_ < 0) {
              truth_ = static_cast<int>(i);
              s.role = Role::kTruth;
              s.use = "ground truth";
            }
          } else {
            odometry.push_back(static_cast<int>(i));
          }
          break;
        }
        default: break;
      }
    }
    if (odometry.size() > 1) {
      std::string names;
      for (int i : odometry) names += (names.empty() ? "" : ", ") + topics[i].name;
      FailFile("several nav_msgs/Odometry topics (" + names + "): choose one with --topics");
    }
    if (odometry.size() == 1) {
      odometry_topic_ = odometry[0];
      streams_[odometry_topic_].role = Role::kOdometry;
      streams_[odometry_topic_].use = "odometry";
    }
    bool any_range = false;
    for (const Stream& s : streams_)
      any_range |= s.role == Role::kLaser || s.role == Role::kRangeSonar || s.role == Role::kCloudSonar;
    if (!any_range)
      FailFile(std::string(odometry_topic_ >= 0 ? "odometry but no range data" : "no range data") +
               ": no LaserScan, Range, PointCloud or PointCloud2 topic with messages" +
               (options_.topics.empty() ? "" : " among the chosen") + " (topics: " + TopicList(true) + ")");
  }

  void AddEdge(std::map<std::string, Edge>* edges, const TransformStamped& t, const std::string& where, bool check) {
    const std::string child = Frame(t.child_frame_id), parent = Frame(t.header.frame_id);
    if (child.empty() || parent.empty()) return;
    auto it = edges->find(child);
    if (it == edges->end()) {
      (*edges)[child] = {parent, Planar(t.transform), where};
    } else if (check && it->second.parent != parent) {
      FailFile(where + ": mismatched tf frames: frame '" + child + "' has parent '" + parent + "' here and '" +
               it->second.parent + "' in " + it->second.where);
    }
  }

  void ReadStaticFrames() {
    if (tf_static_ < 0) return;
    src_->Start({tf_static_});
    BagMessage m;
    while (src_->Next(&m)) {
      const auto* tf = std::get_if<TfMessage>(&m.message);
      if (!tf) Fail(m.topic, m.index, "not a TFMessage");
      const std::string where = src_->topics()[m.topic].name + " message " + std::to_string(m.index);
      for (const auto& t : tf->transforms) AddEdge(&static_, t, where, true);
    }
  }

  // Base frame, and where odometry comes from; the frames that /tf places.
  void FindOdometry() {
    if (odometry_topic_ >= 0) {
      src_->Start({odometry_topic_});
      BagMessage m;
      if (!src_->Next(&m)) FailFile(src_->topics()[odometry_topic_].name + " has no messages");
      const auto& o = std::get<Odometry>(m.message);
      base_ = Frame(o.child_frame_id).empty() ? "base_link" : Frame(o.child_frame_id);
      odom_frame_ = Frame(o.header.frame_id);
    }
    if (tf_ >= 0) {
      src_->Start({tf_});
      BagMessage m;
      long n = 0;
      while (n++ < kTfPrescanMessages && src_->Next(&m)) {
        const auto* tf = std::get_if<TfMessage>(&m.message);
        if (!tf) Fail(m.topic, m.index, "not a TFMessage");
        for (const auto& t : tf->transforms) {
          const std::string parent = Frame(t.header.frame_id), child = Frame(t.child_frame_id);
          if (odometry_topic_ < 0 && base_.empty() && IsOdomFrame(parent)) {
            base_ = child;
            odom_frame_ = parent;
          }
          if (IsOdomFrame(parent) || IsOdomFrame(child) || child == base_) continue;
          AddEdge(&dynamic_, t, src_->topics()[m.topic].name + " message " + std::to_string(m.index), false);
        }
      }
    }
    if (odometry_topic_ < 0) {
      if (base_.empty())
        FailFile("no odometry: no nav_msgs/Odometry topic" + std::string(options_.topics.empty() ? "" : " chosen") +
                 " and no odom -> base transform in " + (tf_ >= 0 ? src_->topics()[tf_].name : std::string("/tf (none)")));
      odom_from_tf_ = true;
      streams_[tf_].use = "odometry (" + odom_frame_ + " -> " + base_ + ")";
    } else if (tf_ >= 0) {
      streams_[tf_].use = "sensor frames not in tf_static";
    }
  }

  // Root frame and root_from_frame, through tf_static edges, then /tf ones.
  std::optional<std::pair<std::string, Pose2>> Root(const std::string& frame) const {
    std::string f = frame;
    Pose2 root_from_frame;
    bool known = false;
    for (int depth = 0; depth < 64; ++depth) {
      const Edge* e = nullptr;
      if (auto it = static_.find(f); it != static_.end()) e = &it->second;
      else if (auto jt = dynamic_.find(f); jt != dynamic_.end()) e = &jt->second;
      if (!e) break;
      known = true;
      root_from_frame = e->pose * root_from_frame;
      f = e->parent;
    }
    if (!known && frame != base_) return std::nullopt;
    return std::make_pair(f, root_from_frame);
  }

  // base_from_frame when tf connects them; nullopt when tf does not know the
  // frame; InputError when it knows both but they are not connected.
  std::optional<Pose2> BaseFrom(const std::string& frame, int topic, long index) const {
    if (frame.empty() || frame == base_) return Pose2{};
    const auto f = Root(frame);
    if (!f) return std::nullopt;
    const auto b = Root(base_);
    if (b->first != f->first)
      Fail(topic, index, "mismatched tf frames: frame '" + frame + "' hangs from '" + f->first + "', base frame '" +
                             base_ + "' from '" + b->first + "' (no tf path between them)");
    return b->second.inverse() * f->second;
  }

  // A built-in Pioneer whose sonar count is n, for sonars tf does not place.
  std::optional<sensors::RobotDescription> RobotFor(size_t n) const {
    if (options_.robot) return options_.robot;  // Range topics: its sensor k is the k-th topic's
    if (n == 16) return sensors::BuiltinRobot("pioneer16");
    if (n == 8) return sensors::BuiltinRobot("pioneer8");
    return std::nullopt;
  }

  void BuildRobot() {
    const auto& topics = src_->topics();
    std::vector<int> order;
    for (size_t i = 0; i < streams_.size(); ++i) {
      const Role r = streams_[i].role;
      if (r == Role::kLaser || r == Role::kRangeSonar || r == Role::kCloudSonar) order.push_back(static_cast<int>(i));
    }
    std::stable_sort(order.begin(), order.end(),
                     [&](int a, int b) { return NaturalLess(topics[a].name, topics[b].name); });
    int n_range_topics = 0;
    for (int i : order) n_range_topics += streams_[i].role == Role::kRangeSonar;
    bool lasers = false, sonars = false;
    int range_k = 0;
    for (int i : order) {
      Stream& s = streams_[i];
      src_->Start({i});
      BagMessage m;
      if (!src_->Next(&m)) FailFile(topics[i].name + " has no messages");
      s.first_sensor = static_cast<int>(robot_.sensors.size());
      if (s.role == Role::kLaser) {
        const auto& scan = std::get<LaserScan>(m.message);
        s.frame = Frame(scan.header.frame_id);
        const size_t n = scan.ranges.size();
        if (n == 0) Fail(i, m.index, "LaserScan without ranges");
        if (!(scan.range_max_m > 0)) Fail(i, m.index, "LaserScan range_max is not positive");
        auto pose = BaseFrom(s.frame, i, m.index);
        std::string where = pose ? "tf" : "at the base: tf does not place frame '" + s.frame + "'";
        for (size_t b = 0; b < n; ++b) {
          sensors::RangeSensor r;
          r.robot_from_sensor = pose.value_or(Pose2{}) * Pose2{0, 0, scan.angle_min_rad + b * scan.angle_increment_rad};
          r.beam_width_rad = n == 1 ? DegToRad(0.5) : std::abs(scan.angle_increment_rad);
          r.min_range_m = scan.range_min_m;
          r.max_range_m = scan.range_max_m;
          r.kind = sensors::SensorKind::kLaser;
          robot_.sensors.push_back(r);
        }
        if (!pose && options_.robot && options_.robot->sensors.size() >= s.first_sensor + n) {
          for (size_t b = 0; b < n; ++b)
            robot_.sensors[s.first_sensor + b] = options_.robot->sensors[s.first_sensor + b];
          where = "the robot description";
        }
        s.n_sensors = static_cast<int>(n);
        s.use = "laser, " + std::to_string(n) + " beams (sensors " + std::to_string(s.first_sensor) + "-" +
                std::to_string(s.first_sensor + n - 1) + "), pose from " + where;
        lasers = true;
      } else if (s.role == Role::kRangeSonar) {
        const auto& r = std::get<Range>(m.message);
        s.frame = Frame(r.header.frame_id);
        if (!(r.max_range_m > 0)) Fail(i, m.index, "Range max_range is not positive");
        auto pose = BaseFrom(s.frame, i, m.index);
        sensors::RangeSensor q;
        std::string where = "tf";
        if (pose) {
          q.robot_from_sensor = *pose;
        } else {
          const auto robot = RobotFor(n_range_topics);
          if (!robot || static_cast<int>(robot->sensors.size()) <= range_k)
            Fail(i, m.index, "tf does not place frame '" + s.frame + "' and no robot description says where sonar " +
                                 std::to_string(range_k) + " is (give --robot)");
          q.robot_from_sensor = robot->sensors[range_k].robot_from_sensor;
          where = robot->name + " sensor " + std::to_string(range_k);
        }
        q.beam_width_rad = r.field_of_view_rad > 0 ? r.field_of_view_rad : q.beam_width_rad;
        q.min_range_m = r.min_range_m;
        q.max_range_m = r.max_range_m;
        q.kind = sensors::SensorKind::kSonar;
        robot_.sensors.push_back(q);
        s.n_sensors = 1;
        s.use = std::string(r.radiation_type == 1 ? "infrared" : "sonar") + " (sensor " +
                std::to_string(s.first_sensor) + "), pose from " + where;
        ++range_k;
        sonars = true;
      } else {
        const auto& c = std::get<PointCloud>(m.message);
        s.frame = Frame(c.header.frame_id);
        auto pose = BaseFrom(s.frame, i, m.index);
        s.base_from_frame = pose.value_or(Pose2{});
        size_t max_points = c.points.size();
        for (int k = 0; k < kCloudPrescanMessages && src_->Next(&m); ++k)
          max_points = std::max(max_points, std::get<PointCloud>(m.message).points.size());
        std::string from;
        if (options_.robot) {
          s.ring.name = options_.robot->name;
          for (const auto& q : options_.robot->sensors)
            if (q.kind == sensors::SensorKind::kSonar) s.ring.sensors.push_back(q);
          from = "robot " + options_.robot->name;
        } else if (auto ring = TransducerFrames(s.frame, i, m.index)) {
          s.ring = *ring;
          from = "tf frames " + s.frame + "_0.." + std::to_string(ring->sensors.size() - 1);
        } else if (auto robot = RobotFor(max_points)) {
          s.ring = *robot;
          from = "robot " + robot->name + " (by its " + std::to_string(max_points) + " points)";
        } else {
          Fail(i, m.index, "a sonar point cloud of up to " + std::to_string(max_points) +
                               " points and no tf frames " + s.frame + "_0..: give --robot (the robot whose sonars these are)");
        }
        if (s.ring.sensors.empty()) FailFile("robot '" + s.ring.name + "' has no sonars for " + topics[i].name);
        for (const auto& q : s.ring.sensors) robot_.sensors.push_back(q);
        s.n_sensors = static_cast<int>(s.ring.sensors.size());
        s.use = "sonar ring (sensors " + std::to_string(s.first_sensor) + "-" +
                std::to_string(s.first_sensor + s.n_sensors - 1) + ") from " + from + "; cloud frame " +
                (pose ? "placed by tf" : "'" + s.frame + "' taken as the base (not in tf)");
        sonars = true;
      }
    }
    robot_.name = lasers && sonars ? "bag-laser-sonar" : lasers ? "bag-laser" : "bag-sonar";
    if (options_.robot && SameSensors(options_.robot->sensors, robot_.sensors, kBuiltinMatchTolerance)) {
      robot_ = *options_.robot;
      return;
    }
    if (auto named = MatchingBuiltinRobot(robot_, kBuiltinMatchTolerance)) robot_ = *named;
  }

  // The transducers of a sonar cloud in frame F as tf frames F_0, F_1, ...
  // (what `cogmap convert --to rosbag` writes), with the Pioneer's cone and
  // ranges.
  std::optional<sensors::RobotDescription> TransducerFrames(const std::string& frame, int topic, long index) const {
    sensors::RobotDescription ring;
    ring.name = "tf";
    const sensors::RangeSensor pioneer = sensors::BuiltinRobot("pioneer16").sensors.at(0);
    for (int k = 0;; ++k) {
      const std::string f = frame + "_" + std::to_string(k);
      if (!static_.count(f) && !dynamic_.count(f)) break;
      sensors::RangeSensor q = pioneer;
      q.robot_from_sensor = *BaseFrom(f, topic, index);
      ring.sensors.push_back(q);
    }
    if (ring.sensors.empty()) return std::nullopt;
    return ring;
  }

  void Push(double t, int order, sensors::LogRecord&& r) {
    r.time_s = t;
    heap_.push({t, order, seq_++, std::move(r)});
  }

  double RangeOf(double r, double min_m, double max_m) const {
    if (std::isinf(r)) return r > 0 ? max_m : min_m;
    if (r >= max_m - kNoEchoSnapM) return max_m;
    return std::max(r, 0.0);
  }

  void CheckFrame(const Stream& s, const Header& h, int topic, long index) const {
    if (Frame(h.frame_id) != s.frame)
      Fail(topic, index, "mismatched frames: frame '" + Frame(h.frame_id) + "', the first message had '" + s.frame + "'");
  }

  void Handle(const BagMessage& m) {
    const Stream& s = streams_[m.topic];
    switch (s.role) {
      case Role::kOdometry: {
        const auto& o = std::get<Odometry>(m.message);
        const std::string child = Frame(o.child_frame_id).empty() ? "base_link" : Frame(o.child_frame_id);
        if (child != base_)
          Fail(m.topic, m.index, "mismatched frames: child frame '" + child + "', earlier '" + base_ + "'");
        const double t = StampNs(o.header, m.time_ns) * 1e-9;
        odom_.Add(t, Checked(m.topic, m.index, Planar(o.pose)));
        sensors::LogRecord r;
        Push(t, 0, std::move(r));
        ++odometry_;
        break;
      }
      case Role::kTruth: {
        const auto& o = std::get<Odometry>(m.message);
        truth_track_.Add(StampNs(o.header, m.time_ns) * 1e-9, Planar(o.pose));
        break;
      }
      case Role::kTf: {
        const auto& tf = std::get<TfMessage>(m.message);
        for (const auto& x : tf.transforms) {
          if (Frame(x.child_frame_id) != base_) continue;
          if (Frame(x.header.frame_id) != odom_frame_)
            Fail(m.topic, m.index, "mismatched tf frames: '" + base_ + "' has parent '" + Frame(x.header.frame_id) +
                                       "', earlier '" + odom_frame_ + "'");
          const double t = StampNs(x.header, m.time_ns) * 1e-9;
          odom_.Add(t, Checked(m.topic, m.index, Planar(x.transform)));
          sensors::LogRecord r;
          Push(t, 0, std::move(r));
          ++odometry_;
        }
        break;
      }
      case Role::kLaser: {
        const auto& scan = std::get<LaserScan>(m.message);
        if (static_cast<int>(scan.ranges.size()) != s.n_sensors)
          Fail(m.topic, m.index, "LaserScan has " + std::to_string(scan.ranges.size()) + " ranges, the first had " +
                                     std::to_string(s.n_sensors));
        CheckFrame(s, scan.header, m.topic, m.index);
        sensors::LogRecord r;
        for (int b = 0; b < s.n_sensors; ++b) {
          const double v = scan.ranges[b];
          if (std::isnan(v)) continue;
          const auto& q = robot_.sensors[s.first_sensor + b];
          r.ranges.push_back({s.first_sensor + b, RangeOf(v, q.min_range_m, q.max_range_m)});
        }
        AddReadings(m, scan.header, std::move(r), "LaserScan");
        break;
      }
      case Role::kRangeSonar: {
        const auto& x = std::get<Range>(m.message);
        CheckFrame(s, x.header, m.topic, m.index);
        sensors::LogRecord r;
        const auto& q = robot_.sensors[s.first_sensor];
        if (!std::isnan(x.range_m)) r.ranges.push_back({s.first_sensor, RangeOf(x.range_m, q.min_range_m, q.max_range_m)});
        AddReadings(m, x.header, std::move(r), "Range");
        break;
      }
      case Role::kCloudSonar: {
        const auto& c = std::get<PointCloud>(m.message);
        CheckFrame(s, c.header, m.topic, m.index);
        sensors::LogRecord r;
        for (const auto& p3 : c.points) {
          const Vec2 p = s.base_from_frame * Vec2(p3[0], p3[1]);
          if (!std::isfinite(p.x()) || !std::isfinite(p.y())) continue;
          int best = -1;
          double best_off = std::numeric_limits<double>::infinity(), best_r = 0;
          for (size_t k = 0; k < s.ring.sensors.size(); ++k) {
            const Pose2& sp = s.ring.sensors[k].robot_from_sensor;
            const Vec2 d = p - sp.translation();
            const Vec2 dir(std::cos(sp.theta), std::sin(sp.theta));
            const double along = d.dot(dir);
            if (along < -kCloudAxisToleranceM) continue;
            const double off = std::abs(dir.x() * d.y() - dir.y() * d.x());
            if (off < best_off) {
              best_off = off;
              best = static_cast<int>(k);
              best_r = d.norm();
            }
          }
          if (best < 0 || best_off > kCloudAxisToleranceM) {
            char buf[160];
            std::snprintf(buf, sizeof buf, "sonar point (%.3f, %.3f) lies on no sonar axis of robot '%s' (nearest %.3f m off)",
                          p.x(), p.y(), s.ring.name.c_str(), best_off);
            Fail(m.topic, m.index, std::string(buf) + ": give --robot");
          }
          const auto& q = s.ring.sensors[best];
          r.ranges.push_back({s.first_sensor + best, RangeOf(best_r, q.min_range_m, q.max_range_m)});
        }
        AddReadings(m, c.header, std::move(r), "PointCloud");
        break;
      }
      default: break;
    }
  }

  void AddReadings(const BagMessage& m, const Header& h, sensors::LogRecord&& r, const std::string& type) {
    if (r.ranges.empty()) {
      ++skipped_[type + " without a valid range"];
      return;
    }
    readings_ += static_cast<long>(r.ranges.size());
    Push(StampNs(h, m.time_ns) * 1e-9, 1, std::move(r));
  }

  bool Ready(double t) const {
    if (done_) return true;
    // Strictly after: readings stamped like the latest odometry may still come.
    return odom_.any() && odom_.latest() > t && (truth_ < 0 || (truth_track_.any() && truth_track_.latest() >= t));
  }

  bool PopReady(sensors::LogRecord* out) {
    while (!heap_.empty() && Ready(heap_.top().t)) {
      Item item = heap_.top();
      heap_.pop();
      const auto odom = odom_.At(item.t);
      if (!odom) {
        ++skipped_["scans outside the odometry (more than 1 s from it)"];
        readings_ -= static_cast<long>(item.record.ranges.size());
        continue;
      }
      *out = std::move(item.record);
      out->odom = *odom;
      out->time_s = item.t;
      if (truth_ >= 0) out->truth = truth_track_.At(item.t);
      // Readings stamped like this odometry message belong to its record.
      if (item.order == 0)
        while (!heap_.empty() && heap_.top().t == item.t && heap_.top().order == 1) {
          for (const auto& q : heap_.top().record.ranges) out->ranges.push_back(q);
          heap_.pop();
        }
      const double keep = heap_.empty() ? item.t : heap_.top().t;
      odom_.TrimBefore(keep);
      truth_track_.TrimBefore(keep);
      return true;
    }
    return false;
  }

  std::unique_ptr<BagSource> src_;
  LogOpenOptions options_;
  std::vector<Stream> streams_;
  int tf_static_ = -1, tf_ = -1, odometry_topic_ = -1, truth_ = -1;
  std::map<std::string, Edge> static_, dynamic_;
  std::string base_, odom_frame_;
  bool odom_from_tf_ = false;
  sensors::RobotDescription robot_;
  PoseTrack odom_, truth_track_;
  std::priority_queue<Item, std::vector<Item>, ItemAfter> heap_;
  long seq_ = 0, readings_ = 0, odometry_ = 0;
  bool done_ = false;
  std::map<std::string, long> skipped_;
};

}  // namespace

std::unique_ptr<LogReader> OpenBagLog(std::unique_ptr<BagSource> source, const LogOpenOptions& options) {
  return std::make_unique<BagReader>(std::move(source), options);
}

namespace {

TransformStamped Stamped(int64_t ns, const std::string& parent, const std::string& child, double x, double y,
                         double yaw) {
  return {{ns, parent}, child, FromPose2(x, y, yaw)};
}

Odometry OdometryMsg(int64_t ns, const std::string& frame, const Pose2& p) {
  return {{ns, frame}, "base_link", FromPose2(p.x, p.y, p.theta)};
}

}  // namespace

long WriteRosAriaMessages(const std::string& path, const sensors::RobotDescription& robot,
                          const std::function<bool(sensors::LogRecord*)>& next, BagWriter& bag) {
  const auto fans = LaserFans(robot);
  std::vector<int> fan_of(robot.sensors.size(), -1);
  for (size_t f = 0; f < fans.size(); ++f)
    for (int k = 0; k < fans[f].count; ++k) fan_of[fans[f].first + k] = static_cast<int>(f);
  std::vector<int> sonars;
  for (size_t i = 0; i < robot.sensors.size(); ++i)
    if (robot.sensors[i].kind == sensors::SensorKind::kSonar) sonars.push_back(static_cast<int>(i));
  auto fan_name = [](size_t f, const std::string& base) { return f == 0 ? base : base + "_" + std::to_string(f + 1); };

  long records = 0;
  sensors::LogRecord r;
  while (next(&r)) {
    if (!(r.time_s >= 0) || !std::isfinite(r.time_s))
      throw InputError(path + ": record " + std::to_string(records + 1) + ": time " + std::to_string(r.time_s) +
                       " cannot be a ROS time (must be >= 0)");
    const int64_t ns = std::llround(r.time_s * 1e9);
    if (records == 0) {
      TfMessage tf;
      if (!sonars.empty()) {
        tf.transforms.push_back(Stamped(ns, "base_link", "sonar", 0, 0, 0));
        for (size_t k = 0; k < sonars.size(); ++k) {
          const Pose2& p = robot.sensors[sonars[k]].robot_from_sensor;
          tf.transforms.push_back(Stamped(ns, "base_link", "sonar_" + std::to_string(k), p.x, p.y, p.theta));
        }
      }
      for (size_t f = 0; f < fans.size(); ++f) {
        const Pose2& p = robot.sensors[fans[f].first].robot_from_sensor;
        tf.transforms.push_back(Stamped(ns, "base_link", fan_name(f, "laser"), p.x, p.y, 0));
      }
      bag.Write("/tf_static", ns, tf);
    }
    bag.Write("/RosAria/pose", ns, OdometryMsg(ns, "odom", r.odom));
    TfMessage tf;
    tf.transforms.push_back(Stamped(ns, "odom", "base_link", r.odom.x, r.odom.y, r.odom.theta));
    bag.Write("/tf", ns, tf);
    if (r.truth) bag.Write("/base_pose_ground_truth", ns, OdometryMsg(ns, "map", *r.truth));
    if (!r.ranges.empty()) {
      PointCloud cloud;
      std::vector<LaserScan> scans(fans.size());
      std::vector<bool> used(fans.size(), false);
      for (const auto& q : r.ranges) {
        if (q.sensor < 0 || q.sensor >= static_cast<int>(robot.sensors.size()))
          throw InputError(path + ": record " + std::to_string(records + 1) + ": reading of sensor " +
                           std::to_string(q.sensor) + " but robot '" + robot.name + "' has " +
                           std::to_string(robot.sensors.size()) + " sensors");
        const auto& s = robot.sensors[q.sensor];
        if (s.kind == sensors::SensorKind::kSonar) {
          const Pose2& p = s.robot_from_sensor;
          cloud.points.push_back({p.x + q.range_m * std::cos(p.theta), p.y + q.range_m * std::sin(p.theta), 0.0});
          continue;
        }
        const int f = fan_of[q.sensor];
        auto& scan = scans[f];
        if (!used[f]) {
          used[f] = true;
          const LaserFan& fan = fans[f];
          scan.header = {ns, fan_name(f, "laser")};
          scan.angle_min_rad = fan.angle_min_rad;
          scan.angle_increment_rad = fan.increment_rad;
          scan.range_min_m = robot.sensors[fan.first].min_range_m;
          scan.range_max_m = robot.sensors[fan.first].max_range_m;
          scan.ranges.assign(fan.count, std::numeric_limits<float>::quiet_NaN());
        }
        scan.ranges[q.sensor - fans[f].first] = static_cast<float>(q.range_m);
      }
      if (!cloud.points.empty()) {
        cloud.header = {ns, "sonar"};
        bag.Write("/RosAria/sonar", ns, cloud);
      }
      for (size_t f = 0; f < fans.size(); ++f)
        if (used[f]) bag.Write(fan_name(f, "/scan"), ns, scans[f]);
    }
    ++records;
  }
  return records;
}

}  // namespace cogmap::io::ros
