#include "cogmap/vectorize/polyline_codec.h"

#include <cmath>

#include "cogmap/core/error.h"

namespace cogmap::vectorize {
namespace {

void PutVarint(std::string* out, uint64_t v) {
  while (v >= 0x80) {
    out->push_back(static_cast<char>((v & 0x7f) | 0x80));
    v >>= 7;
  }
  out->push_back(static_cast<char>(v));
}

void PutSigned(std::string* out, int64_t v) {
  PutVarint(out, (static_cast<uint64_t>(v) << 1) ^ static_cast<uint64_t>(v >> 63));
}

class Reader {
 public:
  Reader(const std::string& bytes, const std::string& source) : b_(bytes), source_(source) {}
  uint64_t Varint() {
    uint64_t v = 0;
    for (int shift = 0; shift < 64; shift += 7) {
      if (pos_ >= b_.size()) Fail("truncated varint");
      const uint8_t c = static_cast<uint8_t>(b_[pos_++]);
      v |= static_cast<uint64_t>(c & 0x7f) << shift;
      if (!(c & 0x80)) return v;
    }
    Fail("varint too long");
    return 0;
  }
  int64_t Signed() {
    const uint64_t u = Varint();
    return static_cast<int64_t>(u >> 1) ^ -static_cast<int64_t>(u & 1);
  }
  size_t pos() const { return pos_; }
  size_t remaining() const { return b_.size() - pos_; }
  [[noreturn]] void Fail(const std::string& what) const {
    throw InputError(source_, -1, "byte " + std::to_string(pos_) + ": " + what);
  }
  void Skip(size_t n) { pos_ += n; }

 private:
  const std::string& b_;
  const std::string& source_;
  size_t pos_ = 0;
};

constexpr char kMagic[4] = {'C', 'P', 'L', 1};

}  // namespace

std::string EncodePolylines(const std::vector<Polyline>& lines, const PolylineCodecOptions& options) {
  std::string out(kMagic, 4);
  const int q_mm = options.quantum_mm > 0 ? options.quantum_mm : 10;
  const double q = q_mm / 1000.0;
  PutVarint(&out, static_cast<uint64_t>(q_mm));
  PutVarint(&out, lines.size());
  for (const auto& line : lines) {
    PutVarint(&out, line.size());
    int64_t px = 0, py = 0;
    for (const auto& v : line) {
      const int64_t x = std::llround(v.x() / q), y = std::llround(v.y() / q);
      PutSigned(&out, x - px);
      PutSigned(&out, y - py);
      px = x;
      py = y;
    }
  }
  return out;
}

std::vector<Polyline> DecodePolylines(const std::string& bytes, const std::string& source) {
  Reader r(bytes, source);
  if (bytes.size() < 4 || bytes.compare(0, 4, std::string(kMagic, 4)) != 0)
    r.Fail("not a cogmap polyline encoding (bad magic)");
  r.Skip(4);
  const uint64_t q_mm = r.Varint();
  if (q_mm == 0 || q_mm > 1000000) r.Fail("bad quantum " + std::to_string(q_mm));
  const double q = q_mm / 1000.0;
  const uint64_t count = r.Varint();
  // Each polyline needs at least one byte.
  if (count > r.remaining()) r.Fail("polyline count " + std::to_string(count) + " exceeds the data");
  std::vector<Polyline> lines;
  lines.reserve(count);
  for (uint64_t i = 0; i < count; ++i) {
    const uint64_t n = r.Varint();
    if (n > r.remaining() / 2) r.Fail("vertex count " + std::to_string(n) + " exceeds the data");
    Polyline line;
    line.reserve(n);
    int64_t x = 0, y = 0;
    for (uint64_t j = 0; j < n; ++j) {
      x += r.Signed();
      y += r.Signed();
      line.push_back(Vec2(x * q, y * q));
    }
    lines.push_back(std::move(line));
  }
  if (r.remaining() != 0) r.Fail("trailing bytes after the last polyline");
  return lines;
}

}  // namespace cogmap::vectorize
