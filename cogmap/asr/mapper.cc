#include "cogmap/asr/mapper.h"

#include <charconv>
#include <chrono>
#include <cmath>
#include <condition_variable>
#include <cstdio>
#include <exception>
#include <limits>
#include <mutex>
#include <thread>

#include "cogmap/vectorize/orientation.h"

namespace cogmap::asr {

namespace {

using Clock = std::chrono::steady_clock;
double Since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

std::string PoseText(const Pose2& p) {
  char buf[96];
  std::snprintf(buf, sizeof(buf), "%.17g %.17g %.17g", p.x, p.y, p.theta);
  return buf;
}

}  // namespace

namespace {
// A positive number in the store's meta, shortest round-trip decimal.
void SetPositiveMeta(AsrStore* store, const char* key, double v) {
  char buf[32];
  const auto end = std::to_chars(buf, buf + sizeof buf, v).ptr;
  store->SetMeta(key, std::string(buf, end));
}
}  // namespace

void SetRobotRadius(AsrStore* store, double radius_m) { SetPositiveMeta(store, kMetaRobotRadius, radius_m); }
std::optional<double> RobotRadius(const AsrStore& store) { return store.GetMetaPositive(kMetaRobotRadius); }
void SetSensorReach(AsrStore* store, double reach_m) { SetPositiveMeta(store, kMetaSensorReach, reach_m); }
std::optional<double> SensorReach(const AsrStore& store) { return store.GetMetaPositive(kMetaSensorReach); }
void SetSensorBeam(AsrStore* store, double beam_rad) { SetPositiveMeta(store, kMetaSensorBeam, beam_rad); }
std::optional<double> SensorBeam(const AsrStore& store) { return store.GetMetaPositive(kMetaSensorBeam); }
std::optional<long> FinishedThrough(const AsrStore& store) {
  return store.GetMetaInt(kMetaFinishedThrough, -1, std::numeric_limits<int>::max());
}
std::optional<long> NextAsrId(const AsrStore& store) {
  return store.GetMetaInt(kMetaNextId, 0, std::numeric_limits<int>::max() - 1);
}
std::optional<Pose2> LastRawPose(const AsrStore& store) { return store.GetMetaPose(kMetaLastRawPose); }

Pose2 BestRigidFit(const std::vector<Pose2>& from, const std::vector<Pose2>& to) {
  const size_t n = std::min(from.size(), to.size());
  if (n == 0) return {};
  double c = 0.0, s = 0.0;
  Vec2 cf(0.0, 0.0), ct(0.0, 0.0);
  for (size_t i = 0; i < n; ++i) {
    const double d = AngleDiff(to[i].theta, from[i].theta);
    c += std::cos(d);
    s += std::sin(d);
    cf += from[i].translation();
    ct += to[i].translation();
  }
  const double theta = (c == 0.0 && s == 0.0) ? 0.0 : std::atan2(s, c);
  cf /= double(n);
  ct /= double(n);
  const Vec2 t = ct - RotateAbout(cf, Vec2(0.0, 0.0), theta);
  return {t.x(), t.y(), theta};
}

std::vector<Vec2> FreeSpaceHull(const grid::Grid2D<float>& values, const vectorize::CellClasses& classes,
                                double opening_m, double max_area_loss) {
  const grid::MapLimits& lim = values.limits();
  const int w = lim.width(), h = lim.height();
  const size_t n = static_cast<size_t>(w) * h;
  auto free = [&](int x, int y) {  // explored empty or path; outside the grid is not
    return x >= 0 && y >= 0 && x < w && y < h && values.at(x, y) < 0.0f;
  };
  const int r = std::max(0, static_cast<int>(std::lround(opening_m / lim.cell_m())));
  // f(index) for each floor cell beside cell 'c' (4-connected).
  auto each_floor_neighbour = [&](int c, auto&& f) {
    const int x = c % w, y = c / w;
    const int nx[4] = {x + 1, x - 1, x, x}, ny[4] = {y, y, y + 1, y - 1};
    for (int i = 0; i < 4; ++i)
      if (free(nx[i], ny[i])) f(ny[i] * w + nx[i]);
  };
  // City-block distance (cells) of every floor cell to the nearest cell that
  // is not floor, up to r + 1 (all the opening asks): a breadth-first pass
  // from the floor cells beside one. Only floor cells are visited. The path
  // cells are listed on the way (row by row).
  constexpr uint16_t kFar = std::numeric_limits<uint16_t>::max();
  std::vector<uint16_t> dist(n, 0);
  std::vector<int> queue, path_cells;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      if (!free(x, y)) continue;
      const bool edge = !free(x + 1, y) || !free(x - 1, y) || !free(x, y + 1) || !free(x, y - 1);
      dist[static_cast<size_t>(y) * w + x] = edge ? 1 : kFar;
      if (edge) queue.push_back(y * w + x);
      if (classes.IsPath(values.at(x, y))) path_cells.push_back(y * w + x);
    }
  for (size_t k = 0; k < queue.size(); ++k) {
    const uint16_t d = dist[queue[k]];
    if (d > r) continue;  // farther than r + 1 is all the core test needs
    each_floor_neighbour(queue[k], [&](int c) {
      if (dist[c] <= d + 1) return;
      dist[c] = static_cast<uint16_t>(d + 1);
      queue.push_back(c);
    });
  }
  // The core: floor cells farther than r from anything else, 4-connected to a
  // path cell of the core; then the core grown back by r through floor cells,
  // and the path. An opening narrower than 2 r (a door, a gap in a wall) does
  // not connect the core to the floor seen through it. 'reach' holds the
  // growth step + 1 of every cell taken (0: not taken).
  std::vector<uint16_t> reach(n, 0);
  queue.clear();
  for (int c : path_cells)
    if (dist[c] > r) reach[c] = 1, queue.push_back(c);
  for (size_t k = 0; k < queue.size(); ++k)
    each_floor_neighbour(queue[k], [&](int c) {
      if (reach[c] || dist[c] <= r) return;
      reach[c] = 1;
      queue.push_back(c);
    });
  for (int c : path_cells)
    if (!reach[c]) reach[c] = 1, queue.push_back(c);
  std::vector<int> row_lo(h, w), row_hi(h, -1);
  for (size_t k = 0; k < queue.size(); ++k) {
    const int x = queue[k] % w, y = queue[k] / w;
    const int d = reach[queue[k]];  // growth step + 1
    row_lo[y] = std::min(row_lo[y], x);
    row_hi[y] = std::max(row_hi[y], x);
    if (d > r) continue;
    each_floor_neighbour(queue[k], [&](int c) {
      if (reach[c]) return;
      reach[c] = static_cast<uint16_t>(d + 1);
      queue.push_back(c);
    });
  }
  // Per row, the extreme cells: their outer corners carry the hull.
  std::vector<Vec2> corners;
  for (int y = 0; y < h; ++y) {
    if (row_hi[y] < 0) continue;
    for (const int x : {row_lo[y], row_hi[y] + 1})
      for (const int d : {0, 1}) corners.push_back(lim.FromCellCoords(Vec2(x, y + d)));
  }
  return SimplifyConvex(ConvexHull(std::move(corners)), max_area_loss);
}

