#include "cogmap/asr/store.h"

#include <gtest/gtest.h>
#include <signal.h>
#include <sqlite3.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <thread>

#include "cogmap/core/error.h"
#include "cogmap/core/test_temp.h"

namespace cogmap::asr {
namespace {

namespace fs = std::filesystem;

// A fresh folder per test.
std::string TempDir(const std::string& name) {
  const fs::path dir = fs::path(testing_util::TestTempDir()) / name;
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir.string();
}

// Runs SQL on the database at 'path' (a store changed behind cogmap's back).
void ExecSql(const std::string& path, const std::string& sql) {
  sqlite3* db = nullptr;
  ASSERT_EQ(sqlite3_open(path.c_str(), &db), SQLITE_OK);
  const int rc = sqlite3_exec(db, sql.c_str(), nullptr, nullptr, nullptr);
  sqlite3_close(db);
  ASSERT_EQ(rc, SQLITE_OK) << sql;
}

// A deterministic ASR whose content follows from its id.
Asr MakeAsr(int id, int walls = 3) {
  Asr a;
  a.id = id;
  a.world_from_local_raw = {id * 4.5, 1.0, 0.0};
  a.world_from_local_corrected = {id * 4.5 + 0.01, 1.02, 0.003 * id};
  a.entry_pivot_m = {id * 4.5, 1.25};
  for (int w = 0; w < walls; ++w) a.walls_local.push_back({{0.1 * w, 0.0}, {0.1 * w + 3.0, 0.25 * id}, {1.0, -2.0}});
  if (id > 0) a.exits.push_back({{id * 4.5, 1.0}, 0.9, id - 1, id});
  a.exits.push_back({{id * 4.5 + 4.5, 1.0}, 1.1, id, id + 1});
  for (int i = 0; i < 20; ++i) a.path.push_back({id * 4.5 + 0.2 * i, 1.0, 0.01 * i});
  a.true_path = a.path;
  a.start_time_s = id * 10.0;
  a.end_time_s = id * 10.0 + 9.5;
  a.bytes = {2500 + id, 56, 8};
  a.seconds.grid = 0.5;
  a.seconds.clean = 0.25;
  a.seconds.extract = 0.125;
  a.seconds.simplify = 0.0625;
  a.seconds.fit = 0.03125;
  a.heading_correction_rad = 0.003 * id;
  a.heading_uncertainty_rad = 0.01;
  return a;
}

void ExpectSame(const Asr& a, const Asr& b) {
  EXPECT_EQ(a.id, b.id);
  EXPECT_EQ(a.world_from_local_raw.x, b.world_from_local_raw.x);
  EXPECT_EQ(a.world_from_local_corrected.theta, b.world_from_local_corrected.theta);
  EXPECT_EQ(a.entry_pivot_m, b.entry_pivot_m);
  ASSERT_EQ(a.walls_local.size(), b.walls_local.size());
  for (size_t i = 0; i < a.walls_local.size(); ++i) EXPECT_EQ(a.walls_local[i], b.walls_local[i]);
  ASSERT_EQ(a.exits.size(), b.exits.size());
  for (size_t i = 0; i < a.exits.size(); ++i) {
    EXPECT_EQ(a.exits[i].center_m, b.exits[i].center_m);
    EXPECT_EQ(a.exits[i].width_m, b.exits[i].width_m);
    EXPECT_EQ(a.exits[i].from_asr, b.exits[i].from_asr);
    EXPECT_EQ(a.exits[i].to_asr, b.exits[i].to_asr);
  }
  ASSERT_EQ(a.path.size(), b.path.size());
  for (size_t i = 0; i < a.path.size(); ++i) {
    EXPECT_EQ(a.path[i].x, b.path[i].x);
    EXPECT_EQ(a.path[i].theta, b.path[i].theta);
  }
  EXPECT_EQ(a.true_path.size(), b.true_path.size());
  EXPECT_EQ(a.start_time_s, b.start_time_s);
  EXPECT_EQ(a.end_time_s, b.end_time_s);
  EXPECT_EQ(a.bytes.grid, b.bytes.grid);
  EXPECT_EQ(a.bytes.vertices, b.bytes.vertices);
  EXPECT_EQ(a.bytes.polylines, b.bytes.polylines);
  EXPECT_EQ(a.seconds.total(), b.seconds.total());
  EXPECT_EQ(a.heading_correction_rad, b.heading_correction_rad);
  EXPECT_EQ(a.heading_uncertainty_rad, b.heading_uncertainty_rad);
}

TEST(StoreEncoding, WallsExitsPosesRoundTrip) {
  const Asr a = MakeAsr(3);
  EXPECT_EQ(DecodeWalls(EncodeWalls(a.walls_local)), a.walls_local);
  EXPECT_EQ(DecodeExits(EncodeExits(a.exits)).size(), 2u);
  EXPECT_EQ(DecodePoses(EncodePoses(a.path)).size(), 20u);
}

TEST(StoreEncoding, TruncatedBlobThrows) {
  std::string blob = EncodeWalls(MakeAsr(1).walls_local);
  blob.resize(blob.size() - 3);
  EXPECT_THROW(DecodeWalls(blob), std::runtime_error);
}

TEST(MemoryAsrStore, RoundTripAndNeighbours) {
  MemoryAsrStore s;
  for (int i = 0; i < 4; ++i) s.Put(MakeAsr(i));
  EXPECT_EQ(s.Count(), 4);
  EXPECT_EQ(s.MaxId(), 3);
  ExpectSame(*s.Get(2), MakeAsr(2));
  EXPECT_EQ(s.Neighbours(2), (std::vector<int>{1, 3}));
  EXPECT_FALSE(s.Get(9).has_value());
}

TEST(SqliteAsrStore, RoundTrip) {
  const std::string dir = TempDir("roundtrip");
  auto s = SqliteAsrStore::Open(dir + "/map.sqlite");
  for (int i = 0; i < 5; ++i) s->Put(MakeAsr(i), {{"last_raw_pose", "1 2 3"}});
  EXPECT_EQ(s->Count(), 5);
  EXPECT_EQ(s->MaxId(), 4);
  EXPECT_EQ(s->Ids(), (std::vector<int>{0, 1, 2, 3, 4}));
  for (int i = 0; i < 5; ++i) ExpectSame(*s->Get(i), MakeAsr(i));
  EXPECT_EQ(s->Neighbours(0), (std::vector<int>{1}));
  EXPECT_EQ(s->Neighbours(2), (std::vector<int>{1, 3}));
  EXPECT_EQ(s->Neighbours(4), (std::vector<int>{3, 5}));  // exit to the ASR not yet stored
  EXPECT_EQ(*s->GetMeta("last_raw_pose"), "1 2 3");
  EXPECT_EQ(*s->GetMeta("application"), "cogmap");
  EXPECT_EQ(*s->GetMeta("schema_version"), std::to_string(kStoreSchemaVersion));
  EXPECT_EQ(s->IntegrityCheck(), "ok");
}

TEST(SqliteAsrStore, ReopenKeepsEverythingAndUsesWal) {
  const std::string dir = TempDir("reopen");
  const std::string path = dir + "/map.sqlite";
  {
    auto s = SqliteAsrStore::Open(path);
    for (int i = 0; i < 3; ++i) s->Put(MakeAsr(i));
  }
  auto s = SqliteAsrStore::Open(path, SqliteAsrStore::OpenMode::kOpenExisting);
  EXPECT_EQ(s->Count(), 3);
  ExpectSame(*s->Get(1), MakeAsr(1));
  sqlite3* db = nullptr;
  ASSERT_EQ(sqlite3_open(path.c_str(), &db), SQLITE_OK);
  sqlite3_stmt* st = nullptr;
  sqlite3_prepare_v2(db, "PRAGMA journal_mode", -1, &st, nullptr);
  ASSERT_EQ(sqlite3_step(st), SQLITE_ROW);
  EXPECT_STREQ(reinterpret_cast<const char*>(sqlite3_column_text(st, 0)), "wal");
  sqlite3_finalize(st);
  sqlite3_prepare_v2(db, "PRAGMA application_id", -1, &st, nullptr);
  ASSERT_EQ(sqlite3_step(st), SQLITE_ROW);
  EXPECT_EQ(sqlite3_column_int(st, 0), kStoreApplicationId);
  sqlite3_finalize(st);
  sqlite3_close(db);
}

TEST(SqliteAsrStore, PlacementsAndClosuresRoundTrip) {
  const std::string path = TempDir("placements") + "/map.sqlite";
  auto s = SqliteAsrStore::Open(path);
  for (int i = 0; i < 3; ++i) s->Put(MakeAsr(i));
  Asr moved = MakeAsr(2);
  moved.world_from_local_corrected = {1.5, -2.0, 0.25};
  Placement p;
  p.asr_id = 2;
  p.room_id = 0;
  p.covariance = Eigen::Matrix3d::Identity() * 0.04;
  p.covariance(0, 1) = p.covariance(1, 0) = 0.01;
  p.uncertain = true;
  p.why = "position 1-sigma 0.6 m";
  p.drift_rate_rad_per_m = 0.0175;
  p.corrected_path = {{1.0, 2.0, 0.5}, {1.5, 2.0, 0.5}};
  ClosureRecord c{0, 2, Pose2{0.1, -0.2, 0.03}, 0.8, 0.05, 2.5, true, true, "accepted"};
  s->PutPlacements({moved}, {p}, {c});
  EXPECT_EQ(s->Get(2)->world_from_local_corrected.theta, 0.25);
  EXPECT_EQ(s->RoomOf(2), 0);
  EXPECT_EQ(s->RoomOf(1), 1);  // never placed: its own room
  const auto q = s->GetPlacement(2);
  ASSERT_TRUE(q);
  EXPECT_EQ(q->covariance, p.covariance);
  EXPECT_TRUE(q->uncertain);
  EXPECT_EQ(q->why, p.why);
  EXPECT_EQ(q->drift_rate_rad_per_m, 0.0175);
  ASSERT_EQ(q->corrected_path.size(), 2u);
  EXPECT_EQ(q->corrected_path[1].x, 1.5);
  const auto cl = s->Closures();
  ASSERT_EQ(cl.size(), 1u);
  EXPECT_EQ(cl[0].to_asr, 2);
  EXPECT_TRUE(cl[0].same_room);
  EXPECT_EQ(cl[0].reason, "accepted");
  EXPECT_EQ(s->IntegrityCheck(), "ok");
}

// RevisePlacements reads each listed ASR, lets the caller revise it and writes
// it back with the placements, in one transaction; ids not stored are skipped.
TEST(SqliteAsrStore, RevisePlacementsRevisesEachListedAsrInPlace) {
  const std::string path = TempDir("revise") + "/map.sqlite";
  auto sq = SqliteAsrStore::Open(path);
  MemoryAsrStore mem;
  for (AsrStore* s : {static_cast<AsrStore*>(sq.get()), static_cast<AsrStore*>(&mem)}) {
    for (int i = 0; i < 3; ++i) s->Put(MakeAsr(i));
    Placement p;
    p.asr_id = 1;
    p.room_id = 0;
    std::vector<int> seen;
    s->RevisePlacements({1, 2, 7}, [&](Asr& a) {
      seen.push_back(a.id);
      a.world_from_local_corrected.theta = 0.5 + a.id;
      a.walls_local.pop_back();
    }, {p}, {});
    EXPECT_EQ(seen, (std::vector<int>{1, 2}));  // 7 is not stored
    EXPECT_EQ(s->Get(0)->world_from_local_corrected.theta, MakeAsr(0).world_from_local_corrected.theta);
    EXPECT_EQ(s->Get(1)->world_from_local_corrected.theta, 1.5);
    EXPECT_EQ(s->Get(2)->walls_local.size(), MakeAsr(2).walls_local.size() - 1);
    ExpectSame(*s->Get(0), MakeAsr(0));
    EXPECT_EQ(s->RoomOf(1), 0);
  }
  EXPECT_EQ(sq->IntegrityCheck(), "ok");
}

// Turns a store back into what an older cogmap wrote: 'sql' drops the newer
// tables, then the version is set.
void DowngradeStore(const std::string& path, const std::string& sql, int version) {
  const std::string v = std::to_string(version);
  // Every version before 7 lacks schema 7's table, before 6 schema 6's, and
  // before 5 schema 5's.
  std::string older = version < 7 ? "DROP TABLE IF EXISTS path_turn; " : "";
  if (version < 6) older += "DROP TABLE IF EXISTS pre_bend; ";
  if (version < 5) older += "DROP TABLE IF EXISTS matched_walls; ";
  ExecSql(path, older + sql + "; PRAGMA user_version=" + v + "; UPDATE meta SET value='" + v +
                    "' WHERE key='schema_version'");
}

TEST(SqliteAsrStore, VersionOneStoreIsMigrated) {
  const std::string path = TempDir("v1") + "/map.sqlite";
  {
    auto s = SqliteAsrStore::Open(path);
    for (int i = 0; i < 2; ++i) s->Put(MakeAsr(i));
  }
  // Back to what version 1 wrote: no placement / closure tables.
  DowngradeStore(path, "DROP TABLE placement; DROP TABLE closure; DROP TABLE orientation; DROP TABLE free_space", 1);
  {
    // Read-only: read as it is.
    auto r = SqliteAsrStore::Open(path, SqliteAsrStore::OpenMode::kReadOnly);
    EXPECT_EQ(r->Count(), 2);
    EXPECT_FALSE(r->GetPlacement(1));
    EXPECT_EQ(r->RoomOf(1), 1);
    EXPECT_TRUE(r->Closures().empty());
  }
  auto s = SqliteAsrStore::Open(path, SqliteAsrStore::OpenMode::kOpenExisting);
  ExpectSame(*s->Get(1), MakeAsr(1));
  EXPECT_EQ(*s->GetMeta("schema_version"), std::to_string(kStoreSchemaVersion));
  Placement p;
  p.asr_id = 1;
  p.room_id = 0;
  s->PutPlacements({}, {p}, {});
  EXPECT_EQ(s->RoomOf(1), 0);
}

// Version 2 had no orientation table: read as it is (no orientation), then
// migrated by creating it; the grid orientation round-trips from version 3 on.
TEST(SqliteAsrStore, VersionTwoStoreIsMigratedAndOrientationsRoundTrip) {
  const std::string path = TempDir("v2") + "/map.sqlite";
  Asr a = MakeAsr(0);
  a.grid_orientation = {true, 0.25, 3.5, 812};
  {
    auto s = SqliteAsrStore::Open(path);
    s->Put(a);
    const Asr back = *s->Get(0);
    EXPECT_TRUE(back.grid_orientation.valid);
    EXPECT_EQ(back.grid_orientation.angle_rad, 0.25);
    EXPECT_EQ(back.grid_orientation.contrast, 3.5);
    EXPECT_EQ(back.grid_orientation.cells, 812);
  }
  DowngradeStore(path, "DROP TABLE orientation; DROP TABLE free_space", 2);
  {
    auto r = SqliteAsrStore::Open(path, SqliteAsrStore::OpenMode::kReadOnly);
    const Asr back = *r->Get(0);
    EXPECT_FALSE(back.grid_orientation.valid);
    EXPECT_EQ(back.grid_orientation.cells, 0);
  }
  auto s = SqliteAsrStore::Open(path, SqliteAsrStore::OpenMode::kOpenExisting);
  EXPECT_EQ(*s->GetMeta("schema_version"), std::to_string(kStoreSchemaVersion));
  EXPECT_FALSE(s->Get(0)->grid_orientation.valid);
  s->Put(a);
  EXPECT_EQ(s->Get(0)->grid_orientation.cells, 812);
}

// Version 3 had no free_space table: read as it is (no floor), then migrated
// by creating it; the floor each ASR saw round-trips from version 4 on.
TEST(SqliteAsrStore, VersionThreeStoreIsMigratedAndFreeHullsRoundTrip) {
  const std::string path = TempDir("v3") + "/map.sqlite";
  Asr a = MakeAsr(0);
  a.free_hull_local = {{0, 0}, {4, 0}, {4, 3.5}, {0.25, 3}};
  {
    auto s = SqliteAsrStore::Open(path);
    s->Put(a);
    s->Put(MakeAsr(1));  // no floor known: no row
    EXPECT_EQ(s->Get(0)->free_hull_local, a.free_hull_local);
    EXPECT_TRUE(s->Get(1)->free_hull_local.empty());
  }
  DowngradeStore(path, "DROP TABLE free_space", 3);
  {
    auto r = SqliteAsrStore::Open(path, SqliteAsrStore::OpenMode::kReadOnly);
    EXPECT_TRUE(r->Get(0)->free_hull_local.empty());
    ExpectSame(*r->Get(1), MakeAsr(1));
  }
  auto s = SqliteAsrStore::Open(path, SqliteAsrStore::OpenMode::kOpenExisting);
  EXPECT_EQ(*s->GetMeta("schema_version"), std::to_string(kStoreSchemaVersion));
  EXPECT_TRUE(s->Get(0)->free_hull_local.empty());
  s->Put(a);
  EXPECT_EQ(s->Get(0)->free_hull_local, a.free_hull_local);
}

// Version 4 had no matched_walls table: read as it is (the walls kept are
// the walls matched), then migrated by creating it; a sonar ASR's matched
// (axis-grid) walls round-trip beside the walls it keeps from version 5 on.
TEST(SqliteAsrStore, VersionFourStoreIsMigratedAndMatchedWallsRoundTrip) {
  const std::string path = TempDir("v4") + "/map.sqlite";
  Asr a = MakeAsr(0);
  a.matched_walls_local = {{{0, 0.1}, {4, 0.1}}, {{4, 0.1}, {4, 3}}};
  a.has_matched_walls = true;
  {
    auto s = SqliteAsrStore::Open(path);
    s->Put(a);
    s->Put(MakeAsr(1));  // walls matched = walls kept: no row
    EXPECT_TRUE(s->Get(0)->has_matched_walls);
    EXPECT_EQ(s->Get(0)->matched_walls_local, a.matched_walls_local);
    EXPECT_FALSE(s->Get(1)->has_matched_walls);
    const Asr view = MatchedView(*s->Get(0));
    EXPECT_EQ(view.walls_local, a.matched_walls_local);
    EXPECT_EQ(view.output_walls_local, a.walls_local);
  }
  DowngradeStore(path, "SELECT 1", 4);  // drops matched_walls
  {
    auto r = SqliteAsrStore::Open(path, SqliteAsrStore::OpenMode::kReadOnly);
    EXPECT_FALSE(r->Get(0)->has_matched_walls);
    ExpectSame(*r->Get(1), MakeAsr(1));
  }
  auto s = SqliteAsrStore::Open(path, SqliteAsrStore::OpenMode::kOpenExisting);
  EXPECT_EQ(*s->GetMeta("schema_version"), std::to_string(kStoreSchemaVersion));
  EXPECT_FALSE(s->Get(0)->has_matched_walls);
  s->Put(a);
  EXPECT_EQ(s->Get(0)->matched_walls_local, a.matched_walls_local);
}

// Version 5 had no pre_bend table: read as it is (every ASR mapped on the
// raw odometry), then migrated by creating it. The rate round-trips; an ASR
// without one has no row, also when written again with none.
TEST(SqliteAsrStore, VersionFiveStoreIsMigratedAndPreBendsRoundTrip) {
  const std::string path = TempDir("v5") + "/map.sqlite";
  Asr a = MakeAsr(0);
  a.pre_bend_rad_per_m = 0.0171;
  {
    auto s = SqliteAsrStore::Open(path);
    s->Put(a);
    s->Put(MakeAsr(1));
    EXPECT_EQ(s->Get(0)->pre_bend_rad_per_m, 0.0171);
    EXPECT_EQ(s->Get(1)->pre_bend_rad_per_m, 0.0);
    Asr again = a;
    again.id = 2;
    s->Put(again);
    again.pre_bend_rad_per_m = 0.0;
    s->Put(again);
    EXPECT_EQ(s->Get(2)->pre_bend_rad_per_m, 0.0);
  }
  DowngradeStore(path, "SELECT 1", 5);  // drops pre_bend
  {
    auto r = SqliteAsrStore::Open(path, SqliteAsrStore::OpenMode::kReadOnly);
    EXPECT_EQ(r->Get(0)->pre_bend_rad_per_m, 0.0);
    ExpectSame(*r->Get(1), MakeAsr(1));
  }
  auto s = SqliteAsrStore::Open(path, SqliteAsrStore::OpenMode::kOpenExisting);
  EXPECT_EQ(*s->GetMeta("schema_version"), std::to_string(kStoreSchemaVersion));
  EXPECT_EQ(s->Get(0)->pre_bend_rad_per_m, 0.0);
  s->Put(a);
  EXPECT_EQ(s->Get(0)->pre_bend_rad_per_m, 0.0171);
}

// The path's turns round-trip from schema 7 on (a resumed run replays a
// killed run's ASRs with the odometry noise their turning gave them); a
// version-6 store reads without them and is migrated by creating the table.
TEST(SqliteAsrStore, VersionSixStoreIsMigratedAndPathTurnsRoundTrip) {
  const std::string path = TempDir("v6") + "/map.sqlite";
  Asr a = MakeAsr(0);
  a.path_turn_rad.assign(a.path.size(), 0.0);
  a.path_turn_rad[5] = 1.5707963267948966;  // a quarter turn on the spot
  a.path_turn_rad[6] = 0.01;
  a.turn_after_path_rad = 0.25;
  {
    auto s = SqliteAsrStore::Open(path);
    s->Put(a);
    s->Put(MakeAsr(1));  // never turned: no row
    EXPECT_EQ(s->Get(0)->path_turn_rad, a.path_turn_rad);
    EXPECT_EQ(s->Get(0)->turn_after_path_rad, 0.25);
    EXPECT_TRUE(s->Get(1)->path_turn_rad.empty());
    EXPECT_EQ(s->Get(1)->turn_after_path_rad, 0.0);
    Asr again = a;
    again.id = 2;
    s->Put(again);
    again.path_turn_rad.clear();
    again.turn_after_path_rad = 0.0;
    s->Put(again);  // written again without turns: its row goes
    EXPECT_TRUE(s->Get(2)->path_turn_rad.empty());
  }
  DowngradeStore(path, "SELECT 1", 6);  // drops path_turn
  {
    auto r = SqliteAsrStore::Open(path, SqliteAsrStore::OpenMode::kReadOnly);
    EXPECT_TRUE(r->Get(0)->path_turn_rad.empty());
    ExpectSame(*r->Get(1), MakeAsr(1));
  }
  auto s = SqliteAsrStore::Open(path, SqliteAsrStore::OpenMode::kOpenExisting);
  EXPECT_EQ(*s->GetMeta("schema_version"), std::to_string(kStoreSchemaVersion));
  EXPECT_TRUE(s->Get(0)->path_turn_rad.empty());
  s->Put(a);
  EXPECT_EQ(s->Get(0)->path_turn_rad, a.path_turn_rad);
}

// A path-turn row that is not the ASR's (another count than its path's
// poses, a value that is not a number) is one error naming the store.
TEST(SqliteAsrStore, PathTurnsThatDoNotFitTheirPathAreAnError) {
  const std::string path = TempDir("turns_bad") + "/map.sqlite";
  Asr a = MakeAsr(0);
  a.path_turn_rad.assign(a.path.size(), 0.1);
  SqliteAsrStore::Open(path)->Put(a);
  ExecSql(path, "UPDATE path_turn SET turns=substr(turns, 1, 4 + 8 * 3)");  // 3 doubles and a count of 20
  try {
    SqliteAsrStore::Open(path, SqliteAsrStore::OpenMode::kReadOnly)->Get(0);
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()), path + ": ASR 0: path turns: corrupt ASR blob (count past the end)");
  }
  ExecSql(path, "UPDATE path_turn SET turns=X'0100000000000000000000F03F'");  // one double (1.0) for 20 poses
  try {
    SqliteAsrStore::Open(path, SqliteAsrStore::OpenMode::kReadOnly)->Get(0);
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()), path + ": ASR 0: 1 path turns for 20 path poses");
  }
}

