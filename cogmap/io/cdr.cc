#include "cogmap/io/cdr.h"

#include <algorithm>
#include <bit>
#include <cstring>
#include <stdexcept>

namespace cogmap::io::cdr {
namespace {

bool HostLittleEndian() {
  const uint16_t one = 1;
  uint8_t b;
  std::memcpy(&b, &one, 1);
  return b == 1;
}

}  // namespace

Reader::Reader(const uint8_t* data, size_t size) : data_(data), size_(size) {
  if (size < 4) throw CdrError("shorter than the 4-byte CDR header (" + std::to_string(size) + " bytes)");
  if (data[0] != 0 || data[1] > 1)
    throw CdrError("encapsulation " + std::to_string(data[0]) + "," + std::to_string(data[1]) +
                   " is not plain CDR (cogmap reads 0,0 big endian and 0,1 little endian)");
  const bool little = data[1] == 1;
  swap_ = little != HostLittleEndian();
}

void Reader::Need(size_t n, const char* what) {
  if (pos_ + n > size_ || pos_ + n < pos_)
    throw CdrError(std::string("data ends at byte ") + std::to_string(size_) + " while reading " + what +
                   " at byte " + std::to_string(pos_));
}

void Reader::Align(size_t n) {
  const size_t rel = pos_ - 4;
  const size_t pad = (n - rel % n) % n;
  pos_ += pad;
}

template <class T>
T Reader::Get(const char* what) {
  Align(sizeof(T));
  Need(sizeof(T), what);
  uint8_t b[sizeof(T)];
  std::memcpy(b, data_ + pos_, sizeof(T));
  if (swap_) std::reverse(b, b + sizeof(T));
  pos_ += sizeof(T);
  T v;
  std::memcpy(&v, b, sizeof(T));
  return v;
}

uint8_t Reader::U8() { return Get<uint8_t>("a byte"); }
uint32_t Reader::U32() { return Get<uint32_t>("a uint32"); }
int32_t Reader::I32() { return Get<int32_t>("an int32"); }
float Reader::F32() { return Get<float>("a float32"); }
double Reader::F64() { return Get<double>("a float64"); }

std::string Reader::String() {
  const uint32_t n = Get<uint32_t>("a string length");
  Need(n, "a string");
  if (n == 0) return "";
  if (data_[pos_ + n - 1] != 0) throw CdrError("string at byte " + std::to_string(pos_) + " does not end in NUL");
  std::string s(reinterpret_cast<const char*>(data_ + pos_), n - 1);
  pos_ += n;
  return s;
}

uint32_t Reader::Count(size_t min_element_bytes) {
  const uint32_t n = Get<uint32_t>("a sequence length");
  if (min_element_bytes > 0 && uint64_t{n} * min_element_bytes > size_ - std::min(pos_, size_))
    throw CdrError("sequence of " + std::to_string(n) + " elements at byte " + std::to_string(pos_) +
                   " is longer than the data left");
  return n;
}

namespace {

ros::Header ReadHeader(Reader& r) {
  ros::Header h;
  const int32_t sec = r.I32();
  const uint32_t nsec = r.U32();
  h.stamp_ns = int64_t{sec} * 1000000000 + nsec;
  h.frame_id = r.String();
  return h;
}

ros::Transform3 ReadPose(Reader& r) {  // Point/Vector3 then Quaternion, all float64
  ros::Transform3 t;
  t.x = r.F64();
  t.y = r.F64();
  t.z = r.F64();
  t.qx = r.F64();
  t.qy = r.F64();
  t.qz = r.F64();
  t.qw = r.F64();
  return t;
}

}  // namespace

ros::Message Decode(ros::MessageType type, const uint8_t* data, size_t size) {
  Reader r(data, size);
  switch (type) {
    case ros::MessageType::kLaserScan: {
      ros::LaserScan s;
      s.header = ReadHeader(r);
      s.angle_min_rad = r.F32();
      r.F32();  // angle_max
      s.angle_increment_rad = r.F32();
      r.F32();  // time_increment
      r.F32();  // scan_time
      s.range_min_m = r.F32();
      s.range_max_m = r.F32();
      const uint32_t n = r.Count(4);
      s.ranges.resize(n);
      for (uint32_t i = 0; i < n; ++i) s.ranges[i] = r.F32();
      return s;  // intensities are not used
    }
    case ros::MessageType::kRange: {
      ros::Range x;
      x.header = ReadHeader(r);
      x.radiation_type = r.U8();
      x.field_of_view_rad = r.F32();
      x.min_range_m = r.F32();
      x.max_range_m = r.F32();
      x.range_m = r.F32();
      return x;
    }
    case ros::MessageType::kPointCloud: {
      ros::PointCloud c;
      c.header = ReadHeader(r);
      const uint32_t n = r.Count(12);
      c.points.reserve(n);
      for (uint32_t i = 0; i < n; ++i) {
        const double x = r.F32(), y = r.F32(), z = r.F32();
        c.points.push_back({x, y, z});
      }
      return c;  // channels are not used
    }
    case ros::MessageType::kPointCloud2: {
      ros::PointCloud c;
      c.header = ReadHeader(r);
      const uint32_t height = r.U32(), width = r.U32();
      const uint32_t nf = r.Count(13);
      std::vector<ros::PointField> fields(nf);
      for (auto& f : fields) {
        f.name = r.String();
        f.offset = r.U32();
        f.datatype = r.U8();
        f.count = r.U32();
      }
      const bool big = r.U8() != 0;
      const uint32_t point_step = r.U32();
      r.U32();  // row_step
      const uint32_t n = r.Count(1);
      const size_t at = r.offset();
      const std::string err = ros::DecodePointCloud2(fields, big, point_step, width, height, data + at, n, &c.points);
      if (!err.empty()) throw CdrError(err);
      return c;
    }
    case ros::MessageType::kOdometry: {
      ros::Odometry o;
      o.header = ReadHeader(r);
      o.child_frame_id = r.String();
      o.pose = ReadPose(r);
      return o;  // covariance and twist are not used
    }
    case ros::MessageType::kTf: {
      ros::TfMessage tf;
      const uint32_t n = r.Count(8 + 4 + 4 + 56);
      tf.transforms.resize(n);
      for (auto& t : tf.transforms) {
        t.header = ReadHeader(r);
        t.child_frame_id = r.String();
        t.transform = ReadPose(r);
      }
      return tf;
    }
    case ros::MessageType::kOther: break;
  }
  return std::monostate{};
}

void Writer::Put(const void* v, size_t n) {
  while ((buf_.size() - 4) % n) buf_.push_back('\0');
  char b[8];
  std::memcpy(b, v, n);
  if constexpr (std::endian::native == std::endian::big) std::reverse(b, b + n);
  buf_.append(b, n);
}

void Writer::String(const std::string& s) {
  U32(static_cast<uint32_t>(s.size() + 1));
  buf_ += s;
  buf_.push_back('\0');
}

namespace {

void WriteHeader(Writer& w, const ros::Header& h) {
  w.I32(static_cast<int32_t>(h.stamp_ns / 1000000000));
  w.U32(static_cast<uint32_t>(h.stamp_ns % 1000000000));
  w.String(h.frame_id);
}

void WritePose(Writer& w, const ros::Transform3& t) {
  for (double v : {t.x, t.y, t.z, t.qx, t.qy, t.qz, t.qw}) w.F64(v);
}

}  // namespace

std::string Encode(const ros::Message& message, std::string* type) {
  Writer w;
  if (const auto* s = std::get_if<ros::LaserScan>(&message)) {
    *type = "sensor_msgs/msg/LaserScan";
    WriteHeader(w, s->header);
    w.F32(static_cast<float>(s->angle_min_rad));
    w.F32(static_cast<float>(s->angle_min_rad + s->angle_increment_rad * (static_cast<double>(s->ranges.size()) - 1)));
    w.F32(static_cast<float>(s->angle_increment_rad));
    w.F32(0);  // time_increment
    w.F32(0);  // scan_time
    w.F32(static_cast<float>(s->range_min_m));
    w.F32(static_cast<float>(s->range_max_m));
    w.U32(static_cast<uint32_t>(s->ranges.size()));
    for (float r : s->ranges) w.F32(r);
    w.U32(0);  // intensities
  } else if (const auto* x = std::get_if<ros::Range>(&message)) {
    *type = "sensor_msgs/msg/Range";
    WriteHeader(w, x->header);
    w.U8(static_cast<uint8_t>(x->radiation_type));
    w.F32(static_cast<float>(x->field_of_view_rad));
    w.F32(static_cast<float>(x->min_range_m));
    w.F32(static_cast<float>(x->max_range_m));
    w.F32(static_cast<float>(x->range_m));
  } else if (const auto* c = std::get_if<ros::PointCloud>(&message)) {
    *type = "sensor_msgs/msg/PointCloud";
    WriteHeader(w, c->header);
    w.U32(static_cast<uint32_t>(c->points.size()));
    for (const auto& p : c->points)
      for (double v : p) w.F32(static_cast<float>(v));
    w.U32(0);  // channels
  } else if (const auto* o = std::get_if<ros::Odometry>(&message)) {
    *type = "nav_msgs/msg/Odometry";
    WriteHeader(w, o->header);
    w.String(o->child_frame_id);
    WritePose(w, o->pose);
    for (int i = 0; i < 36 + 6 + 36; ++i) w.F64(0);  // pose covariance, twist, twist covariance
  } else if (const auto* tf = std::get_if<ros::TfMessage>(&message)) {
    *type = "tf2_msgs/msg/TFMessage";
    w.U32(static_cast<uint32_t>(tf->transforms.size()));
    for (const auto& t : tf->transforms) {
      WriteHeader(w, t.header);
      w.String(t.child_frame_id);
      WritePose(w, t.transform);
    }
  } else {
    throw std::invalid_argument("cdr::Encode: no message");
  }
  return w.bytes();
}

}  // namespace cogmap::io::cdr
