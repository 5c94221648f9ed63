#include "cogmap/io/image.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "cogmap/core/error.h"
#include "cogmap/io/atomic_file.h"
#include "cogmap/core/test_temp.h"

namespace cogmap::io {
namespace {

TEST(Png, RoundTripsPixels) {
  RgbImage img(7, 5, {10, 20, 30});
  img.Set(3, 2, {255, 0, 0});
  const std::string path = ::cogmap::testing_util::TestTempPath("rt.png");
  WritePng(path, img);
  const RgbImage back = ReadRgbPng(path);
  ASSERT_EQ(back.width(), 7);
  ASSERT_EQ(back.height(), 5);
  EXPECT_EQ(back.at(3, 2), (Rgb{255, 0, 0}));
  EXPECT_EQ(back.at(0, 0), (Rgb{10, 20, 30}));
}

TEST(Png, CorruptFileIsAnInputError) {
  const std::string path = ::cogmap::testing_util::TestTempPath("bad.png");
  WriteFileAtomically(path, std::string("\x89PNG\r\n\x1a\nnot really"));
  EXPECT_THROW(ReadGreyPng(path), InputError);
}

TEST(AtomicFile, FailedWriteLeavesOldFile) {
  const std::string path = ::cogmap::testing_util::TestTempPath("keep.txt");
  WriteFileAtomically(path, std::string("old"));
  EXPECT_THROW(WriteFileAtomically(path, [](std::ostream& o) {
                 o << "half";
                 throw InputError("boom");
               }),
               InputError);
  std::ifstream in(path);
  std::string s;
  in >> s;
  EXPECT_EQ(s, "old");
  int n = 0;
  for (auto& e : std::filesystem::directory_iterator(::cogmap::testing_util::TestTempDir()))
    if (e.path().filename().string().rfind("keep.txt.tmp", 0) == 0) ++n;
  EXPECT_EQ(n, 0);
}

}  // namespace
}  // namespace cogmap::io
