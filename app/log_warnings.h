#pragma once
#include <cstdio>

#include "cogmap/io/log_reader.h"

namespace cogmap::app {

// One warning line per message type a reader skipped, with its count.
inline void WarnSkipped(const io::LogReader& log) {
  for (const auto& [type, n] : log.skipped())
    std::fprintf(stderr, "cogmap: warning: %s: skipped %ld %s messages\n", log.path().c_str(), n, type.c_str());
}

}  // namespace cogmap::app
