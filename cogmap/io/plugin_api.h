#pragma once
// The readers and writers that need a large library stack (ROS 1's
// rosbag_storage, MRPT) live in loadable modules, opened on first use by
// cogmap/io/plugins.cc: a command that reads a native or CARMEN log never
// loads them. Linked in, MRPT (with OpenCV, GDAL, ...) and ROS 1 made every
// cogmap process load about 220 shared libraries: 0.45 s and 76 MB of
// resident memory before main() (`cogmap --version`), about a fifth of the
// whole `cogmap map` of the intel log. See docs/cpp-api.md ("Plugins").
//
// Each module exports one C function returning its table. The modules are
// built with the command, from the same sources and compiler: the table's
// abi must equal kPluginAbi and its version cogmap's, or the module is
// refused with an error naming it.
#include <functional>
#include <memory>
#include <string>

#include "cogmap/io/ros_messages.h"

// Declared only: the ROS 1 module is C++17 (the ROS 1 headers), and these
// headers are C++20.
namespace cogmap::sensors {
struct RobotDescription;
struct LogRecord;
}  // namespace cogmap::sensors
namespace cogmap::io {
class LogReader;
struct LogOpenOptions;
}  // namespace cogmap::io

namespace cogmap::io::plugin {

constexpr int kPluginAbi = 1;

// libcogmap_io_ros1.so: ROS 1 bags through rosbag_storage.
struct Ros1Table {
  int abi;
  const char* version;  // COGMAP_VERSION the module was built as
  std::unique_ptr<ros::BagSource> (*open_source)(const std::string& path);
  std::unique_ptr<ros::BagWriter> (*make_writer)(const std::string& path);
};

// libcogmap_io_mrpt.so: MRPT rawlogs through MRPT's own library.
struct MrptTable {
  int abi;
  const char* version;
  std::unique_ptr<LogReader> (*open)(const std::string& path, const LogOpenOptions& options);
  long (*write)(const std::string& path, const sensors::RobotDescription& robot,
                const std::function<bool(sensors::LogRecord*)>& next);
};

}  // namespace cogmap::io::plugin

// The modules' entry points (extern "C": looked up by name with dlsym).
extern "C" const cogmap::io::plugin::Ros1Table* cogmap_io_ros1_table();
extern "C" const cogmap::io::plugin::MrptTable* cogmap_io_mrpt_table();
