#include "cogmap/io/read_ahead.h"

#include <algorithm>
#include <utility>

namespace cogmap::io {

ReadAhead::ReadAhead(LogReader& inner, size_t batch, size_t batches)
    : inner_(inner),
      path_(inner.path()),
      batch_(std::max<size_t>(1, batch)),
      batches_(std::max<size_t>(1, batches)),
      thread_([this] { Read(); }) {}

ReadAhead::~ReadAhead() {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    stop_ = true;
  }
  space_.notify_all();
  thread_.join();
}

void ReadAhead::Read() {
  for (;;) {
    // A batch handed back by the caller when there is one: its records'
    // readings keep their storage, so reading allocates nothing once the
    // first batches have been through.
    Batch b;
    {
      std::lock_guard<std::mutex> lock(mutex_);
      if (!free_.empty()) {
        b = std::move(free_.back());
        free_.pop_back();
      }
    }
    b.count = 0;
    b.end = false;
    b.error = nullptr;
    try {
      while (b.count < batch_) {
        // One record object read into again and again, as a caller of the
        // wrapped reader would (what a reader leaves unset stays as it was).
        if (!inner_.Next(&record_)) {
          b.end = true;
          break;
        }
        if (b.count < b.records.size()) b.records[b.count] = record_;
        else b.records.push_back(record_);
        ++b.count;
      }
    } catch (...) {
      b.error = std::current_exception();
      b.end = true;
    }
    b.progress = inner_.progress();
    const bool end = b.end;
    {
      std::unique_lock<std::mutex> lock(mutex_);
      space_.wait(lock, [this] { return stop_ || queue_.size() < batches_; });
      if (stop_) return;
      queue_.push_back(std::move(b));
    }
    ready_.notify_one();
    if (end) return;
  }
}

bool ReadAhead::Next(sensors::LogRecord* record) {
  while (pos_ == current_.count) {
    if (current_.end) {
      if (current_.error) std::rethrow_exception(current_.error);
      return false;
    }
    {
      std::unique_lock<std::mutex> lock(mutex_);
      if (!current_.records.empty()) free_.push_back(std::move(current_));
      ready_.wait(lock, [this] { return !queue_.empty(); });
      current_ = std::move(queue_.front());
      queue_.pop_front();
    }
    space_.notify_one();
    pos_ = 0;
    progress_ = current_.progress;
  }
  // Copied, not moved: the caller's record and the batch's both keep their
  // readings' storage for the next ones.
  *record = current_.records[pos_++];
  return true;
}

}  // namespace cogmap::io
