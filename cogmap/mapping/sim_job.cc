#include "cogmap/mapping/sim_job.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <filesystem>

#include "cogmap/core/angles.h"
#include "cogmap/core/error.h"
#include "cogmap/core/text.h"
#include "cogmap/draw/world_picture.h"
#include "cogmap/io/atomic_file.h"
#include "cogmap/io/log_reader.h"
#include "cogmap/io/native_log.h"
#include "cogmap/io/world_io.h"
#include "cogmap/sensors/robot_json.h"

namespace cogmap::mapping {
namespace {

io::WorldReadResult LoadWorld(const std::string& path, double m_per_pixel,
                              const std::function<void(const std::string&)>& warning) {
  io::BitmapWorldOptions bitmap;
  bitmap.m_per_pixel = m_per_pixel;
  io::WorldReadResult world = io::ReadWorld(path, bitmap);
  if (warning)
    for (const auto& w : world.warnings) warning(w);
  return world;
}

void CheckMetresPerPixel(double m_per_pixel) {
  // At most a metre per pixel (a coarser image is no floor plan); NaN and
  // infinity are no resolution at all.
  std::string m;
  if (!(m_per_pixel > 0.0) || m_per_pixel > 1.0) AppendF(&m, "--m-per-pixel %g: must be in (0, 1] metres", m_per_pixel);
  if (!m.empty()) throw InputError(m);
}

}  // namespace

Pose2 ParseStartPose(const std::string& text) {
  std::vector<double> v;
  size_t i = 0;
  while (i <= text.size()) {
    const size_t comma = std::min(text.find(',', i), text.size());
    const std::string part = text.substr(i, comma - i);
    char* end = nullptr;
    const double x = std::strtod(part.c_str(), &end);
    if (part.empty() || end != part.c_str() + part.size() || !std::isfinite(x))
      throw InputError("--start: expected X,Y,THETA_DEG (metres, metres, degrees), got '" + text + "'");
    v.push_back(x);
    i = comma + 1;
  }
  if (v.size() != 3)
    throw InputError("--start: expected X,Y,THETA_DEG (3 numbers), got " + std::to_string(v.size()) + " in '" +
                     text + "'");
  return {v[0], v[1], NormalizeAngle(DegToRad(v[2]))};
}

void SimulateJob::Validate() const {
  CheckMetresPerPixel(m_per_pixel);
  std::string m;
  const double drift_deg = RadToDeg(options.odometry.drift_rad_per_m);
  if (!std::isfinite(drift_deg) || std::abs(drift_deg) > 90.0)
    AppendF(&m, "--drift-deg-per-m %g: must be in [-90, 90]", drift_deg);
  else if (!(std::abs(options.odometry.scale_error) < 0.5))
    AppendF(&m, "--scale-error %g: must be in (-0.5, 0.5)", options.odometry.scale_error);
  if (!m.empty()) throw InputError(m);
  if (!(options.cruise_mps > 0.0) || options.cruise_mps > 2.0) throw InputError("--speed must be in (0, 2] m/s");
  if (options.sensor.sonar_rays < 1 || options.sensor.sonar_rays > 100) throw InputError("--rays must be in [1, 100]");
  if (!(options.max_time_s >= 0.0) || options.max_time_s > 1e7)
    throw InputError("--max-time must be in [0, 1e7] s (0: from the route; NaN and infinity are none)");
  if (options.sonar_bank_size < 1 || options.sonar_bank_size > 1000)
    throw InputError("--sonar-bank-size must be in [1, 1000]");
}

SimulateJobResult RunSimulateJob(const SimulateJob& job) {
  const auto start = std::chrono::steady_clock::now();
  job.Validate();
  const io::WorldReadResult world = LoadWorld(job.world_path, job.m_per_pixel, job.warning);
  if (world.plan.walls.empty()) throw InputError(job.world_path, 0, "the world has no walls");
  SimulateJobResult out;
  out.robot = sensors::ResolveRobot(job.robot_spec);
  if (job.options.mode == sim::SimMode::kRoute && world.plan.route.empty())
    throw InputError(job.world_path, 0, "no route (no GoalWithHeading cairns named wpNN): use --explore");
  sim::SimulatorOptions o = job.options;
  if (job.noiseless) {
    o.odometry = sim::OdometryNoiseOptions{0, 0, 0, 0, 0};
    o.sensor.sonar_range_sigma_m = o.sensor.sonar_range_sigma_frac = 0;
    o.sensor.sonar_crosstalk_probability = 0;
    o.sensor.laser_range_sigma_m = 0;
  }
  io::WriteFileAtomically(job.output_path, [&](std::ostream& stream) {
    io::NativeLogWriter writer(stream, out.robot);
    out.stats = sim::Simulate(world.plan, out.robot, o, [&](const sensors::LogRecord& r) { writer.Write(r); },
                              job.progress);
  });
  if (job.warning)
    for (const auto& w : out.stats.warnings) job.warning(w);
  out.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return out;
}

RenderWorldResult RunRenderWorldJob(const RenderWorldJob& job) {
  if (!(job.px_per_m >= 0) || job.px_per_m > 1000) throw InputError("--px-per-m must be in (0, 1000]");
  CheckMetresPerPixel(job.m_per_pixel);
  draw::FormatOfPath(job.picture_path);  // a picture format, before any work
  RenderWorldResult out;
  out.world = LoadWorld(job.world_path, job.m_per_pixel, job.warning).plan;
  std::vector<Vec2> truth, odom;
  if (!job.log_path.empty()) {
    auto log = io::OpenLog(job.log_path);
    sensors::LogRecord r;
    const double min_step = job.px_per_m > 0 ? 0.5 / job.px_per_m : 0.01;
    while (log->Next(&r)) {
      if (odom.empty() || (r.odom.translation() - odom.back()).norm() >= min_step)
        odom.push_back(r.odom.translation());
      if (r.truth && (truth.empty() || (r.truth->translation() - truth.back()).norm() >= min_step))
        truth.push_back(r.truth->translation());
    }
  }
  draw::PictureOptions picture;
  picture.px_per_m = job.px_per_m;
  picture.title = std::filesystem::path(job.world_path).filename().string();
  const draw::MapPicture pic = draw::DrawWorld(out.world, truth, odom, picture);
  pic.drawing.Write(job.picture_path);
  out.width_px = std::lround(std::ceil(pic.drawing.width()));
  out.height_px = std::lround(std::ceil(pic.drawing.height()));
  return out;
}

}  // namespace cogmap::mapping
