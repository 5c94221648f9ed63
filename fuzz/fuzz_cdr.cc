// Fuzz target: a ROS 2 message in CDR, decoded as each type cogmap reads.
#include "cogmap/core/error.h"
#include "cogmap/io/cdr.h"
#include "fuzz/fuzz_util.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  using cogmap::io::ros::MessageType;
  for (MessageType t : {MessageType::kLaserScan, MessageType::kRange, MessageType::kPointCloud2,
                        MessageType::kOdometry, MessageType::kTf}) {
    try {
      cogmap::io::cdr::Decode(t, data, size);
    } catch (const cogmap::io::cdr::CdrError&) {  // the ROS 2 reader names the bag, topic and message
    }
  }
  return 0;
}
