#pragma once
#include <cmath>
#include <Eigen/Core>

#include "cogmap/core/pose2.h"

namespace cogmap::grid {

using CellIndex = Eigen::Vector2i;  // (column x, row y); y grows with world y

// All cell <-> metre maths (after Cartographer's MapLimits). Cell (0, 0) is the
// lower-left cell; its lower-left corner sits at 'origin' in the world frame,
// like the origin of a ROS map_server YAML.
class MapLimits {
 public:
  MapLimits() = default;
  MapLimits(double cell_m, const Vec2& origin, int width, int height)
      : cell_m_(cell_m), origin_(origin), width_(width), height_(height) {}

  double cell_m() const { return cell_m_; }
  const Vec2& origin() const { return origin_; }
  int width() const { return width_; }
  int height() const { return height_; }
  long cell_count() const { return static_cast<long>(width_) * height_; }

  CellIndex CellOf(const Vec2& p) const {
    return {static_cast<int>(std::floor((p.x() - origin_.x()) / cell_m_)),
            static_cast<int>(std::floor((p.y() - origin_.y()) / cell_m_))};
  }
  Vec2 CenterOf(const CellIndex& c) const {
    return {origin_.x() + (c.x() + 0.5) * cell_m_, origin_.y() + (c.y() + 0.5) * cell_m_};
  }
  // Continuous cell coordinates (cell centres at .5).
  Vec2 ToCellCoords(const Vec2& p) const { return (p - origin_) / cell_m_; }
  Vec2 FromCellCoords(const Vec2& c) const { return origin_ + c * cell_m_; }

  bool Contains(const CellIndex& c) const {
    return c.x() >= 0 && c.y() >= 0 && c.x() < width_ && c.y() < height_;
  }
  long Flat(const CellIndex& c) const { return static_cast<long>(c.y()) * width_ + c.x(); }
  long Flat(int x, int y) const { return static_cast<long>(y) * width_ + x; }

  Vec2 max() const { return origin_ + Vec2(width_ * cell_m_, height_ * cell_m_); }

 private:
  double cell_m_ = 0.1;
  Vec2 origin_{0, 0};
  int width_ = 0;
  int height_ = 0;
};

}  // namespace cogmap::grid
