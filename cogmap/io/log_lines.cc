#include "cogmap/io/log_lines.h"

#include <zlib.h>

#include <algorithm>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <streambuf>

#include <unistd.h>

#include "cogmap/core/error.h"

namespace cogmap::io {

namespace {
constexpr size_t kMaxLineBytes = size_t{64} << 20;

// Standard input, read once per process (a pipe cannot be rewound).
struct StdinState {
  bool head_read = false;
  bool at_eof = false;  // the head is all of standard input
  bool taken = false;
  std::string head;
};

StdinState& Stdin() {
  static StdinState state;
  return state;
}

// Reads up to n bytes of fd 0; 0 at its end.
size_t ReadStdin(char* buf, size_t n) {
  while (true) {
    const ssize_t got = ::read(0, buf, n);
    if (got >= 0) return static_cast<size_t>(got);
    if (errno != EINTR) throw InputError(kStdinName, 0, std::string("cannot read: ") + std::strerror(errno));
  }
}

StdinState& StdinWithHead() {
  StdinState& s = Stdin();
  if (s.head_read) return s;
  s.head_read = true;
  s.head.resize(kStdinHeadBytes);
  size_t have = 0;
  while (have < kStdinHeadBytes) {
    const size_t n = ReadStdin(s.head.data() + have, kStdinHeadBytes - have);
    if (n == 0) {
      s.at_eof = true;
      break;
    }
    have += n;
  }
  s.head.resize(have);
  return s;
}

// Serves the head, then reads fd 0.
class StdinReplayBuf : public std::streambuf {
 public:
  StdinReplayBuf() : buf_(size_t{1} << 16) {
    StdinState& s = StdinWithHead();
    head_ = s.head;  // a copy: the head lines may still be asked for
    at_eof_ = s.at_eof;
    char* p = head_.data();
    setg(p, p, p + head_.size());
  }

 protected:
  int_type underflow() override {
    if (gptr() < egptr()) return traits_type::to_int_type(*gptr());
    if (at_eof_) return traits_type::eof();
    const size_t n = ReadStdin(buf_.data(), buf_.size());
    if (n == 0) {
      at_eof_ = true;
      return traits_type::eof();
    }
    setg(buf_.data(), buf_.data(), buf_.data() + n);
    return traits_type::to_int_type(*gptr());
  }

 private:
  std::string head_;
  std::vector<char> buf_;
  bool at_eof_ = false;
};

class StdinStream : public std::istream {
 public:
  StdinStream() : std::istream(nullptr) { rdbuf(&buf_); }

 private:
  StdinReplayBuf buf_;
};

}  // namespace

std::string StdinHead(bool* whole_out) {
  const StdinState& s = StdinWithHead();
  std::string text;
  bool whole = s.at_eof;
  if (s.head.size() >= 2 && static_cast<unsigned char>(s.head[0]) == 0x1f &&
      static_cast<unsigned char>(s.head[1]) == 0x8b) {
    // As much text as the compressed head gives.
    z_stream zs{};
    inflateInit2(&zs, 15 + 16);
    zs.next_in = reinterpret_cast<Bytef*>(const_cast<char*>(s.head.data()));
    zs.avail_in = static_cast<uInt>(s.head.size());
    std::vector<char> out(size_t{1} << 16);
    int ret = Z_OK;
    while (ret == Z_OK && text.size() < (size_t{4} << 20)) {
      zs.next_out = reinterpret_cast<Bytef*>(out.data());
      zs.avail_out = static_cast<uInt>(out.size());
      ret = inflate(&zs, Z_NO_FLUSH);
      text.append(out.data(), out.size() - zs.avail_out);
      if (ret == Z_BUF_ERROR || zs.avail_out == out.size()) break;
    }
    whole = whole && ret == Z_STREAM_END;
    inflateEnd(&zs);
  } else {
    text = s.head;
  }
  if (whole_out) *whole_out = whole;
  return text;
}

std::vector<std::string> StdinHeadLines(size_t max_lines) {
  bool whole = false;
  const std::string text = StdinHead(&whole);
  std::vector<std::string> lines;
  size_t i = 0;
  while (i < text.size() && lines.size() < max_lines) {
    const size_t nl = text.find('\n', i);
    if (nl == std::string::npos && !whole) break;  // cut by the head's end
    std::string line = text.substr(i, nl == std::string::npos ? std::string::npos : nl - i);
    while (!line.empty() && line.back() == '\r') line.pop_back();
    lines.push_back(std::move(line));
    if (nl == std::string::npos) break;
    i = nl + 1;
  }
  return lines;
}

std::unique_ptr<std::istream> TakeStdin() {
  StdinState& s = Stdin();
  if (s.taken) throw InputError(kStdinName, 0, "standard input was already read (give '-' once)");
  s.taken = true;
  return std::make_unique<StdinStream>();
}

StdinCopy::StdinCopy() {
  std::string templ = (std::filesystem::temp_directory_path() / "cogmap-stdin-XXXXXX").string();
  const int fd = ::mkstemp(templ.data());
  if (fd < 0)
    throw InputError(kStdinName, 0, "cannot create a temporary file for standard input: " + std::string(std::strerror(errno)));
  path_ = templ;
  auto in = TakeStdin();
  std::vector<char> buf(size_t{1} << 16);
  while (true) {
    in->read(buf.data(), static_cast<std::streamsize>(buf.size()));
    const auto n = static_cast<size_t>(in->gcount());
    if (n == 0) break;
    for (size_t done = 0; done < n;) {
      const ssize_t w = ::write(fd, buf.data() + done, n - done);
      if (w < 0 && errno == EINTR) continue;
      if (w <= 0) {
        const std::string why = std::strerror(errno);
        ::close(fd);
        std::remove(path_.c_str());
        throw InputError(kStdinName, 0, "cannot write the copy of standard input to " + path_ + ": " + why);
      }
      done += static_cast<size_t>(w);
    }
  }
  ::close(fd);
}

StdinCopy::~StdinCopy() { std::remove(path_.c_str()); }

// A stream read through a buffer: plain bytes, or gzip members inflated.
struct LineSource::Stream {
  std::unique_ptr<std::istream> in;
  bool gzip = false;
  bool zs_init = false;
  bool member_end = false;  // the current gzip member is complete
  bool in_eof = false;
  z_stream zs{};
  std::vector<char> inbuf = std::vector<char>(size_t{1} << 16);
  std::vector<char> out = std::vector<char>(size_t{1} << 16);
  size_t pos = 0, len = 0;

