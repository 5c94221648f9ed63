#pragma once
#include <cstdint>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "cogmap/core/pose2.h"
#include "cogmap/grid/grid2d.h"
#include "cogmap/grid/map_limits.h"
#include "cogmap/sensors/reading.h"
#include "cogmap/sensors/robot.h"

namespace cogmap::grid {

// The four ways of fusing range readings into an occupancy grid (SPEC 2).
enum class FusionRule { kHimm, kMhimm, kBayes, kDempsterShafer };

// "himm", "mhimm", "bayes", "ds" (also "dempster-shafer"). Throws InputError
// naming the unknown rule and the known ones.
FusionRule ParseFusionRule(const std::string& name);
std::string FusionRuleName(FusionRule rule);
std::vector<std::string> FusionRuleNames();

// The classification every rule can give a cell, whatever it stores.
enum class CellClass : uint8_t { kUnknown = 0, kEmpty = 1, kOccupied = 2, kRobotPath = 3 };

// Where the grid lives: a fixed box (cells outside it are never touched), or a
// grid that starts small around the first pose and grows in whole chunks as
// the robot moves (existing cells keep their world position).
struct GridBounds {
  double cell_m = 0.1;                 // the thesis's cell size (SPEC conventions)
  std::optional<MapLimits> fixed;      // bounded grid; its cell_m wins over cell_m
  int grow_chunk_cells = 64;           // growth step of an unbounded grid
  long max_cells = 50'000'000;         // growing past this is an InputError (cell too small)
};

// Counts of what a fusion rule has seen (the app prints them).
struct FusionStats {
  long readings = 0;   // Insert calls
  long hits = 0;       // readings that marked an obstacle
  long misses = 0;     // readings beyond the window or without echo
  long ignored = 0;    // readings below the sensor's min range
  long robot_updates = 0;
};

// A range-reading fusion rule over a 2-D grid (HIMM, modified HIMM, Bayes,
// Dempster-Shafer). The beam of every rule starts at the robot's centre cell
// r0 (SPEC 2, thesis fig. 2.3: "from the robot center point (x0, y0)"); the
// reading's end point comes from the sensor's pose (ReadingEndPoint, SPEC 1).
// The cone rules measure distance and angle from the sensor's position.
class RangeFusion {
 public:
  virtual ~RangeFusion() = default;

  virtual FusionRule rule() const = 0;

  // Marks the cell under the robot centre as robot path (MHIMM: set to
  // robot_path; the other rules remember it for Classify and pictures).
  virtual void MarkRobot(const Pose2& world_from_robot) = 0;

  // Fuses one reading of 'range_m' metres (from the transducer) taken by
  // 'sensor' while the robot is at 'world_from_robot'. A range at or above the
  // sensor's max range is "no echo".
  virtual void Insert(const Pose2& world_from_robot, const sensors::RangeSensor& sensor,
                      double range_m) = 0;

  // One sweep: MarkRobot, then every reading (index into robot.sensors; an
  // index out of range is ignored and counted). Rules override it to share
  // per-pose work.
  virtual void InsertSweep(const Pose2& world_from_robot, const sensors::RobotDescription& robot,
                           std::span<const sensors::RangeReading> readings);

  virtual const MapLimits& limits() const = 0;

  // The rule's own scalar per cell: HIMM / MHIMM certainty values, Bayes
  // log-odds, Dempster-Shafer pignistic probability of occupied.
  virtual Grid2D<float> Values() const = 0;
  // Probability of occupied in [0, 1] (0.5 = nothing known); HIMM values map
  // as value / max.
  virtual Grid2D<float> Occupancy() const = 0;
  virtual CellClass Classify(int x, int y) const = 0;

  // Classify over the whole grid.
  Grid2D<CellClass> Classes() const;

  const FusionStats& stats() const { return stats_; }

