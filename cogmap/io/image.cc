#include "cogmap/io/image.h"

#include <png.h>

#include <algorithm>
#include <array>
#include <cctype>
#include <cmath>
#include <cstring>
#include <map>

#include "cogmap/core/error.h"
#include "cogmap/io/atomic_file.h"

namespace cogmap::io {

void RgbImage::DrawLine(double x0, double y0, double x1, double y1, Rgb c, int thickness) {
  const double len = std::hypot(x1 - x0, y1 - y0);
  const int steps = std::max(1, static_cast<int>(std::ceil(len * 2)));
  const double r = (thickness - 1) / 2.0;
  for (int i = 0; i <= steps; ++i) {
    const double t = static_cast<double>(i) / steps;
    const double x = x0 + t * (x1 - x0), y = y0 + t * (y1 - y0);
    if (thickness <= 1) {
      Set(static_cast<int>(std::floor(x)), static_cast<int>(std::floor(y)), c);
    } else {
      DrawDisc(x, y, r + 0.5, c);
    }
  }
}

void RgbImage::DrawDisc(double cx, double cy, double radius, Rgb c) {
  const int x0 = static_cast<int>(std::floor(cx - radius)), x1 = static_cast<int>(std::ceil(cx + radius));
  const int y0 = static_cast<int>(std::floor(cy - radius)), y1 = static_cast<int>(std::ceil(cy + radius));
  for (int y = y0; y <= y1; ++y)
    for (int x = x0; x <= x1; ++x)
      if ((x + 0.5 - cx) * (x + 0.5 - cx) + (y + 0.5 - cy) * (y + 0.5 - cy) <= radius * radius) Set(x, y, c);
}

void RgbImage::Blit(const RgbImage& other, int x, int y) {
  for (int j = 0; j < other.height(); ++j)
    for (int i = 0; i < other.width(); ++i) Set(x + i, y + j, other.at(i, j));
}

namespace {

// 5x7 glyphs, one byte per row, bit 4 = leftmost column.
const std::map<char, std::array<uint8_t, 7>>& Font() {
  static const std::map<char, std::array<uint8_t, 7>> font = {
      {'0', {14, 17, 19, 21, 25, 17, 14}}, {'1', {4, 12, 4, 4, 4, 4, 14}},
      {'2', {14, 17, 1, 2, 4, 8, 31}},     {'3', {31, 2, 4, 2, 1, 17, 14}},
      {'4', {2, 6, 10, 18, 31, 2, 2}},     {'5', {31, 16, 30, 1, 1, 17, 14}},
      {'6', {6, 8, 16, 30, 17, 17, 14}},   {'7', {31, 1, 2, 4, 8, 8, 8}},
      {'8', {14, 17, 17, 14, 17, 17, 14}}, {'9', {14, 17, 17, 15, 1, 2, 12}},
      {'A', {14, 17, 17, 31, 17, 17, 17}}, {'B', {30, 17, 17, 30, 17, 17, 30}},
      {'C', {14, 17, 16, 16, 16, 17, 14}}, {'D', {28, 18, 17, 17, 17, 18, 28}},
      {'E', {31, 16, 16, 30, 16, 16, 31}}, {'F', {31, 16, 16, 30, 16, 16, 16}},
      {'G', {14, 17, 16, 23, 17, 17, 15}}, {'H', {17, 17, 17, 31, 17, 17, 17}},
      {'I', {14, 4, 4, 4, 4, 4, 14}},      {'J', {7, 2, 2, 2, 2, 18, 12}},
      {'K', {17, 18, 20, 24, 20, 18, 17}}, {'L', {16, 16, 16, 16, 16, 16, 31}},
      {'M', {17, 27, 21, 21, 17, 17, 17}}, {'N', {17, 17, 25, 21, 19, 17, 17}},
      {'O', {14, 17, 17, 17, 17, 17, 14}}, {'P', {30, 17, 17, 30, 16, 16, 16}},
      {'Q', {14, 17, 17, 17, 21, 18, 13}}, {'R', {30, 17, 17, 30, 20, 18, 17}},
      {'S', {15, 16, 16, 14, 1, 1, 30}},   {'T', {31, 4, 4, 4, 4, 4, 4}},
      {'U', {17, 17, 17, 17, 17, 17, 14}}, {'V', {17, 17, 17, 17, 17, 10, 4}},
      {'W', {17, 17, 17, 21, 21, 21, 10}}, {'X', {17, 17, 10, 4, 10, 17, 17}},
      {'Y', {17, 17, 17, 10, 4, 4, 4}},    {'Z', {31, 1, 2, 4, 8, 16, 31}},
      {'.', {0, 0, 0, 0, 0, 12, 12}},      {'-', {0, 0, 0, 31, 0, 0, 0}},
      {':', {0, 12, 12, 0, 12, 12, 0}},    {'/', {1, 1, 2, 4, 8, 16, 16}},
      {'(', {2, 4, 8, 8, 8, 4, 2}},        {')', {8, 4, 2, 2, 2, 4, 8}},
      {'=', {0, 0, 31, 0, 31, 0, 0}},      {'%', {24, 25, 2, 4, 8, 19, 3}},
      {'_', {0, 0, 0, 0, 0, 0, 31}},       {'+', {0, 4, 4, 31, 4, 4, 0}},
      {',', {0, 0, 0, 0, 12, 4, 8}},       {'#', {10, 10, 31, 10, 31, 10, 10}},
  };
  return font;
}

}  // namespace

void RgbImage::DrawText(int x, int y, const std::string& text, Rgb c, int scale) {
  const auto& font = Font();
  int cx = x;
  for (char ch : text) {
    const char u = static_cast<char>(std::toupper(static_cast<unsigned char>(ch)));
    auto it = font.find(u);
    if (it != font.end()) {
      for (int row = 0; row < 7; ++row)
        for (int col = 0; col < 5; ++col)
          if (it->second[row] & (1 << (4 - col)))
            for (int sy = 0; sy < scale; ++sy)
              for (int sx = 0; sx < scale; ++sx) Set(cx + col * scale + sx, y + row * scale + sy, c);
    }
    cx += 6 * scale;
  }
}

namespace {

std::string Encode(int width, int height, int format, const void* data, int row_stride) {
  png_image img;
  std::memset(&img, 0, sizeof img);
  img.version = PNG_IMAGE_VERSION;
  img.width = static_cast<png_uint_32>(width);
  img.height = static_cast<png_uint_32>(height);
  img.format = static_cast<png_uint_32>(format);
  png_alloc_size_t size = 0;
  if (!png_image_write_to_memory(&img, nullptr, &size, 0, data, row_stride, nullptr))
    throw std::runtime_error(std::string("PNG encoding failed: ") + img.message);
  std::string out(size, '\0');
  if (!png_image_write_to_memory(&img, out.data(), &size, 0, data, row_stride, nullptr))
    throw std::runtime_error(std::string("PNG encoding failed: ") + img.message);
  out.resize(size);
  return out;
}

}  // namespace

std::string EncodePng(const RgbImage& image) {
  static_assert(sizeof(Rgb) == 3);
  return Encode(image.width(), image.height(), PNG_FORMAT_RGB, image.pixels().data(), image.width() * 3);
}

std::string EncodeGreyPng(int width, int height, const std::vector<uint8_t>& grey) {
  return Encode(width, height, PNG_FORMAT_GRAY, grey.data(), width);
}

void WritePng(const std::string& path, const RgbImage& image) {
  WriteFileAtomically(path, EncodePng(image));
}

namespace {

// 2^28 pixels (16384 x 16384): a 0.8 km square world at 5 cm per pixel.
constexpr uint64_t kMaxReadPixels = uint64_t{1} << 28;

template <typename Pixel>
std::vector<Pixel> ReadPng(const std::string& path, int format, int* w, int* h) {
  png_image img;
  std::memset(&img, 0, sizeof img);
  img.version = PNG_IMAGE_VERSION;
  if (!png_image_begin_read_from_file(&img, path.c_str()))
    throw InputError(path, 0, std::string("not a readable PNG: ") + img.message);
  img.format = static_cast<png_uint_32>(format);
  // The header's size is checked before the raster is allocated: a 69-byte
  // file may claim 1e6 x 1e6 pixels.
  const uint64_t count = static_cast<uint64_t>(img.width) * img.height;
  if (img.width == 0 || img.height == 0 || count > kMaxReadPixels) {
    png_image_free(&img);
    throw InputError(path, 0, "PNG of " + std::to_string(img.width) + " x " + std::to_string(img.height) +
                                  " pixels: more than the " + std::to_string(kMaxReadPixels) +
                                  " pixels cogmap reads");
  }
  std::vector<Pixel> pixels(static_cast<size_t>(count));
  if (!png_image_finish_read(&img, nullptr, pixels.data(), 0, nullptr)) {
    const std::string msg = img.message;
    png_image_free(&img);
    throw InputError(path, 0, "corrupt PNG: " + msg);
  }
  *w = static_cast<int>(img.width);
  *h = static_cast<int>(img.height);
  return pixels;
}

}  // namespace

GreyImage ReadGreyPng(const std::string& path) {
  GreyImage g;
  g.pixels = ReadPng<uint8_t>(path, PNG_FORMAT_GRAY, &g.width, &g.height);
  return g;
}

RgbImage ReadRgbPng(const std::string& path) {
  int w = 0, h = 0;
  auto px = ReadPng<Rgb>(path, PNG_FORMAT_RGB, &w, &h);
  RgbImage img(w, h);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) img.at(x, y) = px[static_cast<size_t>(y) * w + x];
  return img;
}

}  // namespace cogmap::io
