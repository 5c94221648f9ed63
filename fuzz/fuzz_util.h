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
#include <string>

namespace cogmap::fuzz {

// The input written to a file of this process (reused for every input).
inline std::string AsFile(const uint8_t* data, size_t size, const std::string& suffix = "") {
  static const std::string base =
      (std::filesystem::temp_directory_path() / ("cogmap-fuzz-" + std::to_string(::getpid()))).string();
  const std::string path = base + suffix;
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out.write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(size));
  return path;
}

}  // namespace cogmap::fuzz
