#include "assistive_vo/trifocal_solver.h"

#include <algorithm>
#include <array>
#include <complex>
#include <cmath>
#include <Eigen/Dense>
#include <unsupported/Eigen/Polynomials>

namespace assistive_vo
{
namespace
{
constexpr double RANK_TOL = 1e-9;   // relative singular value below which a block is rank deficient
constexpr double NEAR_REAL = 0.05;  // |imag| / |root| up to which a root of the quintic counts as real
// a^2 <= 1 for a unit quaternion, but noise pushes the root of a small rotation (a near 1) past
// 1: roots up to this are kept, the quaternion normalised afterwards
constexpr double ALPHA_MAX = 4.0;

Eigen::Vector3d hom(const Eigen::Vector2d& x) { return Eigen::Vector3d(x.x(), x.y(), 1.0); }

Eigen::Matrix3d skew(const Eigen::Vector3d& v)
{
  Eigen::Matrix3d S;
  S << 0, -v.z(), v.y(), v.z(), 0, -v.x(), -v.y(), v.x(), 0;
  return S;
}

/// Homogeneous line through two points, scaled so that l^T x is the distance of x (normalised
/// units); zero when the points coincide.
Eigen::Vector3d lineThrough(const Eigen::Vector2d& p, const Eigen::Vector2d& q)
{
  Eigen::Vector3d l = hom(p).cross(hom(q));
  const double n = l.head<2>().norm();
  return n > 1e-12 ? Eigen::Vector3d(l / n) : Eigen::Vector3d::Zero();
}

bool finite2(const Eigen::Vector2d& v) { return std::isfinite(v.x()) && std::isfinite(v.y()); }

/// Input checks shared by the solvers; "" when fine.
std::string validate(const StereoRig& rig, const PointQuads& points, const LineQuads& lines)
{
  if (!rig.R0.allFinite() || !rig.t0.allFinite())
    return "rig not finite";
  if (rig.t0.norm() < 1e-6)
    return "zero baseline: the stereo pair cannot fix the scale";
  if ((rig.R0.transpose() * rig.R0 - Eigen::Matrix3d::Identity()).norm() > 1e-6)
    return "R0 is not a rotation";
  for (const PointQuad& p : points)
    for (int v = 0; v < 4; ++v)
      if (!finite2(p.x[v]))
        return "point coordinates not finite";
  for (const LineQuad& l : lines)
    for (int v = 0; v < 4; ++v)
    {
      if (!finite2(l.p[v]) || !finite2(l.q[v]))
        return "line coordinates not finite";
      if ((l.p[v] - l.q[v]).norm() < 1e-9)
        return "line segment of zero length";
    }
  return "";
}

/// Residuals of all constraints for a general 3x3 R and t (affine in both).
void residuals(const StereoRig& rig, const PointQuads& points, const LineQuads& lines,
               const Eigen::Matrix3d& R, const Eigen::Vector3d& t, Eigen::VectorXd& r)
{
  // eqs. 2.26, 2.27
  Eigen::Matrix3d TL[3], TR[3];
  const Eigen::Vector3d tR = rig.R0 * t + rig.t0;
  const Eigen::Matrix3d RR = rig.R0 * R;
  for (int i = 0; i < 3; ++i)
  {
    TL[i] = rig.R0.col(i) * t.transpose() - rig.t0 * R.col(i).transpose();
    TR[i] = rig.R0.col(i) * tR.transpose() - rig.t0 * RR.col(i).transpose();
  }
  r.resize(static_cast<Eigen::Index>(18 * points.size() + 4 * lines.size()));
  Eigen::Index k = 0;
  for (const PointQuad& p : points)
  {
    // eq. 2.25: [x2]x (sum_i x1_i T_i) [x3]x = 0
    const Eigen::Vector3d x1 = hom(p.x[0]);
    const Eigen::Matrix3d S2 = skew(hom(p.x[1]));
    const Eigen::Matrix3d ML = x1(0) * TL[0] + x1(1) * TL[1] + x1(2) * TL[2];
    const Eigen::Matrix3d MR = x1(0) * TR[0] + x1(1) * TR[1] + x1(2) * TR[2];
    const Eigen::Matrix3d CL = S2 * ML * skew(hom(p.x[2]));
    const Eigen::Matrix3d CR = S2 * MR * skew(hom(p.x[3]));
    for (int e = 0; e < 9; ++e)
      r(k++) = CL(e / 3, e % 3);
    for (int e = 0; e < 9; ++e)
      r(k++) = CR(e / 3, e % 3);
  }
  for (const LineQuad& l : lines)
  {
    // eq. 2.24 as point-line-line: l2^T (sum_i x1_i T_i) l3 = 0 for two points x1 on l1
    const Eigen::Vector3d l2 = lineThrough(l.p[1], l.q[1]);
    const Eigen::Vector3d l3 = lineThrough(l.p[2], l.q[2]);
    const Eigen::Vector3d l4 = lineThrough(l.p[3], l.q[3]);
    for (const Eigen::Vector2d* e : {&l.p[0], &l.q[0]})
    {
      const Eigen::Vector3d x1 = hom(*e);
      const Eigen::Matrix3d ML = x1(0) * TL[0] + x1(1) * TL[1] + x1(2) * TL[2];
      const Eigen::Matrix3d MR = x1(0) * TR[0] + x1(1) * TR[1] + x1(2) * TR[2];
      r(k++) = l2.dot(ML * l3);
      r(k++) = l2.dot(MR * l4);
    }
  }
}

/// The system with each point's 18 rows reduced to its 3 dominant ones (SVD of the point's block,
/// rows sigma_i v_i^T): exact data gives those 3 only (seed 2.2.2.2); under noise the other 15
/// carry mostly noise (the stereo pair's own epipolar constraint, eq. 2.30, and the tensors'
/// redundant rows) and, weighted like the rest, bias every least-squares step.
Eigen::MatrixXd compressedSystem(const StereoRig& rig, const PointQuads& points, const LineQuads& lines)
{
  const Eigen::MatrixXd full = trifocalSystem(rig, points, lines);
  Eigen::MatrixXd A(static_cast<Eigen::Index>(3 * points.size() + 4 * lines.size()), 13);
  for (size_t i = 0; i < points.size(); ++i)
  {
    const Eigen::MatrixXd B = full.middleRows(static_cast<Eigen::Index>(18 * i), 18);
    const Eigen::JacobiSVD<Eigen::MatrixXd> svd(B, Eigen::ComputeThinV);
    for (int k = 0; k < 3; ++k)
      A.row(static_cast<Eigen::Index>(3 * i + k)) = svd.singularValues()(k) * svd.matrixV().col(k).transpose();
  }
  A.bottomRows(static_cast<Eigen::Index>(4 * lines.size())) =
      full.bottomRows(static_cast<Eigen::Index>(4 * lines.size()));
  return A;
}

bool finiteMotion(const StereoMotion& m) { return m.R.allFinite() && m.t.allFinite(); }

/// Common checks + the system; empty reason when usable. `min_rows`: independent rows required.
std::string prepare(const StereoRig& rig, const PointQuads& points, const LineQuads& lines, int min_rows,
                    Eigen::MatrixXd& A)
{
  std::string why = validate(rig, points, lines);
  if (!why.empty())
    return why;
  const int rows = constraintRank(points.size(), lines.size());
  if (rows < min_rows)
    return "too few constraints: " + std::to_string(rows) + " independent rows, need " + std::to_string(min_rows) +
           (points.empty() && lines.size() == 2 ? " ({2 lines} is refused: unstable)" : "");
  A = compressedSystem(rig, points, lines);
  // The set must give as many independent rows as its kind promises (collinear points, lines
  // through the baseline, repeated features... give fewer).
  const Eigen::JacobiSVD<Eigen::MatrixXd> svd(A.leftCols(12));
  const Eigen::VectorXd& s = svd.singularValues();
  const int expect = rows;
  if (!(s(0) > 0) || s(expect - 1) < RANK_TOL * s(0))
    return "degenerate set: the constraints are rank deficient";
  return "";
}

// ------------------------------------------------------------------ tiny polynomials in a
using Poly = std::vector<double>;  // ascending coefficients

Poly padd(const Poly& x, const Poly& y, double sy = 1.0)
{
  Poly r(std::max(x.size(), y.size()), 0.0);
  for (size_t i = 0; i < x.size(); ++i)
    r[i] += x[i];
  for (size_t i = 0; i < y.size(); ++i)
    r[i] += sy * y[i];
  return r;
}
Poly pmul(const Poly& x, const Poly& y)
{
  if (x.empty() || y.empty())
    return {};
  Poly r(x.size() + y.size() - 1, 0.0);
  for (size_t i = 0; i < x.size(); ++i)
    for (size_t j = 0; j < y.size(); ++j)
      r[i + j] += x[i] * y[j];
  return r;
}
double peval(const Poly& p, double a)
{
  double v = 0;
  for (size_t i = p.size(); i-- > 0;)
    v = v * a + p[i];
  return v;
}
using PolyRow = std::array<Poly, 4>;  // coefficients of (b, c, d, 1)

/// det of a 4x4 matrix of polynomials (Laplace expansion).
Poly pdet4(const std::array<PolyRow, 4>& M)
{
  auto det3 = [&](int r0, int r1, int r2, int c0, int c1, int c2) {
    Poly d = pmul(M[r0][c0], padd(pmul(M[r1][c1], M[r2][c2]), pmul(M[r1][c2], M[r2][c1]), -1.0));
    d = padd(d, pmul(M[r0][c1], padd(pmul(M[r1][c0], M[r2][c2]), pmul(M[r1][c2], M[r2][c0]), -1.0)), -1.0);
    d = padd(d, pmul(M[r0][c2], padd(pmul(M[r1][c0], M[r2][c1]), pmul(M[r1][c1], M[r2][c0]), -1.0)));
    return d;
  };
  Poly d;
  const int cols[4][3] = {{1, 2, 3}, {0, 2, 3}, {0, 1, 3}, {0, 1, 2}};
  for (int c = 0; c < 4; ++c)
    d = padd(d, pmul(M[0][c], det3(1, 2, 3, cols[c][0], cols[c][1], cols[c][2])), (c % 2) ? -1.0 : 1.0);
  return d;
}
}  // namespace

int constraintRank(size_t points, size_t lines)
{
  static const int table[4][4] = {{0, 4, 8, 12}, {3, 7, 10, 12}, {6, 10, 12, 12}, {9, 11, 12, 12}};
  if (points >= 4 || lines >= 3)
    return 12;
  return table[points][lines];
}

const char* toString(TrifocalMethod m)
{
  switch (m)
  {
    case TrifocalMethod::Linear:
      return "linear";
    case TrifocalMethod::Subspace:
      return "subspace";
    case TrifocalMethod::Quaternion:
      return "quaternion";
  }
  return "?";
}

Eigen::MatrixXd trifocalSystem(const StereoRig& rig, const PointQuads& points, const LineQuads& lines)
{
  // The residuals are affine in (R, t): column k = r(e_k) - r(0), the last column r(0).
  Eigen::VectorXd r0, rk;
  residuals(rig, points, lines, Eigen::Matrix3d::Zero(), Eigen::Vector3d::Zero(), r0);
  Eigen::MatrixXd A(r0.size(), 13);
  for (int k = 0; k < 12; ++k)
  {
    Eigen::Matrix3d R = Eigen::Matrix3d::Zero();
    Eigen::Vector3d t = Eigen::Vector3d::Zero();
    if (k < 9)
      R(k / 3, k % 3) = 1.0;
    else
      t(k - 9) = 1.0;
    residuals(rig, points, lines, R, t, rk);
    A.col(k) = rk - r0;
  }
  A.col(12) = r0;
  return A;
}

Eigen::Matrix3d nearestRotation(const Eigen::Matrix3d& M)
{
  const Eigen::JacobiSVD<Eigen::Matrix3d> svd(M, Eigen::ComputeFullU | Eigen::ComputeFullV);
  Eigen::Matrix3d D = Eigen::Matrix3d::Identity();
  D(2, 2) = (svd.matrixU() * svd.matrixV().transpose()).determinant() < 0 ? -1.0 : 1.0;
  return svd.matrixU() * D * svd.matrixV().transpose();
}

namespace
{
/// The motion of a solved 12-vector y = [R row-major (9), t (3)]: the nearest rotation to R (noise
/// leaves it non-orthonormal, seed 2.2.2.2), one finite solution or the reason there is none.
TrifocalResult resultFromVector(const Eigen::VectorXd& y, const char* degenerate_reason)
{
  TrifocalResult res;
  StereoMotion m;
  for (int k = 0; k < 9; ++k)
    m.R(k / 3, k % 3) = y(k);
  m.t = y.segment<3>(9);
  if (!m.R.allFinite() || m.R.norm() < 1e-12)
  {
    res.reason = degenerate_reason;
    return res;
  }
  m.R = nearestRotation(m.R);
  if (finiteMotion(m))
    res.solutions.push_back(m);
  res.ok = !res.solutions.empty();
  if (!res.ok)
    res.reason = "no finite solution";
  return res;
}
}  // namespace

TrifocalResult solveTrifocalLinear(const StereoRig& rig, const PointQuads& points, const LineQuads& lines)
{
  TrifocalResult res;
  Eigen::MatrixXd A;
  res.reason = prepare(rig, points, lines, 12, A);
  if (!res.reason.empty())
    return res;
  // eq. 2.28: A(:, 1:12) y = -A(:, 13), least squares
  const Eigen::VectorXd y =
      A.leftCols(12).jacobiSvd(Eigen::ComputeThinU | Eigen::ComputeThinV).solve(-A.col(12));
  return resultFromVector(y, "linear solution degenerate");
}

namespace
{
/// The rotation of the subspace solver: entries affine in lambda, R_e = yp(e) + N(e, :) lambda,
/// and polynomials of them over the monomials [lambda_i lambda_j (i <= j), lambda_i, 1].
class AffineRotation
{
public:
  AffineRotation(const Eigen::VectorXd& yp, const Eigen::MatrixXd& N)
    : yp_(yp), N_(N), k_(static_cast<int>(N.cols())), nq_(k_ * (k_ + 1) / 2), M_(nq_ + k_ + 1)
  {
  }
  int monomials() const { return M_; }
  int quadratic() const { return nq_; }  ///< the first monomials: lambda_i lambda_j

