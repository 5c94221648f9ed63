#include "cogmap/sim/simulator.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>

#include "cogmap/core/bresenham.h"
#include "cogmap/core/error.h"
#include "cogmap/sim/nav_grid.h"
#include "cogmap/sim/world.h"

namespace cogmap::sim {
namespace {

std::string Fmt(const char* fmt, double a) {
  char buf[160];
  std::snprintf(buf, sizeof buf, fmt, a);
  return buf;
}

std::string At(const Vec2& p) { return Fmt("(%.2f, ", p.x()) + Fmt("%.2f)", p.y()); }

// Free cells reachable from 'start' (centres off the walls, neighbours joined
// when the line between their centres crosses no wall).
std::vector<uint8_t> FreeArea(const World& world, const grid::MapLimits& lim, const Vec2& start,
                              long* count) {
  std::vector<uint8_t> free(lim.cell_count(), 0);
  *count = 0;
  const auto c0 = lim.CellOf(start);
  if (!lim.Contains(c0)) return free;
  std::vector<long> stack{lim.Flat(c0)};
  free[lim.Flat(c0)] = 1;
  const int w = lim.width(), h = lim.height();
  while (!stack.empty()) {
    const long cur = stack.back();
    stack.pop_back();
    ++*count;
    const int cx = static_cast<int>(cur % w), cy = static_cast<int>(cur / w);
    const Vec2 pc = lim.CenterOf({cx, cy});
    // Far from every wall, no step to a neighbour can cross one.
    const bool open = world.Clearance(pc, 1.01 * lim.cell_m()) >= 1.01 * lim.cell_m();
    static constexpr int kDx[4] = {1, -1, 0, 0}, kDy[4] = {0, 0, 1, -1};
    for (int k = 0; k < 4; ++k) {
      const int nx = cx + kDx[k], ny = cy + kDy[k];
      if (nx < 0 || ny < 0 || nx >= w || ny >= h) continue;
      const long nf = lim.Flat(nx, ny);
      if (free[nf]) continue;
      if (!open && !world.LineOfSight(pc, lim.CenterOf({nx, ny}))) continue;
      free[nf] = 1;
      stack.push_back(nf);
    }
  }
  return free;
}

}  // namespace

SimStats Simulate(const FloorPlan& plan, const sensors::RobotDescription& robot,
                  const SimulatorOptions& o, const std::function<void(const sensors::LogRecord&)>& emit,
                  const std::function<void(double)>& progress) {
  if (plan.walls.empty()) throw InputError("world has no walls (its LINES section is empty)");
  if (robot.sensors.empty()) throw InputError("robot '" + robot.name + "' has no range sensors");
  if (!(o.step_s > 0) || !(o.cruise_mps > 0) || !(o.nav_cell_m > 0))
    throw InputError("simulator: step, speed and cell size must be positive");
  Pose2 truth;
  if (o.start) truth = *o.start;
  else if (plan.home) truth = *plan.home;
  else if (!plan.route.empty()) truth = plan.route.front().pose;
  else throw InputError("world has no RobotHome and no route: give a start pose");

  const double radius = robot.radius_m;
  const World world(plan.walls);
  std::vector<Vec2> extra{truth.translation()};
  for (const auto& wp : plan.route) extra.push_back(wp.pose.translation());
  const grid::MapLimits lim = LimitsAround(world, extra, o.nav_cell_m, 1.0);
  if (lim.cell_count() > 60'000'000L)
    throw InputError(Fmt("world spans %.0f x ", lim.width() * lim.cell_m()) +
                     Fmt("%.0f m: too large for the navigation grid (at most 60 million cells; raise "
                         "nav_cell_m)", lim.height() * lim.cell_m()));
  const NavGrid nav(world, lim, radius, o.nav_margin_m);
  if (world.Clearance(truth.translation(), radius) < radius)
    throw InputError("start pose " + At(truth.translation()) + " is inside a wall or within the robot radius (" +
                     Fmt("%.2f m", radius) + ") of one");

  SimStats stats;
  stats.waypoints_total = o.mode == SimMode::kRoute ? static_cast<int>(plan.route.size()) : 0;
  long free_count = 0, seen_free = 0;
  const std::vector<uint8_t> free = FreeArea(world, lim, truth.translation(), &free_count);
  std::vector<uint8_t> seen(lim.cell_count(), 0), given_up(lim.cell_count(), 0);
  std::vector<uint8_t> certainty;  // VFH's grid when built from the readings
  if (o.vfh_from_readings) certainty.assign(lim.cell_count(), 0);
  auto mark_seen = [&](long f) {
    if (seen[f]) return;
    seen[f] = 1;
    if (free[f]) ++seen_free;
  };
  auto mark_ray = [&](const Vec2& a, const Vec2& b) {
    Vec2 e = b;
    const double len = (b - a).norm();
    if (len > o.seen_range_m) e = a + (b - a) * (o.seen_range_m / len);
    const auto ca = lim.CellOf(a), cb = lim.CellOf(e);
    WalkBresenham(ca.x(), ca.y(), cb.x(), cb.y(), [&](int x, int y) {
      if (x < 0 || y < 0 || x >= lim.width() || y >= lim.height()) return false;
      mark_seen(lim.Flat(x, y));
      return true;
    });
  };
  auto clear_certainty_under_robot = [&](const Vec2& p) {
    if (certainty.empty()) return;
    const auto c = lim.CellOf(p);
    const int r = static_cast<int>(std::ceil(radius / lim.cell_m()));
    for (int dy = -r; dy <= r; ++dy)
      for (int dx = -r; dx <= r; ++dx) {
        const grid::CellIndex q(c.x() + dx, c.y() + dy);
        if (lim.Contains(q) && (lim.CenterOf(q) - p).norm() <= radius) certainty[lim.Flat(q)] = 0;
      }
  };
  auto mark_footprint = [&](const Vec2& p) {
    const auto c = lim.CellOf(p);
    const int r = static_cast<int>(std::ceil(radius / lim.cell_m()));
    for (int dy = -r; dy <= r; ++dy)
      for (int dx = -r; dx <= r; ++dx) {
        const grid::CellIndex q(c.x() + dx, c.y() + dy);
        if (lim.Contains(q) && (lim.CenterOf(q) - p).norm() <= radius) mark_seen(lim.Flat(q));
      }
  };

  // Time bound.
  double max_time = o.max_time_s;
  if (max_time <= 0) {
    if (o.mode == SimMode::kExplore) {
      max_time = 3600.0;
    } else {
      double legs = 0.0;
      Vec2 prev = truth.translation();
      for (const auto& wp : plan.route) {
        legs += (wp.pose.translation() - prev).norm();
        prev = wp.pose.translation();
      }
      max_time = 300.0 + 4.0 * legs / o.cruise_mps + 30.0 * plan.route.size();
    }
  }

  std::mt19937_64 rng(o.seed);
  OdometryModel odo(truth, o.odometry);

  // Sensor firing schedule: sonars in banks, one unit per bank per slot.
  std::vector<std::vector<int>> banks;
  std::vector<int> lasers;
  for (int i = 0; i < static_cast<int>(robot.sensors.size()); ++i) {
    if (robot.sensors[i].kind == sensors::SensorKind::kLaser) {
      lasers.push_back(i);
    } else {
      if (banks.empty() || static_cast<int>(banks.back().size()) >= std::max(1, o.sonar_bank_size))
        banks.emplace_back();
      banks.back().push_back(i);
    }
  }
  auto every = [&](double interval) { return std::max<long>(1, std::lround(interval / o.step_s)); };
  const long sonar_every = every(o.sonar_interval_s), laser_every = every(o.laser_interval_s),
             control_every = every(o.control_interval_s), replan_every = every(o.replan_interval_s);
  long sonar_slot = 0;
  std::vector<std::pair<Vec2, Vec2>> rays;
  auto himm = [&](int s, double range_m) {
    if (certainty.empty()) return;
    const auto& sensor = robot.sensors[s];
    const bool echo = range_m < sensor.max_range_m;
    const double len = echo ? range_m : std::min(sensor.max_range_m, 2.0);
    const Vec2 a = sensors::SensorPose(truth, sensor).translation();
    const Vec2 b = sensors::ReadingEndPoint(truth, sensor, len);
    const auto ca = lim.CellOf(a), cb = lim.CellOf(b);
    WalkBresenham(ca.x(), ca.y(), cb.x(), cb.y(), [&](int x, int y) {
      if (x < 0 || y < 0 || x >= lim.width() || y >= lim.height()) return false;
      uint8_t& c = certainty[lim.Flat(x, y)];
      if (echo && x == cb.x() && y == cb.y()) c = static_cast<uint8_t>(std::min(15, c + 3));
      else if (c > 0) --c;
      return true;
    });
  };

  // Navigation state.
  size_t next_wp = 0;
  bool active = false;
  Vec2 goal_point(0, 0);
  long goal_cell = -1;
  std::string goal_name;
  std::vector<long> path;
  double best_dist = std::numeric_limits<double>::infinity(), last_progress_t = 0.0;
  bool done = false;
  double v = 0.0, v_cmd = 0.0, omega_cmd = 0.0;
  stats.min_clearance_m = std::numeric_limits<double>::infinity();

  auto robot_cell = [&]() -> long {
    if (nav.Passable(truth.translation())) return lim.Flat(lim.CellOf(truth.translation()));
    return nav.NearestPassable(truth.translation(), 0.6);
  };
  auto plan_path = [&]() {
    const long start = robot_cell();
    if (o.mode == SimMode::kRoute) {
      path = nav.FindPath(start, [&](long c) { return c == goal_cell; });
    } else {
      path = nav.FindPath(start, [&](long c) { return !seen[c] && !given_up[c]; });
      if (!path.empty()) {
        goal_cell = path.back();
        goal_point = lim.CenterOf({static_cast<int>(goal_cell % lim.width()),
                                   static_cast<int>(goal_cell / lim.width())});
      }
    }
  };
  auto start_next_waypoint = [&](double t) {
    while (!active && next_wp < plan.route.size()) {
      const Waypoint& wp = plan.route[next_wp++];
      const Vec2 p = wp.pose.translation();
      goal_name = wp.name.empty() ? "waypoint " + std::to_string(next_wp) : wp.name;
      if ((p - truth.translation()).norm() < o.waypoint_tolerance_m) {
        ++stats.waypoints_reached;
        continue;
      }
      goal_cell = nav.Passable(p) ? lim.Flat(lim.CellOf(p)) : nav.NearestPassable(p, o.waypoint_snap_m);
      if (goal_cell < 0) {
        stats.warnings.push_back("waypoint " + goal_name + " at " + At(p) +
                                 " is inside a wall or too close to one for the robot; skipped");
        continue;
      }
      goal_point = nav.Passable(p) ? p
                                   : lim.CenterOf({static_cast<int>(goal_cell % lim.width()),
                                                   static_cast<int>(goal_cell / lim.width())});
      plan_path();
      if (path.empty()) {
        stats.warnings.push_back("waypoint " + goal_name + " at " + At(p) + " is unreachable from " +
                                 At(truth.translation()) + "; skipped");
        continue;
      }
      active = true;
      best_dist = (goal_point - truth.translation()).norm();
      last_progress_t = t;
    }
  };
  // A straight move from the robot to 'p' keeps the body clear of the walls
  // by the VFH safety distance.
  const double line_clear = radius + o.vfh.safety_m + 0.02;
  auto clear_line = [&](const Vec2& a, const Vec2& b) {
    const double len = (b - a).norm();
    const int k = std::max(1, static_cast<int>(std::ceil(len / 0.05)));
    for (int i = 1; i <= k; ++i) {
      const Vec2 p = a + (b - a) * (static_cast<double>(i) / k);
      if ((p - a).norm() < 0.15) continue;  // leaving a tight spot is allowed
      if (world.Clearance(p, line_clear) < line_clear) return false;
    }
    return true;
  };
  auto cell_centre = [&](long c) {
    return lim.CenterOf({static_cast<int>(c % lim.width()), static_cast<int>(c / lim.width())});
  };
  auto carrot = [&]() -> Vec2 {
    const Vec2 pos = truth.translation();
    if ((goal_point - pos).norm() <= o.lookahead_m && clear_line(pos, goal_point)) return goal_point;
    if (path.empty()) return goal_point;
    // Nearest path cell to the robot, then the farthest visible one ahead.
    size_t near = 0;
    double nd = std::numeric_limits<double>::infinity();
    for (size_t i = 0; i < path.size() && i < 40; ++i) {
      const double d = (cell_centre(path[i]) - pos).norm();
      if (d < nd) {
        nd = d;
        near = i;
      }
    }
    size_t far = near;
    while (far + 1 < path.size() && (cell_centre(path[far + 1]) - pos).norm() <= o.lookahead_m) ++far;
    for (size_t i = far; i > near; --i)
      if (clear_line(pos, cell_centre(path[i]))) return cell_centre(path[i]);
    return cell_centre(path[std::min(near + 1, path.size() - 1)]);
  };

  auto fire = [&](long tick, double t) {
    sensors::LogRecord rec;
    bool any = false;
    if (!banks.empty() && tick % sonar_every == 0) {
      for (const auto& bank : banks) {
        const int s = bank[sonar_slot % bank.size()];
        rays.clear();
        const double r = SimulateReading(world, truth, robot.sensors[s], o.sensor, rng, &rays);
        for (const auto& [a, b] : rays) mark_ray(a, b);
        himm(s, r);
        rec.ranges.push_back({s, r});
      }
      ++sonar_slot;
      any = true;
    }
    if (!lasers.empty() && tick % laser_every == 0) {
      for (int s : lasers) {
        rays.clear();
        const double r = SimulateReading(world, truth, robot.sensors[s], o.sensor, rng, &rays);
        for (const auto& [a, b] : rays) mark_ray(a, b);
        himm(s, r);
        rec.ranges.push_back({s, r});
      }
      any = true;
    }
    if (!any) return;
    rec.time_s = t;
    rec.odom = odo.pose();
    rec.truth = truth;
    ++stats.records;
    if (emit) emit(rec);
  };

  mark_footprint(truth.translation());
  long tick = 0;
  double t = 0.0;
  long last_seen_free = -1;
  double last_seen_t = 0.0, last_give_up_t = 0.0, blocked_since = -1.0;
  if (o.mode == SimMode::kRoute) start_next_waypoint(t);
  for (;; ++tick) {
    t = tick * o.step_s;
    fire(tick, t);
    if (tick % control_every == 0) {
      const Vec2 pos = truth.translation();
      if (o.mode == SimMode::kRoute) {
        if (active && (goal_point - pos).norm() < o.waypoint_tolerance_m) {
          ++stats.waypoints_reached;
          active = false;
        }
        if (active && t - last_progress_t > o.stall_timeout_s) {
          stats.warnings.push_back("waypoint " + goal_name + " at " + At(goal_point) + " not reached within " +
                                   Fmt("%.0f s", o.stall_timeout_s) + " of no progress; skipped");
          active = false;
        }
        if (!active) start_next_waypoint(t);
        if (!active) done = true;
        else if (tick % replan_every == 0) plan_path();
      } else {
        if (seen_free != last_seen_free) {
          last_seen_free = seen_free;
          last_seen_t = t;
        } else if (t - last_seen_t > o.explore_idle_s) {
          stats.warnings.push_back(Fmt("explore: nothing new seen for %.0f s; stopped", o.explore_idle_s));
          break;
        }
        bool need = path.empty() || tick % replan_every == 0 || seen[goal_cell] || given_up[goal_cell];
        // Stalled: no closer to the target, or (the nearest unseen cell
        // changing as the robot wriggles in front of a blocked way) nothing
        // new seen, for stall_timeout_s.
        if (!path.empty() && (t - last_progress_t > o.stall_timeout_s ||
                              t - std::max(last_seen_t, last_give_up_t) > o.stall_timeout_s)) {
          last_give_up_t = t;
          // Cannot get there; nor to the unseen cells around it, which the
          // same blocked way (chairs round a table) leads to: try elsewhere.
          const int gx = static_cast<int>(goal_cell % lim.width()), gy = static_cast<int>(goal_cell / lim.width());
          const int rc = static_cast<int>(std::ceil(o.explore_give_up_radius_m / lim.cell_m()));
          for (int dy = -rc; dy <= rc; ++dy)
            for (int dx = -rc; dx <= rc; ++dx)
              if (dx * dx + dy * dy <= rc * rc && lim.Contains({gx + dx, gy + dy}))
                given_up[lim.Flat({gx + dx, gy + dy})] = 1;
          need = true;
        }
        if (need) {
          const long old = goal_cell;
          plan_path();
          if (path.empty()) done = true;
          else if (goal_cell != old) {
            best_dist = (goal_point - pos).norm();
            last_progress_t = t;
          }
        }
      }
      if (done) break;
      const double d = (goal_point - pos).norm();
      if (d < best_dist - 0.1) {
        best_dist = d;
        last_progress_t = t;
      }
      const Vec2 c = carrot();
      const double want = std::atan2(c.y() - pos.y(), c.x() - pos.x());
      const VfhResult steer =
          o.vfh_from_readings
              ? VfhSteerCertainty(lim, certainty, 15.0, pos, want, radius, o.vfh, (c - pos).norm())
              : VfhSteer(nav, pos, want, radius, o.vfh, (c - pos).norm());
      // Everything blocked: with the true walls, turn toward the aim point in
      // place; with the robot's own certainty grid (phantom echoes), trust the
      // planner's aim point, whose straight line is known to be clear. Blocked
      // for longer than blocked_escape_s (wedged between chairs, where the
      // histogram's safety distance closes every sector but the planner's
      // clearance does not), the aim point is trusted too: the physics still
      // stops the robot short of any wall.
      if (steer.free) blocked_since = -1.0;
      else if (blocked_since < 0.0) blocked_since = t;
      const bool go = steer.free || o.vfh_from_readings || t - blocked_since > o.blocked_escape_s;
      const double heading = steer.free ? steer.heading_rad : want;
      const double err = AngleDiff(heading, truth.theta);
      v_cmd = (!go || std::abs(err) > DegToRad(60.0)) ? 0.0 : o.cruise_mps * std::cos(err);
      if (o.mode == SimMode::kRoute) v_cmd = std::min(v_cmd, std::max(0.15, d));
      omega_cmd = std::clamp(3.0 * err, -o.max_turn_rate_rad_s, o.max_turn_rate_rad_s);
      if (progress && tick % (control_every * 50) == 0)
        progress(o.mode == SimMode::kRoute
                     ? static_cast<double>(next_wp) / std::max<size_t>(1, plan.route.size())
                     : std::min(1.0, static_cast<double>(seen_free) / std::max<long>(1, free_count)));
    }
    if (t >= max_time) {
      stats.time_limit_reached = true;
      stats.warnings.push_back(Fmt("simulated time limit of %.0f s reached", max_time) +
                               (o.mode == SimMode::kRoute
                                    ? " with " + std::to_string(plan.route.size() - next_wp + (active ? 1 : 0)) +
                                          " waypoints left"
                                    : std::string()));
      break;
    }
    // Physics: accelerate, turn, move unless the footprint would touch a wall.
    const double dv = o.accel_mps2 * o.step_s;
    v = std::clamp(v_cmd, v - dv, v + dv);
    const double dtheta = omega_cmd * o.step_s;
    double trans = v * o.step_s;
    const double mid = truth.theta + 0.5 * dtheta;
    const Vec2 next = truth.translation() + trans * Vec2(std::cos(mid), std::sin(mid));
    const double clear = world.Clearance(next, radius + 0.5);
    if (trans != 0.0 && clear < radius) {
      trans = 0.0;
      v = 0.0;
      ++stats.blocked_steps;
    } else if (trans != 0.0) {
      truth.x = next.x();
      truth.y = next.y();
      stats.min_clearance_m = std::min(stats.min_clearance_m, clear);
      mark_footprint(next);
      clear_certainty_under_robot(next);
    }
    truth.theta = NormalizeAngle(truth.theta + dtheta);
    odo.Step(trans, dtheta, rng);
    stats.distance_m += std::abs(trans);
  }
  stats.simulated_s = t;
  stats.coverage = free_count > 0 ? static_cast<double>(seen_free) / free_count : 0.0;
  if (!std::isfinite(stats.min_clearance_m)) stats.min_clearance_m = world.Clearance(truth.translation(), radius + 0.5);
  if (progress) progress(1.0);
  return stats;
}

}  // namespace cogmap::sim
