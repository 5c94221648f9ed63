#pragma once
#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <vector>

#include "cogmap/core/geometry.h"

namespace cogmap::graph {

// A wall segment with the side it was seen from: 'normal' is the unit normal
// pointing into the free space the robot mapped it from. Two rooms that see
// the two faces of one thick wall give segments 0.1-0.3 m apart with opposite
// normals; registration and fusion match only faces with agreeing normals.
struct FacedSegment {
  Vec2 a{0, 0};
  Vec2 b{0, 0};
  Vec2 normal{0, 1};
  double length() const { return (b - a).norm(); }
};

// The faced segments of an ASR's walls (its local frame): each segment's free
// side is the side of the nearest of 'free_points' (the robot's path through
// the room, local frame). Segments shorter than min_length_m are dropped.
std::vector<FacedSegment> FaceWalls(const std::vector<Polyline>& walls, const std::vector<Vec2>& free_points,
                                    double min_length_m = 0.05);

// The faces near a point without looking at every face: a uniform grid over
// the faces' bounding boxes, each cell listing the faces whose box meets it.
// With reach_m > 0 each cell also lists, in index order, the faces whose box
// comes within reach_m of it: a query no farther than that reads its own
// cell's list alone. Nearest() gives exactly what the scan of every face
// gives (same face, same residual, ties to the lowest index). Holds a
// pointer to 'faces': they must outlive the index and not change.
class FaceIndex {
 public:
  explicit FaceIndex(const std::vector<FacedSegment>& faces, double cell_m = 0.5, double reach_m = 0.0);

  // The nearest face to p within max_d (strictly) whose normal agrees with n
  // (normal . n >= cos_max): its index, or -1; *residual is then the signed
  // distance of p from the face's line along its normal, and *distance (if
  // given) the distance from p to the face.
  int Nearest(const Vec2& p, const Vec2& n, double max_d, double cos_max, double* residual,
              double* distance = nullptr) const;

 private:
  // Cell of a coordinate already scaled to cells: clamped, then truncated
  // (no libm floor call; never decreasing, which is all the query needs).
  static int CellOf(double u, int n) { return static_cast<int>(std::clamp(u, 0.0, n - 1.0)); }

