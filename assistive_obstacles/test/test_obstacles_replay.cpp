// Rostest (issue 32): one processing path from the device to the benchmarks. A bag rendered at
// test time (a world with people, reported as movers) is replayed frame by frame through the obstacle
// nodelet in ROS, with tf from the bag's ground truth (the VO is not under test) and the bag's
// forward ranger, and through ObstacleFrameProcessor in this process on the same inputs (the same
// parameters read from the nodelet's namespace, the same tf lookups through a tf2::BufferCore).
// Lockstep: the next frame goes out only once the nodelet answered the last one (its disparity,
// its movers, its grid when the processor gave one), so every frame is delivered. Asserts that
// both give the same grids (codes and geometry) and the same movers, frame by frame.
#include <gtest/gtest.h>

#include <cstdio>
#include <cstdlib>
#include <string>

#include <assistive_msgs/MoverArray.h>
#include <geometry_msgs/TransformStamped.h>
#include <nav_msgs/OccupancyGrid.h>
#include <ros/ros.h>
#include <sensor_msgs/CameraInfo.h>
#include <sensor_msgs/Image.h>
#include <sensor_msgs/Range.h>
#include <stereo_msgs/DisparityImage.h>
#include <tf2/buffer_core.h>
#include <tf2_eigen/tf2_eigen.h>
#include <tf2_ros/static_transform_broadcaster.h>
#include <tf2_ros/transform_broadcaster.h>

#include <assistive_common/ros_params.h>
#include <assistive_common/wearer.h>
#include <assistive_eval/conversions.h>
#include <assistive_eval/stereo_bag.h>
#include <assistive_sim/rendered_bag.h>
#include <assistive_obstacles/conversions.h>
#include <assistive_obstacles/frame_processor.h>
#include <assistive_sim/ultrasonic.h>

// One executable with test_obstacles_nodelet.cpp, which holds main() (issue 31: CMakeLists.txt); this
// file's names in a namespace of their own, apart from that file's.
namespace obstacles_replay_test
{

namespace eval = assistive_eval;
using namespace assistive_obstacles;

namespace
{
const std::string kWorld = "odom", kCamera = "camera_left_optical_frame";

nav_msgs::OccupancyGridConstPtr g_grid;
assistive_msgs::MoverArrayConstPtr g_movers;
stereo_msgs::DisparityImageConstPtr g_disp;
void gridCb(const nav_msgs::OccupancyGridConstPtr& m) { g_grid = m; }
void moversCb(const assistive_msgs::MoverArrayConstPtr& m) { g_movers = m; }
void dispCb(const stereo_msgs::DisparityImageConstPtr& m) { g_disp = m; }


/// The nodelet's parameters, read from its namespace as its onInit() reads them.
ObstaclesParams nodeletParams(ObstaclesNodeParams& node)
{
  ros::NodeHandle pnh("obstacles");
  ObstaclesParams p;
  assistive_common::readParams(pnh, p);
  assistive_common::readParams(pnh, node);
  bool overridden = false;
  assistive_common::wearerCameraHeight(pnh, node.camera_frame, node.footprint_frame, "camera_height", p.camera_height,
                                       &overridden);
  clampParams(p);
  return p;
}

template <class M>
bool waitFor(const M& msg, const ros::Time& stamp, double timeout_s)
{
  const ros::WallTime t0 = ros::WallTime::now();
  while (ros::ok() && (!msg || msg->header.stamp != stamp) && (ros::WallTime::now() - t0).toSec() < timeout_s)
  {
    ros::spinOnce();
    ros::WallDuration(0.002).sleep();
  }
  return msg && msg->header.stamp == stamp;
}
/// The test's topics: the nodelet's answers and its inputs, tf from the bag's truth.
struct Connections
{
  ros::Subscriber sg, sm, sd;
  ros::Publisher pl, pr, pli, pri, ps;
  tf2_ros::TransformBroadcaster tfb;
  tf2_ros::StaticTransformBroadcaster static_tfb;

