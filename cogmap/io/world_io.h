#pragma once
#include <string>
#include <vector>

#include "cogmap/core/floor_plan.h"
#include "cogmap/io/image.h"

namespace cogmap::io {

// ARIA/MobileSim "2D-Map" files (mm, degrees CCW) as FloorPlans (metres,
// radians). Understood: LINES (walls), LineMinPos/LineMaxPos, Cairn RobotHome,
// Cairn GoalWithHeading / Goal named wpNN (the route, in numeric order of NN),
// and this project's Cairn Room / Doorway with "x1 y1 x2 y2" after the name
// (a Room rotated by its theta about the origin, as ARIA rotates sectors, is
// read as the axis-aligned box around the rotated rectangle).
// Tolerated and ignored: the header keywords of ARIA (MinPos, MaxPos,
// NumPoints, Resolution, MapInfo, ObjectInfo, ...), DATA points (counted in a
// warning: they are laser scan points, not walls), other Cairn types
// (ForbiddenLine, ForbiddenArea, Dock, ... : one warning each, naming the
// object). Malformed numbers anywhere -> InputError "path:line: problem".
struct WorldReadResult {
  FloorPlan plan;
  std::vector<std::string> warnings;  // "path:line: ..." one per ignored object
};
WorldReadResult ReadAriaMap(const std::string& path);
WorldReadResult ParseAriaMap(const std::string& text, const std::string& path_for_messages);

// Writes 'plan' as a 2D-Map (integer mm; headings in degrees with 0.1 degree
// precision), atomically. Route waypoints are written as GoalWithHeading in
// order; names that are not wpNN are replaced by wp01, wp02, ... so that the
// order survives a round trip.
void WriteAriaMap(const std::string& path, const FloorPlan& plan);
std::string FormatAriaMap(const FloorPlan& plan);

// Bitmap worlds: pixels darker than occupied_below are walls; by default
// every pixel that is not white. The room-segmentation maps draw free floor
// white, walls light grey (Freiburg52: 211, with no dark outline) and the
// outside mid grey (180); taking only dark pixels (below 128) as walls let
// the simulated robot, and its sensors, pass through Freiburg52's walls. Each
// run of pixel edges between an occupied and a free pixel along a row or a
// column becomes one wall segment, so the walls trace the outline of every
// occupied blob exactly. Row 0 is the top of the image; the world origin is
// the lower-left corner. The RobotHome is placed at the free (grey >=
// free_above) pixel farthest from any occupied pixel.
struct BitmapWorldOptions {
  double m_per_pixel = 0.05;  // the room-segmentation maps' resolution
  int occupied_below = 250;
  int free_above = 250;
};
FloorPlan FloorPlanFromOccupancy(const GreyImage& image, const BitmapWorldOptions& options = {});

// Ground-truth rooms from a room-segmentation image (the benchmark's
// *_gt_segmentation.png: the building's map with its doors closed): a room is
// a 4-connected region of pixels of one colour that is white or not grey
// (r, g, b not all equal: a benchmark that fills each room with its own
// colour); grey and black pixels (walls, the outside, unlabelled floor) are
// no room. Regions smaller than min_room_m2 are dropped (a few pixels left
// between a door line and a jamb). Pixels as in a bitmap world (row 0 on
// top, the lower-left corner at the origin, m_per_pixel); rooms named
// "room 1", "room 2", ... in the order of their first pixel from the top
// left. InputError naming the file for an unreadable image or one without
// a room.
RoomLabels RoomLabelsFromSegmentation(const RgbImage& image, double m_per_pixel, double min_room_m2 = 0.25);
RoomLabels ReadRoomSegmentation(const std::string& path, const BitmapWorldOptions& bitmap = {});

// A ROS map_server map as a world: the YAML (image, resolution, origin,
// negate, occupied_thresh, free_thresh, mode; grid_io.h) and its PGM or PNG.
// Each pixel is classified as map_server does (occupied: 100, free: 0, else
// unknown); occupied pixels become walls exactly as in a bitmap world
// (FloorPlanFromOccupancy at the map's resolution), placed in the map frame by
// the YAML's origin [x, y, yaw]. The RobotHome is the free pixel farthest from
// any wall (unknown pixels are never home). InputError naming the YAML or the
// image (file:line for YAML problems).
WorldReadResult ReadMapServerWorld(const std::string& yaml_path);

// A world by file name: *.png -> bitmap world, *.yaml / *.yml -> ROS map,
// anything else -> 2D-Map.
WorldReadResult ReadWorld(const std::string& path, const BitmapWorldOptions& bitmap = {});

}  // namespace cogmap::io