TEST(SqliteAsrStore, ReplaceStartsEmpty) {
  const std::string path = TempDir("replace") + "/map.sqlite";
  SqliteAsrStore::Open(path)->Put(MakeAsr(0));
  EXPECT_EQ(SqliteAsrStore::Open(path, SqliteAsrStore::OpenMode::kReplace)->Count(), 0);
}

TEST(SqliteAsrStore, NewerSchemaIsAClearError) {
  const std::string path = TempDir("newer") + "/map.sqlite";
  SqliteAsrStore::Open(path)->Put(MakeAsr(0));
  ExecSql(path, "PRAGMA user_version=" + std::to_string(kStoreSchemaVersion + 1));
  try {
    SqliteAsrStore::Open(path);
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()), path + ": schema version " + std::to_string(kStoreSchemaVersion + 1) +
                                         " is newer than this cogmap (" + std::to_string(kStoreSchemaVersion) + ")");
  }
}

TEST(SqliteAsrStore, TextFileIsNotAStore) {
  const std::string path = TempDir("text") + "/map.sqlite";
  std::ofstream(path) << "hello, this is not a database at all\n";
  try {
    SqliteAsrStore::Open(path);
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("not a cogmap store"), std::string::npos) << e.what();
  }
}

TEST(SqliteAsrStore, OtherSqliteDatabaseIsNotAStore) {
  const std::string path = TempDir("other") + "/map.sqlite";
  ExecSql(path, "CREATE TABLE t(x)");
  EXPECT_THROW(SqliteAsrStore::Open(path), InputError);
}

