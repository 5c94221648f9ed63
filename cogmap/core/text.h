#pragma once
// printf-style formatting into a string (reports the library returns as text).
#include <cstdarg>
#include <cstdio>
#include <string>

namespace cogmap {

// Appends the formatted text to *out (at most 1023 characters per call).
inline void AppendF(std::string* out, const char* format, ...) __attribute__((format(printf, 2, 3)));
inline void AppendF(std::string* out, const char* format, ...) {
  char buf[1024];
  va_list args;
  va_start(args, format);
  std::vsnprintf(buf, sizeof buf, format, args);
  va_end(args);
  *out += buf;
}

}  // namespace cogmap
