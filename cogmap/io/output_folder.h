#pragma once
// An output folder that no failure can damage (issue 14): one writer at a time
// (a lock), every file written into a staging folder inside it, and moved into
// place only when the run succeeds. See docs/store.md, "The output folder".
#include <memory>
#include <string>
#include <vector>

namespace cogmap::io {

class OutputFolder {
 public:
  // The lock file, the commit journal and the manifest inside the folder.
  static constexpr const char* kLockName = ".cogmap.lock";
  static constexpr const char* kJournalName = ".cogmap-commit.json";
  static constexpr const char* kManifestName = ".cogmap-manifest.json";

  // Creates 'dir' when missing, locks it for this process (flock on
  // dir/.cogmap.lock, released when the object dies or the process ends),
  // finishes a commit that a killed run left half done, sets aside the staging
  // folders of killed runs as failed-run-* folders, and creates this run's
  // staging folder dir/.staging-<pid>/. Throws InputError:
  // "DIR: locked by another cogmap run (pid N)", "DIR: permission denied",
  // "DIR: cannot create the output folder (...)".
  static std::unique_ptr<OutputFolder> Open(const std::string& dir);
  ~OutputFolder();
  OutputFolder(const OutputFolder&) = delete;
  OutputFolder& operator=(const OutputFolder&) = delete;

  const std::string& dir() const { return dir_; }
  const std::string& staging() const { return staging_; }
  // staging()/name: where the run writes 'name'.
  std::string Staged(const std::string& name) const;
  // dir()/name: where 'name' ends up.
  std::string Final(const std::string& name) const;
  // A unique id of this run (time and pid), for the manifest, the store's meta
  // and report.json, so that a reader can check that files belong together.
  const std::string& run_id() const { return run_id_; }

  // Copies dir/name (and dir/name-wal when present: an SQLite store left by a
  // killed run) into the staging folder. False when dir/name does not exist.
  bool CopyIntoStaging(const std::string& name);

  // Moves every file of the staging folder into place, 'last' last (the store:
  // a reader that finds the new store finds every other new file), removes the
  // files of the previous run that this run did not write (the manifest lists
  // them), and removes the staging folder. The list of files goes first into a
  // commit journal, so that a run killed in the middle of the renames is
  // finished by the next Open(). Files named *-shm, *-journal and *.tmp-* are
  // left out. Throws InputError naming the folder when a rename fails.
  void Commit(const std::string& last);

  // A failed run: moves the staging folder to dir/failed-run-<timestamp>/
  // (the previous map is untouched) and returns that path ("" when the staging
  // folder could not be moved; then it stays where it is). The destructor does
  // this when neither Commit() nor Abandon() was called.
  std::string Abandon();

  bool committed() const { return committed_; }
  const std::string& failed_folder() const { return failed_; }

 private:
  OutputFolder() = default;

  std::string dir_;
  std::string staging_;
  std::string run_id_;
  std::string failed_;
  int lock_fd_ = -1;
  bool committed_ = false;
  bool abandoned_ = false;
};

}  // namespace cogmap::io
