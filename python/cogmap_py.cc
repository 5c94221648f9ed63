// Python bindings (pybind11): read any log the command reads, map it (whole or
// record by record), open a store, get the floor plan. Poses and paths come
// back as numpy arrays (x, y, theta in metres and radians), walls and room
// outlines as (K, 2) arrays.
#include <pybind11/functional.h>
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <memory>
#include <string>

#include "cogmap/asr/store.h"
#include "cogmap/core/angles.h"
#include "cogmap/core/error.h"
#include "cogmap/io/log_reader.h"
#include "cogmap/mapping/evaluate.h"
#include "cogmap/mapping/floor_plan.h"
#include "cogmap/mapping/map_job.h"
#include "cogmap/mapping/pipeline.h"
#include "cogmap/plan/plan_json.h"
#include "cogmap/sensors/robot.h"
#include "cogmap/sensors/robot_json.h"

namespace py = pybind11;

namespace cogmap::python {
namespace {

using Array = py::array_t<double>;

Array Poses(const std::vector<Pose2>& poses) {
  Array a({static_cast<py::ssize_t>(poses.size()), py::ssize_t{3}});
  auto m = a.mutable_unchecked<2>();
  for (size_t i = 0; i < poses.size(); ++i) {
    m(i, 0) = poses[i].x;
    m(i, 1) = poses[i].y;
    m(i, 2) = poses[i].theta;
  }
  return a;
}

Array PoseArray(const Pose2& p) {
  Array a(py::ssize_t{3});
  auto m = a.mutable_unchecked<1>();
  m(0) = p.x;
  m(1) = p.y;
  m(2) = p.theta;
  return a;
}

Array Points(const Polyline& line) {
  Array a({static_cast<py::ssize_t>(line.size()), py::ssize_t{2}});
  auto m = a.mutable_unchecked<2>();
  for (size_t i = 0; i < line.size(); ++i) {
    m(i, 0) = line[i].x();
    m(i, 1) = line[i].y();
  }
  return a;
}

Pose2 ToPose(const Array& a, const char* what) {
  if (a.ndim() != 1 || a.shape(0) != 3) throw py::value_error(std::string(what) + ": expected (x, y, theta)");
  auto m = a.unchecked<1>();
  return Pose2{m(0), m(1), m(2)};
}

py::dict RobotDict(const sensors::RobotDescription& r) {
  py::list sensors;
  for (const auto& s : r.sensors) {
    py::dict d;
    d["kind"] = s.kind == sensors::SensorKind::kLaser ? "laser" : "sonar";
    d["pose"] = PoseArray(s.robot_from_sensor);
    d["beam_width_rad"] = s.beam_width_rad;
    d["min_range_m"] = s.min_range_m;
    d["max_range_m"] = s.max_range_m;
    sensors.append(d);
  }
  py::dict d;
  d["name"] = r.name;
  d["radius_m"] = r.radius_m;
  d["sensors"] = sensors;
  return d;
}

Array Point(const Vec2& p) {
  Array a(py::ssize_t{2});
  auto m = a.mutable_unchecked<1>();
  m(0) = p.x();
  m(1) = p.y();
  return a;
}

// The floor plan with plan.json's names (docs/floor-plan.md), points as numpy
// arrays; 'wall_segments' (S, 4: x0, y0, x1, y1) holds every wall's pieces and
// 'graph' the room graph (nodes: room ids; edges (E, 3): room_a, room_b, door).
py::dict PlanDict(const plan::Plan& p) {
  py::list walls;
  std::vector<double> segments;
  for (const auto& w : p.walls) {
    py::dict d;
    d["points"] = Points(w.points);
    d["free_on_left"] = w.free_on_left;
    d["two_sided"] = w.two_sided;
    d["squared"] = w.squared;
    d["weight"] = w.weight;
    d["asr_ids"] = w.asr_ids;
    walls.append(d);
    for (size_t i = 0; i + 1 < w.points.size(); ++i)
      segments.insert(segments.end(), {w.points[i].x(), w.points[i].y(), w.points[i + 1].x(), w.points[i + 1].y()});
  }
  Array seg({static_cast<py::ssize_t>(segments.size() / 4), py::ssize_t{4}});
  std::copy(segments.begin(), segments.end(), seg.mutable_data());
  py::list rooms;
  py::list nodes;
  for (const auto& r : p.rooms) {
    py::dict d;
    d["id"] = r.id;
    d["name"] = r.name;
    d["corridor"] = r.corridor;
    d["polygon"] = Points(r.polygon);
    d["area_m2"] = r.area_m2;
    d["label"] = Point(r.label);
    d["doors"] = r.doors;
    d["asr_ids"] = r.asr_ids;
    d["graph_rooms"] = r.graph_rooms;
    rooms.append(d);
    nodes.append(r.id);
  }
  py::list doors;
  for (const auto& x : p.doors) {
    py::dict d;
    d["id"] = x.id;
    d["a"] = Point(x.a);
    d["b"] = Point(x.b);
    d["width_m"] = x.width_m();
    d["room_a"] = x.room_a;
    d["room_b"] = x.room_b;
    d["from_asr"] = x.from_asr;
    d["to_asr"] = x.to_asr;
    doors.append(d);
  }
  py::array_t<int> edges({static_cast<py::ssize_t>(p.edges.size()), py::ssize_t{3}});
  auto e = edges.mutable_unchecked<2>();
  for (size_t i = 0; i < p.edges.size(); ++i) {
    e(i, 0) = p.edges[i].room_a;
    e(i, 1) = p.edges[i].room_b;
    e(i, 2) = p.edges[i].door;
  }
  py::dict graph;
  graph["nodes"] = nodes;
  graph["edges"] = edges;
  Array bounds({py::ssize_t{2}, py::ssize_t{2}});
  auto b = bounds.mutable_unchecked<2>();
  b(0, 0) = p.min.x();
  b(0, 1) = p.min.y();
  b(1, 0) = p.max.x();
  b(1, 1) = p.max.y();
  py::dict d;
  d["walls"] = walls;
  d["wall_segments"] = seg;
  d["rooms"] = rooms;
  d["doors"] = doors;
  d["graph"] = graph;
  d["home"] = p.home ? py::object(PoseArray(*p.home)) : py::object(py::none());
  d["bounds"] = bounds;
  d["dominant_direction_rad"] = p.dominant_direction_rad;
  d["direction_scatter_rad"] = p.direction_scatter_rad;
  return d;
}

// A map folder (its plan.json, else built from its map.sqlite), a plan.json,
// or a store (built from it as `cogmap map` builds plan.json).
plan::Plan LoadPlan(const std::string& path) {
  namespace fs = std::filesystem;
  fs::path p(path);
  std::error_code ec;
  if (fs::is_directory(p, ec)) {
    if (fs::exists(p / "plan.json", ec)) return plan::ReadPlanJson((p / "plan.json").string());
    if (!fs::exists(p / "map.sqlite", ec)) throw InputError(path, 0, "no plan.json or map.sqlite in this folder");
    p /= "map.sqlite";
  }
  if (p.extension() == ".json") return plan::ReadPlanJson(p.string());
  auto store = asr::SqliteAsrStore::Open(p.string(), asr::SqliteAsrStore::OpenMode::kReadOnly);
  return mapping::FloorPlanOfStore(*store);
}

py::object Json(const nlohmann::json& j) { return py::module_::import("json").attr("loads")(j.dump()); }

// A log read whole: times (N,), odometry (N, 3), truth (N, 3; NaN where the
// log has none), ranges (M, 3): record index, sensor index, range in metres.
py::dict ReadLog(const std::string& path, const std::string& format) {
  auto log = io::OpenLog(path, format);
  std::vector<double> times;
  std::vector<Pose2> odom, truth;
  std::vector<double> ranges;
  sensors::LogRecord rec;
  const double nan = std::numeric_limits<double>::quiet_NaN();
  while (log->Next(&rec)) {
    const double index = static_cast<double>(times.size());
    times.push_back(rec.time_s);
    odom.push_back(rec.odom);
    truth.push_back(rec.truth ? *rec.truth : Pose2{nan, nan, nan});
    for (const auto& r : rec.ranges) {
      ranges.push_back(index);
      ranges.push_back(r.sensor);
      ranges.push_back(r.range_m);
    }
  }
  Array t(static_cast<py::ssize_t>(times.size()));
  std::copy(times.begin(), times.end(), t.mutable_data());
  Array rg({static_cast<py::ssize_t>(ranges.size() / 3), py::ssize_t{3}});
  std::copy(ranges.begin(), ranges.end(), rg.mutable_data());
  py::dict skipped;
  for (const auto& [type, n] : log->skipped()) skipped[py::str(type)] = n;
  py::dict d;
  d["path"] = path;
  d["time"] = t;
  d["odom"] = Poses(odom);
  d["truth"] = Poses(truth);
  d["ranges"] = rg;
  d["robot"] = log->robot_hint() ? py::object(RobotDict(*log->robot_hint())) : py::object(py::none());
  d["skipped"] = skipped;
  return d;
}

mapping::MappingOptions Options(const std::string& mode, double cell_m, double window_m, bool correct,
                                bool pose_graph, double add_drift_deg_per_m, int threads) {
  if (mode != "paper" && mode != "default") throw InputError("mode " + mode + ": expected paper or default");
  mapping::MappingOptions o;
  o.paper = mode == "paper";
  o.cell_m = cell_m;
  o.window_m = window_m;
  o.correct = correct;
  o.pose_graph = pose_graph;
  o.add_drift_rad_per_m = DegToRad(add_drift_deg_per_m);
  o.threads = threads;
  o.Validate();
  return o;
}

// `cogmap map` as one call; returns report.json's content as a dict.
py::object MapLog(const std::string& path, const std::string& output, const std::string& format,
                  const std::string& robot, const std::string& mode, const std::string& outputs, bool resume,
                  const std::string& world, double add_drift_deg_per_m, bool correct, bool pose_graph,
                  int threads, bool second_pass, const std::string& scan_match, const std::string& distance_scale) {
  mapping::MapJob job;
  job.second_pass = second_pass;
  job.log_path = path;
  job.log_format = format;
  job.robot_spec = robot;
  job.mapping = Options(mode, 0.1, 3.0, correct, pose_graph, add_drift_deg_per_m, threads);
  job.mapping.scan_match = mapping::ParseScanMatch(scan_match);
  job.mapping.distance_scale = mapping::ParseDistanceScale(distance_scale);
  job.outputs = mapping::OutputChoice::Parse(outputs);
  job.output_dir = output;
  job.resume = resume;
  job.world = world;
  auto log = io::OpenLog(path, format);
  if (path != "-") job.reopen_log = [path, format] { return io::OpenLog(path, format); };
  const mapping::MapJobSummary s = mapping::RunMapJob(*log, job);
  // report.json as the run wrote it (the job streams it, never holding it whole).
  std::ifstream in((std::filesystem::path(output) / "report.json").string());
  if (!in) throw std::runtime_error(output + "/report.json: cannot read the report the run wrote");
  py::dict d = Json(nlohmann::json::parse(in));
  d["outputs"] = s.written;
  d["warnings"] = s.warnings;
  return d;
}

// The streaming pipeline, record by record, into a store on disk.
class Mapper {
 public:
  Mapper(const std::string& store_path, const std::string& robot, const std::string& mode, bool correct,
         bool pose_graph, int threads)
      : store_(asr::SqliteAsrStore::Open(store_path, asr::SqliteAsrStore::OpenMode::kReplace)),
        pipeline_(sensors::ResolveRobot(robot), Options(mode, 0.1, 3.0, correct, pose_graph, 0.0, threads),
                  store_.get()) {
    pipeline_.OnAsrClosed([this](const asr::Asr& x, const mapping::AsrSummary&) {
      if (callback_) callback_(x.id);
    });
  }
  void Push(double time_s, const Array& odom, const std::vector<std::pair<int, double>>& ranges,
            const std::optional<Array>& truth) {
    sensors::LogRecord r;
    r.time_s = time_s;
    r.odom = ToPose(odom, "odom");
    if (truth) r.truth = ToPose(*truth, "truth");
    for (const auto& [sensor, range] : ranges) {
      if (sensor < 0 || sensor >= static_cast<int>(pipeline_.robot().sensors.size()))
        throw py::value_error("sensor index " + std::to_string(sensor) + " out of range");
      if (!std::isfinite(range) || range < 0) throw py::value_error("range must be finite and >= 0");
      r.ranges.push_back({sensor, range});
    }
    pipeline_.Push(std::move(r));
  }
  py::dict Finish() {
    const mapping::RunResult& r = pipeline_.Finish();
    py::dict d;
    d["records"] = r.records;
    d["asrs"] = r.asrs.size();
    int closures = 0;
    std::set<int> rooms;
    for (const auto& c : r.graph.closures) closures += c.accepted ? 1 : 0;
    for (const auto& a : r.graph.asrs) rooms.insert(a.room_id);
    d["closures"] = closures;
    d["rooms"] = r.correction == mapping::Correction::kPoseGraph ? py::int_(rooms.size()) : py::int_(r.asrs.size());
    d["drift_rate_deg_per_m"] = RadToDeg(r.graph.drift_rate_rad_per_m);
    if (r.graph.drift_rate_sigma_rad_per_m >= 0.0)
      d["drift_rate_sigma_deg_per_m"] = RadToDeg(r.graph.drift_rate_sigma_rad_per_m);
    else
      d["drift_rate_sigma_deg_per_m"] = py::none();
    if (r.graph.drift_rate_spread_sigma_rad_per_m >= 0.0)
      d["drift_rate_spread_sigma_deg_per_m"] = RadToDeg(r.graph.drift_rate_spread_sigma_rad_per_m);
    else
      d["drift_rate_spread_sigma_deg_per_m"] = py::none();
    d["building_directions_deg"] = graph::BuildingDirectionsDeg(r.graph);
    if (r.graph.odometry_heading_fitted_factor > 0.0)
      d["odometry_heading_fitted_factor"] = r.graph.odometry_heading_fitted_factor;
    else
      d["odometry_heading_fitted_factor"] = py::none();
    d["odometry_heading_held"] = r.graph.odometry_heading_held;
    d["warnings"] = r.graph.warnings;
    return d;
  }
  void OnAsrClosed(std::function<void(int)> f) { callback_ = std::move(f); }
  int asrs_closed() const { return pipeline_.asrs_closed(); }

