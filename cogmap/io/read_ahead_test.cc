#include "cogmap/io/read_ahead.h"

#include <atomic>
#include <optional>
#include <stdexcept>

#include "cogmap/core/error.h"
#include "cogmap/io/log_test_util.h"

namespace cogmap::io {
namespace {

using namespace testing_util;

// A scripted log of 'count' records: record k at time k with k + 1 ranges;
// a truth pose on even records only (left as it was on odd ones, as a
// reader that does not reset its record would); an InputError in place of
// record 'fail_at' (-1: none).
class Scripted : public LogReader {
 public:
  Scripted(int count, int fail_at = -1) : count_(count), fail_at_(fail_at) {}
  bool Next(sensors::LogRecord* r) override {
    const int k = next_;
    if (k == fail_at_) throw InputError(path_, k + 1, "bad record");
    if (k >= count_) return false;
    ++next_;
    r->time_s = k;
    r->odom = Pose2{0.1 * k, 0.0, 0.0};
    if (k % 2 == 0) r->truth = Pose2{0.1 * k, 1.0, 0.0};
    r->ranges.assign(static_cast<size_t>(k % 7) + 1, sensors::RangeReading{});
    for (size_t i = 0; i < r->ranges.size(); ++i) r->ranges[i].range_m = k + 0.01 * static_cast<double>(i);
    return true;
  }
  double progress() const override { return count_ > 0 ? static_cast<double>(next_) / count_ : 1.0; }
  const std::string& path() const override { return path_; }
  int read() const { return next_; }

 private:
  const int count_, fail_at_;
  std::atomic<int> next_{0};
  const std::string path_ = "scripted.log";
};

void ExpectSame(const std::vector<sensors::LogRecord>& a, const std::vector<sensors::LogRecord>& b) {
  ASSERT_EQ(a.size(), b.size());
  for (size_t k = 0; k < a.size(); ++k) {
    EXPECT_EQ(a[k].time_s, b[k].time_s) << k;
    EXPECT_EQ(a[k].odom.x, b[k].odom.x) << k;
    ASSERT_EQ(a[k].truth.has_value(), b[k].truth.has_value()) << k;
    if (a[k].truth) {
      EXPECT_EQ(a[k].truth->x, b[k].truth->x) << k;
    }
    ASSERT_EQ(a[k].ranges.size(), b[k].ranges.size()) << k;
    for (size_t i = 0; i < a[k].ranges.size(); ++i) EXPECT_EQ(a[k].ranges[i].range_m, b[k].ranges[i].range_m);
  }
}

TEST(ReadAhead, GivesTheWrappedReadersRecordsInOrder) {
  for (size_t batch : {1u, 3u, 64u}) {
    Scripted direct(500), wrapped(500);
    const std::vector<sensors::LogRecord> want = ReadAll(direct);
    ReadAhead ahead(wrapped, batch, 2);
    EXPECT_EQ(ahead.path(), "scripted.log");
    const std::vector<sensors::LogRecord> got = ReadAll(ahead);
    ExpectSame(got, want);
    EXPECT_EQ(ahead.progress(), 1.0);
    sensors::LogRecord r;
    EXPECT_FALSE(ahead.Next(&r));  // and stays at the end
  }
  Scripted empty(0);
  ReadAhead ahead(empty);
  sensors::LogRecord r;
  EXPECT_FALSE(ahead.Next(&r));
}

TEST(ReadAhead, RaisesTheErrorAfterTheRecordsBeforeIt) {
  Scripted wrapped(100, 37);
  ReadAhead ahead(wrapped, 8, 2);
  sensors::LogRecord r;
  for (int k = 0; k < 37; ++k) {
    ASSERT_TRUE(ahead.Next(&r)) << k;
    EXPECT_EQ(r.time_s, k);
  }
  for (int again = 0; again < 2; ++again) {
    try {
      ahead.Next(&r);
      FAIL() << "no error";
    } catch (const InputError& e) {
      EXPECT_THAT(e.what(), ::testing::HasSubstr("scripted.log:38: bad record"));
    }
  }
}

TEST(ReadAhead, StopsReadingWhenDestroyedEarly) {
  Scripted wrapped(100000);
  {
    ReadAhead ahead(wrapped, 16, 3);
    sensors::LogRecord r;
    ASSERT_TRUE(ahead.Next(&r));
    ASSERT_TRUE(ahead.Next(&r));
  }
  // At most the batches queued, the one handed out and the one being read.
  EXPECT_LE(wrapped.read(), 16 * 5);
}

TEST(ReadAhead, ReadsARealLogAsItsReaderDoes) {
  const std::string path = std::string(COGMAP_SHARED_DIR) + "/data/carmen/aces-corrected.log.gz";
  auto direct = OpenLog(path, "auto");
  auto wrapped = OpenLog(path, "auto");
  const std::vector<sensors::LogRecord> want = ReadAll(*direct);
  ReadAhead ahead(*wrapped);
  ExpectSame(ReadAll(ahead), want);
  EXPECT_EQ(wrapped->skipped(), direct->skipped());
}

}  // namespace
}  // namespace cogmap::io
