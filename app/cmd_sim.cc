// `cogmap simulate`, `cogmap render-world` and `cogmap gen-building`: the
// simulator (issue 3). Options in, one library call (mapping::RunSimulateJob,
// mapping::RunRenderWorldJob, sim::GenerateBuilding), a summary out.
#include <algorithm>
#include <cstdio>
#include <memory>
#include <string>

#include "app/cli_util.h"
#include "app/command.h"
#include "app/progress.h"
#include "cogmap/core/angles.h"
#include "cogmap/core/error.h"
#include "cogmap/io/world_io.h"
#include "cogmap/mapping/sim_job.h"
#include "cogmap/sensors/robot_json.h"
#include "cogmap/sim/building.h"

namespace cogmap::app {
namespace {

// ---------------------------------------------------------------- simulate
struct SimulateArgs {
  mapping::SimulateJob job;  // most options bind to its fields
  bool route = false;
  bool explore = false;
  double drift_deg_per_m = RadToDeg(sim::OdometryNoiseOptions{}.drift_rad_per_m);
  std::string start;  // "X,Y,THETA_DEG"
};

int RunSimulate(SimulateArgs& a) {
  if (a.route && a.explore) throw InputError("--route and --explore exclude each other");
  mapping::SimulateJob& job = a.job;
  sim::SimulatorOptions& o = job.options;
  o.mode = a.explore ? sim::SimMode::kExplore : sim::SimMode::kRoute;
  o.odometry.drift_rad_per_m = DegToRad(a.drift_deg_per_m);
  job.Validate();
  ProgressBar bar("simulate");
  job.progress = [&bar](double f) { bar.Update(f); };
  job.warning = [&bar](const std::string& w) {
    bar.Finish();
    std::fprintf(stderr, "cogmap: warning: %s\n", w.c_str());
  };
  if (!a.start.empty()) o.start = mapping::ParseStartPose(a.start);
  const mapping::SimulateJobResult r = mapping::RunSimulateJob(job);
  bar.Finish();
  const sim::SimStats& stats = r.stats;
  std::printf("%s: simulated %.1f s, %.1f m, ", job.output_path.c_str(), stats.simulated_s, stats.distance_m);
  if (o.mode == sim::SimMode::kRoute) std::printf("waypoints %d/%d, ", stats.waypoints_reached, stats.waypoints_total);
  std::printf("coverage %.3f, %ld records, robot %s, wall-clock %.2f s (%.0fx real time)\n", stats.coverage,
              stats.records, r.robot.name.c_str(), r.seconds, stats.simulated_s / std::max(r.seconds, 1e-6));
  return 0;
}

std::function<int()> SetupSimulate(CLI::App& sub) {
  auto a = std::make_shared<SimulateArgs>();
  sub.add_option("WORLD", a->job.world_path,
                 "World: an ARIA 2D-Map file (.map), a PNG occupancy image (white pixels are free, every other pixel a wall), or a ROS "
                 "map_server map.yaml with its PGM or PNG (occupied cells are walls)")
      ->required();
  sub.add_option("--start", a->start,
                 "Start pose X,Y,THETA_DEG (metres, metres, degrees CCW; e.g. 1.5,2,90): overrides the world's "
                 "RobotHome (bitmap and ROS-map worlds start at the free cell farthest from walls)");
  sub.add_option("--robot", a->job.robot_spec,
                 "Robot: a built-in name (" + Join(sensors::BuiltinRobotNames()) + ") or a robot JSON file")
      ->capture_default_str();
  sub.add_flag("--route", a->route, "Drive the world's waypoints wp01, wp02, ... in order (the default)");
  sub.add_flag("--explore", a->explore,
               "Drive to the nearest unseen reachable place until none is left (or the time limit)");
  sub.add_option("--seed", a->job.options.seed, "Random seed: the same seed gives the same log")->capture_default_str();
  sub.add_option("--drift-deg-per-m", a->drift_deg_per_m,
                 "Systematic odometry heading drift, degrees per metre driven (CCW positive)")
      ->capture_default_str();
  sub.add_option("--scale-error", a->job.options.odometry.scale_error, "Odometry distance scale error (0.01: reads 1 % long)")
      ->capture_default_str();
  sub.add_option("--speed", a->job.options.cruise_mps, "Cruise speed, m/s")->capture_default_str();
  sub.add_option("--rays", a->job.options.sensor.sonar_rays, "Rays sampling each sonar cone")->capture_default_str();
  sub.add_option("--sonar-bank-size", a->job.options.sonar_bank_size,
                 "Sonars per firing bank: one of each bank fires per record, every 40 ms (8: the Pioneer's two banks "
                 "of 8; 1: the whole ring in every record, as CARMEN's SONAR and RosAria's point cloud hold it)")
      ->capture_default_str();
  sub.add_option("--max-time", a->job.options.max_time_s,
                 "Bound on simulated seconds (0: automatic, from the route length; explore 3600 s)")
      ->capture_default_str();
  sub.add_option("--m-per-pixel", a->job.m_per_pixel, "Metres per pixel of a PNG world")->capture_default_str();
  sub.add_flag("--noiseless", a->job.noiseless, "Perfect odometry and noise-free ranges (specular effects stay)");
  sub.add_flag("--vfh-from-readings", a->job.options.vfh_from_readings,
               "Build VFH's certainty grid from the robot's own readings (HIMM) instead of the true walls");
  sub.add_option("-o,--output", a->job.output_path, "Native log to write")->required();
  return [a] { return RunSimulate(*a); };
}

// ------------------------------------------------------------ render-world
int RunRender(mapping::RenderWorldJob& job) {
  job.warning = [](const std::string& w) { std::fprintf(stderr, "cogmap: warning: %s\n", w.c_str()); };
  const mapping::RenderWorldResult r = mapping::RunRenderWorldJob(job);
  const FloorPlan& p = r.world;
  std::printf("%s: %zu walls, %zu rooms, %zu doors, %zu waypoints%s -> %s (%ldx%ld)\n", job.world_path.c_str(),
              p.walls.size(), p.rooms.size(), p.doorways.size(), p.route.size(),
              job.log_path.empty() ? "" : (", paths of " + job.log_path + " (green true, red odometry)").c_str(),
              job.picture_path.c_str(), r.width_px, r.height_px);
  return 0;
}

std::function<int()> SetupRender(CLI::App& sub) {
  auto a = std::make_shared<mapping::RenderWorldJob>();
  sub.add_option("WORLD", a->world_path, "World: an ARIA 2D-Map file, a PNG occupancy image, or a ROS map.yaml")
      ->required();
  sub.add_option("--log", a->log_path, "A run to draw: true path in green, odometry path in red");
  sub.add_option("--px-per-m", a->px_per_m,
                 "Pixels per metre (default: the picture fits 2000 px on its longest side)");
  sub.add_option("--m-per-pixel", a->m_per_pixel, "Metres per pixel of a PNG world")->capture_default_str();
  sub.add_option("-o,--output", a->picture_path, "Picture to write: .png, .svg or .pdf")->required();
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
  sub.add_option("--wing-deg", a->options.wing_deg,
                 "Not 0: a second wing like the first (seed + 1), turned by this many degrees (at most 60 either way) "
                 "and joined to its east end by a stretch of corridor; its rooms have no truth boxes (docs/simulator.md)")
      ->capture_default_str();
  sub.add_option("--wall-m", a->options.wall_m,
                 "Wall thickness, metres: 0 draws each wall as a line (one face each side); more draws its two "
                 "faces and ends, doors keeping their width (docs/simulator.md)")
      ->capture_default_str();
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
