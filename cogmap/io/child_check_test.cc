#include "cogmap/io/child_check.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <signal.h>

#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "cogmap/core/error.h"
#include "cogmap/core/test_temp.h"

namespace cogmap::io {
namespace {

using ::testing::HasSubstr;

std::string File(const std::string& name) {
  const std::string path = testing_util::TestTempPath(name);
  std::ofstream(path) << "some bytes\n";
  return path;
}

std::string ErrorOf(const std::string& path, const std::function<void(long*)>& read_all,
                    const ChildCheckLimits& limits = {}) {
  try {
    CheckInChild(path, "test file", "testlib", "items", read_all, limits);
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

TEST(CheckInChild, FileReadToItsEndPassesOnceAndIsNotReadAgain) {
  const std::string path = File("good.dat");
  const std::string marker = testing_util::TestTempPath("good.read");
  auto read_all = [&](long* count) {
    std::ofstream(marker) << "read\n";  // the child's side effect on the file system
    *count = 5;
  };
  EXPECT_EQ(ErrorOf(path, read_all), "");
  EXPECT_TRUE(std::filesystem::exists(marker));
  std::filesystem::remove(marker);
  EXPECT_EQ(ErrorOf(path, read_all), "");
  EXPECT_FALSE(std::filesystem::exists(marker));  // checked once per process
}

TEST(CheckInChild, CrashInTheLibraryIsOneErrorNamingTheSignalAndTheCount) {
  const std::string path = File("crash.dat");
  const std::string e = ErrorOf(path, [](long* count) {
    *count = 3;
    ::raise(SIGSEGV);
  });
  EXPECT_EQ(e, path + ": a damaged test file: testlib crashed reading it (SIGSEGV) after 3 items");
}

TEST(CheckInChild, HostileSizeStopsAtTheMemoryBound) {
  const std::string path = File("huge.dat");
  ChildCheckLimits limits;
  limits.memory_floor_bytes = uint64_t{64} << 20;
  const std::string e = ErrorOf(
      path,
      [](long* count) {
        *count = 1;
        std::vector<char> v(size_t{8} << 30, 1);  // 8 GB for a file of 11 bytes
        *count = v[12345];
      },
      limits);
  EXPECT_THAT(e, HasSubstr(path + ": a damaged test file: testlib asked for more memory than such a file can need"));
  EXPECT_THAT(e, HasSubstr("after 1 items"));
}

TEST(CheckInChild, EndlessReadStopsAtTheCpuBound) {
  const std::string path = File("endless.dat");
  ChildCheckLimits limits;
  limits.cpu_floor_s = 1.0;
  limits.cpu_s_per_mb = 0.0;
  const std::string e = ErrorOf(
      path,
      [](long* count) {
        *count = 7;
        for (;;) asm volatile("");  // spins (an empty loop the compiler keeps)
      },
      limits);
  EXPECT_EQ(e, path + ": a damaged test file: testlib was still reading it after 1 s of CPU after 7 items");
}

TEST(CheckInChild, InputErrorOfTheChildIsThrownAsItIs) {
  const std::string path = File("input.dat");
  EXPECT_EQ(ErrorOf(path, [&](long*) { throw InputError(path, 12, "a bad field"); }), path + ":12: a bad field");
}

}  // namespace
}  // namespace cogmap::io
