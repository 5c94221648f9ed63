// Side by side: MRPT's occupancy grid (COccupancyGridMap2D) and cogmap's
// modified HIMM, built from the same readings and the same poses of one log.
//
//   cogmap_mrpt_grid_compare LOG [--format auto] [--robot NAME|FILE]
//       [--poses odom|truth] [--cell 0.1] [--window 3.0]
//       [--engine both|cogmap|mrpt|none] [--png SIDE_BY_SIDE.png] [--json OUT.json]
//       [--world WORLD.map]
//
// Prints one JSON object (also written to --json): per engine the insertion
// time, the process's peak resident memory, the grid's own size in memory and
// its known area, and with --world how close its occupied cells lie to the
// true walls (use --poses truth to judge the fusion rule alone); and the map sizes of docs/BENCHMARKS.md (grid as map_server
// PGM, as PNG, as MRPT's gzip-compressed serialized gridmap) with the mapped
// floor they cover. Memory is per process: run once per engine (and once with
// --engine none for the baseline of reading the log) to compare peak memory;
// the suite driver (bench/run_all) does that.
//
// How MRPT is fed (MRPT 2.5):
// - sonar: one CObservationRange per reading, because MRPT inserts every
//   measurement of one observation from the first measurement's sensor pose
//   (a FIXME in COccupancyGridMap2D_insert.cpp). The observation's cone is
//   the sensor's beam width, its min/max distance the sensor's.
// - laser: one CObservation2DRangeScan per sweep (beams evenly spread over the
//   field of view, as every laser description in cogmap is).
// - insertionOptions.maxDistanceInsertion = the MHIMM window w, so that both
//   grids use readings up to the same distance; readings at or beyond it (and
//   no-echo readings) follow MRPT's own rule (considerInvalidRangesAsFreeSpace).
// - the grid grows as MRPT's does by itself; cogmap's grows in 64-cell chunks.
#include <mrpt/io/CFileGZOutputStream.h>
#include <mrpt/maps/COccupancyGridMap2D.h>
#include <mrpt/obs/CObservation2DRangeScan.h>
#include <mrpt/obs/CObservationRange.h>
#include <mrpt/poses/CPose3D.h>
#include <mrpt/serialization/CArchive.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "cogmap/core/error.h"
#include "cogmap/core/process.h"
#include "cogmap/draw/drawing.h"
#include "cogmap/core/geometry.h"
#include "cogmap/grid/range_fusion.h"
#include "cogmap/io/atomic_file.h"
#include "cogmap/io/image.h"
#include "cogmap/io/log_reader.h"
#include "cogmap/io/world_io.h"
#include "cogmap/sensors/robot.h"
#include "cogmap/sensors/robot_json.h"

