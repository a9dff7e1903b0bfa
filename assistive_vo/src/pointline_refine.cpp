#include "assistive_vo/pointline_refine.h"

#include <cmath>
#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>

namespace assistive_vo
{
namespace
{
using Vec6 = Eigen::Matrix<double, 6, 1>;
using Mat6 = Eigen::Matrix<double, 6, 6>;

/// Left perturbation of T_cur_ref: (translation, rotation vector).
Eigen::Isometry3d perturb(const Eigen::Isometry3d& T_cur_ref, const Vec6& d)
{
  Eigen::Isometry3d D = Eigen::Isometry3d::Identity();
  const Eigen::Vector3d w = d.tail<3>();
  if (w.norm() > 0)
    D.linear() = Eigen::AngleAxisd(w.norm(), w.normalized()).toRotationMatrix();
  D.translation() = d.head<3>();
  return D * T_cur_ref;
}

/// Signed distance (px) of x to the image line through a and b.
double lineDistance(const Eigen::Vector2d& a, const Eigen::Vector2d& b, const Eigen::Vector2d& x)
{
  const Eigen::Vector2d d = b - a;
  const double n = d.norm();
  if (!(n > 1e-9))
    return 1e3;
  return (d.x() * (x.y() - a.y()) - d.y() * (x.x() - a.x())) / n;
}

struct Problem
{
  const StereoCamera& cam;
  const Vec3List& X;
  const std::vector<StereoObservation>& obs;
  const StereoLineObservations& lines;
  const PointLineRefineOptions& opt;

