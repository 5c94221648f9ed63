#pragma once
#include <atomic>
#include <cstddef>
#include <exception>
#include <mutex>
#include <thread>

namespace cogmap {

// Calls f(i) once for each i in [0, n), the i shared out over this thread
// and, with threads >= 2 and n >= 2, one helper (the machines cogmap runs on
// have two cores), in no fixed order between them: each f(i) must touch only
// what belongs to i. The first exception a call raises stops both from
// taking further i and is raised here once both have stopped.
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
  std::thread helper;
  if (threads >= 2 && n >= 2) helper = std::thread(work);
  work();
  if (helper.joinable()) helper.join();
  if (failed) std::rethrow_exception(failed);
}

}  // namespace cogmap
