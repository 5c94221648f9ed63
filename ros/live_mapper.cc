#include "ros/live_mapper.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <condition_variable>
#include <deque>
#include <exception>
#include <fstream>
#include <future>
#include <filesystem>
#include <map>
#include <mutex>
#include <set>
#include <thread>

#include "cogmap/asr/store.h"
#include "cogmap/core/error.h"
#include "cogmap/io/log_reader.h"
#include "cogmap/io/native_log.h"
#include "cogmap/io/ros_log.h"
#include "cogmap/mapping/map_job.h"
#include "cogmap/mapping/pipeline.h"
#include "cogmap/sensors/robot_json.h"

namespace cogmap::rosnode {
namespace {

using io::ros::BagMessage;
using io::ros::MessageType;

int64_t StampOf(const io::ros::Message& m) {
  return std::visit(
      [](const auto& x) -> int64_t {
        using T = std::decay_t<decltype(x)>;
        if constexpr (std::is_same_v<T, std::monostate>) return 0;
        else if constexpr (std::is_same_v<T, io::ros::TfMessage>)
          return x.transforms.empty() ? 0 : x.transforms.front().header.stamp_ns;
        else return x.header.stamp_ns;
      },
      m);
}

bool IsDriving(MessageType t) {  // range or odometry: needed before the reader can open
  return t == MessageType::kLaserScan || t == MessageType::kRange || t == MessageType::kPointCloud ||
         t == MessageType::kPointCloud2 || t == MessageType::kOdometry;
}

// What the callbacks and the mapping thread share.
struct Shared {
  std::mutex mutex;
  std::condition_variable cv;
  std::vector<io::ros::TopicInfo> subscribed;  // every subscription
  std::vector<long> counts;                    // messages received per subscription
  // The reader sees the subscriptions that had messages when it opened (a bag
  // holds no empty topic); the others' messages are dropped.
  std::vector<io::ros::TopicInfo> topics;
  std::vector<int> exposed;                    // subscription -> topics index, or -1
  // A message and when it arrived (steady clock).
  struct Entry {
    BagMessage m;
    std::chrono::steady_clock::time_point arrived;
  };
  std::deque<Entry> buffer;     // in (stamp, arrival) order
  std::vector<Entry> pending;   // arrived while the reader was opening
  bool opening = false;             // the reader's first passes replay a frozen buffer
  bool live = false;
  bool closed = false;
  std::chrono::steady_clock::duration window = std::chrono::milliseconds(500);
  int64_t newest_ns = 0;  // the newest stamp received
  std::deque<std::function<void()>> tasks;  // run by the mapping thread

  void Insert(Entry&& e) {  // under the lock
    auto at = std::upper_bound(buffer.begin(), buffer.end(), e.m.time_ns,
                               [](int64_t t, const Entry& b) { return t < b.m.time_ns; });
    buffer.insert(at, std::move(e));
  }
};

// A bag that is being recorded: the reader's opening passes replay what has
// arrived so far; the main pass then takes messages in stamp order, each once
// it has waited the reorder window since it arrived (messages of one moment
// on different topics arrive over separate connections, in any order), or at
// once when the input has ended.
class LiveSource : public io::ros::BagSource {
 public:
  explicit LiveSource(std::shared_ptr<Shared> s) : s_(std::move(s)), path_("live ROS topics") {}
  const std::vector<io::ros::TopicInfo>& topics() const override { return s_->topics; }
  void Start(const std::vector<int>& topics) override {
    std::lock_guard lock(s_->mutex);
    pass_ = std::set<int>(topics.begin(), topics.end());
    cursor_ = 0;
  }
  bool Next(BagMessage* out) override {
    std::unique_lock lock(s_->mutex);
    if (!s_->live) {
      while (cursor_ < s_->buffer.size()) {
        const BagMessage& m = s_->buffer[cursor_++].m;
        if (pass_.count(m.topic)) {
          *out = m;
          return true;
        }
      }
      return false;
    }
    while (true) {
      while (!s_->tasks.empty()) {
        auto task = std::move(s_->tasks.front());
        s_->tasks.pop_front();
        lock.unlock();
        task();
        lock.lock();
      }
      if (!s_->buffer.empty()) {
        // The front (smallest stamp) goes once it has waited its window: a
        // message of an earlier stamp arriving meanwhile goes before it.
        const auto due = s_->buffer.front().arrived + s_->window;
        if (s_->closed || std::chrono::steady_clock::now() >= due) {
          BagMessage m = std::move(s_->buffer.front().m);
          s_->buffer.pop_front();
          if (!pass_.count(m.topic)) continue;
          *out = std::move(m);
          return true;
        }
        s_->cv.wait_until(lock, due);
        continue;
      }
      if (s_->closed) return false;
      s_->cv.wait(lock);
    }
  }
  double progress() const override { return 0.0; }
  const std::string& path() const override { return path_; }
  std::string kind() const override { return "live ROS topics"; }

