#pragma once
#include <string>

#include "cogmap/io/image.h"
#include "cogmap/localize/heading_error.h"

namespace cogmap::localize {

// Figures of the heading correction (issue 6 item 5).

// Heading error per ASR (degrees, one global rotation removed as in
// ComputeHeadingErrors): odometry (red) and corrected (blue) as polylines
// over the ASRs in visiting order, with axes, ticks, a zero line, a title and
// a legend (median / max of each); a second panel below shows the corrected
// series on its own scale. An empty plot with a note when 'stats' has no ASR.
io::RgbImage PlotHeadingErrors(const HeadingErrorStats& stats, int width = 900, int height = 640);

// Two pictures side by side on white, each with a title above it (the master
// map before and after correction).
io::RgbImage SideBySide(const io::RgbImage& left, const std::string& left_title, const io::RgbImage& right,
                        const std::string& right_title);

// Two SVG documents (as FormatMapSvg writes them: one root <svg> with width
// and height) side by side in one SVG, each under its title.
std::string SideBySideSvg(const std::string& left_svg, const std::string& left_title,
                          const std::string& right_svg, const std::string& right_title);

}  // namespace cogmap::localize
