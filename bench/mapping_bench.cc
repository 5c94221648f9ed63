// What the mapping API (cogmap/mapping) costs over the components it
// assembles: the same records (a simulated run, in memory) mapped by
//  - Direct: asr::CognitiveMapper with graph::MapOptimizer as its placer and
//    the final solve written back to the store, assembled by hand as `cogmap
//    map` did before the API existed;
//  - Pipeline: mapping::MappingPipeline with the same options.
// Both write into a SQLite store in /tmp. Compare the two times in one run
// (docs/BENCHMARKS.md); the machine's noise cancels in the ratio.
#include <benchmark/benchmark.h>

#include <filesystem>
#include <map>
#include <string>
#include <unistd.h>

#include "cogmap/asr/mapper.h"
#include "cogmap/asr/store.h"
#include "cogmap/graph/map_optimizer.h"
#include "cogmap/io/world_io.h"
#include "cogmap/mapping/pipeline.h"
#include "cogmap/sim/simulator.h"

namespace cogmap {
namespace {

const std::vector<sensors::LogRecord>& Run() {
  static const std::vector<sensors::LogRecord> records = [] {
    const FloorPlan plan = io::ReadAriaMap(std::string(COGMAP_SHARED_DIR) + "/worlds/nine_rooms.map").plan;
    sim::SimulatorOptions so;
    so.seed = 11;
    so.odometry.drift_rad_per_m = 0.01745;
    std::vector<sensors::LogRecord> out;
    sim::Simulate(plan, sensors::BuiltinRobot("pioneer16"), so, [&out](const sensors::LogRecord& r) { out.push_back(r); });
    return out;
  }();
  return records;
}

std::string StorePath(const char* name) {
  return (std::filesystem::temp_directory_path() / (std::string(name) + std::to_string(::getpid()) + ".sqlite")).string();
}

// The store a benchmark wrote, and its journal files, once it is done.
void RemoveStore(const char* name) {
  std::error_code ec;
  for (const char* suffix : {"", "-wal", "-shm", "-journal"}) std::filesystem::remove(StorePath(name) + suffix, ec);
}

void BM_Direct(benchmark::State& state) {
  const auto& records = Run();
  const auto robot = sensors::BuiltinRobot("pioneer16");
  const mapping::MappingOptions options;
  for (auto _ : state) {
    auto store = asr::SqliteAsrStore::Open(StorePath("direct"), asr::SqliteAsrStore::OpenMode::kReplace);
    graph::MapOptimizerOptions go;
    go.heading.grid_refine = true;
    graph::MapOptimizer optimizer(go);
    asr::CognitiveMapper mapper(robot, mapping::MapperOptionsFor(robot, options), store.get(), [](const asr::Asr&) {});
    mapper.SetPlacer([&optimizer](asr::Asr x) { return optimizer.Place(std::move(x)); });
    for (const auto& r : records) mapper.Push(r);
    mapper.Finish();
    const graph::OptimizerResult result = optimizer.Finish();
    // As the pipeline writes them: each ASR revised in place, in one transaction.
    std::vector<int> ids;
    std::map<int, Pose2> pose_of;
    std::vector<asr::Placement> placements;
    for (const auto& e : result.asrs) {
      ids.push_back(e.asr_id);
      pose_of[e.asr_id] = e.pose;
      asr::Placement p;
      p.asr_id = e.asr_id;
      p.room_id = e.room_id;
      p.corrected_path = e.corrected_path;
      placements.push_back(p);
    }
    store->RevisePlacements(ids, [&](asr::Asr& x) { x.world_from_local_corrected = pose_of.at(x.id); }, placements,
                            {});
    benchmark::DoNotOptimize(result.asrs.size());
  }
  RemoveStore("direct");
  state.counters["records"] = static_cast<double>(records.size());
}

void BM_Pipeline(benchmark::State& state) {
  const auto& records = Run();
  for (auto _ : state) {
    auto store = asr::SqliteAsrStore::Open(StorePath("pipeline"), asr::SqliteAsrStore::OpenMode::kReplace);
    mapping::MappingPipeline p(sensors::BuiltinRobot("pioneer16"), {}, store.get());
    for (const auto& r : records) p.Push(r);
    benchmark::DoNotOptimize(p.Finish().asrs.size());
  }
  RemoveStore("pipeline");
  state.counters["records"] = static_cast<double>(records.size());
}

BENCHMARK(BM_Direct)->Unit(benchmark::kMillisecond)->MinTime(3.0);
BENCHMARK(BM_Pipeline)->Unit(benchmark::kMillisecond)->MinTime(3.0);

}  // namespace
}  // namespace cogmap

BENCHMARK_MAIN();
