// rostest: the test publishes synthetic traversability grids and the wearer's tf (no bag committed)
// to the planner nodelet and checks the navigation state, the path and the waypoint.
#include <gtest/gtest.h>

#include <cmath>

#include <assistive_msgs/NavigationState.h>
#include <geometry_msgs/PointStamped.h>
#include <geometry_msgs/TransformStamped.h>
#include <nav_msgs/OccupancyGrid.h>
#include <nav_msgs/Path.h>
#include <ros/ros.h>
#include <tf2_ros/transform_broadcaster.h>

namespace
{
struct Recorder
{
  assistive_msgs::NavigationState::ConstPtr state;
  nav_msgs::Path::ConstPtr path;
  geometry_msgs::PointStamped::ConstPtr waypoint;
  void onState(const assistive_msgs::NavigationState::ConstPtr& m) { state = m; }
  void onPath(const nav_msgs::Path::ConstPtr& m) { path = m; }
  void onWaypoint(const geometry_msgs::PointStamped::ConstPtr& m) { waypoint = m; }
};

// 50 x 50 cells of 0.2 m (the 5 m window) centred on (cx, cy); a wall x in [1.5, 1.7], y in [-1, 1] in the world.
nav_msgs::OccupancyGrid makeGrid(double cx, double cy, bool unknown_around_wearer, const ros::Time& stamp)
{
  nav_msgs::OccupancyGrid g;
  g.header.frame_id = "odom";
  g.header.stamp = stamp;
  g.info.resolution = 0.2f;
  g.info.width = g.info.height = 50;
  g.info.origin.position.x = std::round((cx - 5.0) / 0.2) * 0.2;
  g.info.origin.position.y = std::round((cy - 5.0) / 0.2) * 0.2;
  g.info.origin.orientation.w = 1.0;
  g.data.assign(2500, 0);
  for (int y = 0; y < 50; ++y)
    for (int x = 0; x < 50; ++x)
    {
      const double wx = g.info.origin.position.x + (x + 0.5) * 0.2, wy = g.info.origin.position.y + (y + 0.5) * 0.2;
      int8_t& c = g.data[size_t(y * 50 + x)];
      if (wx >= 1.5 && wx <= 1.7 && wy >= -1.0 && wy <= 1.0)
        c = 100;
      if (unknown_around_wearer && std::hypot(wx - cx, wy - cy) < 1.0)
        c = -1;
    }
  return g;
}

bool cellIs(const nav_msgs::OccupancyGrid& g, double wx, double wy, int8_t code)
{
  const int x = int(std::floor((wx - g.info.origin.position.x) / g.info.resolution));
  const int y = int(std::floor((wy - g.info.origin.position.y) / g.info.resolution));
  if (x < 0 || y < 0 || x >= int(g.info.width) || y >= int(g.info.height))
    return false;
  return g.data[size_t(y * int(g.info.width) + x)] == code;
}

class PlannerNodeletTest : public ::testing::Test
{
protected:
  void SetUp() override
  {
    state_sub_ = nh_.subscribe("planner/state", 10, &Recorder::onState, &rec_);
    path_sub_ = nh_.subscribe("planner/path", 10, &Recorder::onPath, &rec_);
    wp_sub_ = nh_.subscribe("planner/waypoint", 10, &Recorder::onWaypoint, &rec_);
    grid_pub_ = nh_.advertise<nav_msgs::OccupancyGrid>("obstacles/traversability", 1);
    const ros::WallTime until = ros::WallTime::now() + ros::WallDuration(20.0);
    while (ros::ok() && grid_pub_.getNumSubscribers() == 0 && ros::WallTime::now() < until)
      ros::WallDuration(0.05).sleep();
  }

  // Publishes the wearer's pose on tf and a grid until a state for this grid's stamp arrives.
  bool step(double x, double y, double yaw, bool unknown_around_wearer, nav_msgs::OccupancyGrid* sent = nullptr)
  {
    for (int attempt = 0; attempt < 40; ++attempt)
    {
      const ros::Time stamp = ros::Time::now();
      geometry_msgs::TransformStamped t;
      t.header.stamp = stamp;
      t.header.frame_id = "odom";
      t.child_frame_id = "camera_link";
      t.transform.translation.x = x;
      t.transform.translation.y = y;
      t.transform.translation.z = 1.6;
      t.transform.rotation.z = std::sin(0.5 * yaw);
      t.transform.rotation.w = std::cos(0.5 * yaw);
      tf_.sendTransform(t);
      ros::WallDuration(0.05).sleep();
      const auto g = makeGrid(x, y, unknown_around_wearer, stamp);
      grid_pub_.publish(g);
      const ros::WallTime until = ros::WallTime::now() + ros::WallDuration(0.5);
      while (ros::WallTime::now() < until)
      {
        ros::spinOnce();
        if (rec_.state && rec_.state->source_stamp == stamp)
        {
          if (sent)
            *sent = g;
          ros::WallDuration(0.1).sleep();  // let path and waypoint arrive
          ros::spinOnce();
          return true;
        }
        ros::WallDuration(0.01).sleep();
      }
    }
    return false;
  }

