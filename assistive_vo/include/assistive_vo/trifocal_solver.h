#pragma once
// Stereo egomotion from mixed point and line correspondences across two calibrated stereo pairs
// (seed 2.2.2-2.2.3, eqs. 2.23-2.41): the two trifocal tensors T^L (views 1, 2, 3) and T^R
// (views 1, 2, 4) are linear in the motion (R, t), so every correspondence gives linear rows in
// y = [R (row-major), t, 1]; three solvers of that system:
//   - linear (12 unknowns, eq. 2.28): needs 12 independent rows ({4 points}, {3 lines}, ...);
//   - subspace (eq. 2.31): particular solution + null space of A, the coefficients fixed by the
//     rotation's polynomial constraints;
//   - quaternion direct solution (eqs. 2.32-2.41): R from a unit quaternion, t eliminated,
//     elimination down to a quintic in a^2; minimal sets {3 points}, {2 points + 1 line}
//     ({2 lines} alone is refused), any larger set over-determined (n = 4, 5, ...).
// Coordinates are normalised (K = I). Views: P1 = [I | 0] (left before), P2 = [R0 | t0] (right
// before), P3 = [R | t] (left after), P4 = [R0 R | R0 t + t0] (right after) (eqs. 2.1-2.2).
// A 3D point X in view-1 coordinates is seen in view 3 at R X + t. ROS-free (Eigen only).
#include <string>
#include <vector>
#include <Eigen/Core>
#include <Eigen/StdVector>

namespace assistive_vo
{
/// The fixed stereo geometry: the right camera is P2 = [R0 | t0] in normalised coordinates.
/// A rectified rig with the right camera `b` metres along +x of the left: R0 = I, t0 = (-b, 0, 0).
struct StereoRig
{
  Eigen::Matrix3d R0 = Eigen::Matrix3d::Identity();
  Eigen::Vector3d t0 = Eigen::Vector3d(-0.075, 0.0, 0.0);
  EIGEN_MAKE_ALIGNED_OPERATOR_NEW
};

/// One point seen in all four views (normalised image coordinates).
struct PointQuad
{
  Eigen::Vector2d x[4];
  EIGEN_MAKE_ALIGNED_OPERATOR_NEW
};

/// One line seen in all four views, each view's observation a segment (two points on the line;
/// the segments need not cover the same part of the 3D line in different views).
struct LineQuad
{
  Eigen::Vector2d p[4], q[4];
  EIGEN_MAKE_ALIGNED_OPERATOR_NEW
};

using PointQuads = std::vector<PointQuad, Eigen::aligned_allocator<PointQuad>>;
using LineQuads = std::vector<LineQuad, Eigen::aligned_allocator<LineQuad>>;

/// A motion hypothesis: view-1 coordinates to view-3 coordinates, X3 = R X1 + t.
struct StereoMotion
{
  Eigen::Matrix3d R = Eigen::Matrix3d::Identity();
  Eigen::Vector3d t = Eigen::Vector3d::Zero();
  EIGEN_MAKE_ALIGNED_OPERATOR_NEW
};
using StereoMotions = std::vector<StereoMotion, Eigen::aligned_allocator<StereoMotion>>;

struct TrifocalResult
{
  bool ok = false;              ///< at least one finite solution
  std::string reason;           ///< why not, when !ok (degenerate set, too few rows, ...)
  StereoMotions solutions;      ///< all real solutions (every entry finite, R a rotation)
};

enum class TrifocalMethod
{
  Linear,
  Subspace,
  Quaternion
};
const char* toString(TrifocalMethod m);

/// Rank of the 12 unknowns' block for a generic set of `points` points and `lines` lines.
/// The seed (2.2.2.2) counts 3 independent rows per point and 4 per line; that holds for points
/// alone and lines alone, but mixed sets lose rows: the points pin the null motions (N, n) to
/// N X + n = 0 on them, and a line then adds fewer rows: {3 points + 1 line} gives 11 (the null
/// motions w pi^T of the points' plane, a line only asks w to be normal to two vectors),
/// {1 point + 2 lines} 10. Measured on random sets (rectified and general rigs) and encoded here.
int constraintRank(size_t points, size_t lines);

/// The stacked trifocal constraints A [y; 1] = 0 (eqs. 2.24, 2.25 with eqs. 2.26, 2.27):
/// 18 rows per point ([x2]x (sum_i x1_i T_i) [x3]x = 0 for T^L and T^R with x4), 4 per line
/// (l2^T (sum_i p_i T_i) l3 = 0 for the two segment ends p of view 1, for T^L and T^R with l4).
/// Columns: R row-major (9), t (3), constant (1). Rows are unit-free (normalised coordinates).
Eigen::MatrixXd trifocalSystem(const StereoRig& rig, const PointQuads& points, const LineQuads& lines);

/// The three solvers. Every one validates its input (finite coordinates, a rig with a baseline,
/// enough independent rows, full-rank blocks) and returns !ok with a reason instead of a NaN.
TrifocalResult solveTrifocalLinear(const StereoRig& rig, const PointQuads& points, const LineQuads& lines);
TrifocalResult solveTrifocalSubspace(const StereoRig& rig, const PointQuads& points, const LineQuads& lines);
TrifocalResult solveTrifocalQuaternion(const StereoRig& rig, const PointQuads& points, const LineQuads& lines);
TrifocalResult solveTrifocal(TrifocalMethod m, const StereoRig& rig, const PointQuads& points,
                             const LineQuads& lines);

/// Nearest rotation (Frobenius norm, det +1), for the linear and subspace estimates.
Eigen::Matrix3d nearestRotation(const Eigen::Matrix3d& M);

/// Reprojection error of a hypothesis over all four views, in the units of `focal` (pass the
/// focal length in pixels to get pixels): points are triangulated from views 1 and 2 (known rig)
/// and projected into the four views (RMS of the four 2D errors); lines are triangulated from the
/// two planes of views 1 and 2 and projected into views 3 and 4, the error the RMS distance of the
/// observed segment ends to the projected lines (views 1 and 2 are exact by construction).
/// Huge (1e9) when a point or line cannot be triangulated or falls behind a camera.
double pointReprojectionError(const StereoRig& rig, const StereoMotion& m, const PointQuad& pt, double focal);
double lineReprojectionError(const StereoRig& rig, const StereoMotion& m, const LineQuad& ln, double focal);

}  // namespace assistive_vo