std::vector<Vec2> SimplifyConvex(std::vector<Vec2> poly, double max_area_loss) {
  // Dropping a vertex of a convex polygon cuts off the triangle it makes with
  // its neighbours; the polygon stays convex and inside the old one.
  const double budget = max_area_loss * std::abs(SignedArea(poly));
  double lost = 0.0;
  auto cut = [&](size_t i) {
    const Vec2& a = poly[(i + poly.size() - 1) % poly.size()];
    const Vec2& c = poly[(i + 1) % poly.size()];
    return std::abs(SignedArea({a, poly[i], c}));
  };
  while (poly.size() > 3) {
    size_t best = 0;
    for (size_t i = 1; i < poly.size(); ++i)
      if (cut(i) < cut(best)) best = i;
    if (lost + cut(best) > budget) break;
    lost += cut(best);
    poly.erase(poly.begin() + static_cast<long>(best));
  }
  return poly;
}

CognitiveMapper::CognitiveMapper(const sensors::RobotDescription& robot, const MapperOptions& options,
                                 AsrStore* store, Callback on_close)
    : robot_(robot),
      options_(options),
      store_(store),
      on_close_(std::move(on_close)),
      detector_(robot, options.boundary) {}

// The threads of MapperOptions::close_in_background: a closed ASR goes through
// two stages, each on a thread of its own, one ASR at a time and in order:
// its walls (the grid vectorised and freed, the floor it saw) and the part
// of its placing that reads it alone (SetPlacer's preparer), then the walls
// it keeps (a sonar's cone grid vectorised), its placement and store entry.
// While one room is placed the next can be vectorised and the one after it
// mapped. At most one ASR waits before each stage, so at most four closed
// rooms hold a grid besides the open one (each grid is freed once
// vectorised); the first error stops both stages and is raised on the
// caller's thread.
class CognitiveMapper::Worker {
 public:
  struct Job {
    std::unique_ptr<Current> closing;
    Pose2 last_raw_pose;
    int next_id = 0;
    Asr out;
    std::unique_ptr<PlacementWork> prepared;
  };
  using Stage = std::function<void(Job&)>;
  Worker(Stage walls, Stage place) : work_{std::move(walls), std::move(place)} {
    for (int s = 0; s < 2; ++s) threads_[s] = std::thread([this, s] { Run(s); });
  }
  // Finishes the ASRs already submitted (they were closed before whatever ends
  // the run), then stops.
  ~Worker() {
    {
      std::lock_guard<std::mutex> lock(mutex_);
      stop_ = true;
    }
    changed_.notify_all();
    for (auto& t : threads_) t.join();
  }
  // After an error the job is dropped (Take raises the error).
  void Submit(Job job) {
    std::unique_lock<std::mutex> lock(mutex_);
    changed_.wait(lock, [this] { return queue_[0].empty() || error_; });
    if (error_) return;
    queue_[0].push_back(std::move(job));
    changed_.notify_all();
  }
  // Returns once the ASR 'id' is placed (or nothing submitted is left to
  // place, or a stage failed: Take raises it).
  void WaitPlaced(int id) {
    std::unique_lock<std::mutex> lock(mutex_);
    changed_.wait(lock, [&] { return placed_through_ >= id || Idle(2) || error_; });
  }
  // The ASRs finished so far, in order; with 'all', once every submitted one
  // is. An error is raised once the ASRs finished before it are taken.
  std::deque<Asr> Take(bool all) {
    std::unique_lock<std::mutex> lock(mutex_);
    if (all) changed_.wait(lock, [this] { return Idle(2) || error_; });
    std::deque<Asr> out;
    out.swap(done_);
    if (out.empty() && error_) std::rethrow_exception(error_);
    return out;
  }

