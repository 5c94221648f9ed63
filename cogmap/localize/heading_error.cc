#include "cogmap/localize/heading_error.h"

#include <algorithm>
#include <cmath>

#include "cogmap/core/angles.h"
#include "cogmap/localize/heading_corrector.h"

namespace cogmap::localize {
namespace {

double CircularMean(const std::vector<double>& a) {
  double c = 0.0, s = 0.0;
  for (double v : a) {
    c += std::cos(v);
    s += std::sin(v);
  }
  return (c == 0.0 && s == 0.0) ? 0.0 : std::atan2(s, c);
}

double Median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  const size_t n = v.size();
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

}  // namespace

HeadingErrorStats ComputeHeadingErrors(const std::vector<asr::Asr>& asrs) {
  HeadingErrorStats st;
  std::vector<double> raw, cor;
  for (const auto& a : asrs) {
    const size_t n = a.path.size(), nt = a.true_path.size();
    if (n == 0 || nt == 0) continue;
    const Pose2 correction = CorrectionOf(a);
    std::vector<double> er, ec;
    er.reserve(n);
    ec.reserve(n);
    for (size_t i = 0; i < n; ++i) {
      // Same length: index pairs. Otherwise the same fraction of the way
      // (both paths are sampled by distance travelled).
      const size_t j = n == nt ? i
                       : n == 1 ? nt / 2
                                : static_cast<size_t>(std::lround(double(i) * double(nt - 1) / double(n - 1)));
      const double truth = a.true_path[j].theta;
      er.push_back(AngleDiff(a.path[i].theta, truth));
      ec.push_back(AngleDiff((correction * a.path[i]).theta, truth));
    }
    AsrHeadingError e;
    e.asr_id = a.id;
    e.poses = static_cast<int>(n);
    e.raw_rad = CircularMean(er);
    e.corrected_rad = CircularMean(ec);
    st.per_asr.push_back(e);
    raw.push_back(e.raw_rad);
    cor.push_back(e.corrected_rad);
  }
  st.asrs = static_cast<int>(st.per_asr.size());
  if (st.asrs == 0) return st;
  st.global_rotation_raw_rad = CircularMean(raw);
  st.global_rotation_rad = CircularMean(cor);
  std::vector<double> abs_raw, abs_cor;
  for (auto& e : st.per_asr) {
    e.raw_rad = AngleDiff(e.raw_rad, st.global_rotation_raw_rad);
    e.corrected_rad = AngleDiff(e.corrected_rad, st.global_rotation_rad);
    abs_raw.push_back(RadToDeg(std::abs(e.raw_rad)));
    abs_cor.push_back(RadToDeg(std::abs(e.corrected_rad)));
  }
  st.median_deg = Median(abs_cor);
  st.max_deg = *std::max_element(abs_cor.begin(), abs_cor.end());
  st.median_raw_deg = Median(abs_raw);
  st.max_raw_deg = *std::max_element(abs_raw.begin(), abs_raw.end());
  return st;
}

std::vector<std::pair<std::string, double>> HeadingErrorEvalKeys(const HeadingErrorStats& stats) {
  if (stats.asrs == 0) return {};
  return {{"heading_error_deg_median", stats.median_deg},
          {"heading_error_deg_max", stats.max_deg},
          {"heading_error_deg_median_raw", stats.median_raw_deg},
          {"heading_error_deg_max_raw", stats.max_raw_deg}};
}

}  // namespace cogmap::localize
