#include "cogmap/vectorize/extract.h"

#include <gtest/gtest.h>

#include <random>

namespace cogmap::vectorize {
namespace {

grid::Grid2D<float> Blank(int w, int h) { return grid::Grid2D<float>(grid::MapLimits(0.1, Vec2(0, 0), w, h), 0.0f); }

TEST(Extract, PaperDefaults) {
  const ExtractOptions o;
  EXPECT_EQ(o.gamma_cells, 4.0);
  EXPECT_EQ(o.classes.occupied_above, 7.0f);
}

TEST(Extract, StraightRunInOrder) {
  auto g = Blank(20, 5);
  for (int x = 3; x < 13; ++x) g.at(x, 2) = 15.0f;
  const auto chains = ExtractPoints(g);
  ASSERT_EQ(chains.size(), 1u);
  ASSERT_EQ(chains[0].size(), 10u);
  for (int i = 0; i < 10; ++i) EXPECT_EQ(chains[0][i], grid::CellIndex(3 + i, 2));
}

TEST(Extract, GapWiderThanGammaSplits) {
  auto g = Blank(40, 5);
  for (int x = 0; x < 10; ++x) g.at(x, 2) = 15.0f;
  for (int x = 15; x < 25; ++x) g.at(x, 2) = 15.0f;  // step 6 > 4
  const auto chains = ExtractPoints(g);
  ASSERT_EQ(chains.size(), 2u);
  EXPECT_EQ(chains[0].back(), grid::CellIndex(9, 2));
  EXPECT_EQ(chains[1].front(), grid::CellIndex(15, 2));
}

TEST(Extract, GapOfGammaDoesNotSplit) {
  auto g = Blank(40, 5);
  for (int x = 0; x < 10; ++x) g.at(x, 2) = 15.0f;
  for (int x = 13; x < 20; ++x) g.at(x, 2) = 15.0f;  // step 4 == gamma
  EXPECT_EQ(ExtractPoints(g).size(), 1u);
}

TEST(Extract, OneCellGapsJoin) {
  auto g = Blank(30, 5);
  for (int x = 0; x < 30; x += 2) g.at(x, 2) = 15.0f;
  const auto chains = ExtractPoints(g);
  ASSERT_EQ(chains.size(), 1u);
  EXPECT_EQ(chains[0].size(), 15u);
}

TEST(Extract, RingClosesAndStartsAtRasterFirst) {
  auto g = Blank(20, 20);
  for (int i = 5; i <= 14; ++i) g.at(i, 5) = g.at(i, 14) = g.at(5, i) = g.at(14, i) = 15.0f;
  ExtractStats st;
  const auto chains = ExtractPoints(g, {}, &st);
  ASSERT_EQ(chains.size(), 1u);
  EXPECT_EQ(st.points, 36);
  EXPECT_EQ(st.closed, 1);
  EXPECT_EQ(chains[0].size(), 37u);
  EXPECT_EQ(chains[0].front(), grid::CellIndex(5, 5));
  EXPECT_EQ(chains[0][1], grid::CellIndex(6, 5));
  EXPECT_EQ(chains[0].back(), chains[0].front());
}

TEST(Extract, BadInputsAreDefined) {
  EXPECT_TRUE(ExtractPoints(grid::Grid2D<float>()).empty());
  EXPECT_TRUE(ExtractPoints(Blank(10, 10)).empty());
  auto g = Blank(10, 10);
  g.at(4, 4) = 15.0f;
  const auto one = ExtractPoints(g);
  ASSERT_EQ(one.size(), 1u);
  EXPECT_EQ(one[0].size(), 1u);
}

// Reference: the same walk with a scan of every remaining cell per step.
std::vector<CellChain> NaiveExtract(const grid::Grid2D<float>& g, double gamma) {
  std::vector<grid::CellIndex> left;
  for (int y = 0; y < g.limits().height(); ++y)
    for (int x = 0; x < g.limits().width(); ++x)
      if (g.at(x, y) > 7.0f) left.push_back({x, y});
  std::vector<CellChain> chains;
  if (left.empty()) return chains;
  CellChain chain;
  grid::CellIndex p = left.front();
  left.erase(left.begin());
  for (;;) {
    chain.push_back(p);
    if (left.empty()) break;
    size_t best = 0;
    long best_d2 = -1;
    for (size_t i = 0; i < left.size(); ++i) {  // raster order: first wins ties
      const long d2 = (left[i] - p).cast<long>().squaredNorm();
      if (best_d2 < 0 || d2 < best_d2) best_d2 = d2, best = i;
    }
    if (best_d2 > gamma * gamma) {
      chains.push_back(chain);
      chain.clear();
    }
    p = left[best];
    left.erase(left.begin() + best);
  }
  chains.push_back(chain);
  return chains;
}

TEST(Extract, IndexMatchesFullScanOnRandomGrids) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(0, 1);
  for (int trial = 0; trial < 10; ++trial) {
    auto g = Blank(45 + trial, 37);
    const double density = 0.01 + 0.03 * (trial % 4);
    for (auto& v : g.cells()) v = u(rng) < density ? 15.0f : 0.0f;
    ExtractOptions o;
    o.close_loops = false;
    o.gamma_cells = 2.0 + trial % 4;
    EXPECT_EQ(ExtractPoints(g, o), NaiveExtract(g, o.gamma_cells)) << "trial " << trial;
  }
}

}  // namespace
}  // namespace cogmap::vectorize
