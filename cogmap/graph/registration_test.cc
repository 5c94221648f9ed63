#include "cogmap/graph/registration.h"

#include <gtest/gtest.h>

#include <Eigen/Dense>

#include <array>
#include <cmath>
#include <random>

namespace cogmap::graph {
namespace {

// A 4 x 3 m room with an L-shaped alcove (not symmetric), seen from inside.
std::vector<Polyline> Room() {
  return {{Vec2(0, 0), Vec2(4, 0), Vec2(4, 2), Vec2(3, 2), Vec2(3, 3), Vec2(0, 3), Vec2(0, 0)}};
}
std::vector<Vec2> Inside() { return {Vec2(1, 1), Vec2(2, 1.5), Vec2(3.5, 1)}; }

// The room's faces seen from a frame placed at 'at' in the room's frame.
std::vector<FacedSegment> RoomSeenFrom(const Pose2& at) {
  std::vector<Vec2> inside;
  for (const auto& q : Inside()) inside.push_back(at.inverse() * q);
  return FaceWalls(Transform(at.inverse(), Room()), inside);
}

TEST(Registration, FacesPointIntoTheRoom) {
  const auto faces = FaceWalls(Room(), Inside());
  ASSERT_EQ(faces.size(), 6u);
  EXPECT_NEAR(faces[0].normal.y(), 1.0, 1e-12);   // floor wall: free side +y
  EXPECT_NEAR(faces[1].normal.x(), -1.0, 1e-12);  // right wall: free side -x
}

TEST(Registration, RecoversAKnownPose) {
  const Pose2 truth{0.3, -0.2, DegToRad(4.0)};
  const auto target = FaceWalls(Room(), Inside());
  // The same room seen from a frame placed at 'truth' in the target frame.
  const auto source = FaceWalls(Transform(truth.inverse(), Room()), [&] {
    std::vector<Vec2> p;
    for (const auto& q : Inside()) p.push_back(truth.inverse() * q);
    return p;
  }());
  const Registration r = RegisterWalls(target, source, Pose2{}, {});
  ASSERT_TRUE(r.converged);
  EXPECT_NEAR(r.target_from_source.x, truth.x, 1e-4);
  EXPECT_NEAR(r.target_from_source.y, truth.y, 1e-4);
  EXPECT_NEAR(r.target_from_source.theta, truth.theta, 1e-5);
  EXPECT_GT(r.match_fraction, 0.95);
  EXPECT_LT(r.covariance(0, 0), 1e-3);
}

TEST(Registration, CorridorLengthIsUncertain) {
  // Two long parallel walls: nothing fixes the position along them.
  const std::vector<Polyline> walls = {{Vec2(0, 0), Vec2(10, 0)}, {Vec2(0, 2), Vec2(10, 2)}};
  const std::vector<Vec2> inside = {Vec2(1, 1), Vec2(9, 1)};
  const auto faces = FaceWalls(walls, inside);
  const Registration r = RegisterWalls(faces, faces, Pose2{0.0, 0.05, 0.0}, {});
  ASSERT_TRUE(r.converged);
  EXPECT_NEAR(r.target_from_source.y, 0.0, 1e-4);
  EXPECT_GT(r.covariance(0, 0), 100.0 * r.covariance(1, 1));
}

TEST(Registration, ItsCovarianceSeenFromTheSourceTurnsWithIt) {
  // The same corridor, the source frame turned a quarter turn: its walls run
  // along its own y. Along the target's x the walls fix nothing, and that is
  // the source's y.
  const std::vector<Polyline> walls = {{Vec2(0, 0), Vec2(10, 0)}, {Vec2(0, 2), Vec2(10, 2)}};
  const auto target = FaceWalls(walls, {Vec2(1, 1), Vec2(9, 1)});
  const Pose2 truth{5.0, 1.0, DegToRad(90.0)};
  const auto source = FaceWalls(Transform(truth.inverse(), walls), {truth.inverse() * Vec2(1, 1), truth.inverse() * Vec2(9, 1)});
  const Registration r = RegisterWalls(target, source, Pose2{5.0, 1.05, DegToRad(89.0)}, {});
  ASSERT_TRUE(r.converged);
  EXPECT_NEAR(r.target_from_source.y, 1.0, 1e-4);
  EXPECT_NEAR(r.target_from_source.theta, truth.theta, 1e-5);
  EXPECT_GT(r.covariance(0, 0), 100.0 * r.covariance(1, 1));
  const Eigen::Matrix3d c = CovarianceInSourceFrame(r);
  EXPECT_GT(c(1, 1), 100.0 * c(0, 0));
  EXPECT_NEAR(c(1, 1), r.covariance(0, 0), 1e-6 * r.covariance(0, 0));
  EXPECT_NEAR(c(0, 0), r.covariance(1, 1), 1e-6 * r.covariance(0, 0));
  EXPECT_NEAR(c(2, 2), r.covariance(2, 2), 1e-12);
  // Unturned, the source frame is the target's.
  Registration same = r;
  same.target_from_source.theta = 0.0;
  EXPECT_TRUE(CovarianceInSourceFrame(same).isApprox(r.covariance));
}

// A corridor 2.4 m wide along x from 'x0' to 'x1', in the frame of a robot
// standing at (at, 1.2), heading +x: its lower wall has a 0.9 m door every
// 6 m (gaps centred on x = 6, 12, 18, ...), as hallway_loop's corridors.
std::vector<FacedSegment> CorridorSeenFrom(double at, double x0, double x1) {
  std::vector<Polyline> walls = {{Vec2(x0 - at, 1.2), Vec2(x1 - at, 1.2)}};
  double start = x0;
  for (double door = 6.0; door < x1; door += 6.0) {
    if (door + 0.45 <= x0) continue;
    if (door - 0.45 > start) walls.push_back({Vec2(start - at, -1.2), Vec2(door - 0.45 - at, -1.2)});
    start = door + 0.45;
  }
  if (start < x1) walls.push_back({Vec2(start - at, -1.2), Vec2(x1 - at, -1.2)});
  return FaceWalls(walls, {Vec2(0.5 * (x0 + x1) - at, 0.0)});
}

TEST(Registration, APriorKeepsACorridorFromSlidingAlongItsLength) {
  // Two 15 m pieces of one corridor meeting at x = 15, the second seen from
  // its own start: its walls overlap the first's over 3 m, around no door
  // (the sensors reach 3 m behind). The odometry guess is 5 cm and 1 degree
  // off the truth (15, 0, 0).
  const auto first = CorridorSeenFrom(0.0, 0.0, 15.0);
  const auto second = CorridorSeenFrom(15.0, 12.6, 27.0);
  const Pose2 guess{15.05, 0.04, DegToRad(1.0)};
  Eigen::Matrix3d prior = Eigen::Vector3d(0.2 * 0.2, 0.2 * 0.2, std::pow(DegToRad(1.5), 2)).asDiagonal();
  const Registration r = RegisterWalls(first, second, guess, {}, &prior);
  ASSERT_TRUE(r.converged);
  // Across the corridor and in heading the walls decide; along it, the
  // prior: the guess's x is kept, and the covariance says so.
  EXPECT_NEAR(r.target_from_source.y, 0.0, 0.01);
  EXPECT_NEAR(r.target_from_source.theta, 0.0, DegToRad(0.1));
  EXPECT_NEAR(r.target_from_source.x, guess.x, 0.01);
  EXPECT_EQ(r.degenerate_directions, 1);
  EXPECT_GT(r.covariance(0, 0), 100.0 * prior(0, 0));
  EXPECT_LT(r.covariance(1, 1), prior(1, 1));
}

TEST(Registration, APriorLeavesADeterminedPoseToTheWalls) {
  // The L-shaped room: every direction is determined, far better than the
  // prior, which then changes nothing (the same pose as without it).
  const Pose2 truth{0.3, -0.2, DegToRad(4.0)};
  const auto target = FaceWalls(Room(), Inside());
  const auto source = RoomSeenFrom(truth);
  const Eigen::Matrix3d prior = Eigen::Vector3d(0.3 * 0.3, 0.3 * 0.3, std::pow(DegToRad(5.0), 2)).asDiagonal();
  const Registration r = RegisterWalls(target, source, Pose2{}, {}, &prior);
  ASSERT_TRUE(r.converged);
  EXPECT_EQ(r.degenerate_directions, 0);
  EXPECT_NEAR(r.target_from_source.x, truth.x, 1e-4);
  EXPECT_NEAR(r.target_from_source.y, truth.y, 1e-4);
  EXPECT_NEAR(r.target_from_source.theta, truth.theta, 1e-5);
  EXPECT_LT(r.covariance(0, 0), 1e-3);
}

// Each wall of both rooms placed with its two ends off along its normal by
// N(0, sigma^2), as the covariance's model (with a prior) has it (RegistrationOptions::
// wall_end_sigma_m): over many draws the errors of the poses found are as
// large as the covariances say (mean chi^2 of 3 for 3 dof), at a sample
// step of 0.1 m and of 0.025 m alike; the errors shared along a wall do not
// average down with its samples.
std::vector<FacedSegment> Jittered(std::vector<FacedSegment> faces, double sigma, std::mt19937* rng) {
  std::normal_distribution<double> n(0.0, sigma);
  for (FacedSegment& f : faces) {
    const Vec2 a = f.a + n(*rng) * f.normal, b = f.b + n(*rng) * f.normal;
    const Vec2 u = (b - a).normalized();
    f.a = a;
    f.b = b;
    f.normal = f.normal.dot(Vec2(-u.y(), u.x())) >= 0.0 ? Vec2(-u.y(), u.x()) : Vec2(u.y(), -u.x());
  }
  return faces;
}

TEST(Registration, ItsCovarianceHoldsTheErrorsOfWallsPlacedWithinACell) {
  const Pose2 truth{0.3, -0.2, DegToRad(4.0)};
  const auto target = FaceWalls(Room(), Inside());
  const auto source = RoomSeenFrom(truth);
  // A prior far wider than the walls' errors (the odometry across an exit).
  const Eigen::Matrix3d wide = Eigen::Vector3d(1.0, 1.0, std::pow(DegToRad(20.0), 2)).asDiagonal();
  for (const double step : {0.1, 0.025}) {
    RegistrationOptions o;
    o.sample_step_m = step;
    std::mt19937 rng(7);
    double chi2 = 0.0;
    const int draws = 400;
    for (int k = 0; k < draws; ++k) {
      const Registration r = RegisterWalls(Jittered(target, o.wall_end_sigma_m, &rng),
                                           Jittered(source, o.wall_end_sigma_m, &rng), Pose2{}, o, &wide);
      ASSERT_TRUE(r.converged);
      const Eigen::Vector3d e(r.target_from_source.x - truth.x, r.target_from_source.y - truth.y,
                              NormalizeAngle(r.target_from_source.theta - truth.theta));
      chi2 += e.dot(r.covariance.ldlt().solve(e));
    }
    chi2 /= draws;
    // chi^2(3)'s mean over 400 draws: 3 +- 0.12 (1 sigma); the residuals'
    // own 2 cm floor adds a little to the covariance (2.7 here; walls off by
    // twice the model's sigma: 11-12).
    EXPECT_GT(chi2, 2.3) << "step " << step;
    EXPECT_LT(chi2, 3.5) << "step " << step;
  }
}

TEST(Registration, OneWallIsMetExactlyAndCountsAsOneFace) {
  // A single wall: the source slid 0.7 m along it and turned by 2 degrees
  // from the target's. ICP lays it on the line exactly (no residual) and
  // leaves the slide: one face matched, nothing to check the fit.
  const auto target = FaceWalls({{Vec2(-3, 0), Vec2(3, 0)}}, {Vec2(0, 1)});
  const Pose2 shifted{0.7, 0.02, DegToRad(2.0)};
  const auto source = FaceWalls(Transform(shifted, std::vector<Polyline>{{Vec2(-2, 0), Vec2(2, 0)}}),
                                {shifted * Vec2(0, 1)});
  const Registration r = RegisterWalls(target, source, Pose2{}, {});
  ASSERT_TRUE(r.converged);
  EXPECT_EQ(r.faces_matched, 1);
  EXPECT_LT(r.rmse_m, 1e-9);
  // The L-shaped room matches on all of its faces.
  const auto room = FaceWalls(Room(), Inside());
  const Registration all = RegisterWalls(room, room, Pose2{0.05, -0.03, DegToRad(1.0)}, {});
  EXPECT_EQ(all.faces_matched, static_cast<int>(room.size()));
}

TEST(Registration, TwoFacesOfAThickWallDoNotMatch) {
  // Room A sees the wall's face at y = 0 from below; room B the face at y = 0.25 from above.
  const auto a = FaceWalls({{Vec2(0, 0), Vec2(5, 0)}}, {Vec2(2.5, -1)});
  const auto b = FaceWalls({{Vec2(0, 0.25), Vec2(5, 0.25)}}, {Vec2(2.5, 1.25)});
  const Registration r = RegisterWalls(a, b, Pose2{}, {});
  EXPECT_FALSE(r.converged);
  EXPECT_EQ(r.matches, 0);
}

TEST(Registration, PathThroughWallIsCounted) {
  const auto faces = FaceWalls({{Vec2(0, 0), Vec2(0, 4)}}, {Vec2(-1, 2)});
  EXPECT_EQ(PathWallCrossings(faces, {Vec2(-0.4, 1), Vec2(0.4, 1), Vec2(0.4, 1.8), Vec2(-0.4, 1.8)}), 2);
  EXPECT_EQ(PathWallCrossings(faces, {Vec2(-1, 1), Vec2(-1, 3)}), 0);
}

}  // namespace
}  // namespace cogmap::graph

