#include "cogmap/asr/boundary_detector.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace cogmap::asr {

namespace {
constexpr double kEps = 1e-9;  // travel sums of exact steps must still reach a length
}  // namespace

SideSensors FindSideSensors(const sensors::RobotDescription& robot, double tolerance_rad) {
  SideSensors sides;
  for (size_t i = 0; i < robot.sensors.size(); ++i) {
    const double h = robot.sensors[i].robot_from_sensor.theta;
    if (std::abs(AngleDiff(h, kPi / 2)) <= tolerance_rad + 1e-9) sides.left.push_back(static_cast<int>(i));
    if (std::abs(AngleDiff(h, -kPi / 2)) <= tolerance_rad + 1e-9) sides.right.push_back(static_cast<int>(i));
  }
  return sides;
}

BoundaryDetector::BoundaryDetector(const sensors::RobotDescription& robot, const BoundaryOptions& options)
    : robot_(robot), options_(options), sides_(FindSideSensors(robot, options.side_tolerance_rad)) {
  side_of_.assign(robot.sensors.size(), 0);
  for (int i : sides_.left) side_of_[i] = 1;
  for (int i : sides_.right) side_of_[i] = -1;
}

std::pair<SideObservation, SideObservation> BoundaryDetector::ObserveSides(const sensors::LogRecord& record,
                                                                           double travel_m) {
  const Pose2 robot_from_world = record.odom.inverse();
  // How far across the robot an echo is remembered and looked at: close_m,
  // or with the gap rule the whole gap (the far jamb of an opening gap_m wide
  // lies almost gap_m away when the robot passes close to the near one).
  const double reach = std::max(options_.close_m, options_.gap_m);
  // Remember the new close echoes of the side sensors.
  for (const auto& r : record.ranges) {
    if (r.sensor < 0 || r.sensor >= static_cast<int>(side_of_.size()) || side_of_[r.sensor] == 0) continue;
    const auto& s = robot_.sensors[r.sensor];
    if (r.range_m < s.min_range_m || r.range_m >= s.max_range_m) continue;
    const Vec2 p = sensors::ReadingEndPoint(record.odom, s, r.range_m);
    const Vec2 q = robot_from_world * p;
    if (std::abs(q.y()) > reach || std::abs(q.x()) > options_.memory_m) continue;
    memory_.push_back({p, travel_m, side_of_[r.sensor] > 0});
  }
  while (!memory_.empty() && (travel_m - memory_.front().travel_m > options_.memory_m || memory_.size() > 512))
    memory_.pop_front();
  // What lies beside the robot now.
  SideObservation left, right;
  left.observed = right.observed = true;
  double best_l = std::numeric_limits<double>::infinity(), best_r = best_l;
  Vec2 point_l{0, 0}, point_r{0, 0};
  for (const Echo& e : memory_) {
    const Vec2 q = robot_from_world * e.point_m;
    if (std::abs(q.x()) > options_.side_window_m) continue;
    if (q.y() > 0.0 && q.y() <= reach && q.y() < best_l) {
      best_l = q.y();
      point_l = e.point_m;
    }
    if (q.y() < 0.0 && -q.y() <= reach && -q.y() < best_r) {
      best_r = -q.y();
      point_r = e.point_m;
    }
  }
  // Each side within close_m (the thesis), or both sides within gap_m of
  // each other across the robot (the gap rule).
  bool gap = options_.gap_m > 0.0 && best_l + best_r <= options_.gap_m;
  // A side beyond close_m counts only when its obstacle is the end of a
  // wall across the robot's way (a jamb), not a wall along it: the echoes
  // remembered on that side at about its distance span little of the way.
  // Both sides may be beyond close_m (an opening wider than 2 close_m,
  // crossed near its middle): then both must be jambs.
  auto jamb = [&](bool left_side, double far) {
    double lo = std::numeric_limits<double>::infinity(), hi = -lo;
    for (const Echo& e : memory_) {
      if (e.left != left_side) continue;
      const Vec2 q = robot_from_world * e.point_m;
      if (std::abs(q.x()) > options_.jamb_window_m || std::abs(std::abs(q.y()) - far) > options_.jamb_band_m) continue;
      lo = std::min(lo, q.x());
      hi = std::max(hi, q.x());
    }
    return hi - lo <= options_.jamb_extent_m;
  };
  if (gap && best_l > options_.close_m) gap = jamb(true, best_l);
  if (gap && best_r > options_.close_m) gap = jamb(false, best_r);
  left.close = best_l <= options_.close_m || gap;
  right.close = best_r <= options_.close_m || gap;
  if (left.close) left.point_m = point_l;
  if (right.close) right.point_m = point_r;
  return {left, right};
}

void BoundaryDetector::Advance(const Pose2& pose) {
  const Vec2 pos = pose.translation();
  if (have_pose_) {
    travel_m_ += (pos - last_pose_.translation()).norm();
  } else {
    prev_pos_ = pos;
    have_pose_ = true;
  }
  last_pose_ = pose;
  if ((pos - prev_pos_).norm() >= 0.2) {
    travel_dir_ = (pos - prev_pos_).normalized();
    has_travel_dir_ = true;
    prev_pos_ = pos;
  }
}

std::optional<BoundaryCut> BoundaryDetector::Push(const sensors::LogRecord& record) {
  Advance(record.odom);
  const auto [left, right] = ObserveSides(record, travel_m_);
  return Step(record.time_s, record.odom, left, right);
}

std::optional<BoundaryCut> BoundaryDetector::PushSides(double time_s, const Pose2& pose,
                                                       const SideObservation& left,
                                                       const SideObservation& right) {
  Advance(pose);
  return Step(time_s, pose, left, right);
}