  /// The rotation's polynomial constraints (R R^T = I, R^T R = I, rows and columns cross
  /// products: quadratic in lambda), one row each over the monomials.
  Eigen::MatrixXd constraints() const
  {
    std::vector<Eigen::VectorXd> C;
    for (int a = 0; a < 3; ++a)
      for (int b = a; b < 3; ++b)
      {
        Eigen::VectorXd rowc = Eigen::VectorXd::Zero(M_), colc = Eigen::VectorXd::Zero(M_);
        for (int e = 0; e < 3; ++e)
        {
          rowc += product(entry(a, e), entry(b, e));
          colc += product(entry(e, a), entry(e, b));
        }
        if (a == b)
        {
          rowc(M_ - 1) -= 1.0;
          colc(M_ - 1) -= 1.0;
        }
        C.push_back(rowc);
        C.push_back(colc);
      }
    for (int i = 0; i < 3; ++i)  // r_i x r_{i+1} = r_{i+2}, same for columns
    {
      const int j = (i + 1) % 3, l = (i + 2) % 3;
      for (int e = 0; e < 3; ++e)
      {
        const int e1 = (e + 1) % 3, e2 = (e + 2) % 3;
        const Eigen::VectorXd rc = product(entry(i, e1), entry(j, e2)) - product(entry(i, e2), entry(j, e1));
        C.push_back(rc - linear(l, e));
        Eigen::VectorXd cc = product(entry(e1, i), entry(e2, j)) - product(entry(e2, i), entry(e1, j));
        C.push_back(cc - linear(e, l));
      }
    }
    Eigen::MatrixXd B(static_cast<Eigen::Index>(C.size()), M_);
    for (size_t i = 0; i < C.size(); ++i)
      B.row(static_cast<Eigen::Index>(i)) = C[i].transpose();
    return B;
  }

