#pragma once
// Walls as straight segments found one line at a time in the cleaned
// occupancy evidence (not in the paper; docs/walls.md). The chain pipeline of
// SPEC 3 walks from cell to cell, so a sonar grid's rounded corners become
// chamfers and a walk through a doorway becomes a diagonal across the wall;
// here every wall is the line that the most evidence supports, its ends are
// where the evidence stops, and two walls meet at their lines' crossing when
// the sonar's blur can explain the cells missing between their ends.
#include <cstdint>
#include <vector>

#include "cogmap/core/geometry.h"
#include "cogmap/grid/grid2d.h"
#include "cogmap/vectorize/clean.h"

namespace cogmap::vectorize {

struct LineExtractOptions {
  CellClasses classes;
  // The evidence: the cleaned grid's occupied cells (false), or every
  // occupied cell of the input grid (true).
  bool all_occupied = false;
  // Hough accumulator over the cleaned cells: angle steps over a half turn
  // and the width of a distance bin (cells).
  int theta_bins = 180;
  double rho_bin_cells = 1.0;
  // A line's inliers lie within a band about it. The first band (around the
  // Hough peak) is this wide each side; after each total-least-squares fit
  // the band becomes band_sigmas x the inliers' RMS distance, kept within
  // [min, max] (min: a cell's centre lies up to half a diagonal off a line
  // through the cell).
  double first_band_cells = 1.5;
  double band_sigmas = 2.5;
  double min_band_cells = 0.75;
  double max_band_cells = 3.0;
  int refits = 3;
  // Once a line is taken, the evidence within this of its kept segments goes
  // with it (the rest of a thick sonar band would otherwise come back as
  // parallel fragments); elsewhere along the line only its inliers go.
  double clear_band_cells = 4.0;
  // Where a line's inliers leave a gap this long (metres) it is split: the
  // robot could pass (a doorway). A shorter gap is split too when the input
  // grid has no occupied cell along it (no evidence that the wall goes on),
  // from min_evidence_gap_cells up.
  double door_gap_m = 0.6;
  double min_evidence_gap_cells = 2.0;
  // A segment is a wall when it has at least min_points inliers, is at least
  // min_length_cells long and has at least min_density inliers per cell of
  // its length. Lines are taken while the Hough peak holds min_points votes.
  int min_points = 4;
  double min_length_cells = 3.0;
  double min_density = 0.5;
  int max_lines = 1000;
  // A segment joined to no other (no corner, no T) shorter than this
  // (metres) is an echo, not a wall.
  double min_isolated_m = 0.6;
  // The robot's body passed wherever its path goes: no wall lies nearer than
  // this (metres, the robot's radius less half a cell) to a robot-path cell.
  // Segments are cut there (a sonar band that bridges a doorway the robot
  // drove through), and no corner is made there. 0: off.
  double path_clearance_m = 0.0;
  // Corners. The sonar cone (half-width beam_half_width_rad) blurs a wall end
  // seen from range r by about r tan(half-width): the blur radius at a point
  // is blur_floor_cells + tan(half-width) x its distance to the nearest
  // robot-path cell (at most max_range_cells). Two segments whose lines
  // cross at min_corner_deg or more are extended or trimmed to the crossing
  // when it lies within the blur radius of an end of each; a segment end
  // within it of another segment's interior is extended to that segment's
  // line (a T junction). A segment no longer than twice the blur radius whose
  // two ends lie within it of such a corner is the rounded corner itself (a
  // chamfer) and is dropped. A laser's beam is narrow: its radius is the floor.
  double beam_half_width_rad = 0.2618;  // Polaroid: 30 degrees full cone
  double blur_floor_cells = 2.0;
  double max_range_cells = 30.0;
  double min_corner_deg = 30.0;
};

struct LineExtractStats {
  int64_t points = 0;            // cleaned cells used as evidence
  int64_t lines = 0;             // Hough peaks taken
  int64_t segments = 0;          // segments kept as walls
  int64_t rejected_runs = 0;     // runs along a line too weak to be a wall
  int64_t corners_joined = 0;    // segment pairs meeting at their crossing
  int64_t t_joins = 0;           // ends extended onto another segment
  int64_t chamfers_removed = 0;  // rounded-corner segments dropped
  int64_t isolated_removed = 0;  // short segments joined to nothing, dropped
  int64_t path_cuts = 0;         // segments cut where the robot drove
};

// One extracted wall segment, cell coordinates (cell (i, j) centre at
// (i + .5, j + .5)).
struct WallSegment {
  Vec2 a{0, 0}, b{0, 0};
  int points = 0;      // inliers behind it
  double rms_cells = 0.0;  // their RMS distance from the line
};

struct LineExtractResult {
  std::vector<WallSegment> segments;       // as found, before the corners
  std::vector<std::vector<Vec2>> walls;    // the walls, cell coordinates: segments joined at corners
  LineExtractStats stats;
};

// Extracts the walls from 'cleaned' (a cleaned grid: its occupied cells are
// the evidence) with 'raw' (the grid before cleaning, same limits: its
// occupied cells tell a gap from a wall that goes on, its robot-path cells
// give the ranges for the blur radius). Defined on every input: no occupied
// cells, no walls.
LineExtractResult ExtractWallLines(const grid::Grid2D<float>& cleaned, const grid::Grid2D<float>& raw,
                                   const LineExtractOptions& options = {});

}  // namespace cogmap::vectorize
