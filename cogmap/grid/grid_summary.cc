#include "cogmap/grid/grid_summary.h"

#include <cmath>

namespace cogmap::grid {

GridSummary Summarize(const RangeFusion& fusion) {
  GridSummary s;
  const Grid2D<CellClass> classes = fusion.Classes();
  const Grid2D<float> p = fusion.Occupancy();
  const int w = classes.limits().width(), h = classes.limits().height();
  s.cells = classes.limits().cell_count();
  double entropy = 0.0;
  long in_line = 0;
  auto occ = [&](int x, int y) { return classes.get(x, y) == CellClass::kOccupied; };
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      switch (classes.at(x, y)) {
        case CellClass::kOccupied:
          ++s.occupied;
          if ((occ(x - 1, y) && occ(x + 1, y)) || (occ(x, y - 1) && occ(x, y + 1))) ++in_line;
          break;
        case CellClass::kEmpty: ++s.empty; break;
        case CellClass::kUnknown: ++s.unknown; break;
        case CellClass::kRobotPath: ++s.robot_path; break;
      }
      const double q = p.at(x, y);
      if (q == 0.5) continue;
      ++s.touched;
      if (q > 0.0 && q < 1.0) entropy += -(q * std::log2(q) + (1 - q) * std::log2(1 - q));
    }
  if (s.touched > 0) s.mean_entropy_bits = entropy / s.touched;
  if (s.occupied > 0) s.line_fraction = static_cast<double>(in_line) / s.occupied;
  return s;
}

}  // namespace cogmap::grid
