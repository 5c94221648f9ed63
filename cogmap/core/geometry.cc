#include "cogmap/core/geometry.h"

namespace cogmap {

std::vector<Segment2> ToSegments(const std::vector<Polyline>& lines) {
  std::vector<Segment2> out;
  for (const auto& line : lines)
    for (size_t i = 1; i < line.size(); ++i) out.push_back({line[i - 1], line[i]});
  return out;
}

Polyline Transform(const Pose2& pose, const Polyline& line) {
  Polyline out;
  out.reserve(line.size());
  for (const auto& p : line) out.push_back(pose * p);
  return out;
}

std::vector<Polyline> Transform(const Pose2& pose, const std::vector<Polyline>& lines) {
  std::vector<Polyline> out;
  out.reserve(lines.size());
  for (const auto& l : lines) out.push_back(Transform(pose, l));
  return out;
}

}  // namespace cogmap
