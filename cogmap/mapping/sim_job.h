#pragma once
// `cogmap simulate` and `cogmap render-world` as one call each: a world read
// (ARIA 2D-Map, PNG occupancy image or ROS map.yaml), a simulated run written
// as a native log, or the world drawn with a run's paths (docs/simulator.md).
#include <functional>
#include <string>
#include <vector>

#include "cogmap/core/floor_plan.h"
#include "cogmap/core/pose2.h"
#include "cogmap/sensors/robot.h"
#include "cogmap/sim/simulator.h"

namespace cogmap::mapping {

// "X,Y,THETA_DEG" (metres, metres, degrees counter-clockwise) as a pose, the
// heading normalised to (-pi, pi]. Throws InputError naming --start.
Pose2 ParseStartPose(const std::string& text);

struct SimulateJob {
  std::string world_path;
  double m_per_pixel = 0.05;            // PNG worlds: metres per pixel
  std::string robot_spec = "pioneer16"; // a built-in robot or a robot JSON file
  sim::SimulatorOptions options;        // mode, start, seed, speed, rays, noise, ...
  bool noiseless = false;               // perfect odometry, noise-free ranges (specular effects stay)
  std::string output_path;              // the native log, written atomically
  std::function<void(double fraction)> progress;       // of the simulated time bound
  std::function<void(const std::string&)> warning;     // the world's, then the run's; one line each

  // Throws InputError naming the option (--speed, --rays, --max-time,
  // --drift-deg-per-m, --scale-error, --m-per-pixel; NaN and infinities too).
  void Validate() const;
};

struct SimulateJobResult {
  sensors::RobotDescription robot;
  sim::SimStats stats;
  double seconds = 0.0;  // the whole job, wall clock
};

// Reads the world, drives the robot through it and writes the log. Throws
// InputError for a bad option, an unreadable world, a world without walls, a
// route run in a world without a route; the log is then not written.
SimulateJobResult RunSimulateJob(const SimulateJob& job);

struct RenderWorldJob {
  std::string world_path;
  double m_per_pixel = 0.05;  // PNG worlds
  std::string log_path;       // "" = no run; else its true (green) and odometry (red) paths
  std::string picture_path;   // .png, .svg or .pdf
  double px_per_m = 0.0;      // 0: fit 2000 px on the longest side
  std::function<void(const std::string&)> warning;  // the world's, one line each
};

struct RenderWorldResult {
  FloorPlan world;
  long width_px = 0, height_px = 0;  // of the picture
};

// Draws the world (and the run) into job.picture_path. Throws InputError for a
// bad scale or picture format (before reading anything), a bad world or log.
RenderWorldResult RunRenderWorldJob(const RenderWorldJob& job);

}  // namespace cogmap::mapping
