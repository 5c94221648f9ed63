#include "cogmap/io/image.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>

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

TEST(Png, RowsEncoderRoundTripsEveryPixel) {
  const int w = 37, h = 23;
  auto colour = [](int x, int y) {
    return Rgb{static_cast<uint8_t>(7 * x), static_cast<uint8_t>(11 * y), static_cast<uint8_t>(x * y)};
  };
  std::ostringstream bytes;
  EncodeRgbPngRows(
      w, h,
      [&](int y, uint8_t* rgb) {
        for (int x = 0; x < w; ++x) {
          const Rgb c = colour(x, y);
          rgb[3 * x] = c.r, rgb[3 * x + 1] = c.g, rgb[3 * x + 2] = c.b;
        }
      },
      bytes);
  const std::string path = ::cogmap::testing_util::TestTempPath("rows.png");
  WriteFileAtomically(path, bytes.str());
  const RgbImage back = ReadRgbPng(path);
  ASSERT_EQ(back.width(), w);
  ASSERT_EQ(back.height(), h);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) ASSERT_EQ(back.at(x, y), colour(x, y)) << x << "," << y;
}

TEST(Png, CorruptFileIsAnInputError) {
  const std::string path = ::cogmap::testing_util::TestTempPath("bad.png");
  WriteFileAtomically(path, std::string("\x89PNG\r\n\x1a\nnot really"));
  EXPECT_THROW(ReadGreyPng(path), InputError);
}

// A PNG chunk: length, type, data, CRC-32 of type and data.
std::string Chunk(const std::string& type, const std::string& data) {
  auto be32 = [](uint32_t v) {
    return std::string{static_cast<char>(v >> 24), static_cast<char>(v >> 16), static_cast<char>(v >> 8),
                       static_cast<char>(v)};
  };
  uint32_t crc = 0xffffffffu;
  for (const char ch : type + data) {
    crc ^= static_cast<uint8_t>(ch);
    for (int k = 0; k < 8; ++k) crc = (crc >> 1) ^ (0xedb88320u & (0u - (crc & 1u)));
  }
  return be32(static_cast<uint32_t>(data.size())) + type + data + be32(~crc);
}

TEST(Png, HugeClaimedSizeIsRefusedBeforeAllocating) {
  // 1e6 x 1e6 grey pixels claimed by a file of a few dozen bytes.
  const std::string ihdr = std::string("\x00\x0f\x42\x40\x00\x0f\x42\x40\x08\x00\x00\x00\x00", 13);
  const std::string png = std::string("\x89PNG\r\n\x1a\n", 8) + Chunk("IHDR", ihdr) +
                          Chunk("IDAT", std::string("\x78\x9c\x03\x00\x00\x00\x00\x01", 8)) + Chunk("IEND", "");
  const std::string path = ::cogmap::testing_util::TestTempPath("huge.png");
  WriteFileAtomically(path, png);
  try {
    ReadGreyPng(path);
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()),
              path + ": PNG of 1000000 x 1000000 pixels: more than the 268435456 pixels cogmap reads");
  }
  EXPECT_THROW(ReadRgbPng(path), InputError);
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
