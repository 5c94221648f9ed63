#include "cogmap/mapping/pipeline.h"

#include <limits>
#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <sstream>

#include "cogmap/core/angles.h"
#include "cogmap/core/error.h"
#include "cogmap/core/text.h"
#include "cogmap/localize/odometry_corrector.h"

namespace cogmap::mapping {
namespace {

std::string Num(double v) {
  std::ostringstream s;
  s << v;
  return s.str();
}

double PathLength(const std::vector<Pose2>& path) {
  double s = 0.0;
  for (size_t i = 1; i < path.size(); ++i) s += (path[i].translation() - path[i - 1].translation()).norm();
  return s;
}

}  // namespace

std::string CellAndWindowProblem(double cell_m, double window_m) {
  if (!(cell_m > 0.0) || cell_m > 10.0) return "--cell " + Num(cell_m) + ": must be in (0, 10] metres";
  if (!(window_m >= cell_m) || window_m > 100.0)
    return "--window " + Num(window_m) + ": must be in [" + Num(cell_m) + ", 100] metres (a cell at least)";
  return "";
}

void MappingOptions::Validate() const {
  if (const std::string problem = CellAndWindowProblem(cell_m, window_m); !problem.empty()) throw InputError(problem);
  // Lengths a robot's ranges and rooms can have: infinities and lengths that
  // cut a space at every record are none (--max-asr 1e-300 made an ASR of
  // every record of nine_rooms, 6944).
  if (!(asr_length_m >= 0.5) || asr_length_m > 100000.0)
    throw InputError("--asr-length " + Num(asr_length_m) + ": must be in [0.5, 100000] metres");
  if (!(max_asr_m == 0.0 || (max_asr_m >= 0.5 && max_asr_m <= 100000.0)))
    throw InputError("--max-asr " + Num(max_asr_m) + ": must be 0 (never) or in [0.5, 100000] metres");
  if (!(direction_split_m >= 0.0) || direction_split_m > 1000.0)
    throw InputError("--direction-split " + Num(direction_split_m) + ": must be in [0, 1000] metres");
  if (!(release_confirm_m >= 0.0) || release_confirm_m > 100.0)
    throw InputError("--door-release " + Num(release_confirm_m) + ": must be in [0, 100] metres");
  if (threads < 1 || threads > 2) throw InputError("--threads " + std::to_string(threads) + ": must be 1 or 2");
  if (!(door_gap_m == 0.0 || (door_gap_m >= 1.0 && door_gap_m <= 4.0)))
    throw InputError("--door-gap-m " + Num(door_gap_m) + ": must be in [1, 4] metres (0: 1.4, twice the thesis's 0.7)");
  if (!std::isfinite(add_drift_rad_per_m) || std::abs(add_drift_rad_per_m) > DegToRad(90.0))
    throw InputError("--add-drift-deg-per-m " + Num(RadToDeg(add_drift_rad_per_m)) + ": must be in [-90, 90]");
  if (!std::isfinite(remove_drift_rad_per_m) || std::abs(remove_drift_rad_per_m) > DegToRad(90.0))
    throw InputError("--remove-drift-deg-per-m " + Num(RadToDeg(remove_drift_rad_per_m)) + ": must be in [-90, 90]");
  if (!std::isnan(distance_scale) && !(distance_scale >= 0.5 && distance_scale <= 2.0))
    throw InputError("--distance-scale " + Num(distance_scale) + ": must be auto, off or in [0.5, 2]");
  if (!(distance_scale_prior > 0.0 && distance_scale_prior <= 0.2))
    throw InputError("distance scale prior " + Num(distance_scale_prior) + ": must be in (0, 0.2]");
  if (remove_drift_rad_per_m != 0.0 && pre_bend)
    throw InputError("--remove-drift-deg-per-m and --pre-bend: one drift removed while mapping, not both");
}

Correction MappingOptions::correction() const {
  if (!correct) return Correction::kNone;
  if (paper) return Correction::kPerAsrEm;
  if (pose_graph) return Correction::kPoseGraph;
  return drift_filter ? Correction::kDriftFilter : Correction::kPerAsrEm;
}

Pose2 DriftAdder::Add(const Pose2& odom) {
  if (!drift_) drift_.emplace(rate_, odom.translation(), step_m_);
  return (*drift_)(odom);
}

bool LaserOnly(const sensors::RobotDescription& robot) {
  return std::all_of(robot.sensors.begin(), robot.sensors.end(),
                     [](const auto& s) { return s.kind == sensors::SensorKind::kLaser; });
}

void ConfigureWallLines(const sensors::RobotDescription& robot, bool on, vectorize::VectorizeOptions* v) {
  v->wall_lines = on;
  v->lines.beam_half_width_rad = 0.5 * sensors::WidestBeamRad(robot);
  v->lines.max_range_cells = v->clean.max_dist_cells;
  v->lines.path_clearance_m = robot.radius_m;
  // A sonar's cleaned faces hold the smear of door jambs in front of the
  // wall; the whole band holds the wall behind it. A laser's hits are the
  // wall's surface, which the cleaning keeps.
  v->lines.all_occupied = !LaserOnly(robot);
}

asr::MapperOptions MapperOptionsFor(const sensors::RobotDescription& robot, const MappingOptions& o) {
  asr::MapperOptions m;
  m.cell_m = o.cell_m;
  m.mhimm.window_m = o.window_m;
  // Default mode, on request (--sonar-cone): free evidence over the sonar's
  // cone and each echo on its arc. Off by default: docs/walls.md, "Sonar cone".
  m.mhimm.cone_hits = !o.paper && o.cone_hits;
  // Default mode, sonar: the walls kept come from a second grid fused over
  // the cone, while the pose graph matches the axis grid's walls (docs/walls.md,
  // "Sonar cone"). A laser's beam is narrower than a cell: its cone grid
  // would be the same grid.
  m.cone_output_walls = !o.paper && !o.cone_hits && o.cone_walls && !LaserOnly(robot);
  // On request (--cone-orientation), a ring that looks only forward: the
  // rooms' orientation from that cone grid too (its axis grid's walls lean
  // with the way driven; docs/walls.md, "A ring that looks only forward").
  m.orientation_from_cone = m.cone_output_walls && o.cone_orientation && sensors::SeesOnlyForward(robot);
  // Where each wall was heard from, for the pose graph's bend (docs/pose-graph.md).
  m.seen_distances = o.correction() == Correction::kPoseGraph;
  m.vectorize = o.paper ? vectorize::VectorizeOptions::Paper() : vectorize::VectorizeOptions{};
  if (!o.paper) ConfigureWallLines(robot, o.wall_lines, &m.vectorize);
  m.boundary.mode = o.boundary;
  m.boundary.asr_length_m = o.asr_length_m;
  // Default mode also bounds how far an ASR runs without a doorway (a hall, a
  // wide corridor); paper mode leaves such a space whole, as the papers do.
  if (!o.paper) m.boundary.max_asr_m = o.max_asr_m;
  // Default mode, on request (--door-release): an access point ends only on a
  // release longer than a door (a corridor's side doors and flickering side
  // echoes do not cut it). Off by default: docs/BENCHMARKS.md, "Door release".
  if (!o.paper) m.boundary.release_confirm_m = o.release_confirm_m;
  // Default mode, on request (--door-gap): an opening at most 2 close_m wide
  // is an access point wherever the robot is in it (asr::BoundaryOptions::
  // gap_m). Off by default: docs/BENCHMARKS.md, "Doors wider than the thesis's".
  if (!o.paper && (o.door_gap || o.door_gap_m > 0.0))
    m.boundary.gap_m = o.door_gap_m > 0.0 ? o.door_gap_m : 2.0 * m.boundary.close_m;
  // The grid orientation serves the heading correction's grid refinement,
  // which is for sonar robots only: not computed for a laser.
  m.grid_orientation = !LaserOnly(robot);
  return m;
}

namespace {
// Whether the run's laser odometry ran (--scan-match auto, decided on its
// first scans): "1" or "0"; a resumed run keeps the decision.
constexpr const char* kMetaScanOdometry = "scan_odometry";
// The distance scale a finished run ended with (--distance-scale auto, when
// it had an estimate): a resumed run drives on with it until its own runs
// give an estimate.
constexpr const char* kMetaDistanceScale = "distance_scale";

localize::HeadingCorrectionOptions HeadingOptionsFor(const sensors::RobotDescription& robot,
                                                     const MappingOptions& o) {
  localize::HeadingCorrectionOptions h;
  h.mode = o.paper ? localize::HeadingMode::kPaper : localize::HeadingMode::kDefault;
  // The grid refinement is for sonar, whose polylines wobble; a laser's
  // polylines give the EM a better direction than the room's occupied cells
  // (docs/heading-correction.md).
  h.grid_refine = !LaserOnly(robot);
  return h;
}
// The pose graph's noise model for odometry the laser's scans corrected
// (localize::ScanOdometry), from the matcher's measured accuracy: heading
// 0.1 degrees per sqrt(m) (simulated 10 Hz laser 0.06-0.09 over 1-20 m of
// travel; the CARMEN logs' reference-free check about 0.13 at their scans'
// 0.55-0.83 m spacing), 0.3 degrees per sqrt(rad) of turning, 0.01 m per
// sqrt(m) (twice the simulated laser's), at least 0.03 m. With the wheels'
// model (0.35, 0.6, 0.02) the graph pulled good scan odometry towards its
// wall directions: worse than its input in 28 of the bench's 60 laser runs
// (docs/BENCHMARKS.md, "Laser odometry"). The variance components scale it
// as they do the wheels'. Its drift rate's prior is 0.5 deg/m, not the
// wheels' 3: the scans measure the heading at every match, so a drift
// would be a bias of every match, each erring by about 0.1 degree at
// random; under the wheels' prior a quarter-turn alias of no drift (7.7
// deg/m over a 12 m laser run) kept 7 % of the likelihood, and good laser
// maps were flagged uncertain (docs/inputs.md, "Laser odometry").
graph::OdometryNoiseOptions ScanOdometryNoise() {
  graph::OdometryNoiseOptions wheels;
  wheels.heading_sigma_rad_per_sqrt_m = DegToRad(0.1);
  wheels.rot_sigma_rad_per_sqrt_rad = DegToRad(0.3);
  wheels.trans_sigma_m_per_sqrt_m = 0.01;
  // However short the way between two rooms, a floor of 0.03 m: the
  // matcher's error after a turn on the spot and the wheels' along what the
  // scans cannot tell remain (with the wheels' 0.01, 2 of bench/never_worse's
  // 40 laser runs had every ASR outside 3 sigma, silently).
  wheels.min_sigma_m = 0.03;
  wheels.rate_prior_sigma_rad_per_m = DegToRad(0.5);
  return wheels;
}

graph::MapOptimizerOptions GraphOptionsFor(const sensors::RobotDescription& robot,
                                           const localize::HeadingCorrectionOptions& h, const MappingOptions& o) {
  graph::MapOptimizerOptions g;
  g.heading = h;
  g.direction_split_m = o.direction_split_m;
  g.threads = o.threads;
  g.drift_known = o.remove_drift_rad_per_m != 0.0;
  g.search_again = o.search_closures_again;
  // A registration's covariance counts each wall's place in its room, to
  // within a cell, when the widest beam spreads less than a cell across the
  // window (a laser's half degree: 1.3 cm at 3 m); a sonar's 30 degrees
  // spread 0.8 m there, and its walls keep the older model
  // (RegistrationOptions::wall_end_sigma_m).
  const double half = 0.5 * sensors::WidestBeamRad(robot);
  g.registration.wall_end_sigma_m = o.window_m * std::tan(half) <= o.cell_m ? o.cell_m / std::sqrt(12.0) : 0.0;
  return g;
}
}  // namespace

MappingPipeline::MappingPipeline(sensors::RobotDescription robot, MappingOptions options, asr::SqliteAsrStore* store)
    : robot_(std::move(robot)),
      options_(options),
      store_(store),
      heading_options_(HeadingOptionsFor(robot_, options_)),
      corrector_(heading_options_),
      drift_corrector_(heading_options_),
      drift_adder_(options.add_drift_rad_per_m) {
  options_.Validate();
  result_.correction = options_.correction();
  if (options_.scan_match == ScanMatch::kOn) {
    scan_odometry_ = std::make_unique<localize::ScanOdometry>(robot_);
    result_.scan_match_active = localize::HasLaser(robot_);
  } else if (options_.scan_match == ScanMatch::kAuto && !options_.paper && localize::HasLaser(robot_)) {
    scan_density_ = std::make_unique<localize::ScanDensity>(robot_);
  }
  // The distance scale: default mode, when correcting (paper mode and
  // --no-correct take the odometry as it comes).
  if (!options_.paper && options_.correct) {
    if (std::isnan(options_.distance_scale)) {
      scale_estimator_ = std::make_unique<localize::OdometryScaleEstimator>(robot_);
      result_.distance_scale_measured = true;
    } else {
      scaler_.SetScale(options_.distance_scale);
    }
  }
  if (store_ && store_->MaxId() < 0 && !store_->GetMeta(asr::kMetaFinishedThrough))
    store_->SetMeta(asr::kMetaFinishedThrough, "-1");
  asr::MapperOptions mapper_options = MapperOptionsFor(robot_, options_);
  mapper_options.close_in_background = options_.threads > 1;
  mapper_ = std::make_unique<asr::CognitiveMapper>(robot_, mapper_options, store_,
                                                   [this](const asr::Asr& x) { Closed(x); });
  switch (result_.correction) {
    case Correction::kDriftFilter:
      mapper_->SetOdometryFilter(
          [this](const Pose2& raw, double t) { return drift_corrector_.CorrectOdometry(raw, t); });
      mapper_->SetCorrector([this](asr::Asr pre) { return KeepEstimate(drift_corrector_.Close(std::move(pre))); });
      break;
    case Correction::kPoseGraph:
      optimizer_ = std::make_unique<graph::MapOptimizer>(GraphOptionsFor(robot_, heading_options_, options_));
      if (result_.scan_match_active)  // --scan-match on
        optimizer_->SetOdometryNoise(ScanOdometryNoise());
      mapper_->SetPlacer([this](const asr::Asr& x) { return optimizer_->Prepare(x); },
                         [this](asr::Asr x, std::unique_ptr<asr::PlacementWork> prepared) {
                           asr::Asr out = KeepEstimate(optimizer_->Place(std::move(x), std::move(prepared)));
                           NotePreBend(out.id);
                           return out;
                         });
      // The rate of two rooms back: the room just closed is still being
      // vectorised and placed on the mapper's threads while the next is
      // mapped, the one before it is placed by then.
      if (options_.pre_bend) mapper_->SetPreBend(2, [this](int placed) { return PreBendAfter(placed); });
      if (const double known = options_.remove_drift_rad_per_m; known != 0.0)
        mapper_->SetPreBend(0, [known](int) { return known; });
      break;
    case Correction::kPerAsrEm:
      mapper_->SetCorrector([this](asr::Asr raw) { return KeepEstimate(corrector_.Close(std::move(raw))); });
      break;
    case Correction::kNone:
      break;
  }
}

// The mapper's second thread may still be placing an ASR with the optimizer:
// it goes first.
MappingPipeline::~MappingPipeline() { mapper_.reset(); }

void MappingPipeline::OnAsrClosed(std::function<void(const asr::Asr&, const AsrSummary&)> callback) {
  callback_ = std::move(callback);
}

const localize::DirectionEstimate* MappingPipeline::LastEstimate() const {
  switch (result_.correction) {
    case Correction::kDriftFilter: return &drift_corrector_.LastEstimate();
    case Correction::kPoseGraph: return optimizer_ ? &optimizer_->LastEstimate() : nullptr;
    case Correction::kPerAsrEm: return &corrector_.LastEstimate();
    case Correction::kNone: return nullptr;
  }
  return nullptr;
}

asr::Asr MappingPipeline::KeepEstimate(asr::Asr x) {
  if (const localize::DirectionEstimate* e = LastEstimate()) {
    std::lock_guard<std::mutex> lock(estimates_mutex_);
    estimates_[x.id] = *e;
  }
  return x;
}

void MappingPipeline::NotePreBend(int asr_id) {
  if (!options_.pre_bend) return;  // nothing will ask
  const double rate = optimizer_->PreBendRate();
  std::lock_guard<std::mutex> lock(pre_bend_mutex_);
  pre_bend_after_[asr_id] = rate;
}

double MappingPipeline::PreBendAfter(int placed_id) {
  std::lock_guard<std::mutex> lock(pre_bend_mutex_);
  const auto it = pre_bend_after_.find(placed_id);
  const double rate = it == pre_bend_after_.end() ? 0.0 : it->second;
  // Rooms start in id order: what came before is no longer asked for.
  pre_bend_after_.erase(pre_bend_after_.begin(), pre_bend_after_.upper_bound(placed_id));
  return rate;
}

void MappingPipeline::Closed(const asr::Asr& x) {
  AsrSummary s;
  s.id = x.id;
  s.seconds = x.seconds.total();
  s.seconds_grid = x.seconds.grid;
  s.path_m = PathLength(x.path);
  s.walls = static_cast<int>(x.walls_local.size());
  s.bytes = x.bytes;
  s.heading_correction_rad = x.heading_correction_rad;
  s.pre_bend_rad_per_m = x.pre_bend_rad_per_m;
  {
    std::lock_guard<std::mutex> lock(estimates_mutex_);
    if (auto it = estimates_.find(x.id); it != estimates_.end()) {
      s.estimate = it->second;
      estimates_.erase(it);
    }
  }
  s.grid_orientation = x.grid_orientation;
  result_.asrs.push_back(s);
  if (callback_) callback_(x, result_.asrs.back());
}

void MappingPipeline::Resume() {
  // A laser run's scan odometry (--scan-match auto) was decided on the
  // stored run's first scans: the resumed run keeps that decision, and the
  // stored ASRs it places again below get the odometry noise model they were
  // placed with (without it a resumed hallway_loop laser run ended at wall
  // p95 0.47 m against the uninterrupted run's 0.30).
  if (scan_density_) {
    if (auto decided = store_->GetMeta(kMetaScanOdometry)) {
      scan_density_.reset();
      if (*decided == "1") MatchScans();
    }
  }
  // The distance scale the stored run ended with, until this run's own
  // estimate is valid (a scale in [0.5, 2]; anything else is a damaged store).
  if (scale_estimator_) {
    if (const auto carried = store_->GetMetaPositive(kMetaDistanceScale)) {
      if (*carried < 0.5 || *carried > 2.0)
        throw InputError(store_->path(), 0,
                         "a damaged store: meta distance_scale is " + Num(*carried) + ", outside [0.5, 2]");
      scaler_.SetScale(*carried);
      result_.distance_scale_carried = *carried;
    }
  }
  // On --resume the correctors continue from the stored run: its last
  // correction and reference direction (docs/store.md).
  const int last = store_->MaxId();
  asr::MapperResume r;
  r.next_id = last + 1;
  if (const auto next = asr::NextAsrId(*store_))
    r.next_id = std::max(r.next_id, static_cast<int>(*next));
  Pose2 carried;  // raw -> corrected at the end of the stored run
  std::optional<double> reference;
  if (last >= 0) {
    r.previous_asr = last;
    const auto last_asr = store_->Get(last);
    carried = localize::CorrectionOf(*last_asr);
    // A run killed after a cut stored the exit it left the last ASR by.
    for (const asr::Exit& e : last_asr->exits)
      if (e.from_asr == last && e.to_asr == r.next_id) r.leaving_exit = e;
    for (int id : store_->Ids()) {  // one ASR at a time: the first accepted one sets it
      reference = localize::ReferenceDirection({asr::MatchedView(*store_->Get(id))}, heading_options_);
      if (reference) break;
    }
  }
  corrector_.Restore(carried, reference);
  drift_corrector_.Restore(carried, reference);
  r.last_raw_pose = asr::LastRawPose(*store_);
  mapper_->Resume(r);
  if (optimizer_) {
    // The ASRs of a run that finished stay where it placed them. The ASRs of a
    // run cut short (killed before Finish: after finished_through, without a
    // placement) are placed again, in order, from their stored raw fields, as
    // that run placed them: the pose graph, its loop closures and its room
    // identities continue as if it had not stopped (docs/store.md).
    const auto through = asr::FinishedThrough(*store_);
    const long finished_through = through ? *through : std::numeric_limits<long>::max();
    for (int id : store_->Ids()) {
      auto x = store_->Get(id);
      if (!x) continue;
      if (id <= finished_through || store_->GetPlacement(id)) {
        optimizer_->AddStored(*x, store_->RoomOf(id));
      } else {
        optimizer_->Place(asr::MatchedView(std::move(*x)));
        NotePreBend(id);
        ++result_.replayed;
      }
    }
  }
  if (result_.correction == Correction::kNone && (carried.theta != 0.0 || carried.x != 0.0 || carried.y != 0.0)) {
    mapper_->SetCorrector([carried](asr::Asr raw) {
      raw.world_from_local_corrected = carried * raw.world_from_local_raw;
      raw.heading_correction_rad = carried.theta;
      return raw;
    });
  }
}

const char* ScanMatchName(ScanMatch m) {
  switch (m) {
    case ScanMatch::kOn:
      return "on";
    case ScanMatch::kOff:
      return "off";
    case ScanMatch::kAuto:
      break;
  }
  return "auto";
}

ScanMatch ParseScanMatch(const std::string& s) {
  if (s == "auto") return ScanMatch::kAuto;
  if (s == "on") return ScanMatch::kOn;
  if (s == "off") return ScanMatch::kOff;
  throw InputError("--scan-match " + s + ": expected auto, on or off");
}

double ParseDistanceScale(const std::string& s) {
  if (s == "auto") return std::numeric_limits<double>::quiet_NaN();
  if (s == "off") return 1.0;
  size_t used = 0;
  double v = 0.0;
  try {
    v = std::stod(s, &used);
  } catch (const std::exception&) {
    used = 0;
  }
  if (used == 0 || used != s.size() || !(v >= 0.5 && v <= 2.0))
    throw InputError("--distance-scale " + s + ": expected auto, off or a scale in [0.5, 2] (true distance / odometry distance)");
  return v;
}

std::vector<std::string> DistanceScaleWarnings(const RunResult& run) {
  std::vector<std::string> out;
  const localize::OdometryScaleEstimate& e = run.distance_scale_estimate;
  if (!run.distance_scale_measured || !e.valid) return out;
  // Three sigmas and 3 %: beyond what tyres and load do to a calibrated robot.
  const double off = e.scale - 1.0;
  if (std::abs(off) > 3.0 * e.sigma && std::abs(off) > 0.03) {
    std::string w;
    AppendF(&w,
            "the range sensors measure the odometry's distances %.1f %% %s (+- %.1f %%, %d runs towards walls): is the "
            "robot's wheel diameter or ticks per metre set right? The odometry was scaled by %.4f",
            100.0 * std::abs(off) / e.scale, off < 0.0 ? "long" : "short", 100.0 * e.sigma, e.runs,
            run.distance_scale_applied);
    out.push_back(w);
  }
  return out;
}

std::vector<std::string> ScanMatchWarnings(const MappingOptions& options, const RunResult& run) {
  std::vector<std::string> out;
  // Asked for: say when it could not help. (auto decides for itself.)
  if (options.scan_match != ScanMatch::kOn) return out;
  const localize::ScanOdometryStats& sm = run.scan_match;
  const localize::ScanOdometryOptions so;
  if (sm.scans == 0) {
    out.push_back("--scan-match: the robot has no laser scans to match; the odometry was used as it came");
  } else if (sm.MeanSpacing() > so.reference_m) {
    std::string w;
    AppendF(&w,
            "--scan-match: the scans are %.2f m apart on average (more than %.1f m): each was matched against one "
            "taken that far back, with less overlap, and the wheels' odometry may be the better of the two "
            "(docs/inputs.md, 'Laser odometry')",
            sm.MeanSpacing(), so.reference_m);
    out.push_back(w);
  }
  if (sm.scans > 0 && sm.matched < 0.9 * sm.scans) {
    std::string w;
    AppendF(&w, "--scan-match: %ld of %ld scans could not be matched (the wheels were kept there)",
            sm.scans - sm.matched, sm.scans);
    out.push_back(w);
  }
  return out;
}

void MappingPipeline::Push(sensors::LogRecord rec) {
  if (options_.add_drift_rad_per_m != 0.0) rec.odom = drift_adder_.Add(rec.odom);
  if (scan_density_) {
    // Deciding: held back until the first scans tell whether they are dense
    // enough to match (or a laser robot's log shows no scans for long).
    const bool decided = scan_density_->Add(rec.odom, rec.ranges);
    scan_pending_.push_back(std::move(rec));
    constexpr size_t kMaxPending = 20000;
    if (decided || scan_pending_.size() >= kMaxPending) DecideScanMatch();
    return;
  }
  Process(std::move(rec));
}

void MappingPipeline::MatchScans() {
  scan_odometry_ = std::make_unique<localize::ScanOdometry>(robot_);
  result_.scan_match_active = true;
  if (optimizer_) optimizer_->SetOdometryNoise(ScanOdometryNoise());
}

void MappingPipeline::DecideScanMatch() {
  if (!scan_density_) return;
  result_.scan_match_mean_step = scan_density_->mean_step();
  result_.scan_match_gaps = scan_density_->gaps();
  if (scan_density_->dense()) MatchScans();
  if (store_) store_->SetMeta(kMetaScanOdometry, scan_density_->dense() ? "1" : "0");
  scan_density_.reset();
  std::vector<sensors::LogRecord> pending;
  pending.swap(scan_pending_);
  for (auto& r : pending) Process(std::move(r));
}

void MappingPipeline::Process(sensors::LogRecord rec) {
  if (scan_odometry_) rec.odom = scan_odometry_->Correct(rec.odom, rec.ranges);
  if (scale_estimator_) {
    scale_estimator_->Add(rec);
    // Re-estimated as the runs grow by a twentieth (a long run holds
    // thousands): the scale from the next record on.
    const size_t runs = scale_estimator_->runs().size();
    if (runs >= scale_runs_next_) {
      scale_runs_next_ = std::max(runs + 1, static_cast<size_t>(std::ceil(1.05 * static_cast<double>(runs))));
      // Not before it is valid: until then the scale stays (1, or a resumed
      // run's carried one).
      const localize::OdometryScaleEstimate e = scale_estimator_->Estimate();
      if (e.valid) scaler_.SetScale(localize::ShrunkScale(e, options_.distance_scale_prior));
    }
  }
  rec.odom = scaler_.Apply(rec.odom);
  if (result_.records == 0) result_.first_time_s = rec.time_s;
  if (!result_.world_from_map && rec.truth) result_.world_from_map = *rec.truth * rec.odom.inverse();
  result_.last_time_s = rec.time_s;
  ++result_.records;
  mapper_->Push(rec);
}

void MappingPipeline::Settle() {
  if (scan_odometry_) result_.scan_match = scan_odometry_->stats();
  if (!finished_) mapper_->Settle();
}

const RunResult& MappingPipeline::Finish() {
  if (finished_) return result_;
  DecideScanMatch();  // a run too short to decide on: the wheels
  if (scan_odometry_) result_.scan_match = scan_odometry_->stats();
  if (scale_estimator_) {
    scale_estimator_->Finish();
    result_.distance_scale_estimate = scale_estimator_->Estimate();
  }
  result_.distance_scale_applied = scaler_.scale();
  finished_ = true;
  mapper_->Finish();
  result_.mapper = mapper_->stats();
  if (store_ && scale_estimator_ && result_.distance_scale_applied != 1.0)
    store_->SetMeta(kMetaDistanceScale, Num(result_.distance_scale_applied));
  std::map<int, double> revised;  // ASR id -> heading correction after the revision
  if (result_.correction == Correction::kPoseGraph) {
    result_.graph = optimizer_->Finish();
    std::vector<int> ids;
    std::map<int, size_t> entry_of;  // ASR id -> its graph entry
    std::vector<asr::Placement> placements;
    std::vector<asr::ClosureRecord> closures;
    // Each ASR's corrected path and walls move into the store (its placement
    // and its walls): RunResult keeps the graph's figures, not a second copy
    // of the map.
    for (auto& e : result_.graph.asrs) {
      asr::Placement p;
      p.asr_id = e.asr_id;
      p.room_id = e.room_id;
      p.covariance = e.covariance;
      p.uncertain = e.uncertain;
      p.drift_rate_rad_per_m = e.drift_rate_rad_per_m;
      p.corrected_path = std::move(e.corrected_path);
      e.corrected_path = {};
      for (const auto& w : e.why) p.why += (p.why.empty() ? "" : "; ") + w;
      placements.push_back(std::move(p));
      entry_of[e.asr_id] = ids.size();
      ids.push_back(e.asr_id);
    }
    for (const auto& c : result_.graph.closures)
      closures.push_back({c.from_asr, c.to_asr, c.relative, c.agreement, c.rmse_m, c.mahalanobis2, c.accepted,
                          c.same_room, c.reason});
    // The ASRs are revised one at a time inside the store's transaction.
    store_->RevisePlacements(ids, [&](asr::Asr& x) {
      auto& e = result_.graph.asrs[entry_of.at(x.id)];
      x.world_from_local_corrected = e.pose;
      if (!e.corrected_walls.empty() || x.walls_local.empty()) x.walls_local = std::move(e.corrected_walls);
      e.corrected_walls = {};
      x.heading_correction_rad = localize::CorrectionOf(x).theta;
      if (e.has_covariance) x.heading_uncertainty_rad = std::sqrt(std::max(0.0, e.covariance(2, 2)));
      revised[e.asr_id] = x.heading_correction_rad;
    }, placements, closures);
    // The graph (every ASR's faces, samples and paths) is no longer needed:
    // the outputs are written from the store.
    optimizer_.reset();
  } else if (result_.correction == Correction::kDriftFilter) {
    if (options_.smooth) {
      // The drift rate learnt along the run revises the corrections of this
      // run's ASRs (RTS smoothing), the first ones above all.
      for (const auto& r : drift_corrector_.Smooth()) {
        auto x = store_->Get(r.asr_id);
        if (!x) continue;
        x->world_from_local_corrected = r.delta * x->world_from_local_corrected;
        x->heading_correction_rad = localize::CorrectionOf(*x).theta;
        store_->Put(*x);
        revised[r.asr_id] = x->heading_correction_rad;
        ++result_.smoothed;
      }
    }
    const auto& f = drift_corrector_.odometry();
    result_.drift_rate_rad_per_m = f.rate_rad_per_m();
    result_.drift_rate_sigma_rad_per_m = f.rate_sigma_rad_per_m();
    result_.drift_measurements = f.measurements();
    result_.drift_rejects = f.rejects();
    result_.drift_walk_rad_per_sqrt_m = f.heading_walk_rad_per_sqrt_m();
    result_.drift_sigma_scale = f.sigma_scale();
  }
  for (auto& s : result_.asrs)
    if (auto it = revised.find(s.id); it != revised.end()) s.heading_correction_rad = it->second;
  if (store_) store_->SetMeta(asr::kMetaFinishedThrough, std::to_string(store_->MaxId()));
  return result_;
}

}  // namespace cogmap::mapping
