#pragma once
// Shared by the fuzz targets: the input as a file (the readers take paths),
// and what counts as a finding. A reader may reject its input only with
// cogmap::InputError (the one-line "FILE:LINE: problem" of the command); any
// other exception (std::bad_alloc from a hostile size, std::out_of_range, ...),
// a crash, a sanitizer report or a hang is a finding.
#include <unistd.h>

#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <set>
#include <string>
#include <system_error>

namespace cogmap::fuzz {

namespace detail {
// The files of this process, removed when it exits (libFuzzer ends a run with
// exit(), so static destructors run).
struct ProcessFiles {
  std::string base =
      (std::filesystem::temp_directory_path() / ("cogmap-fuzz-" + std::to_string(::getpid()))).string();
  std::set<std::string> paths;
  ~ProcessFiles() {
    for (const auto& p : paths) {
      for (const char* tail : {"", "-wal", "-shm", "-journal"}) {
        std::error_code ec;
        std::filesystem::remove(p + tail, ec);
      }
    }
  }
};
}  // namespace detail

// The input written to a file of this process (reused for every input).
inline std::string AsFile(const uint8_t* data, size_t size, const std::string& suffix = "") {
  static detail::ProcessFiles files;
  const std::string path = files.base + suffix;
  files.paths.insert(path);
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out.write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(size));
  return path;
}

}  // namespace cogmap::fuzz
