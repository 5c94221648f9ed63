#include "cogmap/io/polyline_io.h"

#include <cmath>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "cogmap/core/error.h"
#include "cogmap/io/atomic_file.h"

namespace cogmap::io {
namespace {

std::string ReadWhole(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path, 0, "cannot open");
  std::ostringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

nlohmann::json LinesJson(const std::vector<Polyline>& lines) {
  nlohmann::json out = nlohmann::json::array();
  for (const auto& l : lines) {
    nlohmann::json pl = nlohmann::json::array();
    for (const auto& v : l)
      pl.push_back({std::round(v.x() * 1e4) / 1e4, std::round(v.y() * 1e4) / 1e4});
    out.push_back(std::move(pl));
  }
  return out;
}

std::vector<Polyline> LinesFromJson(const nlohmann::json& j, const std::string& source) {
  if (!j.is_array()) throw InputError(source, 0, "polylines: expected an array of polylines");
  std::vector<Polyline> lines;
  for (size_t i = 0; i < j.size(); ++i) {
    const auto& pl = j[i];
    if (!pl.is_array()) throw InputError(source, 0, "polyline " + std::to_string(i) + ": expected an array");
    Polyline line;
    for (size_t k = 0; k < pl.size(); ++k) {
      const auto& v = pl[k];
      if (!v.is_array() || v.size() != 2 || !v[0].is_number() || !v[1].is_number())
        throw InputError(source, 0,
                         "polyline " + std::to_string(i) + " vertex " + std::to_string(k) + ": expected [x, y]");
      line.push_back(Vec2(v[0].get<double>(), v[1].get<double>()));
    }
    lines.push_back(std::move(line));
  }
  return lines;
}

}  // namespace

void WritePolylinesBinary(const std::string& path, const std::vector<Polyline>& lines,
                          const vectorize::PolylineCodecOptions& options) {
  WriteFileAtomically(path, vectorize::EncodePolylines(lines, options));
}

std::vector<Polyline> ReadPolylinesBinary(const std::string& path) {
  return vectorize::DecodePolylines(ReadWhole(path), path);
}

std::string PolylinesToJson(const std::vector<Polyline>& lines) { return LinesJson(lines).dump(); }

std::vector<Polyline> PolylinesFromJson(const std::string& text, const std::string& source) {
  nlohmann::json j;
  try {
    j = nlohmann::json::parse(text);
  } catch (const nlohmann::json::exception& e) {
    throw InputError(source, 0, std::string("not JSON: ") + e.what());
  }
  return LinesFromJson(j, source);
}

void WriteWallsJson(const std::string& path, const WallsFile& w) {
  nlohmann::json j;
  j["format"] = "cogmap-walls";
  j["version"] = 1;
  j["units"] = "m";
  j["frame"] = "map";
  j["world_from_map"] = {{"x", w.world_from_map.x}, {"y", w.world_from_map.y}, {"theta", w.world_from_map.theta}};
  j["has_truth"] = w.has_truth;
  j["log"] = w.log_path;
  j["log_format"] = w.log_format;
  j["robot"] = w.robot;
  j["mode"] = w.mode;
  j["cell_m"] = w.cell_m;
  j["sensor_range_m"] = w.sensor_range_m;
  j["vertex_count"] = w.vertex_count;
  j["bytes_grid"] = w.bytes_grid;
  j["bytes_vertices"] = w.bytes_vertices;
  j["bytes_polylines"] = w.bytes_polylines;
  j["polylines"] = LinesJson(w.polylines);
  WriteFileAtomically(path, j.dump(1) + "\n");
}

WallsFile ReadWallsJson(const std::string& path) {
  const std::string text = ReadWhole(path);
  nlohmann::json j;
  try {
    j = nlohmann::json::parse(text);
  } catch (const nlohmann::json::exception& e) {
    throw InputError(path, 0, std::string("not JSON: ") + e.what());
  }
  if (!j.is_object() || j.value("format", "") != "cogmap-walls")
    throw InputError(path, 0, "not a cogmap walls file (format != cogmap-walls)");
  WallsFile w;
  try {
    const auto& p = j.at("world_from_map");
    w.world_from_map = Pose2{p.at("x").get<double>(), p.at("y").get<double>(), p.at("theta").get<double>()};
    w.has_truth = j.value("has_truth", false);
    w.log_path = j.value("log", "");
    w.log_format = j.value("log_format", "auto");
    w.robot = j.value("robot", "");
    w.mode = j.value("mode", "");
    w.cell_m = j.value("cell_m", 0.1);
    w.sensor_range_m = j.value("sensor_range_m", 0.0);
    w.vertex_count = j.value("vertex_count", int64_t{0});
    w.bytes_grid = j.value("bytes_grid", int64_t{0});
    w.bytes_vertices = j.value("bytes_vertices", int64_t{0});
    w.bytes_polylines = j.value("bytes_polylines", int64_t{0});
  } catch (const nlohmann::json::exception& e) {
    throw InputError(path, 0, std::string("bad field: ") + e.what());
  }
  if (!j.contains("polylines")) throw InputError(path, 0, "missing polylines");
  w.polylines = LinesFromJson(j["polylines"], path);
  return w;
}

}  // namespace cogmap::io
