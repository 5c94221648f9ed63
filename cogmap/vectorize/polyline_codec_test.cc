#include "cogmap/vectorize/polyline_codec.h"

#include <gtest/gtest.h>

#include "cogmap/core/error.h"

namespace cogmap::vectorize {
namespace {

TEST(PolylineCodec, RoundTripWithinHalfAQuantum) {
  const std::vector<Polyline> lines = {{Vec2(1.234, -5.678), Vec2(3.0, 4.0), Vec2(-2.5, 0.004)},
                                       {Vec2(0, 0)},
                                       {}};
  const auto back = DecodePolylines(EncodePolylines(lines));
  ASSERT_EQ(back.size(), lines.size());
  for (size_t i = 0; i < lines.size(); ++i) {
    ASSERT_EQ(back[i].size(), lines[i].size());
    for (size_t j = 0; j < lines[i].size(); ++j) {
      EXPECT_LE(std::abs(back[i][j].x() - lines[i][j].x()), 0.005 + 1e-12);
      EXPECT_LE(std::abs(back[i][j].y() - lines[i][j].y()), 0.005 + 1e-12);
    }
  }
}

TEST(PolylineCodec, ExactSize) {
  // Magic 4 + quantum 1 + count 1 + (vertex count 1 + 2 x 1 byte + 2 x 2 bytes).
  // (0.1, 0.2) -> 10, 20 quanta (zigzag 20, 40: 1 byte each); delta (1.0, 0)
  // -> 100 (zigzag 200: 2 bytes), 0 (1 byte).
  const std::string b = EncodePolylines({{Vec2(0.1, 0.2), Vec2(1.1, 0.2)}});
  EXPECT_EQ(b.size(), 4u + 1 + 1 + 1 + 2 + 3);
}

TEST(PolylineCodec, EmptySetIsSixBytes) { EXPECT_EQ(EncodePolylines({}).size(), 6u); }

TEST(PolylineCodec, BadInputThrows) {
  EXPECT_THROW(DecodePolylines("nope"), InputError);
  std::string b = EncodePolylines({{Vec2(1, 2), Vec2(3, 4)}});
  EXPECT_THROW(DecodePolylines(b.substr(0, b.size() - 1)), InputError);
  EXPECT_THROW(DecodePolylines(b + "x"), InputError);
  std::string huge = std::string("CPL\x01", 4) + "\x0a\x7f";  // 127 polylines, no data
  EXPECT_THROW(DecodePolylines(huge), InputError);
}

}  // namespace
}  // namespace cogmap::vectorize
