// Fuzz target: a map store (map.sqlite) as `cogmap eval`, Python's open_store
// and `cogmap map --resume` read it: opened read-only and read whole through
// the store's API, then opened for writing as --resume opens its copy. Every
// problem must be a cogmap::InputError naming the file.
#include <filesystem>
#include <string>

#include "cogmap/asr/mapper.h"
#include "cogmap/asr/store.h"
#include "cogmap/core/error.h"
#include "fuzz/fuzz_util.h"

namespace {

void RemoveSidecars(const std::string& path) {
  std::error_code ec;
  for (const char* suffix : {"-wal", "-shm", "-journal"}) std::filesystem::remove(path + suffix, ec);
}

// Everything a reader of a finished map asks the store (at most 200 ASRs).
void ReadWhole(const cogmap::asr::SqliteAsrStore& store) {
  store.Count();
  store.MaxId();
  store.GetMeta("application");
  store.GetMeta("run_id");
  store.GetMeta(cogmap::asr::kMetaNextId);
  store.GetMeta(cogmap::asr::kMetaLastRawPose);
  int n = 0;
  for (int id : store.Ids()) {
    if (++n > 200) break;
    if (auto a = store.Get(id)) a->WallsWorldCorrected();
    store.GetPlacement(id);
    store.RoomOf(id);
    store.Neighbours(id);
  }
  store.Edges();
  store.Closures();
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  using cogmap::asr::SqliteAsrStore;
  const std::string path = cogmap::fuzz::AsFile(data, size, ".sqlite");
  RemoveSidecars(path);
  try {
    ReadWhole(*SqliteAsrStore::Open(path, SqliteAsrStore::OpenMode::kReadOnly));
  } catch (const cogmap::InputError&) {
  }
  try {  // --resume: the copy in staging, opened for writing
    auto store = SqliteAsrStore::Open(path, SqliteAsrStore::OpenMode::kOpenExisting);
    ReadWhole(*store);
  } catch (const cogmap::InputError&) {
  }
  RemoveSidecars(path);
  return 0;
}
