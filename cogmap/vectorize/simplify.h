#pragma once
#include <vector>

#include "cogmap/core/geometry.h"

namespace cogmap::vectorize {

// Vertex simplify (SPEC 3.3, fig. A.4).
struct VertexSimplifyOptions {
  double tau_cells = 2.0;  // tau, fig. A.4 ("2 seems to work good")
  // Not in fig. A.4, which may drop the last vertex: keep the polyline's end so
  // a wall keeps its length (the last kept vertex gives way to it when closer
  // than tau).
  bool keep_end = true;
};

// Indices of the vertices kept: the first, then every vertex at least tau from
// the last kept one. Input and distances in cells.
std::vector<int> VertexSimplifyIndices(const std::vector<Vec2>& line,
                                       const VertexSimplifyOptions& options = {});

// Douglas-Peucker (SPEC 3.4, fig. A.5).
struct DouglasPeuckerOptions {
  // eta, perpendicular distance to the chord (cells); the thesis gives no
  // number (table 4.1's gamma row describes it by mistake): SPEC 3.4.
  double eta_cells = 1.5;
};

// Indices of the vertices kept: both ends, and recursively the vertex farthest
// from the chord of its span while that distance exceeds eta (distance to the
// segment, as fig. A.5). Iterative, so long chains cannot overflow the stack.
// A closed outline (first == last) is first split at the vertex farthest from
// its first vertex.
std::vector<int> DouglasPeuckerIndices(const std::vector<Vec2>& line,
                                       const DouglasPeuckerOptions& options = {});

// Picks 'indices' of 'line'.
std::vector<Vec2> Pick(const std::vector<Vec2>& line, const std::vector<int>& indices);

// Polyline forms of the two stages.
Polyline VertexSimplify(const Polyline& line, const VertexSimplifyOptions& options = {});
Polyline SimplifyDouglasPeucker(const Polyline& line, const DouglasPeuckerOptions& options = {});

}  // namespace cogmap::vectorize
