#include "cogmap/io/child_check.h"

#include <fcntl.h>
#include <signal.h>
#include <sys/mman.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <mutex>
#include <new>
#include <set>
#include <tuple>

#include "cogmap/core/error.h"

#if defined(__SANITIZE_ADDRESS__)
#define COGMAP_CHILD_CHECK_ASAN 1
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
#define COGMAP_CHILD_CHECK_ASAN 1
#endif
#endif

namespace cogmap::io {
namespace {

// Exit statuses of the child.
constexpr int kReadToEnd = 0;
constexpr int kInputError = 2;
constexpr int kOutOfMemory = 3;
constexpr int kOtherError = 4;

// The process's address space now (bytes), 0 when unknown.
uint64_t AddressSpace() {
  std::ifstream in("/proc/self/statm");
  uint64_t pages = 0;
  if (!(in >> pages)) return 0;
  return pages * static_cast<uint64_t>(::sysconf(_SC_PAGESIZE));
}

void WriteAll(int fd, const std::string& s) {
  size_t done = 0;
  while (done < s.size()) {
    const ssize_t n = ::write(fd, s.data() + done, s.size() - done);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) return;
    done += static_cast<size_t>(n);
  }
}

std::string SignalName(int sig) {
  const char* abbrev = ::sigabbrev_np(sig);
  return abbrev ? std::string("SIG") + abbrev : "signal " + std::to_string(sig);
}

[[noreturn]] void RunChild(int fd, long* count, const std::function<void(long*)>& read_all, uint64_t memory,
                           double cpu_s) {
  const rlimit no_core{0, 0};
  ::setrlimit(RLIMIT_CORE, &no_core);
  // What the library prints on its own (MRPT's and librosbag's messages) is
  // not cogmap's one line: the error goes back through the pipe.
  const int null = ::open("/dev/null", O_WRONLY);
  if (null >= 0) {
    ::dup2(null, STDERR_FILENO);
    ::dup2(null, STDOUT_FILENO);
    ::close(null);
  }
  const rlim_t cpu = static_cast<rlim_t>(std::ceil(cpu_s));
  const rlimit cpu_limit{cpu, cpu + 1};  // SIGXCPU, then SIGKILL a second later
  ::setrlimit(RLIMIT_CPU, &cpu_limit);
#ifndef COGMAP_CHILD_CHECK_ASAN  // (AddressSanitizer reserves terabytes of address space)
  if (memory > 0) {
    const rlimit as{memory, memory};
    ::setrlimit(RLIMIT_AS, &as);
  }
#endif
  int status = kReadToEnd;
  try {
    read_all(count);
  } catch (const InputError& e) {
    WriteAll(fd, e.what());
    status = kInputError;
  } catch (const std::bad_alloc&) {
    status = kOutOfMemory;
  } catch (const std::exception& e) {
    WriteAll(fd, e.what());
    status = kOtherError;
  } catch (...) {
    status = kOtherError;
  }
  ::close(fd);
  ::_exit(status);  // no destructors, no atexit handlers, no stdio flush: the parent's state stays its own
}

}  // namespace

void CheckInChild(const std::string& path, const std::string& kind, const std::string& library,
                  const std::string& items, const std::function<void(long* count)>& read_all,
                  const ChildCheckLimits& limits) {
  struct stat st {};
  if (::stat(path.c_str(), &st) != 0) return;  // the reader says what is wrong
  static std::mutex mutex;
  static std::set<std::tuple<std::string, int64_t, int64_t, int64_t>> checked;
  const auto key = std::make_tuple(path, static_cast<int64_t>(st.st_size), static_cast<int64_t>(st.st_mtim.tv_sec),
                                   static_cast<int64_t>(st.st_mtim.tv_nsec));
  std::lock_guard<std::mutex> lock(mutex);
  if (checked.count(key)) return;

  const double size = static_cast<double>(st.st_size);
  const uint64_t inherited = AddressSpace();
  const uint64_t memory =
      inherited == 0 ? 0
                     : inherited + limits.memory_floor_bytes + static_cast<uint64_t>(limits.memory_per_file_byte * size);
  const double cpu_s = limits.cpu_floor_s + limits.cpu_s_per_mb * size / 1e6;

  // The count of items read, in memory the child writes and this process reads.
  void* shared = ::mmap(nullptr, sizeof(long), PROT_READ | PROT_WRITE, MAP_SHARED | MAP_ANONYMOUS, -1, 0);
  if (shared == MAP_FAILED) return;
  long* count = static_cast<long*>(shared);
  *count = 0;
  int fds[2];
  if (::pipe(fds) != 0) {
    ::munmap(shared, sizeof(long));
    return;
  }
  std::fflush(nullptr);
  const pid_t pid = ::fork();
  if (pid < 0) {
    ::close(fds[0]);
    ::close(fds[1]);
    ::munmap(shared, sizeof(long));
    return;
  }
  if (pid == 0) {
    ::close(fds[0]);
    RunChild(fds[1], count, read_all, memory, cpu_s);
  }
  ::close(fds[1]);
  std::string message;
  char buf[4096];
  for (;;) {
    const ssize_t n = ::read(fds[0], buf, sizeof buf);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) break;
    if (message.size() < 4096) message.append(buf, static_cast<size_t>(n));
  }
  ::close(fds[0]);
  int status = 0;
  while (::waitpid(pid, &status, 0) < 0 && errno == EINTR) {
  }
  const long read = *count;
  ::munmap(shared, sizeof(long));

  const std::string where = " after " + std::to_string(read) + " " + items;
  const std::string damaged = "a damaged " + kind + ": " + library + " ";
  if (WIFEXITED(status)) {
    switch (WEXITSTATUS(status)) {
      case kReadToEnd:
        checked.insert(key);
        return;
      case kInputError:
        throw InputError(message);
      case kOutOfMemory:
        throw InputError(path, 0,
                         damaged + "asked for more memory than such a file can need (over " +
                             std::to_string((memory - inherited) >> 20) + " MB)" + where);
      default:
        throw InputError(path, 0, damaged + "failed (" + (message.empty() ? "unknown error" : message) + ")" + where);
    }
  }
  const int sig = WIFSIGNALED(status) ? WTERMSIG(status) : 0;
  if (sig == SIGXCPU || sig == SIGKILL)
    throw InputError(path, 0,
                     damaged + "was still reading it after " + std::to_string(static_cast<long>(std::ceil(cpu_s))) +
                         " s of CPU" + where);
  throw InputError(path, 0, damaged + "crashed reading it (" + SignalName(sig) + ")" + where);
}

}  // namespace cogmap::io