  /// Gauss-Newton on the constraints B (residual B [mono(lambda); 1]) from `lambda`.
  void polish(const Eigen::MatrixXd& B, Eigen::VectorXd& lambda) const
  {
    for (int it = 0; it < 8 && lambda.allFinite(); ++it)
    {
      Eigen::MatrixXd dm = Eigen::MatrixXd::Zero(M_, k_);
      for (int i = 0; i < k_; ++i)
      {
        for (int j = i; j < k_; ++j)
        {
          dm(quadIndex(i, j), i) += lambda(j);
          dm(quadIndex(i, j), j) += lambda(i);
        }
        dm(nq_ + i, i) = 1.0;
      }
      const Eigen::VectorXd rres = B * mono(lambda);
      const Eigen::MatrixXd J = B * dm;
      const Eigen::VectorXd step = J.jacobiSvd(Eigen::ComputeThinU | Eigen::ComputeThinV).solve(-rres);
      if (!step.allFinite())
        break;
      lambda += step;
      if (step.norm() < 1e-15 * (1.0 + lambda.norm()))
        break;
    }
  }

private:
  int quadIndex(int i, int j) const
  {
    if (i > j)
      std::swap(i, j);
    return i * k_ - i * (i - 1) / 2 + (j - i);
  }
  /// Affine form of R(rr, cc): [const, coeffs].
  Eigen::VectorXd entry(int rr, int cc) const
  {
    Eigen::VectorXd f(k_ + 1);
    f(0) = yp_(3 * rr + cc);
    f.tail(k_) = N_.row(3 * rr + cc).transpose();
    return f;
  }
  /// R(rr, cc) over the monomials.
  Eigen::VectorXd linear(int rr, int cc) const
  {
    const Eigen::VectorXd f = entry(rr, cc);
    Eigen::VectorXd lin = Eigen::VectorXd::Zero(M_);
    lin(M_ - 1) = f(0);
    for (int q = 0; q < k_; ++q)
      lin(nq_ + q) = f(1 + q);
    return lin;
  }
  /// The product of two affine forms over the monomials.
  Eigen::VectorXd product(const Eigen::VectorXd& f, const Eigen::VectorXd& g) const
  {
    Eigen::VectorXd p = Eigen::VectorXd::Zero(M_);
    p(M_ - 1) += f(0) * g(0);
    for (int i = 0; i < k_; ++i)
    {
      p(nq_ + i) += f(0) * g(1 + i) + g(0) * f(1 + i);
      for (int j = 0; j < k_; ++j)
        p(quadIndex(i, j)) += f(1 + i) * g(1 + j);
    }
    return p;
  }
  /// The monomials at lambda.
  Eigen::VectorXd mono(const Eigen::VectorXd& l) const
  {
    Eigen::VectorXd m(M_);
    for (int i = 0; i < k_; ++i)
      for (int j = i; j < k_; ++j)
        m(quadIndex(i, j)) = l(i) * l(j);
    m.segment(nq_, k_) = l;
    m(M_ - 1) = 1.0;
    return m;
  }

