#pragma once
// Helpers shared by the log reader tests.
#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <zlib.h>

#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "cogmap/core/error.h"
#include "cogmap/io/log_reader.h"
#include "cogmap/core/test_temp.h"

namespace cogmap::io::testing_util {

inline std::string WriteTemp(const std::string& name, const std::string& content) {
  const std::string path = ::cogmap::testing_util::TestTempPath(name);
  std::ofstream(path, std::ios::binary) << content;
  return path;
}

inline std::string FileBytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

inline std::string GzipBytes(const std::string& content) {
  uLongf cap = compressBound(content.size()) + 64;
  std::string out(cap, '\0');
  z_stream zs{};
  deflateInit2(&zs, 6, Z_DEFLATED, 15 + 16, 8, Z_DEFAULT_STRATEGY);  // gzip wrapper
  zs.next_in = reinterpret_cast<Bytef*>(const_cast<char*>(content.data()));
  zs.avail_in = content.size();
  zs.next_out = reinterpret_cast<Bytef*>(out.data());
  zs.avail_out = cap;
  deflate(&zs, Z_FINISH);
  out.resize(zs.total_out);
  deflateEnd(&zs);
  return out;
}

inline std::vector<sensors::LogRecord> ReadAll(LogReader& r) {
  std::vector<sensors::LogRecord> out;
  sensors::LogRecord rec;
  while (r.Next(&rec)) out.push_back(rec);
  return out;
}

inline std::vector<sensors::LogRecord> ReadAll(const std::string& path, const std::string& format) {
  auto r = OpenLog(path, format);
  return ReadAll(*r);
}

// The InputError message from opening and reading 'path' to the end.
inline std::string ErrorReading(const std::string& path, const std::string& format) {
  try {
    ReadAll(path, format);
  } catch (const InputError& e) {
    return e.what();
  }
  return "no error";
}

}  // namespace cogmap::io::testing_util
