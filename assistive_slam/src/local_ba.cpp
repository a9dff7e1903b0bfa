#include "assistive_slam/local_ba.h"
#include <array>
#include <cmath>
#include <ceres/ceres.h>
#include "relative_pose_cost.h"

namespace assistive_slam
{
namespace
{
struct StereoReprojection
{
  StereoReprojection(const StereoModel& c, const Eigen::Vector3d& obs, double inv_sigma)
    : cam(c), z(obs), w(inv_sigma)
  {
  }
  template <typename T>
  bool operator()(const T* p, const T* q_, const T* X_, T* r) const
  {
    const Eigen::Map<const Eigen::Matrix<T, 3, 1>> t(p), X(X_);
    const Eigen::Map<const Eigen::Quaternion<T>> q(q_);
    const Eigen::Matrix<T, 3, 1> Xc = q.conjugate() * (X - t);
    if (Xc.z() < T(1e-3))
    {
      r[0] = r[1] = r[2] = T(1e3 * w);
      return true;
    }
    const T iz = T(1.0) / Xc.z();
    r[0] = (T(cam.fx) * Xc.x() * iz + T(cam.cx) - T(z.x())) * T(w);
    r[1] = (T(cam.fy) * Xc.y() * iz + T(cam.cy) - T(z.y())) * T(w);
    r[2] = (T(cam.fx) * (Xc.x() - T(cam.baseline)) * iz + T(cam.cx) - T(z.z())) * T(w);
    return true;
  }
  StereoModel cam;
  Eigen::Vector3d z;
  double w;
};
}  // namespace

double reprojectionRms(const BaProblem& pb, const StereoModel& cam)
{
  if (pb.observations.empty())
    return 0;
  double s = 0;
  for (const BaObservation& o : pb.observations)
  {
    const Eigen::Vector3d Xc = pb.poses[o.frame].inverse() * pb.landmarks.at(o.landmark);
    if (Xc.z() < 1e-3)
    {
      s += 3e6;
      continue;
    }
    s += (cam.project(Xc) - o.uvr).squaredNorm();
  }
  return std::sqrt(s / (3.0 * pb.observations.size()));
}

BaResult bundleAdjust(BaProblem& pb, const StereoModel& cam, const BaOptions& opt)
{
  BaResult out;
  const size_t n = pb.poses.size();
  if (n == 0 || pb.observations.empty() || !cam.valid())
    return out;
  out.initial_rms_px = reprojectionRms(pb, cam);
  std::vector<std::array<double, 3>> p(n);
  std::vector<std::array<double, 4>> q(n);
  for (size_t i = 0; i < n; ++i)
  {
    const Eigen::Quaterniond qq(pb.poses[i].linear());
    p[i] = {pb.poses[i].translation().x(), pb.poses[i].translation().y(), pb.poses[i].translation().z()};
    q[i] = {qq.x(), qq.y(), qq.z(), qq.w()};
  }
  std::map<int64_t, std::array<double, 3>> X;
  for (const auto& [id, x] : pb.landmarks)
    X[id] = {x.x(), x.y(), x.z()};

  ceres::Problem problem;
  const double w = 1.0 / opt.pixel_sigma_px;
  for (const BaObservation& o : pb.observations)
  {
    auto* cost = new ceres::AutoDiffCostFunction<StereoReprojection, 3, 3, 4, 3>(new StereoReprojection(cam, o.uvr, w / o.scale));
    // Huber threshold in whitened units (the residuals are divided by sigma)
    problem.AddResidualBlock(cost, new ceres::HuberLoss(opt.huber_px / opt.pixel_sigma_px), p[o.frame].data(), q[o.frame].data(),
                             X.at(o.landmark).data());
  }
  for (const PoseGraphEdge& e : pb.priors)
  {
    problem.AddResidualBlock(relativePoseCost(e), nullptr, p[e.from].data(), q[e.from].data(), p[e.to].data(), q[e.to].data());
  }
  for (size_t i = 0; i < n; ++i)
  {
    if (!problem.HasParameterBlock(q[i].data()))
      continue;
    problem.SetManifold(q[i].data(), new ceres::EigenQuaternionManifold);
    if (i < pb.fixed.size() && pb.fixed[i])
    {
      problem.SetParameterBlockConstant(p[i].data());
      problem.SetParameterBlockConstant(q[i].data());
    }
  }
  ceres::Solver::Options so;
  so.linear_solver_type = ceres::SPARSE_SCHUR;
  so.max_num_iterations = opt.max_iterations;
  so.num_threads = 1;
  ceres::Solver::Summary summary;
  ceres::Solve(so, &problem, &summary);
  out.solved = summary.IsSolutionUsable();
  out.iterations = static_cast<int>(summary.iterations.size());
  if (!out.solved)
    return out;
  for (size_t i = 0; i < n; ++i)
  {
    pb.poses[i].linear() = Eigen::Quaterniond(q[i][3], q[i][0], q[i][1], q[i][2]).normalized().toRotationMatrix();
    pb.poses[i].translation() = Eigen::Vector3d(p[i][0], p[i][1], p[i][2]);
  }
  for (auto& [id, x] : pb.landmarks)
    x = Eigen::Vector3d(X[id][0], X[id][1], X[id][2]);
  out.final_rms_px = reprojectionRms(pb, cam);
  return out;
}

}  // namespace assistive_slam
