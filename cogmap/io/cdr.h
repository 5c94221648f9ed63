#pragma once
// A small reader of CDR (XCDR1 as ROS 2's rmw writes it) for exactly the
// messages cogmap reads from ROS 2 bags. Layout: a 4-byte encapsulation header
// (0x00 0x01: little endian, 0x00 0x00: big endian; two option bytes), then
// the fields in order, each primitive aligned to its size (at most 8)
// relative to the byte after the header; strings as a uint32 length counting
// the terminating NUL, then the bytes and the NUL; sequences as a uint32
// count, then the elements; fixed arrays as the elements alone.
#include <cstddef>
#include <cstdint>
#include <stdexcept>
#include <string>

#include "cogmap/io/ros_log.h"

namespace cogmap::io::cdr {

// Malformed or short CDR data; what() says where ("at byte 40 of 36: ...").
class CdrError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

class Reader {
 public:
  // Reads the encapsulation header; CdrError for another encapsulation.
  Reader(const uint8_t* data, size_t size);
  uint8_t U8();
  uint32_t U32();
  int32_t I32();
  float F32();
  double F64();
  std::string String();
  // A sequence's element count, checked against the bytes left (each element
  // takes at least 'min_element_bytes').
  uint32_t Count(size_t min_element_bytes);
  size_t offset() const { return pos_; }

 private:
  void Need(size_t n, const char* what);
  void Align(size_t n);
  template <class T>
  T Get(const char* what);
  const uint8_t* data_;
  size_t size_;
  size_t pos_ = 4;
  bool swap_ = false;
};

// The encoder of the same layout (little endian), for the bags cogmap writes.
class Writer {
 public:
  Writer() : buf_{0, 1, 0, 0} {}
  void U8(uint8_t v) { Put(&v, 1); }
  void U32(uint32_t v) { Put(&v, 4); }
  void I32(int32_t v) { Put(&v, 4); }
  void F32(float v) { Put(&v, 4); }
  void F64(double v) { Put(&v, 8); }
  void String(const std::string& s);
  const std::string& bytes() const { return buf_; }

 private:
  void Put(const void* v, size_t n);
  std::string buf_;
};

// The CDR bytes of a LaserScan, Range, PointCloud (sensor_msgs/msg/PointCloud,
// no channels), Odometry (zero covariances and twist) or TfMessage; the ROS 2
// type name goes to 'type'. std::invalid_argument for monostate.
std::string Encode(const ros::Message& message, std::string* type);

// Decoders for the ROS 2 types ("sensor_msgs/msg/LaserScan", ...). Return the
// message, or monostate for other types; CdrError for bad data.
ros::Message Decode(ros::MessageType type, const uint8_t* data, size_t size);

}  // namespace cogmap::io::cdr
