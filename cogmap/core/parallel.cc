#include "cogmap/core/parallel.h"

#include <condition_variable>
#include <deque>
#include <system_error>
#include <thread>

namespace cogmap::detail {
namespace {

// One call's work, offered to the helpers: each entry of the queue is one
// helper's place in it.
struct Offer {
  const std::function<void()>* work = nullptr;
  int taken = 0;     // helpers that took a place (under the pool's mutex)
  int finished = 0;  // of those, returned from the work
};

class Pool {
 public:
  void Run(const std::function<void()>& work, size_t helpers) {
    Offer offer{&work};
    {
      std::lock_guard<std::mutex> lock(mutex_);
      while (started_ < helpers) {
        try {
          std::thread([this] { Serve(); }).detach();
        } catch (const std::system_error&) {
          break;  // fewer helpers: the others and this thread do the work
        }
        ++started_;
      }
      for (size_t k = 0; k < std::min(helpers, started_); ++k) queue_.push_back(&offer);
    }
    wake_.notify_all();
    work();
    std::unique_lock<std::mutex> lock(mutex_);
    // The places no helper took (the work is done): withdrawn; then wait
    // for the helpers inside it, so that 'offer' and 'work' outlive them.
    queue_.erase(std::remove(queue_.begin(), queue_.end(), &offer), queue_.end());
    done_.wait(lock, [&] { return offer.finished == offer.taken; });
  }

 private:
  void Serve() {
    std::unique_lock<std::mutex> lock(mutex_);
    for (;;) {
      wake_.wait(lock, [&] { return !queue_.empty(); });
      Offer* offer = queue_.front();
      queue_.pop_front();
      ++offer->taken;
      lock.unlock();
      (*offer->work)();
      lock.lock();
      ++offer->finished;
      done_.notify_all();
    }
  }

  std::mutex mutex_;
  std::condition_variable wake_, done_;
  std::deque<Offer*> queue_;
  size_t started_ = 0;
};

}  // namespace

void RunOnHelpers(const std::function<void()>& work, size_t helpers) {
  // Never destroyed: its helpers wait on it until the process exits.
  static Pool* const pool = new Pool;
  pool->Run(work, helpers);
}

}  // namespace cogmap::detail
