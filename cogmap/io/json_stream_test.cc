#include "cogmap/io/json_stream.h"

#include <gtest/gtest.h>

#include <iomanip>
#include <sstream>

namespace cogmap::io {
namespace {

// Elements 0..n-1 of 'all', one per call.
JsonStreams::Next Each(const nlohmann::json& all) {
  return [all, k = size_t{0}](nlohmann::json* e) mutable {
    if (k >= all.size()) return false;
    *e = all[k++];
    return true;
  };
}

std::string Dump2(const nlohmann::json& j) {
  std::ostringstream o;
  o << std::setw(2) << j;
  return o.str();
}

TEST(JsonStreams, WritesWhatDumpTwoWritesWithTheArraysStreamed) {
  const nlohmann::json asrs = {
      {{"id", 0}, {"seconds", 0.25}, {"name", "a \"quoted\"\nline \u00e9"}, {"walls", {1, 2, 3}}, {"none", nullptr}},
      {{"id", 1}, {"seconds", 1e-7}, {"nested", {{"deep", {{"x", {1.5, -2.0}}}}, {"empty", nlohmann::json::array()}}}},
      {{"id", 2}, {"seconds", 3.0}, {"e", nlohmann::json::object()}}};
  const nlohmann::json placements = {{{"id", 0}, {"sigma", 0.1}}, {{"id", 1}, {"sigma", 0.2}}};
  nlohmann::json whole = {{"log", "x.log"}, {"asr_count", 3}, {"asrs", asrs},
                          {"pose_graph", {{"chi2", 1.25}, {"placements", placements},
                                          {"closure_candidates", nlohmann::json::array()},
                                          {"warnings", {"one", "two"}}}},
                          {"zzz", {{"k", true}}}};
  JsonStreams streams;
  nlohmann::json doc = whole;
  doc["asrs"] = streams.Add(Each(asrs));
  doc["pose_graph"]["placements"] = streams.Add(Each(placements));
  doc["pose_graph"]["closure_candidates"] = streams.Add(Each(nlohmann::json::array()));
  std::ostringstream o;
  streams.Write(o, doc);
  EXPECT_EQ(o.str(), Dump2(whole));
  EXPECT_EQ(nlohmann::json::parse(o.str()), whole);
}

TEST(JsonStreams, ADocumentWithoutStreamsIsItsDump) {
  const nlohmann::json j = {{"a", {1, 2}}, {"b", {{"c", "d"}}}};
  JsonStreams streams;
  std::ostringstream o;
  streams.Write(o, j);
  EXPECT_EQ(o.str(), Dump2(j));
}

}  // namespace
}  // namespace cogmap::io
