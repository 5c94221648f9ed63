#pragma once
// One grid row of a sonar cone's free evidence (HimmFusion::InsertRay, default
// mode's cone_hits): each cell of the row inside the sector (nearer than
// 'reach', within the half-angle 'half' of the axis) is lowered by the
// decrement, tapered linearly from the axis to the cone's edge. The cone is
// most of a sonar run's grid time, and the division and square root most of
// a cell's; on x86-64 (SSE2, every such CPU) two cells go at a time, each
// lane the very operations of the one-cell loop, so the cells come out the
// same to the bit (tested against it).
#include <algorithm>
#include <cmath>
#if defined(__SSE2__)
#include <emmintrin.h>
#endif

namespace cogmap::grid {

struct ConeRow {
  double ox, cell, sx;   // the grid's x origin and cell size, the sensor's x
  double py;             // the row's cell centres' y less the sensor's y
  double cos_h, sin_h;   // the axis
  double reach2, cos2;   // the sector: reach squared, cos(half) squared
  double half, inv_half;
  double dec;            // the decrement on the axis
  float path, lo;        // a cell holding 'path' is left alone; none goes below 'lo'

  // Cells [xa, xb] of 'row'; 'packed' false: one at a time (the reference).
  void Decrement(float* row, int xa, int xb, bool packed = true) const {
    const double py2 = py * py, along_y = py * sin_h, cross_y = py * cos_h;
    int x = xa;
#if defined(__SSE2__)
    if (packed) {
      const __m128d v_cell = _mm_set1_pd(cell), v_ox = _mm_set1_pd(ox), v_sx = _mm_set1_pd(sx);
      const __m128d v_py2 = _mm_set1_pd(py2), v_cos = _mm_set1_pd(cos_h), v_sin = _mm_set1_pd(sin_h);
      const __m128d v_along_y = _mm_set1_pd(along_y), v_cross_y = _mm_set1_pd(cross_y);
      const __m128d v_reach2 = _mm_set1_pd(reach2), v_cos2 = _mm_set1_pd(cos2), v_zero = _mm_setzero_pd();
      const __m128d v_half = _mm_set1_pd(half), v_inv_half = _mm_set1_pd(inv_half), v_dec = _mm_set1_pd(dec);
      const __m128d v_one = _mm_set1_pd(1.0), v_sixth = _mm_set1_pd(1.0 / 6.0), v_05 = _mm_set1_pd(0.5);
      for (; x + 1 <= xb; x += 2) {
        const __m128d xd = _mm_set_pd(x + 1, x);
        const __m128d px = _mm_sub_pd(_mm_add_pd(v_ox, _mm_mul_pd(_mm_add_pd(xd, v_05), v_cell)), v_sx);
        const __m128d rr = _mm_add_pd(_mm_mul_pd(px, px), v_py2);
        const __m128d along = _mm_add_pd(_mm_mul_pd(px, v_cos), v_along_y);
        __m128d in = _mm_and_pd(_mm_cmplt_pd(rr, v_reach2), _mm_cmpgt_pd(along, v_zero));
        in = _mm_andnot_pd(_mm_cmplt_pd(_mm_mul_pd(along, along), _mm_mul_pd(v_cos2, rr)), in);
        const int inside = _mm_movemask_pd(in);
        if (!inside) continue;
        const __m128d cross = _mm_sub_pd(_mm_mul_pd(px, v_sin), v_cross_y);
        const __m128d sn2 = _mm_div_pd(_mm_mul_pd(cross, cross), rr);
        const __m128d sn = _mm_sqrt_pd(sn2);
        // _mm_min_pd(t, half) is t < half ? t : half, as std::min(half, t).
        const __m128d angle = _mm_min_pd(_mm_mul_pd(sn, _mm_add_pd(v_one, _mm_mul_pd(sn2, v_sixth))), v_half);
        const __m128 step = _mm_cvtpd_ps(_mm_mul_pd(v_dec, _mm_sub_pd(v_one, _mm_mul_pd(angle, v_inv_half))));
        alignas(16) float by[4];
        _mm_store_ps(by, step);
        for (int k = 0; k < 2; ++k) {
          if (!(inside & (1 << k))) continue;
          float& v = row[x + k];
          if (v != path) v = std::max(v - by[k], lo);
        }
      }
    }
#endif
    for (; x <= xb; ++x) {
      const double px = ox + (x + 0.5) * cell - sx;
      const double rr = px * px + py2;
      const double along = px * cos_h + along_y;
      if (rr >= reach2 || along <= 0.0 || along * along < cos2 * rr) continue;
      // The angle off the axis from its sine (within a cone of at most 90
      // degrees; asin's series to the cube is within 1e-4 rad at 15).
      const double cross = px * sin_h - cross_y;
      const double sn2 = cross * cross / rr;
      const double sn = std::sqrt(sn2);
      const double angle = std::min(half, sn * (1.0 + sn2 * (1.0 / 6.0)));
      float& v = row[x];
      if (v != path) v = std::max(v - static_cast<float>(dec * (1.0 - angle * inv_half)), lo);
    }
  }
};

}  // namespace cogmap::grid
