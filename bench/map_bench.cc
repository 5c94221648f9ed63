// Scale benchmark of the cognitive mapper (issue 5): maps a log streaming from
// disk into a store and reports the time per reading and the peak memory at
// 10 % and at 100 % of the run, so that the claim of a non-increasing cost per
// step as the map grows (§2.4.1) can be checked.
//
//   cogmap gen-building -o building.map            # 100 rooms, 1 km corridor
//   cogmap simulate building.map -o building.log
//   cogmap_map_bench building.log [STORE]          # JSON on stdout
//
// The time per reading at a checkpoint is the mean over the last 5 % of the
// records before it (ASR closes included: vectorising, correcting, storing).
#include <chrono>
#include <cstdio>
#include <nlohmann/json.hpp>
#include <string>

#include "cogmap/asr/mapper.h"
#include "cogmap/asr/store.h"
#include "cogmap/core/error.h"
#include "cogmap/core/process.h"
#include "cogmap/io/log_reader.h"
#include "cogmap/localize/heading_corrector.h"

namespace {

long CountRecords(const std::string& path) {
  auto log = cogmap::io::OpenLog(path);
  cogmap::sensors::LogRecord r;
  long n = 0;
  while (log->Next(&r)) ++n;
  return n;
}

}  // namespace

int main(int argc, char** argv) {
  using namespace cogmap;
  if (argc < 2) {
    std::fprintf(stderr, "usage: %s LOG [STORE]\n", argv[0]);
    return 2;
  }
  const std::string log_path = argv[1];
  const std::string store_path = argc > 2 ? argv[2] : "map_bench.sqlite";
  try {
    const long total = CountRecords(log_path);
    auto log = io::OpenLog(log_path);
    const auto robot = log->robot_hint().value_or(sensors::BuiltinRobot("pioneer16"));
    auto store = asr::SqliteAsrStore::Open(store_path, asr::SqliteAsrStore::OpenMode::kReplace);
    localize::HeadingCorrector corrector;
    asr::CognitiveMapper mapper(robot, {}, store.get());
    mapper.SetCorrector([&corrector](asr::Asr a) { return corrector.Close(std::move(a)); });

    using Clock = std::chrono::steady_clock;
    const long window = std::max<long>(1, total / 20);
    const long at10 = std::max<long>(1, total / 10);
    nlohmann::json checkpoints = nlohmann::json::array();
    double window_s = 0.0;
    long window_readings = 0, window_records = 0, n = 0;
    auto checkpoint = [&](const char* name) {
      checkpoints.push_back({{"at", name},
                             {"records", n},
                             {"asr_count", mapper.stats().asr_count},
                             {"us_per_reading", window_readings ? 1e6 * window_s / window_readings : 0.0},
                             {"us_per_record", window_records ? 1e6 * window_s / window_records : 0.0},
                             {"vm_hwm_kb", cogmap::PeakResidentKib()},
                             {"vm_rss_kb", cogmap::ResidentKib()},
                             {"current_grid_cells", mapper.current_grid_cells()}});
    };
    sensors::LogRecord rec;
    const auto t0 = Clock::now();
    while (log->Next(&rec)) {
      ++n;
      const bool in_window = (n > at10 - window && n <= at10) || n > total - window;
      const auto a = Clock::now();
      mapper.Push(rec);
      if (n == total) mapper.Finish();
      if (in_window) {
        window_s += std::chrono::duration<double>(Clock::now() - a).count();
        window_readings += static_cast<long>(rec.ranges.size());
        ++window_records;
      }
      if (n == at10 || n == total) {
        checkpoint(n == at10 ? "10%" : "100%");
        window_s = 0.0;
        window_readings = window_records = 0;
      }
    }
    mapper.Finish();
    const double seconds = std::chrono::duration<double>(Clock::now() - t0).count();
    const auto& c10 = checkpoints[0];
    const auto& c100 = checkpoints[checkpoints.size() - 1];
    nlohmann::json out = {
        {"log", log_path},
        {"records", total},
        {"asr_count", store->Count()},
        {"seconds", seconds},
        {"checkpoints", checkpoints},
        {"hwm_ratio_100_over_10", c10["vm_hwm_kb"].get<long>() > 0
                                      ? static_cast<double>(c100["vm_hwm_kb"].get<long>()) / c10["vm_hwm_kb"].get<long>()
                                      : 0.0},
        {"time_ratio_100_over_10", c10["us_per_reading"].get<double>() > 0
                                       ? c100["us_per_reading"].get<double>() / c10["us_per_reading"].get<double>()
                                       : 0.0},
    };
    std::printf("%s\n", out.dump(2).c_str());
  } catch (const InputError& e) {
    std::fprintf(stderr, "cogmap_map_bench: %s\n", e.what());
    return 2;
  }
  return 0;
}
