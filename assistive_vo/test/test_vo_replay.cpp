// rostest (issue 32): a rendered bag through the stereo_odometry nodelet in ROS, every frame
// delivered, and through VoFrontEnd in this process as vo_benchmark runs it (the bag read by
// assistive_eval's StereoBagReader): the same frames processed and the same poses, frame by frame.
// The frames go one at a time: the IMU samples up to the frame's stamp (as the bag reader hands
// them to the benchmark), a pause for them to be delivered (they come over their own connection),
// then the four image / camera_info messages, then a wait for that frame's vo/odom.
#include <gtest/gtest.h>
#include <unistd.h>
#include <cstdio>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <map>
#include <mutex>
#include <vector>
#include <nav_msgs/Odometry.h>
#include <ros/ros.h>
#include <rosbag/bag.h>
#include <rosbag/view.h>
#include <sensor_msgs/CameraInfo.h>
#include <sensor_msgs/Image.h>
#include <sensor_msgs/Imu.h>
#include <opencv2/core.hpp>
#include <assistive_common/ros_params.h>
#include <assistive_eval/stereo_bag.h>
#include "assistive_vo/conversions.h"
#include "assistive_vo/vo_front_end.h"
#include <assistive_sim/rendered_bag.h>

// One executable with test_vo_nodelet.cpp, which holds main() (issue 31: CMakeLists.txt); this
// file's names in a namespace of their own, apart from that file's.
namespace vo_replay_test
{

namespace
{
std::mutex mtx;
std::map<int64_t, nav_msgs::Odometry> ros_odom;  // stamp (ns) -> the nodelet's vo/odom

void odomCb(const nav_msgs::OdometryConstPtr& m)
{
  std::lock_guard<std::mutex> l(mtx);
  ros_odom[static_cast<int64_t>(m->header.stamp.toNSec())] = *m;
}

double angleBetween(const geometry_msgs::Quaternion& a, const geometry_msgs::Quaternion& b)
{
  const Eigen::Quaterniond qa(a.w, a.x, a.y, a.z), qb(b.w, b.x, b.y, b.z);
  return qa.angularDistance(qb);
}

/// The test's settings (private parameters of the rostest).
struct ReplaySetup
{
  std::string world = "course", node = "/replay_odometry";
  int frames = 60;
  double imu_pause_s = 0.05;
  // Diagnosis: the in-process run takes each frame's stamp as the nodelet does (ros::Time::toSec())
  // instead of the bag reader's ns * 1e-9 (1 ulp apart on about half the frames).
  bool header_stamps = false;
  assistive_vo::VoParams p;
  assistive_vo::VoNodeParams np;
};

ReplaySetup readSetup()
{
  ros::NodeHandle pnh("~");
  ReplaySetup s;
  pnh.param("world", s.world, s.world);
  pnh.param("frames", s.frames, s.frames);
  pnh.param("node", s.node, s.node);
  pnh.param("imu_pause", s.imu_pause_s, s.imu_pause_s);
  pnh.param("header_stamps", s.header_stamps, s.header_stamps);
  // The nodelet's parameters, read as the nodelet reads them (its params.h tables). No
  // robot_description here: camera_height is the parameter's, as in the nodelet.
  ros::NodeHandle node_nh(s.node);
  assistive_common::readParams(node_nh, s.p);
  assistive_common::readParams(node_nh, s.np);
  return s;
}

/// What the in-process run gave: every frame's stamp, the output of each processed frame.
struct InProcess
{
  // Frames are matched by their stamp in ns (the bag reader's f.stamp is ns * 1e-9, the nodelet's
  // header.stamp.toSec(): the two doubles can differ in the last bit).
  std::map<int64_t, assistive_vo::VoOutput> ours;  // stamp (ns) -> output of a processed frame
  std::vector<int64_t> stamps;
};

/// In process: the processor on the bag, as vo_benchmark runs it.
InProcess runInProcess(const ReplaySetup& s, const std::string& bag_path)
{
  InProcess r;
  cv::setNumThreads(1);  // as the benchmarks (the nodelet runs with OpenCV's default threads)
  assistive_eval::StereoBagReader reader(bag_path);
  assistive_vo::VoFrontEnd::Options o;
  o.input_has_imu = !reader.imuSamples().empty();
  o.imu_wait_s = s.np.imu_wait;
  assistive_vo::VoFrontEnd fe(s.p, o);
  assistive_eval::StereoFrame f;
  while (reader.next(f))
  {
    for (const auto& imu : f.imu)
      fe.addImu(imu.stamp, imu.gyro, imu.accel);
    const int64_t ns = std::llround(f.stamp * 1e9);
    if (s.header_stamps)
      f.stamp = ros::Time().fromNSec(static_cast<uint64_t>(ns)).toSec();
    const assistive_vo::FrontEndStep step =
        fe.process(assistive_vo::StereoCamera::from(f.calib), f.left, f.right, f.stamp);
    r.stamps.push_back(ns);
    if (step.processed && step.out.pose_valid && step.out.T_odom_link.matrix().allFinite())  // what the nodelet publishes
      r.ours[ns] = step.out;
  }
  cv::setNumThreads(-1);
  return r;
}

/// The bag's own messages: the IMU in order, and per frame stamp its left/right image + info.
struct BagMessages
{
  std::vector<sensor_msgs::ImuConstPtr> imus;
  std::map<int64_t, std::vector<rosbag::MessageInstance>> msgs;  // stamp -> left/right image + info
};

void readBagMessages(rosbag::Bag& bag, const assistive_eval::StereoBagTopics& topics, BagMessages& b)
{
  for (const rosbag::MessageInstance& m : rosbag::View(bag))
  {
    if (m.getTopic() == topics.imu)
      b.imus.push_back(m.instantiate<sensor_msgs::Imu>());
    else if (m.getTopic() == topics.left_image || m.getTopic() == topics.right_image)
      b.msgs[static_cast<int64_t>(m.instantiate<sensor_msgs::Image>()->header.stamp.toNSec())].push_back(m);
    else if (m.getTopic() == topics.left_info || m.getTopic() == topics.right_info)
      b.msgs[static_cast<int64_t>(m.instantiate<sensor_msgs::CameraInfo>()->header.stamp.toNSec())].push_back(m);
  }
}

/// Through ROS: the bag's own messages, one frame at a time, each answered by its vo/odom (a
/// processed frame) or given a short wait (one the in-process run did not process). The number of
/// processed frames whose vo/odom never came in `waited_out`.
void replayThroughRos(const ReplaySetup& s, const BagMessages& b, const assistive_eval::StereoBagTopics& topics,
                      const InProcess& in, int& waited_out)
{
  ros::NodeHandle nh;
  ros::Publisher li = nh.advertise<sensor_msgs::Image>("/replay/left/image_rect", 5);
  ros::Publisher ri = nh.advertise<sensor_msgs::Image>("/replay/right/image_rect", 5);
  ros::Publisher lc = nh.advertise<sensor_msgs::CameraInfo>("/replay/left/camera_info", 5);
  ros::Publisher rc = nh.advertise<sensor_msgs::CameraInfo>("/replay/right/camera_info", 5);
  ros::Publisher imu = nh.advertise<sensor_msgs::Imu>("/replay/imu/data", 2000);
  ros::Subscriber sub = nh.subscribe("/replay/odom", 100, odomCb);
  for (int i = 0; i < 300 && (li.getNumSubscribers() == 0 || ri.getNumSubscribers() == 0 || lc.getNumSubscribers() == 0 ||
                              rc.getNumSubscribers() == 0 || imu.getNumSubscribers() == 0 || sub.getNumPublishers() == 0);
       ++i)
    ros::Duration(0.1).sleep();
  ASSERT_GT(imu.getNumSubscribers(), 0u);
  ASSERT_GT(sub.getNumPublishers(), 0u);
  ros::Duration(0.5).sleep();

  size_t next_imu = 0;
  waited_out = 0;
  for (const auto& [t, fm] : b.msgs)
  {
    for (; next_imu < b.imus.size() && static_cast<int64_t>(b.imus[next_imu]->header.stamp.toNSec()) <= t; ++next_imu)
      imu.publish(b.imus[next_imu]);
    ros::Duration(s.imu_pause_s).sleep();
    for (const auto& m : fm)
    {
      const bool left = m.getTopic() == topics.left_image || m.getTopic() == topics.left_info;
      if (auto im = m.instantiate<sensor_msgs::Image>())
        (left ? li : ri).publish(im);
      else if (auto ci = m.instantiate<sensor_msgs::CameraInfo>())
        (left ? lc : rc).publish(ci);
    }
    // A processed frame: wait for its vo/odom (every processed frame publishes); a frame the
    // in-process run did not process (waiting for the IMU): a short wait that nothing comes.
    const double limit = in.ours.count(t) ? 20.0 : 0.5;
    const ros::WallTime until = ros::WallTime::now() + ros::WallDuration(limit);
    bool got = false;
    while (!got && ros::WallTime::now() < until)
    {
      ros::WallDuration(0.002).sleep();
      std::lock_guard<std::mutex> l(mtx);
      got = ros_odom.count(t) > 0;
    }
    waited_out += in.ours.count(t) && !got;
  }
  ros::Duration(0.5).sleep();
}

/// Frame by frame: the nodelet's vo/odom against the in-process output as the nodelet would
/// publish it (toOdometryMsg); the same frames published, bit-identical poses and covariances.
void compareFrameByFrame(const ReplaySetup& s, const InProcess& in, int waited_out)
{
  std::lock_guard<std::mutex> l(mtx);
  std::string which;  // per frame: B both, I in-process only, R ROS only, - neither
  for (int64_t t : in.stamps)
    which += ros_odom.count(t) ? (in.ours.count(t) ? 'B' : 'R') : (in.ours.count(t) ? 'I' : '-');
  std::printf("frames published (B both, I in-process only, R ROS only): %s\n", which.c_str());
  EXPECT_EQ(waited_out, 0) << "frames whose vo/odom never came: " << which;
  EXPECT_EQ(ros_odom.size(), in.ours.size()) << "the nodelet published for other frames than the in-process run";
  double max_dpos = 0, max_drot = 0, max_dcov = 0;
  int compared = 0, exact = 0;
  for (size_t k = 0; k < in.stamps.size(); ++k)
  {
    const int64_t t = in.stamps[k];
    const auto a = ros_odom.find(t);
    const auto b = in.ours.find(t);
    ASSERT_EQ(a != ros_odom.end(), b != in.ours.end()) << "frame " << k << " published by only one of the two";
    if (b == in.ours.end())
      continue;
    // The in-process output as the nodelet would publish it (toOdometryMsg): the message carries
    // the translation and the covariances as they are and the rotation as a quaternion.
    const nav_msgs::Odometry e = assistive_vo::toOdometryMsg(b->second, a->second.header.stamp, "odom", "camera_link");
    const nav_msgs::Odometry& r = a->second;
    const double dpos = std::hypot(r.pose.pose.position.x - e.pose.pose.position.x,
                                   r.pose.pose.position.y - e.pose.pose.position.y,
                                   r.pose.pose.position.z - e.pose.pose.position.z);
    const double drot = angleBetween(r.pose.pose.orientation, e.pose.pose.orientation);
    double dcov = 0;
    for (size_t i = 0; i < 36; ++i)
      dcov = std::max({dcov, std::abs(r.pose.covariance[i] - e.pose.covariance[i]),
                       std::abs(r.twist.covariance[i] - e.twist.covariance[i])});
    // Tolerance: the same code on the same inputs is bit-identical (OpenCV's threads split work
    // per pixel / per track, not the arithmetic); 1e-9 m / rad leaves room for nothing else.
    EXPECT_LT(dpos, 1e-9) << "frame " << k << " t=" << t << " ns";
    EXPECT_LT(drot, 1e-9) << "frame " << k << " t=" << t << " ns";
    EXPECT_LT(dcov, 1e-9) << "frame " << k << " t=" << t << " ns";
    EXPECT_EQ(r.pose.covariance[0] >= assistive_vo::kUntrustedVariance, !b->second.pose_trusted) << "frame " << k;
    max_dpos = std::max(max_dpos, dpos);
    max_drot = std::max(max_drot, drot);
    max_dcov = std::max(max_dcov, dcov);
    exact += dpos == 0 && drot == 0 && dcov == 0;
    ++compared;
  }
  EXPECT_GE(compared, s.frames * 9 / 10 - 2);
  std::printf("replay vs in-process: %zu frames, %d compared, %d bit-identical; max position diff %.3g m, "
              "rotation %.3g rad, covariance %.3g\n",
              in.stamps.size(), compared, exact, max_dpos, max_drot, max_dcov);
}
}  // namespace

TEST(VoReplay, NodeletAndFrontEndGiveTheSamePosesFrameByFrame)
{
  const ReplaySetup s = readSetup();
  const assistive_sim::RenderedBag rendered(s.world, s.frames, "vo_replay");
  const std::string& bag_path = rendered.path();
  ASSERT_FALSE(bag_path.empty()) << "render_bag failed (world " << s.world << ")";

  // ---- in process: the processor on the bag, as vo_benchmark runs it
  const InProcess in = runInProcess(s, bag_path);
  ASSERT_GE(static_cast<int>(in.stamps.size()), s.frames * 9 / 10);
  ASSERT_GE(in.ours.size(), in.stamps.size() - 2) << "the in-process run must track the walk";

  // ---- through ROS: the bag's own messages, one frame at a time
  rosbag::Bag bag(bag_path);
  const assistive_eval::StereoBagTopics topics;
  BagMessages b;
  readBagMessages(bag, topics, b);
  ASSERT_EQ(b.msgs.size(), in.stamps.size());
  int waited_out = 0;
  ASSERT_NO_FATAL_FAILURE(replayThroughRos(s, b, topics, in, waited_out));

  // ---- compare
  compareFrameByFrame(s, in, waited_out);
}
}  // namespace vo_replay_test
