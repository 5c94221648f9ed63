#include "cogmap/io/output_folder.h"

#include <gtest/gtest.h>
#include <sys/stat.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>

#include "cogmap/core/error.h"
#include "cogmap/core/test_temp.h"

namespace cogmap::io {
namespace {

namespace fs = std::filesystem;

std::string Fresh(const std::string& name) {
  const std::string dir = testing_util::TestTempPath(name);
  fs::remove_all(dir);
  return dir;
}

void Write(const std::string& path, const std::string& text) { std::ofstream(path, std::ios::binary) << text; }

std::string Read(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

std::vector<std::string> Named(const std::string& dir, const std::string& prefix) {
  std::vector<std::string> out;
  for (const auto& e : fs::directory_iterator(dir))
    if (e.path().filename().string().rfind(prefix, 0) == 0) out.push_back(e.path().string());
  return out;
}

// A finished run: map.sqlite, map.svg and report.json with 'tag' in them.
void FinishedRun(const std::string& dir, const std::string& tag, bool with_extra = false) {
  auto f = OutputFolder::Open(dir);
  Write(f->Staged("map.sqlite"), "store " + tag);
  Write(f->Staged("map.svg"), "svg " + tag);
  Write(f->Staged("report.json"), "report " + tag);
  if (with_extra) Write(f->Staged("heading_error.png"), "png " + tag);
  f->Commit("map.sqlite");
}

TEST(OutputFolder, SecondOpenerIsRefusedWithTheHolderPid) {
  const std::string dir = Fresh("locked");
  auto first = OutputFolder::Open(dir);
  try {
    OutputFolder::Open(dir);
    FAIL() << "second opener got the lock";
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()), dir + ": locked by another cogmap run (pid " + std::to_string(::getpid()) + ")");
  }
  first.reset();
  EXPECT_NO_THROW(OutputFolder::Open(dir));  // released with the first
}

TEST(OutputFolder, CommitPutsEveryFileInPlaceAndRemovesTheStaging) {
  const std::string dir = Fresh("commit");
  FinishedRun(dir, "one");
  EXPECT_EQ(Read(dir + "/map.sqlite"), "store one");
  EXPECT_EQ(Read(dir + "/map.svg"), "svg one");
  EXPECT_EQ(Read(dir + "/report.json"), "report one");
  EXPECT_TRUE(Named(dir, ".staging-").empty());
  EXPECT_TRUE(fs::exists(dir + "/" + OutputFolder::kManifestName));
  EXPECT_FALSE(fs::exists(dir + "/" + OutputFolder::kJournalName));
}

TEST(OutputFolder, CommitRemovesFilesThePreviousRunWroteAndThisOneDidNot) {
  const std::string dir = Fresh("stale");
  FinishedRun(dir, "one", /*with_extra=*/true);
  ASSERT_TRUE(fs::exists(dir + "/heading_error.png"));
  FinishedRun(dir, "two");
  EXPECT_FALSE(fs::exists(dir + "/heading_error.png"));
  EXPECT_EQ(Read(dir + "/map.sqlite"), "store two");
}

TEST(OutputFolder, FailedRunLeavesThePreviousMapByteIdenticalAndKeepsItsPartAside) {
  const std::string dir = Fresh("failed");
  FinishedRun(dir, "one");
  std::string failed;
  {
    auto f = OutputFolder::Open(dir);
    Write(f->Staged("map.sqlite"), "partial store");
    Write(f->Staged("map.svg"), "partial svg");
    failed = f->Abandon();
  }
  EXPECT_EQ(Read(dir + "/map.sqlite"), "store one");
  EXPECT_EQ(Read(dir + "/map.svg"), "svg one");
  EXPECT_EQ(Read(dir + "/report.json"), "report one");
  ASSERT_FALSE(failed.empty());
  EXPECT_EQ(fs::path(failed).parent_path(), fs::path(dir));
  EXPECT_EQ(fs::path(failed).filename().string().rfind("failed-run-", 0), 0u);
  EXPECT_EQ(Read(failed + "/map.sqlite"), "partial store");
  EXPECT_TRUE(Named(dir, ".staging-").empty());
}

TEST(OutputFolder, DestroyedWithoutCommitIsAFailedRun) {
  const std::string dir = Fresh("unwound");
  FinishedRun(dir, "one");
  {
    auto f = OutputFolder::Open(dir);
    Write(f->Staged("map.sqlite"), "partial");
  }
  EXPECT_EQ(Read(dir + "/map.sqlite"), "store one");
  EXPECT_EQ(Named(dir, "failed-run-").size(), 1u);
}

TEST(OutputFolder, FailedRunThatWroteNothingLeavesNoFolder) {
  const std::string dir = Fresh("nothing");
  { EXPECT_EQ(OutputFolder::Open(dir)->Abandon(), ""); }
  EXPECT_TRUE(Named(dir, "failed-run-").empty());
  EXPECT_TRUE(Named(dir, ".staging-").empty());
}

TEST(OutputFolder, KilledRunsStagingIsSetAsideByTheNextOpen) {
  const std::string dir = Fresh("killed");
  FinishedRun(dir, "one");
  fs::create_directories(dir + "/.staging-999999");
  Write(dir + "/.staging-999999/map.sqlite", "killed");
  auto f = OutputFolder::Open(dir);
  const auto failed = Named(dir, "failed-run-");
  ASSERT_EQ(failed.size(), 1u);
  EXPECT_EQ(Read(failed[0] + "/map.sqlite"), "killed");
  EXPECT_EQ(Read(dir + "/map.sqlite"), "store one");
}

// kill_test found it: a run killed while it wrote the commit's journal left
// the journal's temporary in the output folder, beside the map, for good.
TEST(OutputFolder, KilledWhileWritingTheJournalLeavesTheFolderAsItWas) {
  const std::string dir = Fresh("killed_journal");
  FinishedRun(dir, "one");
  std::set<std::string> before;
  for (const auto& e : fs::directory_iterator(dir)) before.insert(e.path().filename().string());
  // What such a kill leaves now: the staging folder, the journal's
  // temporary inside it. And what earlier versions left: the temporary
  // beside the journal.
  fs::create_directories(dir + "/.staging-999998");
  Write(dir + "/.staging-999998/map.sqlite", "killed");
  Write(dir + "/.staging-999998/" + std::string(OutputFolder::kJournalName) + ".tmp-999998", "{\"format\": \"cogmap-ou");
  Write(dir + "/" + std::string(OutputFolder::kJournalName) + ".tmp-999997", "{\"format\": \"cogmap-ou");
  {
    auto f = OutputFolder::Open(dir);
    std::set<std::string> now;
    for (const auto& e : fs::directory_iterator(dir)) {
      const std::string name = e.path().filename().string();
      if (name.rfind(".staging-", 0) != 0 && name.rfind("failed-run-", 0) != 0) now.insert(name);
    }
    EXPECT_EQ(now, before);
    ASSERT_EQ(Named(dir, "failed-run-").size(), 1u);
  }
  EXPECT_EQ(Read(dir + "/map.sqlite"), "store one");
  // A commit writes its journal's temporary in its staging folder.
  FinishedRun(dir, "two");
  for (const auto& e : fs::directory_iterator(dir))
    EXPECT_EQ(e.path().filename().string().find(".tmp-"), std::string::npos) << e.path();
  EXPECT_EQ(Read(dir + "/map.sqlite"), "store two");
}

TEST(OutputFolder, EmptyStagingOfAFinishedCommitIsRemovedNotKept) {
  const std::string dir = Fresh("empty-staging");
  FinishedRun(dir, "one");
  fs::create_directories(dir + "/.staging-999997");
  auto f = OutputFolder::Open(dir);
  EXPECT_FALSE(fs::exists(dir + "/.staging-999997"));
  EXPECT_TRUE(Named(dir, "failed-run-").empty());
}

TEST(OutputFolder, CommitKilledHalfWayIsFinishedByTheNextOpen) {
  const std::string dir = Fresh("halfway");
  FinishedRun(dir, "one", /*with_extra=*/true);
  // What a run killed after its journal and its first rename leaves behind.
  fs::create_directories(dir + "/.staging-999998");
  Write(dir + "/.staging-999998/map.sqlite", "store two");
  Write(dir + "/.staging-999998/report.json", "report two");
  Write(dir + "/map.svg", "svg two");
  Write(dir + "/" + OutputFolder::kJournalName,
        R"({"format": "cogmap-output", "version": 1, "run_id": "x", "staging": ".staging-999998",
            "files": ["map.svg", "report.json", "map.sqlite"]})");
  OutputFolder::Open(dir);
  EXPECT_EQ(Read(dir + "/map.sqlite"), "store two");
  EXPECT_EQ(Read(dir + "/report.json"), "report two");
  EXPECT_EQ(Read(dir + "/map.svg"), "svg two");
  EXPECT_FALSE(fs::exists(dir + "/heading_error.png"));  // the old run's, not listed by the new one
  EXPECT_FALSE(fs::exists(dir + "/.staging-999998"));
  EXPECT_FALSE(fs::exists(dir + "/" + OutputFolder::kJournalName));
  EXPECT_TRUE(Named(dir, "failed-run-").empty());
}