  ros::NodeHandle nh_;
  Recorder rec_;
  ros::Subscriber state_sub_, path_sub_, wp_sub_;
  ros::Publisher grid_pub_;
  tf2_ros::TransformBroadcaster tf_;
};
}  // namespace

TEST_F(PlannerNodeletTest, UnknownAtStartUpThenPathAroundWall)
{
  // start-up in unmapped space: the planner says so and invents no path
  ASSERT_TRUE(step(0.1, 0.1, 0.0, true));
  EXPECT_EQ(rec_.state->status, assistive_msgs::NavigationState::IN_UNKNOWN) << rec_.state->message;
  EXPECT_EQ(rec_.state->header.frame_id, "odom");

  // the floor around the wearer is mapped now: a path around the wall to a waypoint beyond it
  nav_msgs::OccupancyGrid g;
  ASSERT_TRUE(step(0.1, 0.1, 0.0, false, &g));
  ASSERT_EQ(rec_.state->status, assistive_msgs::NavigationState::OK) << rec_.state->message;
  const auto s = *rec_.state;
  EXPECT_NEAR(s.wearer.x, 0.1, 1e-6);
  EXPECT_NEAR(s.heading, 0.0, 1e-6);
  EXPECT_GT(s.waypoint.x, 3.0);                   // farthest free cell in the triangle, beyond the wall
  EXPECT_LT(std::abs(s.waypoint.y - 0.1), 0.3);   // on the motion vector
  EXPECT_NEAR(s.waypoint_distance, std::hypot(s.waypoint.x - 0.1, s.waypoint.y - 0.1), 1e-3);
  EXPECT_GT(s.path_length, s.waypoint_distance);  // detour round the wall
  EXPECT_GT(std::abs(s.path_heading), 0.2);
  EXPECT_NEAR(s.free_distance_ahead, 1.3, 0.21);  // the wall's cells start at x = 1.4
  EXPECT_GT(s.free_distance_left, 3.0);
  ASSERT_TRUE(rec_.path);
  ASSERT_GE(rec_.path->poses.size(), 10u);
  EXPECT_EQ(rec_.path->header.frame_id, "odom");
  for (const auto& p : rec_.path->poses)
    EXPECT_FALSE(cellIs(g, p.pose.position.x, p.pose.position.y, 100)) << p.pose.position.x << " " << p.pose.position.y;
  EXPECT_NEAR(rec_.path->poses.back().pose.position.x, s.waypoint.x, 1e-6);
  ASSERT_TRUE(rec_.waypoint);
  EXPECT_NEAR(rec_.waypoint->point.x, s.waypoint.x, 1e-6);
  EXPECT_NEAR(rec_.waypoint->point.y, s.waypoint.y, 1e-6);

  // a head turn of 10 degrees keeps the waypoint
  ASSERT_TRUE(step(0.1, 0.1, 10.0 * M_PI / 180.0, false));
  ASSERT_EQ(rec_.state->status, assistive_msgs::NavigationState::OK);
  EXPECT_NEAR(rec_.state->waypoint.x, s.waypoint.x, 1e-6);
  EXPECT_NEAR(rec_.state->waypoint.y, s.waypoint.y, 1e-6);
  EXPECT_NEAR(rec_.state->heading, 0.0, 1e-6);
  EXPECT_NEAR(rec_.state->head_yaw, 10.0 * M_PI / 180.0, 1e-4);

  // walking 0.4 m forward: the window scrolls with the wearer, the waypoint stays put in the world
  ASSERT_TRUE(step(0.3, 0.1, 0.0, false));
  ASSERT_TRUE(step(0.5, 0.1, 0.0, false, &g));
  ASSERT_EQ(rec_.state->status, assistive_msgs::NavigationState::OK) << rec_.state->message;
  EXPECT_NEAR(rec_.state->waypoint.x, s.waypoint.x, 1e-6);
  EXPECT_NEAR(rec_.state->waypoint.y, s.waypoint.y, 1e-6);
  ASSERT_TRUE(rec_.path);
  EXPECT_NEAR(rec_.path->poses.front().pose.position.x, 0.5, 1e-6);
  for (const auto& p : rec_.path->poses)
    EXPECT_FALSE(cellIs(g, p.pose.position.x, p.pose.position.y, 100));

  // turn around (180 degrees): a new waypoint behind
  ASSERT_TRUE(step(0.5, 0.1, M_PI, false));
  ASSERT_EQ(rec_.state->status, assistive_msgs::NavigationState::OK);
  EXPECT_LT(rec_.state->waypoint.x, -2.0);
}

int main(int argc, char** argv)
{
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "test_planner_nodelet");
  return RUN_ALL_TESTS();
}
