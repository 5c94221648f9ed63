#include "cogmap/asr/store.h"

#include <sqlite3.h>

#include <unistd.h>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "cogmap/core/error.h"

namespace cogmap::asr {

// ---------------------------------------------------------------- encodings

namespace {

class Writer {
 public:
  void U32(uint32_t v) { Raw(&v, 4); }
  void I32(int32_t v) { Raw(&v, 4); }
  void F64(double v) { Raw(&v, 8); }
  std::string take() { return std::move(bytes_); }

 private:
  void Raw(const void* p, size_t n) {  // the host is little-endian (x86-64, arm64)
    bytes_.append(static_cast<const char*>(p), n);
  }
  std::string bytes_;
};

class Reader {
 public:
  explicit Reader(const std::string& bytes) : bytes_(bytes) {}
  uint32_t U32() { uint32_t v; Raw(&v, 4); return v; }
  int32_t I32() { int32_t v; Raw(&v, 4); return v; }
  double F64() { double v; Raw(&v, 8); return v; }
  // A count of items of 'item_bytes' each that must fit in what is left.
  uint32_t Count(size_t item_bytes) {
    const uint32_t n = U32();
    if (item_bytes > 0 && n > (bytes_.size() - pos_) / item_bytes)
      throw std::runtime_error("corrupt ASR blob (count past the end)");
    return n;
  }

 private:
  void Raw(void* p, size_t n) {
    if (pos_ + n > bytes_.size()) throw std::runtime_error("corrupt ASR blob (truncated)");
    std::memcpy(p, bytes_.data() + pos_, n);
    pos_ += n;
  }
  const std::string& bytes_;
  size_t pos_ = 0;
};

}  // namespace

std::string EncodeWalls(const std::vector<Polyline>& walls) {
  Writer w;
  w.U32(static_cast<uint32_t>(walls.size()));
  for (const auto& line : walls) {
    w.U32(static_cast<uint32_t>(line.size()));
    for (const auto& p : line) {
      w.F64(p.x());
      w.F64(p.y());
    }
  }
  return w.take();
}

std::vector<Polyline> DecodeWalls(const std::string& blob) {
  if (blob.empty()) return {};
  Reader r(blob);
  std::vector<Polyline> walls(r.Count(4));
  for (auto& line : walls) {
    line.resize(r.Count(16));
    for (auto& p : line) {
      const double x = r.F64();
      p = Vec2(x, r.F64());
    }
  }
  return walls;
}

std::string EncodeExits(const std::vector<Exit>& exits) {
  Writer w;
  w.U32(static_cast<uint32_t>(exits.size()));
  for (const auto& e : exits) {
    w.F64(e.center_m.x());
    w.F64(e.center_m.y());
    w.F64(e.width_m);
    w.I32(e.from_asr);
    w.I32(e.to_asr);
  }
  return w.take();
}

std::vector<Exit> DecodeExits(const std::string& blob) {
  if (blob.empty()) return {};
  Reader r(blob);
  std::vector<Exit> exits(r.Count(32));
  for (auto& e : exits) {
    const double x = r.F64();
    e.center_m = Vec2(x, r.F64());
    e.width_m = r.F64();
    e.from_asr = r.I32();
    e.to_asr = r.I32();
  }
  return exits;
}

std::string EncodePoses(const std::vector<Pose2>& poses) {
  Writer w;
  w.U32(static_cast<uint32_t>(poses.size()));
  for (const auto& p : poses) {
    w.F64(p.x);
    w.F64(p.y);
    w.F64(p.theta);
  }
  return w.take();
}

std::string EncodeDoubles(const std::vector<double>& values) {
  Writer w;
  w.U32(static_cast<uint32_t>(values.size()));
  for (double v : values) w.F64(v);
  return w.take();
}

std::vector<double> DecodeDoubles(const std::string& blob) {
  if (blob.empty()) return {};
  Reader r(blob);
  std::vector<double> values(r.Count(8));
  for (double& v : values) v = r.F64();
  return values;
}

std::vector<Pose2> DecodePoses(const std::string& blob) {
  if (blob.empty()) return {};
  Reader r(blob);
  std::vector<Pose2> poses(r.Count(24));
  for (auto& p : poses) {
    p.x = r.F64();
    p.y = r.F64();
    p.theta = r.F64();
  }
  return poses;
}

// ---------------------------------------------------------------- memory

void MemoryAsrStore::Put(const Asr& asr, const std::map<std::string, std::string>& meta) {
  asrs_[asr.id] = asr;
  for (const auto& e : asr.exits)
    if (e.from_asr >= 0 && e.to_asr >= 0) edges_.insert({e.from_asr, e.to_asr});
  for (const auto& [k, v] : meta) meta_[k] = v;
}

std::optional<Asr> MemoryAsrStore::Get(int id) const {
  const auto it = asrs_.find(id);
  if (it == asrs_.end()) return std::nullopt;
  return it->second;
}

std::vector<int> MemoryAsrStore::Ids() const {
  std::vector<int> ids;
  for (const auto& [id, a] : asrs_) ids.push_back(id);
  return ids;
}

std::vector<int> MemoryAsrStore::Neighbours(int id) const {
  std::set<int> out;
  for (const auto& [a, b] : edges_) {
    if (a == id && b != id) out.insert(b);
    if (b == id && a != id) out.insert(a);
  }
  return {out.begin(), out.end()};
}

void MemoryAsrStore::PutPlacements(const std::vector<Asr>& asrs, const std::vector<Placement>& placements,
                                   const std::vector<ClosureRecord>& closures) {
  for (const Asr& a : asrs) asrs_[a.id] = a;
  for (const Placement& p : placements) placements_[p.asr_id] = p;
  closures_.insert(closures_.end(), closures.begin(), closures.end());
}

void MemoryAsrStore::RevisePlacements(const std::vector<int>& ids, const std::function<void(Asr&)>& revise,
                                      const std::vector<Placement>& placements,
                                      const std::vector<ClosureRecord>& closures) {
  for (int id : ids)
    if (auto it = asrs_.find(id); it != asrs_.end()) revise(it->second);
  PutPlacements({}, placements, closures);
}

int MemoryAsrStore::RoomOf(int id) const {
  auto it = placements_.find(id);
  return it == placements_.end() || it->second.room_id < 0 ? id : it->second.room_id;
}

std::optional<Placement> MemoryAsrStore::GetPlacement(int id) const {
  auto it = placements_.find(id);
  if (it == placements_.end()) return std::nullopt;
  return it->second;
}

std::optional<long> AsrStore::GetMetaInt(const std::string& key, long min, long max) const {
  const std::optional<std::string> text = GetMeta(key);
  if (!text) return std::nullopt;
  long value = 0;
  const char* end = text->data() + text->size();
  const auto [at, ec] = std::from_chars(text->data(), end, value);
  if (ec != std::errc() || at != end || text->empty() || value < min || value > max)
    throw InputError(Name(), 0,
                     "a damaged store: meta " + key + " is '" + *text + "', not an integer in [" +
                         std::to_string(min) + ", " + std::to_string(max) + "]");
  return value;
}

std::optional<Pose2> AsrStore::GetMetaPose(const std::string& key) const {
  const std::optional<std::string> text = GetMeta(key);
  if (!text) return std::nullopt;
  std::istringstream in(*text);
  Pose2 p;
  std::string rest;
  if (!(in >> p.x >> p.y >> p.theta) || (in >> rest) || !std::isfinite(p.x) || !std::isfinite(p.y) ||
      !std::isfinite(p.theta))
    throw InputError(Name(), 0, "a damaged store: meta " + key + " is '" + *text + "', not a pose (x y theta)");
  return p;
}

std::optional<double> AsrStore::GetMetaPositive(const std::string& key) const {
  const std::optional<std::string> text = GetMeta(key);
  if (!text) return std::nullopt;
  double v = 0.0;
  const char* end = text->data() + text->size();
  const auto [at, ec] = std::from_chars(text->data(), end, v);
  if (ec != std::errc() || at != end || text->empty() || !std::isfinite(v) || v <= 0.0)
    throw InputError(Name(), 0, "a damaged store: meta " + key + " is '" + *text + "', not a positive number");
  return v;
}

std::optional<std::string> MemoryAsrStore::GetMeta(const std::string& key) const {
  const auto it = meta_.find(key);
  if (it == meta_.end()) return std::nullopt;
  return it->second;
}

// ---------------------------------------------------------------- SQLite

namespace {

sqlite3* Db(void* p) { return static_cast<sqlite3*>(p); }

// A prepared statement, finalized on scope exit; or, given the store's cache
// of statements, prepared once and reset on scope exit (a store of 1000 ASRs
// runs the same few statements thousands of times: preparing each anew cost
// as much as running it). A cached statement still running (a caller nested
// in another's loop over the same query) is not shared: that use prepares
// its own.
class Stmt {
 public:
  Stmt(sqlite3* db, const char* sql) : db_(db) {
    if (sqlite3_prepare_v2(db, sql, -1, &stmt_, nullptr) != SQLITE_OK) stmt_ = nullptr;
  }
  Stmt(sqlite3* db, const char* sql, std::map<std::string, void*>* cache) : db_(db) {
    void*& slot = (*cache)[sql];
    sqlite3_stmt* cached = static_cast<sqlite3_stmt*>(slot);
    if (cached && !sqlite3_stmt_busy(cached)) {
      stmt_ = cached;
      cached_ = true;
      return;
    }
    if (cached) {  // in use further up: a statement of its own
      if (sqlite3_prepare_v2(db, sql, -1, &stmt_, nullptr) != SQLITE_OK) stmt_ = nullptr;
      return;
    }
    if (sqlite3_prepare_v3(db, sql, -1, SQLITE_PREPARE_PERSISTENT, &stmt_, nullptr) != SQLITE_OK) {
      stmt_ = nullptr;
      return;
    }
    slot = stmt_;
    cached_ = true;
  }
  ~Stmt() {
    if (!cached_) {
      sqlite3_finalize(stmt_);
      return;
    }
    sqlite3_reset(stmt_);
    sqlite3_clear_bindings(stmt_);
  }
  Stmt(const Stmt&) = delete;
  Stmt& operator=(const Stmt&) = delete;
  bool ok() const { return stmt_ != nullptr; }
  sqlite3_stmt* get() { return stmt_; }
  void Bind(int i, double v) { sqlite3_bind_double(stmt_, i, v); }
  void BindInt(int i, int64_t v) { sqlite3_bind_int64(stmt_, i, v); }
  void BindText(int i, const std::string& v) {
    sqlite3_bind_text(stmt_, i, v.data(), static_cast<int>(v.size()), SQLITE_TRANSIENT);
  }
  void BindBlob(int i, const std::string& v) {
    sqlite3_bind_blob(stmt_, i, v.data(), static_cast<int>(v.size()), SQLITE_TRANSIENT);
  }
  int Step() { return last_ = sqlite3_step(stmt_); }
  // Not prepared, or the last step failed (a corrupt file, an I/O error):
  // never read as the end of the rows.
  bool failed() const { return !stmt_ || (last_ != SQLITE_ROW && last_ != SQLITE_DONE); }
  // A number, or the store's error: SQLite keeps whatever a hand-edited or
  // damaged row holds ('abc' in a REAL column stays text), and reading text as
  // a number would silently give 0.
  double Double(int i) {
    const int type = sqlite3_column_type(stmt_, i);
    if (type != SQLITE_FLOAT && type != SQLITE_INTEGER) NotA("number", i, type);
    return sqlite3_column_double(stmt_, i);
  }
  int64_t Int(int i) {
    const int type = sqlite3_column_type(stmt_, i);
    if (type != SQLITE_INTEGER) NotA("whole number", i, type);
    return sqlite3_column_int64(stmt_, i);
  }
  std::string Blob(int i) {
    const void* p = sqlite3_column_blob(stmt_, i);
    const int n = sqlite3_column_bytes(stmt_, i);
    return p ? std::string(static_cast<const char*>(p), n) : std::string();
  }
  std::string Text(int i) {
    const unsigned char* p = sqlite3_column_text(stmt_, i);
    return p ? std::string(reinterpret_cast<const char*>(p)) : std::string();
  }