TEST(OutputFolder, JournalNamingAFolderOutsideIsRefused) {
  const std::string dir = Fresh("hostile-journal");
  fs::create_directories(dir);
  Write(dir + "/" + OutputFolder::kJournalName,
        R"({"format": "cogmap-output", "staging": "../elsewhere", "files": ["map.svg"]})");
  EXPECT_THROW(OutputFolder::Open(dir), InputError);
}

TEST(OutputFolder, CopyIntoStagingTakesTheStoreAndItsWal) {
  const std::string dir = Fresh("copy");
  FinishedRun(dir, "one");
  Write(dir + "/map.sqlite-wal", "wal");
  auto f = OutputFolder::Open(dir);
  EXPECT_TRUE(f->CopyIntoStaging("map.sqlite"));
  EXPECT_EQ(Read(f->Staged("map.sqlite")), "store one");
  EXPECT_EQ(Read(f->Staged("map.sqlite-wal")), "wal");
  EXPECT_FALSE(f->CopyIntoStaging("nothing.sqlite"));
}

TEST(OutputFolder, RunIdsDiffer) {
  const std::string dir = Fresh("ids");
  std::string a = OutputFolder::Open(dir)->run_id();
  std::string b = OutputFolder::Open(dir)->run_id();
  EXPECT_NE(a, b);
}

TEST(OutputFolder, ReadOnlyFolderIsAPermissionError) {
  if (::geteuid() == 0) GTEST_SKIP() << "root ignores folder permissions";
  const std::string dir = Fresh("readonly");
  FinishedRun(dir, "one");
  fs::remove(dir + "/" + std::string(OutputFolder::kLockName));
  ::chmod(dir.c_str(), 0555);
  try {
    OutputFolder::Open(dir);
    ADD_FAILURE() << "opened a read-only folder";
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()), dir + ": permission denied");
  }
  ::chmod(dir.c_str(), 0755);
}

}  // namespace
}  // namespace cogmap::io