  ~Stream() {
    if (zs_init) inflateEnd(&zs);
  }

  // Reads more raw bytes into inbuf when it is empty.
  void Refill() {
    if (zs.avail_in > 0 || in_eof) return;
    in->read(inbuf.data(), static_cast<std::streamsize>(inbuf.size()));
    const auto n = static_cast<size_t>(in->gcount());
    if (n == 0) in_eof = true;
    zs.next_in = reinterpret_cast<Bytef*>(inbuf.data());
    zs.avail_in = static_cast<uInt>(n);
  }

  // Tells plain from gzip by the first two bytes.
  void Start() {
    Refill();
    gzip = zs.avail_in >= 2 && static_cast<unsigned char>(inbuf[0]) == 0x1f &&
           static_cast<unsigned char>(inbuf[1]) == 0x8b;
    if (gzip) {
      inflateInit2(&zs, 15 + 16);
      zs_init = true;
    } else {
      std::copy(inbuf.begin(), inbuf.begin() + zs.avail_in, out.begin());
      len = zs.avail_in;
      pos = 0;
      zs.avail_in = 0;
    }
  }

  // Decoded bytes into out[0, len). False at the end; 'error' set (and false
  // returned) for a truncated or corrupt gzip stream or a read error.
  bool Fill(std::string* error) {
    pos = len = 0;
    if (!gzip) {
      if (in_eof) return false;
      in->read(out.data(), static_cast<std::streamsize>(out.size()));
      len = static_cast<size_t>(in->gcount());
      if (in->bad()) *error = "read error";
      if (len == 0) in_eof = true;
      return len > 0 && error->empty();
    }
    while (true) {
      Refill();
      if (member_end) {
        // Another member follows, or the end (anything else after a member is
        // ignored, as gzread does).
        if (zs.avail_in == 0 || static_cast<unsigned char>(*zs.next_in) != 0x1f) return false;
        inflateReset(&zs);
        member_end = false;
      }
      zs.next_out = reinterpret_cast<Bytef*>(out.data());
      zs.avail_out = static_cast<uInt>(out.size());
      const int ret = inflate(&zs, Z_NO_FLUSH);
      if (ret == Z_STREAM_END) {
        member_end = true;
      } else if (ret != Z_OK && ret != Z_BUF_ERROR) {
        *error = zs.msg ? zs.msg : "inflate error " + std::to_string(ret);
        return false;
      }
      len = out.size() - zs.avail_out;
      if (len > 0) return true;
      if (!member_end && zs.avail_in == 0 && in_eof) {
        *error = in->bad() ? "read error" : "unexpected end of file";
        return false;
      }
    }
  }
};

LineSource::LineSource(const std::string& path) : path_(path) {
  if (path == kStdinPath) {
    path_ = kStdinName;
    stream_ = std::make_unique<Stream>();
    stream_->in = TakeStdin();
    stream_->Start();
    return;
  }
  OpenFile(path);
}

LineSource::LineSource(const std::string& path, const std::string& name) : path_(name) { OpenFile(path); }

LineSource::LineSource(std::unique_ptr<std::istream> in, const std::string& name) : path_(name) {
  stream_ = std::make_unique<Stream>();
  stream_->in = std::move(in);
  stream_->Start();
}

void LineSource::OpenFile(const std::string& path) {
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec)) throw InputError(path_, 0, "is a folder, not a log file");
  open_path_ = path;
  gzFile f = gzopen(path.c_str(), "rb");
  if (!f) throw InputError(path_, 0, std::string("cannot open: ") + std::strerror(errno ? errno : ENOENT));
  gzbuffer(f, 1 << 17);
  gz_ = f;
  const auto size = std::filesystem::file_size(path, ec);
  size_bytes_ = ec ? 0.0 : static_cast<double>(size);
}

