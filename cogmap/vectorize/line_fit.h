#pragma once
#include <cstdint>
#include <vector>

#include "cogmap/core/geometry.h"

namespace cogmap::vectorize {

enum class FitMode {
  kPaper,    // least squares y = b0 + b1 x, Pearson gate (eq. 3.8-3.10)
  kDefault,  // total least squares, rotation-invariant gate, corners closed
};

// Line fit (SPEC 3.5, §3.1.8).
struct LineFitOptions {
  FitMode mode = FitMode::kDefault;
  // Paper mode: accept a fit when |rho| >= this (§3.1.8: "testing showed .9").
  double min_abs_pearson = 0.9;
  // Default mode: accept a fit when the RMS perpendicular residual of the
  // points about the principal axis is at most this (cells).
  double max_rms_cells = 0.75;
  // Fewer points than this: the edge is left as it is (not counted rejected).
  int min_points = 3;
  // Default mode: neighbouring fitted edges meet at their lines' intersection
  // when the lines differ by at least this angle (guard against near-parallel
  // lines) and the intersection lies within max_corner_shift_cells of the
  // vertex; otherwise the vertex goes to the mean of its projections.
  double min_corner_deg = 20.0;
  double max_corner_shift_cells = 4.0;
  // Default mode, not in the paper: an edge shorter than this (cells) between
  // two accepted edges that meet at min_corner_deg or more is a chamfer (a
  // sonar grid rounds corners): it is dropped and its neighbours meet at their
  // intersection, when that lies within this distance of the edge's middle.
  // 0 turns it off.
  double max_chamfer_cells = 6.0;
};

struct LineFitStats {
  int64_t edges = 0;           // simplified edges considered
  int64_t fitted = 0;          // fits accepted
  int64_t rejected = 0;        // fits rejected by the gate (Pearson / RMS)
  int64_t too_few_points = 0;  // edges spanning fewer than min_points points
  int64_t corners_joined = 0;  // vertices moved to a line intersection
  int64_t chamfers_removed = 0;  // short edges replaced by their neighbours' corner
};

// One fitted line: a point on it and a unit direction.
struct FittedLine {
  Vec2 point{0, 0};
  Vec2 direction{1, 0};
  double quality = 0.0;  // |rho| (paper) or RMS residual in cells (default)
  bool accepted = false;
};

// Fits one line to 'points' by the mode's rule. Paper mode regresses on the
// axis of larger spread; a run lying exactly on a horizontal or vertical line
// (zero spread across it) counts as |rho| = 1, the fit being exact. All points
// equal: not accepted.
FittedLine FitLine(const std::vector<Vec2>& points, const LineFitOptions& options = {});

// For each edge (vertices[e], vertices[e + 1]) of a simplified chain, fits a
// line to the extracted points it spans (points[vertices[e]] ..
// points[vertices[e + 1]]) and moves the edge's ends onto it when the fit is
// accepted (a vertex shared by two accepted edges: see LineFitOptions). A
// closed chain (first point == last point) is treated as a ring.
std::vector<Vec2> FitEdges(const std::vector<Vec2>& points, const std::vector<int>& vertices,
                           const LineFitOptions& options = {}, LineFitStats* stats = nullptr);

}  // namespace cogmap::vectorize
