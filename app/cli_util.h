#pragma once
// Small helpers shared by the cmd_*.cc files.
#include <chrono>
#include <cstdio>
#include <string>
#include <vector>

namespace cogmap::app {

// "a, b, c" (for option help texts).
inline std::string Join(const std::vector<std::string>& items) {
  std::string s;
  for (const auto& x : items) s += (s.empty() ? "" : ", ") + x;
  return s;
}

// A number as a user typed it ("%g"), for messages.
inline std::string Num(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%g", v);
  return buf;
}

// Wall-clock seconds since 'since'.
inline double Seconds(std::chrono::steady_clock::time_point since) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - since).count();
}

}  // namespace cogmap::app
