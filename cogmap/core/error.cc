#include "cogmap/core/error.h"

namespace cogmap {

static std::string Compose(const std::string& path, long line, const std::string& problem) {
  std::string s = path;
  if (line > 0) s += ":" + std::to_string(line);
  s += ": " + problem;
  return s;
}

InputError::InputError(const std::string& path, long line, const std::string& problem)
    : std::runtime_error(Compose(path, line, problem)) {}

}  // namespace cogmap
