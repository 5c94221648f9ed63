// OpenCV side by side on known synthetic room layouts: the same cleaned
// modified-HIMM grid (cogmap's clean), then either cogmap's extract ->
// vertex simplify -> Douglas-Peucker -> line fit, or OpenCV's
// cv::findContours (RETR_LIST, CHAIN_APPROX_NONE) + cv::approxPolyDP with
// epsilon = eta (1.5 cells). Prints vertices, encoded bytes, wall precision
// and recall against the layout's true walls (cogmap/eval), and the time of
// the part after the clean (median of repeats).
//
//   cogmap_opencv_compare [REPEATS]
//
// (bench/peer_opencv_vectorize.cc runs the same comparison on a simulated log
// against a world file.)
#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "cogmap/eval/wall_metrics.h"
#include "cogmap/vectorize/synthetic_grid.h"
#include "cogmap/vectorize/vectorize.h"

namespace vz = cogmap::vectorize;
using cogmap::Polyline;
using cogmap::Segment2;
using cogmap::Vec2;
using Clock = std::chrono::steady_clock;

namespace {

struct Layout {
  std::string name;
  std::vector<Segment2> walls;
  Polyline path;
};

std::vector<Segment2> Closed(const std::vector<Vec2>& poly) {
  std::vector<Segment2> out;
  for (size_t i = 0; i < poly.size(); ++i) out.push_back({poly[i], poly[(i + 1) % poly.size()]});
  return out;
}

std::vector<Layout> Layouts() {
  std::vector<Layout> out;
  out.push_back({"room 10x8 m", vz::RectangleWalls(Vec2(0, 0), Vec2(10, 8)),
                 {Vec2(1.5, 1.5), Vec2(8.5, 1.5), Vec2(8.5, 6.5), Vec2(1.5, 6.5), Vec2(1.5, 1.5)}});
  out.push_back({"L-shaped 8x8 m",
                 Closed({Vec2(0, 0), Vec2(8, 0), Vec2(8, 4), Vec2(4, 4), Vec2(4, 8), Vec2(0, 8)}),
                 {Vec2(1.2, 6.8), Vec2(1.2, 1.2), Vec2(6.8, 1.2), Vec2(6.8, 2.8), Vec2(2.8, 2.8), Vec2(2.8, 6.8)}});
  {
    // Two rooms joined by a 1 m door in a shared wall.
    std::vector<Segment2> w = vz::RectangleWalls(Vec2(0, 0), Vec2(12, 6));
    w.push_back({Vec2(6, 0), Vec2(6, 2.5)});
    w.push_back({Vec2(6, 3.5), Vec2(6, 6)});
    out.push_back({"two rooms + door", w,
                   {Vec2(1.5, 1.5), Vec2(4.5, 1.5), Vec2(4.5, 3), Vec2(7.5, 3), Vec2(10.5, 1.5), Vec2(10.5, 4.5),
                    Vec2(7.5, 4.5), Vec2(7.5, 3), Vec2(4.5, 3), Vec2(1.5, 4.5), Vec2(1.5, 1.5)}});
  }
  {
    // A 12 x 10 m room tilted by 20 degrees (walls not on the grid axes).
    const double c = std::cos(0.349), s = std::sin(0.349);
    auto rot = [&](double x, double y) { return Vec2(c * x - s * y + 4, s * x + c * y); };
    out.push_back({"tilted 20 deg", Closed({rot(0, 0), rot(12, 0), rot(12, 10), rot(0, 10)}),
                   {rot(1.5, 1.5), rot(10.5, 1.5), rot(10.5, 8.5), rot(1.5, 8.5), rot(1.5, 1.5)}});
  }
  return out;
}

struct Row {
  long vertices = 0, polylines = 0, bytes = 0;
  double precision_mean = 0, precision_p95 = 0, recall = 0, ms = 0;
};

Row Measure(const std::vector<Polyline>& lines, const Layout& l, double ms) {
  Row r;
  for (const auto& p : lines) r.vertices += static_cast<long>(p.size());
  r.polylines = static_cast<long>(lines.size());
  r.bytes = static_cast<long>(vz::EncodePolylines(lines).size());
  cogmap::eval::WallMetricsOptions o;
  o.sensor_range_m = 3.0;
  const auto p = cogmap::eval::WallPrecision(lines, l.walls, o);
  const auto rc = cogmap::eval::WallRecall(lines, l.walls, cogmap::eval::ThinPath(l.path, 0.1), o);
  r.precision_mean = p.mean_m;
  r.precision_p95 = p.p95_m;
  r.recall = rc.recall();
  r.ms = ms;
  return r;
}

double Median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

// cogmap after the clean: extract, simplify, Douglas-Peucker, fit.
std::vector<Polyline> CogmapAfterClean(const cogmap::grid::Grid2D<float>& cleaned, const vz::VectorizeOptions& o) {
  std::vector<Polyline> out;
  const auto& lim = cleaned.limits();
  for (const auto& chain : vz::ExtractPoints(cleaned, o.extract)) {
    if (static_cast<int>(chain.size()) < std::max(2, o.min_chain_points)) continue;
    const auto pts = vz::ChainToCellCoords(chain);
    const auto vs = vz::VertexSimplifyIndices(pts, o.vertex_simplify);
    const auto dp = vz::DouglasPeuckerIndices(vz::Pick(pts, vs), o.douglas_peucker);
    std::vector<int> idx;
    for (int i : dp) idx.push_back(vs[i]);
    Polyline world;
    for (const auto& p : vz::FitEdges(pts, idx, o.fit)) world.push_back(lim.FromCellCoords(p));
    out.push_back(std::move(world));
  }
  return out;
}

std::vector<Polyline> OpenCvAfterClean(const cogmap::grid::Grid2D<float>& cleaned, double eta_cells) {
  const auto& lim = cleaned.limits();
  const int w = lim.width(), h = lim.height();
  cv::Mat img(h, w, CV_8UC1, cv::Scalar(0));
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
      if (cleaned.at(x, y) > 7.0f) img.at<uint8_t>(h - 1 - y, x) = 255;
  std::vector<std::vector<cv::Point>> contours;
  cv::findContours(img, contours, cv::RETR_LIST, cv::CHAIN_APPROX_NONE);
  std::vector<Polyline> out;
  for (const auto& c : contours) {
    std::vector<cv::Point> approx;
    cv::approxPolyDP(c, approx, eta_cells, true);
    Polyline line;
    for (const auto& p : approx) line.push_back(lim.FromCellCoords(Vec2(p.x + 0.5, h - 1 - p.y + 0.5)));
    if (line.size() >= 2) line.push_back(line.front());  // closed contour
    out.push_back(std::move(line));
  }
  return out;
}

void Print(const char* layout, const char* method, const Row& r) {
  std::printf("%-18s %-22s %8ld %9ld %7ld %10.3f %9.3f %7.3f %9.3f\n", layout, method, r.polylines, r.vertices,
              r.bytes, r.precision_mean, r.precision_p95, r.recall, r.ms);
}

}  // namespace

