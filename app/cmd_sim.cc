// `cogmap simulate`, `cogmap render-world` and `cogmap gen-building`: the
// simulator (issue 3).
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "app/cli_util.h"
#include "app/command.h"
#include "app/progress.h"
#include "cogmap/core/angles.h"
#include "cogmap/core/error.h"
#include "cogmap/io/atomic_file.h"
#include "cogmap/draw/world_picture.h"
#include "cogmap/io/log_reader.h"
#include "cogmap/io/native_log.h"
#include "cogmap/io/world_io.h"
#include "cogmap/sensors/robot_json.h"
#include "cogmap/sim/building.h"
#include "cogmap/sim/simulator.h"

namespace cogmap::app {
namespace {

io::WorldReadResult LoadWorld(const std::string& path, double m_per_pixel) {
  io::BitmapWorldOptions bitmap;
  bitmap.m_per_pixel = m_per_pixel;
  io::WorldReadResult world = io::ReadWorld(path, bitmap);
  for (const auto& w : world.warnings) std::fprintf(stderr, "cogmap: warning: %s\n", w.c_str());
  return world;
}

// ---------------------------------------------------------------- simulate
struct SimulateArgs {
  std::string world;
  std::string robot = "pioneer16";
  bool route = false;
  bool explore = false;
  uint64_t seed = 1;
  double drift_deg_per_m = RadToDeg(sim::OdometryNoiseOptions{}.drift_rad_per_m);
  double scale_error = sim::OdometryNoiseOptions{}.scale_error;
  double speed_mps = sim::SimulatorOptions{}.cruise_mps;
  int rays = sim::SensorModelOptions{}.sonar_rays;
  double max_time_s = 0.0;
  double m_per_pixel = 0.05;
  bool noiseless = false;
  bool vfh_from_readings = false;
  std::string start;  // "X,Y,THETA_DEG"
  std::string output;
};

// "X,Y,THETA_DEG" (metres, metres, degrees CCW) as a pose.
Pose2 ParseStart(const std::string& text) {
  std::vector<double> v;
  size_t i = 0;
  while (i <= text.size()) {
    const size_t comma = std::min(text.find(',', i), text.size());
    const std::string part = text.substr(i, comma - i);
    char* end = nullptr;
    const double x = std::strtod(part.c_str(), &end);
    if (part.empty() || end != part.c_str() + part.size() || !std::isfinite(x))
      throw InputError("--start: expected X,Y,THETA_DEG (metres, metres, degrees), got '" + text + "'");
    v.push_back(x);
    i = comma + 1;
  }
  if (v.size() != 3)
    throw InputError("--start: expected X,Y,THETA_DEG (3 numbers), got " + std::to_string(v.size()) + " in '" +
                     text + "'");
  return {v[0], v[1], NormalizeAngle(DegToRad(v[2]))};
}

int RunSimulate(const SimulateArgs& a) {
  const auto start = std::chrono::steady_clock::now();
  if (a.route && a.explore) throw InputError("--route and --explore exclude each other");
  if (!(a.speed_mps > 0.0) || a.speed_mps > 2.0) throw InputError("--speed must be in (0, 2] m/s");
  if (a.rays < 1 || a.rays > 100) throw InputError("--rays must be in [1, 100]");
  if (a.max_time_s < 0) throw InputError("--max-time must not be negative");
  const io::WorldReadResult world = LoadWorld(a.world, a.m_per_pixel);
  if (world.plan.walls.empty()) throw InputError(a.world, 0, "the world has no walls");
  const sensors::RobotDescription robot = sensors::ResolveRobot(a.robot);

  sim::SimulatorOptions o;
  if (!a.start.empty()) o.start = ParseStart(a.start);
  o.mode = a.explore ? sim::SimMode::kExplore : sim::SimMode::kRoute;
  if (o.mode == sim::SimMode::kRoute && world.plan.route.empty())
    throw InputError(a.world, 0, "no route (no GoalWithHeading cairns named wpNN): use --explore");
  o.seed = a.seed;
  o.cruise_mps = a.speed_mps;
  o.sensor.sonar_rays = a.rays;
  o.max_time_s = a.max_time_s;
  o.odometry.drift_rad_per_m = DegToRad(a.drift_deg_per_m);
  o.odometry.scale_error = a.scale_error;
  o.vfh_from_readings = a.vfh_from_readings;
  if (a.noiseless) {
    o.odometry = sim::OdometryNoiseOptions{0, 0, 0, 0, 0};
    o.sensor.sonar_range_sigma_m = o.sensor.sonar_range_sigma_frac = 0;
    o.sensor.sonar_crosstalk_probability = 0;
    o.sensor.laser_range_sigma_m = 0;
  }

  sim::SimStats stats;
  ProgressBar bar("simulate");
  io::WriteFileAtomically(a.output, [&](std::ostream& out) {
    io::NativeLogWriter writer(out, robot);
    stats = sim::Simulate(world.plan, robot, o, [&](const sensors::LogRecord& r) { writer.Write(r); },
                          [&](double f) { bar.Update(f); });
  });
  bar.Finish();
  for (const auto& w : stats.warnings) std::fprintf(stderr, "cogmap: warning: %s\n", w.c_str());
  const double wall = Seconds(start);
  std::printf("%s: simulated %.1f s, %.1f m, ", a.output.c_str(), stats.simulated_s, stats.distance_m);
  if (o.mode == sim::SimMode::kRoute)
    std::printf("waypoints %d/%d, ", stats.waypoints_reached, stats.waypoints_total);
  std::printf("coverage %.3f, %ld records, robot %s, wall-clock %.2f s (%.0fx real time)\n", stats.coverage,
              stats.records, robot.name.c_str(), wall, stats.simulated_s / std::max(wall, 1e-6));
  return 0;
}

std::function<int()> SetupSimulate(CLI::App& sub) {
  auto a = std::make_shared<SimulateArgs>();
  sub.add_option("WORLD", a->world,
                 "World: an ARIA 2D-Map file (.map), a PNG occupancy image (dark pixels are walls), or a ROS "
                 "map_server map.yaml with its PGM or PNG (occupied cells are walls)")
      ->required();
  sub.add_option("--start", a->start,
                 "Start pose X,Y,THETA_DEG (metres, metres, degrees CCW; e.g. 1.5,2,90): overrides the world's "
                 "RobotHome (bitmap and ROS-map worlds start at the free cell farthest from walls)");
  sub.add_option("--robot", a->robot,
                 "Robot: a built-in name (" + Join(sensors::BuiltinRobotNames()) + ") or a robot JSON file")
      ->capture_default_str();
  sub.add_flag("--route", a->route, "Drive the world's waypoints wp01, wp02, ... in order (the default)");
  sub.add_flag("--explore", a->explore,
               "Drive to the nearest unseen reachable place until none is left (or the time limit)");
  sub.add_option("--seed", a->seed, "Random seed: the same seed gives the same log")->capture_default_str();
  sub.add_option("--drift-deg-per-m", a->drift_deg_per_m,
                 "Systematic odometry heading drift, degrees per metre driven (CCW positive)")
      ->capture_default_str();
  sub.add_option("--scale-error", a->scale_error, "Odometry distance scale error (0.01: reads 1 % long)")
      ->capture_default_str();
  sub.add_option("--speed", a->speed_mps, "Cruise speed, m/s")->capture_default_str();
  sub.add_option("--rays", a->rays, "Rays sampling each sonar cone")->capture_default_str();
  sub.add_option("--max-time", a->max_time_s,
                 "Bound on simulated seconds (0: automatic, from the route length; explore 3600 s)")
      ->capture_default_str();
  sub.add_option("--m-per-pixel", a->m_per_pixel, "Metres per pixel of a PNG world")->capture_default_str();
  sub.add_flag("--noiseless", a->noiseless, "Perfect odometry and noise-free ranges (specular effects stay)");
  sub.add_flag("--vfh-from-readings", a->vfh_from_readings,
               "Build VFH's certainty grid from the robot's own readings (HIMM) instead of the true walls");
  sub.add_option("-o,--output", a->output, "Native log to write")->required();
  return [a] { return RunSimulate(*a); };
}

// ------------------------------------------------------------ render-world
struct RenderArgs {
  std::string world;
  std::string log;
  std::string output;
  double px_per_m = 0.0;  // 0: fit the picture to the pixel budget
  double m_per_pixel = 0.05;
};

int RunRender(const RenderArgs& a) {
  if (!(a.px_per_m >= 0) || a.px_per_m > 1000) throw InputError("--px-per-m must be in (0, 1000]");
  draw::FormatOfPath(a.output);  // a picture format, before any work
  const io::WorldReadResult world = LoadWorld(a.world, a.m_per_pixel);
  const FloorPlan& p = world.plan;
  std::vector<Vec2> truth, odom;
  if (!a.log.empty()) {
    auto log = io::OpenLog(a.log);
    sensors::LogRecord r;
    while (log->Next(&r)) {
      const double min_step = a.px_per_m > 0 ? 0.5 / a.px_per_m : 0.01;
      if (odom.empty() || (r.odom.translation() - odom.back()).norm() >= min_step)
        odom.push_back(r.odom.translation());
      if (r.truth && (truth.empty() || (r.truth->translation() - truth.back()).norm() >= min_step))
        truth.push_back(r.truth->translation());
    }
  }
  draw::PictureOptions picture;
  picture.px_per_m = a.px_per_m;
  picture.title = std::filesystem::path(a.world).filename().string();
  const draw::MapPicture pic = draw::DrawWorld(p, truth, odom, picture);
  pic.drawing.Write(a.output);
  const long w = std::lround(std::ceil(pic.drawing.width())), h = std::lround(std::ceil(pic.drawing.height()));
  std::printf("%s: %zu walls, %zu rooms, %zu doors, %zu waypoints%s -> %s (%ldx%ld)\n", a.world.c_str(),
              p.walls.size(), p.rooms.size(), p.doorways.size(), p.route.size(),
              a.log.empty() ? "" : (", paths of " + a.log + " (green true, red odometry)").c_str(),
              a.output.c_str(), w, h);
  return 0;
}

std::function<int()> SetupRender(CLI::App& sub) {
  auto a = std::make_shared<RenderArgs>();
  sub.add_option("WORLD", a->world, "World: an ARIA 2D-Map file, a PNG occupancy image, or a ROS map.yaml")
      ->required();
  sub.add_option("--log", a->log, "A run to draw: true path in green, odometry path in red");
  sub.add_option("--px-per-m", a->px_per_m,
                 "Pixels per metre (default: the picture fits 2000 px on its longest side)");
  sub.add_option("--m-per-pixel", a->m_per_pixel, "Metres per pixel of a PNG world")->capture_default_str();
  sub.add_option("-o,--output", a->output, "Picture to write: .png, .svg or .pdf")->required();
  return [a] { return RunRender(*a); };
}

// ------------------------------------------------------------ gen-building
struct BuildingArgs {
  sim::BuildingOptions options;
  std::string output;
};

int RunBuilding(const BuildingArgs& a) {
  const FloorPlan plan = sim::GenerateBuilding(a.options);
  io::WriteAriaMap(a.output, plan);
  std::printf("%s: %d rooms along %.0f m of corridor, %zu walls, %zu waypoints\n", a.output.c_str(),
              a.options.rooms, a.options.corridor_m, plan.walls.size(), plan.route.size());
  return 0;
}

std::function<int()> SetupBuilding(CLI::App& sub) {
  auto a = std::make_shared<BuildingArgs>();
  sub.add_option("--rooms", a->options.rooms, "Number of rooms (both sides of the corridor)")->capture_default_str();
  sub.add_option("--corridor-m", a->options.corridor_m, "Corridor length, metres")->capture_default_str();
  sub.add_option("--corridor-width-m", a->options.corridor_width_m, "Corridor width, metres")->capture_default_str();
  sub.add_option("--room-depth-m", a->options.room_depth_m, "Room depth, metres")->capture_default_str();
  sub.add_option("--door-m", a->options.door_width_m, "Door width, metres")->capture_default_str();
  sub.add_option("--seed", a->options.seed, "Random seed (room widths, door positions)")->capture_default_str();
  sub.add_option("-o,--output", a->output, "2D-Map file to write")->required();
  return [a] { return RunBuilding(*a); };
}

const bool kSimulate = RegisterCommand(
    {"simulate", "Drive a simulated Pioneer (sonar ring or laser) through a world; write a native log", 30,
     SetupSimulate});
const bool kRender = RegisterCommand(
    {"render-world", "Draw a world's walls, rooms, doors and route, and a run's true and odometry paths", 31,
     SetupRender});
const bool kBuilding = RegisterCommand(
    {"gen-building", "Generate a corridor building with rooms, doors and a route, as a 2D-Map", 32,
     SetupBuilding});

}  // namespace
}  // namespace cogmap::app