 private:
  [[noreturn]] void NotA(const char* what, int i, int type) {
    static const char* const kTypes[] = {"?", "an integer", "a real number", "text", "a blob", "NULL"};
    const char* name = sqlite3_column_name(stmt_, i);
    const char* file = sqlite3_db_filename(db_, "main");
    throw InputError(file ? file : "store", 0,
                     std::string("store error: column '") + (name ? name : "?") + "' holds " +
                         kTypes[type >= 1 && type <= 5 ? type : 0] + ", not a " + what);
  }

  sqlite3* db_;
  sqlite3_stmt* stmt_ = nullptr;
  bool cached_ = false;
  int last_ = SQLITE_DONE;
};

const char* kSchema = R"sql(
CREATE TABLE IF NOT EXISTS meta(key TEXT PRIMARY KEY, value TEXT NOT NULL);
CREATE TABLE IF NOT EXISTS asr(
  id INTEGER PRIMARY KEY,
  raw_x REAL NOT NULL, raw_y REAL NOT NULL, raw_theta REAL NOT NULL,
  cor_x REAL NOT NULL, cor_y REAL NOT NULL, cor_theta REAL NOT NULL,
  pivot_x REAL NOT NULL, pivot_y REAL NOT NULL,
  start_time_s REAL NOT NULL, end_time_s REAL NOT NULL,
  bytes_grid INTEGER NOT NULL, bytes_vertices INTEGER NOT NULL, bytes_polylines INTEGER NOT NULL,
  sec_grid REAL NOT NULL, sec_clean REAL NOT NULL, sec_extract REAL NOT NULL,
  sec_simplify REAL NOT NULL, sec_fit REAL NOT NULL,
  heading_correction_rad REAL NOT NULL, heading_uncertainty_rad REAL NOT NULL,
  walls BLOB NOT NULL, exits BLOB NOT NULL, path BLOB NOT NULL, true_path BLOB NOT NULL);
CREATE TABLE IF NOT EXISTS edge(
  from_asr INTEGER NOT NULL, to_asr INTEGER NOT NULL,
  center_x REAL NOT NULL, center_y REAL NOT NULL, width_m REAL NOT NULL,
  PRIMARY KEY(from_asr, to_asr));
CREATE INDEX IF NOT EXISTS edge_to ON edge(to_asr);
)sql";

// Schema version 2 (issue 10): the pose graph's placement of each ASR (its
// physical room, pose covariance, whether it is uncertain and why) and every
// loop-closure candidate with its verdict. A version-1 store is migrated by
// creating these tables (its ASRs keep room_id = their own id).
const char* kSchemaV2 = R"sql(
CREATE TABLE IF NOT EXISTS placement(
  asr_id INTEGER PRIMARY KEY, room_id INTEGER NOT NULL,
  cov BLOB NOT NULL, uncertain INTEGER NOT NULL, why TEXT NOT NULL, drift_rate REAL NOT NULL,
  corrected_path BLOB NOT NULL);
CREATE TABLE IF NOT EXISTS closure(
  from_asr INTEGER NOT NULL, to_asr INTEGER NOT NULL,
  rel_x REAL NOT NULL, rel_y REAL NOT NULL, rel_theta REAL NOT NULL,
  agreement REAL NOT NULL, rmse_m REAL NOT NULL, mahalanobis2 REAL NOT NULL,
  accepted INTEGER NOT NULL, same_room INTEGER NOT NULL, reason TEXT NOT NULL,
  PRIMARY KEY(from_asr, to_asr));
)sql";

