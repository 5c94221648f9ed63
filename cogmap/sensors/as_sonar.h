#pragma once
#include <vector>

#include "cogmap/core/pose2.h"
#include "cogmap/sensors/reading.h"
#include "cogmap/sensors/robot.h"

namespace cogmap::sensors {

struct AsSonarOptions {
  // A sonar whose axis points where the source sensors do not look (a rear
  // sonar over a front laser) gets no reading rather than a false "no echo"
  // that would clear cells nobody saw. Covered: some source sensor's heading
  // lies within one beam spacing (the median angle between neighbouring source
  // headings) of the sonar's heading.
  bool skip_unseen_sonars = true;
  // "No echo" is claimed only by a sonar whose axis, from its transducer out
  // to its max range, lies wholly in view of the source (each point of it
  // within one beam spacing of some source sensor's heading, seen from that
  // sensor). A side sonar mounted behind a front laser (pioneer16's 8 and 15)
  // has the part of its cone next to the robot out of the laser's view: when
  // no laser point lies in its cone it gets no reading in that sweep (a wall
  // 0.5 m beside it is seen by the laser only outside its cone).
  bool no_echo_only_when_in_view = true;
};

// One sweep of the source (a laser scan): where the robot was (odometry) and
// its echoes in the robot frame there.
struct SourceScan {
  Pose2 odom;
  std::vector<Vec2> points;
};

// Derives a sonar ring's readings from a laser's (cogmap convert --as-sonar).
// Each echo of the source (a reading with 0 < min_range <= range < max_range
// of its sensor; at or over max range is no return) is the point at its range
// along its beam's axis. Each sonar of the target robot reports the distance,
// from its transducer, of the nearest such point inside its cone (within
// +-beam_width/2 of its axis, in its own mounting frame), or its max_range (no
// echo) when there is none or the nearest is at or beyond it. A nearest point
// closer than the sonar's min_range is still reported as measured.
class AsSonar {
 public:
  AsSonar(const RobotDescription& source, const RobotDescription& sonar, const AsSonarOptions& options = {});

  // The target robot's readings for one sweep of the source robot's. A
  // sweep with no readings (odometry only) gives none. Source readings must
  // name sensors of the source robot (others are ignored; the caller checks).
  std::vector<RangeReading> Convert(const std::vector<RangeReading>& source_readings) const;

  // The source readings' echoes in the robot frame (what Convert reads).
  SourceScan Echoes(const Pose2& odom, const std::vector<RangeReading>& source_readings) const;

  // The readings of 'sonars' (target sensor indices) fired with the robot at
  // 'odom', from the echoes of 'scans' (sweeps taken nearby, each moved into
  // the robot frame at 'odom' by the odometry between them). Where the
  // source looked is judged from the scans' own poses: a sonar reports the
  // nearest echo in its cone when every point of its axis up to that echo
  // lay in view of one of the scans (within one beam spacing of a source
  // beam, inside its max range), no echo (max range) when its whole axis did
  // and no echo lay in its cone, and nothing otherwise (what a sonar reads
  // where no scan looked is not known). A sonar pointing where the source
  // never looks from the robot (covered()) reads what earlier scans saw
  // there: a rear sonar, the corridor a forward laser saw on the way in.
  std::vector<RangeReading> FireAt(const Pose2& odom, const std::vector<int>& sonars,
                                   const std::vector<const SourceScan*>& scans) const;

  // Per target sensor: whether it gets readings (see AsSonarOptions).
  const std::vector<bool>& covered() const { return covered_; }
  // Per target sensor: whether it may report no echo (max range).
  const std::vector<bool>& may_report_no_echo() const { return no_echo_; }

 private:
  RobotDescription source_;
  RobotDescription sonar_;
  std::vector<Pose2> sonar_from_robot_;
  std::vector<bool> covered_;
  std::vector<bool> no_echo_;
  // The source's view: its sensors grouped by mount point, each group's
  // bearings (from the mount, kViewBins bins over the circle) within one
  // beam spacing of one of its sensors' headings, and its longest range.
  static constexpr int kViewBins = 3600;
  struct ViewGroup {
    Vec2 mount;
    double max_range_m = 0.0;
    std::vector<bool> bearing;
  };
  std::vector<ViewGroup> view_;
  bool InView(const Vec2& robot_point) const;
};

}  // namespace cogmap::sensors