namespace cogmap::graph {
namespace {
TEST(Registration, AgreementOverShiftsCountsWhatTheBruteForceCountsAtEveryShift) {
  const auto faces = FaceWalls(Room(), Inside());
  std::vector<FacedPoint> pts = SampleFaces(faces, 0.1);
  for (auto& p : pts) p.p += Vec2(0.13, -0.07);  // some within 0.25 m, none exact
  pts.push_back({Vec2(10, 10), Vec2(0, 1)});
  pts.push_back({Vec2(-3, 1), Vec2(1, 0)});
  std::vector<double> xs, ys;
  for (double d = -1.0; d <= 1.0 + 1e-9; d += 0.25) xs.push_back(d);
  for (double d = -0.6; d <= 0.6 + 1e-9; d += 0.2) ys.push_back(d);
  for (double tol : {0.05, 0.15, 0.25}) {
    const std::vector<int> counts = AgreementOverShifts(faces, pts, xs, ys, tol, 0.5);
    ASSERT_EQ(counts.size(), xs.size() * ys.size());
    int nonzero = 0;
    for (size_t i = 0; i < xs.size(); ++i)
      for (size_t j = 0; j < ys.size(); ++j) {
        std::vector<FacedPoint> moved = pts;
        for (auto& p : moved) p.p += Vec2(xs[i], ys[j]);
        const double expected = AgreementFraction(faces, moved, tol, 0.5) * static_cast<double>(pts.size());
        EXPECT_EQ(counts[i * ys.size() + j], static_cast<int>(std::lround(expected))) << tol << " " << i << " " << j;
        nonzero += counts[i * ys.size() + j] > 0 ? 1 : 0;
      }
    if (tol > 0.1) {  // 0.05: no shift of the grid comes that close
      EXPECT_GT(nonzero, 0) << tol;
    }
  }
}
}  // namespace
}  // namespace cogmap::graph

