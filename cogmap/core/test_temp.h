#pragma once
// Scratch files for tests. ctest runs the tests of one binary in parallel, one
// process per test, so a fixed name under ::testing::TempDir() is shared between
// processes and one test can read a file another is rewriting. Every path here
// lives in a directory of its own process (removed when the process ends).
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <string>
#include <system_error>

namespace cogmap::testing_util {

namespace detail {
struct ProcessTempDir {
  std::filesystem::path path;
  ProcessTempDir()
      : path(std::filesystem::path(::testing::TempDir()) / ("cogmap-test-" + std::to_string(::getpid()))) {
    std::filesystem::create_directories(path);
  }
  ~ProcessTempDir() {
    std::error_code ec;
    std::filesystem::remove_all(path, ec);
  }
};
}  // namespace detail

// A directory private to this test process, created on first use.
inline std::string TestTempDir() {
  static detail::ProcessTempDir dir;
  return dir.path.string();
}

// TestTempDir()/name.
inline std::string TestTempPath(const std::string& name) { return TestTempDir() + "/" + name; }

}  // namespace cogmap::testing_util
