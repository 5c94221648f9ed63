#pragma once
// Occupancy grids as pictures: the cell colours (one pixel per cell, or
// 'scale' pixels) and the grid on a page with a title, scale bar and legend.
#include "cogmap/draw/drawing.h"
#include "cogmap/draw/layout.h"
#include "cogmap/grid/grid2d.h"
#include "cogmap/grid/range_fusion.h"
#include "cogmap/io/image.h"

namespace cogmap::draw {

// How grids become pictures. Images put world y up (row 0 = the grid's top row).
struct GridRenderOptions {
  int scale = 1;                    // pixels per cell side
  float occupied_threshold = 7.0f;  // epsilon (table 4.1): darker than this = black
  float min_value = -3.0f;          // MHIMM's lower clamp: whitest
  float robot_path = -100.0f;       // MHIMM's path marker: red
};

// The MHIMM colours: unknown (0) grey, empty (< 0) white, occupied (> epsilon)
// black, robot path red; values between are shaded (0 -> min_value fades grey
// to white, 0 -> epsilon fades grey to dark grey). HIMM values render the same
// way (HIMM's 0 is "unknown or empty": grey).
constexpr io::Rgb kUnknownRgb{160, 160, 160};
constexpr io::Rgb kEmptyRgb{255, 255, 255};
constexpr io::Rgb kOccupiedRgb{0, 0, 0};
constexpr io::Rgb kRobotPathRgb{220, 0, 0};
io::RgbImage RenderCertainty(const grid::Grid2D<float>& values, const GridRenderOptions& options = {});

// Probability of occupied as grey (0 white, 1 black); untouched cells grey
// (kUnknownRgb) and robot path cells red, from 'classes'.
io::RgbImage RenderProbability(const grid::Grid2D<float>& occupancy,
                           const grid::Grid2D<grid::CellClass>& classes, int scale = 1);

// Picks the picture that suits the rule: certainty colours for HIMM / MHIMM,
// probability grey for Bayes / Dempster-Shafer.
io::RgbImage RenderFusion(const grid::RangeFusion& fusion, const GridRenderOptions& options = {});

// The grid on a page: its cells scaled to the pixel budget (or to
// options.px_per_m), without smoothing; when a pixel holds several cells it
// shows the darkest of them (the robot path over everything), so thin walls
// stay visible. Title, scale bar in metres, legend, north arrow.
Drawing DrawGrid(const grid::RangeFusion& fusion, const PictureOptions& options = {},
                 const GridRenderOptions& render = {});

// A raster made smaller by 'k' (< 1): each output pixel the strongest of the
// pixels it covers (pure robot-path red first, then the darkest).
io::RgbImage ShrinkKeepingDarkest(const io::RgbImage& image, double k);

}  // namespace cogmap::draw