namespace {

using cogmap::Pose2;
using cogmap::Vec2;
using cogmap::grid::CellClass;
using cogmap::sensors::LogRecord;
using cogmap::sensors::RobotDescription;
using Clock = std::chrono::steady_clock;

double Seconds(Clock::time_point a, Clock::time_point b) {
  return std::chrono::duration<double>(b - a).count();
}

struct LoadedLog {
  RobotDescription robot;
  std::vector<LogRecord> records;
  long readings = 0;
  double duration_s = 0;
};

LoadedLog Load(const std::string& path, const std::string& format, const std::string& robot_name,
               bool use_truth) {
  LoadedLog log;
  auto reader = cogmap::io::OpenLog(path, format);
  LogRecord r;
  while (reader->Next(&r)) {
    if (use_truth) {
      if (!r.truth) throw cogmap::InputError(path, 0, "--poses truth: the log has no true poses");
      r.odom = *r.truth;
    }
    log.readings += static_cast<long>(r.ranges.size());
    log.records.push_back(std::move(r));
  }
  if (!robot_name.empty()) {
    log.robot = cogmap::sensors::ResolveRobot(robot_name);
  } else if (auto hint = reader->robot_hint()) {
    log.robot = *hint;
  } else {
    throw cogmap::InputError(path, 0, "the log does not name its robot: give --robot");
  }
  if (log.records.size() >= 2)
    log.duration_s = log.records.back().time_s - log.records.front().time_s;
  return log;
}

bool IsLaser(const RobotDescription& robot) {
  return !robot.sensors.empty() && robot.sensors.front().kind == cogmap::sensors::SensorKind::kLaser;
}

mrpt::poses::CPose3D ToMrpt(const Pose2& p) { return mrpt::poses::CPose3D(p.x, p.y, 0, p.theta, 0, 0); }

struct EngineRun {
  double insert_s = 0;
  long rss_after_kib = 0;
  long grid_bytes = 0;  // the cells in memory
  long cells = 0;
  long known_cells = 0;
  long occupied_cells = 0;
  double cell_m = 0;
};

// ---- cogmap MHIMM --------------------------------------------------------

std::unique_ptr<cogmap::grid::HimmFusion> BuildCogmap(const LoadedLog& log, double cell_m,
                                                      double window_m, EngineRun* run) {
  cogmap::grid::MhimmOptions options;
  options.window_m = window_m;
  cogmap::grid::GridBounds bounds;
  bounds.cell_m = cell_m;
  const auto t0 = Clock::now();
  auto grid = std::make_unique<cogmap::grid::HimmFusion>(true, options, bounds);
  for (const LogRecord& r : log.records) grid->InsertSweep(r.odom, log.robot, r.ranges);
  run->insert_s = Seconds(t0, Clock::now());
  run->rss_after_kib = cogmap::ResidentKib();
  const auto& limits = grid->limits();
  run->cell_m = limits.cell_m();
  run->cells = limits.cell_count();
  run->grid_bytes = run->cells * static_cast<long>(sizeof(float));
  for (int y = 0; y < limits.height(); ++y)
    for (int x = 0; x < limits.width(); ++x) {
      const CellClass c = grid->Classify(x, y);
      if (c != CellClass::kUnknown) ++run->known_cells;
      if (c == CellClass::kOccupied) ++run->occupied_cells;
    }
  return grid;
}

// ---- MRPT ---------------------------------------------------------------

std::unique_ptr<mrpt::maps::COccupancyGridMap2D> BuildMrpt(const LoadedLog& log, double cell_m,
                                                           double window_m, EngineRun* run) {
  const Pose2 first = log.records.empty() ? Pose2{} : log.records.front().odom;
  const auto t0 = Clock::now();
  auto map = std::make_unique<mrpt::maps::COccupancyGridMap2D>(
      first.x - 5, first.x + 5, first.y - 5, first.y + 5, cell_m);
  map->insertionOptions.maxDistanceInsertion = static_cast<float>(window_m);
  const RobotDescription& robot = log.robot;
  if (IsLaser(robot)) {
    const int n = static_cast<int>(robot.sensors.size());
    const auto& s0 = robot.sensors.front();
    const auto& sn = robot.sensors.back();
    const double step = n > 1 ? (sn.robot_from_sensor.theta - s0.robot_from_sensor.theta) / (n - 1) : 0;
    mrpt::obs::CObservation2DRangeScan scan;
    scan.aperture = static_cast<float>(std::abs(step) * (n - 1));
    scan.rightToLeft = step >= 0;
    scan.maxRange = static_cast<float>(s0.max_range_m);
    scan.sensorPose = mrpt::poses::CPose3D(s0.robot_from_sensor.x, s0.robot_from_sensor.y, 0,
                                           0.5 * (s0.robot_from_sensor.theta + sn.robot_from_sensor.theta),
                                           0, 0);
    scan.resizeScan(n);
    for (const LogRecord& r : log.records) {
      if (r.ranges.empty()) continue;
      for (int i = 0; i < n; ++i) {
        scan.setScanRange(i, 0.f);
        scan.setScanRangeValidity(i, false);
      }
      for (const auto& reading : r.ranges) {
        if (reading.sensor < 0 || reading.sensor >= n) continue;
        const auto& s = robot.sensors[reading.sensor];
        const bool valid = reading.range_m >= s.min_range_m && reading.range_m < s.max_range_m;
        const int i = scan.rightToLeft ? reading.sensor : n - 1 - reading.sensor;
        scan.setScanRange(i, static_cast<float>(reading.range_m));
        scan.setScanRangeValidity(i, valid);
      }
      map->insertObservation(scan, ToMrpt(r.odom));
    }
  } else {
    mrpt::obs::CObservationRange obs;
    obs.sensedData.resize(1);
    for (const LogRecord& r : log.records) {
      const mrpt::poses::CPose3D robot_pose = ToMrpt(r.odom);
      for (const auto& reading : r.ranges) {
        if (reading.sensor < 0 || reading.sensor >= static_cast<int>(robot.sensors.size())) continue;
        const auto& s = robot.sensors[reading.sensor];
        if (reading.range_m < s.min_range_m) continue;  // as MHIMM: below min range ignored
        obs.minSensorDistance = static_cast<float>(s.min_range_m);
        obs.maxSensorDistance = static_cast<float>(s.max_range_m);
        obs.sensorConeApperture = static_cast<float>(s.beam_width_rad);
        auto& m = obs.sensedData.front();
        m.sensorPose = mrpt::math::TPose3D(s.robot_from_sensor.x, s.robot_from_sensor.y, 0,
                                           s.robot_from_sensor.theta, 0, 0);
        // No echo: beyond every insertion distance, so MRPT treats it as invalid.
        m.sensedDistance = static_cast<float>(reading.range_m >= s.max_range_m
                                                  ? std::max(s.max_range_m, window_m) + 1.0
                                                  : reading.range_m);
        map->insertObservation(obs, robot_pose);
      }
    }
  }
  run->insert_s = Seconds(t0, Clock::now());
  run->rss_after_kib = cogmap::ResidentKib();
  run->cell_m = map->getResolution();
  run->cells = static_cast<long>(map->getSizeX()) * map->getSizeY();
  run->grid_bytes = run->cells * static_cast<long>(sizeof(mrpt::maps::COccupancyGridMap2D::cellType));
  for (unsigned y = 0; y < map->getSizeY(); ++y)
    for (unsigned x = 0; x < map->getSizeX(); ++x) {
      const float p_free = map->getCell(x, y);
      if (std::abs(p_free - 0.5f) > 0.01f) ++run->known_cells;
      if (p_free < 0.35f) ++run->occupied_cells;  // map_server's occupied_thresh 0.65
    }
  return map;
}

// ---- sizes ----------------------------------------------------------------

// The MHIMM grid as a map_server trinary raster (occupied 0, free 254,
// unknown 205), cropped to the box of known cells, row 0 on top.
struct Raster {
  int width = 0, height = 0;
  std::vector<uint8_t> grey;
};

Raster MapServerRaster(const cogmap::grid::HimmFusion& grid) {
  const auto& l = grid.limits();
  int x0 = l.width(), y0 = l.height(), x1 = -1, y1 = -1;
  for (int y = 0; y < l.height(); ++y)
    for (int x = 0; x < l.width(); ++x)
      if (grid.Classify(x, y) != CellClass::kUnknown) {
        x0 = std::min(x0, x), x1 = std::max(x1, x), y0 = std::min(y0, y), y1 = std::max(y1, y);
      }
  Raster r;
  if (x1 < 0) return r;
  r.width = x1 - x0 + 1;
  r.height = y1 - y0 + 1;
  r.grey.resize(static_cast<size_t>(r.width) * r.height);
  for (int row = 0; row < r.height; ++row)
    for (int col = 0; col < r.width; ++col) {
      const CellClass c = grid.Classify(x0 + col, y1 - row);
      r.grey[static_cast<size_t>(row) * r.width + col] =
          c == CellClass::kOccupied ? 0 : c == CellClass::kUnknown ? 205 : 254;
    }
  return r;
}

long PgmBytes(const Raster& r) {
  const std::string header = "P5\n" + std::to_string(r.width) + " " + std::to_string(r.height) + "\n255\n";
  return static_cast<long>(header.size()) + static_cast<long>(r.grey.size());
}

long MrptGzBytes(const mrpt::maps::COccupancyGridMap2D& map) {
  namespace fs = std::filesystem;
  const fs::path tmp = fs::temp_directory_path() /
                       ("cogmap_mrpt_" + std::to_string(::getpid()) + ".gridmap.gz");
  {
    mrpt::io::CFileGZOutputStream f(tmp.string());
    auto archive = mrpt::serialization::archiveFrom(f);
    archive << map;
  }
  const long bytes = static_cast<long>(fs::file_size(tmp));
  fs::remove(tmp);
  return bytes;
}

// ---- picture --------------------------------------------------------------

void DrawSideBySide(const std::string& path, const cogmap::grid::HimmFusion* ours,
                    const mrpt::maps::COccupancyGridMap2D* theirs, const std::string& title) {
  // The world box of everything known in either map.
  double lo_x = 1e18, lo_y = 1e18, hi_x = -1e18, hi_y = -1e18;
  auto grow = [&](double x, double y) {
    lo_x = std::min(lo_x, x), lo_y = std::min(lo_y, y), hi_x = std::max(hi_x, x), hi_y = std::max(hi_y, y);
  };
  const auto& l = ours->limits();
  for (int y = 0; y < l.height(); ++y)
    for (int x = 0; x < l.width(); ++x)
      if (ours->Classify(x, y) != CellClass::kUnknown) {
        const Vec2 c = l.CenterOf({x, y});
        grow(c.x(), c.y());
      }
  for (unsigned y = 0; y < theirs->getSizeY(); ++y)
    for (unsigned x = 0; x < theirs->getSizeX(); ++x)
      if (std::abs(theirs->getCell(x, y) - 0.5f) > 0.01f) grow(theirs->idx2x(x), theirs->idx2y(y));
  if (hi_x < lo_x) return;
  const double cell = l.cell_m();
  lo_x -= cell, lo_y -= cell, hi_x += cell, hi_y += cell;
  const int w = static_cast<int>(std::ceil((hi_x - lo_x) / cell));
  const int h = static_cast<int>(std::ceil((hi_y - lo_y) / cell));
  const int scale = std::max(1, std::min(4, 600 / std::max(w, h)));
  const int margin = 8, header = 40;
  cogmap::io::RgbImage left(w * scale, h * scale), right(w * scale, h * scale);
  for (int row = 0; row < h; ++row)
    for (int col = 0; col < w; ++col) {
      const Vec2 p(lo_x + (col + 0.5) * cell, hi_y - (row + 0.5) * cell);
      cogmap::io::Rgb a{160, 160, 160};
      const auto c = l.CellOf(p);
      if (l.Contains(c)) {
        switch (ours->Classify(c.x(), c.y())) {
          case CellClass::kOccupied: a = {0, 0, 0}; break;
          case CellClass::kEmpty: a = {255, 255, 255}; break;
          case CellClass::kRobotPath: a = {220, 0, 0}; break;
          case CellClass::kUnknown: break;
        }
      }
      const uint8_t g = static_cast<uint8_t>(std::lround(255.0 * theirs->getPos(p.x(), p.y())));
      const cogmap::io::Rgb b{g, g, g};
      for (int dy = 0; dy < scale; ++dy)
        for (int dx = 0; dx < scale; ++dx) {
          left.at(col * scale + dx, row * scale + dy) = a;
          right.at(col * scale + dx, row * scale + dy) = b;
        }
    }
  cogmap::draw::Drawing img(2 * w * scale + 3 * margin, h * scale + header + margin);
  img.Image(left, margin, header, 1.0);
  img.Image(right, 2 * margin + w * scale, header, 1.0);
  img.Text(cogmap::Vec2(margin, 8), "cogmap MHIMM  " + title, cogmap::draw::Font{16, true});
  img.Text(cogmap::Vec2(2 * margin + w * scale, 8), "MRPT COccupancyGridMap2D", cogmap::draw::Font{16, true});
  img.Write(path);
}

// ---- accuracy against the true walls -------------------------------------

// Distance from each occupied cell's centre to the nearest true wall, over the
// cells a predicate calls occupied: mean, 95th percentile and the share within
// 'near_m' (SPEC's 0.2 m of wall recall; 2 cells at 0.1 m).
template <typename IsOccupied, typename CentreOf>
nlohmann::json OccupiedAccuracy(int width, int height, IsOccupied occupied, CentreOf centre,
                                const std::vector<cogmap::Segment2>& walls, double near_m = 0.2) {
  std::vector<double> d;
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x)
      if (occupied(x, y)) {
        const Vec2 p = centre(x, y);
        double best = 1e18;
        for (const auto& w : walls) best = std::min(best, cogmap::PointSegmentDistance(p, w.a, w.b));
        d.push_back(best);
      }
  if (d.empty()) return {{"occupied_cells", 0}};
  std::sort(d.begin(), d.end());
  double sum = 0;
  long near = 0;
  for (double v : d) sum += v, near += v <= near_m;
  return {{"occupied_cells", static_cast<long>(d.size())},
          {"mean_m", sum / d.size()},
          {"p95_m", d[std::min(d.size() - 1, static_cast<size_t>(0.95 * d.size()))]},
          {"share_within_0_2m", static_cast<double>(near) / d.size()}};
}

