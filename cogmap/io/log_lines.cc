#include "cogmap/io/log_lines.h"

#include <zlib.h>

#include <algorithm>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstring>
#include <filesystem>

#include "cogmap/core/error.h"

namespace cogmap::io {

namespace {
constexpr size_t kMaxLineBytes = size_t{64} << 20;
}

LineSource::LineSource(const std::string& path) : path_(path) {
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec)) throw InputError(path, 0, "is a folder, not a log file");
  gzFile f = gzopen(path.c_str(), "rb");
  if (!f) throw InputError(path, 0, std::string("cannot open: ") + std::strerror(errno ? errno : ENOENT));
  gzbuffer(f, 1 << 17);
  gz_ = f;
  const auto size = std::filesystem::file_size(path, ec);
  size_bytes_ = ec ? 0.0 : static_cast<double>(size);
}

LineSource::~LineSource() {
  if (gz_) gzclose_r(static_cast<gzFile>(gz_));
}

bool LineSource::Next(std::string* line) {
  if (done_) return false;
  gzFile f = static_cast<gzFile>(gz_);
  line->clear();
  char buf[8192];
  bool got = false;
  while (true) {
    if (!gzgets(f, buf, sizeof buf)) break;
    got = true;
    const size_t n = std::strlen(buf);
    line->append(buf, n);
    if (n > 0 && buf[n - 1] == '\n') break;
    if (line->size() > kMaxLineBytes)
      throw InputError(path_, line_ + 1, "line longer than 64 MiB (not a text log?)");
  }
  // zlib flags a truncated stream as soon as its read-ahead hits the end of
  // the file, while whole lines are still buffered: report it only when the
  // data runs out (no line, or a last line cut short).
  const bool complete = got && !line->empty() && line->back() == '\n';
  int err = Z_OK;
  const char* msg = gzerror(f, &err);
  if (!complete && err != Z_OK && err != Z_STREAM_END) {
    const std::string what = err == Z_ERRNO ? std::string(std::strerror(errno)) : std::string(msg ? msg : "");
    throw InputError(path_, line_ + 1, "truncated or corrupt gzip data (" + what + ")");
  }
  if (!got) {
    done_ = true;
    return false;
  }
  ++line_;
  while (!line->empty() && (line->back() == '\n' || line->back() == '\r')) line->pop_back();
  return true;
}

double LineSource::progress() const {
  if (done_) return 1.0;
  if (size_bytes_ <= 0) return 0.0;
  const double off = static_cast<double>(gzoffset(static_cast<gzFile>(gz_)));
  return std::clamp(off / size_bytes_, 0.0, 1.0);
}

std::vector<std::string_view> SplitFields(std::string_view s) {
  std::vector<std::string_view> out;
  size_t i = 0;
  while (i < s.size()) {
    while (i < s.size() && (s[i] == ' ' || s[i] == '\t')) ++i;
    if (i >= s.size()) break;
    size_t j = i;
    while (j < s.size() && s[j] != ' ' && s[j] != '\t') ++j;
    out.push_back(s.substr(i, j - i));
    i = j;
  }
  return out;
}

double ParseNumber(std::string_view t, const std::string& path, long line, const std::string& what) {
  std::string_view s = t;
  if (!s.empty() && s[0] == '+') s.remove_prefix(1);
  double v = 0;
  const auto [p, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
  if (s.empty() || (ec != std::errc() && ec != std::errc::result_out_of_range) || p != s.data() + s.size())
    throw InputError(path, line, what + ": '" + std::string(t) + "' is not a number");
  if (ec == std::errc::result_out_of_range || !std::isfinite(v))
    throw InputError(path, line, what + ": '" + std::string(t) + "' is not a finite number");
  return v;
}

long ParseCount(std::string_view t, const std::string& path, long line, const std::string& what) {
  long v = 0;
  const auto [p, ec] = std::from_chars(t.data(), t.data() + t.size(), v);
  if (t.empty() || ec != std::errc() || p != t.data() + t.size() || v < 0)
    throw InputError(path, line, what + ": '" + std::string(t) + "' is not a whole number >= 0");
  return v;
}

void CheckRange(double r, const std::string& path, long line, const std::string& what) {
  if (r < 0) throw InputError(path, line, what + ": negative range " + std::to_string(r) + " m");
  if (r > kAbsurdRangeM)
    throw InputError(path, line, what + ": absurd range " + std::to_string(r) + " m (more than 1000 m)");
}

void ThrowEmptyLog(const std::string& path) { throw InputError(path, 0, "empty log: no range readings"); }

}  // namespace cogmap::io