 private:
  // Nothing queued or in progress before stage 'upto'.
  bool Idle(int upto) const {
    for (int s = 0; s < upto; ++s)
      if (!queue_[s].empty() || busy_[s]) return false;
    return true;
  }
  void Run(int s) {
    std::unique_lock<std::mutex> lock(mutex_);
    for (;;) {
      changed_.wait(lock, [&] { return !queue_[s].empty() || error_ || (stop_ && Idle(s + 1)); });
      if (error_ || queue_[s].empty()) return;
      Job job = std::move(queue_[s].front());
      queue_[s].pop_front();
      busy_[s] = true;
      changed_.notify_all();
      lock.unlock();
      std::exception_ptr error;
      try {
        work_[s](job);
      } catch (...) {
        error = std::current_exception();
      }
      lock.lock();
      if (error) {
        error_ = error;
      } else if (s == 0) {
        changed_.wait(lock, [this] { return queue_[1].empty() || error_; });
        queue_[1].push_back(std::move(job));
      } else {
        placed_through_ = std::max(placed_through_, job.out.id);
        done_.push_back(std::move(job.out));
      }
      busy_[s] = false;
      changed_.notify_all();
    }
  }

  Stage work_[2];
  std::mutex mutex_;
  std::condition_variable changed_;
  std::deque<Job> queue_[2];
  bool busy_[2] = {false, false};
  std::deque<Asr> done_;
  int placed_through_ = -1;
  bool stop_ = false;
  std::exception_ptr error_;
  std::thread threads_[2];  // last: started once the rest is in place
};