// Schema version 3 (resume after a kill, issue 14): each ASR's grid
// orientation (GridOrientation), which the pose graph's heading estimate uses
// and which cannot be recomputed once the room's grid is gone. With it a
// store cut short by a kill replays into the pose graph as the uninterrupted
// run placed it (docs/store.md, "--resume"). Version-1 and -2 stores are
// migrated by creating the table (their ASRs have no orientation row).
const char* kSchemaV3 = R"sql(
CREATE TABLE IF NOT EXISTS orientation(
  asr_id INTEGER PRIMARY KEY, valid INTEGER NOT NULL, angle_rad REAL NOT NULL,
  contrast REAL NOT NULL, cells INTEGER NOT NULL);
)sql";

// Schema version 4 (issue 11): the floor each ASR's grid saw
// (Asr::free_hull_local), a walls-format blob holding one closed-less
// polygon. Older stores are migrated by creating the table (their ASRs have no
// row: the floor plan bounds them by their walls and path as before).
const char* kSchemaV4 = R"sql(
CREATE TABLE IF NOT EXISTS free_space(asr_id INTEGER PRIMARY KEY, hull BLOB NOT NULL);
)sql";

// Schema version 5: the walls the pose graph matched (Asr::matched_walls_local),
// when they are not the walls kept (a sonar's axis-grid walls beside its
// cone-grid walls, asr::MapperOptions::cone_output_walls). With them a run
// resumed after a kill registers and closes loops on the walls the
// uninterrupted run used. Older stores are migrated by creating the table
// (their ASRs have no row: the walls kept are the walls matched, as then).
const char* kSchemaV5 = R"sql(
CREATE TABLE IF NOT EXISTS matched_walls(asr_id INTEGER PRIMARY KEY, walls BLOB NOT NULL);
)sql";

// Schema version 6: the drift rate removed inside each ASR while its grids
// were built (Asr::pre_bend_rad_per_m), a row only where it is not zero. With
// it the pose graph knows how the walls it matches were mapped (a resumed run
// replays them as the uninterrupted run placed them). Older stores are
// migrated by creating the table (their ASRs were mapped on the raw odometry).
const char* kSchemaV6 = R"sql(
CREATE TABLE IF NOT EXISTS pre_bend(asr_id INTEGER PRIMARY KEY, rate REAL NOT NULL);
)sql";

// Schema version 7: how far the heading turned along each ASR's path
// (Asr::path_turn_rad, a blob of a count and that many doubles) and after it
// (Asr::turn_after_path_rad), a row only where the robot turned. The pose
// graph's odometry noise grows with the turning: without them a run resumed
// after a kill replayed the killed run's ASRs with odometry too sure of its
// heading, accepted other closures and ended metres from the uninterrupted
// run (100-room building: a median 4.6 m for the killed run's ASRs, 16 m
// for the ones after; 0.12 and 0.59 m with the turns). Older stores are
// migrated by creating the table (their ASRs replay without turns, as then).
const char* kSchemaV7 = R"sql(
CREATE TABLE IF NOT EXISTS path_turn(asr_id INTEGER PRIMARY KEY, turns BLOB NOT NULL, after REAL NOT NULL);
)sql";

bool HasSqliteHeader(const std::string& path, bool* empty) {
  std::ifstream in(path, std::ios::binary);
  char header[16] = {};
  in.read(header, 16);
  *empty = in.gcount() == 0;
  return in.gcount() == 16 && std::memcmp(header, "SQLite format 3\0", 16) == 0;
}

void RemoveStoreFiles(const std::string& path) {
  std::error_code ec;
  for (const char* suffix : {"", "-wal", "-shm", "-journal"})
    std::filesystem::remove(path + suffix, ec);
}

std::string FolderOf(const std::string& path) {
  const std::filesystem::path parent = std::filesystem::path(path).parent_path();
  return parent.empty() ? std::string(".") : parent.string();
}

// "file:PATH?mode=ro" or "...?immutable=1" (SQLITE_OPEN_URI): the path with
// the characters a URI gives a meaning to escaped.
std::string FileUri(const std::string& path, const char* query) {
  std::string uri = "file:";
  for (const char c : std::filesystem::absolute(path).string()) {
    if (c == '?' || c == '#' || c == '%') {
      char hex[4];
      std::snprintf(hex, sizeof hex, "%%%02X", static_cast<unsigned char>(c));
      uri += hex;
    } else {
      uri += c;
    }
  }
  return uri + "?" + query;
}

bool NonEmptyFile(const std::string& path) {
  std::error_code ec;
  return std::filesystem::is_regular_file(path, ec) && std::filesystem::file_size(path, ec) > 0 && !ec;
}

// Opens 'path' for reading without creating anything beside it: immutable
// unless a write-ahead log holds transactions (a store of a killed run), which
// a read-only connection applies (and then needs a writable folder).
sqlite3* OpenForReading(const std::string& path, std::string* error) {
  const bool wal = NonEmptyFile(path + "-wal");
  const bool folder_writable = ::access(FolderOf(path).c_str(), W_OK) == 0;
  const std::string uri = FileUri(path, wal && folder_writable ? "mode=ro" : "immutable=1");
  sqlite3* db = nullptr;
  if (sqlite3_open_v2(uri.c_str(), &db, SQLITE_OPEN_READONLY | SQLITE_OPEN_URI, nullptr) != SQLITE_OK) {
    *error = db ? sqlite3_errmsg(db) : "cannot open";
    sqlite3_close(db);
    return nullptr;
  }
  return db;
}

// Column names and types of every table, as "table(name type, ...)" lines.
std::string SchemaOf(sqlite3* db, bool* readable) {
  std::string out;
  Stmt t(db, "SELECT name FROM sqlite_master WHERE type='table' ORDER BY name");
  if (!t.ok()) *readable = false;
  std::vector<std::string> tables;
  while (t.ok() && t.Step() == SQLITE_ROW) tables.push_back(t.Text(0));
  for (const auto& name : tables) {
    out += name + "(";
    Stmt c(db, ("SELECT name, type FROM pragma_table_info('" + name + "') ORDER BY cid").c_str());
    if (!c.ok()) *readable = false;
    while (c.ok() && c.Step() == SQLITE_ROW) out += c.Text(0) + " " + c.Text(1) + ", ";
    out += ")\n";
  }
  return out;
}

