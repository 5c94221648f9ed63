#pragma once
// The master map (§3.1) as a picture: every ASR's walls placed in the map
// frame, the robot's path, the exits, the room graph and the room labels, on
// a page with a title, scale bar, legend and north arrow.
#include <string>
#include <vector>

#include "cogmap/draw/drawing.h"
#include "cogmap/draw/layout.h"
#include "cogmap/io/map_files.h"

namespace cogmap::draw {

struct MapPictureOptions {
  PictureOptions picture{.title = "Master map"};
  bool path = true;    // the robot's path
  bool graph = true;   // the room graph: label -> exit -> label
  bool labels = true;  // "A<id>" at each room
};

// A picture and how it was laid out (for tests and callers that add to it).
struct MapPicture {
  Drawing drawing{1, 1};
  double px_per_m = 0.0;
  ScaleBar scale_bar;
  Box map_box;            // the map's box on the page
  Vec2 origin_px{0, 0};   // page pixel of the world point (0, 0)
  int labels_placed = 0;
  int labels_dropped = 0;
  Vec2 Px(const Vec2& world_m) const { return origin_px + Vec2(world_m.x(), -world_m.y()) * px_per_m; }
};

// Colour of an ASR's walls (cycling palette).
Colour RoomColour(int asr_id);

MapPicture DrawMasterMap(const io::MasterMap& map, const MapPictureOptions& options = {});

// Two maps side by side (before | after correction), each under its own title,
// each in half the pixel budget's width so that the pair fits the budget.
Drawing DrawSideBySide(const io::MasterMap& left, const std::string& left_title, const io::MasterMap& right,
                       const std::string& right_title, const MapPictureOptions& options = {});

// Writes the master map's pictures into 'dir' (each atomically): map.svg when
// 'svg', map.png when 'png', map.pdf when 'pdf'. Returns the paths written.
std::vector<std::string> WriteMasterMapPictures(const std::string& dir, const io::MasterMap& map, bool svg, bool png,
                                                bool pdf = false, const MapPictureOptions& options = {});

}  // namespace cogmap::draw
