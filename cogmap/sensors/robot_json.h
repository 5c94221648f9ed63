#pragma once
#include <nlohmann/json.hpp>
#include <string>

#include "cogmap/sensors/robot.h"

namespace cogmap::sensors {

// Robot descriptions as JSON (docs/log-format.md, "Robot JSON"):
//   {"name": "myrobot", "units": "m" | "mm", "angles": "deg" | "rad",
//    "radius": 0.26,
//    "sensors": [{"x": 0.069, "y": 0.136, "heading": 90, "beam_width": 30,
//                 "min_range": 0.15, "max_range": 5.0, "kind": "sonar"}],
//    "laser": {"beams": 181, "fov": 180, "max_range": 8.0, "min_range": 0.02}}
// "units" applies to x, y, radius and the ranges (default "m"); "angles" to
// heading, beam_width and fov (default "deg"). "sensors" and "laser" are each
// optional but at least one sensor must result; the laser's beams (MakeLaser)
// come after the listed sensors. Per sensor, beam_width/min_range/max_range/
// kind default to the RangeSensor defaults (30 deg, 0.15 m, 5 m, sonar).
// Unknown keys, wrong types and invalid values are InputErrors naming the
// source and the key ("robot.json: sensors[3].heading: expected a number").
RobotDescription ParseRobotJson(const nlohmann::json& j, const std::string& source_name);

// Reads and parses a robot JSON file (InputError for a missing file or bad JSON).
RobotDescription LoadRobotJson(const std::string& path);

// The description as JSON that ParseRobotJson reads back. Lengths in metres;
// angles in degrees, or in radians when 'angles_in_degrees' is false (then the
// round trip is bit-exact, which the native log uses).
nlohmann::json RobotToJson(const RobotDescription& robot, bool angles_in_degrees = true);

// A built-in robot name (BuiltinRobotNames) or else the path of a robot JSON
// file. InputError naming the argument when it is neither.
RobotDescription ResolveRobot(const std::string& name_or_path);

// True when the two descriptions are identical (every number bit-equal).
bool SameRobot(const RobotDescription& a, const RobotDescription& b);

}  // namespace cogmap::sensors