// The tables a store of 'version' (1 .. kStoreSchemaVersion) has.
std::string SchemaOfVersion(int version) {
  sqlite3* db = nullptr;
  sqlite3_open(":memory:", &db);
  sqlite3_exec(db, kSchema, nullptr, nullptr, nullptr);
  if (version >= 2) sqlite3_exec(db, kSchemaV2, nullptr, nullptr, nullptr);
  if (version >= 3) sqlite3_exec(db, kSchemaV3, nullptr, nullptr, nullptr);
  if (version >= 4) sqlite3_exec(db, kSchemaV4, nullptr, nullptr, nullptr);
  if (version >= 5) sqlite3_exec(db, kSchemaV5, nullptr, nullptr, nullptr);
  if (version >= 6) sqlite3_exec(db, kSchemaV6, nullptr, nullptr, nullptr);
  if (version >= 7) sqlite3_exec(db, kSchemaV7, nullptr, nullptr, nullptr);
  bool readable = true;
  std::string s = SchemaOf(db, &readable);
  sqlite3_close(db);
  return s;
}
const std::string& ExpectedSchema() {
  static const std::string schema = SchemaOfVersion(kStoreSchemaVersion);
  return schema;
}
bool HasTable(sqlite3* db, const char* name) {
  Stmt s(db, "SELECT count(*) FROM sqlite_master WHERE type='table' AND name=?");
  sqlite3_bind_text(s.get(), 1, name, -1, SQLITE_TRANSIENT);
  return s.ok() && s.Step() == SQLITE_ROW && s.Int(0) > 0;
}

// An older version this cogmap migrates (and reads as it is when read-only):
// its tables must be exactly that version's.
bool MigratableVersion(int version, const std::string& schema) {
  static const std::string v1 = SchemaOfVersion(1), v2 = SchemaOfVersion(2), v3 = SchemaOfVersion(3),
                           v4 = SchemaOfVersion(4), v5 = SchemaOfVersion(5), v6 = SchemaOfVersion(6);
  return (version == 1 && schema == v1) || (version == 2 && schema == v2) || (version == 3 && schema == v3) ||
         (version == 4 && schema == v4) || (version == 5 && schema == v5) || (version == 6 && schema == v6);
}

}  // namespace

void SqliteAsrStore::Exec(const std::string& sql) const {
  char* err = nullptr;
  if (sqlite3_exec(Db(db_), sql.c_str(), nullptr, nullptr, &err) != SQLITE_OK) {
    const std::string msg = err ? err : "unknown error";
    sqlite3_free(err);
    Fail(msg);
  }
}

std::optional<std::vector<Polyline>> SqliteAsrStore::WallsRow(const char* sql, int id, const std::string& what) const {
  Stmt q(Db(db_), sql, &statements_);
  if (!q.ok()) Fail(sqlite3_errmsg(Db(db_)));
  q.BindInt(1, id);
  if (q.Step() == SQLITE_ROW) {
    try {
      return DecodeWalls(q.Blob(0));
    } catch (const std::runtime_error& e) {
      throw InputError(path_, 0, "ASR " + std::to_string(id) + ": " + what + ": " + e.what());
    }
  }
  if (q.failed()) Fail(what + " of ASR " + std::to_string(id) + ": " + sqlite3_errmsg(Db(db_)));
  return std::nullopt;
}

void SqliteAsrStore::Fail(const std::string& what) const {
  throw InputError(path_, 0, "store error: " + what);
}