 protected:
  FusionStats stats_;
};

// HIMM (Borenstein and Koren; thesis §2.2.3) and the modified HIMM (§3.1.4,
// fig. A.2/A.3) with the increments fixed by SPEC 2.
struct HimmOptions {
  double window_m = 3.0;             // w: hits closer than this; the thesis gives none (SPEC 2)
  float hit_increment = 3.0f;        // end cell t (SPEC 2)
  float neighbour_increment = 1.5f;  // each of t's 8 neighbours (SPEC 2, fig. A.2/A.3)
  float beam_decrement = 1.0f;       // cells between r0 and t, both ends excluded
  float min_value = 0.0f;            // clamp (§2.2.3)
  float max_value = 15.0f;           // clamp (§2.2.3)
  float occupied_threshold = 7.0f;   // epsilon: occupied when value > epsilon (table 4.1)
  bool ignore_below_min_range = true;  // readings closer than the sensor's min range
};

// The modified HIMM: empty cells go below 0, the robot's path is kept, and
// readings beyond the window clear the beam up to the window (SPEC 2).
struct MhimmOptions : HimmOptions {
  MhimmOptions() { min_value = -3.0f; }  // [-3, 15] (§3.1.4)
  float robot_path = -100.0f;           // set under the robot, never changed (§3.1.4)
  // Default mode: also mark the Bresenham line between consecutive robot
  // cells (up to this many metres apart), so that a robot moving more than a
  // cell between sweeps leaves an unbroken path for cleaning. The papers mark
  // only the centre cell at each update: 0 reproduces that.
  double join_path_max_m = 1.0;
  // Default mode on request (--sonar-cone; off by default, docs/walls.md,
  // "Sonar cone" says why): the sonar's cone, not only its axis. An echo at range r comes from the nearest reflector
  // inside the cone, so (1) every cell of the cone nearer than r, less a
  // cell and a half, is free evidence, weighted (1 - |angle| / half-angle)
  // x beam_decrement (Moravec's angular weight: a cell near the cone's edge
  // is less surely empty), beside the axis's own decrement; and (2) the hit
  // goes on the arc of radius r, to the arc cell nearest the axis that is
  // not known empty (value >= 0), on the axis when every arc cell is. HIMM
  // puts the echo on the axis, which for an oblique sonar is in front of
  // the wall: the echo came from the cone's edge (a Pioneer's 50-degree
  // sonar 1 m from a wall: 0.22 m in front). Only for a sensor whose cone
  // at the range is wider than a cell; a laser's beam stays a ray. The
  // papers use the axis alone: false reproduces them.
  bool cone_hits = false;
};

// The two sonar-cone rules of chapter II (Moravec / Murphy): the cone of
// half-angle beta = half the sensor's beam width; region I is the arc
// |d - r| <= region_half_width_m, region II the cells nearer than it.
struct ConeOptions {
  double window_m = 3.0;            // readings at/after w clear region II up to w (as MHIMM)
  double max_occupied = 0.98;       // MO of table 2.1 (Murphy's "Max_occupied")
  double region_half_width_m = 0.1; // tolerance of region I; the thesis leaves it open
  double occupied_probability = 0.65;  // classify occupied above (map_server's default)
  double free_probability = 0.35;      // classify empty below
  float log_odds_clamp = 10.0f;        // Bayes only: keeps cells revisable
  // Bayes only: table 2.2's region II gives Pr(occupied) = 1 - f, which is
  // above 0.5 (evidence *for* an obstacle) near the cone's edges far from the
  // sensor. True caps it at 0.5 there (no evidence); the table's model is the
  // default.
  bool region2_never_occupied = false;
  bool ignore_below_min_range = true;
};

// A HIMM (modified = false) or MHIMM grid.
class HimmFusion : public RangeFusion {
 public:
  HimmFusion(bool modified, const MhimmOptions& options, const GridBounds& bounds);

  FusionRule rule() const override { return modified_ ? FusionRule::kMhimm : FusionRule::kHimm; }
  void MarkRobot(const Pose2& world_from_robot) override;
  void Insert(const Pose2& world_from_robot, const sensors::RangeSensor& sensor,
              double range_m) override;
  void InsertSweep(const Pose2& world_from_robot, const sensors::RobotDescription& robot,
                   std::span<const sensors::RangeReading> readings) override;
  const MapLimits& limits() const override { return grid_.limits(); }
  Grid2D<float> Values() const override { return grid_; }
  Grid2D<float> Occupancy() const override;
  CellClass Classify(int x, int y) const override;

