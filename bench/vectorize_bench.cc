// Time per stage of SPEC 3 on realistic synthetic room grids (Google
// Benchmark): a 10 m x 8 m room and a 200 x 200 cell room (19 m x 19 m) at
// 0.1 m, walls 3 cells thick, the free space seen, sparse noise, the robot
// path a loop 1.5 m inside the walls.
#include <benchmark/benchmark.h>

#include "cogmap/vectorize/orientation.h"
#include "cogmap/vectorize/synthetic_grid.h"
#include "cogmap/vectorize/vectorize.h"

namespace cv = cogmap::vectorize;
using cogmap::Polyline;
using cogmap::Vec2;

namespace {

// Room 'w_m' x 'h_m' with a margin so the grid is (w_m + 1) x (h_m + 1) m.
cogmap::grid::Grid2D<float> Room(double w_m, double h_m) {
  const auto walls = cv::RectangleWalls(Vec2(0, 0), Vec2(w_m, h_m));
  const Polyline path = {Vec2(1.5, 1.5), Vec2(w_m - 1.5, 1.5), Vec2(w_m - 1.5, h_m - 1.5),
                         Vec2(1.5, h_m - 1.5), Vec2(1.5, 1.5)};
  cv::SyntheticGridOptions o;
  o.wall_half_width_m = 0.15;
  o.see_m = 3.0;
  o.noise_fraction = 0.002;
  o.seed = 3;
  return cv::MakeSyntheticGrid(walls, path, o);
}

const cogmap::grid::Grid2D<float>& Grid(int which) {
  static const auto small = Room(10.0, 8.0);   // 110 x 90 cells
  static const auto large = Room(19.0, 19.0);  // 200 x 200 cells
  return which == 0 ? small : large;
}

void SetLabel(benchmark::State& state, const cogmap::grid::Grid2D<float>& g) {
  state.SetLabel(std::to_string(g.limits().width()) + "x" + std::to_string(g.limits().height()) + " cells");
}

void BM_Clean(benchmark::State& state) {
  const auto& g = Grid(static_cast<int>(state.range(0)));
  const cv::VectorizeOptions o;
  for (auto _ : state) benchmark::DoNotOptimize(cv::CleanMap(g, o.clean));
  SetLabel(state, g);
}

void BM_CleanPaperBruteForce(benchmark::State& state) {
  const auto& g = Grid(static_cast<int>(state.range(0)));
  for (auto _ : state) benchmark::DoNotOptimize(cv::CleanMapBruteForce(g));
  SetLabel(state, g);
}

void BM_Extract(benchmark::State& state) {
  const auto& g = Grid(static_cast<int>(state.range(0)));
  const auto cleaned = cv::CleanMap(g, cv::VectorizeOptions{}.clean);
  for (auto _ : state) benchmark::DoNotOptimize(cv::ExtractPoints(cleaned));
  SetLabel(state, g);
}

void BM_SimplifyAndFit(benchmark::State& state) {
  const auto& g = Grid(static_cast<int>(state.range(0)));
  const auto chains = cv::ExtractPoints(cv::CleanMap(g, cv::VectorizeOptions{}.clean));
  for (auto _ : state) {
    for (const auto& c : chains) {
      const auto pts = cv::ChainToCellCoords(c);
      const auto vs = cv::VertexSimplifyIndices(pts);
      const auto dp = cv::DouglasPeuckerIndices(cv::Pick(pts, vs));
      std::vector<int> idx;
      for (int i : dp) idx.push_back(vs[i]);
      benchmark::DoNotOptimize(cv::FitEdges(pts, idx));
    }
  }
  SetLabel(state, g);
}

void BM_Vectorize(benchmark::State& state) {
  const auto& g = Grid(static_cast<int>(state.range(0)));
  const auto o = state.range(1) ? cv::VectorizeOptions::Paper() : cv::VectorizeOptions{};
  cv::VectorizeResult r;
  for (auto _ : state) r = cv::Vectorize(g, o);
  SetLabel(state, g);
  state.counters["vertices"] = static_cast<double>(r.vertex_count);
  state.counters["bytes_grid"] = static_cast<double>(r.bytes.grid);
  state.counters["bytes_vertices"] = static_cast<double>(r.bytes.vertices);
  state.counters["bytes_polylines"] = static_cast<double>(r.bytes.polylines);
  state.counters["clean_ms"] = r.seconds.clean * 1e3;
  state.counters["extract_ms"] = r.seconds.extract * 1e3;
  state.counters["simplify_ms"] = r.seconds.simplify * 1e3;
  state.counters["fit_ms"] = r.seconds.fit * 1e3;
}

}  // namespace

// The dominant orientation of the occupied cells (what the mapper computes
// for each ASR as it closes, for the heading correction's grid refinement).
void BM_DominantOrientation(benchmark::State& state) {
  const auto& g = Grid(static_cast<int>(state.range(0)));
  std::vector<Vec2> cells;
  for (int y = 0; y < g.limits().height(); ++y)
    for (int x = 0; x < g.limits().width(); ++x)
      if (g.at(x, y) > 7.0f) cells.push_back(Vec2(x + 0.5, y + 0.5));
  for (auto _ : state) benchmark::DoNotOptimize(cv::DominantOrientation(cells));
  state.SetLabel(std::to_string(cells.size()) + " occupied cells");
}

BENCHMARK(BM_Clean)->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_DominantOrientation)->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_CleanPaperBruteForce)->Arg(0)->Unit(benchmark::kMillisecond)->Iterations(1);
BENCHMARK(BM_Extract)->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_SimplifyAndFit)->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_Vectorize)->Args({0, 0})->Args({1, 0})->Args({1, 1})->Unit(benchmark::kMillisecond);
BENCHMARK_MAIN();
