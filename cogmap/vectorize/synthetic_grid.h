#pragma once
#include <cstdint>
#include <vector>

#include "cogmap/core/geometry.h"
#include "cogmap/grid/grid2d.h"

namespace cogmap::vectorize {

// A modified-HIMM grid drawn from known walls and a known path, for tests,
// benchmarks and comparisons (no sensor model: see cogmap/sim for that).
struct SyntheticGridOptions {
  double cell_m = 0.1;
  double margin_m = 0.5;           // grid border around walls and path
  double wall_half_width_m = 0.05;  // cells whose centre lies this close to a wall are occupied
  float wall_value = 15.0f;
  float empty_value = -3.0f;       // cells within see_m of the path, not occupied
  double see_m = 0.0;              // 0: leave free space unknown (0)
  double noise_fraction = 0.0;     // fraction of free cells set occupied at random
  uint32_t seed = 1;
};

// Walls and path in world metres. The grid's lower-left corner sits at the
// lower-left of their bounding box minus the margin, snapped to cell_m.
grid::Grid2D<float> MakeSyntheticGrid(const std::vector<Segment2>& walls, const Polyline& path,
                                      const SyntheticGridOptions& options = {});

// The four walls of an axis-aligned rectangle.
std::vector<Segment2> RectangleWalls(const Vec2& min, const Vec2& max);

}  // namespace cogmap::vectorize
