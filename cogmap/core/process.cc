#include "cogmap/core/process.h"

#include <sys/resource.h>

#include <cstdlib>
#include <fstream>
#include <algorithm>
#include <string>

namespace cogmap {
namespace {

// A "Key:   N kB" line of /proc/self/status, KiB; -1 when there is none.
long StatusKib(const char* key) {
  std::ifstream status("/proc/self/status");
  const std::string lead = std::string(key) + ":";
  for (std::string line; std::getline(status, line);)
    if (line.rfind(lead, 0) == 0) return std::strtol(line.c_str() + lead.size(), nullptr, 10);
  return -1;
}

}  // namespace

long PeakResidentKib() {
  const long hwm = StatusKib("VmHWM");
  if (hwm >= 0) return hwm;
  rusage u{};
  getrusage(RUSAGE_SELF, &u);
  return u.ru_maxrss;
}

long ResidentKib() { return std::max(0L, StatusKib("VmRSS")); }

}  // namespace cogmap
