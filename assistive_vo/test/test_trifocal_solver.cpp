// The point+line trifocal solvers (seed 2.2.2-2.2.3) on exact synthetic four-view data: baseline
// 7.5 cm, random motions, random points and lines. Every solver recovers the motion to 1e-8;
// degenerate sets are refused with a reason and never produce a NaN.
#include <gtest/gtest.h>
#include <cmath>
#include <limits>
#include "assistive_vo/trifocal_solver.h"
#include "assistive_vo/trifocal_synthetic.h"

using namespace assistive_vo;

namespace
{
/// Smallest error over the returned solutions (R Frobenius, t in m); checks every entry finite.
double bestError(const TrifocalResult& r, const StereoMotion& truth)
{
  double best = std::numeric_limits<double>::infinity();
  for (const StereoMotion& m : r.solutions)
  {
    EXPECT_TRUE(m.R.allFinite() && m.t.allFinite());
    EXPECT_NEAR(m.R.determinant(), 1.0, 1e-9);
    best = std::min(best, std::max((m.R - truth.R).norm(), (m.t - truth.t).norm()));
  }
  return best;
}

PointQuads firstPoints(const TrifocalScene& s, int n) { return PointQuads(s.points.begin(), s.points.begin() + n); }
LineQuads firstLines(const TrifocalScene& s, int n) { return LineQuads(s.lines.begin(), s.lines.begin() + n); }

void expectAllSolveExactly(TrifocalMethod method, int n_points, int n_lines, int scenes)
{
  for (bool random_rig : {false, true})
  {
    std::mt19937 rng(100 + 7 * n_points + 13 * n_lines + (random_rig ? 1 : 0));
    TrifocalSceneOptions o;
    o.random_rig = random_rig;
    for (int i = 0; i < scenes; ++i)
    {
      const TrifocalScene s = makeTrifocalScene(rng, n_points, n_lines, o);
      ASSERT_EQ(static_cast<int>(s.points.size()), n_points);
      ASSERT_EQ(static_cast<int>(s.lines.size()), n_lines);
      const TrifocalResult r = solveTrifocal(method, s.rig, s.points, s.lines);
      ASSERT_TRUE(r.ok) << toString(method) << " " << n_points << "p+" << n_lines << "l scene " << i << ": " << r.reason;
      EXPECT_LT(bestError(r, s.motion), 1e-8)
          << toString(method) << " " << n_points << "p+" << n_lines << "l scene " << i << (random_rig ? " random rig" : "");
    }
  }
}
}  // namespace

TEST(TrifocalSystem, TrueMotionSatisfiesEveryRow)
{
  std::mt19937 rng(1);
  const TrifocalScene s = makeTrifocalScene(rng, 5, 4, TrifocalSceneOptions());
  const Eigen::MatrixXd A = trifocalSystem(s.rig, s.points, s.lines);
  EXPECT_EQ(A.rows(), 18 * 5 + 4 * 4);
  Eigen::VectorXd y(13);
  for (int e = 0; e < 9; ++e)
    y(e) = s.motion.R(e / 3, e % 3);
  y.segment<3>(9) = s.motion.t;
  y(12) = 1.0;
  EXPECT_LT((A * y).cwiseAbs().maxCoeff(), 1e-12);
  // 3 independent rows per point, 4 per line (seed 2.2.2.2): rank of the 12 unknowns' block
  const TrifocalScene s1 = makeTrifocalScene(rng, 3, 0, TrifocalSceneOptions());
  Eigen::JacobiSVD<Eigen::MatrixXd> svd(trifocalSystem(s1.rig, s1.points, s1.lines).leftCols(12));
  EXPECT_GT(svd.singularValues()(8), 1e-9 * svd.singularValues()(0));
  EXPECT_LT(svd.singularValues()(9), 1e-12 * svd.singularValues()(0));
}