 private:
  std::shared_ptr<Shared> s_;
  std::string path_;
  std::set<int> pass_;
  size_t cursor_ = 0;
};

GridSnapshot FromValues(const grid::HimmFusion& g, const Pose2& world_from_local) {
  GridSnapshot out;
  const grid::MapLimits& l = g.limits();
  out.resolution_m = l.cell_m();
  out.width = l.width();
  out.height = l.height();
  const Vec2 o = world_from_local * l.origin();
  out.origin_x = o.x();
  out.origin_y = o.y();
  out.origin_yaw = world_from_local.theta;
  out.data.resize(static_cast<size_t>(out.width) * out.height);
  for (int y = 0; y < out.height; ++y)
    for (int x = 0; x < out.width; ++x) {
      const grid::CellClass c = g.Classify(x, y);
      out.data[static_cast<size_t>(y) * out.width + x] =
          c == grid::CellClass::kOccupied ? 100 : (c == grid::CellClass::kEmpty || c == grid::CellClass::kRobotPath) ? 0 : -1;
    }
  return out;
}

}  // namespace

struct LiveMapper::Impl {
  LiveOptions options;
  std::shared_ptr<Shared> shared = std::make_shared<Shared>();
  std::thread thread;
  mutable std::mutex state_mutex;  // snapshot, grid, error, finished
  MapSnapshot snapshot;
  // The last snapshot of each open room's grid (raw odometry frame), by ASR
  // id, taken by the mapping thread every 50 records; a room's goes to
  // free_layers when its ASR is placed (on the pipeline's placing thread,
  // by then the mapping thread may be rooms ahead: the id, not the time,
  // says whose grid it is). current_room: the id of the latest snapshot.
  std::map<int, GridSnapshot> room_grids;
  int current_room = -1;
  // Per closed ASR: the last snapshot of its room grid (raw odometry frame)
  // and where the map puts that frame (corrected from raw, at close; the final
  // placements after the run).
  struct FreeLayer {
    int asr = 0;
    GridSnapshot grid;
    Pose2 map_from_raw;
  };
  std::vector<FreeLayer> free_layers;
  std::string error;
  bool finished = false;
  std::string summary;
  // Set by the mapping thread once the pipeline exists (for WriteFloorPlan).
  std::function<std::vector<std::string>()> write_outputs;

