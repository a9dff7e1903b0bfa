// rostest mobility_chain (issue 19, the closed loop in CI): the planner and cue logic nodelets run
// in one manager as pipeline.launch loads them, fed the glass world's TRUE occupancy (as
// `mobility_trials --mode truth` does), lock-stepped on /clock; the simulated wearer starts 15 deg
// off the way to the exit and walks on /tactile/cue only.
//   expect: safe      -> no collision and the course completed (cue stage in the chain)
//   expect: collision -> at least one collision (cues:=false: the cue stage is not loaded; this
//                        proves the `safe` test fails when the cue stage is removed)
//   expect: stopped   -> (pipeline:=false: nothing answers) runTrial throws within seconds, the chain
//                        stopped (a vision pipeline that died once left a trial crawling for hours)
//   expect: movers    -> (a world with people, issue 22) every frame's /obstacles/movers came, in the
//                        grid's frame, each person exactly where personAt puts them at the frame's
//                        trial time (the planner of this branch does not avoid them: no collision check)
#include <cmath>
#include <cstdio>
#include <stdexcept>
#include <sys/stat.h>

#include <gtest/gtest.h>
#include <ros/ros.h>

#include <assistive_msgs/MoverArray.h>
#include <assistive_trials/ros_chain.h>
#include <assistive_trials/trials.h>

using namespace assistive_sim;
using namespace assistive_trials;

namespace
{
std::string worldPath(const std::string& w)
{
  struct stat st;
  const std::string dir = stat(ASSISTIVE_SIM_WORLDS_DIR, &st) == 0 ? ASSISTIVE_SIM_WORLDS_DIR : ".";
  return resolveWorldPath(w, dir);
}
}  // namespace