LineSource::~LineSource() {
  if (gz_) gzclose_r(static_cast<gzFile>(gz_));
}

bool LineSource::NextFromStream(std::string* line) {
  Stream& s = *stream_;
  line->clear();
  bool got = false;
  terminated_ = false;
  while (true) {
    if (s.pos == s.len) {
      std::string error;
      if (!s.Fill(&error)) {
        if (!error.empty()) throw InputError(path_, line_ + 1, "truncated or corrupt gzip data (" + error + ")");
        break;
      }
    }
    got = true;
    const char* begin = s.out.data() + s.pos;
    const char* end = s.out.data() + s.len;
    const char* nl = std::find(begin, end, '\n');
    line->append(begin, nl);
    s.pos = static_cast<size_t>(nl - s.out.data());
    if (nl != end) {
      ++s.pos;
      terminated_ = true;
      break;
    }
    if (line->size() > kMaxLineBytes)
      throw InputError(path_, line_ + 1, "line longer than 64 MiB (not a text log?)");
  }
  if (!got) {
    done_ = true;
    return false;
  }
  ++line_;
  while (!line->empty() && line->back() == '\r') line->pop_back();
  return true;
}

bool LineSource::Next(std::string* line) {
  if (done_) return false;
  if (stream_) return NextFromStream(line);
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
    std::string what = err == Z_ERRNO ? std::string(std::strerror(errno)) : std::string(msg ? msg : "");
    // zlib prefixes the path it opened (a temporary copy of standard input).
    if (what.rfind(open_path_ + ": ", 0) == 0) what.erase(0, open_path_.size() + 2);
    throw InputError(path_, line_ + 1, "truncated or corrupt gzip data (" + what + ")");
  }
  if (!got) {
    done_ = true;
    return false;
  }
  ++line_;
  terminated_ = complete;
  while (!line->empty() && (line->back() == '\n' || line->back() == '\r')) line->pop_back();
  return true;
}

double LineSource::progress() const {
  if (done_) return 1.0;
  if (stream_ || size_bytes_ <= 0) return 0.0;
  const double off = static_cast<double>(gzoffset(static_cast<gzFile>(gz_)));
  return std::clamp(off / size_bytes_, 0.0, 1.0);
}

std::vector<std::string_view> SplitFields(std::string_view s) {
  std::vector<std::string_view> out;
  // Room for a sonar ring's line at once (fields are at least two characters
  // apart), instead of growing through 1, 2, 4, 8, 16 and 32.
  out.reserve(std::min<size_t>(s.size() / 2 + 1, 48));
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
  // %g: a range of 1e308 printed with std::to_string ran to 309 digits.
  char text[96];
  if (r < 0) {
    std::snprintf(text, sizeof text, ": negative range %g m", r);
    throw InputError(path, line, what + text);
  }
  if (r > kAbsurdRangeM) {
    std::snprintf(text, sizeof text, ": absurd range %g m (more than 1000 m)", r);
    throw InputError(path, line, what + text);
  }
}

const Pose2& CheckPosition(const Pose2& pose, const std::string& path, long line, const std::string& what) {
  if (std::abs(pose.x) <= kAbsurdPositionM && std::abs(pose.y) <= kAbsurdPositionM) return pose;
  throw InputError(path, line, what + ": " + AbsurdPosition(pose));
}

void ThrowEmptyLog(const std::string& path) { throw InputError(path, 0, "empty log: no range readings"); }

}  // namespace cogmap::io
