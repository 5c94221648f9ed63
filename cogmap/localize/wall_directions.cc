#include "cogmap/localize/wall_directions.h"

#include <cmath>

#include "cogmap/core/angles.h"

namespace cogmap::localize {

double FoldToQuarterTurn(double direction_rad) {
  constexpr double kQuarter = kPi / 2.0;
  double r = std::fmod(direction_rad + kQuarter / 2.0, kQuarter);
  if (r < 0.0) r += kQuarter;
  double folded = r - kQuarter / 2.0;
  // Rounding can leave exactly +pi/4; the interval is half-open.
  if (folded >= kQuarter / 2.0) folded -= kQuarter;
  return folded;
}

std::vector<WallDirection> WallDirections(const std::vector<Polyline>& walls, double min_edge_m) {
  std::vector<WallDirection> out;
  for (const auto& line : walls) {
    for (size_t i = 1; i < line.size(); ++i) {
      const Vec2 d = line[i] - line[i - 1];
      const double len = d.norm();
      if (!(len > min_edge_m) || !std::isfinite(len)) continue;
      out.push_back({FoldToQuarterTurn(std::atan2(d.y(), d.x())), len});
    }
  }
  return out;
}

std::vector<WallDirection> WallDirectionsWorldRaw(const asr::Asr& asr) {
  return WallDirections(asr.WallsWorldRaw());
}

std::vector<double> MotorDirections(const asr::Asr& asr, double min_chord_m) {
  std::vector<double> out;
  auto add_chord = [&](const Vec2& a, const Vec2& b) {
    const Vec2 d = b - a;
    if (!(d.norm() >= min_chord_m) || !std::isfinite(d.norm())) return;
    out.push_back(FoldToQuarterTurn(std::atan2(d.y(), d.x())));
  };
  if (!asr.exits.empty()) {
    Vec2 from = asr.entry_pivot_m;
    for (const auto& exit : asr.exits) {
      add_chord(from, exit.center_m);
      from = exit.center_m;
    }
  } else if (asr.path.size() >= 2) {
    add_chord(asr.path.front().translation(), asr.path.back().translation());
  }
  return out;
}

}  // namespace cogmap::localize
