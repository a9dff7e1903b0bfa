#include "assistive_vo/bundle_adjustment.h"
#include <cmath>
#include <Eigen/Cholesky>

namespace assistive_vo
{
namespace
{
using Mat23 = Eigen::Matrix<double, 2, 3>;
using Mat63 = Eigen::Matrix<double, 6, 3>;
using Mat66 = Eigen::Matrix<double, 6, 6>;
using Vec6 = Eigen::Matrix<double, 6, 1>;

inline double huberWeight(double r2, double k)
{
  const double r = std::sqrt(r2);
  return r <= k ? 1.0 : k / r;
}
inline double huberCost(double r2, double k)
{
  const double r = std::sqrt(r2);
  return r <= k ? r2 : 2.0 * k * r - k * k;
}

Eigen::Matrix3d skew(const Eigen::Vector3d& v)
{
  Eigen::Matrix3d m;
  m << 0, -v.z(), v.y(), v.z(), 0, -v.x(), -v.y(), v.x(), 0;
  return m;
}

Eigen::Matrix3d expSO3(const Eigen::Vector3d& w)
{
  const double th = w.norm();
  if (th < 1e-12)
    return Eigen::Matrix3d::Identity() + skew(w);
  return Eigen::AngleAxisd(th, w / th).toRotationMatrix();
}

/// Adds the residual/Jacobian of one stereo observation of point p (camera frame) to the blocks.
/// Jp: d(pred)/d(p_cam). Returns the robust cost.
struct StereoResidual
{
  double r[3];
  double J[3][3];  // rows: uL, vL, uR ; cols: d/dp
  int rows;
};

inline bool evalObs(const StereoCamera& cam, const Eigen::Vector3d& p, const StereoObservation& o,
                    StereoResidual& out)
{
  if (p.z() < 1e-3)
    return false;
  const double iz = 1.0 / p.z(), iz2 = iz * iz;
  out.r[0] = o.u - (cam.fx * p.x() * iz + cam.cx);
  out.r[1] = o.v - (cam.fy * p.y() * iz + cam.cy);
  out.J[0][0] = cam.fx * iz; out.J[0][1] = 0; out.J[0][2] = -cam.fx * p.x() * iz2;
  out.J[1][0] = 0; out.J[1][1] = cam.fy * iz; out.J[1][2] = -cam.fy * p.y() * iz2;
  out.rows = 2;
  if (o.ur >= 0)
  {
    out.r[2] = o.ur - (cam.fx * (p.x() - cam.baseline) * iz + cam.cx);
    out.J[2][0] = cam.fx * iz; out.J[2][1] = 0; out.J[2][2] = -cam.fx * (p.x() - cam.baseline) * iz2;
    out.rows = 3;
  }
  if (o.sigma_scale != 1.0)
  {
    // whitened: a residual in units of this observation's own pixel sigma
    const double w = 1.0 / o.sigma_scale;
    for (int a = 0; a < out.rows; ++a)
    {
      out.r[a] *= w;
      for (int c = 0; c < 3; ++c)
        out.J[a][c] *= w;
    }
  }
  return true;
}

double squaredResidual(const StereoResidual& s)
{
  return s.r[0] * s.r[0] + s.r[1] * s.r[1] + (s.rows == 3 ? s.r[2] * s.r[2] : 0.0);
}

using Mat3List = std::vector<Eigen::Matrix3d, Eigen::aligned_allocator<Eigen::Matrix3d>>;

/// The Gauss-Newton normal equations of one iteration in Schur blocks: motion (c) and points (p).
struct NormalEquations
{
  explicit NormalEquations(size_t n) : Hpp(n), Hcp(n), gp(n) {}
  Mat66 Hcc = Mat66::Zero();
  Vec6 gc = Vec6::Zero();
  Mat3List Hpp;
  std::vector<Mat63, Eigen::aligned_allocator<Mat63>> Hcp;
  Vec3List gp;
};

/// The state T_cur_ref = (R, t) as T_ref_cur.
Eigen::Isometry3d refFromCur(const Eigen::Matrix3d& Rc, const Eigen::Vector3d& tc)
{
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = Rc.transpose();
  T.translation() = -Rc.transpose() * tc;
  return T;
}

/// Linearises every observation (Huber-weighted) at the state (R, t, points) into `ne`.
void linearize(const StereoCamera& cam, const Eigen::Matrix3d& R, const Eigen::Vector3d& t,
               const Vec3List& points_ref, const std::vector<StereoObservation>& obs_ref,
               const std::vector<StereoObservation>& obs_cur, bool refine_points, double k, NormalEquations& ne)
{
  ne.Hcc.setZero();
  ne.gc = Vec6::Zero();
  StereoResidual s;
  for (size_t i = 0; i < points_ref.size(); ++i)
  {
    ne.Hpp[i].setZero();
    ne.Hcp[i].setZero();
    ne.gp[i].setZero();
    const Eigen::Vector3d& X = points_ref[i];
    if (refine_points && evalObs(cam, X, obs_ref[i], s))
    {
      const double wgt = huberWeight(squaredResidual(s), k);
      for (int a = 0; a < s.rows; ++a)
      {
        const Eigen::Vector3d Ja(s.J[a][0], s.J[a][1], s.J[a][2]);
        ne.Hpp[i] += wgt * Ja * Ja.transpose();
        ne.gp[i] += wgt * Ja * s.r[a];
      }
    }
    const Eigen::Vector3d Xc = R * X + t;
    if (!evalObs(cam, Xc, obs_cur[i], s))
      continue;
    const double wgt = huberWeight(squaredResidual(s), k);
    // d Xc / d(dt, dw) = [I, -[Xc]x] (left perturbation), d Xc / dX = R
    Eigen::Matrix<double, 3, 6> dXc;
    dXc.leftCols<3>().setIdentity();
    dXc.rightCols<3>() = -skew(Xc);
    for (int a = 0; a < s.rows; ++a)
    {
      const Eigen::RowVector3d Ja(s.J[a][0], s.J[a][1], s.J[a][2]);
      const Vec6 Jc = (Ja * dXc).transpose();
      const Eigen::Vector3d Jp = (Ja * R).transpose();
      ne.Hcc += wgt * Jc * Jc.transpose();
      ne.gc += wgt * Jc * s.r[a];
      if (refine_points)
      {
        ne.Hpp[i] += wgt * Jp * Jp.transpose();
        ne.Hcp[i] += wgt * Jc * Jp.transpose();
        ne.gp[i] += wgt * Jp * s.r[a];
      }
    }
  }
}

/// The damped motion step `dc` of the reduced (Schur) system, and the damped point blocks' inverses
/// (for the points' back substitution); false when the step is not finite.
bool solveStep(const NormalEquations& ne, double lambda, bool refine_points, Vec6& dc, Mat3List& Hinv)
{
  const size_t n = ne.Hpp.size();
  Mat66 S = ne.Hcc;
  Vec6 b = ne.gc;
  S.diagonal() *= (1.0 + lambda);
  Hinv.resize(refine_points ? n : 0);  // every block is set below
  if (refine_points)
    for (size_t i = 0; i < n; ++i)
    {
      Eigen::Matrix3d H = ne.Hpp[i];
      H.diagonal() *= (1.0 + lambda);
      H.diagonal().array() += 1e-9;
      Hinv[i] = H.inverse();
      S -= ne.Hcp[i] * Hinv[i] * ne.Hcp[i].transpose();
      b -= ne.Hcp[i] * Hinv[i] * ne.gp[i];
    }
  dc = S.ldlt().solve(b);
  return dc.allFinite();
}

/// Covariance of the motion from the reduced (Schur) information at the solution, scaled by the
/// pixel noise (first-order propagation).
Mat66 motionCovariance(const NormalEquations& ne, bool refine_points, double pixel_sigma_px)
{
  Mat66 info = ne.Hcc;
  if (refine_points)
    for (size_t i = 0; i < ne.Hpp.size(); ++i)
    {
      Eigen::Matrix3d H = ne.Hpp[i];
      H.diagonal().array() += 1e-9;
      info -= ne.Hcp[i] * H.inverse() * ne.Hcp[i].transpose();
    }
  return (info + 1e-9 * Mat66::Identity()).inverse() * pixel_sigma_px * pixel_sigma_px;
}

double obsCost(const StereoResidual& s, double k)
{
  return huberCost(squaredResidual(s), k);
}
}  // namespace

double TwoFrameBundleAdjuster::cost(const StereoCamera& cam, const Eigen::Isometry3d& T_ref_cur,
                                    const Vec3List& points_ref, const std::vector<StereoObservation>& obs_ref,
                                    const std::vector<StereoObservation>& obs_cur, double huber_px)
{
  const Eigen::Isometry3d T_cur_ref = T_ref_cur.inverse();
  double c = 0;
  StereoResidual s;
  for (size_t i = 0; i < points_ref.size(); ++i)
  {
    if (evalObs(cam, points_ref[i], obs_ref[i], s))
      c += obsCost(s, huber_px);
    else
      c += 1e6;
    if (evalObs(cam, T_cur_ref * points_ref[i], obs_cur[i], s))
      c += obsCost(s, huber_px);
    else
      c += 1e6;
  }
  return c;
}

BundleAdjustmentResult TwoFrameBundleAdjuster::optimize(const StereoCamera& cam,
                                                        const Eigen::Isometry3d& T_ref_cur_init,
                                                        Vec3List& points_ref,
                                                        const std::vector<StereoObservation>& obs_ref,
                                                        const std::vector<StereoObservation>& obs_cur,
                                                        const Options& opt) const
{
  BundleAdjustmentResult res;
  const size_t n = points_ref.size();
  if (n < 3 || obs_ref.size() != n || obs_cur.size() != n || !cam.valid())
    return res;
  const double k = opt.huber_px;

  // State: T_cur_ref (R, t), X_i in the reference frame.
  Eigen::Matrix3d R = T_ref_cur_init.linear().transpose();
  Eigen::Vector3d t = -R * T_ref_cur_init.translation();
  // Rotation prior on R_cur_ref (the state's rotation): residual log(Rp_cur_ref * R^T).
  const Eigen::Matrix3d Rp_cur_ref = opt.rotation_prior.transpose();
  const double wp = opt.use_rotation_prior ? std::max(0.0, opt.rotation_prior_weight) : 0.0;
  auto priorResidual = [&](const Eigen::Matrix3d& Rc) {
    const Eigen::AngleAxisd aa(Rp_cur_ref * Rc.transpose());
    return Eigen::Vector3d(aa.angle() * aa.axis());
  };
  auto priorCost = [&](const Eigen::Matrix3d& Rc) { return wp > 0 ? wp * priorResidual(Rc).squaredNorm() : 0.0; };
  double cur_cost = cost(cam, T_ref_cur_init, points_ref, obs_ref, obs_cur, k) + priorCost(R);
  res.initial_cost = cur_cost;
  double lambda = 1e-4;

  NormalEquations ne(n);
  Vec3List new_pts(n);
  Mat3List Hinv;
  int it = 0;
  for (; it < opt.iterations; ++it)
  {
    linearize(cam, R, t, points_ref, obs_ref, obs_cur, opt.refine_points, k, ne);
    if (wp > 0)
    {
      ne.Hcc.bottomRightCorner<3, 3>() += wp * Eigen::Matrix3d::Identity();
      ne.gc.tail<3>() += wp * priorResidual(R);
    }
    // LM inner loop: try the step, raise lambda until the cost drops.
    bool improved = false;
    for (int tries = 0; tries < 6 && !improved; ++tries)
    {
      Vec6 dc;
      if (!solveStep(ne, lambda, opt.refine_points, dc, Hinv))
      {
        lambda *= 10;
        continue;
      }
      const Eigen::Matrix3d dR = expSO3(dc.tail<3>());
      const Eigen::Matrix3d R_new = dR * R;
      const Eigen::Vector3d t_new = dR * t + dc.head<3>();
      if (opt.refine_points)
        for (size_t i = 0; i < n; ++i)
          new_pts[i] = points_ref[i] + Hinv[i] * (ne.gp[i] - ne.Hcp[i].transpose() * dc);
      else
        new_pts = points_ref;
      const double c = cost(cam, refFromCur(R_new, t_new), new_pts, obs_ref, obs_cur, k) + priorCost(R_new);
      if (std::isfinite(c) && c < cur_cost)
      {
        const double rel = (cur_cost - c) / std::max(cur_cost, 1e-12);
        R = R_new;
        t = t_new;
        points_ref.swap(new_pts);
        cur_cost = c;
        lambda = std::max(1e-7, lambda * 0.1);
        improved = true;
        if (rel < 1e-6 || dc.norm() < 1e-9)
          it = opt.iterations;  // converged
      }
      else
        lambda *= 10;
    }
    if (!improved)
      break;
  }
  res.covariance = motionCovariance(ne, opt.refine_points, opt.pixel_sigma_px);
  R = Eigen::Quaterniond(R).normalized().toRotationMatrix();
  res.T_ref_cur = refFromCur(R, t);
  res.final_cost = cur_cost;
  res.iterations = it;
  res.ok = res.T_ref_cur.matrix().allFinite();
  return res;
}
}  // namespace assistive_vo
