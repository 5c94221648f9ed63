#pragma once
#include <condition_variable>
#include <cstddef>
#include <deque>
#include <exception>
#include <mutex>
#include <thread>
#include <vector>

#include "cogmap/io/log_reader.h"

namespace cogmap::io {

// A log read on a thread of its own, a few batches of records ahead of the
// caller, so that decompressing and parsing it overlap with what the caller
// does with the records (`cogmap map`: the grids). Next() gives the wrapped
// reader's records in their order; where the wrapped reader raised an error,
// Next() raises it, after every record read before it. progress() is the
// wrapped reader's at the end of the batch being handed out.
//
// The wrapped reader is used by the reading thread alone until Next() has
// returned false or raised (or this is destroyed, which stops the thread
// after the record it is reading): only then ask it for skipped().
// Not for a log that may block for long between records (standard input
// from a live robot): destroying this early waits for the record being read.
class ReadAhead : public LogReader {
 public:
  // 'batch' records a batch, at most 'batches' batches read ahead.
  explicit ReadAhead(LogReader& inner, size_t batch = 64, size_t batches = 4);
  ~ReadAhead() override;
  ReadAhead(const ReadAhead&) = delete;
  ReadAhead& operator=(const ReadAhead&) = delete;

  bool Next(sensors::LogRecord* record) override;
  double progress() const override { return progress_; }
  const std::string& path() const override { return path_; }

 private:
  struct Batch {
    std::vector<sensors::LogRecord> records;  // the first 'count' hold records
    size_t count = 0;
    double progress = 0.0;      // the wrapped reader's after the batch's last record
    bool end = false;           // the log ends (or fails) after this batch
    std::exception_ptr error;   // why it failed, when it did
  };
  void Read();

  LogReader& inner_;
  sensors::LogRecord record_;  // the reading thread's
  const std::string path_;
  const size_t batch_, batches_;
  std::mutex mutex_;
  std::condition_variable ready_, space_;
  std::deque<Batch> queue_;
  std::vector<Batch> free_;  // batches handed back by the caller, to be read into again
  bool stop_ = false;
  // The caller's side.
  Batch current_;
  size_t pos_ = 0;
  double progress_ = 0.0;
  std::thread thread_;  // last: started once the rest is in place
};

}  // namespace cogmap::io
