#pragma once
// The pose graph's factors (pose_graph.cc), each a functor with two faces:
// its templated operator() is the model, in the form ceres::AutoDiffCostFunction
// differentiates (the tests check the other face against it), and its
// Evaluate gives the same residuals, to the bit, with the Jacobians written
// out by the chain rule. Forward-mode automatic differentiation carries a
// derivative for every parameter (8 for a bent registration) through every
// sine and product; the solves spent a third of their time there (intel:
// 25 of 80 ms over 107 solves).
#include <ceres/ceres.h>

#include <Eigen/Core>
#include <array>
#include <cmath>
#include <cstring>
#include <memory>

#include "cogmap/core/angles.h"
#include "cogmap/graph/pose_graph.h"

namespace cogmap::graph::costs {

constexpr double kQuarter = kPi / 2.0;

inline double Value(double x) { return x; }
template <typename T, int N>
double Value(const ceres::Jet<T, N>& x) {
  return x.a;
}

// Angle difference wrapped into [-pi, pi) by the value (the wrap is a constant
// offset for the derivatives).
template <typename T>
T Wrap(const T& a) {
  const double k = std::round(Value(a) / (2.0 * kPi));
  return a - T(k * 2.0 * kPi);
}

// Residual of node j in node i's frame against a measured (mx, my, mth): the
// error expressed in the measured pose's frame, whitened.
template <typename T>
void RelativeResidual(const T* pi, const T* pj, const T& mx, const T& my, const T& mth, const Eigen::Matrix3d& W,
                      T* r) {
  using std::cos;
  using std::sin;
  const T c = cos(pi[2]), s = sin(pi[2]);
  const T dx = pj[0] - pi[0], dy = pj[1] - pi[1];
  const T px = c * dx + s * dy, py = -s * dx + c * dy;
  const T ex = px - mx, ey = py - my;
  const T cm = cos(mth), sm = sin(mth);
  const T e[3] = {cm * ex + sm * ey, -sm * ex + cm * ey, Wrap(pj[2] - pi[2] - mth)};
  for (int a = 0; a < 3; ++a) r[a] = T(W(a, 0)) * e[0] + T(W(a, 1)) * e[1] + T(W(a, 2)) * e[2];
}

// RelativeResidual in doubles (the same operations: the same residual) and
// its Jacobian J over (pi, pj, m = (mx, my, mth)), 3 x 9.
inline void RelativeResidualJ(const double* pi, const double* pj, const double* m, const Eigen::Matrix3d& W,
                              double* r, Eigen::Matrix<double, 3, 9>* J) {
  const double c = std::cos(pi[2]), s = std::sin(pi[2]);
  const double dx = pj[0] - pi[0], dy = pj[1] - pi[1];
  const double px = c * dx + s * dy, py = -s * dx + c * dy;
  const double ex = px - m[0], ey = py - m[1];
  const double cm = std::cos(m[2]), sm = std::sin(m[2]);
  const double e[3] = {cm * ex + sm * ey, -sm * ex + cm * ey, Wrap(pj[2] - pi[2] - m[2])};
  for (int a = 0; a < 3; ++a) r[a] = W(a, 0) * e[0] + W(a, 1) * e[1] + W(a, 2) * e[2];
  // (px, py) over each input, then e = R(-mth) (px - mx, py - my).
  const double dp[2][9] = {{-c, -s, py, c, s, 0.0, -1.0, 0.0, 0.0}, {s, -c, -px, -s, c, 0.0, 0.0, -1.0, 0.0}};
  Eigen::Matrix<double, 3, 9> E;
  for (int k = 0; k < 9; ++k) {
    E(0, k) = cm * dp[0][k] + sm * dp[1][k];
    E(1, k) = -sm * dp[0][k] + cm * dp[1][k];
    E(2, k) = 0.0;
  }
  E(0, 8) = e[1];  // the measured heading turns the error
  E(1, 8) = -e[0];
  E(2, 2) = -1.0;
  E(2, 5) = 1.0;
  E(2, 8) = -1.0;
  *J = W * E;
}

// Node i's path end under drift rate 'rate' (m's steps re-integrated).
template <typename T>
void BentEnd(const OdometryMeasurement& m, const T& rate, T* out) {
  using std::cos;
  using std::sin;
  T bx(0.0), by(0.0);
  for (const Eigen::Vector3d& st : m.steps) {
    const T a = -rate * T(st.z());
    bx += cos(a) * T(st.x()) - sin(a) * T(st.y());
    by += sin(a) * T(st.x()) + cos(a) * T(st.y());
  }
  out[0] = bx;
  out[1] = by;
  out[2] = T(m.delta.theta) - rate * T(m.distance_m);
}

// BentEnd in doubles (the same operations: the same end) and its derivative
// over the rate.
inline void BentEndD(const OdometryMeasurement& m, double rate, double* out, double* d) {
  double bx = 0.0, by = 0.0, dx = 0.0, dy = 0.0;
  for (const Eigen::Vector3d& st : m.steps) {
    const double a = -rate * st.z();
    const double ca = std::cos(a), sa = std::sin(a);
    bx += ca * st.x() - sa * st.y();
    by += sa * st.x() + ca * st.y();
    dx += st.z() * (sa * st.x() + ca * st.y());  // d a / d rate = -z
    dy -= st.z() * (ca * st.x() - sa * st.y());
  }
  out[0] = bx;
  out[1] = by;
  out[2] = m.delta.theta - rate * m.distance_m;
  d[0] = dx;
  d[1] = dy;
  d[2] = -m.distance_m;
}

// The doubles of a scalar that the solver evaluates: a double, or a Jet's
// value and then its derivatives.
template <typename T>
struct Scalars;
template <>
struct Scalars<double> {
  static constexpr int n = 1;
  static double Get(const double& x, int) { return x; }
  static void Set(double& x, int, double v) { x = v; }
};
template <int N>
struct Scalars<ceres::Jet<double, N>> {
  static constexpr int n = 1 + N;
  static double Get(const ceres::Jet<double, N>& x, int k) { return k == 0 ? x.a : x.v[k - 1]; }
  static void Set(ceres::Jet<double, N>& x, int k, double v) {
    if (k == 0) x.a = v;
    else x.v[k - 1] = v;
  }
};

// One measurement's last BentEnd, per scalar type, and its last BentEndD. A
// factor's drift rate often stays as it was from one evaluation to the next
// (rates held at zero, the rates outside a local solve's window, the
// variance-component rounds' solves that start where the last one ended),
// and BentEnd costs a sine and a cosine per step of the path. Given the same
// rate to the bit it hands back what it gave for it, so the solves' numbers
// are the same. Not for evaluations on several threads at once (the graph's
// solves use one).
class BentEndCache {
 public:
  template <typename T>
  void operator()(const OdometryMeasurement& m, const T& rate, T* out) const {
    using S = Scalars<T>;
    static_assert(S::n <= kMaxScalars);
    Slot& c = S::n == 1 ? plain_ : jet_;
    if (c.n == S::n) {
      bool same = true;
      for (int k = 0; k < S::n && same; ++k) {
        const double x = S::Get(rate, k);
        same = std::memcmp(&x, &c.v[k], sizeof x) == 0;
      }
      if (same) {
        for (int o = 0; o < 3; ++o)
          for (int k = 0; k < S::n; ++k) S::Set(out[o], k, c.v[S::n * (1 + o) + k]);
        return;
      }
    }
    BentEnd(m, rate, out);
    c.n = S::n;
    for (int k = 0; k < S::n; ++k) c.v[k] = S::Get(rate, k);
    for (int o = 0; o < 3; ++o)
      for (int k = 0; k < S::n; ++k) c.v[S::n * (1 + o) + k] = S::Get(out[o], k);
  }
  // The end and its derivative over the rate.
  void WithDerivative(const OdometryMeasurement& m, double rate, double* out, double* d) const {
    if (!derived_.valid || std::memcmp(&rate, &derived_.rate, sizeof rate) != 0) {
      BentEndD(m, rate, derived_.out.data(), derived_.d.data());
      derived_.rate = rate;
      derived_.valid = true;
    }
    for (int o = 0; o < 3; ++o) {
      out[o] = derived_.out[o];
      d[o] = derived_.d[o];
    }
  }

