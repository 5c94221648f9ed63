#include "cogmap/mapping/grid_job.h"

#include <chrono>
#include <filesystem>

#include "cogmap/core/error.h"
#include "cogmap/draw/grid_picture.h"
#include "cogmap/io/grid_io.h"
#include "cogmap/mapping/pipeline.h"
#include "cogmap/sensors/robot_json.h"

namespace cogmap::mapping {

void GridJob::Validate() const {
  if (const std::string m = CellAndWindowProblem(cell_m, window_m); !m.empty()) throw InputError(m);
  if (px_per_cell < 0 || px_per_cell > 64)
    throw InputError("--scale " + std::to_string(px_per_cell) + ": must be in [1, 64]");
  if (!(px_per_m >= 0) || px_per_m > 1000) throw InputError("--px-per-m: must be in (0, 1000]");
  draw::FormatOfPath(picture_path);  // a picture format, before any work
}

GridJobResult RunGridJob(io::LogReader& log, const GridJob& job) {
  const auto start = std::chrono::steady_clock::now();
  job.Validate();
  GridJobResult out;
  out.robot = io::RobotFor(log, job.robot_spec);

  grid::FusionOptions options;
  options.bounds.cell_m = job.cell_m;
  options.himm.window_m = job.window_m;
  options.mhimm.window_m = job.window_m;
  options.cone.window_m = job.window_m;
  out.fusion = grid::MakeFusion(job.rule, options);
  io::FuseLogOptions fuse;
  fuse.use_truth = job.use_truth;
  const io::FuseLogStats fused = io::FuseLog(log, out.robot, *out.fusion, fuse, job.progress);
  out.records = fused.records;
  out.readings = fused.readings;

  draw::PictureOptions picture;
  picture.px_per_m = job.px_per_cell > 0 ? job.px_per_cell / job.cell_m : job.px_per_m;
  picture.title = "Occupancy grid (" + grid::FusionRuleName(job.rule) +
                  "): " + std::filesystem::path(job.log_path).filename().string();
  draw::DrawGrid(*out.fusion, picture).Write(job.picture_path);
  if (!job.pgm_base.empty()) io::WriteMapServer(job.pgm_base, out.fusion->Classes());
  out.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  if (job.summarize) out.summary = grid::Summarize(*out.fusion);
  return out;
}

}  // namespace cogmap::mapping
