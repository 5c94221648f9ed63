#pragma once
#include <cstdint>
#include <functional>
#include <ostream>
#include <string>
#include <vector>

#include "cogmap/core/pose2.h"

namespace cogmap::io {

struct Rgb {
  uint8_t r = 0, g = 0, b = 0;
  bool operator==(const Rgb&) const = default;
};

// An 8-bit RGB raster, row 0 at the top (image convention): pixels read from
// or written to PNG files. Drawing on rasters is cogmap/draw's (cairo).
class RgbImage {
 public:
  RgbImage() = default;
  RgbImage(int width, int height, Rgb fill = {255, 255, 255})
      : width_(width), height_(height), pixels_(static_cast<size_t>(width) * height, fill) {}

  int width() const { return width_; }
  int height() const { return height_; }
  Rgb& at(int x, int y) { return pixels_[static_cast<size_t>(y) * width_ + x]; }
  const Rgb& at(int x, int y) const { return pixels_[static_cast<size_t>(y) * width_ + x]; }
  bool Inside(int x, int y) const { return x >= 0 && y >= 0 && x < width_ && y < height_; }
  void Set(int x, int y, Rgb c) {
    if (Inside(x, y)) at(x, y) = c;
  }
  const std::vector<Rgb>& pixels() const { return pixels_; }

 private:
  int width_ = 0, height_ = 0;
  std::vector<Rgb> pixels_;
};

// Writes an RGB PNG atomically (see WriteFileAtomically).
void WritePng(const std::string& path, const RgbImage& image);
// Encodes to PNG bytes in memory.
std::string EncodePng(const RgbImage& image);
// Encodes an 8-bit RGB image row by row into 'out' (row(y, rgb) fills row y,
// 3 x width bytes), without holding the image: drawings, whose large flat
// areas compress well with the fastest settings (no row filter, zlib level 1).
// nine_rooms' 2000 x 1731 px plan.png: `--outputs plan` 0.229 -> 0.173 s for
// the whole command, the file 186 -> 248 KB (cairo's writer: libpng's
// adaptive row filters and zlib level 6).
void EncodeRgbPngRows(int width, int height, const std::function<void(int y, uint8_t* rgb)>& row, std::ostream& out);
// Encodes an 8-bit grey image (row 0 on top) to PNG bytes.
std::string EncodeGreyPng(int width, int height, const std::vector<uint8_t>& grey);

// Reads a PNG as 8-bit grey (colour is converted by luminance). Throws
// InputError naming the file for a missing or corrupt PNG.
struct GreyImage {
  int width = 0, height = 0;
  std::vector<uint8_t> pixels;  // row 0 on top
};
GreyImage ReadGreyPng(const std::string& path);
// Reads a PNG as 8-bit RGB.
RgbImage ReadRgbPng(const std::string& path);

}  // namespace cogmap::io