TEST(SqliteAsrStore, FullDiskLosesNoFinishedAsr) {
  const std::string path = TempDir("full") + "/map.sqlite";
  auto s = SqliteAsrStore::Open(path);
  s->Put(MakeAsr(0));
  s->Put(MakeAsr(1));
  const int pages = [&] {
    sqlite3* db = nullptr;
    sqlite3_open(path.c_str(), &db);
    sqlite3_stmt* st = nullptr;
    sqlite3_prepare_v2(db, "PRAGMA page_count", -1, &st, nullptr);
    sqlite3_step(st);
    const int n = sqlite3_column_int(st, 0);
    sqlite3_finalize(st);
    sqlite3_close(db);
    return n;
  }();
  s->LimitPagesForTest(pages);
  EXPECT_THROW(s->Put(MakeAsr(2, 400)), InputError);  // ~40 KB of walls do not fit
  EXPECT_EQ(s->Count(), 2);
  s.reset();
  auto again = SqliteAsrStore::Open(path);
  EXPECT_EQ(again->Count(), 2);
  EXPECT_EQ(again->IntegrityCheck(), "ok");
  ExpectSame(*again->Get(1), MakeAsr(1));
}

TEST(SqliteAsrStore, KillDuringWritesLeavesAValidStore) {
  const std::string path = TempDir("kill") + "/map.sqlite";
  SqliteAsrStore::Open(path);  // created by the parent
  const pid_t child = ::fork();
  ASSERT_GE(child, 0);
  if (child == 0) {
    try {
      auto s = SqliteAsrStore::Open(path);
      for (int i = 0;; ++i) s->Put(MakeAsr(i, 50));
    } catch (...) {
    }
    ::_exit(1);
  }
  // Let it commit a few, then kill it mid-stream.
  for (int waited = 0; waited < 200; ++waited) {
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
    sqlite3* db = nullptr;
    sqlite3_open_v2(path.c_str(), &db, SQLITE_OPEN_READONLY, nullptr);
    sqlite3_stmt* st = nullptr;
    int n = 0;
    if (sqlite3_prepare_v2(db, "SELECT count(*) FROM asr", -1, &st, nullptr) == SQLITE_OK &&
        sqlite3_step(st) == SQLITE_ROW)
      n = sqlite3_column_int(st, 0);
    sqlite3_finalize(st);
    sqlite3_close(db);
    if (n >= 5) break;
  }
  ::kill(child, SIGKILL);
  int status = 0;
  ::waitpid(child, &status, 0);
  ASSERT_TRUE(WIFSIGNALED(status));
  auto s = SqliteAsrStore::Open(path);
  EXPECT_EQ(s->IntegrityCheck(), "ok");
  const int count = s->Count();
  EXPECT_GE(count, 5);
  EXPECT_EQ(s->MaxId(), count - 1);  // no gap: every committed ASR is whole
  for (int i = 0; i < count; ++i) ExpectSame(*s->Get(i), MakeAsr(i, 50));
}