  /// All residuals (px) at T_cur_ref; false when a point falls behind the camera.
  bool residuals(const Eigen::Isometry3d& T_cur_ref, Eigen::VectorXd& r) const
  {
    std::vector<double> v;
    v.reserve(3 * X.size() + 4 * lines.size() + 6);
    for (size_t i = 0; i < X.size(); ++i)
    {
      const Eigen::Vector3d Xc = T_cur_ref * X[i];
      if (!(Xc.z() > 1e-3))
        return false;
      const Eigen::Vector2d x = cam.projectLeft(Xc);
      v.push_back(x.x() - obs[i].u);
      v.push_back(x.y() - obs[i].v);
      if (obs[i].ur >= 0)
        v.push_back(cam.projectRightU(Xc) - obs[i].ur);
    }
    for (const StereoLineObservation& l : lines)
    {
      const Eigen::Vector3d P = T_cur_ref * l.P, Q = T_cur_ref * l.Q;
      if (!(P.z() > 1e-3 && Q.z() > 1e-3))
        return false;
      const Eigen::Vector2d pl = cam.projectLeft(P), ql = cam.projectLeft(Q);
      const Eigen::Vector2d pr(cam.projectRightU(P), pl.y()), qr(cam.projectRightU(Q), ql.y());
      v.push_back(lineDistance(pl, ql, l.left_p));
      v.push_back(lineDistance(pl, ql, l.left_q));
      v.push_back(lineDistance(pr, qr, l.right_p));
      v.push_back(lineDistance(pr, qr, l.right_q));
    }
    if (opt.use_rotation_prior && opt.rotation_prior_weight > 0)
    {
      const Eigen::AngleAxisd e(opt.rotation_prior.transpose() * T_cur_ref.linear().transpose());
      const Eigen::Vector3d w = e.angle() * e.axis() * std::sqrt(opt.rotation_prior_weight);
      v.insert(v.end(), {w.x(), w.y(), w.z()});
    }
    if (opt.use_translation_prior && opt.translation_prior_weight > 0)
    {
      const Eigen::Vector3d e =
          (T_cur_ref.inverse().translation() - opt.translation_prior) * std::sqrt(opt.translation_prior_weight);
      v.insert(v.end(), {e.x(), e.y(), e.z()});
    }
    r = Eigen::Map<const Eigen::VectorXd>(v.data(), static_cast<Eigen::Index>(v.size()));
    return r.allFinite();
  }
  /// Huber weights (the prior's rows unweighted).
  Eigen::VectorXd weights(const Eigen::VectorXd& r) const
  {
    Eigen::VectorXd w = Eigen::VectorXd::Ones(r.size());
    const Eigen::Index n_prior = (opt.use_rotation_prior && opt.rotation_prior_weight > 0 ? 3 : 0) +
                                 (opt.use_translation_prior && opt.translation_prior_weight > 0 ? 3 : 0);
    for (Eigen::Index i = 0; i < r.size() - n_prior; ++i)
      if (std::abs(r(i)) > opt.huber_px)
        w(i) = opt.huber_px / std::abs(r(i));
    return w;
  }
  double cost(const Eigen::VectorXd& r) const
  {
    const Eigen::VectorXd w = weights(r);
    double c = 0;
    for (Eigen::Index i = 0; i < r.size(); ++i)
      c += w(i) < 1 ? opt.huber_px * (2 * std::abs(r(i)) - opt.huber_px) : r(i) * r(i);
    return c;
  }
};
}  // namespace

bool triangulateStereoSegment(const StereoCamera& cam, const LineSegment& left, const LineSegment& right,
                              double min_disparity, Eigen::Vector3d& P, Eigen::Vector3d& Q)
{
  const Eigen::Vector2d d = right.q - right.p;
  if (!(std::abs(d.y()) > 1e-6 * std::max(1.0, d.norm())))
    return false;
  const auto at = [&](const Eigen::Vector2d& x, Eigen::Vector3d& X) {
    const double ur = right.p.x() + (x.y() - right.p.y()) * d.x() / d.y();
    const double disp = x.x() - ur;
    if (!(disp >= std::max(min_disparity, 1e-6)))
      return false;
    X = cam.triangulate(x.x(), x.y(), disp);
    return X.allFinite();
  };
  return at(left.p, P) && at(left.q, Q);
}

BundleAdjustmentResult refineMotionPointsLines(const StereoCamera& cam, const Eigen::Isometry3d& T_ref_cur_init,
                                               const Vec3List& points_ref,
                                               const std::vector<StereoObservation>& obs_cur,
                                               const StereoLineObservations& lines,
                                               const PointLineRefineOptions& opt)
{
  BundleAdjustmentResult res;
  res.T_ref_cur = T_ref_cur_init;
  if (points_ref.size() != obs_cur.size() || !T_ref_cur_init.matrix().allFinite())
    return res;
  const Problem pb{cam, points_ref, obs_cur, lines, opt};
  Eigen::Isometry3d T = T_ref_cur_init.inverse();
  Eigen::VectorXd r;
  if (!pb.residuals(T, r))
    return res;
  double c = pb.cost(r);
  res.initial_cost = c;
  double lambda = 1e-4;
  Mat6 H = Mat6::Zero();
  bool have_h = false;
  const double h = 1e-6;
  for (int it = 0; it < opt.iterations; ++it)
  {
    // numeric Jacobian (6 unknowns: seven residual evaluations)
    Eigen::MatrixXd J(r.size(), 6);
    bool good = true;
    for (int k = 0; k < 6 && good; ++k)
    {
      Vec6 d = Vec6::Zero();
      d(k) = h;
      Eigen::VectorXd rk;
      good = pb.residuals(perturb(T, d), rk) && rk.size() == r.size();
      if (good)
        J.col(k) = (rk - r) / h;
    }
    if (!good)
      break;
    const Eigen::VectorXd w = pb.weights(r);
    H = J.transpose() * w.asDiagonal() * J;
    have_h = true;
    const Vec6 g = J.transpose() * (w.asDiagonal() * r);
    bool stepped = false;
    for (int tries = 0; tries < 6 && !stepped; ++tries)
    {
      Mat6 A = H;
      A.diagonal() += lambda * H.diagonal().cwiseMax(1e-9);
      const Vec6 step = -A.ldlt().solve(g);
      if (!step.allFinite())
        break;
      const Eigen::Isometry3d Tn = perturb(T, step);
      Eigen::VectorXd rn;
      if (pb.residuals(Tn, rn) && rn.size() == r.size() && pb.cost(rn) < c)
      {
        T = Tn;
        r = rn;
        c = pb.cost(rn);
        lambda = std::max(1e-7, lambda * 0.3);
        stepped = true;
        if (step.norm() < 1e-9)
          it = opt.iterations;  // converged
      }
      else
        lambda *= 10;
    }
    ++res.iterations;
    if (!stepped)
      break;
  }
  if (!have_h)
    return res;
  // observability: a system that leaves a direction free (e.g. lines all parallel, no point)
  const Eigen::SelfAdjointEigenSolver<Mat6> es(H);
  if (!(es.eigenvalues()(0) > 1e-9 * std::max(1.0, es.eigenvalues()(5))))
    return res;
  res.ok = true;
  res.T_ref_cur = T.inverse();
  res.final_cost = c;
  res.covariance = H.inverse() * opt.pixel_sigma_px * opt.pixel_sigma_px;
  return res;
}
}  // namespace assistive_vo
