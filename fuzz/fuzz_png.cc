// Fuzz target: a PNG (a bitmap world, ReadGreyPng).
#include "cogmap/core/error.h"
#include "cogmap/io/image.h"
#include "fuzz/fuzz_util.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string path = cogmap::fuzz::AsFile(data, size, ".png");
  try {
    cogmap::io::ReadGreyPng(path);
  } catch (const cogmap::InputError&) {
  }
  return 0;
}
