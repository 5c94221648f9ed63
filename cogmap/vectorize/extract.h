#pragma once
#include <cstdint>
#include <vector>

#include "cogmap/grid/grid2d.h"
#include "cogmap/vectorize/clean.h"

namespace cogmap::vectorize {

// A chain of grid cells (column x, row y), in walking order.
using CellChain = std::vector<grid::CellIndex>;

// Extract points (SPEC 3.2, fig. 3.9).
struct ExtractOptions {
  CellClasses classes;
  // gamma: a step longer than this (cells, Euclidean) ends the polyline
  // (§3.1.6, table 4.1).
  double gamma_cells = 4.0;
  // Not in the paper: when a chain ends within gamma of its own first cell
  // (a room walked all the way round), repeat the first cell at its end so the
  // outline is closed (the geometry.h convention). Adds no cell.
  bool close_loops = true;
};

struct ExtractStats {
  int64_t points = 0;  // occupied cells taken (vertices of all chains)
  int64_t chains = 0;
  int64_t closed = 0;  // chains closed by close_loops
};

// From the first occupied cell in raster order (row y ascending, then x), walks
// to the nearest remaining occupied cell (Euclidean; ties to the lower row, then
// the lower column), removing each as it is taken, until none is left; a step
// longer than gamma starts a new chain at that cell. The nearest-neighbour
// search uses a bucket index (side gamma) with per-bucket counts, so a step
// costs a few buckets, never a scan of the grid.
std::vector<CellChain> ExtractPoints(const grid::Grid2D<float>& grid,
                                     const ExtractOptions& options = {},
                                     ExtractStats* stats = nullptr);

// Cell centres of a chain, in cell coordinates (cell (i, j) -> (i + .5, j + .5)).
std::vector<Vec2> ChainToCellCoords(const CellChain& chain);

}  // namespace cogmap::vectorize