  // The certainty values themselves (MHIMM: occupied > 7, robot path -100,
  // unknown 0, empty < 0), as the vectorizer and the ASR builder consume them.
  const Grid2D<float>& values() const { return grid_; }
  const MhimmOptions& options() const { return options_; }

  // Where each echo was heard from, as the distance the robot had driven:
  // after SetDistance(s), every hit inserted adds s to its cell, weighted by
  // the evidence it adds (the hit increment). HitDistance is the weighted
  // mean over the cells within radius_m of p (nullopt: no hit there, or
  // SetDistance never called). The mapper bends each wall point by the
  // drift at the distance it was seen from (MapOptimizer::BendWalls).
  void SetDistance(double s_m);
  std::optional<double> HitDistance(const Vec2& p, double radius_m) const;

 private:
  // Fuses one reading given the sensor's world position and unit heading.
  void InsertRay(const CellIndex& r0, double sx, double sy, double cos_h, double sin_h,
                 const sensors::RangeSensor& sensor, double range_m);
  // Grows (unbounded) so that the box lies inside.
  void Reach(const Vec2& lo, const Vec2& hi);

  bool modified_;
  MhimmOptions options_;
  GridBounds bounds_;
  Grid2D<float> grid_;
  bool bounded_;
  std::optional<Vec2> last_path_point_;  // for join_path_max_m
  // SetDistance: per cell of grid_ (the same limits, grown with it) the sum
  // of distance x weight and of weight of the hits on it.
  bool track_distance_ = false;
  double distance_ = 0.0;
  Grid2D<float> hit_distance_sum_, hit_weight_;
  // The cosine and sine of each sensor's mount angle, by sensor index, with
  // the angle they are of: a mount is fixed, so a sweep of a 180-beam laser
  // need not take 180 of them again (the same values, so the same grid).
  struct MountTurn {
    double theta, c, s;
  };
  std::vector<MountTurn> mount_turn_;
};

// Bayes in log-odds (Moravec; thesis §2.2.1, table 2.2, eq. 2.9) or
// Dempster-Shafer (Murphy; §2.2.2, table 2.3, eq. 2.11-2.13).
class ConeFusion : public RangeFusion {
 public:
  ConeFusion(bool dempster_shafer, const ConeOptions& options, const GridBounds& bounds);

  FusionRule rule() const override {
    return ds_ ? FusionRule::kDempsterShafer : FusionRule::kBayes;
  }
  void MarkRobot(const Pose2& world_from_robot) override;
  void Insert(const Pose2& world_from_robot, const sensors::RangeSensor& sensor,
              double range_m) override;
  const MapLimits& limits() const override { return occupied_.limits(); }
  Grid2D<float> Values() const override;
  Grid2D<float> Occupancy() const override;
  CellClass Classify(int x, int y) const override;

  // Probability of occupied at one cell (0.5 when untouched).
  float OccupancyAt(int x, int y) const;
  // Dempster-Shafer masses at one cell (Bayes: probability of occupied and of
  // empty, no "don't know").
  float OccupiedMass(int x, int y) const { return occupied_.get(x, y); }
  float EmptyMass(int x, int y) const { return empty_.get(x, y); }
  const ConeOptions& options() const { return options_; }

 private:
  void Reach(const Vec2& lo, const Vec2& hi);
  // Region I (arc) when 'arc', region II otherwise; 'f' is table 2.2's
  // ((R - d) / R + (beta - alpha) / beta) / 2.
  void Update(long flat, bool arc, double f);

  bool ds_;
  ConeOptions options_;
  GridBounds bounds_;
  bool bounded_;
  // Bayes: occupied_ holds log-odds, empty_ unused (0). DS: the masses
  // m(occupied), m(empty); m(don't know) = 1 - both.
  Grid2D<float> occupied_;
  Grid2D<float> empty_;
  Grid2D<uint8_t> touched_;  // 1 = updated, 2 = robot path
};

// Options for every rule, so that callers can pick the rule at run time.
struct FusionOptions {
  GridBounds bounds;
  HimmOptions himm;
  MhimmOptions mhimm;
  ConeOptions cone;
};

std::unique_ptr<RangeFusion> MakeFusion(FusionRule rule, const FusionOptions& options = {});

}  // namespace cogmap::grid