CognitiveMapper::~CognitiveMapper() { worker_.reset(); }

void CognitiveMapper::Resume(const MapperResume& resume) {
  resume_ = resume;
  resumed_ = true;
  next_id_ = resume.next_id;
}

int64_t CognitiveMapper::current_grid_cells() const {
  return current_ && current_->grid ? current_->grid->limits().cell_count() : 0;
}

void CognitiveMapper::Start(const Pose2& entry_pose, double time_s, const std::optional<Exit>& entry_exit) {
  current_ = std::make_unique<Current>();
  Asr& a = current_->asr;
  a.id = next_id_++;
  if (pre_bend_ && !odometry_filter_ && a.id - pre_bend_lag_ >= 0) {
    if (worker_ && pre_bend_lag_ > 0) worker_->WaitPlaced(a.id - pre_bend_lag_);
    const double rate = pre_bend_(a.id - pre_bend_lag_);
    a.pre_bend_rad_per_m = std::isfinite(rate) ? rate : 0.0;
  }
  current_->bend = DriftReintegration(-a.pre_bend_rad_per_m, Vec2(0.0, 0.0));
  a.world_from_local_raw = Pose2{entry_pose.x, entry_pose.y, 0.0};
  a.world_from_local_corrected = a.world_from_local_raw;
  a.entry_pivot_m = entry_exit ? entry_exit->center_m : entry_pose.translation();
  a.start_time_s = time_s;
  a.end_time_s = time_s;
  if (entry_exit) a.exits.push_back(*entry_exit);
  current_->local_from_world = a.world_from_local_raw.inverse();
  grid::GridBounds bounds;
  bounds.cell_m = options_.cell_m;
  bounds.grow_chunk_cells = options_.grow_chunk_cells;
  current_->grid = std::make_unique<grid::HimmFusion>(true, options_.mhimm, bounds);
  if (options_.cone_output_walls) {
    grid::MhimmOptions cone = options_.mhimm;
    cone.cone_hits = true;
    current_->cone_grid = std::make_unique<grid::HimmFusion>(true, cone, bounds);
  }
}

