// rostest: the test publishes synthetic traversability grids and the wearer's tf (no bag committed)
// to the planner nodelet and checks the navigation state, the path and the waypoint.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include <assistive_msgs/MoverArray.h>
#include <assistive_msgs/NavigationState.h>
#include <geometry_msgs/PointStamped.h>
#include <geometry_msgs/PoseStamped.h>
#include <geometry_msgs/TransformStamped.h>
#include <nav_msgs/OccupancyGrid.h>
#include <sensor_msgs/Range.h>
#include <nav_msgs/Odometry.h>
#include <nav_msgs/Path.h>
#include <ros/ros.h>
#include <tf2_ros/static_transform_broadcaster.h>
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
    odom_pub_ = nh_.advertise<nav_msgs::Odometry>("vo/odom", 5);
    movers_pub_ = nh_.advertise<assistive_msgs::MoverArray>("obstacles/movers", 1);
    goal_pub_ = nh_.advertise<geometry_msgs::PoseStamped>("planner/goal", 1);
    const ros::WallTime until = ros::WallTime::now() + ros::WallDuration(20.0);
    while (ros::ok() &&
           (grid_pub_.getNumSubscribers() == 0 || odom_pub_.getNumSubscribers() == 0 ||
            movers_pub_.getNumSubscribers() == 0 || goal_pub_.getNumSubscribers() == 0) &&
           ros::WallTime::now() < until)
      ros::WallDuration(0.05).sleep();
  }

  // Publishes the wearer's pose on tf and a grid until a state for this grid's stamp arrives
  // (`movers`: published before the grid, stamped like it).
  bool step(double x, double y, double yaw, bool unknown_around_wearer, nav_msgs::OccupancyGrid* sent = nullptr,
            const assistive_msgs::MoverArray* movers = nullptr)
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
      odom_pub_.publish(odom(x, y, stamp, true));
      if (movers)
      {
        assistive_msgs::MoverArray m = *movers;
        m.header.stamp = stamp;
        movers_pub_.publish(m);
      }
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

  // vo/odom as the VO publishes it: an untrusted pose carries variances of 9999.
  static nav_msgs::Odometry odom(double x, double y, const ros::Time& stamp, bool trusted)
  {
    nav_msgs::Odometry o;
    o.header.stamp = stamp;
    o.header.frame_id = "odom";
    o.child_frame_id = "camera_link";
    o.pose.pose.position.x = x;
    o.pose.pose.position.y = y;
    o.pose.pose.position.z = 1.6;
    o.pose.pose.orientation.w = 1.0;
    for (int i = 0; i < 6; ++i)
      o.pose.covariance[size_t(i * 7)] = o.twist.covariance[size_t(i * 7)] = trusted ? 1e-4 : 9999.0;
    return o;
  }

  // Publishes odometry alone and waits for the state the planner decides from it.
  bool odomOnly(double x, double y, bool trusted, const ros::Time& stamp)
  {
    odom_pub_.publish(odom(x, y, stamp, trusted));
    const ros::WallTime until = ros::WallTime::now() + ros::WallDuration(2.0);
    while (ros::WallTime::now() < until)
    {
      ros::spinOnce();
      if (rec_.state && rec_.state->source_stamp == stamp)
        return true;
      ros::WallDuration(0.01).sleep();
    }
    return false;
  }

  ros::NodeHandle nh_;
  Recorder rec_;
  ros::Subscriber state_sub_, path_sub_, wp_sub_;
  ros::Publisher grid_pub_, odom_pub_, movers_pub_, goal_pub_;
  tf2_ros::TransformBroadcaster tf_;
  tf2_ros::StaticTransformBroadcaster static_tf_;
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
  // standing: what lies ahead is judged along the steering heading, round the wall's end
  EXPECT_GT(std::abs(s.steer_heading), 0.2);
  EXPECT_GT(s.free_distance_ahead, 1.4);
  ASSERT_TRUE(rec_.path);
  ASSERT_GE(rec_.path->poses.size(), 3u);  // smoothed: the corners round the wall
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