std::unique_ptr<SqliteAsrStore> SqliteAsrStore::Open(const std::string& path, OpenMode mode) {
  namespace fs = std::filesystem;
  std::error_code ec;
  const bool exists = fs::exists(path, ec);
  const bool read_only = mode == OpenMode::kReadOnly;
  if ((mode == OpenMode::kOpenExisting || read_only) && !exists) throw InputError(path, 0, "no such store");
  if (exists && fs::is_directory(path, ec)) throw InputError(path, 0, "is a directory, not a cogmap store");
  // Permissions first: a store we may not read or write is not a foreign file.
  if (exists && ::access(path.c_str(), R_OK) != 0) throw InputError(path, 0, "permission denied");
  if (!read_only) {
    if (::access(FolderOf(path).c_str(), W_OK) != 0) throw InputError(FolderOf(path), 0, "permission denied");
    if (exists && ::access(path.c_str(), W_OK) != 0) throw InputError(path, 0, "permission denied");
  }
  bool empty = false;
  if (exists && !HasSqliteHeader(path, &empty) && !empty)
    throw InputError(path, 0, "not a cogmap store (not an SQLite database)");
  if (read_only && empty) throw InputError(path, 0, "not a cogmap store (empty file)");
  if (exists && !empty) {
    // Check the markers before anything is changed (and without creating
    // -wal / -shm files beside a file that is then refused).
    std::string error;
    sqlite3* probe = OpenForReading(path, &error);
    if (!probe) throw InputError(path, 0, "cannot open store: " + error);
    int app_id = 0, version = 0;
    bool readable = true;
    std::string why;  // SQLite's first complaint ("database disk image is malformed")
    auto unreadable = [&] {
      if (readable) why = sqlite3_errmsg(probe);
      readable = false;
    };
    {
      Stmt a(probe, "PRAGMA application_id");
      if (a.ok() && a.Step() == SQLITE_ROW) app_id = static_cast<int>(a.Int(0)); else unreadable();
      Stmt v(probe, "PRAGMA user_version");
      if (v.ok() && v.Step() == SQLITE_ROW) version = static_cast<int>(v.Int(0)); else unreadable();
    }
    int tables = 0;
    {
      Stmt t(probe, "SELECT count(*) FROM sqlite_master");
      if (t.ok() && t.Step() == SQLITE_ROW) tables = static_cast<int>(t.Int(0)); else unreadable();
    }
    std::string schema;
    if (readable && tables > 0) {
      schema = SchemaOf(probe, &readable);
      if (!readable) why = sqlite3_errmsg(probe);
    }
    sqlite3_close(probe);
    // A cogmap store cut short or overwritten reads like this too: say both.
    if (!readable)
      throw InputError(path, 0, "a damaged store or not a cogmap store (unreadable SQLite file: " + why + ")");
    if (tables > 0 && app_id != kStoreApplicationId)
      throw InputError(path, 0, "not a cogmap store (an SQLite database of another application)");
    if (version > kStoreSchemaVersion)
      throw InputError(path, 0, "schema version " + std::to_string(version) +
                                    " is newer than this cogmap (" + std::to_string(kStoreSchemaVersion) + ")");
    // Versions 1 to 3 are migrated (read-only: read as they are, without
    // placements, orientations or free space).
    const bool older = tables > 0 && version < kStoreSchemaVersion && MigratableVersion(version, schema);
    if (tables > 0 && version < kStoreSchemaVersion && !older)
      throw InputError(path, 0, "schema version " + std::to_string(version) +
                                    " is older than this cogmap (" + std::to_string(kStoreSchemaVersion) +
                                    ") and cannot be migrated");
    if (tables > 0 && !older && schema != ExpectedSchema())
      throw InputError(path, 0, "not a cogmap store of schema version " + std::to_string(kStoreSchemaVersion) +
                                    " (its tables differ)");
    if (read_only && tables == 0) throw InputError(path, 0, "not a cogmap store (an empty SQLite database)");
    if (mode == OpenMode::kReplace) RemoveStoreFiles(path);
  }
  if (read_only) {
    std::string error;
    sqlite3* db = OpenForReading(path, &error);
    if (!db) throw InputError(path, 0, "cannot open store: " + error);
    std::unique_ptr<SqliteAsrStore> store(new SqliteAsrStore(path, db, /*read_only=*/true));
    store->has_orientation_ = HasTable(db, "orientation");
    store->has_free_space_ = HasTable(db, "free_space");
    store->has_matched_walls_ = HasTable(db, "matched_walls");
    store->has_pre_bend_ = HasTable(db, "pre_bend");
    store->has_path_turn_ = HasTable(db, "path_turn");
    store->has_placement_ = HasTable(db, "placement");
    store->has_closure_ = HasTable(db, "closure");
    return store;
  }
  sqlite3* db = nullptr;
  if (sqlite3_open_v2(path.c_str(), &db, SQLITE_OPEN_READWRITE | SQLITE_OPEN_CREATE, nullptr) != SQLITE_OK) {
    const std::string msg = db ? sqlite3_errmsg(db) : "cannot open";
    sqlite3_close(db);
    throw InputError(path, 0, "cannot create store: " + msg);
  }
  sqlite3_busy_timeout(db, 5000);
  std::unique_ptr<SqliteAsrStore> store(new SqliteAsrStore(path, db));
  // The switch to WAL rewrites the file's header in a transaction of the
  // rollback journal, synced twice at SQLite's default (synchronous=FULL):
  // 1-6 ms of a run's start. A store created here holds nothing a crash
  // could lose (cogmap map's is a staging copy until the output folder's
  // commit syncs it, io::OutputFolder), so its switch is not synced; one
  // with rows in it is.
  const bool fresh = !exists || empty || mode == OpenMode::kReplace;
  if (fresh) store->Exec("PRAGMA synchronous=OFF");
  store->Exec("PRAGMA journal_mode=WAL");
  // Under WAL, NORMAL keeps the store consistent through a crash of the
  // application or of the machine; a power cut may lose the last commits
  // (https://www.sqlite.org/pragma.html#pragma_synchronous). FULL would sync
  // at every ASR.
  store->Exec("PRAGMA synchronous=NORMAL");
  // ASRs are written once and read on demand: a small page cache keeps the
  // memory of a long run flat (SQLite's default is 2 MB).
  store->Exec("PRAGMA cache_size=-256");
  store->Exec("BEGIN IMMEDIATE");
  try {
    store->Exec(kSchema);
    store->Exec(kSchemaV2);
    store->Exec(kSchemaV3);
    store->Exec(kSchemaV4);
    store->Exec(kSchemaV5);
    store->Exec(kSchemaV6);
    store->Exec(kSchemaV7);
    store->has_orientation_ = true;
    store->has_pre_bend_ = true;
    store->has_path_turn_ = true;
    store->has_free_space_ = true;
    store->has_matched_walls_ = true;
    store->has_placement_ = true;
    store->has_closure_ = true;
    store->Exec("PRAGMA application_id=" + std::to_string(kStoreApplicationId));
    store->Exec("PRAGMA user_version=" + std::to_string(kStoreSchemaVersion));
    store->Exec("INSERT OR IGNORE INTO meta(key, value) VALUES('application', 'cogmap')");
    store->Exec("INSERT OR REPLACE INTO meta(key, value) VALUES('schema_version', '" +
                std::to_string(kStoreSchemaVersion) + "')");
    store->Exec("COMMIT");
  } catch (...) {
    sqlite3_exec(db, "ROLLBACK", nullptr, nullptr, nullptr);
    throw;
  }
  return store;
}

SqliteAsrStore::~SqliteAsrStore() {
  sqlite3* db = Db(db_);
  for (auto& [sql, stmt] : statements_) sqlite3_finalize(static_cast<sqlite3_stmt*>(stmt));
  if (db && !read_only_) {
    // Leave the file self-contained: everything checkpointed into it and no
    // WAL (a store on read-only media, or copied alone, reads whole). Skipped
    // silently while another connection holds the store.
    sqlite3_busy_timeout(db, 0);
    if (sqlite3_exec(db, "PRAGMA wal_checkpoint(TRUNCATE)", nullptr, nullptr, nullptr) == SQLITE_OK)
      sqlite3_exec(db, "PRAGMA journal_mode=DELETE", nullptr, nullptr, nullptr);
  }
  sqlite3_close(db);
}

