#pragma once
#include <cstdint>

#include "cogmap/grid/grid2d.h"

namespace cogmap::vectorize {

// Cell values of the modified HIMM (SPEC 2, 3): occupied > epsilon, the robot
// path is exactly robot_path, unknown is 0, explored empty is below 0.
struct CellClasses {
  float occupied_above = 7.0f;   // epsilon, table 4.1
  float robot_path = -100.0f;    // §3.1.5
  bool IsOccupied(float v) const { return v > occupied_above; }
  bool IsPath(float v) const { return v == robot_path; }
};

// Which cell of a wall survives cleaning.
enum class KeepCell {
  kFace,       // the first occupied cell the path sees (fig. 3.8)
  kRunMiddle,  // the middle of the occupied run behind it, along the sight line
};

// Clean (SPEC 3.1, fig. 3.8).
struct CleanOptions {
  CellClasses classes;
  // max_dist: half-size (cells) of the square searched around each occupied
  // cell, the sonar's effective range; default = window w = 3 m at 0.1 m
  // (SPEC 2, 3.1).
  int max_dist_cells = 30;
  // Not in the paper (kRunMiddle): a sonar grid's wall is a band several
  // cells thick whose face toward the path sits in front of the true wall
  // (the cone returns the nearest echo, drawn along the axis); the middle of
  // the band lies much closer to it. Each surviving face cell a, seen from
  // path cell p, is replaced by the middle cell of the run of occupied cells
  // starting at a along the ray p -> a (at most max_run_cells long).
  KeepCell keep = KeepCell::kFace;
  int max_run_cells = 12;
};

struct CleanStats {
  int64_t occupied_in = 0;   // occupied cells before cleaning
  int64_t kept = 0;          // occupied cells that survived
  int64_t path_cells = 0;    // distinct robot_path cells
  int64_t rays_walked = 0;   // Bresenham walks started
  int64_t steps_walked = 0;  // cells visited by them
  int64_t buried = 0;        // dropped at once: all 8 neighbours occupied
};

// The fast clean. An occupied cell a survives when the Bresenham ray from a
// toward some robot_path cell p, with |p - a| <= max_dist in both axes, meets
// no occupied cell strictly between a and p. Every other occupied cell becomes
// unknown (0); all other cells are copied unchanged. The path cells are found
// through a bucket index and tried nearest first, a cell whose 8 neighbours
// are all occupied is dropped at once (every ray's first step is blocked), a
// path cell whose ray's first step is an occupied neighbour is not tried at
// all, and a walk stops at its first occupied cell, so
// a wall cell costs a few short walks rather than the (2 max_dist + 1)^2 long
// ones of the paper's loop. With keep = kRunMiddle the survivors are then
// moved to the middle of their wall band (see CleanOptions).
//
// Relation to the paper's loop (CleanMapBruteForce, fig. 3.8), which walks a
// ray toward every cell b of the square and keeps a when the ray meets a path
// cell before an occupied one: each survivor here is one there (the ray toward
// p is one of the paper's rays), and the paper keeps a few more, where a ray
// aimed past a path cell grazes it although the direct ray to it is blocked
// (Bresenham asymmetry). CleanMapPathTargets is the plain reference for this
// function's exact definition; tests compare all three.
grid::Grid2D<float> CleanMap(const grid::Grid2D<float>& grid, const CleanOptions& options = {},
                             CleanStats* stats = nullptr);

// Fig. 3.8 as printed: every occupied cell x every cell b of its square x
// every step of the ray toward b (with the figure's slip H_pa -> H_pt fixed).
// O(occupied x max_dist^3): for tests and small grids only.
grid::Grid2D<float> CleanMapBruteForce(const grid::Grid2D<float>& grid,
                                       const CleanOptions& options = {});

// Reference for CleanMap's exact definition: every occupied cell x every path
// cell of its square, walked without the index or early ordering.
grid::Grid2D<float> CleanMapPathTargets(const grid::Grid2D<float>& grid,
                                        const CleanOptions& options = {});

}  // namespace cogmap::vectorize
