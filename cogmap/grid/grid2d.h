#pragma once
#include <algorithm>
#include <cmath>
#include <vector>

#include "cogmap/grid/map_limits.h"

namespace cogmap::grid {

// A dense 2-D array of cells over MapLimits, which can grow (in whole chunks,
// keeping the cell lattice) so that a moving robot stays inside it.
template <typename T>
class Grid2D {
 public:
  Grid2D() = default;
  Grid2D(const MapLimits& limits, T fill)
      : limits_(limits), fill_(fill), cells_(limits.cell_count(), fill) {}

  const MapLimits& limits() const { return limits_; }
  T fill() const { return fill_; }
  const std::vector<T>& cells() const { return cells_; }
  std::vector<T>& cells() { return cells_; }

  T& at(int x, int y) { return cells_[limits_.Flat(x, y)]; }
  const T& at(int x, int y) const { return cells_[limits_.Flat(x, y)]; }
  T& at(const CellIndex& c) { return at(c.x(), c.y()); }
  const T& at(const CellIndex& c) const { return at(c.x(), c.y()); }
  // Value at c, or the fill value outside the grid.
  T get(int x, int y) const {
    return (x >= 0 && y >= 0 && x < limits_.width() && y < limits_.height()) ? at(x, y) : fill_;
  }

  // Grows the grid (by at least 'chunk_cells' on a side that must grow) so that
  // the world box [lo, hi] lies inside. Returns true when it grew. Existing
  // cells keep their world position.
  bool EnsureContains(const Vec2& lo, const Vec2& hi, int chunk_cells = 64) {
    const CellIndex a = limits_.CellOf(lo), b = limits_.CellOf(hi);
    if (limits_.Contains(a) && limits_.Contains(b)) return false;
    const int grow_left = a.x() < 0 ? std::max(-a.x(), chunk_cells) : 0;
    const int grow_down = a.y() < 0 ? std::max(-a.y(), chunk_cells) : 0;
    const int grow_right = b.x() >= limits_.width() ? std::max(b.x() - limits_.width() + 1, chunk_cells) : 0;
    const int grow_up = b.y() >= limits_.height() ? std::max(b.y() - limits_.height() + 1, chunk_cells) : 0;
    const int w = limits_.width() + grow_left + grow_right;
    const int h = limits_.height() + grow_down + grow_up;
    const MapLimits next(limits_.cell_m(),
                         limits_.origin() - Vec2(grow_left, grow_down) * limits_.cell_m(), w, h);
    std::vector<T> cells(next.cell_count(), fill_);
    for (int y = 0; y < limits_.height(); ++y)
      std::copy_n(cells_.begin() + limits_.Flat(0, y), limits_.width(),
                  cells.begin() + next.Flat(grow_left, y + grow_down));
    limits_ = next;
    cells_ = std::move(cells);
    return true;
  }

 private:
  MapLimits limits_;
  T fill_{};
  std::vector<T> cells_;
};

}  // namespace cogmap::grid