std::string JournalMode(const std::string& path) {
  sqlite3* db = nullptr;
  sqlite3_open_v2(path.c_str(), &db, SQLITE_OPEN_READONLY, nullptr);
  sqlite3_stmt* st = nullptr;
  std::string mode;
  if (sqlite3_prepare_v2(db, "PRAGMA journal_mode", -1, &st, nullptr) == SQLITE_OK && sqlite3_step(st) == SQLITE_ROW)
    mode = reinterpret_cast<const char*>(sqlite3_column_text(st, 0));
  sqlite3_finalize(st);
  sqlite3_close(db);
  return mode;
}

bool WalOrShm(const std::string& path) { return fs::exists(path + "-wal") || fs::exists(path + "-shm"); }

TEST(SqliteAsrStore, ClosedStoreIsOneFileWithoutWal) {
  const std::string path = TempDir("sealed") + "/map.sqlite";
  {
    auto s = SqliteAsrStore::Open(path);
    for (int i = 0; i < 3; ++i) s->Put(MakeAsr(i));
    EXPECT_TRUE(fs::exists(path + "-wal"));  // WAL while the run writes
  }
  EXPECT_FALSE(WalOrShm(path));
  EXPECT_EQ(JournalMode(path), "delete");
  // The file alone is the store.
  const std::string copy = TempDir("sealed_copy") + "/map.sqlite";
  fs::copy_file(path, copy);
  EXPECT_EQ(SqliteAsrStore::Open(copy, SqliteAsrStore::OpenMode::kReadOnly)->Count(), 3);
}

