// Fuzz target: a floor plan's plan.json (ParsePlanJson), as cogmap eval reads it.
#include "cogmap/core/error.h"
#include "cogmap/plan/plan_json.h"
#include "fuzz/fuzz_util.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  try {
    cogmap::plan::ParsePlanJson(std::string(reinterpret_cast<const char*>(data), size), "plan.json");
  } catch (const cogmap::InputError&) {
  }
  return 0;
}
