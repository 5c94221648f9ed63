#pragma once
#include <cstdint>
#include <functional>
#include <list>
#include <map>
#include <mutex>
#include <memory>
#include <optional>
#include <set>
#include <string>
#include <unordered_map>
#include <vector>

#include "cogmap/asr/asr.h"

namespace cogmap::asr {

// Where the pose graph placed an ASR (schema version 2; graph::MapOptimizer).
struct Placement {
  int asr_id = -1;
  int room_id = -1;  // the physical room: the id of the ASR of its first visit
  Eigen::Matrix3d covariance = Eigen::Matrix3d::Zero();  // of (x, y, theta); zero: unknown
  bool uncertain = false;
  std::string why;  // reasons it is uncertain, "; "-separated
  double drift_rate_rad_per_m = 0.0;  // the odometry drift the graph estimated on the way out (CorrectedPath)
  std::vector<Pose2> corrected_path;  // the robot's path as placed (world), one pose per Asr::path pose
};

// A loop-closure candidate and its verdict.
struct ClosureRecord {
  int from_asr = -1, to_asr = -1;
  Pose2 relative;  // to_asr's pose in from_asr's frame (registration)
  double agreement = 0.0, rmse_m = 0.0, mahalanobis2 = 0.0;
  bool accepted = false, same_room = false;
  std::string reason;
};

// Where finished ASRs live (SPEC 4, §2.4.1: only the current ASR and its
// neighbours need to be in memory). Two implementations: SQLite on disk (the
// default, map.sqlite) and memory (tests, short runs). Every Put is atomic: it
// stores the whole ASR, its graph edges and the run-state keys, or nothing.
class AsrStore {
 public:
  virtual ~AsrStore() = default;
  // Inserts or replaces 'asr' (by id), its edges (exits whose two ASRs are
  // known), and the 'meta' key/values, in one transaction. Throws on a write
  // error (full disk...), leaving the store as before the call.
  virtual void Put(const Asr& asr, const std::map<std::string, std::string>& meta = {}) = 0;
  virtual std::optional<Asr> Get(int id) const = 0;
  virtual std::vector<int> Ids() const = 0;
  virtual int Count() const = 0;
  // Largest id, -1 when empty.
  virtual int MaxId() const = 0;
  // ASRs joined to 'id' by an exit, ascending.
  virtual std::vector<int> Neighbours(int id) const = 0;
  virtual std::optional<std::string> GetMeta(const std::string& key) const = 0;
  virtual void SetMeta(const std::string& key, const std::string& value) = 0;
  // What errors name the store by: its file, or "memory store".
  virtual std::string Name() const = 0;
  // A meta value that is an integer in [min, max] (an ASR id, a record
  // number): none when the key is absent, an InputError naming the store
  // when the value is anything else.
  std::optional<long> GetMetaInt(const std::string& key, long min, long max) const;
  // A meta value that is a pose, "x y theta" (three finite numbers): none
  // when absent, an InputError naming the store when it is anything else.
  std::optional<Pose2> GetMetaPose(const std::string& key) const;
  // A meta value that is a positive finite number: none when absent, an
  // InputError naming the store when it is anything else.
  std::optional<double> GetMetaPositive(const std::string& key) const;
  // Rewrites the given ASRs (their optimised poses), their placements and the
  // run's closure candidates, in one transaction.
  virtual void PutPlacements(const std::vector<Asr>& asrs, const std::vector<Placement>& placements,
                             const std::vector<ClosureRecord>& closures) = 0;
  // The same, each stored ASR of 'ids' read, revised in place by 'revise' and
  // written back one at a time (an id not stored is skipped): the end of a
  // long run holds one ASR, not all of them (1000-room building: some 18 MB).
  virtual void RevisePlacements(const std::vector<int>& ids, const std::function<void(Asr&)>& revise,
                                const std::vector<Placement>& placements,
                                const std::vector<ClosureRecord>& closures) = 0;
  // The physical room of an ASR (its own id when never placed).
  virtual int RoomOf(int id) const = 0;
  virtual std::optional<Placement> GetPlacement(int id) const = 0;
  virtual std::vector<ClosureRecord> Closures() const = 0;
};

// A graph edge: an exit joining two stored ASRs.
struct Edge {
  int from_asr = -1;
  int to_asr = -1;
  Vec2 center_m{0, 0};
  double width_m = 0.0;
};

class MemoryAsrStore : public AsrStore {
 public:
  void Put(const Asr& asr, const std::map<std::string, std::string>& meta = {}) override;
  std::optional<Asr> Get(int id) const override;
  std::vector<int> Ids() const override;
  int Count() const override { return static_cast<int>(asrs_.size()); }
  int MaxId() const override { return asrs_.empty() ? -1 : asrs_.rbegin()->first; }
  std::vector<int> Neighbours(int id) const override;
  std::optional<std::string> GetMeta(const std::string& key) const override;
  void SetMeta(const std::string& key, const std::string& value) override { meta_[key] = value; }
  std::string Name() const override { return "memory store"; }
  void PutPlacements(const std::vector<Asr>& asrs, const std::vector<Placement>& placements,
                     const std::vector<ClosureRecord>& closures) override;
  void RevisePlacements(const std::vector<int>& ids, const std::function<void(Asr&)>& revise,
                        const std::vector<Placement>& placements, const std::vector<ClosureRecord>& closures) override;
  int RoomOf(int id) const override;
  std::optional<Placement> GetPlacement(int id) const override;
  std::vector<ClosureRecord> Closures() const override { return closures_; }

