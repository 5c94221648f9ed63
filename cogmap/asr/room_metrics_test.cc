#include "cogmap/asr/room_metrics.h"

#include <gtest/gtest.h>

namespace cogmap::asr {
namespace {

Asr PathAsr(int id, Vec2 a, Vec2 b) {
  Asr asr;
  asr.id = id;
  for (int i = 0; i <= 20; ++i) {
    const Vec2 p = a + (b - a) * (i / 20.0);
    asr.path.push_back({p.x(), p.y(), 0.0});
  }
  return asr;
}

const std::vector<NamedBox> kRooms = {{"a", {0, 0}, {5, 4}}, {"b", {5, 0}, {10, 4}}, {"c", {10, 0}, {15, 4}}};

TEST(RoomMetrics, OneAsrPerRoomIsPerfect) {
  const auto m = EvaluateRooms({PathAsr(0, {1, 2}, {4.5, 2}), PathAsr(1, {5.5, 2}, {9, 2}),
                                PathAsr(2, {10.5, 2}, {14, 2})},
                               kRooms);
  EXPECT_EQ(m.asr_room, (std::vector<int>{0, 1, 2}));
  EXPECT_DOUBLE_EQ(m.room_precision, 1.0);
  EXPECT_DOUBLE_EQ(m.room_recall, 1.0);
}

TEST(RoomMetrics, RoomsFromARaster) {
  // The three rooms of kRooms as 1 m cells over 15 x 4 m.
  RoomLabels l;
  l.cell_m = 1.0;
  l.width = 15;
  l.height = 4;
  l.names = {"a", "b", "c"};
  l.cells = {20, 20, 20};
  for (int y = 0; y < 4; ++y)
    for (int x = 0; x < 15; ++x) l.label.push_back(x / 5);
  const auto m = EvaluateRooms({PathAsr(0, {1, 2}, {4.5, 2}), PathAsr(1, {5.5, 2}, {9, 2}), PathAsr(2, {6, 2}, {9, 3})},
                               l);
  EXPECT_EQ(m.asr_room, (std::vector<int>{0, 1, 1}));
  EXPECT_DOUBLE_EQ(m.room_precision, 2.0 / 3.0);
  EXPECT_DOUBLE_EQ(m.room_recall, 2.0 / 3.0);
}

TEST(RoomMetrics, SecondAsrInTheSameRoomLowersPrecision) {
  const auto m = EvaluateRooms({PathAsr(0, {1, 2}, {2.5, 2}), PathAsr(1, {2.6, 2}, {4.5, 2}),
                                PathAsr(2, {5.5, 2}, {9, 2})},
                               kRooms);
  EXPECT_EQ(m.matched_asrs, 2);
  EXPECT_DOUBLE_EQ(m.room_precision, 2.0 / 3.0);
  EXPECT_DOUBLE_EQ(m.room_recall, 2.0 / 3.0);
}

TEST(RoomMetrics, AsrSpreadOverThreeRoomsMatchesNone) {
  const auto m = EvaluateRooms({PathAsr(0, {2, 2}, {13, 2})}, kRooms);
  EXPECT_EQ(m.asr_room, (std::vector<int>{-1}));
  EXPECT_DOUBLE_EQ(m.room_precision, 0.0);
}

TEST(RoomMetrics, TruePathWinsOverOdometry) {
  Asr a = PathAsr(0, {6, 2}, {9, 2});  // odometry says room b
  a.true_path = PathAsr(0, {1, 2}, {4, 2}).path;  // truth says room a
  EXPECT_EQ(EvaluateRooms({a}, kRooms).asr_room, (std::vector<int>{0}));
}

TEST(RoomMetrics, CorrectedFrameIsUsedWithoutTruth) {
  Asr a = PathAsr(0, {1, 2}, {4, 2});
  a.world_from_local_raw = {0, 0, 0};
  a.world_from_local_corrected = {5, 0, 0};  // the correction moved it to room b
  EXPECT_EQ(EvaluateRooms({a}, kRooms).asr_room, (std::vector<int>{1}));
}

TEST(RoomMetrics, RevisitsAreScoredAgainstTheTrueRooms) {
  // ASRs 0..4 in true rooms 0, 1, 0, 1, -1 (none); the store calls 2 a
  // revisit of 0 (right), 3 a revisit of 0 (wrong: it lies in room 1) and
  // 4 a revisit of 1 (unscored: 4 lies in no single room).
  const RevisitMetrics m = EvaluateRevisits({0, 1, 2, 3, 4}, {0, 1, 0, 0, 1}, {0, 1, 0, 1, -1});
  EXPECT_EQ(m.graph_rooms, 2);
  EXPECT_EQ(m.revisits, 3);
  EXPECT_EQ(m.revisits_right, 1);
  EXPECT_EQ(m.revisits_wrong, 1);
  const RevisitMetrics none = EvaluateRevisits({5, 6}, {5, 6}, {0, 0});
  EXPECT_EQ(none.graph_rooms, 2);
  EXPECT_EQ(none.revisits, 0);
}

}  // namespace
}  // namespace cogmap::asr