TEST(SqliteAsrStore, ReadOnlyOpenCreatesNothingAndWritesNothing) {
  const std::string path = TempDir("readonly") + "/map.sqlite";
  SqliteAsrStore::Open(path)->Put(MakeAsr(0));
  {
    // A store left in WAL mode (by an older cogmap): read without a -shm.
    ExecSql(path, "PRAGMA journal_mode=WAL");
  }
  ASSERT_EQ(JournalMode(path), "wal");
  fs::remove(path + "-wal");
  fs::remove(path + "-shm");
  auto s = SqliteAsrStore::Open(path, SqliteAsrStore::OpenMode::kReadOnly);
  EXPECT_EQ(s->Count(), 1);
  ExpectSame(*s->Get(0), MakeAsr(0));
  EXPECT_THROW(s->Put(MakeAsr(1)), InputError);
  s.reset();
  EXPECT_FALSE(WalOrShm(path));
}

TEST(SqliteAsrStore, ReadOnlyFolderStillReads) {
  if (::geteuid() == 0) GTEST_SKIP() << "root ignores folder permissions";
  const std::string dir = TempDir("readonly_folder");
  const std::string path = dir + "/map.sqlite";
  SqliteAsrStore::Open(path)->Put(MakeAsr(0));
  ::chmod(dir.c_str(), 0555);
  EXPECT_EQ(SqliteAsrStore::Open(path, SqliteAsrStore::OpenMode::kReadOnly)->Count(), 1);
  try {
    SqliteAsrStore::Open(path, SqliteAsrStore::OpenMode::kOpenExisting);
    ADD_FAILURE() << "opened for writing in a read-only folder";
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()), dir + ": permission denied");
  }
  ::chmod(dir.c_str(), 0755);
}

