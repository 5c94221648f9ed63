#include "cogmap/io/ros1_bag.h"

#include <cstdio>
#include <filesystem>

#include "cogmap/core/error.h"
#include "cogmap/io/ros_log.h"

namespace cogmap::io {
namespace {

namespace msg = cogmap::io::ros;  // the neutral messages; ::ros is ROS 1's namespace

}  // namespace

std::unique_ptr<LogReader> OpenRos1Bag(const std::string& path, const LogOpenOptions& options) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec)) throw InputError(path, 0, "cannot open: no such file");
  return msg::OpenBagLog(msg::OpenRos1BagSource(path), options);
}

long WriteRosAriaBag(const std::string& path, const sensors::RobotDescription& robot,
                     const std::function<bool(sensors::LogRecord*)>& next) {
  const std::string tmp = path + ".partial";
  long records = 0;
  try {
    const std::unique_ptr<msg::BagWriter> bag = msg::MakeRos1BagWriter(tmp);
    records = msg::WriteRosAriaMessages(path, robot, next, *bag);
    bag->Close();
  } catch (...) {
    std::remove(tmp.c_str());
    throw;
  }
  std::error_code ec;
  std::filesystem::rename(tmp, path, ec);
  if (ec) {
    std::remove(tmp.c_str());
    throw InputError(path + ": cannot write (" + ec.message() + ")");
  }
  return records;
}

}  // namespace cogmap::io
