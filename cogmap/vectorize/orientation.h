#pragma once
#include <vector>

#include "cogmap/core/angles.h"
#include "cogmap/core/geometry.h"

namespace cogmap::vectorize {

// The dominant wall orientation of a set of wall points (not in the thesis;
// used by the default heading correction, docs/heading-correction.md).
//
// A projection (Radon) profile: for an angle theta, the points are projected
// on the normal n(theta) = (cos theta, sin theta) and on the perpendicular
// normal n(theta + 90 deg), each projection binned (bin_size wide, linear
// interpolation between the two nearest bins so the score is smooth in theta),
// and the score is the sum of the squared bin counts of both histograms. Points
// on a straight wall fall into one or two bins only when theta matches the
// wall, so the score peaks at the orientation shared by most wall points
// (walls parallel or perpendicular to each other add up; clutter spreads out).
// A coarse scan of [-45, 45) degrees with a wide kernel, a fine scan around
// its best with the fine one, then golden-section refinement.
struct OrientationOptions {
  double bin_size = 0.5;                   // Gaussian sigma, unit of the points (cells)
  double coarse_sigma_factor = 4.0;        // coarse scan: sigma x this
  double coarse_step_rad = DegToRad(2.0);  // coarse scan step
  double fine_step_rad = DegToRad(0.25);   // fine scan around the coarse best
  double tolerance_rad = DegToRad(0.01);   // golden-section refinement stops here
  int min_points = 10;
};

struct Orientation {
  bool valid = false;      // enough points
  double angle_rad = 0.0;  // folded into [-45, 45) degrees
  // Peak score over the median score of 8 angles spread over the rest of the
  // quarter turn (>= 1; about 1 for points without a dominant orientation,
  // e.g. a round room).
  double contrast = 0.0;
  int points = 0;
};

// The profile score at one angle (exposed for tests and pictures).
double OrientationScore(const std::vector<Vec2>& points, double theta_rad, double bin_size);

Orientation DominantOrientation(const std::vector<Vec2>& points, const OrientationOptions& options = {});

}  // namespace cogmap::vectorize
