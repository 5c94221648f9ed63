#pragma once
// Pictures of vectorization: the stages side by side (thesis figure 3.3) and
// walls over the true walls.
#include <vector>

#include "cogmap/core/geometry.h"
#include "cogmap/draw/drawing.h"
#include "cogmap/draw/map_picture.h"
#include "cogmap/grid/grid2d.h"
#include "cogmap/vectorize/vectorize.h"

namespace cogmap::draw {

struct StagesPictureOptions {
  int max_side_px = 2000;     // pixel budget of the whole strip (five panels)
  int gap_px = 10;
  int crop_margin_cells = 5;  // panels show the known cells' bounding box plus this
  std::string title = "Vectorization stages";
};

// The stages side by side, like the thesis's figure 3.3: raw grid, cleaned
// grid, extracted points (one colour per chain), simplified (vertex simplify +
// Douglas-Peucker) and fitted, each panel titled, cropped to the cells that
// hold anything, all at one scale; below them a band with the scale bar, the
// legend and the north arrow, as on every map page. Grids: unknown grey,
// empty white, occupied black, robot path red. When a panel has fewer pixels
// than cells, a pixel shows the strongest of its cells (path over occupied
// over the rest), so thin walls stay visible.
struct StagesPicture {
  Drawing drawing;
  double px_per_m = 0.0;     // every panel's scale
  ScaleBar scale_bar;
  double band_top_px = 0.0;  // the panels end above it
};
StagesPicture DrawStages(const grid::Grid2D<float>& raw, const vectorize::VectorizeResult& result,
                         const StagesPictureOptions& options = {});

// Walls (black, vertices red) over the true walls (light blue, when given)
// and a path (faint red, when given), on a page fitted to the pixel budget.
MapPicture DrawWalls(const std::vector<Polyline>& walls, const std::vector<Segment2>& truth,
                     const Polyline& path, const PictureOptions& options = {});

}  // namespace cogmap::draw
