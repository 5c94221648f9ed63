#pragma once
#include <cstdio>
#include <map>
#include <string>

#include "cogmap/io/log_reader.h"

namespace cogmap::app {

// One warning line per message type a reader skipped, with its count.
inline void WarnSkipped(const std::string& path, const std::map<std::string, long>& skipped) {
  for (const auto& [type, n] : skipped)
    std::fprintf(stderr, "cogmap: warning: %s: skipped %ld %s messages\n", path.c_str(), n, type.c_str());
}
inline void WarnSkipped(const io::LogReader& log) { WarnSkipped(log.path(), log.skipped()); }

}  // namespace cogmap::app
