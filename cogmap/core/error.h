#pragma once
#include <stdexcept>
#include <string>

namespace cogmap {

// Bad user data: a file the user can fix. The message names the file, the line
// (when there is one) and the problem, e.g. "logs/run3.log:112: expected 18
// fields, got 17". The app prints what() on one line and exits with status 2.
class InputError : public std::runtime_error {
 public:
  explicit InputError(const std::string& message) : std::runtime_error(message) {}
  // "path:line: problem" (line <= 0 leaves the line out).
  InputError(const std::string& path, long line, const std::string& problem);
};

}  // namespace cogmap
