#pragma once
// A file read first in a child process, for libraries that trust the sizes
// and offsets a file states. librosbag reads a message's header at whatever
// offset and length a bag's index and records say (a damaged bag: SIGBUS or
// SIGSEGV inside librosbag); MRPT sizes a container from a count in a rawlog
// before reading what it counts (a damaged count: gigabytes and minutes of
// allocation). Neither can be checked from outside before the library reads,
// so the whole file is read once in a child whose address space and CPU time
// are bounded; only a file the child read to its end is read by cogmap itself.
#include <cstdint>
#include <functional>
#include <string>

namespace cogmap::io {

struct ChildCheckLimits {
  // Address space the child may add to what it inherits: floor + per_byte x
  // the file's size (honest readers stream: a message or an entry at a time).
  uint64_t memory_floor_bytes = uint64_t{256} << 20;
  double memory_per_file_byte = 16.0;
  // CPU seconds: floor + per MB of the file.
  double cpu_floor_s = 30.0;
  double cpu_s_per_mb = 1.0;
};

// Runs read_all(count) in a child process, read_all counting the messages or
// entries it read into *count. Returns when the child returned normally (or
// when it cannot be started: then the file is read here unchecked). Throws
// InputError when the child threw one (the same message), and otherwise
// "PATH: a damaged <kind>: <library> <what happened> after N <items>" when the
// child crashed, ran out of its memory or its CPU time, or threw anything
// else. A file is checked once per process (same path, size and time).
void CheckInChild(const std::string& path, const std::string& kind, const std::string& library,
                  const std::string& items, const std::function<void(long* count)>& read_all,
                  const ChildCheckLimits& limits = {});

}  // namespace cogmap::io
