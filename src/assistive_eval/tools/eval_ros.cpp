#include "eval_ros.h"

#include <nav_msgs/OccupancyGrid.h>
#include <nav_msgs/Odometry.h>
#include <ros/ros.h>
#include <rosbag/bag.h>
#include <rosbag/view.h>
#include <tf2_eigen/tf2_eigen.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <stdexcept>

namespace assistive_eval
{
namespace cli
{
namespace
{
void openBag(rosbag::Bag& b, const std::string& path)
{
  try
  {
    b.open(path, rosbag::bagmode::Read);
  }
  catch (const rosbag::BagException& e)
  {
    throw std::runtime_error("cannot open bag '" + path + "': " + e.what());
  }
}

std::string topicList(rosbag::Bag& b)
{
  std::string s;
  rosbag::View all(b);
  for (const auto* c : all.getConnections())
    if (s.find(c->topic + " ") == std::string::npos)
      s += c->topic + " (" + c->datatype + ") ";
  return s;
}
}  // namespace

std::vector<std::pair<std::string, std::string>> bagTopics(const std::string& path)
{
  rosbag::Bag b;
  openBag(b, path);
  rosbag::View all(b);
  std::vector<std::pair<std::string, std::string>> out;
  for (const auto* c : all.getConnections())
  {
    bool seen = false;
    for (const auto& t : out)
      seen |= t.first == c->topic;
    if (!seen)
      out.emplace_back(c->topic, c->datatype);
  }
  return out;
}

Trajectory readOdometry(const std::string& path, const std::string& topic, std::string* child_frame)
{
  rosbag::Bag b;
  openBag(b, path);
  rosbag::View view(b, rosbag::TopicQuery(topic));
  if (view.size() == 0)
    throw std::runtime_error("bag '" + path + "' has no messages on " + topic + "; topics: " + topicList(b));
  Trajectory out;
  for (const rosbag::MessageInstance& m : view)
  {
    const auto odom = m.instantiate<nav_msgs::Odometry>();
    if (!odom)
      throw std::runtime_error(topic + " in '" + path + "' is " + m.getDataType() + ", not nav_msgs/Odometry");
    if (child_frame && out.empty())
      *child_frame = odom->child_frame_id;
    StampedPose sp;
    sp.t = odom->header.stamp.toSec();
    Eigen::Isometry3d T;
    tf2::fromMsg(odom->pose.pose, T);
    if (!T.matrix().allFinite())
      continue;  // a broken message: skip it rather than poison the statistics
    sp.pose = T;
    out.push_back(sp);
  }
  return out;
}

void collectLive(int argc, char** argv, const std::string& gt_topic, const std::string& est_topic, double duration_s,
                 Trajectory& gt, Trajectory& est, std::string* gt_child, std::string* est_child)
{
  ros::init(argc, argv, "evaluate_trajectory", ros::init_options::AnonymousName);
  if (!ros::master::check())
    throw std::runtime_error("live mode: no ROS master at " + ros::master::getURI());
  ros::NodeHandle nh;
  double first = -1.0;  // wall time of the first message
  auto make = [&](Trajectory& out, std::string* child) {
    return [&out, child, &first](const nav_msgs::Odometry::ConstPtr& m) {
      Eigen::Isometry3d T;
      tf2::fromMsg(m->pose.pose, T);
      if (!T.matrix().allFinite())
        return;
      if (child && out.empty())
        *child = m->child_frame_id;
      if (first < 0)
        first = ros::WallTime::now().toSec();
      StampedPose sp;
      sp.t = m->header.stamp.toSec();
      sp.pose = T;
      out.push_back(sp);
    };
  };
  const boost::function<void(const nav_msgs::Odometry::ConstPtr&)> fa = make(gt, gt_child), fb = make(est, est_child);
  ros::Subscriber a = nh.subscribe<nav_msgs::Odometry>(gt_topic, 1000, fa);
  ros::Subscriber b = nh.subscribe<nav_msgs::Odometry>(est_topic, 1000, fb);
  std::fprintf(stderr, "live: collecting %s and %s (%s)\n", gt_topic.c_str(), est_topic.c_str(),
               duration_s > 0 ? (std::to_string(duration_s) + " s").c_str() : "until Ctrl-C");
  ros::WallRate r(50);
  size_t tick = 0;
  while (ros::ok())
  {
    ros::spinOnce();
    if (duration_s > 0 && first >= 0 && ros::WallTime::now().toSec() - first >= duration_s)
      break;
    if (++tick % 50 == 0)  // once a second
      std::fprintf(stderr, "\rlive: %zu truth, %zu estimate poses", gt.size(), est.size());
    r.sleep();
  }
  std::fprintf(stderr, "\n");
  ros::shutdown();
  std::sort(gt.begin(), gt.end(), [](const StampedPose& x, const StampedPose& y) { return x.t < y.t; });
  std::sort(est.begin(), est.end(), [](const StampedPose& x, const StampedPose& y) { return x.t < y.t; });
}

std::vector<StampedGrid> readGrids(const std::string& path, const std::string& topic, size_t max_count)
{
  rosbag::Bag b;
  openBag(b, path);
  rosbag::View view(b, rosbag::TopicQuery(topic));
  if (view.size() == 0)
    throw std::runtime_error("bag '" + path + "' has no messages on " + topic + "; topics: " + topicList(b));
  const size_t n = view.size();
  const size_t stride = (max_count > 0 && n > max_count) ? (n + max_count - 1) / max_count : 1;
  std::vector<StampedGrid> out;
  size_t k = 0;
  for (const rosbag::MessageInstance& m : view)
  {
    const bool last = (k + 1 == n);
    if ((k++ % stride) != 0 && !last)
      continue;
    const auto g = m.instantiate<nav_msgs::OccupancyGrid>();
    if (!g)
      throw std::runtime_error(topic + " in '" + path + "' is " + m.getDataType() + ", not nav_msgs/OccupancyGrid");
    if (g->data.size() != static_cast<size_t>(g->info.width) * g->info.height || !(g->info.resolution > 0))
      throw std::runtime_error(topic + ": grid with " + std::to_string(g->data.size()) + " cells for " +
                               std::to_string(g->info.width) + "x" + std::to_string(g->info.height));
    StampedGrid s;
    s.stamp = g->header.stamp.toSec();
    s.frame_id = g->header.frame_id;
    const auto& q = g->info.origin.orientation;
    const double yaw = std::atan2(2.0 * (q.w * q.z + q.x * q.y), 1.0 - 2.0 * (q.y * q.y + q.z * q.z));
    s.origin = Eigen::Translation2d(g->info.origin.position.x, g->info.origin.position.y) * Eigen::Rotation2Dd(yaw);
    s.grid.resolution = g->info.resolution;
    s.grid.width = static_cast<int>(g->info.width);
    s.grid.height = static_cast<int>(g->info.height);
    s.grid.data = g->data;
    out.push_back(std::move(s));
  }
  return out;
}

}  // namespace cli
}  // namespace assistive_eval