 private:
  static constexpr int kMaxScalars = 9;  // a Jet of the widest factor: 3 + 3 + 1 + 1 parameters
  struct Slot {
    int n = 0;  // doubles per scalar held (0: none yet)
    std::array<double, 4 * kMaxScalars> v;  // the rate, then the three outputs
  };
  struct Derived {
    bool valid = false;
    double rate = 0.0;
    std::array<double, 3> out, d;
  };
  mutable Slot plain_, jet_;
  mutable Derived derived_;
};

template <typename T>
void ComposeT(const T* a, const T* b, T* out) {
  using std::cos;
  using std::sin;
  const T c = cos(a[2]), s = sin(a[2]);
  const T x = a[0] + c * b[0] - s * b[1];
  const T y = a[1] + s * b[0] + c * b[1];
  out[0] = x;
  out[1] = y;
  out[2] = a[2] + b[2];
}

template <typename T>
void InverseT(const T* a, T* out) {
  using std::cos;
  using std::sin;
  const T c = cos(a[2]), s = sin(a[2]);
  const T x = -(c * a[0] + s * a[1]);
  const T y = -(-s * a[0] + c * a[1]);
  out[0] = x;
  out[1] = y;
  out[2] = -a[2];
}

// The 3-vector d of a pose's change: the change of ComposeT(a, b) for a
// change da of a (Da), or db of b (Db), and of InverseT(a) for da (Di).
inline Eigen::Matrix3d ComposeDa(const double* a, const double* b) {
  const double c = std::cos(a[2]), s = std::sin(a[2]);
  Eigen::Matrix3d D = Eigen::Matrix3d::Identity();
  D(0, 2) = -s * b[0] - c * b[1];
  D(1, 2) = c * b[0] - s * b[1];
  return D;
}
inline Eigen::Matrix3d ComposeDb(const double* a) {
  const double c = std::cos(a[2]), s = std::sin(a[2]);
  Eigen::Matrix3d D;
  D << c, -s, 0.0, s, c, 0.0, 0.0, 0.0, 1.0;
  return D;
}
inline Eigen::Matrix3d InverseDa(const double* a) {
  const double c = std::cos(a[2]), s = std::sin(a[2]);
  Eigen::Matrix3d D;
  D << -c, -s, s * a[0] - c * a[1], s, -c, c * a[0] + s * a[1], 0.0, 0.0, -1.0;
  return D;
}

// Rows 'rows' of 'J' (residuals x 9 over pi, pj, m), each scaled, into
// Ceres's row-major Jacobian blocks for pi and pj (when asked for).
inline void WritePoseBlocks(const Eigen::Matrix<double, 3, 9>& J, const double* row_scale, double** jacobians) {
  for (int b = 0; b < 2; ++b) {
    if (!jacobians[b]) continue;
    for (int a = 0; a < 3; ++a)
      for (int k = 0; k < 3; ++k) jacobians[b][a * 3 + k] = row_scale[a] * J(a, 3 * b + k);
  }
}
// The rate's column: J's measurement columns times the measurement's
// derivative over the rate dm.
inline void WriteRateBlock(const Eigen::Matrix<double, 3, 9>& J, const double* row_scale, const Eigen::Vector3d& dm,
                           double* block) {
  if (!block) return;
  const Eigen::Vector3d col = J.rightCols<3>() * dm;
  for (int a = 0; a < 3; ++a) block[a] = row_scale[a] * col(a);
}

// The odometry's whitening, heading first (HeadingFirstSqrtInformation in
// pose_graph.cc): row 2 is the heading error over its marginal sigma, rows 0
// and 1 the translation error less what the heading explains of it; each
// part scaled on its own by the variance components.
struct OdometryCost {
  OdometryMeasurement m;
  Eigen::Matrix3d W;
  double offset = 0.0;  // the drift already removed from m (node i's rate offset)
  double scale = 1.0;   // 1 / the translation component's sigma factor (rows 0, 1)
  double scale_heading = 1.0;  // 1 / the heading component's sigma factor (row 2)
  BentEndCache bent{};
  template <typename T>
  bool operator()(const T* pi, const T* pj, const T* rate, T* r) const {
    T end[3];
    bent(m, rate[0] - T(offset), end);
    RelativeResidual(pi, pj, end[0], end[1], end[2], W, r);
    r[0] *= T(scale);
    r[1] *= T(scale);
    r[2] *= T(scale_heading);
    return true;
  }
  bool Evaluate(double const* const* p, double* r, double** jacobians) const {
    if (!jacobians) return (*this)(p[0], p[1], p[2], r);
    double end[3], d_end[3];
    bent.WithDerivative(m, p[2][0] - offset, end, d_end);
    Eigen::Matrix<double, 3, 9> J;
    RelativeResidualJ(p[0], p[1], end, W, r, &J);
    const double row_scale[3] = {scale, scale, scale_heading};
    for (int a = 0; a < 3; ++a) r[a] *= row_scale[a];
    WritePoseBlocks(J, row_scale, jacobians);
    WriteRateBlock(J, row_scale, Eigen::Vector3d(d_end[0], d_end[1], d_end[2]), jacobians[2]);
    return true;
  }
};

struct RelativeCost {
  Pose2 z;
  Eigen::Matrix3d W;
  double scale = 1.0;
  template <typename T>
  bool operator()(const T* pi, const T* pj, T* r) const {
    RelativeResidual(pi, pj, T(z.x), T(z.y), T(z.theta), W, r);
    for (int a = 0; a < 3; ++a) r[a] *= T(scale);
    return true;
  }
  bool Evaluate(double const* const* p, double* r, double** jacobians) const {
    if (!jacobians) return (*this)(p[0], p[1], r);
    const double m[3] = {z.x, z.y, z.theta};
    Eigen::Matrix<double, 3, 9> J;
    RelativeResidualJ(p[0], p[1], m, W, r, &J);
    const double row_scale[3] = {scale, scale, scale};
    for (int a = 0; a < 3; ++a) r[a] *= scale;
    WritePoseBlocks(J, row_scale, jacobians);
    return true;
  }
};

// A registration of raw walls: node j's against node i's, where they overlap
// at a distance driven s_i into node i and s_j into node j. Walls seen there
// were placed with the heading drifted by rate x s more than at the node's
// origin, so the measured raw pose z is bent at both ends as the odometry is:
// the prediction of node j in node i is B_i z B_j^-1, with B = (the path to s
// re-integrated under the node's rate) x (the raw path to s)^-1. Across an
// exit s_i is node i's whole path and s_j = 0 (B_j the identity).
struct BentRelativeCost {
  OdometryMeasurement mi, mj;  // each node's path (as mapped) to where the walls overlap
  Pose2 middle;                // mi.delta^-1 z mj.delta
  Eigen::Matrix3d W;
  double offset_i = 0.0, offset_j = 0.0;  // the nodes' rate offsets
  double scale = 1.0;
  BentEndCache bent_i{}, bent_j{};
  template <typename T>
  bool operator()(const T* pi, const T* pj, const T* rate_i, const T* rate_j, T* r) const {
    T bi[3], bj[3], bj_inv[3], t[3], m[3];
    bent_i(mi, rate_i[0] - T(offset_i), bi);
    bent_j(mj, rate_j[0] - T(offset_j), bj);
    InverseT(bj, bj_inv);
    const T mid[3] = {T(middle.x), T(middle.y), T(middle.theta)};
    ComposeT(bi, mid, t);
    ComposeT(t, bj_inv, m);
    RelativeResidual(pi, pj, m[0], m[1], m[2], W, r);
    for (int a = 0; a < 3; ++a) r[a] *= T(scale);
    return true;
  }
  bool Evaluate(double const* const* p, double* r, double** jacobians) const {
    if (!jacobians) return (*this)(p[0], p[1], p[2], p[3], r);
    double bi[3], dbi[3], bj[3], dbj[3], bj_inv[3], t[3], m[3];
    bent_i.WithDerivative(mi, p[2][0] - offset_i, bi, dbi);
    bent_j.WithDerivative(mj, p[3][0] - offset_j, bj, dbj);
    InverseT(bj, bj_inv);
    const double mid[3] = {middle.x, middle.y, middle.theta};
    ComposeT(bi, mid, t);
    ComposeT(t, bj_inv, m);
    Eigen::Matrix<double, 3, 9> J;
    RelativeResidualJ(p[0], p[1], m, W, r, &J);
    const double row_scale[3] = {scale, scale, scale};
    for (int a = 0; a < 3; ++a) r[a] *= scale;
    WritePoseBlocks(J, row_scale, jacobians);
    // m = (B_i mid) B_j^-1: through t for rate i, through B_j^-1 for rate j.
    const Eigen::Matrix3d dm_dt = ComposeDa(t, bj_inv);
    WriteRateBlock(J, row_scale, dm_dt * ComposeDa(bi, mid) * Eigen::Vector3d(dbi[0], dbi[1], dbi[2]), jacobians[2]);
    WriteRateBlock(J, row_scale, ComposeDb(t) * InverseDa(bj) * Eigen::Vector3d(dbj[0], dbj[1], dbj[2]),
                   jacobians[3]);
    return true;
  }
};

struct DirectionCost {
  double d = 0.0, sigma = 1.0, s_mean = 0.0, floor = 0.0;
  double offset = 0.0;  // the node's rate offset (drift removed while it was mapped)
  double scale = 1.0;   // 1 / the variance components' factor on sigma
  double s_spread = 0.0;  // 1-sigma spread of where along the path the walls were seen
  double bend = 0.0;      // s_spread x |the rate left| at the last update (SetDirectionBend)
  // The factor's 1-sigma: the measurement's (scaled by the variance
  // components) with the bend error, at least the floor.
  double Sigma() const {
    const double m = sigma / scale;
    return std::max({floor, std::sqrt(m * m + bend * bend), 1e-9});
  }
  template <typename T>
  bool operator()(const T* pi, const T* phi, const T* rate, T* r) const {
    // Walls seen after driving s from the ASR's origin were placed with a
    // heading that had drifted by rate x s more: they lean by +rate x s in the
    // ASR's frame (less what was removed while mapping). The measured
    // direction is corrected by the mean.
    const T v = pi[2] + T(d) - (rate[0] - T(offset)) * T(s_mean) - phi[0];
    const double k = std::round(Value(v) / kQuarter);  // nearest of the four branches
    r[0] = (v - T(k * kQuarter)) / T(Sigma());
    return true;
  }
  bool Evaluate(double const* const* p, double* r, double** jacobians) const {
    if (!jacobians) return (*this)(p[0], p[1], p[2], r);
    const double v = p[0][2] + d - (p[2][0] - offset) * s_mean - p[1][0];
    const double k = std::round(v / kQuarter);
    // (Times the inverse, as a Jet divided by a constant is: the residual
    // the derivatives belong with, to the bit.)
    const double inv = 1.0 / Sigma();
    r[0] = (v - k * kQuarter) * inv;
    if (jacobians[0]) {
      jacobians[0][0] = 0.0;
      jacobians[0][1] = 0.0;
      jacobians[0][2] = inv;
    }
    if (jacobians[1]) jacobians[1][0] = -inv;
    if (jacobians[2]) jacobians[2][0] = -s_mean * inv;
    return true;
  }
};

struct RateWalkCost {
  double inv_sigma = 1.0;
  template <typename T>
  bool operator()(const T* ri, const T* rj, T* r) const {
    r[0] = (rj[0] - ri[0]) * T(inv_sigma);
    return true;
  }
  bool Evaluate(double const* const* p, double* r, double** jacobians) const {
    (*this)(p[0], p[1], r);
    if (jacobians && jacobians[0]) jacobians[0][0] = -inv_sigma;
    if (jacobians && jacobians[1]) jacobians[1][0] = inv_sigma;
    return true;
  }
};

struct RatePriorCost {
  double inv_sigma = 1.0;
  template <typename T>
  bool operator()(const T* ri, T* r) const {
    r[0] = ri[0] * T(inv_sigma);
    return true;
  }
  bool Evaluate(double const* const* p, double* r, double** jacobians) const {
    (*this)(p[0], r);
    if (jacobians && jacobians[0]) jacobians[0][0] = inv_sigma;
    return true;
  }
};

// A functor's Evaluate as a Ceres cost function (owning the functor, as
// ceres::AutoDiffCostFunction does).
template <typename F, int kResiduals, int... kBlocks>
class Analytic final : public ceres::SizedCostFunction<kResiduals, kBlocks...> {
 public:
  explicit Analytic(F* functor) : functor_(functor) {}
  bool Evaluate(double const* const* parameters, double* residuals, double** jacobians) const override {
    return functor_->Evaluate(parameters, residuals, jacobians);
  }

 private:
  std::unique_ptr<F> functor_;
};

}  // namespace cogmap::graph::costs