TEST(SqliteAsrStore, RefusedStoresLeaveNoWalOrShm) {
  const std::string dir = TempDir("refused");
  const std::string newer = dir + "/newer.sqlite", other = dir + "/other.sqlite";
  SqliteAsrStore::Open(newer)->Put(MakeAsr(0));
  ExecSql(newer, "PRAGMA user_version=" + std::to_string(kStoreSchemaVersion + 1) + "; PRAGMA journal_mode=WAL");
  ExecSql(other, "PRAGMA journal_mode=WAL; CREATE TABLE t(x)");
  ASSERT_FALSE(WalOrShm(newer));
  ASSERT_FALSE(WalOrShm(other));
  for (const auto& path : {newer, other}) {
    for (auto mode : {SqliteAsrStore::OpenMode::kOpenExisting, SqliteAsrStore::OpenMode::kReadOnly,
                      SqliteAsrStore::OpenMode::kReplace})
      EXPECT_THROW(SqliteAsrStore::Open(path, mode), InputError);
    EXPECT_FALSE(WalOrShm(path)) << path;
  }
}

TEST(SqliteAsrStore, StoreOfAnotherSchemaIsRefusedAtOpening) {
  const std::string path = TempDir("schema") + "/map.sqlite";
  const std::string v = std::to_string(kStoreSchemaVersion);
  ExecSql(path, "PRAGMA application_id=" + std::to_string(kStoreApplicationId) + "; PRAGMA user_version=" + v +
                    ";"
                    "CREATE TABLE meta(key TEXT PRIMARY KEY, value TEXT NOT NULL);"
                    "CREATE TABLE asr(id INTEGER PRIMARY KEY, walls BLOB NOT NULL);");
  try {
    SqliteAsrStore::Open(path, SqliteAsrStore::OpenMode::kOpenExisting);
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()), path + ": not a cogmap store of schema version " + v + " (its tables differ)");
  }
}

