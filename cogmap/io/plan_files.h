#pragma once
// The floor plan (cogmap/plan/plan.h) as the files people open: a GeoPackage
// for GIS tools, GeoJSON (map frame metres, or WGS 84 with a geo anchor), a
// room-level route graph for the Nav2 Route Server, an ARIA 2D-Map and the
// ROS map_server pair. docs/map-files.md describes each file.
#include <optional>
#include <ostream>
#include <string>
#include <vector>

#include "cogmap/grid/grid2d.h"
#include "cogmap/grid/range_fusion.h"
#include "cogmap/io/gpkg.h"
#include "cogmap/plan/plan.h"

namespace cogmap::io {

// Where the map frame lies on the Earth. The map is taken as the plane
// tangent to the WGS 84 ellipsoid at the anchor (east-north-up), so a map
// point (x, y) sits x cos/sin-rotated metres east and north of the anchor.
struct GeoAnchor {
  double lat_deg = 0.0;       // WGS 84 latitude of the map origin (0, 0), degrees north
  double lon_deg = 0.0;       // WGS 84 longitude of the map origin, degrees east
  double heading_deg = 90.0;  // bearing of the map's +x axis, degrees clockwise from true north
                              // (90: +x points east and +y north)
};

// Parses "LAT,LON,HEADING_DEG" (as in `--geo-anchor 48.8584,2.2945,90`):
// three decimal numbers, latitude in [-90, 90] (not a pole: |lat| < 90),
// longitude in [-180, 180], any finite heading. Throws InputError
// "--geo-anchor 'text': problem" naming the field that is wrong.
GeoAnchor ParseGeoAnchor(const std::string& text);

// WGS 84 (longitude, latitude) in degrees of the map point 'map_m'.
Vec2 LonLatOf(const GeoAnchor& anchor, const Vec2& map_m);

struct PlanFileOptions {
  std::optional<GeoAnchor> geo_anchor;  // map.geojson in WGS 84 lon/lat when set, else map frame metres
  // map.pgm: the cell side. 0 picks the finest cell of at least
  // raster_min_cell_m whose image stays within raster_max_pixels.
  double raster_cell_m = 0.0;
  double raster_min_cell_m = 0.05;
  double raster_max_pixels = 16e6;  // 16 Mpx: a 16 MB PGM
  double raster_margin_m = 0.5;     // unknown border around the plan
  // Which files to write.
  bool gpkg = true;         // map.gpkg
  bool geojson = true;      // map.geojson
  bool route_graph = true;  // route_graph.geojson
  bool aria = true;         // map.map
  bool map_server = true;   // map.pgm + map.yaml
  // Files written at once (each on a thread of its own, up to this many).
  int threads = 1;
};

// Writes the files chosen in 'options' into 'dir' (which must exist), each
// one atomically (a temporary file renamed into place), up to
// options.threads at once. Returns the paths written, in the order above.
// Throws InputError naming a file that cannot be written.
std::vector<std::string> WritePlanFiles(const std::string& dir, const plan::Plan& plan,
                                        const PlanFileOptions& options = {});

// ---- The pieces (for tests and for callers that want one file).

// The GeoPackage layers: rooms (POLYGON: name, area_m2, corridor, ...), walls
// (LINESTRING: weight, squared, ...), doors (LINESTRING jamb to jamb: width_m,
// room ids and names), room_graph (LINESTRING room label -> door -> room
// label), robot_home (POINT, when the plan has a home). Map frame metres.
std::vector<GpkgLayer> PlanGpkgLayers(const plan::Plan& plan);

// map.geojson: one FeatureCollection; each feature's "layer" property says
// rooms / walls / doors / room_graph / robot_home. Without an anchor the
// coordinates are map frame metres (rounded to 1 mm) and the collection
// carries a legacy "crs" member with MapFrameWkt(), so GDAL and QGIS read
// metres, not degrees; with one, WGS 84 longitude/latitude (RFC 7946, 1e-8
// degrees). Lines have at least two distinct points; a door whose jambs
// coincide is a Point.
std::string FormatPlanGeoJson(const plan::Plan& plan, const std::optional<GeoAnchor>& anchor = std::nullopt);
// The same text written to 'out' feature by feature (WritePlanFiles: no
// whole document in memory).
void WritePlanGeoJson(std::ostream& out, const plan::Plan& plan, const std::optional<GeoAnchor>& anchor = std::nullopt);

// route_graph.geojson for the Nav2 Route Server (GeoJsonGraphFileLoader):
// Point nodes with "id" (unsigned) and "frame": "map" at each room's label
// point and each door's centre; directed MultiLineString edges with "id",
// "startid", "endid", both ways, room -> door -> room through every doorway.
// Map frame metres (the frame the robot navigates in), with or without an
// anchor. Node and edge ids share one numbering, as Nav2 expects.
std::string FormatRouteGraphGeoJson(const plan::Plan& plan);
void WriteRouteGraphGeoJson(std::ostream& out, const plan::Plan& plan);  // the same, to a stream

// map.map: an ARIA 2D-Map: RobotHome, each room as a sector cairn "Room"
// (ARIA sectors are rectangles, rotated by theta about the map origin: the
// rectangle bounding the room polygon along DominantWallDirection, in whole
// degrees, with the room's name), each door as a boundary cairn "Doorway"
// (jamb to jamb), every wall edge in LINES. Integer millimetres and degrees.
std::string FormatPlanAriaMap(const plan::Plan& plan);
void WritePlanAriaMap(std::ostream& out, const plan::Plan& plan);  // the same, to a stream

// The building's main wall direction in (-pi/4, pi/4]: the length-weighted
// mean of the wall segments' directions modulo a right angle (0 without walls).
double DominantWallDirection(const plan::Plan& plan);

// The map_server cell for 'plan' under 'options' (see PlanFileOptions).
double PlanRasterCell(const plan::Plan& plan, const PlanFileOptions& options);

// The free space the plan implies: unknown everywhere, room polygons free,
// a band through each door free (the jambs stay walls), walls occupied (every
// cell within 0.71 cells of a wall, so a wall is a 4-connected barrier that
// no 8-connected path slips through). Origin: the plan's lower-left corner
// minus the margin.
grid::Grid2D<grid::CellClass> RasterizePlan(const plan::Plan& plan, double cell_m, double margin_m);

}  // namespace cogmap::io
