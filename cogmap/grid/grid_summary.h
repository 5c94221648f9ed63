#pragma once
#include "cogmap/grid/range_fusion.h"

namespace cogmap::grid {

// Counts of the classes of a grid and measures of how sharp it is: for the
// same readings, straighter walls give fewer and thinner occupied cells, and
// a lower mean entropy of the cells the readings touched.
struct GridSummary {
  long cells = 0;
  long occupied = 0;
  long empty = 0;
  long unknown = 0;
  long robot_path = 0;
  long touched = 0;            // cells whose occupancy differs from 0.5
  double mean_entropy_bits = 0.0;  // over touched cells, of Occupancy()
  // Occupied cells with at least one occupied 4-neighbour on both sides of a
  // row or a column (part of a line 3 cells long) over all occupied cells.
  double line_fraction = 0.0;
};

GridSummary Summarize(const RangeFusion& fusion);

}  // namespace cogmap::grid
