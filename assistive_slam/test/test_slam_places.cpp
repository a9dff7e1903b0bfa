// The way back on a replayed parking walk (see slam_places.test): the start is tagged, the walk
// comes back past it (loop closure), and at the end the goal the planner receives lies on the
// start's true position.
#include <algorithm>
#include <cmath>
#include <map>
#include <string>
#include <vector>
#include <Eigen/Geometry>
#include <assistive_msgs/GuideToPlace.h>
#include <assistive_msgs/TagPlace.h>
#include <geometry_msgs/PoseStamped.h>
#include <gtest/gtest.h>
#include <nav_msgs/Odometry.h>
#include <nav_msgs/Path.h>
#include <ros/ros.h>
#include <rosbag/bag.h>
#include <rosbag/view.h>
#include <std_msgs/String.h>
#include <tf2_eigen/tf2_eigen.h>
#include <tf2_ros/buffer.h>
#include <tf2_ros/transform_listener.h>

#include "replay_test_util.h"

using replay_test::ate;
using replay_test::spinFor;
using replay_test::toEigen;
using replay_test::truthAt;

namespace
{
/// The keyframes of slam/path with a truth at their stamps (est, gt), and the VO's poses of the
/// same frames (vo_est, vo_gt; the VO's camera_link moved to the optical frame by T_link_opt).
void keyframesAgainstTruth(const nav_msgs::Path& path, const std::vector<nav_msgs::Odometry>& vo,
                           const std::map<double, Eigen::Isometry3d>& truth, const Eigen::Isometry3d& T_link_opt,
                           std::vector<Eigen::Vector3d>* est, std::vector<Eigen::Vector3d>* gt,
                           std::vector<Eigen::Vector3d>* vo_est, std::vector<Eigen::Vector3d>* vo_gt)
{
  std::map<double, Eigen::Isometry3d> vo_at;
  for (const auto& o : vo)
    vo_at[o.header.stamp.toSec()] = toEigen(o.pose.pose) * T_link_opt;
  for (const auto& ps : path.poses)
  {
    Eigen::Isometry3d T, V;
    if (!truthAt(truth, ps.header.stamp.toSec(), &T))
      continue;
    est->push_back(toEigen(ps.pose).translation());
    gt->push_back(T.translation());
    if (truthAt(vo_at, ps.header.stamp.toSec(), &V))
    {
      vo_est->push_back(V.translation());
      vo_gt->push_back(T.translation());
    }
  }
}
}  // namespace

