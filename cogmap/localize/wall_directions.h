#pragma once
#include <vector>

#include "cogmap/asr/asr.h"
#include "cogmap/core/geometry.h"

namespace cogmap::localize {

// Folds a direction (radians) into [-pi/4, pi/4): the offset of a line from
// the nearest of the x and y axes (SPEC 5, thesis §3.1.10 and fig. A.7).
// Indoor walls are parallel or perpendicular, so a wall and its normal fold to
// the same value. This is the rotation-correct fold (theta mod 90 degrees);
// fig. A.7 as printed reflects some quadrants instead (docs/heading-correction.md).
double FoldToQuarterTurn(double direction_rad);

// One edge of a polyline: its folded direction and its length.
struct WallDirection {
  double folded_rad = 0.0;  // in [-pi/4, pi/4)
  double length_m = 0.0;
};

// The s data (fig. A.7): one entry per edge (pair of consecutive vertices) of
// every polyline, in order. Edges shorter than 'min_edge_m' (repeated vertices)
// carry no direction and are skipped, as are edges with a non-finite vertex.
std::vector<WallDirection> WallDirections(const std::vector<Polyline>& walls,
                                          double min_edge_m = 1e-9);

// The s data of an ASR, measured in the world frame of the raw (odometry) map:
// walls_local transformed by world_from_local_raw.
std::vector<WallDirection> WallDirectionsWorldRaw(const asr::Asr& asr);

// The m data (thesis §3.1.10: "the center point of the exit locations, the m
// data set"). The thesis does not say how points become angles; our reading:
// the folded directions of the chords the robot drove through the ASR: from the
// entry pivot to the first exit centre, then from each exit centre to the next
// (in the order of asr.exits). When the ASR has no exits yet, the chord from the first to the last
// pose of its path stands in. Chords shorter than 'min_chord_m' are skipped.
// World frame of the raw map. Radians in [-pi/4, pi/4).
std::vector<double> MotorDirections(const asr::Asr& asr, double min_chord_m = 0.2);

}  // namespace cogmap::localize