void SqliteAsrStore::Put(const Asr& asr, const std::map<std::string, std::string>& meta) {
  std::lock_guard<std::recursive_mutex> lock(mutex_);
  sqlite3* db = Db(db_);
  if (!in_batch_) Exec("BEGIN IMMEDIATE");
  auto fail = [&](const std::string& what) {
    const std::string msg = what + ": " + sqlite3_errmsg(db);
    if (!in_batch_) sqlite3_exec(db, "ROLLBACK", nullptr, nullptr, nullptr);
    Fail("cannot store ASR " + std::to_string(asr.id) + " (" + msg + ")");
  };
  {
    Stmt s(db, "INSERT OR REPLACE INTO asr VALUES(?,?,?,?,?,?,?,?,?,?,?,?,?,?,?,?,?,?,?,?,?,?,?,?,?)", &statements_);
    if (!s.ok()) fail("prepare");
    int i = 1;
    s.BindInt(i++, asr.id);
    s.Bind(i++, asr.world_from_local_raw.x);
    s.Bind(i++, asr.world_from_local_raw.y);
    s.Bind(i++, asr.world_from_local_raw.theta);
    s.Bind(i++, asr.world_from_local_corrected.x);
    s.Bind(i++, asr.world_from_local_corrected.y);
    s.Bind(i++, asr.world_from_local_corrected.theta);
    s.Bind(i++, asr.entry_pivot_m.x());
    s.Bind(i++, asr.entry_pivot_m.y());
    s.Bind(i++, asr.start_time_s);
    s.Bind(i++, asr.end_time_s);
    s.BindInt(i++, asr.bytes.grid);
    s.BindInt(i++, asr.bytes.vertices);
    s.BindInt(i++, asr.bytes.polylines);
    s.Bind(i++, asr.seconds.grid);
    s.Bind(i++, asr.seconds.clean);
    s.Bind(i++, asr.seconds.extract);
    s.Bind(i++, asr.seconds.simplify);
    s.Bind(i++, asr.seconds.fit);
    s.Bind(i++, asr.heading_correction_rad);
    s.Bind(i++, asr.heading_uncertainty_rad);
    s.BindBlob(i++, EncodeWalls(asr.walls_local));
    s.BindBlob(i++, EncodeExits(asr.exits));
    s.BindBlob(i++, EncodePoses(asr.path));
    s.BindBlob(i++, EncodePoses(asr.true_path));
    if (s.Step() != SQLITE_DONE) fail("insert");
  }
  {
    const GridOrientation& g = asr.grid_orientation;
    Stmt s(db, "INSERT OR REPLACE INTO orientation VALUES(?,?,?,?,?)", &statements_);
    if (!s.ok()) fail("prepare");
    s.BindInt(1, asr.id);
    s.BindInt(2, g.valid ? 1 : 0);
    s.Bind(3, g.angle_rad);
    s.Bind(4, g.contrast);
    s.BindInt(5, g.cells);
    if (s.Step() != SQLITE_DONE) fail("insert orientation");
  }
  if (asr.has_matched_walls) {
    Stmt s(db, "INSERT OR REPLACE INTO matched_walls VALUES(?,?)", &statements_);
    if (!s.ok()) fail("prepare");
    s.BindInt(1, asr.id);
    s.BindBlob(2, EncodeWalls(asr.matched_walls_local));
    if (s.Step() != SQLITE_DONE) fail("insert matched walls");
  }
  {
    // A row only where the rate is not zero (an ASR written again with none
    // loses its row).
    const bool bent = asr.pre_bend_rad_per_m != 0.0;
    Stmt s(db, bent ? "INSERT OR REPLACE INTO pre_bend VALUES(?,?)" : "DELETE FROM pre_bend WHERE asr_id=?",
           &statements_);
    if (!s.ok()) fail("prepare");
    s.BindInt(1, asr.id);
    if (bent) s.Bind(2, asr.pre_bend_rad_per_m);
    if (s.Step() != SQLITE_DONE) fail("insert pre-bend");
  }
  {
    // A row only where the robot turned (an ASR written again without turns
    // loses its row).
    const bool turned = asr.turn_after_path_rad != 0.0 ||
                        std::any_of(asr.path_turn_rad.begin(), asr.path_turn_rad.end(), [](double t) { return t != 0.0; });
    Stmt s(db, turned ? "INSERT OR REPLACE INTO path_turn VALUES(?,?,?)" : "DELETE FROM path_turn WHERE asr_id=?",
           &statements_);
    if (!s.ok()) fail("prepare");
    s.BindInt(1, asr.id);
    if (turned) {
      s.BindBlob(2, EncodeDoubles(asr.path_turn_rad));
      s.Bind(3, asr.turn_after_path_rad);
    }
    if (s.Step() != SQLITE_DONE) fail("insert path turns");
  }
  if (!asr.free_hull_local.empty()) {
    Stmt s(db, "INSERT OR REPLACE INTO free_space VALUES(?,?)", &statements_);
    if (!s.ok()) fail("prepare");
    s.BindInt(1, asr.id);
    s.BindBlob(2, EncodeWalls({asr.free_hull_local}));
    if (s.Step() != SQLITE_DONE) fail("insert free space");
  }
  for (const auto& e : asr.exits) {
    if (e.from_asr < 0 || e.to_asr < 0) continue;
    Stmt s(db, "INSERT OR REPLACE INTO edge VALUES(?,?,?,?,?)", &statements_);
    if (!s.ok()) fail("prepare");
    s.BindInt(1, e.from_asr);
    s.BindInt(2, e.to_asr);
    s.Bind(3, e.center_m.x());
    s.Bind(4, e.center_m.y());
    s.Bind(5, e.width_m);
    if (s.Step() != SQLITE_DONE) fail("insert edge");
  }
  for (const auto& [k, v] : meta) {
    Stmt s(db, "INSERT OR REPLACE INTO meta VALUES(?,?)", &statements_);
    if (!s.ok()) fail("prepare");
    s.BindText(1, k);
    s.BindText(2, v);
    if (s.Step() != SQLITE_DONE) fail("insert meta");
  }
  if (!in_batch_ && sqlite3_exec(db, "COMMIT", nullptr, nullptr, nullptr) != SQLITE_OK) fail("commit");
}

std::optional<Asr> SqliteAsrStore::Get(int id) const {
  std::lock_guard<std::recursive_mutex> lock(mutex_);
  Stmt s(Db(db_), "SELECT * FROM asr WHERE id=?", &statements_);
  if (!s.ok()) Fail(sqlite3_errmsg(Db(db_)));
  s.BindInt(1, id);
  if (s.Step() != SQLITE_ROW) {
    if (s.failed()) Fail("ASR " + std::to_string(id) + ": " + sqlite3_errmsg(Db(db_)));
    return std::nullopt;
  }
  Asr a;
  int i = 0;
  a.id = static_cast<int>(s.Int(i++));
  a.world_from_local_raw.x = s.Double(i++);
  a.world_from_local_raw.y = s.Double(i++);
  a.world_from_local_raw.theta = s.Double(i++);
  a.world_from_local_corrected.x = s.Double(i++);
  a.world_from_local_corrected.y = s.Double(i++);
  a.world_from_local_corrected.theta = s.Double(i++);
  const double px = s.Double(i++);
  a.entry_pivot_m = Vec2(px, s.Double(i++));
  a.start_time_s = s.Double(i++);
  a.end_time_s = s.Double(i++);
  a.bytes.grid = s.Int(i++);
  a.bytes.vertices = s.Int(i++);
  a.bytes.polylines = s.Int(i++);
  a.seconds.grid = s.Double(i++);
  a.seconds.clean = s.Double(i++);
  a.seconds.extract = s.Double(i++);
  a.seconds.simplify = s.Double(i++);
  a.seconds.fit = s.Double(i++);
  a.heading_correction_rad = s.Double(i++);
  a.heading_uncertainty_rad = s.Double(i++);
  try {
    a.walls_local = DecodeWalls(s.Blob(i++));
    a.exits = DecodeExits(s.Blob(i++));
    a.path = DecodePoses(s.Blob(i++));
    a.true_path = DecodePoses(s.Blob(i++));
  } catch (const std::runtime_error& e) {
    throw InputError(path_, 0, "ASR " + std::to_string(id) + ": " + e.what());
  }
  if (has_orientation_) {
    Stmt o(Db(db_), "SELECT valid, angle_rad, contrast, cells FROM orientation WHERE asr_id=?", &statements_);
    if (!o.ok()) Fail(sqlite3_errmsg(Db(db_)));
    o.BindInt(1, id);
    if (o.Step() == SQLITE_ROW) {
      a.grid_orientation.valid = o.Int(0) != 0;
      a.grid_orientation.angle_rad = o.Double(1);
      a.grid_orientation.contrast = o.Double(2);
      a.grid_orientation.cells = static_cast<int>(o.Int(3));
    } else if (o.failed()) {
      Fail("orientation of ASR " + std::to_string(id) + ": " + sqlite3_errmsg(Db(db_)));
    }
  }
  if (has_free_space_) {
    if (auto hull = WallsRow("SELECT hull FROM free_space WHERE asr_id=?", id, "free space")) {
      if (hull->size() != 1)
        throw InputError(path_, 0, "ASR " + std::to_string(id) + ": free space: " + std::to_string(hull->size()) +
                                       " polygons");
      a.free_hull_local = std::move((*hull)[0]);
    }
  }
  if (has_matched_walls_) {
    if (auto walls = WallsRow("SELECT walls FROM matched_walls WHERE asr_id=?", id, "matched walls")) {
      a.matched_walls_local = std::move(*walls);
      a.has_matched_walls = true;
    }
  }
  if (has_pre_bend_) {
    Stmt o(Db(db_), "SELECT rate FROM pre_bend WHERE asr_id=?", &statements_);
    if (!o.ok()) Fail(sqlite3_errmsg(Db(db_)));
    o.BindInt(1, id);
    if (o.Step() == SQLITE_ROW) {
      a.pre_bend_rad_per_m = o.Double(0);
      if (!std::isfinite(a.pre_bend_rad_per_m))
        throw InputError(path_, 0, "ASR " + std::to_string(id) + ": pre-bend rate is not a finite number");
    } else if (o.failed()) {
      Fail("pre-bend of ASR " + std::to_string(id) + ": " + sqlite3_errmsg(Db(db_)));
    }
  }
  if (has_path_turn_) {
    Stmt o(Db(db_), "SELECT turns, after FROM path_turn WHERE asr_id=?", &statements_);
    if (!o.ok()) Fail(sqlite3_errmsg(Db(db_)));
    o.BindInt(1, id);
    if (o.Step() == SQLITE_ROW) {
      std::vector<double> turns;
      try {
        turns = DecodeDoubles(o.Blob(0));
      } catch (const std::runtime_error& e) {
        throw InputError(path_, 0, "ASR " + std::to_string(id) + ": path turns: " + e.what());
      }
      const double after = o.Double(1);
      const bool finite = std::isfinite(after) && std::all_of(turns.begin(), turns.end(), [](double t) { return std::isfinite(t); });
      if (!finite) throw InputError(path_, 0, "ASR " + std::to_string(id) + ": a path turn is not a finite number");
      // One per pose of the path, as mapped (a row that disagrees is not this ASR's).
      if (turns.size() != a.path.size())
        throw InputError(path_, 0, "ASR " + std::to_string(id) + ": " + std::to_string(turns.size()) +
                                       " path turns for " + std::to_string(a.path.size()) + " path poses");
      a.path_turn_rad = std::move(turns);
      a.turn_after_path_rad = after;
    } else if (o.failed()) {
      Fail("path turns of ASR " + std::to_string(id) + ": " + sqlite3_errmsg(Db(db_)));
    }
  }
  return a;
}

