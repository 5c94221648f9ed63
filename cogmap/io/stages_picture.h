#pragma once
#include <vector>

#include "cogmap/core/geometry.h"
#include "cogmap/grid/grid2d.h"
#include "cogmap/io/image.h"
#include "cogmap/vectorize/vectorize.h"

namespace cogmap::io {

struct StagesPictureOptions {
  int max_panel_px = 360;  // longest side of one panel
  int gap_px = 8;
  int label_scale = 2;     // DrawText scale of the panel titles
  int crop_margin_cells = 5;  // panels show the known cells' bounding box plus this
};

// The stages side by side, like the thesis's figure 3.3: raw grid, cleaned
// grid, extracted points (one colour per chain), simplified (vertex simplify +
// Douglas-Peucker) and fitted, each panel titled, cropped to the cells that
// hold anything. Grids: unknown grey, empty
// white, occupied black, robot path red.
RgbImage DrawStages(const grid::Grid2D<float>& raw, const vectorize::VectorizeResult& result,
                    const StagesPictureOptions& options = {});

// Walls (and, when given, the true walls under them in light blue) on white,
// 'px_per_m' pixels per metre over the box [min, max]: a raster twin of the
// SVG, for looking at without an SVG viewer.
RgbImage DrawWalls(const std::vector<Polyline>& walls, const std::vector<Segment2>& truth,
                   const Vec2& min, const Vec2& max, double px_per_m = 40.0);

}  // namespace cogmap::io
