// The fastslam backend in the running pipeline (see slam_fastslam.test): the filter runs (its
// particles and landmarks on /diagnostics) and the keyframes it chains stay on the truth.
#include <cmath>
#include <map>
#include <string>
#include <vector>
#include <Eigen/Geometry>
#include <diagnostic_msgs/DiagnosticArray.h>
#include <gtest/gtest.h>
#include <nav_msgs/Odometry.h>
#include <nav_msgs/Path.h>
#include <ros/ros.h>
#include <rosbag/bag.h>
#include <rosbag/view.h>
#include <tf2_eigen/tf2_eigen.h>

#include "replay_test_util.h"

// One executable with test_slam_places.cpp, which holds main() (issue 31: CMakeLists.txt); this
// file's names in a namespace of their own, apart from that file's.
namespace slam_fastslam_test
{

using replay_test::spinFor;
using replay_test::toEigen;
using replay_test::truthAt;

TEST(SlamFastSlam, FilterRunsAndKeyframesFollowTheTruth)
{
  ros::NodeHandle nh, pnh("~");
  std::string bag_path;
  ASSERT_TRUE(pnh.getParam("bag", bag_path));
  const double duration = pnh.param("duration", 24.0);
  const double ate_bound = pnh.param("ate_bound_m", 0.05);
  std::string backend;
  ASSERT_TRUE(nh.getParam("/slam/metric_backend", backend));
  EXPECT_EQ(backend, "fastslam");

  const std::map<double, Eigen::Isometry3d> truth = replay_test::readTruth(bag_path);  // left optical frame in world
  ASSERT_GT(truth.size(), 100u);
  const double end = truth.begin()->first + duration;

  nav_msgs::Path path;
  int particles = -1, landmarks = -1;
  auto path_sub = nh.subscribe<nav_msgs::Path>("/slam/path", 2, [&](const nav_msgs::Path::ConstPtr& m) { path = *m; });
  auto diag_sub = nh.subscribe<diagnostic_msgs::DiagnosticArray>("/diagnostics", 20, [&](const diagnostic_msgs::DiagnosticArray::ConstPtr& m) {
    for (const auto& st : m->status)
      for (const auto& kv : st.values)
      {
        if (kv.key == "fastslam particles")
          particles = std::stoi(kv.value);
        if (kv.key == "fastslam landmarks")
          landmarks = std::stoi(kv.value);
      }
  });
  ros::WallTime deadline = ros::WallTime::now() + ros::WallDuration(75.0);
  while (ros::ok() && ros::WallTime::now() < deadline && ros::Time::now().toSec() < end - 0.2)
    spinFor(0.05);
  ASSERT_GE(ros::Time::now().toSec(), end - 0.2) << "the bag did not play to " << duration << " s: the clock stopped at " << ros::Time::now();
  spinFor(2.5);  // the worker's last keyframes, the newest slam/path and diagnostics

  EXPECT_GT(particles, 0) << "no fastslam figures on /diagnostics";
  EXPECT_GT(landmarks, 0);
  std::vector<Eigen::Vector3d> est, gt;
  for (const auto& ps : path.poses)
  {
    Eigen::Isometry3d T;
    if (truthAt(truth, ps.header.stamp.toSec(), &T))
    {
      est.push_back(toEigen(ps.pose).translation());
      gt.push_back(T.translation());
    }
  }
  ASSERT_GT(est.size(), 10u) << "slam/path has " << path.poses.size() << " keyframes";
  Eigen::Isometry3d A;
  const double rmse = replay_test::ate(est, gt, &A);
  std::printf("slam_fastslam: %zu keyframes, %d particles, %d landmarks in the filter's submap; keyframe ATE %.4f m\n",
              est.size(), particles, landmarks, rmse);
  EXPECT_LT(rmse, ate_bound);
}
}  // namespace slam_fastslam_test
