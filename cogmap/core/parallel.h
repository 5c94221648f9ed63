#pragma once
#include <algorithm>
#include <atomic>
#include <cstddef>
#include <exception>
#include <functional>
#include <mutex>
#include <vector>

namespace cogmap {

namespace detail {
// Runs 'work' on this thread and on up to 'helpers' threads of a pool kept
// for the life of the process (started when first wanted; a helper the
// system cannot start is done without), and returns once every thread that
// took it has returned from it. A helper busy elsewhere (a nested call)
// leaves its share to the others: 'work' must take its share of the work
// itself until none is left, so that any number of threads, this one alone
// included, finish it. A mapping run shares out work a hundred times and
// more (each ASR's loop-closure candidates): a thread started and joined
// for each cost a clone, a stack mapped and unmapped, and the page faults
// of a fresh stack every time.
void RunOnHelpers(const std::function<void()>& work, size_t helpers);
}  // namespace detail

// Calls f(i) once for each i in [0, n), the i shared out over this thread
// and, with threads >= 2 and n >= 2, up to threads - 1 helpers (the mapping
// passes its --threads, 2: the machines cogmap runs on have two cores; work
// that waits on the disk asks for more), in no fixed order between them:
// each f(i) must touch only what belongs to i. The first exception a call
// raises stops every thread from taking further i and is raised here once
// all have stopped.
template <class F>
void ForEachShared(size_t n, int threads, F&& f) {
  std::atomic<size_t> next{0};
  std::exception_ptr failed;
  std::mutex failed_mutex;
  const std::function<void()> work = [&] {
    try {
      for (size_t i; (i = next++) < n;) f(i);
    } catch (...) {
      std::lock_guard<std::mutex> lock(failed_mutex);
      if (!failed) failed = std::current_exception();
      next = n;
    }
  };
  const size_t wanted = threads >= 2 && n >= 2 ? std::min(static_cast<size_t>(threads), n) - 1 : 0;
  if (wanted == 0) work();
  else detail::RunOnHelpers(work, wanted);
  if (failed) std::rethrow_exception(failed);
}

}  // namespace cogmap
