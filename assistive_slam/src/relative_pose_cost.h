#pragma once
// The relative-pose residual shared by the pose graph and the local bundle adjustment's odometry
// priors (core-internal; needs Ceres).
#include <ceres/ceres.h>
#include <Eigen/Cholesky>
#include <Eigen/Geometry>
#include "assistive_slam/pose_graph.h"

namespace assistive_slam
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
    const Eigen::Quaternion<T> q_ab = qa.conjugate() * qb;
    const Eigen::Matrix<T, 3, 1> t_ab = qa.conjugate() * (tb - ta);
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

/// The edge's cost over (t_from, q_from, t_to, q_to); sqrt of the information is its Cholesky
/// factor (upper), so that r^T r = e^T I e.
inline ceres::CostFunction* relativePoseCost(const PoseGraphEdge& e)
{
  const Eigen::LLT<Matrix6d> llt(e.information);
  return new ceres::AutoDiffCostFunction<RelativePoseError, 6, 3, 4, 3, 4>(
      new RelativePoseError(e.T_from_to, llt.matrixL().transpose()));
}
}  // namespace assistive_slam
