// `cogmap grid`: options in, mapping::RunGridJob (a log's readings fused into
// an occupancy grid, drawn, optionally a ROS map_server pair), a summary out.
#include <cstdio>
#include <string>

#include "app/cli_util.h"
#include "app/command.h"
#include "app/progress.h"
#include "cogmap/io/log_reader.h"
#include "cogmap/mapping/grid_job.h"
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
  mapping::GridJob job;
  job.log_path = a.log;
  job.robot_spec = a.robot;
  job.cell_m = a.cell_m;
  job.window_m = a.window_m;
  job.use_truth = a.truth;
  job.picture_path = a.output;
  job.pgm_base = a.pgm;
  job.px_per_cell = a.scale;
  job.px_per_m = a.px_per_m;
  job.summarize = a.stats;
  job.Validate();
  job.rule = grid::ParseFusionRule(a.fusion);
  auto log = io::OpenLog(a.log, a.format);
  ProgressBar bar("grid");
  job.progress = [&bar](double f) { bar.Update(f); };
  const mapping::GridJobResult r = mapping::RunGridJob(*log, job);
  bar.Finish();

  const auto& lim = r.fusion->limits();
  std::printf("%s: %ld records, %ld readings, robot %s, %s grid %dx%d cells of %.3g m, %.2f s -> %s%s\n",
              a.log.c_str(), r.records, r.readings, r.robot.name.c_str(), grid::FusionRuleName(job.rule).c_str(),
              lim.width(), lim.height(), lim.cell_m(), r.seconds, a.output.c_str(),
              a.pgm.empty() ? "" : (" + " + a.pgm + ".pgm/.yaml").c_str());
  if (r.summary) {
    const grid::GridSummary& s = *r.summary;
    std::printf("cells %ld occupied %ld empty %ld unknown %ld path %ld touched %ld "
                "mean_entropy_bits %.4f line_fraction %.4f\n",
                s.cells, s.occupied, s.empty, s.unknown, s.robot_path, s.touched, s.mean_entropy_bits,
                s.line_fraction);
  }
  return 0;
}

std::function<int()> SetupGrid(CLI::App& sub) {
  auto a = std::make_shared<GridArgs>();
  sub.add_option("LOG", a->log, "The log (any format cogmap reads; - for standard input)")->required();
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