nlohmann::json ToJson(const EngineRun& r) {
  return {{"insert_s", r.insert_s},
          {"rss_after_kib", r.rss_after_kib},
          {"grid_bytes_in_memory", r.grid_bytes},
          {"cells", r.cells},
          {"known_cells", r.known_cells},
          {"known_area_m2", r.known_cells * r.cell_m * r.cell_m},
          {"occupied_cells", r.occupied_cells}};
}

int Run(int argc, char** argv) {
  CLI::App app{"MRPT's COccupancyGridMap2D against cogmap's modified HIMM on one log"};
  std::string log_path, format = "auto", robot, poses = "odom", engine = "both", png, json_path,
                        title;
  double cell_m = 0.1, window_m = 3.0;
  app.add_option("log", log_path, "the log (any format cogmap reads)")->required();
  app.add_option("--format", format, "log format")->capture_default_str();
  app.add_option("--robot", robot, "robot name or JSON file (default: the log's)");
  app.add_option("--poses", poses, "odom or truth")->check(CLI::IsMember({"odom", "truth"}))
      ->capture_default_str();
  app.add_option("--cell", cell_m, "cell size in metres, both grids")->capture_default_str();
  app.add_option("--window", window_m, "MHIMM window w = MRPT maxDistanceInsertion, metres")
      ->capture_default_str();
  app.add_option("--engine", engine, "which grid to build: both, cogmap, mrpt, none (baseline)")
      ->check(CLI::IsMember({"both", "cogmap", "mrpt", "none"}))->capture_default_str();
  app.add_option("--png", png, "side-by-side picture (needs --engine both)");
  app.add_option("--title", title, "label drawn over the picture");
  app.add_option("--json", json_path, "also write the JSON here");
  std::string world;
  app.add_option("--world", world, "a world (2D-Map) whose walls the occupied cells are measured against");
  CLI11_PARSE(app, argc, argv);

  nlohmann::json out;
  const auto t_load = Clock::now();
  const LoadedLog log = Load(log_path, format, robot, poses == "truth");
  out["log"] = log_path;
  out["robot"] = log.robot.name;
  out["sensor"] = IsLaser(log.robot) ? "laser" : "sonar";
  out["records"] = log.records.size();
  out["readings"] = log.readings;
  out["log_duration_s"] = log.duration_s;
  out["load_s"] = Seconds(t_load, Clock::now());
  out["rss_after_load_kib"] = cogmap::ResidentKib();
  out["cell_m"] = cell_m;
  out["window_m"] = window_m;
  out["engine"] = engine;

  std::unique_ptr<cogmap::grid::HimmFusion> ours;
  std::unique_ptr<mrpt::maps::COccupancyGridMap2D> theirs;
  if (engine == "both" || engine == "cogmap") {
    EngineRun r;
    ours = BuildCogmap(log, cell_m, window_m, &r);
    out["cogmap"] = ToJson(r);
    out["cogmap"]["readings_per_s"] = r.insert_s > 0 ? log.readings / r.insert_s : 0.0;
    const Raster raster = MapServerRaster(*ours);
    const double floor_m2 = r.known_cells * r.cell_m * r.cell_m;
    out["mapped_floor_m2"] = floor_m2;
    out["sizes"]["raster_cells"] = static_cast<long>(raster.grey.size());
    out["sizes"]["grid_pgm_bytes"] = PgmBytes(raster);
    out["sizes"]["grid_png_bytes"] =
        static_cast<long>(cogmap::io::EncodeGreyPng(raster.width, raster.height, raster.grey).size());
  }
  if (engine == "both" || engine == "mrpt") {
    EngineRun r;
    theirs = BuildMrpt(log, cell_m, window_m, &r);
    out["mrpt"] = ToJson(r);
    out["mrpt"]["readings_per_s"] = r.insert_s > 0 ? log.readings / r.insert_s : 0.0;
    out["sizes"]["mrpt_gridmap_gz_bytes"] = MrptGzBytes(*theirs);
  }
  if (!world.empty()) {
    const auto walls = cogmap::io::ReadWorld(world).plan.walls;
    if (ours) {
      const auto& l = ours->limits();
      out["cogmap"]["occupied_vs_walls"] = OccupiedAccuracy(
          l.width(), l.height(),
          [&](int x, int y) { return ours->Classify(x, y) == CellClass::kOccupied; },
          [&](int x, int y) { return l.CenterOf({x, y}); }, walls);
    }
    if (theirs) {
      out["mrpt"]["occupied_vs_walls"] = OccupiedAccuracy(
          static_cast<int>(theirs->getSizeX()), static_cast<int>(theirs->getSizeY()),
          [&](int x, int y) { return theirs->getCell(x, y) < 0.35f; },
          [&](int x, int y) { return Vec2(theirs->idx2x(x), theirs->idx2y(y)); }, walls);
    }
  }
  out["peak_rss_kib"] = cogmap::PeakResidentKib();
  if (!png.empty() && ours && theirs) {
    DrawSideBySide(png, ours.get(), theirs.get(), title);
    out["png"] = png;
  }
  const std::string text = out.dump(2);
  std::cout << text << "\n";
  if (!json_path.empty()) cogmap::io::WriteFileAtomically(json_path, text + "\n");
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  try {
    return Run(argc, argv);
  } catch (const cogmap::InputError& e) {
    std::cerr << "cogmap_mrpt_grid_compare: " << e.what() << "\n";
    return 2;
  } catch (const std::exception& e) {
    std::cerr << "cogmap_mrpt_grid_compare: " << e.what() << "\n";
    return 1;
  }
}
