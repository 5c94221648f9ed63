// Simulator speed: simulated seconds per wall-clock second ("x_real_time"),
// pioneer16 with 5 rays per sonar cone. Target: >= 1000x real time.
#include <benchmark/benchmark.h>

#include <string>

#include "cogmap/io/world_io.h"
#include "cogmap/sim/building.h"
#include "cogmap/sim/simulator.h"

namespace {

const std::string kWorlds = std::string(COGMAP_SHARED_DIR) + "/worlds/";

void RunSim(benchmark::State& state, const cogmap::FloorPlan& plan, cogmap::sim::SimulatorOptions o) {
  const auto robot = cogmap::sensors::BuiltinRobot("pioneer16");
  o.sensor.sonar_rays = 5;
  double simulated = 0.0, distance = 0.0;
  long records = 0;
  for (auto _ : state) {
    const auto stats = cogmap::sim::Simulate(plan, robot, o, [&](const cogmap::sensors::LogRecord& r) {
      benchmark::DoNotOptimize(r.ranges.data());
    });
    simulated += stats.simulated_s;
    distance += stats.distance_m;
    records += stats.records;
  }
  state.counters["x_real_time"] = benchmark::Counter(simulated, benchmark::Counter::kIsRate);
  state.counters["sim_s"] = simulated / state.iterations();
  state.counters["metres"] = distance / state.iterations();
  state.counters["records"] = static_cast<double>(records) / state.iterations();
}

// The largest bundled ARIA map (101 walls, no route): explore for 600 s.
void BM_ExploreOfficeMap(benchmark::State& state) {
  const auto plan = cogmap::io::ReadAriaMap(kWorlds + "aria/office.map").plan;
  cogmap::sim::SimulatorOptions o;
  o.mode = cogmap::sim::SimMode::kExplore;
  o.max_time_s = 600;
  RunSim(state, plan, o);
}
BENCHMARK(BM_ExploreOfficeMap)->Unit(benchmark::kMillisecond)->UseRealTime();

// The nine-room route.
void BM_RouteNineRooms(benchmark::State& state) {
  const auto plan = cogmap::io::ReadAriaMap(kWorlds + "nine_rooms.map").plan;
  RunSim(state, plan, {});
}
BENCHMARK(BM_RouteNineRooms)->Unit(benchmark::kMillisecond)->UseRealTime();

// A generated building: 100 rooms along 1 km of corridor; the first 1200 s of
// its route (setup of the 1 km grids included).
void BM_RouteGeneratedBuilding(benchmark::State& state) {
  const auto plan = cogmap::sim::GenerateBuilding({});
  cogmap::sim::SimulatorOptions o;
  o.max_time_s = 1200;
  RunSim(state, plan, o);
}
BENCHMARK(BM_RouteGeneratedBuilding)->Unit(benchmark::kMillisecond)->UseRealTime()->Iterations(1);

}  // namespace

BENCHMARK_MAIN();
