#pragma once
#include <cstdint>
#include <vector>

#include "cogmap/core/geometry.h"
#include "cogmap/grid/grid2d.h"
#include "cogmap/vectorize/clean.h"
#include "cogmap/vectorize/extract.h"
#include "cogmap/vectorize/line_extract.h"
#include "cogmap/vectorize/line_fit.h"
#include "cogmap/vectorize/polyline_codec.h"
#include "cogmap/vectorize/simplify.h"

namespace cogmap::vectorize {

// The whole of SPEC 3: clean -> extract -> vertex simplify -> Douglas-Peucker
// -> line fit. Each stage's options struct holds the paper's defaults;
// VectorizeOptions{} is cogmap's default pipeline, which differs from the
// paper (Paper()) in two places: the clean keeps the middle of each wall band
// instead of its face, and the fit is total least squares with corners closed.
struct VectorizeOptions {
  CleanOptions clean = [] {
    CleanOptions c;
    c.keep = KeepCell::kRunMiddle;
    return c;
  }();
  ExtractOptions extract;
  VertexSimplifyOptions vertex_simplify;
  DouglasPeuckerOptions douglas_peucker;
  LineFitOptions fit;
  PolylineCodecOptions codec;
  // Not in the paper: chains of fewer extracted cells than this are not walls
  // (isolated echoes). 2 keeps every chain that can make a segment.
  int min_chain_points = 2;
  // Not in the paper: each extracted point (cell coordinates) is replaced by
  // the mean of the points within this many steps along its chain before the
  // simplify and the fit (0: off, as the paper). Damps the zig-zag of a walk
  // through a ragged band; ends and loop seams use the points that exist.
  // Off by default: on the nine_rooms sonar run +-1 cut the p95 wall error
  // from 0.35 m to 0.30 m and the vertices by a quarter, but it chamfers
  // corners (an L room's inner corner moved 0.2 m).
  int smooth_half_window = 0;
  // Not in the paper: the walls are found as lines in the cleaned cells
  // (ExtractWallLines, docs/walls.md) instead of by simplifying and fitting
  // the extracted chains (the chains are still extracted, for the pictures).
  bool wall_lines = false;
  LineExtractOptions lines;

  // The paper's choices: the face of the wall, least squares with Pearson,
  // walls from the chains.
  static VectorizeOptions Paper() {
    VectorizeOptions o;
    o.clean.keep = KeepCell::kFace;
    o.fit.mode = FitMode::kPaper;
    o.wall_lines = false;
    return o;
  }
};

struct VectorizeBytes {
  int64_t grid = 0;       // one byte per cell of the input grid
  int64_t vertices = 0;   // extracted points, 2 x int16 per vertex
  int64_t polylines = 0;  // EncodePolylines(result polylines).size()
};

struct VectorizeSeconds {
  double clean = 0.0;
  double extract = 0.0;
  double simplify = 0.0;  // vertex simplify + Douglas-Peucker
  double fit = 0.0;
  double total() const { return clean + extract + simplify + fit; }
};

struct VectorizeResult {
  std::vector<Polyline> polylines;  // the walls, world metres
  // Intermediate products (cell coordinates, cell centres at .5) for pictures.
  grid::Grid2D<float> cleaned;
  std::vector<CellChain> chains;                // extracted, every chain
  std::vector<std::vector<Vec2>> simplified;    // after VS + DP (walls only); wall_lines: the segments as found
  std::vector<std::vector<Vec2>> fitted;        // after the fit (walls only); wall_lines: joined at corners
  CleanStats clean_stats;
  ExtractStats extract_stats;
  LineFitStats fit_stats;
  LineExtractStats line_stats;  // wall_lines only
  int64_t vertices_after_vertex_simplify = 0;
  int64_t vertex_count = 0;  // vertices of 'polylines'
  int64_t dropped_chains = 0;  // chains shorter than min_chain_points
  VectorizeBytes bytes;
  VectorizeSeconds seconds;
};

// Runs the pipeline on a modified-HIMM grid. Defined results on every input:
// an empty grid, a grid without robot path (cleaning keeps nothing: no walls),
// or without occupied cells gives no polylines (and no error).
VectorizeResult Vectorize(const grid::Grid2D<float>& grid, const VectorizeOptions& options = {});

}  // namespace cogmap::vectorize