std::vector<int> SqliteAsrStore::Ids() const {
  std::lock_guard<std::recursive_mutex> lock(mutex_);
  Stmt s(Db(db_), "SELECT id FROM asr ORDER BY id", &statements_);
  std::vector<int> ids;
  while (s.ok() && s.Step() == SQLITE_ROW) ids.push_back(static_cast<int>(s.Int(0)));
  if (s.failed()) Fail(sqlite3_errmsg(Db(db_)));
  return ids;
}

int SqliteAsrStore::Count() const {
  std::lock_guard<std::recursive_mutex> lock(mutex_);
  Stmt s(Db(db_), "SELECT count(*) FROM asr", &statements_);
  if (!s.ok() || s.Step() != SQLITE_ROW) Fail(sqlite3_errmsg(Db(db_)));
  return static_cast<int>(s.Int(0));
}

int SqliteAsrStore::MaxId() const {
  std::lock_guard<std::recursive_mutex> lock(mutex_);
  Stmt s(Db(db_), "SELECT coalesce(max(id), -1) FROM asr", &statements_);
  if (!s.ok() || s.Step() != SQLITE_ROW) Fail(sqlite3_errmsg(Db(db_)));
  return static_cast<int>(s.Int(0));
}

std::vector<int> SqliteAsrStore::Neighbours(int id) const {
  std::lock_guard<std::recursive_mutex> lock(mutex_);
  Stmt s(Db(db_),
         "SELECT to_asr FROM edge WHERE from_asr=?1 AND to_asr<>?1 UNION "
         "SELECT from_asr FROM edge WHERE to_asr=?1 AND from_asr<>?1 ORDER BY 1");
  s.BindInt(1, id);
  std::vector<int> out;
  while (s.ok() && s.Step() == SQLITE_ROW) out.push_back(static_cast<int>(s.Int(0)));
  if (s.failed()) Fail(sqlite3_errmsg(Db(db_)));
  return out;
}

std::vector<Edge> SqliteAsrStore::Edges() const {
  std::lock_guard<std::recursive_mutex> lock(mutex_);
  Stmt s(Db(db_), "SELECT from_asr, to_asr, center_x, center_y, width_m FROM edge ORDER BY from_asr, to_asr",
         &statements_);
  std::vector<Edge> out;
  while (s.ok() && s.Step() == SQLITE_ROW) {
    Edge e;
    e.from_asr = static_cast<int>(s.Int(0));
    e.to_asr = static_cast<int>(s.Int(1));
    e.center_m = Vec2(s.Double(2), s.Double(3));
    e.width_m = s.Double(4);
    out.push_back(e);
  }
  if (s.failed()) Fail(sqlite3_errmsg(Db(db_)));
  return out;
}

std::optional<std::string> SqliteAsrStore::GetMeta(const std::string& key) const {
  std::lock_guard<std::recursive_mutex> lock(mutex_);
  Stmt s(Db(db_), "SELECT value FROM meta WHERE key=?", &statements_);
  s.BindText(1, key);
  if (s.ok() && s.Step() == SQLITE_ROW) return s.Text(0);
  if (s.failed()) Fail("meta " + key + ": " + sqlite3_errmsg(Db(db_)));
  return std::nullopt;
}

void SqliteAsrStore::SetMeta(const std::string& key, const std::string& value) {
  std::lock_guard<std::recursive_mutex> lock(mutex_);
  Stmt s(Db(db_), "INSERT OR REPLACE INTO meta VALUES(?,?)", &statements_);
  s.BindText(1, key);
  s.BindText(2, value);
  if (!s.ok() || s.Step() != SQLITE_DONE) Fail(sqlite3_errmsg(Db(db_)));
}

std::string SqliteAsrStore::IntegrityCheck() const {
  std::lock_guard<std::recursive_mutex> lock(mutex_);
  Stmt s(Db(db_), "PRAGMA integrity_check", &statements_);
  if (!s.ok() || s.Step() != SQLITE_ROW) return sqlite3_errmsg(Db(db_));
  return s.Text(0);
}

void SqliteAsrStore::LimitPagesForTest(int pages) {
  std::lock_guard<std::recursive_mutex> lock(mutex_);
  Exec("PRAGMA max_page_count=" + std::to_string(pages));
}

// ---------------------------------------------------------------- graph

void AsrGraph::Touch(int id) {
  lru_.remove(id);
  lru_.push_front(id);
}

void AsrGraph::Evict() {
  size_t unpinned = 0;
  for (int id : lru_) unpinned += pinned_.count(id) ? 0 : 1;
  for (auto it = lru_.end(); unpinned > capacity_ && it != lru_.begin();) {
    --it;
    if (pinned_.count(*it)) continue;
    cache_.erase(*it);
    it = lru_.erase(it);
    --unpinned;
  }
}

std::shared_ptr<const Asr> AsrGraph::Get(int id) {
  auto it = cache_.find(id);
  if (it != cache_.end()) {
    Touch(id);
    return it->second;
  }
  auto asr = store_->Get(id);
  if (!asr) return nullptr;
  ++loads_;
  auto ptr = std::make_shared<const Asr>(std::move(*asr));
  cache_[id] = ptr;
  Touch(id);
  Evict();
  return ptr;
}