  const Eigen::VectorXd& yp_;
  const Eigen::MatrixXd& N_;
  const int k_, nq_, M_;
};
}  // namespace

TrifocalResult solveTrifocalSubspace(const StereoRig& rig, const PointQuads& points, const LineQuads& lines)
{
  TrifocalResult res;
  Eigen::MatrixXd A;
  res.reason = prepare(rig, points, lines, 9, A);
  if (!res.reason.empty())
    return res;
  const int rows = constraintRank(points.size(), lines.size());
  const int k = std::max(0, 12 - rows);  // null-space dimension (eq. 2.31: 3 for {3 points})
  if (k == 0)
    return solveTrifocalLinear(rig, points, lines);
  // full V: the null vectors are needed even when A has fewer than 12 rows
  const Eigen::JacobiSVD<Eigen::MatrixXd> svd(A.leftCols(12), Eigen::ComputeThinU | Eigen::ComputeFullV);
  const Eigen::VectorXd& s = svd.singularValues();
  const int r = 12 - k;
  // particular solution from the rank-r pseudo-inverse, null vectors: the k smallest singular vectors
  Eigen::VectorXd yp = Eigen::VectorXd::Zero(12);
  for (int i = 0; i < r; ++i)
    yp += (svd.matrixU().col(i).dot(-A.col(12)) / s(i)) * svd.matrixV().col(i);
  const Eigen::MatrixXd N = svd.matrixV().rightCols(k);

  // The rotation's polynomial constraints linearised over the monomials, solved by least squares,
  // then polished by Gauss-Newton on the same constraints (a closed-form alternative to the
  // seed's Groebner basis / polynomial eigenvalue problem).
  const AffineRotation rot(yp, N);
  const Eigen::MatrixXd B = rot.constraints();
  const int M = rot.monomials();
  const Eigen::VectorXd z =
      B.leftCols(M - 1).jacobiSvd(Eigen::ComputeThinU | Eigen::ComputeThinV).solve(-B.col(M - 1));
  Eigen::VectorXd lambda = z.segment(rot.quadratic(), k);
  rot.polish(B, lambda);
  return resultFromVector(yp + N * lambda, "subspace solution degenerate");
}

namespace
{
/// eq. 2.32: R (row-major) from the quaternion (a, b, c, d) over the monomials
/// m = [a2 b2 c2 d2 ab ac ad bc bd cd].
Eigen::Matrix<double, 9, 10> rotationOfMonomials()
{
  Eigen::Matrix<double, 9, 10> Q = Eigen::Matrix<double, 9, 10>::Zero();
  Q.row(0) << 1, 1, -1, -1, 0, 0, 0, 0, 0, 0;  // R00 = a2+b2-c2-d2
  Q.row(1) << 0, 0, 0, 0, 0, 0, -2, 2, 0, 0;   // R01 = 2(bc-ad)
  Q.row(2) << 0, 0, 0, 0, 0, 2, 0, 0, 2, 0;    // R02 = 2(ac+bd)
  Q.row(3) << 0, 0, 0, 0, 0, 0, 2, 2, 0, 0;    // R10 = 2(ad+bc)
  Q.row(4) << 1, -1, 1, -1, 0, 0, 0, 0, 0, 0;  // R11 = a2-b2+c2-d2
  Q.row(5) << 0, 0, 0, 0, -2, 0, 0, 0, 0, 2;   // R12 = 2(cd-ab)
  Q.row(6) << 0, 0, 0, 0, 0, -2, 0, 0, 2, 0;   // R20 = 2(bd-ac)
  Q.row(7) << 0, 0, 0, 0, 2, 0, 0, 0, 0, 2;    // R21 = 2(ab+cd)
  Q.row(8) << 1, -1, -1, 1, 0, 0, 0, 0, 0, 0;  // R22 = a2-b2-c2+d2
  return Q;
}

/// Eliminates the translation (eqs. 2.33-2.35: t = -Ct [m; 1]) and solves the six monomials of
/// (b, c, d) for the others (eqs. 2.36-2.37: [b2 c2 d2 bc bd cd] = Cq [a2 ab ac ad 1]); the reason
/// when the set is degenerate, else "".
std::string eliminate(const Eigen::MatrixXd& A, const Eigen::Matrix<double, 9, 10>& Q, Eigen::MatrixXd& Ct,
                      Eigen::MatrixXd& Cq)
{
  const Eigen::Index nr = A.rows();
  Eigen::MatrixXd Arest(nr, 11);  // [m (10), 1]
  Arest.leftCols(10) = A.leftCols(9) * Q;
  Arest.col(10) = A.col(12);
  const Eigen::MatrixXd At3 = A.middleCols(9, 3);
  const Eigen::JacobiSVD<Eigen::MatrixXd> svdT(At3, Eigen::ComputeThinU | Eigen::ComputeThinV);
  if (svdT.singularValues()(2) < RANK_TOL * svdT.singularValues()(0))
    return "degenerate set: translation not observable";
  Ct = svdT.solve(Arest);
  Eigen::MatrixXd At(nr + 1, 11);
  At.topRows(nr) = Arest - At3 * Ct;
  // the unit norm a2+b2+c2+d2 = 1, weighted like the data rows
  const double w = std::max(At.topRows(nr).norm() / std::sqrt(static_cast<double>(nr)), 1e-300);
  At.row(nr).setZero();
  At.row(nr).head<4>().setConstant(w);
  At(nr, 10) = -w;
  const int c6[6] = {1, 2, 3, 7, 8, 9}, c5[5] = {0, 4, 5, 6, 10};
  Eigen::MatrixXd A6(nr + 1, 6), A5(nr + 1, 5);
  for (int i = 0; i < 6; ++i)
    A6.col(i) = At.col(c6[i]);
  for (int i = 0; i < 5; ++i)
    A5.col(i) = At.col(c5[i]);
  const Eigen::JacobiSVD<Eigen::MatrixXd> svd6(A6, Eigen::ComputeThinU | Eigen::ComputeThinV);
  if (svd6.singularValues()(5) < RANK_TOL * svd6.singularValues()(0))
    return "degenerate set: the rotation's monomials are rank deficient";
  Cq = -svd6.solve(A5);  // 6 x 5
  return "";
}

/// eqs. 2.38-2.39: the six monomials of Cq as rows over (b, c, d, 1) with entries polynomial in
/// a, then the six consistency conditions between them ((bc)^2 = b2 c2, ...), rows of the same kind.
std::array<PolyRow, 6> consistencyRows(const Eigen::MatrixXd& Cq)
{
  std::array<PolyRow, 6> L;
  for (int i = 0; i < 6; ++i)
  {
    L[i][0] = {0.0, Cq(i, 1)};
    L[i][1] = {0.0, Cq(i, 2)};
    L[i][2] = {0.0, Cq(i, 3)};
    L[i][3] = {Cq(i, 4), 0.0, Cq(i, 0)};
  }
  // product of two rows, quadratic monomials of (b, c, d) substituted back by their rows
  const int quad[3][3] = {{0, 3, 4}, {3, 1, 5}, {4, 5, 2}};  // b2 c2 d2 bc bd cd
  auto prodRow = [&](const PolyRow& x, const PolyRow& y) {
    PolyRow out;
    for (int u = 0; u < 4; ++u)
      for (int v = 0; v < 4; ++v)
      {
        const Poly c = pmul(x[u], y[v]);
        if (u < 3 && v < 3)
          for (int e = 0; e < 4; ++e)
            out[e] = padd(out[e], pmul(c, L[quad[u][v]][e]));
        else if (u < 3)
          out[u] = padd(out[u], c);
        else if (v < 3)
          out[v] = padd(out[v], c);
        else
          out[3] = padd(out[3], c);
      }
    return out;
  };
  auto diffRow = [&](int x, int y, int z, int q) {
    const PolyRow p1 = prodRow(L[x], L[y]), p2 = prodRow(L[z], L[q]);
    PolyRow out;
    for (int e = 0; e < 4; ++e)
      out[e] = padd(p1[e], p2[e], -1.0);
    return out;
  };
  // eq. 2.39: (bc)^2 = b2 c2, (bd)^2 = b2 d2, (cd)^2 = c2 d2, bc bd = b2 cd, bc cd = c2 bd, bd cd = d2 bc
  return {diffRow(3, 3, 0, 1), diffRow(4, 4, 0, 2), diffRow(5, 5, 1, 2),
          diffRow(3, 4, 0, 5), diffRow(3, 5, 1, 4), diffRow(4, 5, 2, 3)};
}

Eigen::Matrix<double, 6, 4> evalRows(const std::array<PolyRow, 6>& M6, double a)
{
  Eigen::Matrix<double, 6, 4> E;
  for (int i = 0; i < 6; ++i)
    for (int e = 0; e < 4; ++e)
      E(i, e) = peval(M6[i][e], a);
  return E;
}

/// Any 4x4 minor vanishes at the solution (eq. 2.40); the best conditioned one (rows most
/// independent at a few sample values of a).
std::array<PolyRow, 4> bestMinor(const std::array<PolyRow, 6>& M6)
{
  int best_rows[4] = {0, 1, 2, 3};
  double best_score = -1;
  const double samples[3] = {0.35, 0.7, 0.95};
  for (int r0 = 0; r0 < 6; ++r0)
    for (int r1 = r0 + 1; r1 < 6; ++r1)
      for (int r2 = r1 + 1; r2 < 6; ++r2)
        for (int r3 = r2 + 1; r3 < 6; ++r3)
        {
          double score = 0;
          for (double a : samples)
          {
            const Eigen::Matrix<double, 6, 4> E = evalRows(M6, a);
            Eigen::Matrix4d S;
            S << E.row(r0), E.row(r1), E.row(r2), E.row(r3);
            double norms = 1;
            for (int i = 0; i < 4; ++i)
              norms *= std::max(S.row(i).norm(), 1e-300);
            score += std::abs(S.determinant()) / norms;
          }
          if (score > best_score)
          {
            best_score = score;
            best_rows[0] = r0, best_rows[1] = r1, best_rows[2] = r2, best_rows[3] = r3;
          }
        }
  std::array<PolyRow, 4> S4;
  for (int i = 0; i < 4; ++i)
    S4[i] = M6[best_rows[i]];
  return S4;
}

/// eq. 2.41: the real roots alpha = a^2 of the quintic in the coefficients of a^3, a^5, ..., a^13
/// of the minor's determinant `det`; the reason when it is degenerate, else "".
std::string quinticRoots(Poly det, std::vector<double>& alphas)
{
  det.resize(14, 0.0);
  Eigen::VectorXd k5(6);
  for (int j = 0; j < 6; ++j)
    k5(j) = det[3 + 2 * j];
  const double kmax = k5.cwiseAbs().maxCoeff();
  if (!(kmax > 0) || !std::isfinite(kmax))
    return "degenerate set: the quintic vanishes";
  k5 /= kmax;
  int deg = 5;
  while (deg > 0 && std::abs(k5(deg)) < 1e-12)
    --deg;
  if (deg == 0)
    return "degenerate set: the quintic is constant";
  Eigen::PolynomialSolver<double, Eigen::Dynamic> solver;
  solver.compute(k5.head(deg + 1));
  for (int i = 0; i < solver.roots().size(); ++i)
  {
    const std::complex<double> z = solver.roots()(i);
    // Noise splits a double real root into a close complex pair: such near-real roots are kept
    // (their real part), otherwise a noisy minimal set often has no solution at all.
    if (std::abs(z.imag()) <= NEAR_REAL * std::max(0.1, std::abs(z)) && z.real() > -1e-9 && z.real() <= ALPHA_MAX)
      alphas.push_back(std::max(0.0, z.real()));
  }
  return "";
}

/// The motion at a = sqrt(alpha): (b, c, d, 1) the null vector of all six rows at a; false when
/// there is none.
bool motionAt(double alpha, const std::array<PolyRow, 6>& M6, const Eigen::Matrix<double, 9, 10>& Q,
              const Eigen::MatrixXd& Ct, StereoMotion& m)
{
  const double a = std::sqrt(alpha);
  // dynamic size on purpose: the file already instantiates JacobiSVD<MatrixXd>, and a fixed-size
  // 6x4 (and 4x4 below) SVD would instantiate it twice more at about a quarter of its compile time
  const Eigen::JacobiSVD<Eigen::MatrixXd> svd(evalRows(M6, a), Eigen::ComputeFullV);
  const Eigen::Vector4d v = svd.matrixV().col(3);
  if (std::abs(v(3)) < 1e-12)
    return false;
  Eigen::Vector4d q(a, v(0) / v(3), v(1) / v(3), v(2) / v(3));
  if (!q.allFinite() || q.norm() < 1e-12)
    return false;
  q.normalize();
  const double qa = q(0), qb = q(1), qc = q(2), qd = q(3);
  Eigen::Matrix<double, 11, 1> yt;
  yt << qa * qa, qb * qb, qc * qc, qd * qd, qa * qb, qa * qc, qa * qd, qb * qc, qb * qd, qc * qd, 1.0;
  const Eigen::Matrix<double, 9, 1> rv = Q * yt.head<10>();
  for (int e = 0; e < 9; ++e)
    m.R(e / 3, e % 3) = rv(e);
  m.t = -Ct * yt;
  return finiteMotion(m);
}
}  // namespace

TrifocalResult solveTrifocalQuaternion(const StereoRig& rig, const PointQuads& points, const LineQuads& lines)
{
  TrifocalResult res;
  Eigen::MatrixXd A;
  res.reason = prepare(rig, points, lines, 9, A);
  if (!res.reason.empty())
    return res;
  const Eigen::Matrix<double, 9, 10> Q = rotationOfMonomials();
  Eigen::MatrixXd Ct, Cq;
  res.reason = eliminate(A, Q, Ct, Cq);
  if (!res.reason.empty())
    return res;
  const std::array<PolyRow, 6> M6 = consistencyRows(Cq);
  std::vector<double> alphas;
  res.reason = quinticRoots(pdet4(bestMinor(M6)), alphas);  // det: degree 13, a^3 (k1 a^10 + ... + k6), eq. 2.40
  if (!res.reason.empty())
    return res;
  for (double alpha : alphas)
  {
    StereoMotion m;
    if (!motionAt(alpha, M6, Q, Ct, m))
      continue;
    bool dup = false;
    for (const StereoMotion& o : res.solutions)
      dup = dup || ((o.R - m.R).norm() < 1e-9 && (o.t - m.t).norm() < 1e-9);
    if (!dup)
      res.solutions.push_back(m);
  }
  res.ok = !res.solutions.empty();
  if (!res.ok)
    res.reason = "no real solution";
  else
    res.reason.clear();
  return res;
}

TrifocalResult solveTrifocal(TrifocalMethod m, const StereoRig& rig, const PointQuads& points,
                             const LineQuads& lines)
{
  switch (m)
  {
    case TrifocalMethod::Linear:
      return solveTrifocalLinear(rig, points, lines);
    case TrifocalMethod::Subspace:
      return solveTrifocalSubspace(rig, points, lines);
    case TrifocalMethod::Quaternion:
      return solveTrifocalQuaternion(rig, points, lines);
  }
  return {};
}

namespace
{
constexpr double HUGE_ERR = 1e9;

/// Cameras of the four views as 3x4 matrices.
void cameras(const StereoRig& rig, const StereoMotion& m, Eigen::Matrix<double, 3, 4> P[4])
{
  P[0] << Eigen::Matrix3d::Identity(), Eigen::Vector3d::Zero();
  P[1] << rig.R0, rig.t0;
  P[2] << m.R, m.t;
  P[3] << rig.R0 * m.R, rig.R0 * m.t + rig.t0;
}

bool project(const Eigen::Matrix<double, 3, 4>& P, const Eigen::Vector3d& X, Eigen::Vector2d& x)
{
  const Eigen::Vector3d h = P.leftCols<3>() * X + P.col(3);
  if (!(h.z() > 1e-9))
    return false;
  x = h.head<2>() / h.z();
  return true;
}
}  // namespace

double pointReprojectionError(const StereoRig& rig, const StereoMotion& m, const PointQuad& pt, double focal)
{
  Eigen::Matrix<double, 3, 4> P[4];
  cameras(rig, m, P);
  // DLT from views 1 and 2
  Eigen::Matrix4d D;
  for (int v = 0; v < 2; ++v)
  {
    D.row(2 * v) = pt.x[v].x() * P[v].row(2) - P[v].row(0);
    D.row(2 * v + 1) = pt.x[v].y() * P[v].row(2) - P[v].row(1);
  }
  const Eigen::JacobiSVD<Eigen::MatrixXd> svd(D, Eigen::ComputeFullV);
  const Eigen::Vector4d Xh = svd.matrixV().col(3);
  if (std::abs(Xh(3)) < 1e-12)
    return HUGE_ERR;
  const Eigen::Vector3d X = Xh.head<3>() / Xh(3);
  double sq = 0;
  for (int v = 0; v < 4; ++v)
  {
    Eigen::Vector2d x;
    if (!project(P[v], X, x))
      return HUGE_ERR;
    sq += (x - pt.x[v]).squaredNorm();
  }
  const double e = focal * std::sqrt(sq / 4.0);
  return std::isfinite(e) ? e : HUGE_ERR;
}

double lineReprojectionError(const StereoRig& rig, const StereoMotion& m, const LineQuad& ln, double focal)
{
  Eigen::Matrix<double, 3, 4> P[4];
  cameras(rig, m, P);
  // the plane of view 2's line; the rays of view 1's segment ends meet it on the 3D line
  const Eigen::Vector3d l2 = lineThrough(ln.p[1], ln.q[1]);
  const Eigen::Vector4d pi2 = P[1].transpose() * l2;
  Eigen::Vector3d X[2];
  int k = 0;
  for (const Eigen::Vector2d* e : {&ln.p[0], &ln.q[0]})
  {
    const Eigen::Vector3d ray = hom(*e);  // X = s ray (camera 1 at the origin)
    const double den = pi2.head<3>().dot(ray);
    if (std::abs(den) < 1e-12)
      return HUGE_ERR;  // the ray lies in the plane: the line passes through the baseline
    const double s = -pi2(3) / den;
    if (!(s > 1e-9) || !std::isfinite(s))
      return HUGE_ERR;
    X[k++] = s * ray;
  }
  double sq = 0;
  for (int v = 2; v < 4; ++v)
  {
    Eigen::Vector2d a, b;
    if (!project(P[v], X[0], a) || !project(P[v], X[1], b))
      return HUGE_ERR;
    const Eigen::Vector3d l = lineThrough(a, b);
    if (l.isZero())
      return HUGE_ERR;
    sq += std::pow(l.dot(hom(ln.p[v])), 2) + std::pow(l.dot(hom(ln.q[v])), 2);
  }
  const double e = focal * std::sqrt(sq / 4.0);
  return std::isfinite(e) ? e : HUGE_ERR;
}

}  // namespace assistive_vo
