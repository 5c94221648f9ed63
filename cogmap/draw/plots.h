#pragma once
// Plots: the heading error per ASR (issue 6 item 5).
#include "cogmap/draw/drawing.h"
#include "cogmap/localize/heading_error.h"

namespace cogmap::draw {

// Heading error per ASR (degrees, one global rotation removed as in
// localize::ComputeHeadingErrors): odometry (red) and corrected (blue) over the
// ASRs in visiting order, with axes, ticks, a zero line, a title and a legend
// (median / max of each); a second panel below shows the corrected series on
// its own scale. A note instead of the panels when 'stats' has no ASR.
Drawing PlotHeadingErrors(const localize::HeadingErrorStats& stats, double width_px = 900, double height_px = 640);

constexpr Colour kRawSeries = Rgb8(210, 40, 40);
constexpr Colour kCorrectedSeries = Rgb8(30, 80, 200);

}  // namespace cogmap::draw
