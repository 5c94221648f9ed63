// Heading errors of a `cogmap map` output folder, for the benchmark suite
// when `cogmap eval` does not report them: the ASRs of OUTDIR/map.sqlite
// through cogmap::localize::ComputeHeadingErrors (the metric of issue 6,
// the same code the eval keys come from), printed as JSON.
//
//   cogmap_suite_heading_eval OUTDIR
#include <iostream>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "cogmap/asr/store.h"
#include "cogmap/core/error.h"
#include "cogmap/localize/heading_error.h"

int main(int argc, char** argv) {
  if (argc != 2) {
    std::cerr << "usage: cogmap_suite_heading_eval OUTDIR (a folder written by cogmap map)\n";
    return 2;
  }
  try {
    const std::string path = std::string(argv[1]) + "/map.sqlite";
    auto store = cogmap::asr::SqliteAsrStore::Open(path, cogmap::asr::SqliteAsrStore::OpenMode::kOpenExisting);
    std::vector<cogmap::asr::Asr> asrs;
    for (int id : store->Ids())
      if (auto a = store->Get(id)) asrs.push_back(std::move(*a));
    const auto stats = cogmap::localize::ComputeHeadingErrors(asrs);
    nlohmann::json out;
    out["asrs"] = static_cast<int>(asrs.size());
    out["asrs_with_truth"] = stats.asrs;
    for (const auto& [key, value] : cogmap::localize::HeadingErrorEvalKeys(stats)) out[key] = value;
    std::cout << out.dump(2) << "\n";
    return 0;
  } catch (const cogmap::InputError& e) {
    std::cerr << "cogmap_suite_heading_eval: " << e.what() << "\n";
    return 2;
  } catch (const std::exception& e) {
    std::cerr << "cogmap_suite_heading_eval: " << e.what() << "\n";
    return 1;
  }
}