TEST(SqliteAsrStore, OlderSchemaIsAClearError) {
  const std::string path = TempDir("older") + "/map.sqlite";
  SqliteAsrStore::Open(path)->Put(MakeAsr(0));
  ExecSql(path, "PRAGMA user_version=0");
  try {
    SqliteAsrStore::Open(path, SqliteAsrStore::OpenMode::kOpenExisting);
    FAIL() << "no error";
  } catch (const InputError& e) {
    // "... (N)", or "... (N) and cannot be migrated" where a migration exists for other versions.
    EXPECT_EQ(std::string(e.what()).rfind(
                  path + ": schema version 0 is older than this cogmap (" + std::to_string(kStoreSchemaVersion) + ")", 0),
              0u)
        << e.what();
  }
}

// A corrupt placement blob (found by fuzz_store) is the file's error, not a crash.
TEST(SqliteAsrStore, CorruptPlacementIsAnInputError) {
  const std::string path = TempDir("corrupt_placement") + "/map.sqlite";
  {
    auto s = SqliteAsrStore::Open(path);
    Placement p;
    p.asr_id = 0;
    p.room_id = 0;
    p.corrected_path = {{0, 0, 0}, {1, 0, 0}};
    s->PutPlacements({MakeAsr(0)}, {p}, {});
  }
  // A count of 5 poses and no pose after it.
  ExecSql(path, "UPDATE placement SET corrected_path=x'05000000'");
  auto s = SqliteAsrStore::Open(path, SqliteAsrStore::OpenMode::kReadOnly);
  try {
    s->GetPlacement(0);
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()), path + ": placement of ASR 0: corrupt ASR blob (count past the end)");
  }
  EXPECT_THROW(s->RoomOf(0), InputError);
}

