#include "cogmap/io/grid_io.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "cogmap/core/error.h"
#include "cogmap/io/atomic_file.h"

namespace cogmap::io {
namespace {

std::string Trim(const std::string& s) {
  size_t a = 0, b = s.size();
  while (a < b && std::isspace(static_cast<unsigned char>(s[a]))) ++a;
  while (b > a && std::isspace(static_cast<unsigned char>(s[b - 1]))) --b;
  return s.substr(a, b - a);
}

double ParseNumber(const std::string& path, long line, const std::string& key, const std::string& text) {
  const std::string t = Trim(text);
  try {
    size_t used = 0;
    const double v = std::stod(t, &used);
    if (used != t.size() || !std::isfinite(v)) throw std::invalid_argument(t);
    return v;
  } catch (const std::exception&) {
    throw InputError(path, line, "'" + key + "' is not a number: '" + t + "'");
  }
}

std::string ReadWholeFile(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path, 0, "cannot open");
  std::ostringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

}  // namespace

// ---------------------------------------------------------------- map_server

std::string EncodePgm(const PgmImage& image) {
  std::string out = "P5\n# cogmap occupancy grid\n" + std::to_string(image.width) + " " +
                    std::to_string(image.height) + "\n" + std::to_string(image.max_value) + "\n";
  out.append(reinterpret_cast<const char*>(image.pixels.data()), image.pixels.size());
  return out;
}

std::string EncodeMapServerYaml(const MapServerYaml& y) {
  char buf[512];
  std::snprintf(buf, sizeof buf,
                "image: %s\nresolution: %.9g\norigin: [%.9g, %.9g, %.9g]\nnegate: %d\n"
                "occupied_thresh: %.9g\nfree_thresh: %.9g\nmode: %s\n",
                y.image.c_str(), y.resolution, y.origin.x(), y.origin.y(), y.origin_yaw, y.negate,
                y.occupied_thresh, y.free_thresh, y.mode.c_str());
  return buf;
}

void WriteMapServer(const std::string& base, const grid::Grid2D<grid::CellClass>& classes) {
  const auto& lim = classes.limits();
  PgmImage pgm;
  pgm.width = lim.width();
  pgm.height = lim.height();
  pgm.pixels.resize(static_cast<size_t>(pgm.width) * pgm.height);
  for (int y = 0; y < pgm.height; ++y)
    for (int x = 0; x < pgm.width; ++x) {
      uint8_t v = kPgmUnknown;
      switch (classes.at(x, y)) {
        case grid::CellClass::kOccupied: v = kPgmOccupied; break;
        case grid::CellClass::kEmpty:
        case grid::CellClass::kRobotPath: v = kPgmFree; break;
        case grid::CellClass::kUnknown: v = kPgmUnknown; break;
      }
      pgm.pixels[static_cast<size_t>(pgm.height - 1 - y) * pgm.width + x] = v;
    }
  MapServerYaml yaml;
  yaml.image = std::filesystem::path(base + ".pgm").filename().string();
  yaml.resolution = lim.cell_m();
  yaml.origin = lim.origin();
  WriteFileAtomically(base + ".pgm", EncodePgm(pgm));
  WriteFileAtomically(base + ".yaml", EncodeMapServerYaml(yaml));
}

PgmImage ReadPgm(const std::string& path) {
  const std::string data = ReadWholeFile(path);
  size_t i = 0;
  // Header tokens separated by whitespace; '#' starts a comment to end of line.
  auto token = [&]() -> std::string {
    for (;;) {
      while (i < data.size() && std::isspace(static_cast<unsigned char>(data[i]))) ++i;
      if (i < data.size() && data[i] == '#') {
        while (i < data.size() && data[i] != '\n') ++i;
        continue;
      }
      break;
    }
    const size_t a = i;
    while (i < data.size() && !std::isspace(static_cast<unsigned char>(data[i])) && data[i] != '#') ++i;
    return data.substr(a, i - a);
  };
  if (token() != "P5") throw InputError(path, 0, "not a binary PGM (expected 'P5')");
  PgmImage img;
  int* fields[] = {&img.width, &img.height, &img.max_value};
  const char* names[] = {"width", "height", "max value"};
  for (int k = 0; k < 3; ++k) {
    const std::string t = token();
    if (t.empty() || !std::all_of(t.begin(), t.end(), [](char c) { return std::isdigit(static_cast<unsigned char>(c)); }) ||
        t.size() > 9)
      throw InputError(path, 0, std::string("bad PGM ") + names[k] + " '" + t + "'");
    *fields[k] = std::stoi(t);
  }
  if (img.width <= 0 || img.height <= 0) throw InputError(path, 0, "empty PGM");
  if (img.max_value <= 0 || img.max_value > 255)
    throw InputError(path, 0, "PGM max value " + std::to_string(img.max_value) + " (only 8-bit supported)");
  if (i >= data.size() || !std::isspace(static_cast<unsigned char>(data[i])))
    throw InputError(path, 0, "truncated PGM header");
  ++i;  // the single whitespace before the raster
  const size_t n = static_cast<size_t>(img.width) * img.height;
  if (data.size() - i < n)
    throw InputError(path, 0, "truncated PGM: " + std::to_string(data.size() - i) + " of " +
                                  std::to_string(n) + " pixels");
  img.pixels.assign(data.begin() + i, data.begin() + i + n);
  return img;
}

MapServerYaml ReadMapServerYaml(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw InputError(path, 0, "cannot open");
  MapServerYaml y;
  bool has_image = false, has_resolution = false, has_origin = false;
  std::string text;
  long line = 0;
  while (std::getline(in, text)) {
    ++line;
    if (const size_t hash = text.find('#'); hash != std::string::npos) text.resize(hash);
    text = Trim(text);
    if (text.empty()) continue;
    const size_t colon = text.find(':');
    if (colon == std::string::npos) throw InputError(path, line, "expected 'key: value'");
    const std::string key = Trim(text.substr(0, colon));
    std::string value = Trim(text.substr(colon + 1));
    if (value.size() >= 2 && (value.front() == '"' || value.front() == '\'') && value.back() == value.front())
      value = value.substr(1, value.size() - 2);
    if (key == "image") {
      if (value.empty()) throw InputError(path, line, "empty 'image'");
      y.image = value;
      has_image = true;
    } else if (key == "resolution") {
      y.resolution = ParseNumber(path, line, key, value);
      if (y.resolution <= 0) throw InputError(path, line, "'resolution' must be positive");
      has_resolution = true;
    } else if (key == "origin") {
      if (value.size() < 2 || value.front() != '[' || value.back() != ']')
        throw InputError(path, line, "'origin' must be [x, y, yaw]");
      std::vector<double> v;
      std::stringstream ss(value.substr(1, value.size() - 2));
      std::string part;
      while (std::getline(ss, part, ',')) v.push_back(ParseNumber(path, line, key, part));
      if (v.size() != 3) throw InputError(path, line, "'origin' must have 3 numbers, got " + std::to_string(v.size()));
      y.origin = Vec2(v[0], v[1]);
      y.origin_yaw = v[2];
      has_origin = true;
    } else if (key == "negate") {
      const double n = ParseNumber(path, line, key, value);
      if (n != 0 && n != 1) throw InputError(path, line, "'negate' must be 0 or 1");
      y.negate = static_cast<int>(n);
    } else if (key == "occupied_thresh") {
      y.occupied_thresh = ParseNumber(path, line, key, value);
    } else if (key == "free_thresh") {
      y.free_thresh = ParseNumber(path, line, key, value);
    } else if (key == "mode") {
      if (value != "trinary" && value != "scale" && value != "raw")
        throw InputError(path, line, "unknown mode '" + value + "' (trinary, scale, raw)");
      y.mode = value;
    } else {
      throw InputError(path, line, "unknown key '" + key + "'");
    }
  }
  if (!has_image) throw InputError(path, 0, "missing 'image'");
  if (!has_resolution) throw InputError(path, 0, "missing 'resolution'");
  if (!has_origin) throw InputError(path, 0, "missing 'origin'");
  return y;
}

MapServerMap ReadMapServer(const std::string& yaml_path) {
  MapServerMap map;
  map.yaml = ReadMapServerYaml(yaml_path);
  std::filesystem::path image(map.yaml.image);
  if (image.is_relative()) image = std::filesystem::path(yaml_path).parent_path() / image;
  const PgmImage pgm = ReadPgm(image.string());
  map.occupancy = grid::Grid2D<int8_t>(
      grid::MapLimits(map.yaml.resolution, map.yaml.origin, pgm.width, pgm.height), -1);
  for (int row = 0; row < pgm.height; ++row)
    for (int x = 0; x < pgm.width; ++x) {
      // map_server: scale to [0, 255], p = (255 - v) / 255 unless negated.
      const double v = 255.0 * pgm.pixels[static_cast<size_t>(row) * pgm.width + x] / pgm.max_value;
      const double p = map.yaml.negate ? v / 255.0 : (255.0 - v) / 255.0;
      int8_t o = -1;
      if (map.yaml.mode == "raw") o = static_cast<int8_t>(std::lround(std::min(v, 100.0)));
      else if (p > map.yaml.occupied_thresh) o = 100;
      else if (p < map.yaml.free_thresh) o = 0;
      else if (map.yaml.mode == "scale")
        o = static_cast<int8_t>(std::lround(99.0 * (p - map.yaml.free_thresh) /
                                            (map.yaml.occupied_thresh - map.yaml.free_thresh)));
      map.occupancy.at(x, pgm.height - 1 - row) = o;
    }
  return map;
}

grid::Grid2D<grid::CellClass> ClassesFromMapServer(const MapServerMap& map) {
  grid::Grid2D<grid::CellClass> out(map.occupancy.limits(), grid::CellClass::kUnknown);
  for (size_t i = 0; i < out.cells().size(); ++i) {
    const int8_t o = map.occupancy.cells()[i];
    out.cells()[i] = o == 100 ? grid::CellClass::kOccupied
                     : o == 0 ? grid::CellClass::kEmpty
                              : grid::CellClass::kUnknown;
  }
  return out;
}

// ---------------------------------------------------------------- logs

FuseLogStats FuseLog(LogReader& log, const sensors::RobotDescription& robot,
                     grid::RangeFusion& fusion, const FuseLogOptions& options,
                     const std::function<void(double)>& progress) {
  FuseLogStats stats;
  sensors::LogRecord record;
  const int sensors = static_cast<int>(robot.sensors.size());
  while (log.Next(&record)) {
    ++stats.records;
    for (const auto& r : record.ranges)
      if (r.sensor < 0 || r.sensor >= sensors)
        throw InputError(log.path(), 0,
                         "record " + std::to_string(stats.records) + " has a reading of sensor " +
                             std::to_string(r.sensor) + ", but robot '" + robot.name + "' has " +
                             std::to_string(sensors) + " sensors");
    const Pose2& pose = options.use_truth && record.truth ? *record.truth : record.odom;
    fusion.InsertSweep(pose, robot, record.ranges);
    stats.readings += static_cast<long>(record.ranges.size());
    if (progress && (stats.records & 63) == 0) progress(log.progress());
  }
  if (stats.records == 0) throw InputError(log.path(), 0, "empty log: no records");
  if (progress) progress(1.0);
  return stats;
}

}  // namespace cogmap::io
