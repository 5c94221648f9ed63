// Side by side: OpenCV's contour tracing + approxPolyDP against cogmap's
// vectorization (extract, simplify, Douglas-Peucker, line fit), on the same
// cleaned modified-HIMM grid of one log.
//
//   cogmap_peer_opencv_vectorize LOG --world WORLD.map [--poses truth|odom]
//       [--robot NAME|FILE] [--cell 0.1] [--window 3.0] [--mode default|paper]
//       [--epsilon-cells 1.5] [--repeat 7] [--json OUT.json]
//
// Both start from VectorizeResult::cleaned (SPEC 3.1's cleaned grid: walls one
// cell thick), so the clean stage, common to both, is timed apart. OpenCV:
// occupied cells (> epsilon 7) as a binary image, cv::findContours
// (RETR_LIST, CHAIN_APPROX_NONE), cv::approxPolyDP with the same tolerance as
// cogmap's Douglas-Peucker (eta = 1.5 cells), each contour a closed polyline
// at the cell centres. A one-cell-thick wall has a contour that goes along it
// and back, so OpenCV's outline holds every wall twice: that is what
// approxPolyDP on a grid gives, and it is counted as it is (vertices, bytes).
// Measured for both: vertices, polylines, encoded bytes (cogmap's polyline
// codec), wall precision and recall against the world (cogmap/eval), seconds.
#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <iostream>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "cogmap/core/error.h"
#include "cogmap/eval/wall_metrics.h"
#include "cogmap/grid/range_fusion.h"
#include "cogmap/io/atomic_file.h"
#include "cogmap/io/log_reader.h"
#include "cogmap/io/world_io.h"
#include "cogmap/sensors/robot_json.h"
#include "cogmap/vectorize/polyline_codec.h"
#include "cogmap/vectorize/vectorize.h"

