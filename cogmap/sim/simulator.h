#pragma once
#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "cogmap/core/angles.h"
#include "cogmap/core/floor_plan.h"
#include "cogmap/sensors/reading.h"
#include "cogmap/sensors/robot.h"
#include "cogmap/sim/odometry.h"
#include "cogmap/sim/sensor_model.h"
#include "cogmap/sim/vfh.h"

namespace cogmap::sim {

enum class SimMode {
  kRoute,    // drive the floor plan's waypoints in order
  kExplore,  // drive to the nearest unseen reachable place until none is left
};

// Every default is documented in docs/simulator.md.
struct SimulatorOptions {
  SimMode mode = SimMode::kRoute;
  uint64_t seed = 1;
  std::optional<Pose2> start;  // overrides the floor plan's RobotHome

  // Motion (Pioneer 3-DX; the thesis drives at 0.5 m/s, §4).
  double cruise_mps = 0.5;
  double max_turn_rate_rad_s = DegToRad(100.0);  // ARIA's default RotVelMax
  double accel_mps2 = 0.3;                        // ARIA's default TransAccel (300 mm/s^2)
  double step_s = 0.02;                           // physics and odometry step

  // Sensor timing. The Pioneer fires one transducer per bank every 40 ms
  // (25 Hz); the 16-ring has two banks of 8 (front, rear) firing in parallel,
  // so a full sweep takes 8 x 40 ms = 0.32 s. One LogRecord per firing.
  double sonar_interval_s = 0.04;
  int sonar_bank_size = 8;
  double laser_interval_s = 0.1;  // all laser beams in one record, 10 Hz

  // Navigation.
  double control_interval_s = 0.1;  // VFH and steering, 10 Hz
  double nav_cell_m = 0.1;          // configuration-space grid
  double nav_margin_m = 0.08;       // passable: clearance >= radius + margin
  double lookahead_m = 1.5;         // carrot distance along the planned path
  double replan_interval_s = 1.0;
  double waypoint_tolerance_m = 0.2;  // a waypoint is reached within this distance
  double waypoint_snap_m = 0.3;       // a waypoint too near a wall moves this far at most
  double stall_timeout_s = 60.0;      // no progress for this long: skip the waypoint
  // Upper bound of simulated time; 0 picks one: route: 300 s + 4 x the length
  // of the straight legs / cruise + 30 s per waypoint; explore: 3600 s.
  double max_time_s = 0.0;
  double explore_idle_s = 300.0;  // explore ends when no new free cell was seen for this long
  // A target given up (stall_timeout_s without progress) takes the unseen
  // cells within this radius with it: the way to them is the same blocked
  // one, and giving them up one by one used the whole explore_idle_s
  // (Freiburg52 with furniture: the sonar robot stopped after one room).
  double explore_give_up_radius_m = 1.0;
  // VFH blocked in every sector for this long: drive to the planner's aim
  // point anyway (the physics keeps the robot off the walls). Without it a
  // robot wedged among chairs turned in place for the rest of the run.
  double blocked_escape_s = 3.0;
  double seen_range_m = 3.0;  // coverage: cells along sensor rays up to this range count as seen

  // VFH's certainty grid: false: the true walls (c = 1 on every cell a wall
  // crosses); true: the robot's own readings, HIMM-style (+3 at the echo cell,
  // -1 along the sensor axis before it, within [0, 15]; no echo clears 2 m).
  bool vfh_from_readings = false;

  SensorModelOptions sensor;
  OdometryNoiseOptions odometry;
  VfhOptions vfh;
};

struct SimStats {
  double simulated_s = 0.0;
  double distance_m = 0.0;  // true distance driven
  int waypoints_total = 0;
  int waypoints_reached = 0;
  long records = 0;
  long blocked_steps = 0;    // steps whose translation was refused (would touch a wall)
  double min_clearance_m = 0.0;  // smallest true distance from the robot centre to a wall
  double coverage = 0.0;     // fraction of the free area reachable from the start seen by the sensors
  bool time_limit_reached = false;
  std::vector<std::string> warnings;  // skipped waypoints and the like, one line each
};

// Drives 'robot' through 'plan' and calls 'emit' with every record (true pose
// in LogRecord::truth). 'progress' (optional) gets a fraction in [0, 1].
// Throws InputError for a world without walls, a robot without sensors, or a
// start pose inside a wall. Always ends within the simulated time bound.
SimStats Simulate(const FloorPlan& plan, const sensors::RobotDescription& robot,
                  const SimulatorOptions& options,
                  const std::function<void(const sensors::LogRecord&)>& emit,
                  const std::function<void(double)>& progress = {});

}  // namespace cogmap::sim
