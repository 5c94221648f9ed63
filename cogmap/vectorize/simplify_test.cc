#include "cogmap/vectorize/simplify.h"

#include <gtest/gtest.h>

namespace cogmap::vectorize {
namespace {

TEST(VertexSimplify, PaperDefaults) { EXPECT_EQ(VertexSimplifyOptions{}.tau_cells, 2.0); }
TEST(DouglasPeucker, PaperDefaults) { EXPECT_EQ(DouglasPeuckerOptions{}.eta_cells, 1.5); }

TEST(VertexSimplify, DropsVerticesCloserThanTau) {
  std::vector<Vec2> line;
  for (int i = 0; i <= 10; ++i) line.push_back(Vec2(i, 0));
  // Kept: 0, 2, 4, 6, 8, 10.
  EXPECT_EQ(VertexSimplifyIndices(line), (std::vector<int>{0, 2, 4, 6, 8, 10}));
}

TEST(VertexSimplify, KeepsTheEnd) {
  std::vector<Vec2> line;
  for (int i = 0; i <= 9; ++i) line.push_back(Vec2(i, 0));
  // 0, 2, 4, 6, 8 then 9 is 1 from 8: 8 gives way to the end.
  EXPECT_EQ(VertexSimplifyIndices(line), (std::vector<int>{0, 2, 4, 6, 9}));
  VertexSimplifyOptions paper;
  paper.keep_end = false;
  EXPECT_EQ(VertexSimplifyIndices(line, paper), (std::vector<int>{0, 2, 4, 6, 8}));
}

TEST(VertexSimplify, EmptyAndSingle) {
  EXPECT_TRUE(VertexSimplifyIndices({}).empty());
  EXPECT_EQ(VertexSimplifyIndices({Vec2(1, 1)}), (std::vector<int>{0}));
}

TEST(DouglasPeucker, StraightRunKeepsEnds) {
  std::vector<Vec2> line;
  for (int i = 0; i <= 20; ++i) line.push_back(Vec2(i, (i % 2) * 1.0));  // zig-zag of 1 cell
  EXPECT_EQ(DouglasPeuckerIndices(line), (std::vector<int>{0, 20}));
}

TEST(DouglasPeucker, KeepsCornerOfLShape) {
  std::vector<Vec2> line;
  for (int i = 0; i <= 10; ++i) line.push_back(Vec2(i, 0));
  for (int j = 1; j <= 10; ++j) line.push_back(Vec2(10, j));
  EXPECT_EQ(DouglasPeuckerIndices(line), (std::vector<int>{0, 10, 20}));
}

TEST(DouglasPeucker, ClosedSquareKeepsFourCorners) {
  std::vector<Vec2> line;
  for (int i = 0; i < 10; ++i) line.push_back(Vec2(i, 0));
  for (int i = 0; i < 10; ++i) line.push_back(Vec2(10, i));
  for (int i = 10; i > 0; --i) line.push_back(Vec2(i, 10));
  for (int i = 10; i > 0; --i) line.push_back(Vec2(0, i));
  line.push_back(line.front());
  const auto kept = Pick(line, DouglasPeuckerIndices(line));
  ASSERT_EQ(kept.size(), 5u);
  EXPECT_EQ(kept.front(), kept.back());
  std::vector<Vec2> corners = {Vec2(0, 0), Vec2(10, 0), Vec2(10, 10), Vec2(0, 10)};
  for (const auto& c : corners)
    EXPECT_TRUE(std::find(kept.begin(), kept.end(), c) != kept.end()) << c.transpose();
}

TEST(DouglasPeucker, ToleranceIsStrict) {
  // Middle vertex exactly eta from the chord stays dropped; a bit more keeps it.
  EXPECT_EQ(DouglasPeuckerIndices({Vec2(0, 0), Vec2(5, 1.5), Vec2(10, 0)}), (std::vector<int>{0, 2}));
  EXPECT_EQ(DouglasPeuckerIndices({Vec2(0, 0), Vec2(5, 1.6), Vec2(10, 0)}), (std::vector<int>{0, 1, 2}));
}

}  // namespace
}  // namespace cogmap::vectorize
