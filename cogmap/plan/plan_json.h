#pragma once
// The floor plan as JSON (OUTDIR/plan.json, docs/floor-plan.md): written by
// `cogmap map`, read by `cogmap eval` and the drawing and file writers.
#include <ostream>
#include <string>

#include <nlohmann/json.hpp>

#include "cogmap/plan/plan.h"

namespace cogmap::plan {

constexpr const char* kPlanFormat = "cogmap-plan";
constexpr int kPlanFormatVersion = 1;

nlohmann::json PlanToJson(const Plan& plan);
// The JSON text (2-space indent, PlanToJson(plan).dump(2) and a newline);
// WriteFileAtomically (cogmap/io) puts it on disk.
std::string PlanToJsonText(const Plan& plan);
// The same text written to 'out' a wall, door, room or edge at a time (no
// document of the whole plan in memory).
void WritePlanJson(std::ostream& out, const Plan& plan);

// Validates as it reads: a wrong type, a missing key, a non-finite number, a
// wall of fewer than 2 points, a room polygon of fewer than 3, or an id that
// names no room or door throws InputError("SOURCE: <where>: <problem>").
Plan PlanFromJson(const nlohmann::json& j, const std::string& source);
Plan ParsePlanJson(const std::string& text, const std::string& source);
// Reads 'path' (InputError naming it when it cannot be read or is not a plan).
Plan ReadPlanJson(const std::string& path);

}  // namespace cogmap::plan