void AsrGraph::SetCurrent(int id) {
  current_ = id;
  pinned_.clear();
  pinned_.insert(id);
  for (int n : store_->Neighbours(id)) pinned_.insert(n);
  for (int p : std::set<int>(pinned_)) Get(p);
  Evict();
}

void AsrGraph::Invalidate(int id) {
  cache_.erase(id);
  lru_.remove(id);
}

}  // namespace cogmap::asr

namespace cogmap::asr {


void SqliteAsrStore::PutPlacements(const std::vector<Asr>& asrs, const std::vector<Placement>& placements,
                                   const std::vector<ClosureRecord>& closures) {
  std::lock_guard<std::recursive_mutex> lock(mutex_);
  WritePlacements([&] {
    for (const Asr& a : asrs) Put(a);
  }, placements, closures);
}

void SqliteAsrStore::RevisePlacements(const std::vector<int>& ids, const std::function<void(Asr&)>& revise,
                                      const std::vector<Placement>& placements,
                                      const std::vector<ClosureRecord>& closures) {
  std::lock_guard<std::recursive_mutex> lock(mutex_);
  WritePlacements([&] {
    for (int id : ids)
      if (auto a = Get(id)) {
        revise(*a);
        Put(*a);
      }
  }, placements, closures);
}

void SqliteAsrStore::WritePlacements(const std::function<void()>& write_asrs, const std::vector<Placement>& placements,
                                     const std::vector<ClosureRecord>& closures) {
  // One transaction for everything (one sync at the end of a run).
  Exec("BEGIN IMMEDIATE");
  in_batch_ = true;
  try {
    write_asrs();
    sqlite3* db = Db(db_);
    for (const Placement& p : placements) {
      Stmt s(db, "INSERT OR REPLACE INTO placement VALUES(?,?,?,?,?,?,?)", &statements_);
      sqlite3_bind_int(s.get(), 1, p.asr_id);
      sqlite3_bind_int(s.get(), 2, p.room_id);
      double c[9];
      for (int k = 0; k < 9; ++k) c[k] = p.covariance(k / 3, k % 3);
      sqlite3_bind_blob(s.get(), 3, c, sizeof c, SQLITE_TRANSIENT);
      sqlite3_bind_int(s.get(), 4, p.uncertain ? 1 : 0);
      sqlite3_bind_text(s.get(), 5, p.why.c_str(), -1, SQLITE_TRANSIENT);
      sqlite3_bind_double(s.get(), 6, p.drift_rate_rad_per_m);
      s.BindBlob(7, EncodePoses(p.corrected_path));
      if (s.Step() != SQLITE_DONE) Fail("write placement");
    }
    for (const ClosureRecord& c : closures) {
      Stmt s(db, "INSERT OR REPLACE INTO closure VALUES(?,?,?,?,?,?,?,?,?,?,?)", &statements_);
      sqlite3_bind_int(s.get(), 1, c.from_asr);
      sqlite3_bind_int(s.get(), 2, c.to_asr);
      sqlite3_bind_double(s.get(), 3, c.relative.x);
      sqlite3_bind_double(s.get(), 4, c.relative.y);
      sqlite3_bind_double(s.get(), 5, c.relative.theta);
      sqlite3_bind_double(s.get(), 6, c.agreement);
      sqlite3_bind_double(s.get(), 7, c.rmse_m);
      sqlite3_bind_double(s.get(), 8, c.mahalanobis2);
      sqlite3_bind_int(s.get(), 9, c.accepted ? 1 : 0);
      sqlite3_bind_int(s.get(), 10, c.same_room ? 1 : 0);
      sqlite3_bind_text(s.get(), 11, c.reason.c_str(), -1, SQLITE_TRANSIENT);
      if (s.Step() != SQLITE_DONE) Fail("write closure");
    }
    in_batch_ = false;
    Exec("COMMIT");
  } catch (...) {
    in_batch_ = false;
    sqlite3_exec(Db(db_), "ROLLBACK", nullptr, nullptr, nullptr);
    throw;
  }
}

std::optional<Placement> SqliteAsrStore::GetPlacement(int id) const {
  std::lock_guard<std::recursive_mutex> lock(mutex_);
  sqlite3* db = Db(db_);
  if (!has_placement_) return std::nullopt;  // a version-1 store read as it is
  Stmt s(db, "SELECT room_id, cov, uncertain, why, drift_rate, corrected_path FROM placement WHERE asr_id=?",
         &statements_);
  sqlite3_bind_int(s.get(), 1, id);
  if (!s.ok() || s.Step() != SQLITE_ROW) {
    if (s.failed()) Fail("placement of ASR " + std::to_string(id) + ": " + sqlite3_errmsg(db));
    return std::nullopt;
  }
  Placement p;
  p.asr_id = id;
  p.room_id = static_cast<int>(s.Int(0));
  const void* blob = sqlite3_column_blob(s.get(), 1);
  if (blob && sqlite3_column_bytes(s.get(), 1) == 9 * static_cast<int>(sizeof(double))) {
    double c[9];
    std::memcpy(c, blob, sizeof c);
    for (int k = 0; k < 9; ++k) p.covariance(k / 3, k % 3) = c[k];
  }
  p.uncertain = s.Int(2) != 0;
  p.why = s.Text(3);
  p.drift_rate_rad_per_m = s.Double(4);
  {
    const void* b = sqlite3_column_blob(s.get(), 5);
    const int n = sqlite3_column_bytes(s.get(), 5);
    try {
      p.corrected_path = DecodePoses(std::string(b ? static_cast<const char*>(b) : "", b ? n : 0));
    } catch (const std::runtime_error& e) {  // a corrupt blob: the file's error, not a crash
      throw InputError(path_, 0, "placement of ASR " + std::to_string(id) + ": " + e.what());
    }
  }
  return p;
}

int SqliteAsrStore::RoomOf(int id) const {
  std::lock_guard<std::recursive_mutex> lock(mutex_);
  const auto p = GetPlacement(id);
  return p && p->room_id >= 0 ? p->room_id : id;
}

std::vector<ClosureRecord> SqliteAsrStore::Closures() const {
  std::lock_guard<std::recursive_mutex> lock(mutex_);
  std::vector<ClosureRecord> out;
  sqlite3* db = Db(db_);
  if (!has_closure_) return out;
  Stmt s(db, "SELECT * FROM closure ORDER BY to_asr, from_asr", &statements_);
  while (s.ok() && s.Step() == SQLITE_ROW) {
    ClosureRecord c;
    c.from_asr = static_cast<int>(s.Int(0));
    c.to_asr = static_cast<int>(s.Int(1));
    c.relative = Pose2{s.Double(2), s.Double(3), s.Double(4)};
    c.agreement = s.Double(5);
    c.rmse_m = s.Double(6);
    c.mahalanobis2 = s.Double(7);
    c.accepted = s.Int(8) != 0;
    c.same_room = s.Int(9) != 0;
    c.reason = s.Text(10);
    out.push_back(c);
  }
  if (s.failed()) Fail(sqlite3_errmsg(db));
  return out;
}

}  // namespace cogmap::asr