 private:
  std::unique_ptr<asr::SqliteAsrStore> store_;
  mapping::MappingPipeline pipeline_;
  std::function<void(int)> callback_;
};

// A store opened read-only.
class Store {
 public:
  explicit Store(const std::string& path)
      : store_(asr::SqliteAsrStore::Open(path, asr::SqliteAsrStore::OpenMode::kReadOnly)) {}
  std::vector<int> Ids() const { return store_->Ids(); }
  int RoomOf(int id) const { return store_->RoomOf(id); }
  py::dict Asr(int id) const {
    auto x = store_->Get(id);
    if (!x) throw py::key_error("no ASR " + std::to_string(id));
    py::list walls;
    for (const auto& w : x->WallsWorldCorrected()) walls.append(Points(w));
    py::list exits;
    for (const auto& e : x->exits) {
      py::dict d;
      d["center"] = Points({e.center_m});
      d["width_m"] = e.width_m;
      d["from_asr"] = e.from_asr;
      d["to_asr"] = e.to_asr;
      exits.append(d);
    }
    py::dict d;
    d["id"] = x->id;
    d["room"] = store_->RoomOf(id);
    d["pose"] = PoseArray(x->world_from_local_corrected);
    d["pose_raw"] = PoseArray(x->world_from_local_raw);
    d["walls"] = walls;
    d["path_raw"] = Poses(x->path);
    d["true_path"] = Poses(x->true_path);
    auto p = store_->GetPlacement(id);
    d["path"] = Poses(p && !p->corrected_path.empty() ? p->corrected_path : x->path);
    d["uncertain"] = p ? p->uncertain : false;
    d["exits"] = exits;
    return d;
  }
  std::optional<std::string> Meta(const std::string& key) const { return store_->GetMeta(key); }
  py::dict FloorPlan() const { return PlanDict(mapping::FloorPlanOfStore(*store_)); }

