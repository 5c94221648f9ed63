#include "cogmap/io/output_folder.h"

#include <fcntl.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <optional>
#include <set>
#include <sstream>

#include "cogmap/core/error.h"
#include "cogmap/core/parallel.h"

namespace cogmap::io {
namespace {

namespace fs = std::filesystem;

constexpr const char* kStagingPrefix = ".staging-";
constexpr const char* kFailedPrefix = "failed-run-";

bool IsPermission(int err) { return err == EACCES || err == EPERM || err == EROFS; }

std::string Utc(std::time_t t, const char* format) {
  std::tm tm{};
  gmtime_r(&t, &tm);
  char buf[64];
  std::strftime(buf, sizeof buf, format, &tm);
  return buf;
}

// A plain file name: no folder part, not "." or "..".
bool PlainName(const std::string& name) {
  return !name.empty() && name != "." && name != ".." && name.find('/') == std::string::npos &&
         name.find('\0') == std::string::npos;
}

// Temporaries that never belong to a finished output.
bool Scratch(const std::string& name) {
  auto ends = [&](const std::string& s) {
    return name.size() >= s.size() && name.compare(name.size() - s.size(), s.size(), s) == 0;
  };
  return ends("-shm") || ends("-journal") || name.find(".tmp-") != std::string::npos;
}

void SyncPath(const std::string& path, bool directory) {
  const int fd = ::open(path.c_str(), (directory ? O_RDONLY | O_DIRECTORY : O_RDONLY) | O_CLOEXEC);
  if (fd < 0) return;
  ::fsync(fd);
  ::close(fd);
}

// Writes 'text' to 'path' through a temporary file in 'tmp_dir' (on the
// same file system), synced before the rename: a run killed while writing it
// leaves the temporary there, not beside 'path'.
void WriteSynced(const std::string& path, const std::string& text, const std::string& tmp_dir) {
  const std::string tmp =
      (fs::path(tmp_dir) / (fs::path(path).filename().string() + ".tmp-" + std::to_string(::getpid()))).string();
  {
    std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
    out << text;
    out.flush();
    if (!out) {
      std::error_code ec;
      fs::remove(tmp, ec);
      throw InputError(path, 0, "write failed (disk full?)");
    }
  }
  SyncPath(tmp, false);
  std::error_code ec;
  fs::rename(tmp, path, ec);
  if (ec) {
    fs::remove(tmp, ec);
    throw InputError(path, 0, "cannot rename into place: " + ec.message());
  }
}

struct FileList {
  std::string run_id;
  std::string staging;  // folder name inside the output folder
  std::vector<std::string> files;
};

std::string ToJson(const FileList& l) {
  nlohmann::json j = {{"format", "cogmap-output"},
                      {"version", 1},
                      {"run_id", l.run_id},
                      {"staging", l.staging},
                      {"files", l.files}};
  return j.dump(1) + "\n";
}

// The journal or the manifest; nullopt when missing. Throws InputError when
// it is not one (a journal is written whole, so this is someone else's file).
std::optional<FileList> ReadFileList(const std::string& path) {
  std::error_code ec;
  if (!fs::exists(path, ec)) return std::nullopt;
  std::ifstream in(path, std::ios::binary);
  std::stringstream ss;
  ss << in.rdbuf();
  FileList l;
  try {
    const nlohmann::json j = nlohmann::json::parse(ss.str());
    if (!j.is_object() || j.value("format", "") != "cogmap-output") throw std::runtime_error("format");
    l.run_id = j.value("run_id", "");
    l.staging = j.value("staging", "");
    for (const auto& f : j.at("files")) {
      const std::string name = f.get<std::string>();
      if (!PlainName(name)) throw std::runtime_error("file name");
      l.files.push_back(name);
    }
  } catch (const std::exception&) {
    throw InputError(path, 0, "not a cogmap output list (remove it to continue)");
  }
  if (!l.staging.empty() && (!PlainName(l.staging) || l.staging.rfind(kStagingPrefix, 0) != 0))
    throw InputError(path, 0, "not a cogmap output list (bad staging folder name)");
  return l;
}

// The second half of a commit, from its journal: every file still in the
// staging folder is moved into place (in the journal's order), the previous
// run's files that the new list lacks are removed, the journal becomes the
// manifest and the staging folder goes. Safe to repeat after a kill.
void RollForward(const std::string& dir, const FileList& l) {
  const fs::path d(dir);
  const fs::path staging = d / l.staging;
  std::error_code ec;
  // A new store replaces the old one whole: an old write-ahead log must not
  // end up beside it (stores are left without one at the end of a run).
  for (const auto& name : l.files)
    for (const char* suffix : {"-wal", "-shm"})
      if (fs::exists(staging / name, ec) && !fs::exists(staging / (name + suffix), ec))
        fs::remove(d / (name + suffix), ec);
  for (const auto& name : l.files) {
    const fs::path from = staging / name;
    if (!fs::exists(from, ec)) continue;  // moved before a kill
    fs::rename(from, d / name, ec);
    if (ec) throw InputError((d / name).string(), 0, "cannot move the new file into place: " + ec.message());
  }
  SyncPath(dir, true);
  const std::set<std::string> now(l.files.begin(), l.files.end());
  std::optional<FileList> old;
  try {
    old = ReadFileList((d / OutputFolder::kManifestName).string());
  } catch (const InputError&) {
    // Not ours: replaced below, and the files it names are left alone.
  }
  if (old)
    for (const auto& name : old->files)
      if (!now.count(name)) fs::remove(d / name, ec);
  fs::rename(d / OutputFolder::kJournalName, d / OutputFolder::kManifestName, ec);
  if (ec) throw InputError((d / OutputFolder::kJournalName).string(), 0, "cannot finish the commit: " + ec.message());
  SyncPath(dir, true);
  fs::remove_all(staging, ec);
}

// dir/failed-run-<UTC time>-<pid>, not yet taken.
std::string FreeFailedName(const std::string& dir, std::time_t t, const std::string& pid) {
  const std::string base = (fs::path(dir) / (kFailedPrefix + Utc(t, "%Y%m%d-%H%M%S") + "-" + pid)).string();
  std::string name = base;
  std::error_code ec;
  for (int k = 2; fs::exists(name, ec); ++k) name = base + "-" + std::to_string(k);
  return name;
}

}  // namespace

std::unique_ptr<OutputFolder> OutputFolder::Open(const std::string& dir) {
  std::error_code ec;
  fs::create_directories(dir, ec);
  if (!fs::is_directory(dir)) {
    if (ec && IsPermission(ec.value())) throw InputError(dir, 0, "permission denied");
    throw InputError(dir, 0, "cannot create the output folder" + (ec ? " (" + ec.message() + ")" : std::string()));
  }
  std::unique_ptr<OutputFolder> f(new OutputFolder());
  f->dir_ = dir;
  const std::string lock_path = (fs::path(dir) / kLockName).string();
  f->lock_fd_ = ::open(lock_path.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644);
  if (f->lock_fd_ < 0) {
    const int err = errno;
    if (IsPermission(err)) throw InputError(dir, 0, "permission denied");
    throw InputError(lock_path, 0, std::string("cannot create the lock file: ") + std::strerror(err));
  }
  if (::flock(f->lock_fd_, LOCK_EX | LOCK_NB) != 0) {
    const int err = errno;
    if (err != EWOULDBLOCK) throw InputError(lock_path, 0, std::string("cannot lock: ") + std::strerror(err));
    char buf[32] = {};
    const ssize_t n = ::pread(f->lock_fd_, buf, sizeof buf - 1, 0);
    std::string pid = n > 0 ? std::string(buf, static_cast<size_t>(n)) : "";
    while (!pid.empty() && (pid.back() == '\n' || pid.back() == ' ')) pid.pop_back();
    if (pid.empty() || !std::all_of(pid.begin(), pid.end(), [](char c) { return c >= '0' && c <= '9'; })) pid = "?";
    throw InputError(dir, 0, "locked by another cogmap run (pid " + pid + ")");
  }
  const std::string me = std::to_string(::getpid());
  if (::ftruncate(f->lock_fd_, 0) == 0) {
    const std::string text = me + "\n";
    [[maybe_unused]] const ssize_t w = ::pwrite(f->lock_fd_, text.data(), text.size(), 0);
  }

  // A commit that a killed run left half done: finish it.
  const std::string journal = (fs::path(dir) / kJournalName).string();
  if (auto l = ReadFileList(journal)) RollForward(dir, *l);
  // Staging folders of killed runs: set aside, as a failed run's would be.
  // (Journal temporaries that earlier versions wrote beside the journal, of
  // a run killed while writing one: never part of a map.)
  const std::string journal_tmp = std::string(kJournalName) + ".tmp-";
  for (const auto& e : fs::directory_iterator(dir, ec)) {
    const std::string name = e.path().filename().string();
    if (name.rfind(journal_tmp, 0) == 0 && e.is_regular_file()) {
      std::error_code rec;
      fs::remove(e.path(), rec);
      continue;
    }
    if (name.rfind(kStagingPrefix, 0) != 0 || !e.is_directory()) continue;
    std::error_code rec;
    if (fs::is_empty(e.path(), rec) && !rec) {  // a commit killed after its last rename
      fs::remove(e.path(), rec);
      continue;
    }
    struct stat st {};
    const std::time_t t = ::stat(e.path().c_str(), &st) == 0 ? st.st_mtime : std::time(nullptr);
    fs::rename(e.path(), FreeFailedName(dir, t, name.substr(std::strlen(kStagingPrefix)) + "-killed"), rec);
  }

  f->staging_ = (fs::path(dir) / (kStagingPrefix + me)).string();
  fs::create_directory(f->staging_, ec);
  if (ec || !fs::is_directory(f->staging_)) {
    if (ec && IsPermission(ec.value())) throw InputError(dir, 0, "permission denied");
    throw InputError(f->staging_, 0, "cannot create the staging folder" + (ec ? " (" + ec.message() + ")" : ""));
  }
  const auto now = std::chrono::system_clock::now();
  const auto us = std::chrono::duration_cast<std::chrono::microseconds>(now.time_since_epoch()).count() % 1000000;
  char frac[16];
  std::snprintf(frac, sizeof frac, ".%06lld", static_cast<long long>(us));
  f->run_id_ = Utc(std::chrono::system_clock::to_time_t(now), "%Y%m%dT%H%M%S") + frac + "Z-" + me;
  return f;
}

OutputFolder::~OutputFolder() {
  if (!staging_.empty() && !committed_ && !abandoned_) {
    try {
      Abandon();
    } catch (...) {
    }
  }
  if (lock_fd_ >= 0) ::close(lock_fd_);  // releases the flock
}

std::string OutputFolder::Staged(const std::string& name) const { return (fs::path(staging_) / name).string(); }

std::string OutputFolder::Final(const std::string& name) const { return (fs::path(dir_) / name).string(); }

bool OutputFolder::CopyIntoStaging(const std::string& name) {
  std::error_code ec;
  if (!fs::exists(Final(name), ec)) return false;
  for (const std::string suffix : {"", "-wal"}) {
    const std::string from = Final(name + suffix);
    if (!suffix.empty() && !fs::exists(from, ec)) continue;
    fs::copy_file(from, Staged(name + suffix), fs::copy_options::overwrite_existing, ec);
    if (ec) {
      if (IsPermission(ec.value())) throw InputError(from, 0, "permission denied");
      throw InputError(from, 0, "cannot copy into the staging folder: " + ec.message());
    }
  }
  return true;
}

void OutputFolder::Commit(const std::string& last) {
  if (committed_ || abandoned_) return;
  FileList l;
  l.run_id = run_id_;
  l.staging = fs::path(staging_).filename().string();
  std::error_code ec;
  bool has_last = false;
  for (const auto& e : fs::directory_iterator(staging_, ec)) {
    const std::string name = e.path().filename().string();
    if (!e.is_regular_file() || Scratch(name)) continue;
    if (name == last) {
      has_last = true;
      continue;
    }
    l.files.push_back(name);
  }
  if (ec) throw InputError(staging_, 0, "cannot list the staging folder: " + ec.message());
  std::sort(l.files.begin(), l.files.end());
  if (has_last) l.files.push_back(last);
  // Everything on disk before the first rename (a power cut after the commit
  // must not leave renamed but empty files). The files are synced up to
  // eight at once, each on a thread (a wait on the disk, not work for a
  // core): the file system commits them together, where one after the other
  // each waits for a journal commit of its own (nine_rooms' nine files: 2.0
  // -> 1.1 ms).
  constexpr int kMostAtOnce = 8;
  ForEachShared(l.files.size(), kMostAtOnce, [&](size_t k) { SyncPath(Staged(l.files[k]), false); });
  SyncPath(staging_, true);
  // The journal's temporary in the staging folder: a kill while it is
  // written leaves the output folder as it was (the next run sets the
  // staging folder aside).
  WriteSynced(Final(kJournalName), ToJson(l), staging_);
  SyncPath(dir_, true);
  RollForward(dir_, l);
  committed_ = true;
}

std::string OutputFolder::Abandon() {
  if (committed_ || abandoned_) return failed_;
  abandoned_ = true;
  std::error_code ec;
  if (fs::is_empty(staging_, ec) && !ec) {
    fs::remove(staging_, ec);
    return failed_;
  }
  const std::string target = FreeFailedName(dir_, std::time(nullptr), std::to_string(::getpid()));
  fs::rename(staging_, target, ec);
  if (ec) return failed_;
  failed_ = target;
  return failed_;
}

}  // namespace cogmap::io
