#pragma once
#include <string>
#include <map>
#include <vector>

#include "cogmap/asr/asr.h"
#include "cogmap/core/floor_plan.h"
#include "cogmap/grid/grid2d.h"
#include "cogmap/grid/range_fusion.h"

namespace cogmap::io {

// The master map (§3.1): every ASR placed by its world pose. Everything here
// is in the map frame: metres, x east, y north, the raw odometry frame after
// heading correction (or before it, with corrected = false).
struct MasterRoom {
  int id = -1;
  std::vector<Polyline> walls;  // map frame
  std::vector<Vec2> path;       // robot positions, map frame
  Vec2 label_m{0, 0};           // where the room's label goes (mean of its path)
};
struct MasterExit {
  int from_asr = -1;
  int to_asr = -1;  // -1: the robot never went through
  Vec2 center_m{0, 0};
  double width_m = 0.0;
};
struct MasterMap {
  std::vector<MasterRoom> rooms;
  std::vector<MasterExit> exits;  // each exit once
  Vec2 min{0, 0}, max{0, 0};      // bounds of walls, paths and exits
};

// Places the ASRs (by world_from_local_corrected, or _raw when !corrected).
// Exit centres are recorded in the raw frame; they follow the correction of
// the ASR they lead out of. 'placed_paths' (corrected only; optional): each
// ASR's path as the correction placed it, the drift inside the ASR removed
// (asr::Placement::corrected_path), drawn instead of its raw path moved as
// a whole (which leans with that drift); each entry used is freed.
MasterMap BuildMasterMap(const std::vector<asr::Asr>& asrs, bool corrected = true,
                         std::map<int, std::vector<Pose2>>* placed_paths = nullptr);

// The master map's pictures (map.svg, map.png) are drawn by cogmap/draw
// (draw::DrawMasterMap, draw::WriteMasterMapPictures).
struct MasterMapStyle {
  double margin_m = 1.0;  // around the map in the map_server raster
};

// The walls rasterised for ROS map_server: wall cells occupied, cells inside an
// ASR's footprint (the convex hull of its walls and path) free, the rest
// unknown. The grid's origin is the map's lower-left corner minus the margin.
grid::Grid2D<grid::CellClass> RasterizeMap(const MasterMap& map, double cell_m = 0.05,
                                           double margin_m = 1.0);

// GeoJSON FeatureCollection in the map frame (metres, not WGS84 degrees; the
// collection says so in a "crs_note" member and in a legacy "crs" member with
// the engineering frame that GDAL reads): LineString walls (>= 2 distinct
// points; degenerate ones are left out) with "asr",
// Point exits with "from", "to", "width_m", Point room labels with "asr" and
// Polygon footprints (convex hull) with "asr", and the path as one LineString
// per ASR with "kind": "path".
std::string FormatMapGeoJson(const MasterMap& map);

// The walls as a FloorPlan (for ARIA's 2D-Map LINES): one segment per
// polyline edge; route/home left empty.
FloorPlan MapFloorPlan(const MasterMap& map);

// Which of the master map's files to write (`cogmap map --outputs`).
struct MasterMapOutputs {
  bool svg = true;      // map.svg (written by draw::WriteMasterMapPictures)
  bool png = true;      // map.png (written by draw::WriteMasterMapPictures)
  bool pgm = true;      // map.pgm + map.yaml (ROS map_server)
  bool geojson = true;  // map.geojson
  bool aria = true;     // map.map (ARIA 2D-Map)
};

// Writes map.pgm + map.yaml, map.geojson and map.map into 'dir' (each file
// atomically), as 'outputs' asks (its svg and png are for the pictures, which
// cogmap/draw writes). Returns the paths written.
std::vector<std::string> WriteMasterMapFiles(const std::string& dir, const MasterMap& map,
                                             const MasterMapStyle& style = {},
                                             double raster_cell_m = 0.05, const MasterMapOutputs& outputs = {});

}  // namespace cogmap::io