 private:
  std::unique_ptr<asr::SqliteAsrStore> store_;
};

}  // namespace
}  // namespace cogmap::python

PYBIND11_MODULE(cogmap, m) {
  using namespace cogmap::python;
  m.doc() = "cogmap: cognitive maps (rooms as ASRs, wall polylines, a pose graph) from range readings and odometry";
  // A bad file or option is cogmap.InputError (a ValueError), with the file and line in its message.
  static py::exception<cogmap::InputError> input_error(m, "InputError", PyExc_ValueError);
  py::register_exception_translator([](std::exception_ptr p) {
    try {
      if (p) std::rethrow_exception(p);
    } catch (const cogmap::InputError& e) {
      input_error(e.what());
    }
  });
  m.def("read_log", &ReadLog, py::arg("path"), py::arg("format") = "auto",
        "Reads a log whole: dict with time (N,), odom (N,3), truth (N,3; NaN where unknown), "
        "ranges (M,3: record, sensor, range_m), robot (the log's robot or None), skipped message counts");
  m.def("map_log", &MapLog, py::arg("path"), py::arg("output"), py::arg("format") = "auto",
        py::arg("robot") = "", py::arg("mode") = "default", py::arg("outputs") = "default",
        py::arg("resume") = false, py::arg("world") = "", py::arg("add_drift_deg_per_m") = 0.0,
        py::arg("correct") = true, py::arg("pose_graph") = true, py::arg("threads") = 2,
        py::arg("second_pass") = false, py::arg("scan_match") = "auto", py::arg("distance_scale") = "auto",
        "Maps a log into an output folder exactly as `cogmap map` does (second_pass: `--second-pass`, "
        "scan_match: `--scan-match`, auto, on or off; distance_scale: `--distance-scale`, auto, off or a "
        "number); returns report.json as a dict");
  m.def("robot", [](const std::string& spec) { return RobotDict(cogmap::sensors::ResolveRobot(spec)); },
        py::arg("spec"), "A built-in robot by name, or a robot JSON file");
  py::class_<Mapper>(m, "Mapper", "The mapping pipeline, record by record, into a store on disk")
      .def(py::init<const std::string&, const std::string&, const std::string&, bool, bool, int>(), py::arg("store"),
           py::arg("robot") = "pioneer16", py::arg("mode") = "default", py::arg("correct") = true,
           py::arg("pose_graph") = true, py::arg("threads") = 2)
      .def("push", &Mapper::Push, py::arg("time"), py::arg("odom"), py::arg("ranges") = std::vector<std::pair<int, double>>{},
           py::arg("truth") = py::none(), "One record: time (s), odom (x, y, theta), ranges [(sensor, range_m)]")
      .def("finish", &Mapper::Finish, "Closes the open room, places every ASR, writes the placements")
      .def("on_asr_closed", &Mapper::OnAsrClosed, "Calls f(asr_id) as each ASR closes")
      .def_property_readonly("asrs_closed", &Mapper::asrs_closed);
  py::class_<Store>(m, "Store", "A map store (map.sqlite), read-only")
      .def(py::init<const std::string&>(), py::arg("path"))
      .def("ids", &Store::Ids)
      .def("room_of", &Store::RoomOf)
      .def("asr", &Store::Asr, "One ASR: pose, walls (map frame), path as placed, exits, room")
      .def("meta", &Store::Meta)
      .def("floor_plan", &Store::FloorPlan, "The floor plan built from the store, as floor_plan() returns it");
  m.def(
      "evaluate",
      [](const std::string& dir, const std::string& world, double range_m, const std::string& rooms) {
        cogmap::mapping::EvaluateOptions o;
        o.world = world;
        o.range_m = range_m;
        o.rooms = rooms;
        return Json(cogmap::mapping::EvaluateFolder(dir, o).metrics);
      },
      py::arg("folder"), py::arg("world") = "", py::arg("range_m") = -1.0, py::arg("rooms") = "",
      "Scores a map folder as `cogmap eval --json` does (against a world when given; rooms: a room-segmentation "
      "image of a bitmap world, as --rooms); returns the metrics as a dict");
  m.def("open_store", [](const std::string& path) { return Store(path); }, py::arg("path"));
  m.def(
      "floor_plan", [](const std::string& path) { return PlanDict(LoadPlan(path)); }, py::arg("path"),
      "The floor plan of a map folder (its plan.json, else built from its map.sqlite), a plan.json or a "
      "map.sqlite: dict with walls (points (K,2), free_on_left, two_sided, squared, weight, asr_ids), "
      "wall_segments (S,4), rooms (id, name, corridor, polygon (K,2), area_m2, label, doors, asr_ids, "
      "graph_rooms), doors (id, a, b, width_m, room_a, room_b, from_asr, to_asr), graph (nodes, edges (E,3): "
      "room_a, room_b, door), home, bounds, dominant_direction_rad, direction_scatter_rad");
}