 private:
  std::map<int, Asr> asrs_;
  std::set<std::pair<int, int>> edges_;
  std::map<std::string, std::string> meta_;
  std::map<int, Placement> placements_;
  std::vector<ClosureRecord> closures_;
};


// map.sqlite: schema version kStoreSchemaVersion, PRAGMA application_id
// kStoreApplicationId ("cogm"), a meta table (application = "cogmap",
// schema_version), WAL journal with synchronous=NORMAL while a run writes, one
// transaction per Put; closing a writable store checkpoints it and leaves WAL
// (journal_mode=DELETE), so that the file alone is the store (read-only media,
// copies). See docs/store.md.
constexpr int kStoreSchemaVersion = 7;
constexpr int32_t kStoreApplicationId = 0x636f676d;  // "cogm"

class SqliteAsrStore : public AsrStore {
 public:
  enum class OpenMode {
    kCreateOrOpen,  // open a cogmap store, or create one (missing or empty file)
    kOpenExisting,  // the file must exist and be a cogmap store
    kReplace,       // an existing cogmap store is deleted first (a new run)
    kReadOnly,      // an existing store, read only; works on read-only media
                    // (opened immutable when its folder is not writable)
  };
  // Throws InputError: "PATH: schema version N is newer than this cogmap (M)",
  // "PATH: schema version N is older than this cogmap (M)", "PATH: not a
  // cogmap store (...)" (also for a store whose tables differ from this
  // version's schema), "PATH: permission denied" / "DIR: permission denied",
  // or a message naming the path when the file cannot be opened or created.
  // Refusing a file leaves no -wal / -shm files behind.
  static std::unique_ptr<SqliteAsrStore> Open(const std::string& path,
                                              OpenMode mode = OpenMode::kCreateOrOpen);
  ~SqliteAsrStore() override;
  SqliteAsrStore(const SqliteAsrStore&) = delete;
  SqliteAsrStore& operator=(const SqliteAsrStore&) = delete;

  void Put(const Asr& asr, const std::map<std::string, std::string>& meta = {}) override;
  std::optional<Asr> Get(int id) const override;
  std::vector<int> Ids() const override;
  int Count() const override;
  int MaxId() const override;
  std::vector<int> Neighbours(int id) const override;
  std::optional<std::string> GetMeta(const std::string& key) const override;
  void SetMeta(const std::string& key, const std::string& value) override;
  std::string Name() const override { return path_; }
  void PutPlacements(const std::vector<Asr>& asrs, const std::vector<Placement>& placements,
                     const std::vector<ClosureRecord>& closures) override;
  void RevisePlacements(const std::vector<int>& ids, const std::function<void(Asr&)>& revise,
                        const std::vector<Placement>& placements, const std::vector<ClosureRecord>& closures) override;
  int RoomOf(int id) const override;
  std::optional<Placement> GetPlacement(int id) const override;
  std::vector<ClosureRecord> Closures() const override;

