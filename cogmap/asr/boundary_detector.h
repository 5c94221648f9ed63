#pragma once
#include <cstdint>
#include <deque>
#include <optional>
#include <utility>
#include <vector>

#include "cogmap/core/angles.h"
#include "cogmap/core/pose2.h"
#include "cogmap/sensors/reading.h"
#include "cogmap/sensors/robot.h"

namespace cogmap::asr {

// How the run is cut into ASRs (SPEC 4).
enum class BoundaryMode {
  kDoorway,      // fig. 3.4 state machine plus the corridor rule (§3.1.2)
  kFixedLength,  // a new ASR every asr_length_m of travel, no doorway test (§4.2)
};

struct BoundaryOptions {
  BoundaryMode mode = BoundaryMode::kDoorway;
  // L / R: an obstacle within close_m of the robot's centre line on that side
  // (SPEC 4). Measured across the robot (robot-frame |y| of the echo point).
  double close_m = 0.7;
  double corridor_m = 2.0;     // L and R held longer than this: a corridor (SPEC 4)
  double asr_length_m = 4.5;   // corridor and fixed-length cut (§3.1.2; §4.2 uses 4 m)
  // Side sensors: mounting heading within 90 deg +- this of the robot's left
  // (right). Pioneer ring: units 0, 1, 2, 13, 14, 15 (left: 90, 50, 30, 150,
  // 130, 90 degrees) and 5..10 (right); laser: the beams from 30 to 90 degrees
  // each side. A sonar pointing straight at a door jamb's thin edge rarely gets
  // an echo (the jamb's faces are parallel to its beam), and a robot crossing a
  // doorway at an angle sees one jamb only with its front or rear units: the
  // diagonal units see the jambs before and after they are beside the robot,
  // and the memory below carries those echoes until they are (on the generated
  // 100-room building, 45 degrees found 64 % of the rooms, 60 degrees 95 %).
  double side_tolerance_rad = DegToRad(60.0);
  // Echo points of the side sensors are remembered (odometry frame) for this
  // much travel; a remembered point counts for L (R) while it lies beside the
  // robot: |robot-frame x| <= side_window_m, 0 < y <= close_m (-close_m <= y < 0).
  double memory_m = 1.5;
  double side_window_m = 0.35;
  // A side switches on (off) after this many consecutive sweeps in which its
  // sensors reported close (not close). Sweeps without a side reading leave it.
  int debounce_sweeps = 2;
  // Corridor entry: the room before the corridor is only cut at the corridor's
  // mouth when it has at least this much travel (else the corridor continues it).
  double min_asr_m = 1.0;
  // Default mode: a space the robot has driven this far in without a doorway
  // or corridor cut is cut here anyway (a hall or a corridor wider than twice
  // close_m, where L and R never come on together), so that no ASR's grid
  // grows without bound and its walls are mapped over a bounded stretch of
  // odometry drift. 0 = never (the papers). 15 m leaves rooms of the size of
  // the thesis's whole (nine_rooms: about 12 m of driving per room) uncut.
  double max_asr_m = 0.0;
  // Default mode: when L or R releases at an access point, the stretch ends
  // only if they stay released for this much travel; if both come back on
  // sooner, the gap was a side opening passed (a door on one side of a
  // corridor, a sonar echo flickering around close_m) and the stretch goes
  // on. A door leaf is at most about 1 m wide (ADA/DIN clear widths 0.8-0.9 m
  // plus the jambs), so a release shorter than that is no way out. When the
  // stretch does end, it ends where the release began (cut, depth and width
  // as if decided then). 0 = end at the first release (the thesis, fig. 3.4).
  double release_confirm_m = 0.0;
  // Default mode, on request (--door-gap): L and R also come on together
  // when the nearest echoes beside the robot on the left and on the right are
  // at most this far apart across it (0 = off: each side within close_m of
  // the centre line, the thesis). The thesis's rule bounds the opening at
  // 2 close_m only for a robot in its middle: one 0.25 m off the middle of a
  // 1.2 m door has its far jamb at 0.85 m and never sees L and R together
  // (docs/BENCHMARKS.md, "Doors wider than the thesis's"). The side beyond
  // close_m counts only when its obstacle is a jamb, the end of a wall across
  // the robot's way, not a wall along it: the remembered echoes of that side
  // within jamb_band_m of its distance and jamb_window_m ahead or behind span
  // at most jamb_extent_m along the way (a corridor's wall spans the window;
  // a jamb, blurred by the sonar's cone, a few tenths of a metre).
  double gap_m = 0.0;
  double jamb_band_m = 0.15;
  double jamb_extent_m = 0.7;
  double jamb_window_m = 1.0;
};

// Indices into robot.sensors of the side sensors.
struct SideSensors {
  std::vector<int> left;
  std::vector<int> right;
};
SideSensors FindSideSensors(const sensors::RobotDescription& robot, double tolerance_rad);

// What the side sensors of one sweep say. 'observed' is false when no side
// sensor of that side reported in the sweep (sonar fired in turn).
struct SideObservation {
  bool observed = false;
  bool close = false;
  Vec2 point_m{0, 0};  // world position of the nearest close echo (when close)
};

enum class BoundaryState { kInRoom, kAtAccessPoint };

enum class CutKind {
  kDoorway,        // L and R released on the far side of an access point
  kCorridorEntry,  // a corridor was recognised: cut at its mouth
  kCorridor,       // asr_length_m of corridor since the last cut
  kCorridorExit,   // L and R released at the end of a corridor
  kFixedLength,    // fixed-length mode
  kMaxLength,      // doorway mode: max_asr_m of travel without another cut
};

// The robot left one ASR for the next. The cut happened at 'pose' / 'time_s',
// which can lie in the past (the midpoint of a doorway's L-and-R stretch, the
// mouth of a corridor): readings after time_s belong to the next ASR too.
struct BoundaryCut {
  CutKind kind = CutKind::kDoorway;
  Pose2 pose;              // odometry pose of the robot at the cut
  double time_s = 0.0;
  Vec2 center_m{0, 0};     // exit centre (world, raw odometry frame)
  double width_m = 0.0;    // distance between the L and R obstacles; 0 unknown
};

// The exit-detection state machine of fig. 3.4 with the corridor rule and the
// fixed-length mode (SPEC 4). Feed it every sweep in order; it returns a cut
// when the robot has just left an ASR.
//
// Doorway: room -> access point when L and R are both on; access point -> room
// when both are off again. When the robot left the access point on the far
// side from where it came in (its displacement along the entry direction is
// more than half of its deepest point in the stretch) the exit is the midpoint
// (by travel) of the stretch and the width the narrowest L-R distance seen.
// Otherwise the robot turned back in the doorway: no cut, turn_backs() counts
// it. An L-and-R stretch longer than corridor_m is a corridor: the room before
// it is cut at the corridor's mouth, then the corridor every asr_length_m; its
// release cuts once more at the release point.
class BoundaryDetector {
 public:
  BoundaryDetector(const sensors::RobotDescription& robot, const BoundaryOptions& options);