TEST(SlamPlaces, TagTheStartWalkTheLoopAndComeBack)
{
  ros::NodeHandle nh, pnh("~");
  std::string bag_path;
  ASSERT_TRUE(pnh.getParam("bag", bag_path));
  const double ate_bound = pnh.param("ate_bound_m", 0.05);
  const double goal_tol = pnh.param("goal_tolerance_m", 0.15);

  tf2_ros::Buffer tf;
  tf2_ros::TransformListener listener(tf);
  int accepted = 0, rejected = 0;
  nav_msgs::Path path;
  std::vector<nav_msgs::Odometry> vo;
  geometry_msgs::PoseStamped goal;
  bool have_goal = false;
  auto loop_sub = nh.subscribe<std_msgs::String>("/slam/loop_closures", 100, [&](const std_msgs::String::ConstPtr& m) {
    (m->data.rfind("accepted", 0) == 0 ? accepted : rejected)++;
  });
  auto path_sub = nh.subscribe<nav_msgs::Path>("/slam/path", 2, [&](const nav_msgs::Path::ConstPtr& m) { path = *m; });
  auto vo_sub = nh.subscribe<nav_msgs::Odometry>("/vo/odom", 100, [&](const nav_msgs::Odometry::ConstPtr& m) { vo.push_back(*m); });
  auto goal_sub = nh.subscribe<geometry_msgs::PoseStamped>("/planner/goal", 2, [&](const geometry_msgs::PoseStamped::ConstPtr& m) {
    goal = *m;
    have_goal = true;
  });
  ros::ServiceClient tag = nh.serviceClient<assistive_msgs::TagPlace>("/slam/tag_place");
  ros::ServiceClient guide = nh.serviceClient<assistive_msgs::GuideToPlace>("/slam/guide_to_place");
  ASSERT_TRUE(tag.waitForExistence(ros::Duration(60.0)));
  ASSERT_TRUE(guide.waitForExistence(ros::Duration(10.0)));

  // 1. Tag the start as soon as the map holds a keyframe.
  assistive_msgs::TagPlace t;
  t.request.name = "start";
  ros::WallTime deadline = ros::WallTime::now() + ros::WallDuration(60.0);
  while (ros::ok() && ros::WallTime::now() < deadline && !(tag.call(t) && t.response.success))
    spinFor(0.1);
  ASSERT_TRUE(t.response.success) << t.response.message;
  EXPECT_EQ(t.response.name, "start");

  // The truth is read only after the tag: the bag plays on the wall clock from launch, and reading
  // the truth scans the whole 0.45 GB bag (slow on a cold disk while another test reads it too);
  // read first, it let CI tag the start 7.4 s into the walk.
  const std::map<double, Eigen::Isometry3d> truth = replay_test::readTruth(bag_path);  // left optical frame in world
  ASSERT_GT(truth.size(), 600u) << "the bag must reach the second pass of the start";
  const double bag_end = truth.rbegin()->first;
  Eigen::Isometry3d T_w_tag;
  ASSERT_TRUE(truthAt(truth, t.response.stamp.toSec(), &T_w_tag)) << "tag stamp " << t.response.stamp;
  const double tag_time = t.response.stamp.toSec() - truth.begin()->first;
  EXPECT_LT(tag_time, 3.0) << "the start was tagged late: " << tag_time << " s into the walk";

  // 2. Walk: until the simulated clock reaches the end of the bag, then let the worker finish.
  deadline = ros::WallTime::now() + ros::WallDuration(200.0);
  while (ros::ok() && ros::WallTime::now() < deadline && ros::Time::now().toSec() < bag_end - 0.1)
    spinFor(0.05);
  ASSERT_GE(ros::Time::now().toSec(), bag_end - 0.1)
      << "the bag did not finish playing: the clock stopped at " << ros::Time::now() << " of " << bag_end;
  spinFor(3.0);

  // 3. The way back.
  assistive_msgs::GuideToPlace g;
  g.request.name = "start";
  ASSERT_TRUE(guide.call(g));
  ASSERT_TRUE(g.response.success) << g.response.message;
  for (int i = 0; i < 300 && !have_goal; ++i)
    spinFor(0.01);
  ASSERT_TRUE(have_goal) << "no goal on planner/goal";
  EXPECT_EQ(goal.header.frame_id, "map");
  spinFor(1.5);  // the newest slam/path (published at graph_rate)

  // Loop closure: the walk passes its start again at about frame 600.
  EXPECT_GE(accepted, 1) << "no loop closure accepted (" << rejected << " rejected)";

  // The head (camera_link) in the left optical frame: the goal is the head's pose, the truth the optical frame's.
  const Eigen::Isometry3d T_link_opt =
      tf2::transformToEigen(tf.lookupTransform("camera_link", "camera_left_optical_frame", ros::Time(0), ros::Duration(2.0)));

  // ATE of the corrected keyframes, and of the VO on the same frames.
  std::vector<Eigen::Vector3d> est, gt, vo_est, vo_gt;
  keyframesAgainstTruth(path, vo, truth, T_link_opt, &est, &gt, &vo_est, &vo_gt);
  ASSERT_GT(est.size(), 50u) << "slam/path has " << path.poses.size() << " keyframes";
  Eigen::Isometry3d A, A_vo;
  const double slam_ate = ate(est, gt, &A);
  const double vo_ate = vo_est.size() > 10 ? ate(vo_est, vo_gt, &A_vo) : -1;
  std::printf("slam_places: %zu keyframes, %d loop closures accepted, %d rejected; ATE SLAM %.4f m, VO %.4f m (same keyframes)\n",
              est.size(), accepted, rejected, slam_ate, vo_ate);
  EXPECT_LT(slam_ate, ate_bound);

  // The goal: the start's true position (the head, in world through the trajectory's fit) ...
  const Eigen::Vector3d goal_w = A * toEigen(goal.pose).translation();
  const Eigen::Vector3d start_w = (T_w_tag * T_link_opt.inverse()).translation();
  const double err_fit = (goal_w - start_w).head<2>().norm();
  // ... and, what guiding needs, the way from where the wearer stands now (map -> camera_link
  // now against the truth at that time): no fit involved.
  const geometry_msgs::TransformStamped now = tf.lookupTransform("map", "camera_left_optical_frame", ros::Time(0), ros::Duration(2.0));
  Eigen::Isometry3d T_w_now;
  ASSERT_TRUE(truthAt(truth, now.header.stamp.toSec(), &T_w_now)) << "no truth at " << now.header.stamp;
  const Eigen::Vector3d way_est = tf2::transformToEigen(now).inverse() * toEigen(goal.pose).translation();
  const Eigen::Vector3d way_true = T_w_now.inverse() * start_w;
  const double err_way = (way_est - way_true).norm();
  std::printf("slam_places: tagged %.2f s into the walk; goal vs the start's truth %.3f m (fit), the way from the last pose %.3f m off over %.2f m\n",
              tag_time, err_fit, err_way, way_true.norm());
  EXPECT_LT(err_fit, goal_tol);
  EXPECT_LT(err_way, goal_tol);
}

int main(int argc, char** argv)
{
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "test_slam_places");
  ros::NodeHandle nh;
  return RUN_ALL_TESTS();
}