TEST(TrifocalQuaternion, MinimalThreePoints) { expectAllSolveExactly(TrifocalMethod::Quaternion, 3, 0, 40); }
TEST(TrifocalQuaternion, MinimalTwoPointsOneLine) { expectAllSolveExactly(TrifocalMethod::Quaternion, 2, 1, 40); }
TEST(TrifocalQuaternion, OnePointTwoLines) { expectAllSolveExactly(TrifocalMethod::Quaternion, 1, 2, 40); }
TEST(TrifocalQuaternion, ThreeLines) { expectAllSolveExactly(TrifocalMethod::Quaternion, 0, 3, 40); }
TEST(TrifocalQuaternion, OverdeterminedFour)
{
  expectAllSolveExactly(TrifocalMethod::Quaternion, 4, 0, 20);
  expectAllSolveExactly(TrifocalMethod::Quaternion, 2, 2, 20);
}
TEST(TrifocalQuaternion, OverdeterminedFive)
{
  expectAllSolveExactly(TrifocalMethod::Quaternion, 5, 0, 20);
  expectAllSolveExactly(TrifocalMethod::Quaternion, 3, 2, 20);
}
TEST(TrifocalSubspace, ThreePoints) { expectAllSolveExactly(TrifocalMethod::Subspace, 3, 0, 40); }
TEST(TrifocalSubspace, TwoPointsOneLine) { expectAllSolveExactly(TrifocalMethod::Subspace, 2, 1, 40); }
TEST(TrifocalSubspace, OnePointTwoLines) { expectAllSolveExactly(TrifocalMethod::Subspace, 1, 2, 40); }
TEST(TrifocalLinear, FourPoints) { expectAllSolveExactly(TrifocalMethod::Linear, 4, 0, 40); }
TEST(TrifocalLinear, ThreeLines) { expectAllSolveExactly(TrifocalMethod::Linear, 0, 3, 40); }
TEST(TrifocalLinear, Mixed)
{
  expectAllSolveExactly(TrifocalMethod::Linear, 2, 2, 20);
  expectAllSolveExactly(TrifocalMethod::Linear, 1, 3, 20);
  expectAllSolveExactly(TrifocalMethod::Linear, 4, 1, 20);
}

TEST(TrifocalSystem, MixedSetsLoseRows)
{
  // The seed's 3n + 4m holds for points alone and lines alone; {3 points + 1 line} has rank 11
  // and {1 point + 2 lines} rank 10 (constraintRank): the linear solver refuses the first.
  std::mt19937 rng(4);
  for (auto [np, nl] : std::vector<std::pair<int, int>>{{3, 1}, {1, 2}, {2, 1}, {1, 1}, {0, 3}, {3, 0}})
  {
    const TrifocalScene s = makeTrifocalScene(rng, np, nl, TrifocalSceneOptions());
    Eigen::JacobiSVD<Eigen::MatrixXd> svd(trifocalSystem(s.rig, s.points, s.lines).leftCols(12));
    int rank = 0;
    for (int i = 0; i < svd.singularValues().size(); ++i)
      rank += svd.singularValues()(i) > 1e-10 * svd.singularValues()(0) ? 1 : 0;
    EXPECT_EQ(rank, constraintRank(np, nl)) << np << "p+" << nl << "l";
  }
  const TrifocalScene s = makeTrifocalScene(rng, 3, 1, TrifocalSceneOptions());
  EXPECT_FALSE(solveTrifocalLinear(s.rig, s.points, s.lines).ok);
}

TEST(TrifocalDegenerate, TwoLinesAloneRefused)
{
  std::mt19937 rng(5);
  const TrifocalScene s = makeTrifocalScene(rng, 0, 2, TrifocalSceneOptions());
  for (TrifocalMethod m : {TrifocalMethod::Linear, TrifocalMethod::Subspace, TrifocalMethod::Quaternion})
  {
    const TrifocalResult r = solveTrifocal(m, s.rig, s.points, s.lines);
    EXPECT_FALSE(r.ok) << toString(m);
    EXPECT_TRUE(r.solutions.empty());
    EXPECT_FALSE(r.reason.empty());
  }
}

TEST(TrifocalDegenerate, TooFewFeaturesRefused)
{
  std::mt19937 rng(6);
  const TrifocalScene s = makeTrifocalScene(rng, 3, 1, TrifocalSceneOptions());
  // {1 point + 1 line}: 7 rows; {2 points}: 6; the linear solver also refuses {3 points}: 9 < 12
  EXPECT_FALSE(solveTrifocalQuaternion(s.rig, firstPoints(s, 1), firstLines(s, 1)).ok);
  EXPECT_FALSE(solveTrifocalSubspace(s.rig, firstPoints(s, 2), LineQuads()).ok);
  EXPECT_FALSE(solveTrifocalLinear(s.rig, firstPoints(s, 3), LineQuads()).ok);
  EXPECT_FALSE(solveTrifocalQuaternion(s.rig, PointQuads(), LineQuads()).ok);
}

