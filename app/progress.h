#pragma once
#include <chrono>
#include <cstdio>
#include <string>
#include <unistd.h>

namespace cogmap::app {

// A one-line progress bar on stderr, drawn only when stderr is a terminal and
// at most ten times a second. Finish() clears the line.
class ProgressBar {
 public:
  explicit ProgressBar(std::string label)
      : label_(std::move(label)), enabled_(::isatty(2) != 0), last_(std::chrono::steady_clock::now()) {}
  ~ProgressBar() { Finish(); }

  void Update(double fraction, const std::string& extra = "") {
    if (!enabled_) return;
    const auto now = std::chrono::steady_clock::now();
    if (now - last_ < std::chrono::milliseconds(100) && fraction < 1.0) return;
    last_ = now;
    if (fraction < 0) fraction = 0;
    if (fraction > 1) fraction = 1;
    const int width = 30, filled = static_cast<int>(fraction * width);
    std::string bar(filled, '#');
    bar.resize(width, '.');
    std::fprintf(stderr, "\r%s [%s] %3d%% %s\033[K", label_.c_str(), bar.c_str(),
                 static_cast<int>(fraction * 100), extra.c_str());
    std::fflush(stderr);
    drawn_ = true;
  }
  void Finish() {
    if (drawn_) std::fprintf(stderr, "\r\033[K");
    drawn_ = false;
  }

 private:
  std::string label_;
  bool enabled_;
  bool drawn_ = false;
  std::chrono::steady_clock::time_point last_;
};

}  // namespace cogmap::app