  /// Subscribes and advertises, then waits (up to 60 s) until the nodelet is connected.
  explicit Connections(ros::NodeHandle& nh)
  {
    sg = nh.subscribe("obstacles/traversability", 5, gridCb);
    sm = nh.subscribe("obstacles/movers", 5, moversCb);
    sd = nh.subscribe("obstacles/disparity", 5, dispCb);
    pl = nh.advertise<sensor_msgs::Image>("/stereo/left/image_rect", 2);
    pr = nh.advertise<sensor_msgs::Image>("/stereo/right/image_rect", 2);
    pli = nh.advertise<sensor_msgs::CameraInfo>("/stereo/left/camera_info", 2);
    pri = nh.advertise<sensor_msgs::CameraInfo>("/stereo/right/camera_info", 2);
    ps = nh.advertise<sensor_msgs::Range>("/sonar/front", 50);
    const ros::WallTime t_start = ros::WallTime::now();
    while (ros::ok() && (pl.getNumSubscribers() == 0 || pr.getNumSubscribers() == 0 || pli.getNumSubscribers() == 0 ||
                         pri.getNumSubscribers() == 0 || ps.getNumSubscribers() == 0 || sg.getNumPublishers() == 0 ||
                         sm.getNumPublishers() == 0 || sd.getNumPublishers() == 0) &&
           (ros::WallTime::now() - t_start).toSec() < 60.0)
    {
      ros::spinOnce();
      ros::WallDuration(0.05).sleep();
    }
  }
};

/// Both sides of the replay: the nodelet in ROS, and the processor in this process with what
/// the nodelet's tf buffer holds; the counts of the frames.
struct Replay
{
  Replay(const ObstaclesParams& params, const ObstaclesNodeParams& node) : proc(params, node.octomap_insert_every) {}
  ObstacleFrameProcessor proc;
  tf2::BufferCore tf;  // what the nodelet's tf buffer holds, in this process
  std::vector<eval::RangeSample> ranges;
  size_t next_range = 0;
  int sent = 0, grids = 0, grids_equal = 0, movers_frames = 0, movers_seen = 0, answered = 0;