void CognitiveMapper::Feed(const sensors::LogRecord& record, const Pose2& raw_odom) {
  Current& c = *current_;
  const auto t0 = Clock::now();
  const Pose2 at = c.bend(c.local_from_world * record.odom);
  // Where along the path these echoes are heard from (the path's poses as
  // the pose graph's bend counts them, then the way to this record).
  const double seen_s =
      c.path_s + (c.asr.path.empty() ? 0.0 : (record.odom.translation() - c.asr.path.back().translation()).norm());
  if (options_.seen_distances) c.grid->SetDistance(seen_s);
  c.grid->InsertSweep(at, robot_, record.ranges);
  if (c.cone_grid) {
    if (options_.seen_distances) c.cone_grid->SetDistance(seen_s);
    c.cone_grid->InsertSweep(at, robot_, record.ranges);
  }
  c.asr.seconds.grid += Since(t0);
  stats_.peak_grid_cells = std::max<int64_t>(stats_.peak_grid_cells, c.grid->limits().cell_count());
  // The path is sampled every path_step_m of odometry. When the log has
  // ground truth, samples are taken only at records that carry it, and the
  // true pose of the same record goes into true_path: path[i] and
  // true_path[i] are then the same instant (what the heading error compares).
  // Records without truth in such a log (CARMEN's ODOM between FLASERs) add
  // nothing to either path.
  if (record.truth) seen_truth_ = true;
  if (c.turn_started) c.turn_acc += std::abs(NormalizeAngle(raw_odom.theta - c.turn_last));
  c.turn_last = raw_odom.theta;
  c.turn_started = true;
  auto& path = c.asr.path;
  const bool moved =
      path.empty() || (path.back().translation() - record.odom.translation()).norm() >= options_.path_step_m - 1e-9;
  if (moved && (record.truth || !seen_truth_)) {
    if (!path.empty()) c.path_s += (record.odom.translation() - path.back().translation()).norm();
    path.push_back(record.odom);
    c.asr.path_turn_rad.push_back(path.size() == 1 ? 0.0 : c.turn_acc);
    c.turn_acc = 0.0;
    c.path_times.push_back(record.time_s);
    c.raw_path.push_back(raw_odom);
    if (record.truth) {
      c.asr.true_path.push_back(*record.truth);
      c.true_path_times.push_back(record.time_s);
    }
  }
  c.asr.end_time_s = record.time_s;
}

void CognitiveMapper::Close(const std::optional<Exit>& exit, double end_time_s) {
  Current& c = *current_;
  Asr& a = c.asr;
  // The path ends at the cut (records of the doorway's far half went to the
  // old grid as well, but the robot was already in the next ASR).
  auto truncate = [end_time_s](std::vector<Pose2>* poses, std::vector<double>* times) {
    size_t n = times->size();
    while (n > 1 && (*times)[n - 1] > end_time_s) --n;
    poses->resize(n);
    times->resize(n);
  };
  truncate(&a.path, &c.path_times);
  truncate(&a.true_path, &c.true_path_times);
  c.raw_path.resize(a.path.size());
  // The turn after the last pose kept: the cut poses' and what followed them.
  a.turn_after_path_rad = c.turn_acc;
  for (size_t k = a.path.size(); k < a.path_turn_rad.size(); ++k) a.turn_after_path_rad += a.path_turn_rad[k];
  a.path_turn_rad.resize(a.path.size());
  if (exit) a.exits.push_back(*exit);
  a.end_time_s = std::max(a.start_time_s, end_time_s);
  current_->records_through = first_record_ + stats_.records;
  if (options_.close_in_background && !odometry_filter_) {
    if (!worker_)
      worker_ = std::make_unique<Worker>(
          [this](Worker::Job& job) {
            BuildWalls(*job.closing);
            job.prepared = Prepare(*job.closing);
          },
          [this](Worker::Job& job) {
            job.out = Place(std::move(job.closing), job.last_raw_pose, job.next_id, std::move(job.prepared));
          });
    worker_->Submit({std::move(current_), last_raw_pose_, next_id_, {}, nullptr});
    DeliverFinished(false);
    return;
  }
  BuildWalls(*current_);
  const Asr out = Place(std::move(current_), last_raw_pose_, next_id_, nullptr);
  Deliver(out);
}

namespace {
// Per vertex of 'walls', the distance driven when the hits within two cells
// of it were heard (HimmFusion::HitDistance; NaN: none).
std::vector<std::vector<double>> SeenDistances(const grid::HimmFusion& grid, const std::vector<Polyline>& walls) {
  std::vector<std::vector<double>> out(walls.size());
  const double radius = 2.0 * grid.limits().cell_m();
  for (size_t i = 0; i < walls.size(); ++i)
    for (const Vec2& p : walls[i]) {
      const std::optional<double> s = grid.HitDistance(p, radius);
      out[i].push_back(s ? *s : std::numeric_limits<double>::quiet_NaN());
    }
  return out;
}
}  // namespace