int main(int argc, char** argv) {
  const int repeats = argc > 1 ? std::max(1, std::atoi(argv[1])) : 21;
  std::printf("%-18s %-22s %8s %9s %7s %10s %9s %7s %9s\n", "layout", "method", "polylines", "vertices", "bytes",
              "prec_mean", "prec_p95", "recall", "ms");
  for (const auto& l : Layouts()) {
    vz::SyntheticGridOptions g;
    g.wall_half_width_m = 0.15;  // walls 3 cells thick
    g.see_m = 3.0;
    g.noise_fraction = 0.002;
    g.seed = 5;
    const auto grid = vz::MakeSyntheticGrid(l.walls, l.path, g);
    for (int paper = 0; paper < 2; ++paper) {
      const auto o = paper ? vz::VectorizeOptions::Paper() : vz::VectorizeOptions{};
      const auto cleaned = vz::CleanMap(grid, o.clean);
      std::vector<double> tc, to;
      std::vector<Polyline> a, b;
      for (int i = 0; i < repeats; ++i) {
        auto t0 = Clock::now();
        a = CogmapAfterClean(cleaned, o);
        auto t1 = Clock::now();
        b = OpenCvAfterClean(cleaned, o.douglas_peucker.eta_cells);
        auto t2 = Clock::now();
        tc.push_back(std::chrono::duration<double, std::milli>(t1 - t0).count());
        to.push_back(std::chrono::duration<double, std::milli>(t2 - t1).count());
      }
      Print(l.name.c_str(), (std::string(paper ? "cogmap paper, " : "cogmap default, ") + (paper ? "face" : "mid")).c_str(),
            Measure(a, l, Median(tc)));
      Print(l.name.c_str(), (std::string("opencv, ") + (paper ? "face" : "mid")).c_str(), Measure(b, l, Median(to)));
    }
  }
  return 0;
}