  void Run(std::function<void()> on_asr);
};

LiveMapper::LiveMapper(const LiveOptions& options) : impl_(std::make_unique<Impl>()) {
  impl_->options = options;
  if (options.mode != "paper" && options.mode != "default")
    throw InputError("mode " + options.mode + ": expected paper or default");
  for (const auto& t : options.topics) impl_->shared->subscribed.push_back({t.name, t.type, 0});
  impl_->shared->counts.assign(options.topics.size(), 0);
  impl_->shared->window = std::chrono::duration_cast<std::chrono::steady_clock::duration>(
      std::chrono::duration<double>(options.reorder_window_s));
  std::filesystem::create_directories(options.output_dir);
}

LiveMapper::~LiveMapper() {
  {
    std::lock_guard lock(impl_->shared->mutex);
    impl_->shared->closed = true;
  }
  impl_->shared->cv.notify_all();
  if (impl_->thread.joinable()) impl_->thread.join();
}

void LiveMapper::Receive(int topic, int64_t receive_ns, io::ros::Message message) {
  Shared& s = *impl_->shared;
  {
    std::lock_guard lock(s.mutex);
    if (s.closed || topic < 0 || topic >= static_cast<int>(s.subscribed.size())) return;
    Shared::Entry e;
    e.arrived = std::chrono::steady_clock::now();
    BagMessage& m = e.m;
    m.topic = topic;
    m.index = ++s.counts[topic];
    s.subscribed[topic].count = s.counts[topic];
    // A message without a stamp is taken to be as recent as the newest stamped
    // one (at the start: 1 ns, as a bag of the run holds it); the receive
    // time is on another clock than the stamps of a played bag.
    const int64_t stamp = StampOf(message);
    if (stamp != 0) s.newest_ns = std::max(s.newest_ns, stamp);
    m.time_ns = stamp != 0 ? stamp : std::max<int64_t>(s.newest_ns, 1);
    (void)receive_ns;
    m.message = std::move(message);
    if (s.opening) {
      s.pending.push_back(std::move(e));
    } else if (s.live) {
      m.topic = s.exposed[m.topic];
      if (m.topic < 0) return;
      s.topics[m.topic].count = m.index;
      s.Insert(std::move(e));
    } else {
      s.Insert(std::move(e));  // indexed by subscription until the reader opens
    }
  }
  s.cv.notify_all();
}

void LiveMapper::Start(std::function<void()> on_asr) {
  impl_->thread = std::thread([this, on_asr] { impl_->Run(on_asr); });
}

void LiveMapper::Impl::Run(std::function<void()> on_asr) {
  try {
    // Wait for a message on a range topic and on an odometry topic, and a little
    // for the latched tf_static.
    {
      std::unique_lock lock(shared->mutex);
      auto ready = [this] {
        if (shared->closed) return true;
        bool range = false, odometry = false;
        for (size_t i = 0; i < shared->subscribed.size(); ++i) {
          if (shared->counts[i] == 0) continue;
          const MessageType t = io::ros::TypeOf(shared->subscribed[i].type);
          range = range || (IsDriving(t) && t != MessageType::kOdometry);
          odometry = odometry || t == MessageType::kOdometry || t == MessageType::kTf;
        }
        return range && odometry;
      };
      shared->cv.wait(lock, ready);
      if (shared->closed && !ready()) return;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(500));
    {
      std::lock_guard lock(shared->mutex);
      shared->opening = true;
      shared->exposed.assign(shared->subscribed.size(), -1);
      for (size_t i = 0; i < shared->subscribed.size(); ++i)
        if (shared->counts[i] > 0) {
          shared->exposed[i] = static_cast<int>(shared->topics.size());
          shared->topics.push_back(shared->subscribed[i]);
        }
      for (auto& e : shared->buffer) e.m.topic = shared->exposed[e.m.topic];
    }
    io::LogOpenOptions open;
    if (!options.robot.empty()) open.robot = sensors::ResolveRobot(options.robot);
    std::unique_ptr<io::LogReader> reader = io::ros::OpenBagLog(std::make_unique<LiveSource>(shared), open);
    {
      std::lock_guard lock(shared->mutex);
      shared->opening = false;
      shared->live = true;
      for (auto& e : shared->pending) {
        e.m.topic = shared->exposed[e.m.topic];
        if (e.m.topic >= 0) shared->Insert(std::move(e));
      }
      shared->pending.clear();
    }
    const sensors::RobotDescription robot = open.robot ? *open.robot : *reader->robot_hint();
    const std::string store_path = (std::filesystem::path(options.output_dir) / "map.sqlite").string();
    auto store = asr::SqliteAsrStore::Open(store_path, asr::SqliteAsrStore::OpenMode::kReplace);
    mapping::MappingOptions mo;
    mo.paper = options.mode == "paper";
    mo.scan_match = mapping::ParseScanMatch(options.scan_match);
    mo.distance_scale = mapping::ParseDistanceScale(options.distance_scale);
    mapping::MappingPipeline pipeline(robot, mo, store.get());
    mapping::MapJob job;
    job.log_path = "-";
    job.log_format = "rosbag";
    job.robot_spec = options.robot;
    job.mapping = mo;
    job.output_dir = options.output_dir;
    const auto start = std::chrono::steady_clock::now();
    auto write = [&]() {
      // The rooms still being closed on the mapper's threads join the store
      // and the summaries first, so the files agree with each other.
      pipeline.Settle();
      mapping::OutputContext ctx;
      ctx.store_path = store_path;
      ctx.run_id = "live";
      ctx.start = start;
      return mapping::WriteMapOutputs(*store, pipeline.result(), job, robot, options.output_dir, ctx);
    };
    {
      std::lock_guard lock(state_mutex);
      write_outputs = [&]() { return write().written; };
    }
    pipeline.OnAsrClosed([&](const asr::Asr& x, const mapping::AsrSummary&) {
      {
        std::lock_guard lock(state_mutex);
        for (const auto& line : x.WallsWorldCorrected())
          for (size_t i = 1; i < line.size(); ++i)
            snapshot.walls.push_back({line[i - 1].x(), line[i - 1].y(), line[i].x(), line[i].y(), x.id});
        Vec2 c(0, 0);
        for (const auto& p : x.path) c += p.translation();
        if (!x.path.empty()) c /= static_cast<double>(x.path.size());
        c = x.world_from_local_corrected * (x.world_from_local_raw.inverse() * c);
        snapshot.rooms.push_back({x.id, store->RoomOf(x.id), c.x(), c.y()});
        for (const auto& e : x.exits) {
          if (e.from_asr != x.id && e.to_asr != x.id) continue;
          const Vec2 ec = x.world_from_local_corrected * (x.world_from_local_raw.inverse() * e.center_m);
          snapshot.graph.push_back({c.x(), c.y(), ec.x(), ec.y()});
        }
        ++snapshot.asrs;
        // The room's grid is gone once it closes: its last snapshot (at most
        // 50 records old) gives the free space the whole map shows. (This
        // runs on the placing thread: the mapper's current grid is the
        // mapping thread's, and by now may be a later room's.)
        if (auto it = room_grids.find(x.id); it != room_grids.end()) {
          if (!it->second.data.empty())
            free_layers.push_back({x.id, std::move(it->second),
                                   x.world_from_local_corrected * x.world_from_local_raw.inverse()});
          room_grids.erase(it);
        }
      }
      if (on_asr) on_asr();
    });
    // The records as mapped, as a native log beside the store: the run can be
    // mapped again offline (cogmap map OUTPUT/records.log).
    std::ofstream records_out((std::filesystem::path(options.output_dir) / "records.log").string());
    io::NativeLogWriter records_log(records_out, robot);
    sensors::LogRecord rec;
    long n = 0;
    while (reader->Next(&rec)) {
      records_log.Write(rec);
      pipeline.Push(rec);
      if (++n % 50 == 0)
        if (const auto* g = pipeline.mapper().current_grid()) {
          GridSnapshot grid = FromValues(*g, pipeline.mapper().current_world_from_local());
          const int id = pipeline.mapper().current_id();
          std::lock_guard lock(state_mutex);
          room_grids[id] = std::move(grid);
          current_room = id;
        }
    }
    pipeline.Finish();
    const mapping::MapJobSummary s = write();
    // The final placements replace what was published while mapping.
    MapSnapshot final_snapshot;
    for (int id : store->Ids()) {
      const auto x = store->Get(id);
      for (const auto& line : x->WallsWorldCorrected())
        for (size_t i = 1; i < line.size(); ++i)
          final_snapshot.walls.push_back({line[i - 1].x(), line[i - 1].y(), line[i].x(), line[i].y(), id});
      const auto placed = store->GetPlacement(id);
      const auto& path = placed && !placed->corrected_path.empty() ? placed->corrected_path : x->path;
      Vec2 c(0, 0);
      for (const auto& p : path) c += p.translation();
      if (!path.empty()) c /= static_cast<double>(path.size());
      final_snapshot.rooms.push_back({id, store->RoomOf(id), c.x(), c.y()});
    }
    final_snapshot.asrs = store->Count();
    {
      std::lock_guard lock(state_mutex);
      for (auto& layer : free_layers)
        if (const auto x = store->Get(layer.asr))
          layer.map_from_raw = x->world_from_local_corrected * x->world_from_local_raw.inverse();
      snapshot = std::move(final_snapshot);
      summary = std::to_string(s.records) + " records, " + std::to_string(s.asrs) + " ASRs, " +
                std::to_string(s.rooms) + " rooms; outputs in " + options.output_dir;
      finished = true;
      write_outputs = nullptr;
    }
    if (on_asr) on_asr();
  } catch (const std::exception& e) {
    std::lock_guard lock(state_mutex);
    error = e.what();
    write_outputs = nullptr;
  }
}

std::string LiveMapper::Finish() {
  {
    std::lock_guard lock(impl_->shared->mutex);
    impl_->shared->closed = true;
  }
  impl_->shared->cv.notify_all();
  if (impl_->thread.joinable()) impl_->thread.join();
  std::lock_guard lock(impl_->state_mutex);
  if (!impl_->error.empty()) throw InputError(impl_->error);
  if (!impl_->finished) throw InputError("no map: the input ended before every range and odometry topic had a message");
  return impl_->summary;
}

std::vector<std::string> LiveMapper::WriteFloorPlan() {
  // Run by the mapping thread between messages (it owns the store).
  auto done = std::make_shared<std::promise<std::vector<std::string>>>();
  auto result = done->get_future();
  {
    std::lock_guard state(impl_->state_mutex);
    if (!impl_->write_outputs) throw InputError("no map to write yet (mapping has not started, or has ended)");
    std::lock_guard lock(impl_->shared->mutex);
    impl_->shared->tasks.push_back([this, done] {
      try {
        std::function<std::vector<std::string>()> write;
        {
          std::lock_guard state(impl_->state_mutex);
          write = impl_->write_outputs;
        }
        done->set_value(write ? write() : std::vector<std::string>{});
      } catch (...) {
        done->set_exception(std::current_exception());
      }
    });
  }
  impl_->shared->cv.notify_all();
  return result.get();
}

MapSnapshot LiveMapper::Snapshot() const {
  std::lock_guard lock(impl_->state_mutex);
  return impl_->snapshot;
}

GridSnapshot LiveMapper::CurrentRoomGrid() const {
  std::lock_guard lock(impl_->state_mutex);
  const auto it = impl_->room_grids.find(impl_->current_room);
  return it == impl_->room_grids.end() ? GridSnapshot{} : it->second;
}

GridSnapshot LiveMapper::WholeMapGrid(double cell_m) const {
  std::lock_guard lock(impl_->state_mutex);
  const MapSnapshot& s = impl_->snapshot;
  const auto& layers = impl_->free_layers;
  GridSnapshot g;
  g.resolution_m = cell_m;
  // Extent: every wall and every room grid's corners where the map puts them.
  double x0 = 1e300, y0 = 1e300, x1 = -1e300, y1 = -1e300;
  auto extend = [&](double x, double y) {
    x0 = std::min(x0, x);
    y0 = std::min(y0, y);
    x1 = std::max(x1, x);
    y1 = std::max(y1, y);
  };
  for (const auto& w : s.walls) {
    extend(w.x0, w.y0);
    extend(w.x1, w.y1);
  }
  // A layer's cell (i, j) centre in its raw frame, and back.
  auto raw_from_grid = [](const GridSnapshot& l) { return Pose2{l.origin_x, l.origin_y, l.origin_yaw}; };
  for (const auto& l : layers) {
    const Pose2 map_from_grid = l.map_from_raw * raw_from_grid(l.grid);
    for (double u : {0.0, l.grid.width * l.grid.resolution_m})
      for (double v : {0.0, l.grid.height * l.grid.resolution_m}) {
        const Vec2 c = map_from_grid * Vec2(u, v);
        extend(c.x(), c.y());
      }
  }
  if (x0 > x1) return g;
  const double margin = 1.0;
  // Within 16 Mpx whatever the building: a coarser cell for a larger one.
  const double area = (x1 - x0 + 2 * margin) * (y1 - y0 + 2 * margin);
  g.resolution_m = std::max(cell_m, std::sqrt(area / 16e6));
  g.origin_x = x0 - margin;
  g.origin_y = y0 - margin;
  g.width = static_cast<int>(std::ceil((x1 - x0 + 2 * margin) / g.resolution_m));
  g.height = static_cast<int>(std::ceil((y1 - y0 + 2 * margin) / g.resolution_m));
  g.data.assign(static_cast<size_t>(g.width) * g.height, -1);
  // Free: every map cell whose centre falls in a free cell of a room's grid
  // (resampled, nearest cell, over the room's footprint).
  for (const auto& l : layers) {
    const Pose2 map_from_grid = l.map_from_raw * raw_from_grid(l.grid);
    const Pose2 grid_from_map = map_from_grid.inverse();
    double lx0 = 1e300, ly0 = 1e300, lx1 = -1e300, ly1 = -1e300;
    for (double u : {0.0, l.grid.width * l.grid.resolution_m})
      for (double v : {0.0, l.grid.height * l.grid.resolution_m}) {
        const Vec2 c = map_from_grid * Vec2(u, v);
        lx0 = std::min(lx0, c.x());
        ly0 = std::min(ly0, c.y());
        lx1 = std::max(lx1, c.x());
        ly1 = std::max(ly1, c.y());
      }
    const int i0 = std::max(0, static_cast<int>((lx0 - g.origin_x) / g.resolution_m));
    const int j0 = std::max(0, static_cast<int>((ly0 - g.origin_y) / g.resolution_m));
    const int i1 = std::min(g.width - 1, static_cast<int>((lx1 - g.origin_x) / g.resolution_m));
    const int j1 = std::min(g.height - 1, static_cast<int>((ly1 - g.origin_y) / g.resolution_m));
    for (int j = j0; j <= j1; ++j)
      for (int i = i0; i <= i1; ++i) {
        const Vec2 c = grid_from_map * Vec2(g.origin_x + (i + 0.5) * g.resolution_m,
                                            g.origin_y + (j + 0.5) * g.resolution_m);
        const int u = static_cast<int>(std::floor(c.x() / l.grid.resolution_m));
        const int v = static_cast<int>(std::floor(c.y() / l.grid.resolution_m));
        if (u < 0 || v < 0 || u >= l.grid.width || v >= l.grid.height) continue;
        if (l.grid.data[static_cast<size_t>(v) * l.grid.width + u] == 0)
          g.data[static_cast<size_t>(j) * g.width + i] = 0;
      }
  }
  // Occupied: the walls, drawn over the free space.
  for (const auto& w : s.walls) {
    const double len = std::hypot(w.x1 - w.x0, w.y1 - w.y0);
    const int steps = std::max(1, static_cast<int>(std::ceil(len / (0.5 * g.resolution_m))));
    for (int k = 0; k <= steps; ++k) {
      const double t = static_cast<double>(k) / steps;
      const int cx = static_cast<int>((w.x0 + t * (w.x1 - w.x0) - g.origin_x) / g.resolution_m);
      const int cy = static_cast<int>((w.y0 + t * (w.y1 - w.y0) - g.origin_y) / g.resolution_m);
      if (cx >= 0 && cy >= 0 && cx < g.width && cy < g.height) g.data[static_cast<size_t>(cy) * g.width + cx] = 100;
    }
  }
  return g;
}

std::string LiveMapper::error() const {
  std::lock_guard lock(impl_->state_mutex);
  return impl_->error;
}

bool LiveMapper::finished() const {
  std::lock_guard lock(impl_->state_mutex);
  return impl_->finished;
}

}  // namespace cogmap::rosnode
