// The odometry's distance scale measured by the range sensors
// (localize::OdometryScaleEstimator) for each log given: one line per log
// with the estimate, its sigma, the runs and the travel they span; with
// --runs first, every run of every sensor too.
#include <cstdio>
#include <exception>
#include <string>

#include "cogmap/io/log_reader.h"
#include "cogmap/localize/odometry_scale.h"

int main(int argc, char** argv) {
  using namespace cogmap;
  const bool list_runs = argc > 1 && std::string(argv[1]) == "--runs";
  const int first = list_runs ? 2 : 1;
  if (argc <= first) {
    std::fprintf(stderr, "usage: %s [--runs] LOG...\n", argv[0]);
    return 2;
  }
  for (int a = first; a < argc; ++a) {
    try {
      auto log = io::OpenLog(argv[a]);
      const sensors::RobotDescription robot = io::RobotFor(*log, "");
      localize::OdometryScaleEstimator est(robot);
      sensors::LogRecord rec;
      while (log->Next(&rec)) est.Add(rec);
      est.Finish();
      const auto e = est.Estimate();
      std::printf("%s: scale %.4f +- %.4f (%d runs, %.1f m)%s\n", argv[a], e.scale, e.sigma, e.runs, e.travel_m,
                  e.valid ? "" : " (too few runs)");
      if (list_runs)
        for (const auto& r : est.runs())
          std::printf("  sensor %2d  s %7.2f..%7.2f  %3d readings  scale %.4f +- %.4f  rms %.3f  side %.3f  r(mid) %.3f\n", r.sensor, r.s_begin, r.s_end, r.readings,
                      r.scale, r.sigma, r.rms_m, r.side_slope, r.line_r + r.line_slope * (0.5 * (r.s_begin + r.s_end) - r.line_s));
    } catch (const std::exception& e) {
      std::fprintf(stderr, "%s: %s\n", argv[a], e.what());
      return 2;
    }
  }
  return 0;
}
