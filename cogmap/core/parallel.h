#pragma once
#include <algorithm>
#include <atomic>
#include <cstddef>
#include <exception>
#include <mutex>
#include <system_error>
#include <thread>
#include <vector>

namespace cogmap {

// Calls f(i) once for each i in [0, n), the i shared out over this thread
// and, with threads >= 2 and n >= 2, up to threads - 1 helpers (the mapping
// passes its --threads, 2: the machines cogmap runs on have two cores; work
// that waits on the disk asks for more), in no fixed order between them:
// each f(i) must touch only what belongs to i. A helper the system cannot
// start is done without (the others take its share). The first exception a
// call raises stops every thread from taking further i and is raised here
// once all have stopped.
template <class F>
void ForEachShared(size_t n, int threads, F&& f) {
  std::atomic<size_t> next{0};
  std::exception_ptr failed;
  std::mutex failed_mutex;
  auto work = [&] {
    try {
      for (size_t i; (i = next++) < n;) f(i);
    } catch (...) {
      std::lock_guard<std::mutex> lock(failed_mutex);
      if (!failed) failed = std::current_exception();
      next = n;
    }
  };
  std::vector<std::thread> helpers;
  const size_t wanted = threads >= 2 && n >= 2 ? std::min(static_cast<size_t>(threads), n) - 1 : 0;
  try {
    while (helpers.size() < wanted) helpers.emplace_back(work);
  } catch (const std::system_error&) {
    // Fewer helpers: this thread and the ones started take their share.
  }
  work();
  for (auto& t : helpers) t.join();
  if (failed) std::rethrow_exception(failed);
}

}  // namespace cogmap