namespace cogmap::graph {
namespace {
TEST(FaceIndex, FindsTheNearestAgreeingFace) {
  const std::vector<FacedSegment> faces = {
      {Vec2(0, 0), Vec2(4, 0), Vec2(0, 1)},   // floor, seen from above
      {Vec2(0, 1), Vec2(4, 1), Vec2(0, -1)},  // ceiling, seen from below
      {Vec2(0, 0), Vec2(4, 0), Vec2(0, 1)},   // the floor again: the lower index wins
  };
  const FaceIndex index(faces);
  const double cos_max = std::cos(0.5);
  double e = -1.0;
  EXPECT_EQ(index.Nearest(Vec2(1, 0.25), Vec2(0, 1), 0.6, cos_max, &e), 0);
  EXPECT_EQ(e, 0.25);
  EXPECT_EQ(index.Nearest(Vec2(1, 0.25), Vec2(0, -1), 0.8, cos_max, &e), 1);
  EXPECT_EQ(e, 0.75);
  // Only faces strictly closer than max_d; no face whose normal disagrees.
  EXPECT_EQ(index.Nearest(Vec2(1, 0.25), Vec2(0, -1), 0.75, cos_max, &e), -1);
  EXPECT_EQ(index.Nearest(Vec2(1, 0.25), Vec2(1, 0), 5.0, cos_max, &e), -1);
  // Beyond the end of the floor: the distance to its end point.
  EXPECT_EQ(index.Nearest(Vec2(4.5, 0.0), Vec2(0, 1), 0.6, cos_max, &e), 0);
  EXPECT_EQ(index.Nearest(Vec2(4.5, 0.0), Vec2(0, 1), 0.5, cos_max, &e), -1);
  // Far outside the grid.
  EXPECT_EQ(index.Nearest(Vec2(1e6, -1e6), Vec2(0, 1), 0.6, cos_max, &e), -1);
  EXPECT_EQ(FaceIndex({}).Nearest(Vec2(0, 0), Vec2(0, 1), 1.0, cos_max, &e), -1);
}

TEST(FaceIndex, GivesWhatTheScanGivesOnRandomFaces) {
  std::mt19937 rng(14);
  std::uniform_real_distribution<double> ux(-3.0, 23.0), uy(-2.0, 12.0), ua(-M_PI, M_PI), ul(0.0, 5.0);
  for (int trial = 0; trial < 20; ++trial) {
    std::vector<FacedSegment> faces;
    const int n_faces = 1 + trial * 10;
    for (int k = 0; k < n_faces; ++k) {
      const Vec2 a(ux(rng), uy(rng));
      const double t = ua(rng), len = trial % 4 == 0 ? 0.0 : ul(rng);  // some points as faces
      const double nt = ua(rng);
      faces.push_back({a, a + len * Vec2(std::cos(t), std::sin(t)), Vec2(std::cos(nt), std::sin(nt))});
    }
    // Exact ties: copies of faces (and their normals) later in the list.
    for (int k = 0; k < n_faces / 5; ++k) faces.push_back(faces[rng() % n_faces]);
    for (const auto& [cell, reach] : std::vector<std::pair<double, double>>{
             {0.1, 0.0}, {0.5, 0.0}, {3.0, 0.0}, {0.1, 0.6}, {0.25, 0.6}, {0.5, 2.5}, {3.0, 0.3}}) {
      // With a reach, queries within it read one cell's list (max_d 0.1 and
      // 0.3 always, 0.6 and 2.5 where the reach covers them).
      const FaceIndex index(faces, cell, reach);
      int found = 0;
      for (int q = 0; q < 2000; ++q) {
        const Vec2 p(ux(rng), uy(rng));
        const double nt = ua(rng);
        const Vec2 n(std::cos(nt), std::sin(nt));
        const double max_d = std::array<double, 4>{0.1, 0.3, 0.6, 2.5}[q % 4];
        const double cos_max = q % 3 == 0 ? -2.0 : std::cos(0.5);
        double e_scan = 0.0, e_index = 0.0;
        const int k_scan = NearestFaceByScan(faces, p, n, max_d, cos_max, &e_scan);
        const int k_index = index.Nearest(p, n, max_d, cos_max, &e_index);
        ASSERT_EQ(k_index, k_scan) << trial << " " << cell << " " << reach << " " << q;
        if (k_scan >= 0) {
          ASSERT_EQ(e_index, e_scan) << trial << " " << cell << " " << reach << " " << q;
          ++found;
        }
      }
      if (trial > 2) {
        EXPECT_GT(found, 100) << trial;
      }
    }
  }
}
}  // namespace
}  // namespace cogmap::graph
