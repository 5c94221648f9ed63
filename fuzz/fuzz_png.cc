// Fuzz target: a PNG, as a bitmap world (ReadGreyPng, the walls traced from
// it) and as a room segmentation (ReadRoomSegmentation: RGB, rooms labelled).
#include "cogmap/core/error.h"
#include "cogmap/io/image.h"
#include "cogmap/io/world_io.h"
#include "fuzz/fuzz_util.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string path = cogmap::fuzz::AsFile(data, size, ".png");
  try {
    cogmap::io::FloorPlanFromOccupancy(cogmap::io::ReadGreyPng(path));
  } catch (const cogmap::InputError&) {
  }
  try {
    cogmap::io::ReadRoomSegmentation(path);
  } catch (const cogmap::InputError&) {
  }
  return 0;
}
