// Fuzz target: a robot JSON file (LoadRobotJson).
#include "cogmap/core/error.h"
#include "cogmap/sensors/robot_json.h"
#include "fuzz/fuzz_util.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string path = cogmap::fuzz::AsFile(data, size, ".json");
  try {
    cogmap::sensors::LoadRobotJson(path);
  } catch (const cogmap::InputError&) {
  }
  return 0;
}
