#pragma once
#include <cstdlib>

namespace cogmap {

// Visits the cells of the Bresenham line from (x0, y0) to (x1, y1), both ends
// included, in order from the start. 'visit(x, y)' returns false to stop early.
// Returns false when stopped early.
template <typename Visit>
bool WalkBresenham(int x0, int y0, int x1, int y1, Visit&& visit) {
  const int dx = std::abs(x1 - x0), sx = x0 < x1 ? 1 : -1;
  const int dy = -std::abs(y1 - y0), sy = y0 < y1 ? 1 : -1;
  int err = dx + dy;
  for (;;) {
    if (!visit(x0, y0)) return false;
    if (x0 == x1 && y0 == y1) return true;
    const int e2 = 2 * err;
    if (e2 >= dy) { err += dy; x0 += sx; }
    if (e2 <= dx) { err += dx; y0 += sy; }
  }
}

// The first step WalkBresenham takes from a start toward a cell (dx, dy) away,
// (dx, dy) != (0, 0): x moves when 2|dx| >= |dy|, y when |dx| <= 2|dy|.
// Each component of the result is -1, 0 or 1.
inline void BresenhamFirstStep(int dx, int dy, int* step_x, int* step_y) {
  const int adx = std::abs(dx), ady = std::abs(dy);
  *step_x = 2 * adx >= ady ? (dx > 0 ? 1 : -1) : 0;
  *step_y = adx <= 2 * ady ? (dy > 0 ? 1 : -1) : 0;
}

}  // namespace cogmap