TEST(TrifocalDegenerate, CollinearPointsRejected)
{
  std::mt19937 rng(8);
  TrifocalScene s = makeTrifocalScene(rng, 0, 0, TrifocalSceneOptions());
  // five points on one 3D line, observed exactly
  const Eigen::Vector3d A(-0.4, 0.1, 3.0), B(0.5, -0.2, 4.0);
  PointQuads pts;
  for (int i = 0; i < 5; ++i)
  {
    const Eigen::Vector3d X = A + (0.2 * i) * (B - A);
    PointQuad q;
    for (int v = 0; v < 4; ++v)
    {
      const Eigen::Vector3d c = synthetic_detail::inView(s, v, X);
      q.x[v] = c.head<2>() / c.z();
    }
    pts.push_back(q);
  }
  for (TrifocalMethod m : {TrifocalMethod::Linear, TrifocalMethod::Subspace, TrifocalMethod::Quaternion})
  {
    for (int n : {3, 4, 5})
    {
      const TrifocalResult r = solveTrifocal(m, s.rig, PointQuads(pts.begin(), pts.begin() + n), LineQuads());
      EXPECT_FALSE(r.ok) << toString(m) << " n=" << n;
      EXPECT_TRUE(r.solutions.empty());
    }
  }
}

TEST(TrifocalDegenerate, ZeroBaselineAndBadInputRejected)
{
  std::mt19937 rng(9);
  TrifocalScene s = makeTrifocalScene(rng, 5, 2, TrifocalSceneOptions());
  StereoRig flat = s.rig;
  flat.t0.setZero();
  const double nan = std::numeric_limits<double>::quiet_NaN();
  PointQuads bad = s.points;
  bad[1].x[2].x() = nan;
  LineQuads short_line = s.lines;
  short_line[0].q[3] = short_line[0].p[3];
  LineQuads inf_line = s.lines;
  inf_line[1].p[0].y() = std::numeric_limits<double>::infinity();
  StereoRig skew = s.rig;
  skew.R0 *= 2.0;
  for (TrifocalMethod m : {TrifocalMethod::Linear, TrifocalMethod::Subspace, TrifocalMethod::Quaternion})
  {
    EXPECT_FALSE(solveTrifocal(m, flat, s.points, s.lines).ok) << toString(m);
    EXPECT_FALSE(solveTrifocal(m, s.rig, bad, s.lines).ok) << toString(m);
    EXPECT_FALSE(solveTrifocal(m, s.rig, s.points, short_line).ok) << toString(m);
    EXPECT_FALSE(solveTrifocal(m, s.rig, s.points, inf_line).ok) << toString(m);
    EXPECT_FALSE(solveTrifocal(m, skew, s.points, s.lines).ok) << toString(m);
  }
}

TEST(TrifocalDegenerate, RepeatedPointRejected)
{
  std::mt19937 rng(10);
  const TrifocalScene s = makeTrifocalScene(rng, 3, 0, TrifocalSceneOptions());
  PointQuads pts = s.points;
  pts[2] = pts[1];  // two of three points the same: rank 6
  for (TrifocalMethod m : {TrifocalMethod::Subspace, TrifocalMethod::Quaternion})
    EXPECT_FALSE(solveTrifocal(m, s.rig, pts, LineQuads()).ok) << toString(m);
}

TEST(TrifocalNoise, FiniteUnderNoiseAndRandomSets)
{
  // Never a NaN: noisy, far and near sets, every method and mix.
  std::mt19937 rng(11);
  TrifocalSceneOptions o;
  o.noise_px = 2.0;
  int solved = 0;
  for (int i = 0; i < 200; ++i)
  {
    const TrifocalScene s = makeTrifocalScene(rng, 5, 5, o);
    const int np = i % 4, nl = 3 - np + (i % 3 == 0 ? 1 : 0);
    for (TrifocalMethod m : {TrifocalMethod::Linear, TrifocalMethod::Subspace, TrifocalMethod::Quaternion})
    {
      const TrifocalResult r = solveTrifocal(m, s.rig, firstPoints(s, np), firstLines(s, nl));
      for (const StereoMotion& mo : r.solutions)
        ASSERT_TRUE(mo.R.allFinite() && mo.t.allFinite());
      solved += r.ok ? 1 : 0;
    }
  }
  EXPECT_GT(solved, 400);
}

TEST(TrifocalReprojection, ZeroForTruthPositiveForWrongMotion)
{
  std::mt19937 rng(12);
  TrifocalSceneOptions o;
  o.random_rig = true;
  const TrifocalScene s = makeTrifocalScene(rng, 4, 4, o);
  StereoMotion wrong = s.motion;
  wrong.t.x() += 0.02;
  for (const PointQuad& p : s.points)
  {
    EXPECT_LT(pointReprojectionError(s.rig, s.motion, p, 500.0), 1e-8);
    EXPECT_GT(pointReprojectionError(s.rig, wrong, p, 500.0), 0.1);
  }
  for (const LineQuad& l : s.lines)
  {
    EXPECT_LT(lineReprojectionError(s.rig, s.motion, l, 500.0), 1e-8);
    EXPECT_GT(lineReprojectionError(s.rig, wrong, l, 500.0), 1e-3);
  }
}
