// Maps a log record by record through cogmap's mapping API and prints one
// line per room as it closes, then the corrected map's summary.
//
//   map_a_log LOG STORE.sqlite
#include <cstdio>
#include <exception>
#include <set>

#include "cogmap/asr/store.h"
#include "cogmap/core/error.h"
#include "cogmap/io/log_reader.h"
#include "cogmap/mapping/pipeline.h"
#include "cogmap/sensors/robot.h"

int main(int argc, char** argv) {
  if (argc != 3) {
    std::fprintf(stderr, "usage: %s LOG STORE.sqlite\n", argv[0]);
    return 2;
  }
  try {
    auto log = cogmap::io::OpenLog(argv[1]);
    const cogmap::sensors::RobotDescription robot =
        log->robot_hint() ? *log->robot_hint() : cogmap::sensors::BuiltinRobot("pioneer16");
    auto store = cogmap::asr::SqliteAsrStore::Open(argv[2], cogmap::asr::SqliteAsrStore::OpenMode::kReplace);

    cogmap::mapping::MappingOptions options;  // default mode: the pose graph
    cogmap::mapping::MappingPipeline pipeline(robot, options, store.get());
    pipeline.OnAsrClosed([](const cogmap::asr::Asr& asr, const cogmap::mapping::AsrSummary& s) {
      std::printf("ASR %d closed: %d walls, %.1f m of path\n", asr.id, s.walls, s.path_m);
    });
    cogmap::sensors::LogRecord record;
    while (log->Next(&record)) pipeline.Push(record);
    const cogmap::mapping::RunResult& run = pipeline.Finish();

    int closures = 0;
    for (const auto& c : run.graph.closures) closures += c.accepted ? 1 : 0;
    std::set<int> rooms;  // a revisited room keeps its first visit's id
    for (const auto& placed : run.graph.asrs) rooms.insert(placed.room_id);
    std::printf("asrs %d rooms %zu closures %d records %ld\n", store->Count(), rooms.size(), closures,
                run.records);
    return 0;
  } catch (const cogmap::InputError& e) {
    std::fprintf(stderr, "map_a_log: %s\n", e.what());
    return 2;
  }
}