TEST_F(PlannerNodeletTest, UntrustedPoseAndUnrefreshedMapStopTheGuidance)
{
  ASSERT_TRUE(step(0.1, 0.1, 0.0, false));
  ASSERT_EQ(rec_.state->status, assistive_msgs::NavigationState::OK) << rec_.state->message;

  // the VO says it cannot trust its pose: NO_POSE at once, decided on that frame
  ASSERT_TRUE(odomOnly(0.1, 0.1, false, ros::Time::now()));
  EXPECT_EQ(rec_.state->status, assistive_msgs::NavigationState::NO_POSE) << rec_.state->message;

  // trusted again: the pose may have jumped against the old map, which is forgotten
  ASSERT_TRUE(odomOnly(0.1, 0.1, true, ros::Time::now()));
  EXPECT_EQ(rec_.state->status, assistive_msgs::NavigationState::NO_MAP) << rec_.state->message;

  // a fresh grid brings the guidance back
  ASSERT_TRUE(step(0.1, 0.1, 0.0, false));
  EXPECT_EQ(rec_.state->status, assistive_msgs::NavigationState::OK) << rec_.state->message;
  const ros::Time last_grid = rec_.state->source_stamp;

  // trusted poses, but no new grid (frames without depth): NO_MAP once the grid lags the newest
  // frame by more than max_input_age_s (0.5 s)
  ros::WallDuration(0.6).sleep();
  const ros::Time late = ros::Time::now();
  ASSERT_GT((late - last_grid).toSec(), 0.5);
  ASSERT_TRUE(odomOnly(0.1, 0.1, true, late));
  EXPECT_EQ(rec_.state->status, assistive_msgs::NavigationState::NO_MAP) << rec_.state->message;
  EXPECT_NE(rec_.state->message.find("not refreshed"), std::string::npos) << rec_.state->message;
}

// Callback hygiene: malformed grids (wrong data size, NaN resolution, rotated, another frame)
// each get a NO_MAP answer, and the nodelet keeps planning on the next good grid.
TEST_F(PlannerNodeletTest, MalformedGridsDoNotStopThePlanner)
{
  ASSERT_TRUE(step(0.0, 0.0, 0.0, false));
  for (int kind = 0; kind < 4; ++kind)
  {
    const ros::Time stamp = ros::Time::now();
    odom_pub_.publish(odom(0.0, 0.0, stamp, true));
    auto g = makeGrid(0.0, 0.0, false, stamp);
    if (kind == 0)
      g.data.resize(17);
    else if (kind == 1)
      g.info.resolution = std::nanf("");
    else if (kind == 2)
      g.info.origin.orientation.z = g.info.origin.orientation.w = std::sqrt(0.5);
    else
      g.header.frame_id = "elsewhere";
    ros::WallDuration(0.05).sleep();
    grid_pub_.publish(g);
    const ros::WallTime until = ros::WallTime::now() + ros::WallDuration(2.0);
    while (ros::WallTime::now() < until && !(rec_.state && rec_.state->source_stamp == stamp))
    {
      ros::spinOnce();
      ros::WallDuration(0.01).sleep();
    }
    ASSERT_TRUE(rec_.state && rec_.state->source_stamp == stamp) << "no answer to malformed grid " << kind;
    EXPECT_EQ(rec_.state->status, assistive_msgs::NavigationState::NO_MAP) << kind << ": " << rec_.state->message;
  }
  ASSERT_TRUE(step(0.2, 0.0, 0.0, false)) << "the planner stopped after the malformed grids";
  EXPECT_NE(rec_.state->status, assistive_msgs::NavigationState::NO_MAP) << rec_.state->message;
}

