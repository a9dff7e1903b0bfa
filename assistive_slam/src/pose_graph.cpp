#include "assistive_slam/pose_graph.h"
#include <array>
#include <stdexcept>
#include <ceres/ceres.h>
#include "relative_pose_cost.h"

namespace assistive_slam
{
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
    problem.AddResidualBlock(relativePoseCost(e), nullptr, p[e.from].data(), q[e.from].data(), p[e.to].data(), q[e.to].data());
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
