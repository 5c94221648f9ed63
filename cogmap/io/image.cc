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

void EncodeRgbPngRows(int width, int height, const std::function<void(int y, uint8_t* rgb)>& row,
                      std::ostream& out) {
  png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, nullptr, nullptr, nullptr);
  png_infop info = png ? png_create_info_struct(png) : nullptr;
  if (!info) {
    png_destroy_write_struct(&png, nullptr);
    throw std::runtime_error("PNG encoding failed: out of memory");
  }
  std::vector<uint8_t> buffer(static_cast<size_t>(width) * 3);
  // libpng reports errors by longjmp: nothing with a destructor is created
  // between here and the end of the writing.
  if (setjmp(png_jmpbuf(png))) {
    png_destroy_write_struct(&png, &info);
    throw std::runtime_error("PNG encoding failed");
  }
  png_set_write_fn(
      png, &out,
      [](png_structp p, png_bytep data, png_size_t n) {
        static_cast<std::ostream*>(png_get_io_ptr(p))->write(reinterpret_cast<const char*>(data),
                                                             static_cast<std::streamsize>(n));
      },
      [](png_structp p) { static_cast<std::ostream*>(png_get_io_ptr(p))->flush(); });
  png_set_IHDR(png, info, static_cast<png_uint_32>(width), static_cast<png_uint_32>(height), 8, PNG_COLOR_TYPE_RGB,
               PNG_INTERLACE_NONE, PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
  png_set_filter(png, PNG_FILTER_TYPE_BASE, PNG_FILTER_NONE);
  png_set_compression_level(png, 1);
  png_write_info(png, info);
  for (int y = 0; y < height; ++y) {
    row(y, buffer.data());
    png_write_row(png, buffer.data());
  }
  png_write_end(png, info);
  png_destroy_write_struct(&png, &info);
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
