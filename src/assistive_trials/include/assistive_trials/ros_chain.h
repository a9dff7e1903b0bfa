#pragma once
// The mobility trials' chain over ROS (issue 19): the planner and cue logic nodelets (and, in
// vision mode, the renderer and the whole pipeline) run in a nodelet manager as pipeline.launch
// loads them; this class drives them one camera frame at a time on simulated time (/clock) and
// waits for the cue of that frame (lock-step), so a slow machine changes the wall time, never the
// result. The wearer still reacts only to /tactile/cue.
//
// TRUTH_GRID (the `mobility_chain` rostest): per frame /clock, tf odom -> camera_link (the
// wearer's head), /vo/odom (trusted) and the world's true occupancy on /obstacles/traversability,
// all stamped with the frame's time, and the world's people (if any) on /obstacles/movers
// (assistive_msgs/MoverArray in the same frame, at the trial's time t: the truth tracks); the
// planner/state and the cue follow. The `world` must outlive the chain.
// VISION (`mobility_trials --mode vision`): per frame /clock and the left camera's pose on
// /sim/camera_pose; the renderer nodelet renders the pair, VO, SLAM, obstacles, planner and cue
// logic do the rest. The explicit goals go to /planner/goal in the pipeline's map frame.
#include <deque>
#include <memory>
#include <mutex>
#include <string>

#include <ros/ros.h>

#include <assistive_trials/trials.h>
#include <assistive_sim/world.h>

namespace assistive_trials
{
class RosChain : public CueChain
{
public:
  enum Kind
  {
    TRUTH_GRID,
    VISION
  };
  struct Options
  {
    Kind kind = TRUTH_GRID;
    double wait_s = 10.0;     ///< wall s to wait for a frame's cue before giving up on it
    double grace_s = 1.0;     ///< wall s to wait for the cue once the frame's planner state came (none: at once
                              ///< when nobody publishes /tactile/cue)
    /// wall s without a cue, a rendered image or a planner state from any frame: the pipeline has
    /// stopped (its nodelet manager died, its bonds broke under load); frame() then returns at once
    /// and stopped() says so (before, each frame waited wait_s: a trial crawled for hours)
    double stopped_after_s = 120.0;
    double start_time = 100.0;///< simulated clock at t = 0 of the first trial
    std::string frame = "odom";    ///< TRUTH_GRID: the planner's world frame
    std::string goal_frame = "map";   ///< VISION: the goals' frame: SLAM's map, which starts as the VO's
                                      ///< odom (on the floor under the camera's start, x along its
                                      ///< heading); the planner keeps a goal in map through a VO reset
                                      ///< (one in odom is dropped then: issue 34)
    double eye_height = 1.6;
    double pitch_down_deg = 15.0;  ///< VISION: the head's pitch (the worlds' scripts: 10-30 deg)
    double warmup_s = 1.0;         ///< VISION: the wearer stands this long before each trial (the VO
                                   ///< takes gravity from 0.5 s of IMU at rest)
    /// VISION: the vest's own gyro, published on /vest/imu (sensor_msgs/Imu, an upright vest) at
    /// every body step; null: the vest has none
    std::shared_ptr<VestGyroSim> vest_gyro;
  };
  RosChain(ros::NodeHandle& nh, const assistive_sim::World& world, const Options& o);
  ~RosChain() override;

  void reset(const BodyState& start) override;
  void setGoal(const Eigen::Vector2d& goal) override;
  void setPeople(const assistive_sim::World& world) override;
  ChainCue frame(double t, const BodyState& s) override;
  void observe(double t, const BodyState& s) override;
  bool stopped() const override;

  /// Whether a /tactile/cue publisher exists (the cue stage is in the chain).
  bool cueStageConnected() const;
  long framesSent() const { return frames_; }

private:
  struct Impl;
  std::unique_ptr<Impl> d_;
  void publishImu(double t, const BodyState& s);
  /// VISION: the people's give-way offsets and delays at trial time `t` for the renderer.
  void publishGiveWay(double t);
  long frames_ = 0;
};
}  // namespace assistive_trials