  /// The ranger's pose from the tf buffer, as the nodelet looks it up.
  bool rangePose(const RangeSample& s, Eigen::Isometry3f& T) const
  {
    try
    {
      T = tf2::transformToEigen(tf.lookupTransform(kWorld, s.frame, ros::Time(s.stamp))).cast<float>();
      return true;
    }
    catch (const tf2::TransformException&)
    {
      return false;
    }
  }
};

/// The ranger on the head: camera_link -> sonar_front (URDF) seen from the left optical frame,
/// to the nodelet (static tf) and to the test's buffer.
void sendRangerMount(Connections& c, Replay& r)
{
  geometry_msgs::TransformStamped mount =
      tf2::eigenToTransform(eval::linkToLeftOptical().inverse() * assistive_sim::linkToSonar());
  mount.header.frame_id = kCamera;
  mount.child_frame_id = r.ranges.front().frame_id;
  c.static_tfb.sendTransform(mount);
  r.tf.setTransform(mount, "test", true);
}

/// The frame's truth pose as tf (ground truth stands in for the VO: gt_world == odom), and the
/// ranger's readings up to the frame, to both sides.
void sendPoseAndRanges(const eval::StereoFrame& f, const std_msgs::Header& h, Connections& c, Replay& r)
{
  geometry_msgs::TransformStamped pose = tf2::eigenToTransform(f.gt_pose);
  pose.header.stamp = h.stamp;
  pose.header.frame_id = kWorld;  // ground truth stands in for the VO: gt_world == odom
  pose.child_frame_id = kCamera;
  c.tfb.sendTransform(pose);
  r.tf.setTransform(pose, "test");
  // The ranger's readings up to this frame go out before its images (the nodelet applies those
  // that arrived by then).
  for (; r.next_range < r.ranges.size() && r.ranges[r.next_range].stamp <= f.stamp; ++r.next_range)
  {
    const eval::RangeSample& rs = r.ranges[r.next_range];
    sensor_msgs::Range m;
    m.header.stamp = ros::Time(rs.stamp);
    m.header.frame_id = rs.frame_id;
    m.radiation_type = sensor_msgs::Range::ULTRASOUND;
    m.field_of_view = static_cast<float>(rs.field_of_view);
    m.min_range = static_cast<float>(rs.min_range);
    m.max_range = static_cast<float>(rs.max_range);
    m.range = static_cast<float>(rs.range);
    c.ps.publish(m);
    // As the nodelet receives it: sensor_msgs/Range carries float32, stamps in ns.
    r.proc.queueRange({ m.header.stamp.toSec(), m.range, m.min_range, m.max_range, m.field_of_view, m.header.frame_id });
  }
}

/// The nodelet's movers of the frame against the processor's.
void compareMovers(const ObstacleFrameResult& res, const ros::Time& stamp, Replay& r)
{
  ++r.movers_frames;
  EXPECT_TRUE(waitFor(g_movers, stamp, 10.0)) << "frame " << r.sent << ": no movers";
  if (!g_movers || g_movers->header.stamp != stamp) return;
  ASSERT_EQ(g_movers->movers.size(), res.movers.size()) << "frame " << r.sent;
  for (size_t i = 0; i < res.movers.size(); ++i)
  {
    EXPECT_EQ(g_movers->movers[i].id, static_cast<uint32_t>(res.movers[i].track.id)) << "frame " << r.sent;
    EXPECT_EQ(g_movers->movers[i].position.x, res.movers[i].track.position().x()) << "frame " << r.sent;
    EXPECT_EQ(g_movers->movers[i].position.y, res.movers[i].track.position().y()) << "frame " << r.sent;
  }
  r.movers_seen += static_cast<int>(res.movers.size());
}

/// The nodelet's grid of the frame against the processor's (codes and geometry); none from the
/// nodelet when the processor gave none.
void compareGrid(const ObstacleFrameResult& res, const ros::Time& stamp, Replay& r)
{
  if (!res.has_grid)
  {
    // No grid from the processor (the map is being rebuilt): none from the nodelet either (it
    // would come just after the frame's disparity).
    waitFor(g_grid, stamp, 0.2);
    EXPECT_FALSE(g_grid && g_grid->header.stamp == stamp) << "frame " << r.sent << ": a grid the processor withheld";
    return;
  }
  ++r.grids;
  ASSERT_TRUE(waitFor(g_grid, stamp, 10.0)) << "frame " << r.sent << ": the processor gave a grid, the nodelet none";
  const GridData got = fromMsg(*g_grid);
  EXPECT_EQ(got.origin_x, res.grid.origin_x) << "frame " << r.sent;
  EXPECT_EQ(got.origin_y, res.grid.origin_y) << "frame " << r.sent;
  EXPECT_EQ(got.resolution, static_cast<float>(res.grid.resolution)) << "frame " << r.sent;  // float32 in the message
  ASSERT_EQ(got.width, res.grid.width) << "frame " << r.sent;
  ASSERT_EQ(got.height, res.grid.height) << "frame " << r.sent;
  size_t differ = 0;
  for (size_t i = 0; i < got.data.size(); ++i) differ += got.data[i] != res.grid.data[i];
  EXPECT_EQ(differ, 0u) << "frame " << r.sent << ": cells that differ";
  r.grids_equal += differ == 0;
}

/// One frame: its pose and ranges out, the processor on it here, its images to the nodelet, and
/// the nodelet's answers (disparity, movers, grid) compared. `answered` false: the nodelet dropped it.
void replayFrame(const eval::StereoFrame& f, Connections& c, Replay& r, bool& answered)
{
  answered = false;
  ASSERT_TRUE(f.has_gt_pose);
  std_msgs::Header h;
  h.stamp = ros::Time(f.stamp);
  h.frame_id = kCamera;
  sendPoseAndRanges(f, h, c, r);
  ros::WallDuration(0.05).sleep();
  const sensor_msgs::CameraInfo li = eval::toCameraInfo(f.calib, false, h.frame_id, h.stamp),
                               ri = eval::toCameraInfo(f.calib, true, h.frame_id, h.stamp);
  ObstacleFrame in;
  ASSERT_TRUE(fromMsg(li, ri, in.model));
  in.stamp = h.stamp.toSec();
  in.left = f.left;
  in.right = f.right;
  in.T_world_cam = tf2::transformToEigen(r.tf.lookupTransform(kWorld, kCamera, h.stamp));
  const RangePoseLookup range_pose = [&r](const RangeSample& s, Eigen::Isometry3f& T) { return r.rangePose(s, T); };
  const ObstacleFrameResult& res = r.proc.process(in, range_pose);
  ASSERT_TRUE(res.disparity_ok);

  c.pli.publish(li);
  c.pri.publish(ri);
  c.pl.publish(eval::toImageMsg(f.left, h.frame_id, h.stamp));
  c.pr.publish(eval::toImageMsg(f.right, h.frame_id, h.stamp));
  ++r.sent;
  // Every frame is answered: its disparity, its movers (every frame the map took), its grid.
  const bool got_disp = waitFor(g_disp, h.stamp, 20.0);
  EXPECT_TRUE(got_disp) << "frame " << r.sent << " dropped by the nodelet";
  if (!got_disp) return;
  answered = true;
  ++r.answered;
  if (res.movers_enabled)
  {
    ASSERT_NO_FATAL_FAILURE(compareMovers(res, h.stamp, r));
  }
  compareGrid(res, h.stamp, r);
}
}  // namespace

TEST(ObstaclesReplay, NodeletGivesTheProcessorsGridsFrameByFrame)
{
  ros::NodeHandle nh, pnh("~");
  std::string world = "plaza_busy";
  int frames = 90;
  pnh.param("world", world, world);
  pnh.param("frames", frames, frames);
  const assistive_sim::RenderedBag rendered(world, frames, "obstacles_replay");
  const std::string& bag = rendered.path();
  ASSERT_FALSE(bag.empty()) << "render_bag failed on " << world << " (its output:\n" << rendered.log() << ")";

  Connections c(nh);
  ASSERT_GT(c.ps.getNumSubscribers(), 0u) << "nodelet did not subscribe";
  ASSERT_GT(c.sm.getNumPublishers(), 0u) << "nodelet does not publish movers";

  ObstaclesNodeParams node;
  const ObstaclesParams params = nodeletParams(node);
  ASSERT_EQ(node.world_frame, kWorld);
  Replay r(params, node);
  eval::StereoBagReader reader(bag);
  ASSERT_TRUE(reader.readRanges(r.ranges));
  ASSERT_FALSE(r.ranges.empty());
  sendRangerMount(c, r);

  eval::StereoFrame f;
  ros::Duration(0.5).sleep();  // the static mount reaches the nodelet's listener
  while (reader.next(f))
  {
    bool answered = false;
    replayFrame(f, c, r, answered);
    if (HasFatalFailure()) return;
    if (!answered) break;
  }
  std::printf("replay %s: %d frames sent, %d answered, %d grids (%d equal), %d frames with movers (%d movers)\n",
              world.c_str(), r.sent, r.answered, r.grids, r.grids_equal, r.movers_frames, r.movers_seen);
  EXPECT_EQ(r.sent, frames);
  EXPECT_EQ(r.answered, r.sent);
  EXPECT_EQ(r.grids, r.sent - (params.rebuild_frames - 1));  // the truth has depth at every frame
  EXPECT_EQ(r.grids_equal, r.grids);
  EXPECT_GT(r.proc.counters().ranges_echo + r.proc.counters().ranges_no_echo, 0);
}
}  // namespace obstacles_replay_test