// People crossing: obstacles/movers reach NavigationState.crossing; old movers, or movers in
// another frame, give none.
TEST_F(PlannerNodeletTest, CrossingAdviceFromMovers)
{
  // the wearer stands (speed 0 over the last second) at (0.2, 0)
  ASSERT_TRUE(step(0.2, 0.0, 0.0, false));
  ros::WallDuration(1.1).sleep();
  ASSERT_TRUE(step(0.2, 0.0, 0.0, false));
  ASSERT_EQ(rec_.state->status, assistive_msgs::NavigationState::OK) << rec_.state->message;
  EXPECT_EQ(rec_.state->crossing, assistive_msgs::NavigationState::CROSSING_NONE);  // nobody yet
  const double h = rec_.state->heading, wx = rec_.state->wearer.x, wy = rec_.state->wearer.y;
  // a person 2.1 m to the right of the motion vector, 0.2 m ahead, walking across at 1.2 m/s:
  // t* = 2.1 / 1.2 = 1.75 s, d* = 0.2 m; it walks to the left: pass behind it, to the right
  assistive_msgs::MoverArray movers;
  movers.header.frame_id = "odom";
  assistive_msgs::Mover m;
  m.id = 5;
  m.position.x = wx + 0.2 * std::cos(h) + 2.1 * std::sin(h);
  m.position.y = wy + 0.2 * std::sin(h) - 2.1 * std::cos(h);
  m.velocity.x = -1.2 * std::sin(h);
  m.velocity.y = 1.2 * std::cos(h);
  m.radius = 0.3f;
  movers.movers.push_back(m);
  ASSERT_TRUE(step(0.2, 0.0, 0.0, false, nullptr, &movers));
  ASSERT_EQ(rec_.state->status, assistive_msgs::NavigationState::OK) << rec_.state->message;
  EXPECT_EQ(rec_.state->crossing, assistive_msgs::NavigationState::CROSSING_RIGHT);
  EXPECT_EQ(rec_.state->crossing_id, 5u);
  EXPECT_NEAR(rec_.state->crossing_time, 1.75, 1e-3);
  EXPECT_NEAR(rec_.state->crossing_distance, 0.2, 1e-3);

  // no movers for 0.6 s: the last ones are too old for this cycle: no stale warning
  ros::WallDuration(0.6).sleep();
  ASSERT_TRUE(step(0.2, 0.0, 0.0, false));
  EXPECT_EQ(rec_.state->crossing, assistive_msgs::NavigationState::CROSSING_NONE);
  EXPECT_EQ(rec_.state->crossing_time, 0.0f);

  // movers in another frame than world_frame: ignored
  movers.header.frame_id = "map";
  ASSERT_TRUE(step(0.2, 0.0, 0.0, false, nullptr, &movers));
  EXPECT_EQ(rec_.state->crossing, assistive_msgs::NavigationState::CROSSING_NONE);
}

