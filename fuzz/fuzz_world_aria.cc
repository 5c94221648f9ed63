// Fuzz target: an ARIA 2D-Map world (ParseAriaMap).
#include "cogmap/core/error.h"
#include "cogmap/io/world_io.h"
#include "fuzz/fuzz_util.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  try {
    cogmap::io::ParseAriaMap(std::string(reinterpret_cast<const char*>(data), size), "fuzz.map");
  } catch (const cogmap::InputError&) {
  }
  return 0;
}
