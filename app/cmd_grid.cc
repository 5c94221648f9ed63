// `cogmap grid`: a log's readings fused into an occupancy grid, written as a
// PNG and optionally as a ROS map_server PGM + YAML pair.
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <string>

#include "app/cli_util.h"
#include "app/command.h"
#include "app/progress.h"
#include "cogmap/core/error.h"
#include "cogmap/grid/grid_summary.h"
#include "cogmap/grid/range_fusion.h"
#include "cogmap/io/grid_io.h"
#include "cogmap/draw/grid_picture.h"
#include "cogmap/io/log_reader.h"
#include "cogmap/sensors/robot_json.h"

namespace cogmap::app {
namespace {

struct GridArgs {
  std::string log;
  std::string format = "auto";
  std::string robot;
  std::string fusion = "mhimm";
  double cell_m = 0.1;
  double window_m = 3.0;
  std::string output;
  std::string pgm;
  int scale = 0;          // pixels per cell side; 0: fit the pixel budget
  double px_per_m = 0.0;  // pixels per metre; 0: fit the pixel budget
  bool truth = false;
  bool stats = false;
};

int RunGrid(const GridArgs& a) {
  const auto start = std::chrono::steady_clock::now();
  if (!(a.cell_m > 0.0) || a.cell_m > 10.0)
    throw InputError("--cell " + Num(a.cell_m) + ": must be in (0, 10] metres");
  if (!(a.window_m > 0.0)) throw InputError("--window " + Num(a.window_m) + ": must be positive");
  if (a.scale < 0 || a.scale > 64) throw InputError("--scale " + std::to_string(a.scale) + ": must be in [1, 64]");
  if (!(a.px_per_m >= 0) || a.px_per_m > 1000) throw InputError("--px-per-m: must be in (0, 1000]");
  draw::FormatOfPath(a.output);  // a picture format, before any work
  const grid::FusionRule rule = grid::ParseFusionRule(a.fusion);

  auto log = io::OpenLog(a.log, a.format);
  sensors::RobotDescription robot;
  if (!a.robot.empty()) robot = sensors::ResolveRobot(a.robot);
  else if (auto hint = log->robot_hint()) robot = *hint;
  else robot = sensors::BuiltinRobot("pioneer16");

  grid::FusionOptions options;
  options.bounds.cell_m = a.cell_m;
  options.himm.window_m = a.window_m;
  options.mhimm.window_m = a.window_m;
  options.cone.window_m = a.window_m;
  auto fusion = grid::MakeFusion(rule, options);

  ProgressBar bar("grid");
  io::FuseLogOptions fuse;
  fuse.use_truth = a.truth;
  const io::FuseLogStats fused =
      io::FuseLog(*log, robot, *fusion, fuse, [&](double f) { bar.Update(f); });
  bar.Finish();

  draw::PictureOptions picture;
  picture.px_per_m = a.scale > 0 ? a.scale / a.cell_m : a.px_per_m;
  picture.title = "Occupancy grid (" + grid::FusionRuleName(rule) + "): " + std::filesystem::path(a.log).filename().string();
  draw::DrawGrid(*fusion, picture).Write(a.output);
  if (!a.pgm.empty()) io::WriteMapServer(a.pgm, fusion->Classes());

  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  const auto& lim = fusion->limits();
  std::printf("%s: %ld records, %ld readings, robot %s, %s grid %dx%d cells of %.3g m, %.2f s -> %s%s\n",
              a.log.c_str(), fused.records, fused.readings, robot.name.c_str(),
              grid::FusionRuleName(rule).c_str(), lim.width(), lim.height(), lim.cell_m(), seconds,
              a.output.c_str(), a.pgm.empty() ? "" : (" + " + a.pgm + ".pgm/.yaml").c_str());
  if (a.stats) {
    const grid::GridSummary s = grid::Summarize(*fusion);
    std::printf("cells %ld occupied %ld empty %ld unknown %ld path %ld touched %ld "
                "mean_entropy_bits %.4f line_fraction %.4f\n",
                s.cells, s.occupied, s.empty, s.unknown, s.robot_path, s.touched,
                s.mean_entropy_bits, s.line_fraction);
  }
  return 0;
}

std::function<int()> SetupGrid(CLI::App& sub) {
  auto a = std::make_shared<GridArgs>();
  sub.add_option("LOG", a->log,
                 "The log to map: a native log, a CARMEN log (.gz too), the Pioneer pair "
                 "(measurement.txt, poses.txt or their folder), or an EV3 log")
      ->required();
  sub.add_option("--format", a->format, "Log format: " + Join(io::LogFormatNames()) +
                                            " (default auto: by content)")
      ->capture_default_str();
  sub.add_option("--robot", a->robot,
                 "Robot: a built-in name (" + Join(sensors::BuiltinRobotNames()) +
                     ") or a robot JSON file (default: the log's own robot, else pioneer16)");
  sub.add_option("--fusion", a->fusion,
                 "Fusion rule: himm (Borenstein-Koren, [0,15]), mhimm (modified HIMM, [-3,15], "
                 "robot path), bayes (log-odds, sonar cone), ds (Dempster-Shafer, sonar cone)")
      ->capture_default_str();
  sub.add_option("--cell", a->cell_m, "Cell size in metres (0.055 suits small cluttered rooms)")
      ->capture_default_str();
  sub.add_option("--window", a->window_m,
                 "Window w in metres: readings nearer mark a hit; farther ones (and no echo) "
                 "only clear the beam up to w (mhimm, bayes, ds) or are ignored (himm)")
      ->capture_default_str();
  sub.add_option("-o,--output", a->output, "Picture to write, .png, .svg or .pdf (world y up; MHIMM colours: grey "
                                           "unknown, white empty, black occupied, red robot path)")
      ->required();
  sub.add_option("--pgm", a->pgm,
                 "Also write the ROS map_server pair PGM.pgm + PGM.yaml (trinary: 0 occupied, "
                 "254 free, 205 unknown)");
  sub.add_option("--scale", a->scale, "Pixels per cell side (default: the picture fits 2000 px on its longest side)");
  sub.add_option("--px-per-m", a->px_per_m, "Pixels per metre (default: fit 2000 px)");
  sub.add_flag("--truth", a->truth, "Fuse at the log's ground-truth poses where it has them "
                                    "(e.g. the corrected CARMEN logs) instead of odometry");
  sub.add_flag("--stats", a->stats,
               "Print a second line of grid statistics (class counts, mean entropy, fraction of "
               "occupied cells on straight runs)");
  return [a] { return RunGrid(*a); };
}

const bool kRegistered = RegisterCommand(
    {"grid", "Fuse a log's range readings into an occupancy grid (PNG, ROS map)", 20, SetupGrid});

}  // namespace
}  // namespace cogmap::app