// Issue 34: a goal given in SLAM's map is kept there: the planner waits (NO_POSE) while the map is
// not on tf, follows the map -> odom it is given, and still guides to it after a reset (an
// untrusted pose); a goal given in odom itself is dropped at the reset.
TEST_F(PlannerNodeletTest, GoalInTheMapFrameSurvivesAReset)
{
  auto goalIn = [&](const std::string& frame, double x, double y) {
    geometry_msgs::PoseStamped g;
    g.header.frame_id = frame;
    g.pose.position.x = x;
    g.pose.position.y = y;
    g.pose.orientation.w = 1.0;
    goal_pub_.publish(g);
    ros::WallDuration(0.2).sleep();
  };
  auto waypointNear = [&](double x, double y) {
    return rec_.waypoint && rec_.waypoint->header.stamp == rec_.state->source_stamp &&
           std::hypot(rec_.waypoint->point.x - x, rec_.waypoint->point.y - y) < 0.15;
  };
  ASSERT_TRUE(step(0.1, 0.1, 0.0, false));
  ASSERT_EQ(rec_.state->status, assistive_msgs::NavigationState::OK) << rec_.state->message;

  // "test_map" is not on tf yet: no guidance on a guess
  goalIn("test_map", 1.0, 3.0);
  ASSERT_TRUE(step(0.1, 0.1, 0.0, false));
  EXPECT_EQ(rec_.state->status, assistive_msgs::NavigationState::NO_POSE) << rec_.state->message;
  EXPECT_NE(rec_.state->message.find("explicit goal"), std::string::npos) << rec_.state->message;

  // test_map -> odom known: the goal (1, 3) in test_map is (1.5, 2) in odom
  geometry_msgs::TransformStamped t;
  t.header.stamp = ros::Time::now();
  t.header.frame_id = "test_map";
  t.child_frame_id = "odom";
  t.transform.translation.x = -0.5;
  t.transform.translation.y = 1.0;
  t.transform.rotation.w = 1.0;
  static_tf_.sendTransform(t);
  ros::WallDuration(0.3).sleep();
  ASSERT_TRUE(step(0.1, 0.1, 0.0, false));
  ASSERT_EQ(rec_.state->status, assistive_msgs::NavigationState::OK) << rec_.state->message;
  EXPECT_TRUE(waypointNear(1.5, 2.0)) << (rec_.waypoint ? rec_.waypoint->point.x : NAN) << ", "
                                      << (rec_.waypoint ? rec_.waypoint->point.y : NAN);

  // an untrusted pose, trusted again: the planner resets, the goal in test_map survives it
  ASSERT_TRUE(odomOnly(0.1, 0.1, false, ros::Time::now()));
  ASSERT_TRUE(odomOnly(0.1, 0.1, true, ros::Time::now()));
  ASSERT_TRUE(step(0.1, 0.1, 0.0, false));
  ASSERT_EQ(rec_.state->status, assistive_msgs::NavigationState::OK) << rec_.state->message;
  EXPECT_TRUE(waypointNear(1.5, 2.0)) << "the goal in test_map was lost at the reset";

  // a goal in odom (behind the wearer) is dropped at the reset: back to the automatic waypoint ahead
  goalIn("odom", -2.0, 2.0);
  ASSERT_TRUE(step(0.1, 0.1, 0.0, false));
  ASSERT_EQ(rec_.state->status, assistive_msgs::NavigationState::OK) << rec_.state->message;
  EXPECT_TRUE(waypointNear(-2.0, 2.0));
  ASSERT_TRUE(odomOnly(0.1, 0.1, false, ros::Time::now()));
  ASSERT_TRUE(odomOnly(0.1, 0.1, true, ros::Time::now()));
  ASSERT_TRUE(step(0.1, 0.1, 0.0, false));
  ASSERT_EQ(rec_.state->status, assistive_msgs::NavigationState::OK) << rec_.state->message;
  ASSERT_TRUE(rec_.waypoint);
  EXPECT_GT(rec_.waypoint->point.x, 0.1) << "the goal in odom should be gone after the reset";

  goalIn("", 0.0, 0.0);  // cleared for the other tests
}

