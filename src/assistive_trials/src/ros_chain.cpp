// RosChain (ros_chain.h): drives the planner/cue nodelets (or the whole pipeline with the
// renderer) one camera frame at a time on simulated time and waits for that frame's cue.
#include <assistive_trials/ros_chain.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cmath>
#include <thread>

#include <Eigen/Geometry>
#include <assistive_eval/conversions.h>
#include <assistive_eval/types.h>
#include <assistive_msgs/NavigationState.h>
#include <assistive_sim/people_msg.h>
#include <assistive_msgs/TactileCue.h>
#include <geometry_msgs/PoseStamped.h>
#include <geometry_msgs/TransformStamped.h>
#include <nav_msgs/OccupancyGrid.h>
#include <nav_msgs/Odometry.h>
#include <rosgraph_msgs/Clock.h>
#include <sensor_msgs/Image.h>
#include <sensor_msgs/Imu.h>
#include <std_msgs/Float64MultiArray.h>
#include <tf2_eigen/tf2_eigen.h>
#include <tf2_ros/transform_broadcaster.h>

namespace assistive_trials
{
// The simulator's world and its people as messages (assistive_sim), named as the chain always did.
using assistive_sim::OccupancyParams;
using assistive_sim::World;
using assistive_sim::peopleMessage;

struct RosChain::Impl
{
  Options o;
  ros::Publisher clock, odom, grid, goal, pose, imu, vest_imu, movers, give_way;
  const World* world = nullptr;
  const World* people = nullptr;  ///< the trial's people (setPeople; giving way: the trial's copy)
  // IMU by finite differences of the wearer's states (VISION)
  bool have_prev = false, have_prev2 = false;
  double prev_t = 0.0, prev_yaw = 0.0, prev_rate = 0.0;
  Eigen::Vector2d prev_xy = Eigen::Vector2d::Zero(), prev_v = Eigen::Vector2d::Zero();
  ros::Subscriber cue_sub, state_sub, image_sub;
  std::unique_ptr<tf2_ros::TransformBroadcaster> tf;
  nav_msgs::OccupancyGrid grid_msg;
  std::mutex m;
  // newest per stamp (sim time, ns) of what came back
  int64_t cue_stamp = -1, state_stamp = -1, image_stamp = -1;
  std::chrono::steady_clock::time_point last_answer = std::chrono::steady_clock::now();
  bool stopped = false;  ///< nothing came back for stopped_after_s (wall)
  assistive_msgs::TactileCue last_cue;
  assistive_msgs::NavigationState last_state;  // for the trace: what the cue logic was given
  std::chrono::steady_clock::time_point cue_wall, image_wall, sent_wall;
  double base = 100.0;  // sim time of this trial's t = 0
  double last_sent = 0.0;
  bool goal_pending = false, goal_known = false, warm = false;
  Eigen::Vector2d goal_xy = Eigen::Vector2d::Zero();
  Eigen::Isometry3d world_to_goal_frame = Eigen::Isometry3d::Identity();  // VISION: world -> map
  bool first_frame = true;
  long frames_since_goal = 0;
  bool trace = std::getenv("MOBILITY_TRIALS_TRACE") != nullptr;
};

namespace
{
Eigen::Isometry3d headLink(const BodyState& s, double eye_height, double pitch_down)
{
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.translation() = Eigen::Vector3d(s.xy.x(), s.xy.y(), eye_height);
  T.linear() = (Eigen::AngleAxisd(s.head_yaw, Eigen::Vector3d::UnitZ()) *
                Eigen::AngleAxisd(pitch_down, Eigen::Vector3d::UnitY()))
                   .toRotationMatrix();
  return T;
}
}  // namespace

RosChain::RosChain(ros::NodeHandle& nh, const World& world, const Options& o) : d_(new Impl)
{
  d_->o = o;
  d_->base = o.start_time;
  d_->clock = nh.advertise<rosgraph_msgs::Clock>("/clock", 1);
  d_->goal = nh.advertise<geometry_msgs::PoseStamped>("/planner/goal", 1, true);
  d_->people = &world;
  if (o.kind == TRUTH_GRID)
  {
    d_->odom = nh.advertise<nav_msgs::Odometry>("/vo/odom", 5);
    d_->grid = nh.advertise<nav_msgs::OccupancyGrid>("/obstacles/traversability", 1);
    // The truth people (issue 22) replace the obstacle stage's tracks as the truth grid replaces its map.
    if (!world.people.empty()) d_->movers = nh.advertise<assistive_msgs::MoverArray>("/obstacles/movers", 5);
    d_->world = &world;
    d_->tf.reset(new tf2_ros::TransformBroadcaster());
    OccupancyParams op;
    op.head_above_eye = 0.12;
    d_->grid_msg = assistive_eval::toMsg(computeOccupancy(world, op), o.frame, ros::Time(0));
  }
  else
  {
    d_->pose = nh.advertise<geometry_msgs::PoseStamped>("/sim/camera_pose", 1);
    // people who give way (issue 37): their tracks for the renderer, which draws and hears them
    if (!world.people.empty()) d_->give_way = nh.advertise<std_msgs::Float64MultiArray>("/sim/people_give_way", 10);
    d_->imu = nh.advertise<sensor_msgs::Imu>("/imu/data", 200);
    if (o.vest_gyro) d_->vest_imu = nh.advertise<sensor_msgs::Imu>("/vest/imu", 200);
    d_->image_sub = nh.subscribe<sensor_msgs::Image>("/stereo/left/image_rect", 2,
                                                     boost::function<void(const sensor_msgs::Image::ConstPtr&)>([this](const sensor_msgs::Image::ConstPtr& m) {
                                                       std::lock_guard<std::mutex> l(d_->m);
                                                       d_->image_stamp = int64_t(m->header.stamp.toNSec());
                                                       d_->image_wall = std::chrono::steady_clock::now();
                                                     }));
  }
  d_->cue_sub = nh.subscribe<assistive_msgs::TactileCue>("/tactile/cue", 10,
                                                         boost::function<void(const assistive_msgs::TactileCue::ConstPtr&)>([this](const assistive_msgs::TactileCue::ConstPtr& m) {
                                                           std::lock_guard<std::mutex> l(d_->m);
                                                           const int64_t s = int64_t(m->source_stamp.toNSec());
                                                           if (s <= d_->cue_stamp) return;  // a heartbeat repeat
                                                           d_->cue_stamp = s;
                                                           d_->last_cue = *m;
                                                           d_->cue_wall = std::chrono::steady_clock::now();
                                                         }));
  d_->state_sub = nh.subscribe<assistive_msgs::NavigationState>(
      "/planner/state", 10,
      boost::function<void(const assistive_msgs::NavigationState::ConstPtr&)>(
          [this](const assistive_msgs::NavigationState::ConstPtr& m) {
            std::lock_guard<std::mutex> l(d_->m);
            d_->state_stamp = std::max(d_->state_stamp, int64_t(m->source_stamp.toNSec()));
            d_->last_state = *m;
          }));
}

RosChain::~RosChain() = default;

bool RosChain::cueStageConnected() const { return d_->cue_sub.getNumPublishers() > 0; }

void RosChain::setPeople(const World& world) { d_->people = &world; }

void RosChain::publishGiveWay(double t)
{
  // [t, then per person its offset x, y (m) and its script's delay (s)]: the renderer adds them to
  // its own people's tracks (assistive_sim renderer nodelet, `people_give_way`)
  Impl& d = *d_;
  if (!d.give_way || !d.people || d.people->people.empty() || !d.people->people.front().give_way)
    return;
  std_msgs::Float64MultiArray m;
  m.data.reserve(1 + 3 * d.people->people.size());
  m.data.push_back(t);
  for (const assistive_sim::Person& p : d.people->people)
  {
    double delay = 0.0;
    const Eigen::Vector2d o = p.give_way ? p.give_way->at(t, nullptr, &delay) : Eigen::Vector2d::Zero();
    m.data.insert(m.data.end(), { o.x(), o.y(), delay });
  }
  d.give_way.publish(m);
}

void RosChain::reset(const BodyState& start)
{
  // The next trial starts 5 s of simulated time after the last frame: the planner sees a gap and
  // forgets the motion vector, the waypoint and the goal of the last trial (its own reset rule).
  d_->base = d_->first_frame && frames_ == 0 ? d_->o.start_time : d_->last_sent + 5.0;
  d_->first_frame = true;
  d_->goal_pending = d_->goal_known = false;
  d_->last_answer = std::chrono::steady_clock::now();  // (the wall time between trials is no silence)
  if (d_->o.kind == VISION)
  {
    // The pipeline's map starts at the first camera pose (the VO's origin): goals in the world go
    // through the start's camera_link pose, levelled.
    Eigen::Isometry3d odom = Eigen::Isometry3d::Identity();
    odom.translation() = Eigen::Vector3d(start.xy.x(), start.xy.y(), 0.0);
    odom.linear() = Eigen::AngleAxisd(start.head_yaw, Eigen::Vector3d::UnitZ()).toRotationMatrix();
    d_->world_to_goal_frame = odom.inverse();
    // The wearer stands still before walking: the VO takes gravity from the IMU at rest and its
    // first keyframe. Frames at t < 0 (their cues are not used).
    d_->have_prev = d_->have_prev2 = false;
    d_->base += d_->o.warmup_s;
    const double period = 1.0 / 15.0, dt = 1.0 / 60.0;
    d_->warm = true;
    for (double t = -d_->o.warmup_s; t < -1e-9; t += period)
    {
      for (double u = t - period + dt; u <= t + 1e-9; u += dt) publishImu(u, start);
      frame(t, start);
    }
    d_->warm = false;
    for (double u = -period + dt; u <= 1e-9; u += dt) publishImu(u, start);
  }
}

void RosChain::observe(double t, const BodyState& s)
{
  if (d_->o.kind == VISION) publishImu(t, s);
  if (d_->o.kind == VISION && d_->o.vest_gyro)
  {
    // an upright vest: its z axis is the vertical, its rate the torso's turn
    sensor_msgs::Imu m;
    m.header.stamp = ros::Time(d_->base + t);
    m.header.frame_id = "vest_imu";  // as the vest bridge publishes it (the URDF's link)
    m.orientation_covariance[0] = -1.0;
    const VestGyroSim::Sample v = d_->o.vest_gyro->sample(t, s);
    m.angular_velocity.z = v.rate_z;
    m.linear_acceleration.x = v.accel.x();
    m.linear_acceleration.y = v.accel.y();
    m.linear_acceleration.z = v.accel.z();
    d_->vest_imu.publish(m);
  }
}

void RosChain::publishImu(double t, const BodyState& s)
{
  Impl& d = *d_;
  // camera_link: the head at eye height, yawed and pitched down; specific force = R^T (a + g),
  // rate = R^T (0, 0, yaw rate) (the body does not pitch or roll)
  const Eigen::Isometry3d link = headLink(s, d.o.eye_height, d.o.pitch_down_deg * M_PI / 180.0);
  double rate = 0.0;
  Eigen::Vector2d v = Eigen::Vector2d::Zero(), a = Eigen::Vector2d::Zero();
  if (d.have_prev && t - d.prev_t > 1e-6)
  {
    const double h = t - d.prev_t;
    rate = std::atan2(std::sin(s.head_yaw - d.prev_yaw), std::cos(s.head_yaw - d.prev_yaw)) / h;
    v = (s.xy - d.prev_xy) / h;
    if (d.have_prev2) a = (v - d.prev_v) / h;
  }
  // The backward difference is the mean rate over the last step, half a step (8 ms at 60 Hz) behind
  // the stamp; a gyro samples the rate at its stamp, and the VO interpolates between samples. The
  // rate at the stamp: extrapolated by half a step from the last two means (exact for a steady
  // ramp). Without it the closed loop's gyro lagged the images by 8 ms: at the ends of turns on
  // the spot the VO's gyro prior pulled its pose 2 deg and 0.2 m off ("stereo pair inconsistent",
  // issue 34, h-pose4).
  const double rate_mean = rate;
  if (d.have_prev2)
    rate = rate_mean + 0.5 * (rate_mean - d.prev_rate);
  d.prev_rate = rate_mean;
  d.have_prev2 = d.have_prev;
  d.have_prev = true;
  d.prev_t = t;
  d.prev_yaw = s.head_yaw;
  d.prev_xy = s.xy;
  d.prev_v = v;
  const Eigen::Matrix3d Rt = link.linear().transpose();
  const Eigen::Vector3d w = Rt * Eigen::Vector3d(0, 0, rate);
  const Eigen::Vector3d f = Rt * Eigen::Vector3d(a.x(), a.y(), 9.81);
  sensor_msgs::Imu m;
  m.header.stamp = ros::Time(d.base + t);
  m.header.frame_id = "camera_link";
  m.orientation_covariance[0] = -1.0;
  m.angular_velocity.x = w.x();
  m.angular_velocity.y = w.y();
  m.angular_velocity.z = w.z();
  m.linear_acceleration.x = f.x();
  m.linear_acceleration.y = f.y();
  m.linear_acceleration.z = f.z();
  d.imu.publish(m);
}

void RosChain::setGoal(const Eigen::Vector2d& goal)
{
  d_->goal_xy = goal;
  d_->goal_pending = d_->goal_known = true;
}

bool RosChain::stopped() const
{
  return d_->stopped;
}

ChainCue RosChain::frame(double t, const BodyState& s)
{
  Impl& d = *d_;
  if (d.stopped)
    return ChainCue{};
  const ros::Time stamp(d.base + t);
  const int64_t ns = int64_t(stamp.toNSec());
  d.last_sent = d.base + t;
  rosgraph_msgs::Clock c;
  c.clock = stamp;
  d.clock.publish(c);

  if (d.o.kind == TRUTH_GRID)
  {
    const Eigen::Isometry3d link = headLink(s, d.o.eye_height, 0.0);
    geometry_msgs::TransformStamped tr = tf2::eigenToTransform(link);
    tr.header.stamp = stamp;
    tr.header.frame_id = d.o.frame;
    tr.child_frame_id = "camera_link";
    d.tf->sendTransform(tr);
    nav_msgs::Odometry od;
    od.header = tr.header;
    od.child_frame_id = "camera_link";
    od.pose.pose = tf2::toMsg(link);
    for (int i = 0; i < 6; ++i) od.pose.covariance[size_t(i * 7)] = 1e-4;
    d.odom.publish(od);
  }
  // The goal again every second: the planner drops it when it resets (a VO loss, a gap), as the
  // experimenter would say it again.
  if (++d.frames_since_goal >= 15) d.goal_pending = true;
  if ((d.goal_pending || d.first_frame) && d.goal_known)
  {
    d.frames_since_goal = 0;
    if (d.first_frame && d.o.kind == TRUTH_GRID)
      std::this_thread::sleep_for(std::chrono::milliseconds(30));  // the planner's reset on the gap comes first
    geometry_msgs::PoseStamped g;
    g.header.stamp = stamp;
    g.header.frame_id = d.o.kind == TRUTH_GRID ? d.o.frame : d.o.goal_frame;
    Eigen::Vector3d p(d.goal_xy.x(), d.goal_xy.y(), 0.0);
    if (d.o.kind == VISION) p = d.world_to_goal_frame * p;
    g.pose.position.x = p.x();
    g.pose.position.y = p.y();
    g.pose.orientation.w = 1.0;
    d.goal.publish(g);
    d.goal_pending = false;
  }
  if (d.o.kind == TRUTH_GRID)
  {
    // tf and the goal before the grid: the planner looks the pose up at the grid's stamp
    std::this_thread::sleep_for(std::chrono::milliseconds(d.first_frame ? 30 : 3));
    if (!d.people->people.empty()) d.movers.publish(peopleMessage(*d.people, t, stamp, d.o.frame));
    d.grid_msg.header.stamp = stamp;
    d.grid_msg.info.map_load_time = stamp;
    d.grid.publish(d.grid_msg);
  }
  else
  {
    publishGiveWay(t);  // (before the pose: the renderer draws the people aside in this frame)
    // the left optical frame for the renderer; the head pitched 15 deg down (the worlds' 10-30)
    const Eigen::Isometry3d opt =
        headLink(s, d.o.eye_height, d.o.pitch_down_deg * M_PI / 180.0) * assistive_eval::linkToLeftOptical();
    geometry_msgs::PoseStamped p;
    p.header.stamp = stamp;
    p.header.frame_id = "gt_world";
    p.pose = tf2::toMsg(opt);
    d.pose.publish(p);
  }
  d.first_frame = false;
  ++frames_;
  const auto sent = std::chrono::steady_clock::now();

  ChainCue out;
  out.received = false;
  using Clock = std::chrono::steady_clock;
  auto secs = [](double v) { return std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(v)); };
  Clock::time_point deadline = sent + secs(d.o.wait_s);
  bool grace_set = false, image_seen = false;
  if (d.warm) deadline = std::min(deadline, sent + secs(1.5));
  while (ros::ok() && std::chrono::steady_clock::now() < deadline)
  {
    ros::spinOnce();
    std::unique_lock<std::mutex> l(d.m);
    if (d.cue_stamp >= ns)
    {
      d.last_answer = Clock::now();
      out.received = d.cue_stamp == ns;
      const assistive_msgs::TactileCue& q = d.last_cue;
      for (size_t i = 0; i < 4; ++i) out.motors[i] = q.intensity[i];
      out.mode = int(q.mode);
      out.planner_status = d.state_stamp >= 0 ? int(d.last_state.status) : -1;
      out.pattern_id = q.pattern_id;
      out.pulse_on_ms = q.pulse_on_ms;
      out.pulse_off_ms = q.pulse_off_ms;
      out.pulse_count = q.pulse_count;
      out.instruction = q.instruction;
      out.level = q.level;
      const auto from = d.o.kind == VISION && d.image_stamp == ns ? d.image_wall : sent;
      out.latency_ms = std::chrono::duration<double, std::milli>(d.cue_wall - from).count();
      if (d.trace)
      {
        // the planner's state in its own frame (map): free distances ahead / left / right / along
        // the steering point, the steering point's and the walk's yaw, the waypoint's distance, the
        // crossing advice (NavigationState.crossing) and its person
        const assistive_msgs::NavigationState& n = d.last_state;
        std::fprintf(stderr,
                     "t %.2f xy %.2f %.2f yaw %.0f head %.0f | mode %d %.2f %.2f %.2f %.2f | %.0f ms | %s"
                     " | st %d free %.2f l %.2f r %.2f steer %.0f free %.2f walk %.0f v %.2f wp %.2f cross %d id %u\n",
                     t, s.xy.x(), s.xy.y(), s.yaw * 180 / M_PI, s.head_yaw * 180 / M_PI, out.mode, out.motors[0],
                     out.motors[1], out.motors[2], out.motors[3], out.latency_ms, q.reason.c_str(), int(n.status),
                     n.free_distance_ahead, n.free_distance_left, n.free_distance_right, n.steer_heading * 180 / M_PI,
                     n.free_distance_steer, n.walk_heading * 180 / M_PI, n.walking_speed, n.waypoint_distance,
                     int(n.crossing), n.crossing_id);
      }
      return out;
    }
    if (!image_seen && d.o.kind == VISION && d.image_stamp == ns)
    {
      // the frame is rendered: the pipeline gets 2 s (wall) for it, whatever it decides
      image_seen = true;
      d.last_answer = Clock::now();
      deadline = std::min(deadline, d.image_wall + secs(2.0));
    }
    if (!grace_set && d.state_stamp >= ns)
    {
      grace_set = true;
      d.last_answer = Clock::now();
      // no cue stage in the chain (nobody publishes /tactile/cue): nothing will come
      if (d.cue_sub.getNumPublishers() == 0) return out;
      deadline = std::min(deadline, Clock::now() + secs(d.o.grace_s));
    }
    l.unlock();
    std::this_thread::sleep_for(std::chrono::microseconds(500));
  }
  if (Clock::now() - d.last_answer > secs(d.o.stopped_after_s))
  {
    d.stopped = true;
    ROS_ERROR("mobility chain: no cue, image or planner state for %.0f s of wall time: the pipeline has stopped",
              d.o.stopped_after_s);
  }
  return out;
}
}  // namespace assistive_trials
