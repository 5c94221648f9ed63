// Fuzz target: a log read by the ev3 reader (OpenLog(path, "ev3")), every record.
#include "cogmap/core/error.h"
#include "cogmap/io/log_reader.h"
#include "fuzz/fuzz_util.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string path = cogmap::fuzz::AsFile(data, size, ".log");
  try {
    auto log = cogmap::io::OpenLog(path, "ev3");
    cogmap::sensors::LogRecord record;
    long n = 0;
    while (log->Next(&record) && ++n < 1000000) {
    }
  } catch (const cogmap::InputError&) {
  }
  return 0;
}
