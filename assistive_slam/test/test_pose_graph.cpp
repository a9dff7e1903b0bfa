// The pose graph closes a synthetic square loop: exact edges from a drifted start give the truth;
// one edge off by e spreads -e/4 over each of the loop's four edges.
#include <gtest/gtest.h>
#include "assistive_slam/pose_graph.h"

using namespace assistive_slam;

namespace
{
Eigen::Isometry3d pose(double x, double y, double yaw_deg)
{
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = Eigen::AngleAxisd(yaw_deg * M_PI / 180.0, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  T.translation() = Eigen::Vector3d(x, y, 0);
  return T;
}
// corners of a 4 m square walked counter-clockwise, facing along the next side
std::vector<Eigen::Isometry3d> square()
{
  return {pose(0, 0, 0), pose(4, 0, 90), pose(4, 4, 180), pose(0, 4, 270)};
}
}  // namespace

TEST(PoseGraph, ClosesSquareLoopToTruth)
{
  const auto truth = square();
  PoseGraph g;
  // initial guess: the odometry chain with 5 deg of yaw drift and 0.2 m of scale error per side
  Eigen::Isometry3d T = truth[0];
  const Eigen::Isometry3d drift = pose(0.2, 0.1, 5);
  for (int i = 0; i < 4; ++i)
  {
    g.addNode(i, T);
    if (i < 3)
      T = T * truth[i].inverse() * truth[i + 1] * drift;
  }
  for (int i = 0; i < 4; ++i)
  {
    PoseGraphEdge e;
    e.from = i;
    e.to = (i + 1) % 4;
    e.T_from_to = truth[i].inverse() * truth[(i + 1) % 4];
    e.information = isotropicInformation(0.05, 0.01);
    g.addEdge(e);
  }
  ASSERT_GT((g.pose(3).translation() - truth[3].translation()).norm(), 0.3);  // really drifted
  const PoseGraphResult r = g.optimise();
  EXPECT_LT(r.final_cost, 1e-12);
  for (int i = 0; i < 4; ++i)
  {
    EXPECT_NEAR((g.pose(i).translation() - truth[i].translation()).norm(), 0.0, 1e-6) << i;
    EXPECT_NEAR(Eigen::AngleAxisd(g.pose(i).linear().transpose() * truth[i].linear()).angle(), 0.0, 1e-6) << i;
  }
}

TEST(PoseGraph, SpreadsLoopErrorEvenly)
{
  const auto truth = square();
  PoseGraph g;
  for (int i = 0; i < 4; ++i)
    g.addNode(i, truth[i]);
  const Eigen::Vector3d e_world(0.4, -0.2, 0.0);  // the closing edge 3 -> 0 is off by this (world axes)
  for (int i = 0; i < 4; ++i)
  {
    PoseGraphEdge e;
    e.from = i;
    e.to = (i + 1) % 4;
    e.T_from_to = truth[i].inverse() * truth[(i + 1) % 4];
    if (i == 3)
      e.T_from_to.translation() += truth[3].linear().transpose() * e_world;
    e.information = isotropicInformation(0.1, 1e-5);  // rotations held: the answer is linear
    g.addEdge(e);
  }
  g.setFixed(0);
  g.optimise();
  // sum of the world-frame residuals over the cycle is -e: each edge takes -e/4
  for (int i = 1; i < 4; ++i)
    EXPECT_NEAR((g.pose(i).translation() - (truth[i].translation() - i * e_world / 4.0)).norm(), 0.0, 1e-4) << i;
}

TEST(PoseGraph, RejectsEdgeToUnknownNode)
{
  PoseGraph g;
  g.addNode(0, Eigen::Isometry3d::Identity());
  PoseGraphEdge e;
  e.from = 0;
  e.to = 7;
  EXPECT_THROW(g.addEdge(e), std::invalid_argument);
}
