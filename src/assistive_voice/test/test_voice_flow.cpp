// The way back by voice (see voice_flow.test): "save place door" at the start of the walk,
// "take me back to the door" at its end; the planner receives the saved place as its goal and the
// wearer hears the expected replies.
#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include <assistive_voice/audio.h>
#include <geometry_msgs/PoseStamped.h>
#include <gtest/gtest.h>
#include <nav_msgs/Odometry.h>
#include <ros/ros.h>
#include <rosbag/bag.h>
#include <rosbag/view.h>
#include <std_msgs/String.h>
#include <tf2_ros/buffer.h>
#include <tf2_ros/transform_listener.h>

namespace
{
void spinFor(double wall_s)
{
  const ros::WallTime end = ros::WallTime::now() + ros::WallDuration(wall_s);
  while (ros::ok() && ros::WallTime::now() < end)
  {
    ros::spinOnce();
    ros::WallDuration(0.01).sleep();
  }
}
template <class F>
bool waitFor(F done, double wall_s)
{
  const ros::WallTime end = ros::WallTime::now() + ros::WallDuration(wall_s);
  while (ros::ok() && ros::WallTime::now() < end && !done())
    spinFor(0.02);
  return done();
}
}  // namespace

TEST(VoiceFlow, SavePlaceWalkTakeMeBack)
{
  ros::NodeHandle nh, pnh("~");
  std::string bag_path, replies_dir;
  ASSERT_TRUE(pnh.getParam("bag", bag_path));
  ASSERT_TRUE(pnh.getParam("replies", replies_dir));
  const double goal_tol = pnh.param("goal_tolerance_m", 0.5);
  tf2_ros::Buffer tf(ros::Duration(600.0));
  tf2_ros::TransformListener listener(tf);
  std::vector<std::string> replies, commands;
  std::vector<geometry_msgs::PoseStamped> goals;
  auto reply_sub = nh.subscribe<std_msgs::String>("/voice/reply", 10, [&](const std_msgs::String::ConstPtr& m) {
    replies.push_back(m->data);
  });
  auto cmd_sub = nh.subscribe<std_msgs::String>("/voice/command", 10, [&](const std_msgs::String::ConstPtr& m) {
    commands.push_back(m->data);
  });
  auto goal_sub = nh.subscribe<geometry_msgs::PoseStamped>("/planner/goal", 10, [&](const geometry_msgs::PoseStamped::ConstPtr& m) {
    goals.push_back(*m);
  });
  ros::Publisher say = nh.advertise<std_msgs::String>("/voice/command_text", 1);

  // The bag is opened only now that the replies are heard: it plays on the wall clock from launch
  // and the scripted "save place" comes 3 s into it (slam_places once lost 7 s to reading its bag first).
  double bag_end = 0;
  {
    rosbag::Bag bag(bag_path);
    rosbag::View view(bag);
    bag_end = view.getEndTime().toSec();
    // the player stops `duration` seconds after the bag's start (a longer walk's first part)
    double duration = 0;
    if (pnh.getParam("duration", duration))
      bag_end = std::min(bag_end, view.getBeginTime().toSec() + duration);
  }

  // 1. The script's "save place door" (3 s into the walk): the wearer hears "door saved".
  ASSERT_TRUE(waitFor([&] { return !replies.empty(); }, 90.0)) << "no reply to the scripted save place";
  EXPECT_EQ(replies[0], "door saved");
  geometry_msgs::TransformStamped at_tag;
  ASSERT_NO_THROW(at_tag = tf.lookupTransform("map", "camera_link", ros::Time(0), ros::Duration(2.0)));

  // 2. Walk: until the simulated clock reaches the end of the bag.
  ASSERT_TRUE(waitFor([&] { return ros::Time::now().toSec() >= bag_end - 0.5; }, 120.0)) << "the bag did not finish";
  spinFor(1.0);
  const geometry_msgs::TransformStamped at_end = tf.lookupTransform("map", "camera_link", ros::Time(0), ros::Duration(2.0));
  EXPECT_TRUE(goals.empty()) << "a goal before the wearer asked for one";

  // 3. "take me back to the door".
  std_msgs::String m;
  m.data = "take me back to the door";
  ASSERT_TRUE(waitFor([&] { return say.getNumSubscribers() > 0; }, 5.0));
  say.publish(m);
  ASSERT_TRUE(waitFor([&] { return !goals.empty() && replies.size() >= 2; }, 10.0))
      << goals.size() << " goals, " << replies.size() << " replies";
  spinFor(2.5);  // anything more would be an unexpected reply (min_interval_s is 2 s)

  const geometry_msgs::PoseStamped& goal = goals.back();
  EXPECT_EQ(goal.header.frame_id, "map");
  const double dx_tag = goal.pose.position.x - at_tag.transform.translation.x;
  const double dy_tag = goal.pose.position.y - at_tag.transform.translation.y;
  const double dx_end = goal.pose.position.x - at_end.transform.translation.x;
  const double dy_end = goal.pose.position.y - at_end.transform.translation.y;
  const double from_tag = std::hypot(dx_tag, dy_tag), from_end = std::hypot(dx_end, dy_end);
  std::printf("voice_flow: goal %.3f m from the head when 'door saved' was heard, %.2f m from the end of the walk\n",
              from_tag, from_end);
  EXPECT_LT(from_tag, goal_tol);
  EXPECT_GT(from_end, 2.0 * goal_tol) << "the walk must lead away from the saved place";

  EXPECT_EQ(replies, (std::vector<std::string>{"door saved", "guiding back to the door"}));
  EXPECT_EQ(commands, (std::vector<std::string>{"save_place door", "guide_back door"}));
  // espeak-ng wrote each reply as a WAV file
  for (const char* f : {"/reply_000.wav", "/reply_001.wav"})
  {
    assistive_voice::Audio a;
    std::string err;
    EXPECT_TRUE(assistive_voice::readWav(replies_dir + f, &a, &err)) << err;
    EXPECT_GT(a.samples.size(), static_cast<size_t>(a.rate / 4)) << f << ": shorter than 0.25 s";
  }
}

int main(int argc, char** argv)
{
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "test_voice_flow");
  ros::NodeHandle nh;
  return RUN_ALL_TESTS();
}
