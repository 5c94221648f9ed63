// EM time per ASR: paper mode (fig. A.6) and default mode (von Mises +
// clutter on 4 theta), for ASRs with 20 and 200 wall edges.
#include <benchmark/benchmark.h>

#include <cmath>
#include <random>

#include "cogmap/localize/em.h"
#include "cogmap/localize/heading_corrector.h"
#include "cogmap/localize/odometry_corrector.h"

namespace {

using namespace cogmap;
using namespace cogmap::localize;

// 'n' edges: 80% walls at 7 degrees (+- 2 degrees noise) in both axis
// directions, 20% clutter at random angles; lengths 0.2-2 m. Fixed seed.
std::vector<WallDirection> Edges(int n) {
  std::mt19937 rng(11);
  std::normal_distribution<double> noise(0.0, DegToRad(2.0));
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::vector<WallDirection> out;
  for (int i = 0; i < n; ++i) {
    const bool clutter = i % 5 == 4;
    const double a = clutter ? unit(rng) * 2 * kPi : DegToRad(7) + (i % 2) * kPi / 2 + noise(rng);
    out.push_back({FoldToQuarterTurn(a), 0.2 + 1.8 * unit(rng)});
  }
  return out;
}

void BM_PaperEm(benchmark::State& state) {
  const auto s = Edges(static_cast<int>(state.range(0)));
  const std::vector<double> m = {DegToRad(6.0)};
  for (auto _ : state) benchmark::DoNotOptimize(EstimateDirectionPaper(s, m));
  state.SetLabel("edges per ASR");
}
BENCHMARK(BM_PaperEm)->Arg(20)->Arg(200)->Unit(benchmark::kMicrosecond);

void BM_DefaultEm(benchmark::State& state) {
  const auto s = Edges(static_cast<int>(state.range(0)));
  for (auto _ : state) benchmark::DoNotOptimize(EstimateDirectionRobust(s));
  state.SetLabel("edges per ASR");
}
BENCHMARK(BM_DefaultEm)->Arg(20)->Arg(200)->Unit(benchmark::kMicrosecond);

// Close(): wall directions from polylines, EM and the pose update.
void BM_CloseAsr(benchmark::State& state) {
  const int n = static_cast<int>(state.range(0));
  asr::Asr a;
  Polyline line;
  std::mt19937 rng(3);
  std::normal_distribution<double> jitter(0.0, 0.01);
  for (int i = 0; i <= n; ++i) {
    const double t = 2 * kPi * i / n;
    // A square outline traced with n edges.
    const double c = std::cos(t), s = std::sin(t), k = std::max(std::abs(c), std::abs(s));
    line.push_back({3 * c / k + jitter(rng), 3 * s / k + jitter(rng)});
  }
  a.walls_local = {line};
  HeadingCorrectionOptions o;
  o.mode = state.range(1) ? HeadingMode::kDefault : HeadingMode::kPaper;
  HeadingCorrector corrector(o);
  for (auto _ : state) benchmark::DoNotOptimize(corrector.Close(a));
  state.SetLabel(state.range(1) ? "default" : "paper");
}
BENCHMARK(BM_CloseAsr)->Args({20, 0})->Args({200, 0})->Args({20, 1})->Args({200, 1})
    ->Unit(benchmark::kMicrosecond);

// Drift filter: the pre-correction of one odometry record (every record of a
// log goes through it).
void BM_CorrectOdometry(benchmark::State& state) {
  OdometryCorrector c;
  Pose2 raw;
  double t = 0.0;
  long n = 0;
  for (auto _ : state) {
    raw = raw * Pose2{0.02, 0.0, 0.001};
    benchmark::DoNotOptimize(c.Correct(raw, t));
    t += 0.1;
    if (++n % 1024 == 0) c.Forget(t);  // as each ASR's Close does
  }
  state.SetLabel("per record");
}
BENCHMARK(BM_CorrectOdometry)->Unit(benchmark::kNanosecond);

// Drift filter: Close of one ASR (EM + filter update + rotation), 200 records
// per ASR window, and the end-of-run smoothing of 100 ASRs.
void BM_DriftClose(benchmark::State& state) {
  asr::Asr a;
  a.walls_local = {{{-2, -2}, {2, -2}, {2, 2}, {-2, 2}, {-2, -2}}};
  for (auto _ : state) {
    state.PauseTiming();
    DriftHeadingCorrector c;
    Pose2 raw;
    double t = 0.0;
    state.ResumeTiming();
    for (int k = 0; k < 100; ++k) {
      a.start_time_s = t;
      for (int i = 0; i < 200; ++i, t += 0.1) {
        raw = raw * Pose2{0.02, 0.0, 0.0002};
        c.CorrectOdometry(raw, t);
      }
      a.end_time_s = t;
      a.id = k;
      benchmark::DoNotOptimize(c.Close(a));
    }
    benchmark::DoNotOptimize(c.Smooth());
  }
  state.SetLabel("100 ASRs x 200 records, then Smooth");
}
BENCHMARK(BM_DriftClose)->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