// Issue 34: SLAM stops sending map -> odom while it has lost the wearer (a VO loss, until it finds
// the wearer again in its map); tf2 would hand out the last one however old. A goal in such a frame
// gives NO_POSE once its newest transform is older than goal_tf_max_age (1 s) against the grid,
// and guidance comes back with a fresh one.
TEST_F(PlannerNodeletTest, GoalInAFrameNoLongerSentGivesNoPose)
{
  auto mapToOdom = [&]() {
    geometry_msgs::TransformStamped t;
    t.header.stamp = ros::Time::now();
    // (as odom -> slam_map: odom already has a parent, the earlier test's static test_map)
    t.header.frame_id = "odom";
    t.child_frame_id = "slam_map";
    t.transform.translation.x = 0.5;
    t.transform.translation.y = -1.0;
    t.transform.rotation.w = 1.0;
    tf_.sendTransform(t);
    ros::WallDuration(0.1).sleep();
  };
  geometry_msgs::PoseStamped g;
  g.header.frame_id = "slam_map";
  g.pose.position.x = 1.0;
  g.pose.position.y = 3.0;
  g.pose.orientation.w = 1.0;
  mapToOdom();
  goal_pub_.publish(g);
  ros::WallDuration(0.2).sleep();
  mapToOdom();
  ASSERT_TRUE(step(0.1, 0.1, 0.0, false));
  ASSERT_EQ(rec_.state->status, assistive_msgs::NavigationState::OK) << rec_.state->message;
  ASSERT_TRUE(rec_.waypoint);
  EXPECT_NEAR(rec_.waypoint->point.x, 1.5, 0.15);
  EXPECT_NEAR(rec_.waypoint->point.y, 2.0, 0.15);

  // no map -> odom for 1.5 s: the goal's place is no longer known
  ros::WallDuration(1.5).sleep();
  ASSERT_TRUE(step(0.1, 0.1, 0.0, false));
  EXPECT_EQ(rec_.state->status, assistive_msgs::NavigationState::NO_POSE) << rec_.state->message;
  EXPECT_NE(rec_.state->message.find("s old"), std::string::npos) << rec_.state->message;

  // found again: a fresh map -> odom, guidance to the goal (1, 3) in slam_map = (1.5, 2) in odom
  mapToOdom();
  ASSERT_TRUE(step(0.1, 0.1, 0.0, false));
  EXPECT_EQ(rec_.state->status, assistive_msgs::NavigationState::OK) << rec_.state->message;

  geometry_msgs::PoseStamped clear;
  goal_pub_.publish(clear);  // cleared for the other tests
  ros::WallDuration(0.2).sleep();
}

// Issue 34: the blind zone. A standing wearer whose floor within 1 m nobody has mapped (the wall
// mapped past it): IN_UNKNOWN while no ranger reading came; with a fresh sonar/front reading (no
// echo, frame camera_link on tf) the planner vouches for the floor ahead: OK; a reading without a
// frame is ignored (and the next grid, without a fresh reading, is IN_UNKNOWN again).
TEST_F(PlannerNodeletTest, TheRangerVouchesForTheBlindZone)
{
  ros::Publisher sonar = nh_.advertise<sensor_msgs::Range>("sonar/front", 5);
  const ros::WallTime until = ros::WallTime::now() + ros::WallDuration(10.0);
  while (ros::ok() && sonar.getNumSubscribers() == 0 && ros::WallTime::now() < until)
    ros::WallDuration(0.05).sleep();
  ASSERT_GT(sonar.getNumSubscribers(), 0u);
  auto reading = [&](const std::string& frame) {
    sensor_msgs::Range r;
    r.header.stamp = ros::Time::now();
    r.header.frame_id = frame;
    r.radiation_type = sensor_msgs::Range::ULTRASOUND;
    r.field_of_view = 0.26f;
    r.min_range = 0.2f;
    r.max_range = 4.0f;
    r.range = std::numeric_limits<float>::infinity();
    sonar.publish(r);
    ros::WallDuration(0.05).sleep();
  };
  reading("");  // no frame: ignored
  ASSERT_TRUE(step(0.1, 0.1, 0.0, true));
  EXPECT_EQ(rec_.state->status, assistive_msgs::NavigationState::IN_UNKNOWN) << rec_.state->message;
  bool ok = false;
  for (int i = 0; i < 10 && !ok; ++i)
  {
    reading("camera_link");
    ASSERT_TRUE(step(0.1, 0.1, 0.0, true));
    ok = rec_.state->status == assistive_msgs::NavigationState::OK;
  }
  EXPECT_TRUE(ok) << rec_.state->message;
  EXPECT_GT(rec_.state->free_distance_ahead, 1.0) << rec_.state->message;
  ros::WallDuration(0.7).sleep();  // the reading is stale now
  ASSERT_TRUE(step(0.1, 0.1, 0.0, true));
  EXPECT_EQ(rec_.state->status, assistive_msgs::NavigationState::IN_UNKNOWN) << rec_.state->message;
}

int main(int argc, char** argv)
{
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "test_planner_nodelet");
  return RUN_ALL_TESTS();
}
