#pragma once
// A small OGC GeoPackage (1.3) writer through SQLite: the required metadata
// tables (gpkg_spatial_ref_sys, gpkg_contents, gpkg_geometry_columns) and one
// feature table per layer, geometries as GeoPackage binary (header with an xy
// envelope, then little-endian ISO WKB). Points, line strings and
// single-ring polygons in 2-D: what the floor plan needs, nothing more.
#include <cstdint>
#include <string>
#include <variant>
#include <vector>

#include "cogmap/core/pose2.h"

namespace cogmap::io {

// A spatial reference system row (gpkg_spatial_ref_sys).
struct GpkgSrs {
  int srs_id = 0;
  std::string name;
  std::string organization;       // "EPSG", or "NONE" for one defined here only
  int organization_coordsys_id = 0;
  std::string definition;         // WKT (OGC 01-009, as the 1.3 spec asks)
  std::string description;
};

// The plan's engineering frame: a local Cartesian system in metres (x east,
// y north of the map frame), no datum on the Earth. srs_id 100000,
// organization "NONE".
GpkgSrs MapFrameSrs();
// The WKT of MapFrameSrs() (also written as the GeoJSON "crs" of the files in
// map-frame metres).
std::string MapFrameWkt();

enum class GpkgGeometryType { kPoint, kLineString, kPolygon };
const char* GpkgGeometryTypeName(GpkgGeometryType type);  // "POINT", ...

// A 2-D geometry: a point (1 vertex), a line string (>= 2 vertices) or a
// polygon (one exterior ring of >= 3 vertices, first not repeated: the
// encoder closes it). Empty 'points': a NULL geometry.
struct GpkgGeometry {
  GpkgGeometryType type = GpkgGeometryType::kPoint;
  std::vector<Vec2> points;
};

enum class GpkgFieldType { kInteger, kReal, kText, kBoolean };
struct GpkgField {
  std::string name;
  GpkgFieldType type = GpkgFieldType::kReal;
};
// One attribute value: monostate is NULL.
using GpkgValue = std::variant<std::monostate, int64_t, double, std::string, bool>;

struct GpkgFeature {
  GpkgGeometry geometry;
  std::vector<GpkgValue> values;  // one per field, in field order
};

struct GpkgLayer {
  std::string name;          // table name: [a-z_][a-z0-9_]*
  std::string description;
  GpkgGeometryType type = GpkgGeometryType::kLineString;
  std::vector<GpkgField> fields;
  std::vector<GpkgFeature> features;
};

// The GeoPackage binary form of one geometry: "GP", version 0, flags (little
// endian, xy envelope), srs_id, envelope [minx, maxx, miny, maxy], WKB.
std::string EncodeGpkgGeometry(const GpkgGeometry& geometry, int srs_id);

// Writes a new GeoPackage at 'path' with every layer in 'srs', all or
// nothing: SQLite writes a temporary file beside 'path', which is renamed over
// it at the end. Throws InputError naming 'path' (a SQLite error, a layer or
// field name that is not a plain identifier, a feature with the wrong number
// of values or a geometry of the wrong type).
void WriteGeoPackage(const std::string& path, const GpkgSrs& srs, const std::vector<GpkgLayer>& layers);

}  // namespace cogmap::io
