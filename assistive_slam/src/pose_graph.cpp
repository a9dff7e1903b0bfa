#include "assistive_slam/pose_graph.h"
#include <array>
#include <stdexcept>
#include <ceres/ceres.h>

namespace assistive_slam
{
namespace
{
/// Residual of one edge: sqrt(information) * [R_m^T (t_ab - t_m); 2 vec(q_m^-1 q_ab)]
/// (the 3D pose-graph residual of Ceres' own example).
struct RelativePoseError
{
  RelativePoseError(const Eigen::Isometry3d& T, const Matrix6d& sqrt_info)
    : t_m(T.translation()), q_m(Eigen::Quaterniond(T.linear()).normalized()), sqrt_info(sqrt_info)
  {
  }
  template <typename T>
  bool operator()(const T* pa, const T* qa_, const T* pb, const T* qb_, T* res) const
  {
    const Eigen::Map<const Eigen::Matrix<T, 3, 1>> ta(pa), tb(pb);
    const Eigen::Map<const Eigen::Quaternion<T>> qa(qa_), qb(qb_);
    const Eigen::Quaternion<T> qa_inv = qa.conjugate();
    const Eigen::Quaternion<T> q_ab = qa_inv * qb;
    const Eigen::Matrix<T, 3, 1> t_ab = qa_inv * (tb - ta);
    const Eigen::Quaternion<T> dq = q_m.template cast<T>().conjugate() * q_ab;
    Eigen::Map<Eigen::Matrix<T, 6, 1>> r(res);
    r.template head<3>() = q_m.template cast<T>().conjugate() * (t_ab - t_m.template cast<T>());
    r.template tail<3>() = T(2.0) * dq.vec();
    r.applyOnTheLeft(sqrt_info.template cast<T>());
    return true;
  }
  Eigen::Vector3d t_m;
  Eigen::Quaterniond q_m;
  Matrix6d sqrt_info;
};
}  // namespace

Matrix6d isotropicInformation(double sigma_t, double sigma_r)
{
  Matrix6d I = Matrix6d::Zero();
  I.diagonal().head<3>().setConstant(1.0 / (sigma_t * sigma_t));
  I.diagonal().tail<3>().setConstant(1.0 / (sigma_r * sigma_r));
  return I;
}

void PoseGraph::addNode(uint32_t id, const Eigen::Isometry3d& T)
{
  nodes_[id] = T;
}

void PoseGraph::addEdge(const PoseGraphEdge& e)
{
  if (!nodes_.count(e.from) || !nodes_.count(e.to))
    throw std::invalid_argument("PoseGraph::addEdge: unknown node");
  edges_.push_back(e);
}

PoseGraphResult PoseGraph::optimise(int max_iterations)
{
  PoseGraphResult out;
  if (nodes_.empty() || edges_.empty())
    return out;
  // Parameter blocks: position and quaternion (x y z w, Eigen's storage) per node.
  std::map<uint32_t, std::array<double, 3>> p;
  std::map<uint32_t, std::array<double, 4>> q;
  for (const auto& [id, T] : nodes_)
  {
    const Eigen::Quaterniond qq(T.linear());
    p[id] = {T.translation().x(), T.translation().y(), T.translation().z()};
    q[id] = {qq.x(), qq.y(), qq.z(), qq.w()};
  }
  ceres::Problem problem;
  for (const PoseGraphEdge& e : edges_)
  {
    // sqrt of the information: its Cholesky factor (upper), so that r^T r = e^T I e
    const Eigen::LLT<Matrix6d> llt(e.information);
    const Matrix6d sqrt_info = llt.matrixL().transpose();
    auto* cost = new ceres::AutoDiffCostFunction<RelativePoseError, 6, 3, 4, 3, 4>(
        new RelativePoseError(e.T_from_to, sqrt_info));
    problem.AddResidualBlock(cost, nullptr, p[e.from].data(), q[e.from].data(), p[e.to].data(), q[e.to].data());
  }
  for (auto& [id, qq] : q)
    if (problem.HasParameterBlock(qq.data()))
      problem.SetManifold(qq.data(), new ceres::EigenQuaternionManifold);
  std::set<uint32_t> fixed = fixed_;
  if (fixed.empty())
    fixed.insert(nodes_.begin()->first);
  for (uint32_t id : fixed)
    if (problem.HasParameterBlock(p[id].data()))
    {
      problem.SetParameterBlockConstant(p[id].data());
      problem.SetParameterBlockConstant(q[id].data());
    }
  ceres::Solver::Options opt;
  opt.linear_solver_type = ceres::SPARSE_NORMAL_CHOLESKY;
  opt.max_num_iterations = max_iterations;
  opt.num_threads = 1;
  opt.function_tolerance = 1e-12;
  opt.gradient_tolerance = 1e-14;
  opt.parameter_tolerance = 1e-12;
  ceres::Solver::Summary summary;
  ceres::Solve(opt, &problem, &summary);
  out.converged = summary.termination_type == ceres::CONVERGENCE;
  out.iterations = static_cast<int>(summary.iterations.size());
  out.initial_cost = summary.initial_cost;
  out.final_cost = summary.final_cost;
  for (auto& [id, T] : nodes_)
  {
    const auto& qq = q[id];
    T.linear() = Eigen::Quaterniond(qq[3], qq[0], qq[1], qq[2]).normalized().toRotationMatrix();
    T.translation() = Eigen::Vector3d(p[id][0], p[id][1], p[id][2]);
  }
  return out;
}

}  // namespace assistive_slam