TEST(MobilityChain, WearerOnTheCuesOfTheChain)
{
  ros::NodeHandle nh, pnh("~");
  std::string world_name = "glass", expect = "safe";
  double yaw_off = 15.0;
  pnh.param("world", world_name, world_name);
  pnh.param("expect", expect, expect);
  pnh.param("start_yaw_deg", yaw_off, yaw_off);
  const World world = World::load(worldPath(world_name));

  TrialOptions opt;
  opt.wearer.eye_height = world.trajectory.eye_height;
  opt.wearer.walk_speed = world.trajectory.speed;
  opt.fixed_start_yaw_deg = yaw_off;
  opt.population = false;  // the typical wearer: the chain is tested here, the population in the trials
  // without the cue stage the vest is silent, and a silent vest stops the wearer (protocol): the
  // negative control gives it a vest that only ticks "walk on", so it walks straight on
  if (expect == "collision") opt.cues_enabled = false;
  RosChain::Options ro;
  ro.kind = RosChain::TRUTH_GRID;
  ro.eye_height = world.trajectory.eye_height;
  ro.wait_s = 5.0;
  if (expect == "stopped")
  {
    ro.wait_s = 0.2;
    ro.stopped_after_s = 1.0;
    RosChain silent(nh, world, ro);
    const ros::WallTime t0 = ros::WallTime::now();
    EXPECT_THROW(runTrial(world, opt, 1, 0, &silent), std::runtime_error);
    EXPECT_TRUE(silent.stopped());
    const double wall = (ros::WallTime::now() - t0).toSec();
    std::printf("mobility_chain: nothing answered, the trial ended after %.1f s of wall time, %ld frames\n", wall,
                silent.framesSent());
    EXPECT_LT(wall, 10.0);  // (a frame waits wait_s; the chain gives up after stopped_after_s)
    return;
  }
  RosChain chain(nh, world, ro);
  // The truth people on /obstacles/movers: stamp (trial time = stamp - start_time) -> message.
  std::vector<assistive_msgs::MoverArray> movers;
  ros::Subscriber movers_sub = nh.subscribe<assistive_msgs::MoverArray>(
      "/obstacles/movers", 50,
      boost::function<void(const assistive_msgs::MoverArray::ConstPtr&)>(
          [&movers](const assistive_msgs::MoverArray::ConstPtr& m) { movers.push_back(*m); }));

  // the planner must be listening before the first frame (its subscriptions are the chain's input)
  ros::NodeHandle probe;
  const ros::WallTime until = ros::WallTime::now() + ros::WallDuration(60.0);
  ros::Publisher dummy;
  while (ros::ok() && ros::WallTime::now() < until)
  {
    ros::master::V_TopicInfo topics;
    ros::master::getTopics(topics);
    bool state = false;
    for (const auto& t : topics) state |= t.name == "/planner/state";
    if (state) break;
    ros::WallDuration(0.2).sleep();
  }
  ros::WallDuration(2.0).sleep();  // subscriptions connect
  ros::spinOnce();

  const TrialResult r = runTrial(world, opt, 1, 0, &chain);
  int missed = r.missed_cues, frames = int(chain.framesSent());
  std::printf("mobility_chain %s: completed %d, time %.1f s (guide %.1f s), collisions %d (wall %d, overhang %d, glass %d, "
              "furniture %d), missed cues %d of %d frames, cue stage %s\n",
              world_name.c_str(), int(r.completed), r.time_s, r.guide_time_s, r.totalCollisions(), r.collisions[0],
              r.collisions[1], r.collisions[2], r.collisions[3], missed, frames,
              chain.cueStageConnected() ? "connected" : "absent");
  if (expect == "movers")
  {
    ASSERT_FALSE(world.people.empty()) << "expect:=movers needs a world with people";
    ros::WallDuration(0.2).sleep();
    ros::spinOnce();
    std::printf("mobility_chain %s: %zu movers messages for %d frames, %d people collisions\n", world_name.c_str(),
                movers.size(), frames, r.collisions[size_t(ObstacleKind::PERSON)]);
    EXPECT_GE(int(movers.size()), frames - 1);
    EXPECT_LE(int(movers.size()), frames);
    // the trial's people, who gave way to the wearer (issue 37): where the collider had them
    ASSERT_TRUE(r.people_give_way);
    ASSERT_EQ(r.people.size(), world.people.size());
    EXPECT_GE(r.give_way_episodes, 1);
    int aside = 0;  // published positions off the scripts: the chain sends the trial's people
    for (const auto& m : movers)
    {
      EXPECT_EQ(m.header.frame_id, ro.frame);
      ASSERT_EQ(m.movers.size(), world.people.size());
      const double t = m.header.stamp.toSec() - ro.start_time;
      for (size_t i = 0; i < world.people.size(); ++i)
      {
        const PersonState s = personAt(r.people[i], t);
        aside += (personScriptAt(world.people[i], t).position - s.position).norm() > 0.05;
        EXPECT_EQ(m.movers[i].id, i + 1);
        EXPECT_NEAR(m.movers[i].position.x, s.position.x(), 1e-6);
        EXPECT_NEAR(m.movers[i].position.y, s.position.y(), 1e-6);
        // The velocity jumps at a script's corner: the stamp (ns) may put t on either side of it.
        const Eigen::Vector2d v(m.movers[i].velocity.x, m.movers[i].velocity.y);
        bool v_ok = false;
        for (double dt : {0.0, -1e-6, 1e-6}) v_ok |= (v - personAt(r.people[i], t + dt).velocity).norm() < 1e-6;
        EXPECT_TRUE(v_ok) << "person " << i << " at t " << t;
      }
    }
    EXPECT_GT(aside, 0);
  }
  else if (expect == "collision")
  {
    EXPECT_GE(r.totalCollisions(), 1) << "without the cue stage the wearer walks straight 15 deg off and must collide";
  }
  else
  {
    EXPECT_EQ(r.totalCollisions(), 0);
    EXPECT_TRUE(r.completed);
    // lock-step: every frame's cue came back (a missing cue stage fails here too)
    EXPECT_LE(missed, frames / 100) << "frames without their cue";
  }
}

int main(int argc, char** argv)
{
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "test_mobility_chain");
  ros::NodeHandle nh;
  return RUN_ALL_TESTS();
}