void CognitiveMapper::BuildWalls(Current& c) {
  Asr& a = c.asr;
  const vectorize::VectorizeResult v = vectorize::Vectorize(c.grid->values(), options_.vectorize);
  a.walls_local = v.polylines;
  if (options_.seen_distances) a.walls_seen_s = SeenDistances(*c.grid, a.walls_local);
  a.bytes.grid = v.bytes.grid;
  a.bytes.vertices = v.bytes.vertices;
  a.bytes.polylines = v.bytes.polylines;
  a.seconds.clean = v.seconds.clean;
  a.seconds.extract = v.seconds.extract;
  a.seconds.simplify = v.seconds.simplify;
  a.seconds.fit = v.seconds.fit;
  if (options_.grid_orientation) {
    // The orientation of the occupied cells, for the heading correction.
    auto orientation = [this](const grid::Grid2D<float>& g) {
      std::vector<Vec2> cells;
      for (int y = 0; y < g.limits().height(); ++y)
        for (int x = 0; x < g.limits().width(); ++x)
          if (options_.vectorize.clean.classes.IsOccupied(g.at(x, y))) cells.push_back(Vec2(x + 0.5, y + 0.5));
      return vectorize::DominantOrientation(cells);
    };
    vectorize::Orientation o = orientation(c.grid->values());
    // A ring that looks only forward: the cone grid's, where it is within
    // the lean of the axis grid's (MapperOptions::orientation_from_cone).
    if (options_.orientation_from_cone && c.cone_grid && o.valid) {
      const vectorize::Orientation cone = orientation(c.cone_grid->values());
      const double apart = std::abs(std::remainder(cone.angle_rad - o.angle_rad, 0.5 * kPi));
      if (cone.valid && apart <= options_.orientation_cone_window_rad) o = cone;
    }
    a.grid_orientation = {o.valid, o.angle_rad, o.contrast, o.points};
  }
  a.free_hull_local = FreeSpaceHull(c.grid->values(), options_.vectorize.clean.classes, options_.free_opening_m,
                                     options_.free_hull_area_loss);
  c.grid.reset();  // the room's grid is gone from here on
}

std::unique_ptr<PlacementWork> CognitiveMapper::Prepare(const Current& closing) const {
  // A corrector changes the ASR before the placer sees it.
  if (!preparer_ || corrector_) return nullptr;
  return preparer_(closing.asr);
}

Asr CognitiveMapper::Place(std::unique_ptr<Current> closing, const Pose2& last_raw_pose, int next_id,
                           std::unique_ptr<PlacementWork> prepared) {
  Current& c = *closing;
  Asr& a = c.asr;
  // The walls kept from the cone grid (on this stage's thread: the walls
  // stage, which vectorises the axis grid, has more to do).
  if (c.cone_grid) {
    const auto t0 = Clock::now();
    vectorize::VectorizeResult kept = vectorize::Vectorize(c.cone_grid->values(), options_.vectorize);
    a.output_walls_local = std::move(kept.polylines);
    if (options_.seen_distances) a.output_walls_seen_s = SeenDistances(*c.cone_grid, a.output_walls_local);
    a.has_output_walls = true;
    // The sizes are those of the walls kept (the grid's, of the axis grid).
    a.bytes.vertices = kept.bytes.vertices;
    a.bytes.polylines = kept.bytes.polylines;
    c.cone_grid.reset();
    a.seconds.fit += Since(t0);
  }
  Asr out = corrector_ ? corrector_(std::move(a)) : std::move(a);
  // The placer sees the ASR in the frame its walls were built in (the
  // pre-corrected one when the odometry is filtered).
  if (placer_) out = placer_(std::move(out), std::move(prepared));
  if (out.has_output_walls) {
    out.matched_walls_local = std::move(out.walls_local);
    out.has_matched_walls = true;
    out.walls_local = std::move(out.output_walls_local);
    out.output_walls_local = {};
    out.has_output_walls = false;
  }
  if (odometry_filter_) {
    // Back to the raw odometry frame (see SetOdometryFilter).
    const Pose2 raw_from_pre = BestRigidFit(out.path, c.raw_path);
    out.world_from_local_raw = raw_from_pre * out.world_from_local_raw;
    out.entry_pivot_m = raw_from_pre * out.entry_pivot_m;
    for (auto& e : out.exits) e.center_m = raw_from_pre * e.center_m;
    out.path = std::move(c.raw_path);
    out.heading_correction_rad = (out.world_from_local_corrected * out.world_from_local_raw.inverse()).theta;
  }
  const long records_through = closing->records_through;
  closing.reset();
  if (store_) {
    store_->Put(out, {{kMetaLastRawPose, PoseText(last_raw_pose)},
                      {kMetaNextId, std::to_string(next_id)},
                      {kMetaLogFingerprint, log_fingerprint_},
                      {kMetaLastRecord, std::to_string(records_through)}});
  }
  return out;
}

