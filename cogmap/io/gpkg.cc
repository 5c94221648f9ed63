#include "cogmap/io/gpkg.h"

#include <sqlite3.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cctype>
#include <cstring>
#include <filesystem>
#include <limits>

#include "cogmap/core/error.h"

namespace cogmap::io {
namespace {

constexpr int kGpkgApplicationId = 0x47504B47;  // "GPKG"
constexpr int kGpkgUserVersion = 10300;          // GeoPackage 1.3.0

// The EPSG:4326 definition every GeoPackage carries (spec requirement 11).
constexpr const char* kWgs84Wkt =
    "GEOGCS[\"WGS 84\",DATUM[\"WGS_1984\",SPHEROID[\"WGS 84\",6378137,298.257223563,"
    "AUTHORITY[\"EPSG\",\"7030\"]],AUTHORITY[\"EPSG\",\"6326\"]],PRIMEM[\"Greenwich\",0,"
    "AUTHORITY[\"EPSG\",\"8901\"]],UNIT[\"degree\",0.0174532925199433,AUTHORITY[\"EPSG\",\"9122\"]],"
    "AXIS[\"Latitude\",NORTH],AXIS[\"Longitude\",EAST],AUTHORITY[\"EPSG\",\"4326\"]]";

void PutU32(std::string& out, uint32_t v) {
  for (int i = 0; i < 4; ++i) out.push_back(static_cast<char>((v >> (8 * i)) & 0xff));
}
void PutF64(std::string& out, double v) {
  uint64_t bits;
  std::memcpy(&bits, &v, sizeof bits);
  for (int i = 0; i < 8; ++i) out.push_back(static_cast<char>((bits >> (8 * i)) & 0xff));
}

bool IsIdentifier(const std::string& s) {
  if (s.empty() || std::isdigit(static_cast<unsigned char>(s[0]))) return false;
  return std::all_of(s.begin(), s.end(), [](char c) {
    return (c >= 'a' && c <= 'z') || (c >= '0' && c <= '9') || c == '_';
  });
}

const char* SqlType(GpkgFieldType t) {
  switch (t) {
    case GpkgFieldType::kInteger: return "INTEGER";
    case GpkgFieldType::kReal: return "REAL";
    case GpkgFieldType::kText: return "TEXT";
    case GpkgFieldType::kBoolean: return "BOOLEAN";
  }
  return "TEXT";
}

// One SQLite connection on the temporary file; every failure becomes an
// InputError naming the GeoPackage being written.
class Db {
 public:
  Db(const std::string& file, const std::string& name_for_messages) : name_(name_for_messages) {
    if (sqlite3_open_v2(file.c_str(), &db_, SQLITE_OPEN_READWRITE | SQLITE_OPEN_CREATE, nullptr) != SQLITE_OK) {
      const std::string msg = db_ ? sqlite3_errmsg(db_) : "out of memory";
      sqlite3_close(db_);
      db_ = nullptr;
      throw InputError(name_, 0, "cannot create the GeoPackage: " + msg);
    }
  }
  ~Db() { sqlite3_close(db_); }
  Db(const Db&) = delete;
  Db& operator=(const Db&) = delete;

  void Exec(const std::string& sql) {
    char* err = nullptr;
    if (sqlite3_exec(db_, sql.c_str(), nullptr, nullptr, &err) != SQLITE_OK) {
      const std::string msg = err ? err : sqlite3_errmsg(db_);
      sqlite3_free(err);
      throw InputError(name_, 0, "SQLite: " + msg);
    }
  }
  sqlite3_stmt* Prepare(const std::string& sql) {
    sqlite3_stmt* s = nullptr;
    if (sqlite3_prepare_v2(db_, sql.c_str(), -1, &s, nullptr) != SQLITE_OK)
      throw InputError(name_, 0, std::string("SQLite: ") + sqlite3_errmsg(db_));
    return s;
  }
  void Step(sqlite3_stmt* s) {
    const int rc = sqlite3_step(s);
    if (rc != SQLITE_DONE) {
      const std::string msg = sqlite3_errmsg(db_);
      throw InputError(name_, 0, "SQLite: " + msg);
    }
    sqlite3_reset(s);
    sqlite3_clear_bindings(s);
  }
  void Close() {
    if (sqlite3_close(db_) != SQLITE_OK) throw InputError(name_, 0, std::string("SQLite: ") + sqlite3_errmsg(db_));
    db_ = nullptr;
  }

