#pragma once
// report.json of `cogmap map` (docs/pose-graph.md describes its pose_graph
// section).
#include <nlohmann/json.hpp>
#include <optional>
#include <ostream>
#include <string>
#include <vector>

#include "cogmap/asr/asr.h"
#include "cogmap/asr/room_metrics.h"
#include "cogmap/localize/heading_error.h"
#include "cogmap/mapping/pipeline.h"

namespace cogmap::mapping {

struct MapJob;

struct ReportContext {
  const MapJob* job = nullptr;
  const sensors::RobotDescription* robot = nullptr;
  const RunResult* run = nullptr;
  const std::vector<asr::Asr>* all = nullptr;  // every ASR in the store
  const localize::HeadingErrorStats* heading = nullptr;
  int exits = 0;
  int rooms = 0;
  std::string store_path;
  std::string run_id;
  double mapping_seconds = 0.0;
  double total_seconds = 0.0;
  double startup_seconds = 0.0;
  long rss_mapping_kb = 0;
  std::optional<asr::RoomMetrics> room_metrics;
};

// report.json's text (nlohmann's dump(2) and a newline), written as it is
// made: the per-ASR arrays (asrs, pose_graph.placements and
// closure_candidates) one entry at a time (io::JsonStreams).
void WriteReport(const ReportContext& c, std::ostream& out);
// One ASR's entry of report.json's "asrs".
nlohmann::json AsrJson(const AsrSummary& s);

}  // namespace cogmap::mapping