namespace {

using cogmap::Polyline;
using cogmap::Pose2;
using cogmap::Vec2;
using Clock = std::chrono::steady_clock;

double Seconds(Clock::time_point a, Clock::time_point b) {
  return std::chrono::duration<double>(b - a).count();
}

struct Side {
  std::vector<Polyline> polylines;
  double seconds = 0;
};

nlohmann::json Measure(const Side& side, const std::vector<cogmap::Segment2>& walls,
                       const std::vector<Vec2>& true_path, double range_m) {
  long vertices = 0;
  for (const auto& p : side.polylines) vertices += static_cast<long>(p.size());
  cogmap::eval::WallMetricsOptions o;
  o.sensor_range_m = range_m;
  const auto precision = cogmap::eval::WallPrecision(side.polylines, walls, o);
  const auto recall = cogmap::eval::WallRecall(side.polylines, walls, true_path, o);
  return {{"seconds", side.seconds},
          {"polylines", static_cast<long>(side.polylines.size())},
          {"vertex_count", vertices},
          {"bytes_polylines", static_cast<long>(cogmap::vectorize::EncodePolylines(side.polylines).size())},
          {"wall_precision_mean_m", precision.mean_m},
          {"wall_precision_p95_m", precision.p95_m},
          {"wall_recall", recall.recall()}};
}

int Run(int argc, char** argv) {
  CLI::App app{"OpenCV findContours + approxPolyDP against cogmap's vectorization, same cleaned grid"};
  std::string log_path, world_path, poses = "truth", robot_name, mode = "default", json_path;
  double cell_m = 0.1, window_m = 3.0, epsilon_cells = 1.5;
  app.add_option("log", log_path, "the log (any format cogmap reads)")->required();
  app.add_option("--world", world_path, "the world the log was driven in (true walls)")->required();
  app.add_option("--poses", poses, "poses the grid is built with: truth or odom")
      ->check(CLI::IsMember({"truth", "odom"}))->capture_default_str();
  app.add_option("--robot", robot_name, "robot name or JSON file (default: the log's)");
  app.add_option("--cell", cell_m, "cell size, metres")->capture_default_str();
  app.add_option("--window", window_m, "MHIMM window w, metres")->capture_default_str();
  app.add_option("--mode", mode, "cogmap's vectorization mode: default or paper")
      ->check(CLI::IsMember({"default", "paper"}))->capture_default_str();
  app.add_option("--epsilon-cells", epsilon_cells, "approxPolyDP tolerance, cells (= DP eta)")
      ->capture_default_str();
  app.add_option("--json", json_path, "also write the JSON here");
  int repeat = 7;
  app.add_option("--repeat", repeat, "runs of each side; times are the median")->check(CLI::PositiveNumber)
      ->capture_default_str();
  CLI11_PARSE(app, argc, argv);

  // The grid of the whole log, and the true path for recall.
  auto reader = cogmap::io::OpenLog(log_path);
  std::vector<cogmap::sensors::LogRecord> records;
  cogmap::sensors::LogRecord r;
  std::vector<Vec2> true_path;
  while (reader->Next(&r)) {
    if (poses == "truth") {
      if (!r.truth) throw cogmap::InputError(log_path, 0, "--poses truth: the log has no true poses");
      r.odom = *r.truth;
    }
    true_path.push_back(r.truth ? Vec2(r.truth->x, r.truth->y) : Vec2(r.odom.x, r.odom.y));
    records.push_back(std::move(r));
  }
  cogmap::sensors::RobotDescription robot;
  if (!robot_name.empty()) robot = cogmap::sensors::ResolveRobot(robot_name);
  else if (auto hint = reader->robot_hint()) robot = *hint;
  else throw cogmap::InputError(log_path, 0, "the log does not name its robot: give --robot");
  cogmap::grid::MhimmOptions mhimm;
  mhimm.window_m = window_m;
  cogmap::grid::GridBounds bounds;
  bounds.cell_m = cell_m;
  cogmap::grid::HimmFusion grid(true, mhimm, bounds);
  for (const auto& rec : records) grid.InsertSweep(rec.odom, robot, rec.ranges);
  const auto walls = cogmap::io::ReadWorld(world_path).plan.walls;
  const auto thin_path = cogmap::eval::ThinPath(true_path, 0.1);
  double range_m = window_m;
  for (const auto& s : robot.sensors) range_m = std::min(range_m, s.max_range_m);

  // cogmap.
  auto options = mode == "paper" ? cogmap::vectorize::VectorizeOptions::Paper()
                                 : cogmap::vectorize::VectorizeOptions{};
  // The clean stage's reach is the sonar's effective range, w (SPEC 3.1).
  options.clean.max_dist_cells = std::max(1, static_cast<int>(std::lround(window_m / cell_m)));
  // Every timing is the median of 'repeat' runs (the machine is shared).
  auto median = [](std::vector<double> v) {
    std::sort(v.begin(), v.end());
    return v[v.size() / 2];
  };
  std::vector<double> ours_s, clean_s, theirs_s;
  cogmap::vectorize::VectorizeResult result;
  for (int i = 0; i < repeat; ++i) {
    result = cogmap::vectorize::Vectorize(grid.values(), options);
    ours_s.push_back(result.seconds.total() - result.seconds.clean);
    clean_s.push_back(result.seconds.clean);
  }
  Side ours{result.polylines, median(ours_s)};

  // OpenCV on the same cleaned grid.
  const auto& cleaned = result.cleaned;
  const auto& l = cleaned.limits();
  const float occupied = mhimm.occupied_threshold;
  Side theirs;
  std::vector<std::vector<cv::Point>> contours;
  for (int i = 0; i < repeat; ++i) {
    const auto t0 = Clock::now();
    cv::Mat image(l.height(), l.width(), CV_8UC1, cv::Scalar(0));
    for (int y = 0; y < l.height(); ++y)
      for (int x = 0; x < l.width(); ++x)
        if (cleaned.at(x, y) > occupied) image.at<uint8_t>(y, x) = 255;
    contours.clear();
    cv::findContours(image, contours, cv::RETR_LIST, cv::CHAIN_APPROX_NONE);
    theirs.polylines.clear();
    for (const auto& c : contours) {
      std::vector<cv::Point> approx;
      cv::approxPolyDP(c, approx, epsilon_cells, /*closed=*/true);
      Polyline p;
      for (const auto& q : approx) p.push_back(l.CenterOf({q.x, q.y}));
      if (p.size() > 2) p.push_back(p.front());  // closed outline
      if (p.size() >= 2) theirs.polylines.push_back(std::move(p));
      else if (p.size() == 1) theirs.polylines.push_back({p.front(), p.front()});
    }
    theirs_s.push_back(Seconds(t0, Clock::now()));
  }
  theirs.seconds = median(theirs_s);

  nlohmann::json out;
  out["log"] = log_path;
  out["world"] = world_path;
  out["robot"] = robot.name;
  out["poses"] = poses;
  out["mode"] = mode;
  out["cell_m"] = cell_m;
  out["epsilon_cells"] = epsilon_cells;
  out["grid_cells"] = l.cell_count();
  out["clean_seconds"] = median(clean_s);
  out["repeat"] = repeat;
  out["cogmap"] = Measure(ours, walls, thin_path, range_m);
  out["opencv"] = Measure(theirs, walls, thin_path, range_m);
  out["opencv"]["contours"] = static_cast<long>(contours.size());
  const std::string text = out.dump(2);
  std::cout << text << "\n";
  if (!json_path.empty()) cogmap::io::WriteFileAtomically(json_path, text + "\n");
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  try {
    return Run(argc, argv);
  } catch (const cogmap::InputError& e) {
    std::cerr << "cogmap_peer_opencv_vectorize: " << e.what() << "\n";
    return 2;
  } catch (const std::exception& e) {
    std::cerr << "cogmap_peer_opencv_vectorize: " << e.what() << "\n";
    return 1;
  }
}