 private:
  sqlite3* db_ = nullptr;
  std::string name_;
};

struct Finalizer {
  sqlite3_stmt* s;
  ~Finalizer() { sqlite3_finalize(s); }
};

void WriteLayers(Db& db, const std::string& path, const GpkgSrs& srs, const std::vector<GpkgLayer>& layers) {
  db.Exec("PRAGMA journal_mode = OFF; PRAGMA synchronous = OFF;");
  db.Exec("PRAGMA application_id = " + std::to_string(kGpkgApplicationId) + ";");
  db.Exec("PRAGMA user_version = " + std::to_string(kGpkgUserVersion) + ";");
  db.Exec("BEGIN;");
  db.Exec(
      "CREATE TABLE gpkg_spatial_ref_sys ("
      " srs_name TEXT NOT NULL, srs_id INTEGER NOT NULL PRIMARY KEY, organization TEXT NOT NULL,"
      " organization_coordsys_id INTEGER NOT NULL, definition TEXT NOT NULL, description TEXT);"
      "CREATE TABLE gpkg_contents ("
      " table_name TEXT NOT NULL PRIMARY KEY, data_type TEXT NOT NULL, identifier TEXT UNIQUE,"
      " description TEXT DEFAULT '',"
      " last_change DATETIME NOT NULL DEFAULT (strftime('%Y-%m-%dT%H:%M:%fZ','now')),"
      " min_x DOUBLE, min_y DOUBLE, max_x DOUBLE, max_y DOUBLE, srs_id INTEGER,"
      " CONSTRAINT fk_gc_r_srs_id FOREIGN KEY (srs_id) REFERENCES gpkg_spatial_ref_sys(srs_id));"
      "CREATE TABLE gpkg_geometry_columns ("
      " table_name TEXT NOT NULL, column_name TEXT NOT NULL, geometry_type_name TEXT NOT NULL,"
      " srs_id INTEGER NOT NULL, z TINYINT NOT NULL, m TINYINT NOT NULL,"
      " CONSTRAINT pk_geom_cols PRIMARY KEY (table_name, column_name),"
      " CONSTRAINT uk_gc_table_name UNIQUE (table_name),"
      " CONSTRAINT fk_gc_tn FOREIGN KEY (table_name) REFERENCES gpkg_contents(table_name),"
      " CONSTRAINT fk_gc_srs FOREIGN KEY (srs_id) REFERENCES gpkg_spatial_ref_sys(srs_id));");
  {
    sqlite3_stmt* s = db.Prepare(
        "INSERT INTO gpkg_spatial_ref_sys (srs_name, srs_id, organization, organization_coordsys_id, definition,"
        " description) VALUES (?, ?, ?, ?, ?, ?);");
    Finalizer f{s};
    auto row = [&](const GpkgSrs& r) {
      sqlite3_bind_text(s, 1, r.name.c_str(), -1, SQLITE_TRANSIENT);
      sqlite3_bind_int(s, 2, r.srs_id);
      sqlite3_bind_text(s, 3, r.organization.c_str(), -1, SQLITE_TRANSIENT);
      sqlite3_bind_int(s, 4, r.organization_coordsys_id);
      sqlite3_bind_text(s, 5, r.definition.c_str(), -1, SQLITE_TRANSIENT);
      sqlite3_bind_text(s, 6, r.description.c_str(), -1, SQLITE_TRANSIENT);
      db.Step(s);
    };
    // The three rows every GeoPackage has (spec requirements 11-13).
    const GpkgSrs required[] = {
        {4326, "WGS 84 geodetic", "EPSG", 4326, kWgs84Wkt,
         "longitude/latitude coordinates in decimal degrees on the WGS 84 spheroid"},
        {-1, "Undefined cartesian SRS", "NONE", -1, "undefined", "undefined cartesian coordinate reference system"},
        {0, "Undefined geographic SRS", "NONE", 0, "undefined", "undefined geographic coordinate reference system"}};
    for (const auto& r : required)
      if (r.srs_id != srs.srs_id) row(r);
    row(srs);
  }
  for (const auto& layer : layers) {
    if (!IsIdentifier(layer.name))
      throw InputError(path, 0, "GeoPackage layer name '" + layer.name + "' is not a plain identifier");
    std::string create = "CREATE TABLE \"" + layer.name + "\" (fid INTEGER PRIMARY KEY AUTOINCREMENT NOT NULL, geom " +
                         GpkgGeometryTypeName(layer.type);
    std::string insert = "INSERT INTO \"" + layer.name + "\" (geom";
    std::string marks = "?";
    for (const auto& f : layer.fields) {
      if (!IsIdentifier(f.name) || f.name == "fid" || f.name == "geom")
        throw InputError(path, 0, "GeoPackage field name '" + f.name + "' of layer '" + layer.name +
                                      "' is not a plain identifier (or is fid/geom)");
      create += ", \"" + f.name + "\" " + SqlType(f.type);
      insert += ", \"" + f.name + "\"";
      marks += ", ?";
    }
    db.Exec(create + ");");
    sqlite3_stmt* s = db.Prepare(insert + ") VALUES (" + marks + ");");
    Finalizer fin{s};
    const double inf = std::numeric_limits<double>::infinity();
    Vec2 lo(inf, inf), hi(-inf, -inf);
    for (size_t i = 0; i < layer.features.size(); ++i) {
      const auto& feature = layer.features[i];
      const std::string where = "layer '" + layer.name + "' feature " + std::to_string(i + 1);
      if (feature.values.size() != layer.fields.size())
        throw InputError(path, 0, where + ": " + std::to_string(feature.values.size()) + " values for " +
                                      std::to_string(layer.fields.size()) + " fields");
      if (!feature.geometry.points.empty() && feature.geometry.type != layer.type)
        throw InputError(path, 0, where + ": a " + GpkgGeometryTypeName(feature.geometry.type) + " in a " +
                                      GpkgGeometryTypeName(layer.type) + " layer");
      if (feature.geometry.points.empty()) {
        sqlite3_bind_null(s, 1);
      } else {
        const std::string blob = EncodeGpkgGeometry(feature.geometry, srs.srs_id);
        sqlite3_bind_blob(s, 1, blob.data(), static_cast<int>(blob.size()), SQLITE_TRANSIENT);
        for (const Vec2& p : feature.geometry.points) {
          lo = lo.cwiseMin(p);
          hi = hi.cwiseMax(p);
        }
      }
      for (size_t k = 0; k < feature.values.size(); ++k) {
        const int col = static_cast<int>(k) + 2;
        const GpkgValue& v = feature.values[k];
        if (std::holds_alternative<int64_t>(v)) sqlite3_bind_int64(s, col, std::get<int64_t>(v));
        else if (std::holds_alternative<double>(v)) sqlite3_bind_double(s, col, std::get<double>(v));
        else if (std::holds_alternative<std::string>(v))
          sqlite3_bind_text(s, col, std::get<std::string>(v).c_str(), -1, SQLITE_TRANSIENT);
        else if (std::holds_alternative<bool>(v)) sqlite3_bind_int(s, col, std::get<bool>(v) ? 1 : 0);
        else sqlite3_bind_null(s, col);
      }
      db.Step(s);
    }
    sqlite3_stmt* c = db.Prepare(
        "INSERT INTO gpkg_contents (table_name, data_type, identifier, description, min_x, min_y, max_x, max_y,"
        " srs_id) VALUES (?, 'features', ?, ?, ?, ?, ?, ?, ?);");
    Finalizer cf{c};
    sqlite3_bind_text(c, 1, layer.name.c_str(), -1, SQLITE_TRANSIENT);
    sqlite3_bind_text(c, 2, layer.name.c_str(), -1, SQLITE_TRANSIENT);
    sqlite3_bind_text(c, 3, layer.description.c_str(), -1, SQLITE_TRANSIENT);
    if (lo.x() <= hi.x()) {
      sqlite3_bind_double(c, 4, lo.x());
      sqlite3_bind_double(c, 5, lo.y());
      sqlite3_bind_double(c, 6, hi.x());
      sqlite3_bind_double(c, 7, hi.y());
    }
    sqlite3_bind_int(c, 8, srs.srs_id);
    db.Step(c);
    sqlite3_stmt* g = db.Prepare(
        "INSERT INTO gpkg_geometry_columns (table_name, column_name, geometry_type_name, srs_id, z, m)"
        " VALUES (?, 'geom', ?, ?, 0, 0);");
    Finalizer gf{g};
    sqlite3_bind_text(g, 1, layer.name.c_str(), -1, SQLITE_TRANSIENT);
    sqlite3_bind_text(g, 2, GpkgGeometryTypeName(layer.type), -1, SQLITE_STATIC);
    sqlite3_bind_int(g, 3, srs.srs_id);
    db.Step(g);
  }
  db.Exec("COMMIT;");
}

}  // namespace

std::string MapFrameWkt() {
  return "LOCAL_CS[\"cogmap map frame\",LOCAL_DATUM[\"cogmap map frame (the robot's odometry frame at the start)\","
         "32767],UNIT[\"metre\",1,AUTHORITY[\"EPSG\",\"9001\"]],AXIS[\"x\",EAST],AXIS[\"y\",NORTH]]";
}

GpkgSrs MapFrameSrs() {
  return {100000, "cogmap map frame (metres)", "NONE", 100000, MapFrameWkt(),
          "engineering coordinate system: metres in cogmap's map frame, x east, y north of the map; not placed on "
          "the Earth"};
}

const char* GpkgGeometryTypeName(GpkgGeometryType type) {
  switch (type) {
    case GpkgGeometryType::kPoint: return "POINT";
    case GpkgGeometryType::kLineString: return "LINESTRING";
    case GpkgGeometryType::kPolygon: return "POLYGON";
  }
  return "GEOMETRY";
}

std::string EncodeGpkgGeometry(const GpkgGeometry& g, int srs_id) {
  std::string out = "GP";
  out.push_back(0);  // version 1 of the binary format
  const bool point = g.type == GpkgGeometryType::kPoint;
  // Flags: bit 0 little endian; bits 1-3 envelope (1: [minx, maxx, miny, maxy]);
  // points carry no envelope (it would repeat the point).
  out.push_back(static_cast<char>(point ? 0x01 : 0x03));
  PutU32(out, static_cast<uint32_t>(srs_id));
  if (!point) {
    Vec2 lo = g.points.front(), hi = g.points.front();
    for (const Vec2& p : g.points) {
      lo = lo.cwiseMin(p);
      hi = hi.cwiseMax(p);
    }
    PutF64(out, lo.x());
    PutF64(out, hi.x());
    PutF64(out, lo.y());
    PutF64(out, hi.y());
  }
  out.push_back(1);  // WKB little endian
  switch (g.type) {
    case GpkgGeometryType::kPoint:
      PutU32(out, 1);
      PutF64(out, g.points.front().x());
      PutF64(out, g.points.front().y());
      break;
    case GpkgGeometryType::kLineString:
      PutU32(out, 2);
      PutU32(out, static_cast<uint32_t>(g.points.size()));
      for (const Vec2& p : g.points) {
        PutF64(out, p.x());
        PutF64(out, p.y());
      }
      break;
    case GpkgGeometryType::kPolygon:
      PutU32(out, 3);
      PutU32(out, 1);  // one ring
      PutU32(out, static_cast<uint32_t>(g.points.size() + 1));
      for (const Vec2& p : g.points) {
        PutF64(out, p.x());
        PutF64(out, p.y());
      }
      PutF64(out, g.points.front().x());
      PutF64(out, g.points.front().y());
      break;
  }
  return out;
}

void WriteGeoPackage(const std::string& path, const GpkgSrs& srs, const std::vector<GpkgLayer>& layers) {
  const std::string tmp = path + ".tmp-" + std::to_string(::getpid());
  std::error_code ec;
  std::filesystem::remove(tmp, ec);
  try {
    Db db(tmp, path);
    WriteLayers(db, path, srs, layers);
    db.Close();
    std::filesystem::rename(tmp, path, ec);
    if (ec) throw InputError(path, 0, "cannot rename into place: " + ec.message());
  } catch (...) {
    std::filesystem::remove(tmp, ec);
    throw;
  }
}

}  // namespace cogmap::io