  std::vector<Edge> Edges() const;
  // "ok" when PRAGMA integrity_check passes, else its first message.
  std::string IntegrityCheck() const;
  // Test seam: limits the file to 'pages' pages (PRAGMA max_page_count), so
  // that a write fails as on a full disk.
  void LimitPagesForTest(int pages);
  const std::string& path() const { return path_; }

 private:
  SqliteAsrStore(std::string path, void* db, bool read_only = false)
      : path_(std::move(path)), db_(db), read_only_(read_only) {}
  void Exec(const std::string& sql) const;
  [[noreturn]] void Fail(const std::string& what) const;
  // The walls blob of the row 'sql' (one ? for the ASR id) selects; none
  // without a row. A blob that does not decode is an InputError naming the
  // store, the ASR and 'what'.
  std::optional<std::vector<Polyline>> WallsRow(const char* sql, int id, const std::string& what) const;
  // One transaction: write_asrs() (its Puts join it), then the placements and
  // closures.
  void WritePlacements(const std::function<void()>& write_asrs, const std::vector<Placement>& placements,
                       const std::vector<ClosureRecord>& closures);

  std::string path_;
  void* db_ = nullptr;  // sqlite3*
  bool read_only_ = false;
  bool in_batch_ = false;  // inside PutPlacements' transaction
  // Prepared statements by their SQL (sqlite3_stmt*), kept for the store's
  // life and finalized before it closes.
  mutable std::map<std::string, void*> statements_;
  // Every public call holds it: the mapper's placing thread stores rooms
  // while the caller's thread may read the store (a callback, a live map's
  // outputs). Recursive: a revision's Puts run inside RevisePlacements.
  mutable std::recursive_mutex mutex_;
  bool has_orientation_ = false;  // schema 3's orientation table (older stores read-only: none)
  bool has_matched_walls_ = false;  // schema 5's matched_walls table
  bool has_pre_bend_ = false;       // schema 6's pre_bend table
  bool has_path_turn_ = false;      // schema 7's path_turn table
  bool has_free_space_ = false;   // schema 4's free_space table (older stores read-only: none)
  bool has_placement_ = false;    // schema 2's placement and closure tables (a version-1 store read
  bool has_closure_ = false;      // as it is: none); known at Open, not asked of every read
};

// Binary encodings of the ASR's variable parts (little-endian, versioned by
// the schema): walls, exits, poses. Exposed for the store's tests.
std::string EncodeWalls(const std::vector<Polyline>& walls);
std::vector<Polyline> DecodeWalls(const std::string& blob);
std::string EncodeExits(const std::vector<Exit>& exits);
std::vector<Exit> DecodeExits(const std::string& blob);
std::string EncodePoses(const std::vector<Pose2>& poses);
std::vector<Pose2> DecodePoses(const std::string& blob);
// A count and that many float64 (the path turns of schema 7).
std::string EncodeDoubles(const std::vector<double>& values);
std::vector<double> DecodeDoubles(const std::string& blob);

// The room graph over a store: ASRs are nodes, exits edges. Holds the current
// ASR and its neighbours pinned in memory, plus at most 'capacity' others
// (least recently used first out); everything else is loaded on demand.
class AsrGraph {
 public:
  explicit AsrGraph(const AsrStore* store, size_t capacity = 8) : store_(store), capacity_(capacity) {}
  // The ASR, loaded when needed; nullptr when the store has no such id.
  std::shared_ptr<const Asr> Get(int id);
  // Pins 'id' and its neighbours (loading them), unpinning the previous ones.
  void SetCurrent(int id);
  // Drops a cached copy (after the ASR was rewritten in the store).
  void Invalidate(int id);
  std::vector<int> Neighbours(int id) const { return store_->Neighbours(id); }
  size_t resident() const { return cache_.size(); }
  long loads() const { return loads_; }
  int current() const { return current_; }

 private:
  void Touch(int id);
  void Evict();

  const AsrStore* store_;
  size_t capacity_;
  int current_ = -1;
  std::set<int> pinned_;
  std::unordered_map<int, std::shared_ptr<const Asr>> cache_;
  std::list<int> lru_;  // front = most recent (unpinned and pinned alike)
  long loads_ = 0;
};

}  // namespace cogmap::asr