// A number column holding text (a hand-edited or damaged row; SQLite keeps
// it as text) is the store's error, never read as 0.
TEST(SqliteAsrStore, TextInANumberColumnIsAnInputError) {
  const std::string path = TempDir("text_in_number") + "/map.sqlite";
  SqliteAsrStore::Open(path)->Put(MakeAsr(0));
  ExecSql(path, "UPDATE asr SET raw_x='abc'");
  auto s = SqliteAsrStore::Open(path, SqliteAsrStore::OpenMode::kReadOnly);
  try {
    s->Get(0);
    FAIL() << "no error";
  } catch (const InputError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("map.sqlite: store error: column 'raw_x' holds text, not a number"), std::string::npos)
        << what;
  }
}

// A store whose data pages were overwritten reads as an error naming the
// file, never as a store with fewer ASRs. (A store cut short is refused when
// opened: SQLite finds fewer pages than its header says.)
TEST(SqliteAsrStore, CorruptPagesAreAnInputErrorNotFewerAsrs) {
  const std::string path = TempDir("corrupt_pages") + "/map.sqlite";
  {
    auto s = SqliteAsrStore::Open(path);
    for (int id = 0; id < 40; ++id) s->Put(MakeAsr(id, 20));
  }
  const auto size = fs::file_size(path);
  {
    std::fstream f(path, std::ios::in | std::ios::out | std::ios::binary);
    f.seekp(static_cast<std::streamoff>(size / 2));
    const std::string junk(size - size / 2, '\x55');
    f.write(junk.data(), static_cast<std::streamsize>(junk.size()));
  }
  try {
    auto s = SqliteAsrStore::Open(path, SqliteAsrStore::OpenMode::kReadOnly);
    for (int id : s->Ids()) s->Get(id);
    s->Count();
    FAIL() << "a store whose second half is overwritten read without an error";
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()).rfind(path + ": ", 0), 0u) << e.what();
    std::printf("%s\n", e.what());
  }
}

// A store cut short (a copy that stopped half way) is refused when opened,
// with SQLite's reason, in every mode.
TEST(SqliteAsrStore, TruncatedStoreIsRefusedWhenOpened) {
  const std::string path = TempDir("truncated") + "/map.sqlite";
  {
    auto s = SqliteAsrStore::Open(path);
    for (int id = 0; id < 40; ++id) s->Put(MakeAsr(id, 20));
  }
  fs::resize_file(path, fs::file_size(path) / 2);
  for (auto mode : {SqliteAsrStore::OpenMode::kReadOnly, SqliteAsrStore::OpenMode::kOpenExisting}) {
    try {
      SqliteAsrStore::Open(path, mode);
      FAIL() << "no error";
    } catch (const InputError& e) {
      EXPECT_EQ(std::string(e.what()),
                path + ": a damaged store or not a cogmap store (unreadable SQLite file: database disk image is "
                       "malformed)");
    }
  }
}

TEST(AsrGraph, HoldsCurrentAndNeighboursAndLoadsTheRestOnDemand) {
  MemoryAsrStore store;
  for (int i = 0; i < 20; ++i) store.Put(MakeAsr(i));
  AsrGraph graph(&store, 2);
  graph.SetCurrent(10);
  EXPECT_EQ(graph.resident(), 3u);  // 9, 10, 11
  EXPECT_EQ(graph.loads(), 3);
  for (int i = 0; i < 20; ++i) ASSERT_NE(graph.Get(i), nullptr);
  EXPECT_EQ(graph.resident(), 5u);  // 3 pinned + 2 least recently used
  EXPECT_EQ(graph.Get(99), nullptr);
  const long loads = graph.loads();
  graph.Get(10);
  EXPECT_EQ(graph.loads(), loads);  // pinned: no reload
  graph.SetCurrent(15);
  EXPECT_LE(graph.resident(), 5u);
  EXPECT_EQ(graph.Get(16)->id, 16);
}

}  // namespace
}  // namespace cogmap::asr