  std::optional<BoundaryCut> Push(const sensors::LogRecord& record);
  // The same from precomputed side observations (scripted tests, other sensors).
  std::optional<BoundaryCut> PushSides(double time_s, const Pose2& pose, const SideObservation& left,
                                       const SideObservation& right);

  BoundaryState state() const { return state_; }
  bool left_on() const { return left_.on; }
  bool right_on() const { return right_.on; }
  int turn_backs() const { return turn_backs_; }
  // Travel (m) since the current ASR began.
  double asr_travel_m() const { return travel_m_ - asr_start_travel_m_; }
  const SideSensors& side_sensors() const { return sides_; }
  const BoundaryOptions& options() const { return options_; }

  // Remembers the record's side echoes and says what each side sees now
  // (called by Push; exposed for tests). 'travel_m' is the travel at the record.
  std::pair<SideObservation, SideObservation> ObserveSides(const sensors::LogRecord& record,
                                                           double travel_m);

 private:
  struct Side {
    bool on = false;
    int run = 0;  // consecutive sweeps disagreeing with 'on'
    Vec2 last_point{0, 0};
    bool has_point = false;
  };
  struct StretchSample {
    Pose2 pose;
    double time_s;
    double travel_m;
  };
  struct Echo {
    Vec2 point_m;
    double travel_m;
    bool left;
  };
  void UpdateSide(Side* side, const SideObservation& obs) const;
  void Advance(const Pose2& pose);
  std::optional<BoundaryCut> Step(double time_s, const Pose2& pose, const SideObservation& left,
                                  const SideObservation& right);
  BoundaryCut MakeCut(CutKind kind, const Pose2& pose, double time_s, double width_m);
  Pose2 PoseAtTravel(double travel_m, double* time_s) const;

  sensors::RobotDescription robot_;
  BoundaryOptions options_;
  SideSensors sides_;
  std::vector<int8_t> side_of_;  // per sensor: +1 left, -1 right, 0 neither
  std::deque<Echo> memory_;
  BoundaryState state_ = BoundaryState::kInRoom;
  Side left_, right_;
  bool have_pose_ = false;
  Pose2 last_pose_;
  double travel_m_ = 0.0;
  double asr_start_travel_m_ = 0.0;
  int turn_backs_ = 0;
  // The current L-and-R stretch.
  std::vector<StretchSample> stretch_;
  Vec2 entry_dir_{1, 0};
  double max_depth_m_ = 0.0;
  double min_width_m_ = 0.0;
  bool corridor_ = false;
  // A release waiting for release_confirm_m of travel (default mode).
  bool releasing_ = false;
  StretchSample release_{};
  double release_max_depth_m_ = 0.0;
  Vec2 prev_pos_{0, 0};  // a position a little behind, for the direction of travel
  Vec2 travel_dir_{1, 0};
  bool has_travel_dir_ = false;
};

}  // namespace cogmap::asr
