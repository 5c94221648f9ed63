#include "cogmap/vectorize/extract.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace cogmap::vectorize {
namespace {

// Occupied cells with per-bucket counts, for nearest-remaining queries.
class BucketIndex {
 public:
  BucketIndex(int width, int height, int bucket)
      : w_(width), h_(height), b_(bucket), bw_((width + bucket - 1) / bucket),
        bh_((height + bucket - 1) / bucket), occ_(static_cast<size_t>(width) * height, 0),
        counts_(static_cast<size_t>(bw_) * bh_, 0) {}

  void Add(int x, int y) {
    occ_[static_cast<size_t>(y) * w_ + x] = 1;
    ++counts_[static_cast<size_t>(y / b_) * bw_ + x / b_];
    ++total_;
  }
  void Remove(int x, int y) {
    occ_[static_cast<size_t>(y) * w_ + x] = 0;
    --counts_[static_cast<size_t>(y / b_) * bw_ + x / b_];
    --total_;
  }
  long total() const { return total_; }

  // Nearest occupied cell to (x, y); ties to the lower (y, x). Requires total > 0.
  grid::CellIndex Nearest(int x, int y) const {
    const int cbx = x / b_, cby = y / b_;
    long best_d2 = std::numeric_limits<long>::max();
    grid::CellIndex best(-1, -1);
    const int max_ring = std::max(bw_, bh_);
    for (int r = 0; r <= max_ring; ++r) {
      // Cells in ring r lie at least (r - 1) * b + 1 cells away in x or y.
      if (r >= 1) {
        const long gap = static_cast<long>(r - 1) * b_ + 1;
        if (gap * gap > best_d2) break;
      }
      for (int by = cby - r; by <= cby + r; ++by) {
        if (by < 0 || by >= bh_) continue;
        const bool edge_row = (by == cby - r || by == cby + r);
        for (int bx = cbx - r; bx <= cbx + r; bx += (edge_row ? 1 : 2 * r)) {
          if (bx >= 0 && bx < bw_) ScanBucket(bx, by, x, y, &best_d2, &best);
          if (r == 0) break;
        }
      }
    }
    return best;
  }

 private:
  void ScanBucket(int bx, int by, int x, int y, long* best_d2, grid::CellIndex* best) const {
    if (counts_[static_cast<size_t>(by) * bw_ + bx] == 0) return;
    const int x0 = bx * b_, y0 = by * b_;
    const int x1 = std::min(w_, x0 + b_), y1 = std::min(h_, y0 + b_);
    for (int cy = y0; cy < y1; ++cy)
      for (int cx = x0; cx < x1; ++cx) {
        if (!occ_[static_cast<size_t>(cy) * w_ + cx]) continue;
        const long dx = cx - x, dy = cy - y, d2 = dx * dx + dy * dy;
        if (d2 < *best_d2 || (d2 == *best_d2 && (cy < best->y() || (cy == best->y() && cx < best->x())))) {
          *best_d2 = d2;
          *best = {cx, cy};
        }
      }
  }

  int w_, h_, b_, bw_, bh_;
  std::vector<uint8_t> occ_;
  std::vector<int> counts_;
  long total_ = 0;
};

}  // namespace

std::vector<CellChain> ExtractPoints(const grid::Grid2D<float>& grid, const ExtractOptions& options,
                                     ExtractStats* stats) {
  ExtractStats local;
  ExtractStats& st = stats ? *stats : local;
  st = ExtractStats{};
  std::vector<CellChain> chains;
  const auto& lim = grid.limits();
  const int w = lim.width(), h = lim.height();
  if (w <= 0 || h <= 0) return chains;
  const int bucket = std::max(2, static_cast<int>(std::ceil(options.gamma_cells)));
  BucketIndex index(w, h, bucket);
  grid::CellIndex first(-1, -1);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
      if (options.classes.IsOccupied(grid.at(x, y))) {
        index.Add(x, y);
        if (first.x() < 0) first = {x, y};
      }
  if (index.total() == 0) return chains;
  const double gamma2 = options.gamma_cells * options.gamma_cells;

  auto finish = [&](CellChain& chain) {
    if (options.close_loops && chain.size() >= 4) {
      const auto d = (chain.back() - chain.front()).cast<double>();
      if (d.squaredNorm() <= gamma2) {
        chain.push_back(chain.front());
        ++st.closed;
      }
    }
    chains.push_back(std::move(chain));
    ++st.chains;
  };

  CellChain chain;
  grid::CellIndex p = first;
  for (;;) {
    chain.push_back(p);
    index.Remove(p.x(), p.y());
    ++st.points;
    if (index.total() == 0) break;
    const grid::CellIndex next = index.Nearest(p.x(), p.y());
    const double d2 = (next - p).cast<double>().squaredNorm();
    if (d2 > gamma2) {
      finish(chain);
      chain = CellChain{};
    }
    p = next;
  }
  finish(chain);
  return chains;
}

std::vector<Vec2> ChainToCellCoords(const CellChain& chain) {
  std::vector<Vec2> out;
  out.reserve(chain.size());
  for (const auto& c : chain) out.push_back(Vec2(c.x() + 0.5, c.y() + 0.5));
  return out;
}

}  // namespace cogmap::vectorize