void CognitiveMapper::Deliver(const Asr& out) {
  ++stats_.asr_count;
  if (on_close_) on_close_(out);
}

void CognitiveMapper::DeliverFinished(bool all) {
  if (!worker_) return;
  // A second look raises an error that came after the ASRs handed over.
  for (int look = 0; look < 2; ++look) {
    const std::deque<Asr> finished = worker_->Take(all);
    for (const Asr& out : finished) Deliver(out);
    if (finished.empty()) break;
  }
}

void CognitiveMapper::Push(const sensors::LogRecord& input) {
  const auto t0 = Clock::now();
  if (!world_from_odom_) {
    world_from_odom_ = (resumed_ && resume_.last_raw_pose) ? *resume_.last_raw_pose * input.odom.inverse()
                                                           : Pose2{};
  }
  sensors::LogRecord record = input;
  record.odom = *world_from_odom_ * input.odom;
  last_raw_pose_ = record.odom;
  const Pose2 raw_odom = record.odom;
  if (odometry_filter_) record.odom = odometry_filter_(raw_odom, record.time_s);
  ++stats_.records;
  stats_.readings += static_cast<long>(record.ranges.size());
  finished_ = false;

  if (!current_) {
    std::optional<Exit> entry;
    if (resumed_ && resume_.previous_asr && stats_.asr_count == 0) {
      entry = resume_.leaving_exit ? Exit{resume_.leaving_exit->center_m, resume_.leaving_exit->width_m,
                                          *resume_.previous_asr, next_id_}
                                   : Exit{record.odom.translation(), 0.0, *resume_.previous_asr, next_id_};
    }
    Start(record.odom, record.time_s, entry);
  }
  Feed(record, raw_odom);
  buffer_.push_back({seq_++, record, raw_odom});
  while (buffer_.size() > std::max<size_t>(1, options_.max_replay_records)) buffer_.pop_front();

  const auto cut = detector_.Push(record);
  if (cut) {
    const Exit exit{cut->center_m, cut->width_m, current_->asr.id, next_id_};
    Close(exit, cut->time_s);
    Start(cut->pose, cut->time_s, exit);
    // Readings after the cut belong to the new ASR as well: replay them.
    while (!buffer_.empty() && buffer_.front().record.time_s < cut->time_s) buffer_.pop_front();
    for (const auto& b : buffer_) Feed(b.record, b.raw_odom);
  }
  if (detector_.state() == BoundaryState::kInRoom) buffer_.clear();
  stats_.turn_backs = detector_.turn_backs();
  DeliverFinished(false);
  stats_.seconds += Since(t0);
}

void CognitiveMapper::Finish() {
  if (finished_) return;
  const auto t0 = Clock::now();
  if (current_) Close(std::nullopt, current_->asr.end_time_s);
  DeliverFinished(true);
  buffer_.clear();
  finished_ = true;
  stats_.seconds += Since(t0);
}

}  // namespace cogmap::asr