void BoundaryDetector::UpdateSide(Side* side, const SideObservation& obs) const {
  if (!obs.observed) return;
  if (obs.close) {
    side->last_point = obs.point_m;
    side->has_point = true;
  }
  if (obs.close == side->on) {
    side->run = 0;
    return;
  }
  if (++side->run >= std::max(1, options_.debounce_sweeps)) {
    side->on = obs.close;
    side->run = 0;
  }
}

BoundaryCut BoundaryDetector::MakeCut(CutKind kind, const Pose2& pose, double time_s, double width_m) {
  BoundaryCut cut;
  cut.kind = kind;
  cut.pose = pose;
  cut.time_s = time_s;
  cut.center_m = pose.translation();
  cut.width_m = width_m;
  return cut;
}

Pose2 BoundaryDetector::PoseAtTravel(double travel_m, double* time_s) const {
  // First stretch sample at or past 'travel_m'.
  for (const auto& s : stretch_) {
    if (s.travel_m >= travel_m - 1e-12) {
      *time_s = s.time_s;
      return s.pose;
    }
  }
  *time_s = stretch_.back().time_s;
  return stretch_.back().pose;
}

std::optional<BoundaryCut> BoundaryDetector::Step(double time_s, const Pose2& pose, const SideObservation& left,
                                                  const SideObservation& right) {
  const Vec2 pos = pose.translation();
  UpdateSide(&left_, left);
  UpdateSide(&right_, right);

  if (options_.mode == BoundaryMode::kFixedLength) {
    if (asr_travel_m() >= options_.asr_length_m - kEps) {
      asr_start_travel_m_ = travel_m_;
      return MakeCut(CutKind::kFixedLength, pose, time_s, 0.0);
    }
    return std::nullopt;
  }

  if (options_.max_asr_m > 0.0 && state_ == BoundaryState::kInRoom &&
      asr_travel_m() >= options_.max_asr_m - kEps) {
    asr_start_travel_m_ = travel_m_;
    return MakeCut(CutKind::kMaxLength, pose, time_s, 0.0);
  }

  const bool both = left_.on && right_.on;
  const double width_now = (both && left_.has_point && right_.has_point)
                               ? (left_.last_point - right_.last_point).norm()
                               : 0.0;
  if (state_ == BoundaryState::kInRoom) {
    if (!both) return std::nullopt;
    state_ = BoundaryState::kAtAccessPoint;
    stretch_.clear();
    stretch_.push_back({pose, time_s, travel_m_});
    entry_dir_ = has_travel_dir_ ? travel_dir_ : Vec2(std::cos(pose.theta), std::sin(pose.theta));
    max_depth_m_ = 0.0;
    min_width_m_ = width_now;
    corridor_ = false;
    return std::nullopt;
  }

  // At an access point.
  stretch_.push_back({pose, time_s, travel_m_});
  const Vec2 p0 = stretch_.front().pose.translation();
  max_depth_m_ = std::max(max_depth_m_, entry_dir_.dot(pos - p0));
  if (width_now > 0.0 && (min_width_m_ <= 0.0 || width_now < min_width_m_)) min_width_m_ = width_now;

  if (!both) {  // L or R released
    if (!releasing_) {
      releasing_ = true;
      release_ = stretch_.back();
      release_max_depth_m_ = max_depth_m_;
    }
    // Still within a side opening's length: wait (the state stays at the
    // access point, so the mapper keeps the records to replay).
    if (travel_m_ - release_.travel_m < options_.release_confirm_m - kEps) return std::nullopt;
    // The L-and-R stretch ended where the release began: back in a room.
    releasing_ = false;
    state_ = BoundaryState::kInRoom;
    const double release_travel = release_.travel_m;
    if (corridor_) {
      if (release_travel - asr_start_travel_m_ < options_.min_asr_m - kEps) return std::nullopt;
      asr_start_travel_m_ = release_travel;
      return MakeCut(CutKind::kCorridorExit, release_.pose, release_.time_s, min_width_m_);
    }
    const double depth = entry_dir_.dot(release_.pose.translation() - p0);
    if (depth <= 0.0 || depth <= 0.5 * release_max_depth_m_) {
      ++turn_backs_;  // left on the side it came in: the same room
      return std::nullopt;
    }
    double cut_time = release_.time_s;
    const double mid = 0.5 * (stretch_.front().travel_m + release_travel);
    const Pose2 cut_pose = PoseAtTravel(mid, &cut_time);
    asr_start_travel_m_ = mid;
    BoundaryCut cut = MakeCut(CutKind::kDoorway, cut_pose, cut_time, min_width_m_);
    stretch_.clear();
    return cut;
  }
  releasing_ = false;  // both on again: the gap was a side opening

  const double stretch_m = travel_m_ - stretch_.front().travel_m;
  if (!corridor_ && stretch_m > options_.corridor_m + kEps) {
    corridor_ = true;
    const StretchSample mouth = stretch_.front();
    if (mouth.travel_m - asr_start_travel_m_ >= options_.min_asr_m - kEps) {
      asr_start_travel_m_ = mouth.travel_m;
      stretch_.erase(stretch_.begin() + 1, stretch_.end());  // keep the mouth only
      return MakeCut(CutKind::kCorridorEntry, mouth.pose, mouth.time_s, min_width_m_);
    }
  }
  if (corridor_) {
    stretch_.erase(stretch_.begin() + 1, stretch_.end());  // nothing else needed in a corridor
    if (asr_travel_m() >= options_.asr_length_m - kEps) {
      asr_start_travel_m_ = travel_m_;
      return MakeCut(CutKind::kCorridor, pose, time_s, width_now > 0.0 ? width_now : min_width_m_);
    }
  }
  return std::nullopt;
}

}  // namespace cogmap::asr
