// Ingestion speed of the four fusion rules (readings per second): a Pioneer
// 16-sonar ring driving laps of a simulated 10 m x 8 m room, ranges by ray
// casting against its walls (5 m max range: longer rays are "no echo"), and
// the same ring with random ranges in [0.2, 5] m. 0.1 m cells, 3 m window.
#include <benchmark/benchmark.h>

#include <cmath>
#include <random>
#include <vector>

#include "cogmap/grid/range_fusion.h"

namespace {

using cogmap::Pose2;
using cogmap::Vec2;
namespace grid = cogmap::grid;
namespace sensors = cogmap::sensors;

struct Sweep {
  Pose2 pose;
  std::vector<sensors::RangeReading> readings;
};

// Distance from p along heading h to the walls of the box [0, w] x [0, h].
double CastInBox(const Vec2& p, double heading, double box_w, double box_h) {
  const double c = std::cos(heading), s = std::sin(heading);
  double t = 1e9;
  if (c > 1e-12) t = std::min(t, (box_w - p.x()) / c);
  if (c < -1e-12) t = std::min(t, -p.x() / c);
  if (s > 1e-12) t = std::min(t, (box_h - p.y()) / s);
  if (s < -1e-12) t = std::min(t, -p.y() / s);
  return t;
}

const sensors::RobotDescription& Robot() {
  static const auto robot = sensors::BuiltinRobot("pioneer16");
  return robot;
}

// Laps of a rectangle 1.5 m inside the room's walls, a sweep every 5 cm.
const std::vector<Sweep>& RoomSweeps() {
  static const std::vector<Sweep> sweeps = [] {
    const double w = 10.0, h = 8.0, m = 1.5;
    std::mt19937 rng(1);
    std::normal_distribution<double> noise(0.0, 0.02);
    std::vector<Sweep> out;
    const Vec2 corners[] = {{m, m}, {w - m, m}, {w - m, h - m}, {m, h - m}};
    for (int lap = 0; lap < 2; ++lap)
      for (int k = 0; k < 4; ++k) {
        const Vec2 a = corners[k], b = corners[(k + 1) % 4];
        const double heading = std::atan2(b.y() - a.y(), b.x() - a.x());
        const int steps = static_cast<int>((b - a).norm() / 0.05);
        for (int i = 0; i < steps; ++i) {
          Sweep s;
          const Vec2 p = a + (b - a) * (static_cast<double>(i) / steps);
          s.pose = Pose2{p.x(), p.y(), heading};
          for (int j = 0; j < static_cast<int>(Robot().sensors.size()); ++j) {
            const auto sp = sensors::SensorPose(s.pose, Robot().sensors[j]);
            double r = CastInBox(sp.translation(), sp.theta, w, h) + noise(rng);
            r = std::clamp(r, 0.2, Robot().sensors[j].max_range_m);
            s.readings.push_back({j, r});
          }
          out.push_back(std::move(s));
        }
      }
    return out;
  }();
  return sweeps;
}

const std::vector<Sweep>& RandomSweeps() {
  static const std::vector<Sweep> sweeps = [] {
    std::mt19937 rng(2);
    std::uniform_real_distribution<double> range(0.2, 5.0), step(-0.05, 0.05), turn(-0.1, 0.1);
    std::vector<Sweep> out;
    Pose2 pose{0, 0, 0};
    for (int i = 0; i < 2000; ++i) {
      pose = Pose2{pose.x + step(rng), pose.y + step(rng), pose.theta + turn(rng)};
      Sweep s;
      s.pose = pose;
      for (int j = 0; j < 16; ++j) s.readings.push_back({j, range(rng)});
      out.push_back(std::move(s));
    }
    return out;
  }();
  return sweeps;
}

void Ingest(benchmark::State& state, grid::FusionRule rule, const std::vector<Sweep>& sweeps) {
  grid::FusionOptions options;  // 0.1 m cells, 3 m window (paper defaults)
  auto fusion = grid::MakeFusion(rule, options);
  long readings = 0;
  for (auto _ : state) {
    for (const auto& s : sweeps) fusion->InsertSweep(s.pose, Robot(), s.readings);
    readings += static_cast<long>(sweeps.size()) * 16;
    benchmark::ClobberMemory();
  }
  state.SetItemsProcessed(readings);
  state.counters["cells"] = static_cast<double>(fusion->limits().cell_count());
}

void BM_RoomHimm(benchmark::State& s) { Ingest(s, grid::FusionRule::kHimm, RoomSweeps()); }
void BM_RoomMhimm(benchmark::State& s) { Ingest(s, grid::FusionRule::kMhimm, RoomSweeps()); }
void BM_RoomBayes(benchmark::State& s) { Ingest(s, grid::FusionRule::kBayes, RoomSweeps()); }
void BM_RoomDempsterShafer(benchmark::State& s) {
  Ingest(s, grid::FusionRule::kDempsterShafer, RoomSweeps());
}
void BM_RandomMhimm(benchmark::State& s) { Ingest(s, grid::FusionRule::kMhimm, RandomSweeps()); }
void BM_RandomHimm(benchmark::State& s) { Ingest(s, grid::FusionRule::kHimm, RandomSweeps()); }

BENCHMARK(BM_RoomHimm)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_RoomMhimm)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_RoomBayes)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_RoomDempsterShafer)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_RandomHimm)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_RandomMhimm)->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