  const std::vector<FacedSegment>* faces_;
  Vec2 lo_{0, 0};
  double inv_cell_ = 1.0;  // cells per metre
  int nx_ = 0, ny_ = 0;
  std::vector<int> start_;  // cell c's faces: items_[start_[c] .. start_[c + 1])
  std::vector<int> items_;
  double reach_ = 0.0;           // the faces within this of a cell are listed for it (0: none)
  std::vector<int> near_start_;  // cell c's faces within reach: near_[near_start_[c] .. near_start_[c + 1])
  std::vector<int> near_;
  struct Box {
    double x0, y0, x1, y1;
  };
  std::vector<Box> boxes_;  // each face's bounding box
};

// The same answer by scanning every face (the reference of FaceIndex).
int NearestFaceByScan(const std::vector<FacedSegment>& faces, const Vec2& p, const Vec2& n, double max_d,
                      double cos_max, double* residual);

struct RegistrationOptions {
  double sample_step_m = 0.1;          // source walls sampled every this far
  double max_correspondence_m = 0.6;   // first iterations
  double final_correspondence_m = 0.3; // last iterations (shrinks linearly)
  double max_normal_angle_rad = 0.5;   // ~30 deg between matched faces
  double huber_m = 0.1;                // Huber weight on point-to-line residuals
  int iterations = 30;
  double min_sigma_m = 0.02;           // floor of the residual 1-sigma
  // With a prior (a registration across an exit), when the walls are
  // placed in their rooms to within a grid cell: each wall's ends off by
  // 1-sigma cell / sqrt(12) (uniform over the cell; 0.1 m cells: 2.9 cm).
  // That error is one per wall, shared by every sample along it, so it does
  // not average down with the samples: the covariance counts it once per
  // matched pair of walls (docs/pose-graph.md, "Registration"). 0: the
  // older model below (a sonar's walls, placed by a beam wider than a cell
  // across the window: MappingPipeline sets it for narrow beams only).
  double wall_end_sigma_m = 0.1 / std::sqrt(12.0);
  // The older model, and the iterations' weights: residuals of neighbouring
  // samples along one wall taken as correlated over this length, the
  // residual variance inflated by correlation_length_m / sample_step_m.
  // A loop closure's search (no prior) keeps it.
  double correlation_length_m = 0.5;
  int min_matches = 12;
};

// The pose of a source frame in a target frame, found by point-to-line ICP
// (Gauss-Newton on SE(2), Huber-weighted) of the source walls' samples onto
// the target walls, face-aware.
struct Registration {
  bool converged = false;
  Pose2 target_from_source;
  // 3x3 covariance of (x, y, theta) of target_from_source: sigma^2 H^-1 with the
  // residual variance sigma^2 and the correlation inflation. Degenerate
  // directions (a corridor's length) get large variances.
  Eigen::Matrix3d covariance = Eigen::Matrix3d::Identity() * 1e6;
  int samples = 0;           // source samples
  int matches = 0;           // samples with a correspondence at the end
  double match_fraction = 0; // matches / samples
  double rmse_m = 0.0;       // of the matched point-to-line residuals
  int iterations = 0;
  int degenerate_directions = 0;  // with a prior: directions left at the prior (0-3)
  // Target faces with at least one matched sample at the end. One face (a
  // line: two constraints on three unknowns) is met exactly by a whole
  // family of poses, so the residuals cannot check the fit.
  int faces_matched = 0;
};

//
// 'prior_covariance' (optional): the covariance of the initial pose (x, y in
// the target frame, theta), for example the odometry's between the two
// frames. With it, the registration moves only along the directions where
// the walls say more than the prior does (in the prior's whitened
// coordinates, the data's information eigenvalues of at least 1: solution
// remapping, Zhang, Kaess and Singh, ICRA 2016), and its covariance says
// nothing along the others. A corridor's length, or the period of its
// doors, then stays where the prior put it instead of sliding to wherever the
// walls overlap most; without it the walls decide every direction.
Registration RegisterWalls(const std::vector<FacedSegment>& target, const std::vector<FacedSegment>& source,
                           const Pose2& initial_target_from_source, const RegistrationOptions& options = {},
                           const Eigen::Matrix3d* prior_covariance = nullptr);

// A pose covariance (x, y, theta) of one frame, in a frame turned by theta
// from it: x and y turned by theta, the heading as it is.
Eigen::Matrix3d TurnedCovariance(const Eigen::Matrix3d& cov, double theta);

// The registration's covariance as the error of target_from_source seen
// from the source frame: x and y along the source's axes, then theta. That
// is the frame of the pose graph's relative factors (PoseGraph::AddRelative,
// as the odometry's covariance is in its end pose's frame) and of a^-1 b
// differences; Registration::covariance has x and y along the target's axes
// (the ICP moves the source in the target frame). The two differ by the
// turn between the frames: a corridor registered across a quarter turn has
// its weak axis along the target's x and along the source's y.
Eigen::Matrix3d CovarianceInSourceFrame(const Registration& r);

// Samples of faced segments every 'step_m' (point, normal).
struct FacedPoint {
  Vec2 p;
  Vec2 normal;
  int face = -1;  // the index of the segment it lies on
};
std::vector<FacedPoint> SampleFaces(const std::vector<FacedSegment>& faces, double step_m);

// Fraction of 'points' (already in the target frame) that lie within
// 'tolerance_m' of a target face whose normal agrees within max_normal_angle_rad.
double AgreementFraction(const std::vector<FacedSegment>& target, const std::vector<FacedPoint>& points,
                         double tolerance_m, double max_normal_angle_rad);

// The agreement of 'points' (target frame) with 'target' at every shift of a
// grid at once: count[i * ys.size() + j] is the number of points that lie
// within tolerance_m of a face with agreeing normal once moved by (xs[i],
// ys[j]) (the test of AgreementFraction). Each point marks the shifts that put
// it on a face, so the cost is that of the faces near each point, not of every
// point at every shift. xs and ys ascend.
std::vector<int> AgreementOverShifts(const std::vector<FacedSegment>& target, const std::vector<FacedPoint>& points,
                                     const std::vector<double>& xs, const std::vector<double>& ys, double tolerance_m,
                                     double max_normal_angle_rad);

// Number of crossings of the path polyline 'path' (target frame) by target
// walls: a path that runs through a wall means the placement is wrong (the
// robot drove there). Consecutive path points farther apart than max_gap_m are
// not joined.
int PathWallCrossings(const std::vector<FacedSegment>& walls, const std::vector<Vec2>& path, double max_gap_m = 1.0);

}  // namespace cogmap::graph
