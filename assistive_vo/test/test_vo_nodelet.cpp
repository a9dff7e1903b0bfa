// rostest: render a short bag, play it through the stereo_odometry nodelet, compare vo/odom with
// /ground_truth/odom; then feed unsynchronised input and expect a diagnostics error, no crash.
#include <gtest/gtest.h>
#include <unistd.h>
#include <cstdlib>
#include <map>
#include <set>
#include <mutex>
#include <thread>
#include <diagnostic_msgs/DiagnosticArray.h>
#include <nav_msgs/Odometry.h>
#include <rosbag/bag.h>
#include <rosbag/view.h>
#include <sensor_msgs/Imu.h>
#include <ros/ros.h>
#include <sensor_msgs/CameraInfo.h>
#include <sensor_msgs/Image.h>
#include <tf2_eigen/tf2_eigen.h>
#include <tf2_msgs/TFMessage.h>
#include "assistive_vo/frames.h"
#include <assistive_sim/rendered_bag.h>

namespace
{
std::mutex mtx;
std::map<double, Eigen::Isometry3d> est, gt;  // stamp -> pose of the left optical frame
int nan_poses = 0;
std::vector<diagnostic_msgs::DiagnosticStatus> diags;

Eigen::Isometry3d poseOf(const geometry_msgs::Pose& p)
{
  Eigen::Isometry3d T;
  tf2::fromMsg(p, T);
  return T;
}
void odomCb(const nav_msgs::OdometryConstPtr& m)
{
  std::lock_guard<std::mutex> l(mtx);
  Eigen::Isometry3d T_odom_link = poseOf(m->pose.pose);
  if (!T_odom_link.matrix().allFinite())
  {
    ++nan_poses;
    return;
  }
  EXPECT_EQ(m->header.frame_id, "odom");
  EXPECT_EQ(m->child_frame_id, "camera_link");
  Eigen::Isometry3d T_link_opt = Eigen::Isometry3d::Identity();
  T_link_opt.linear() = assistive_vo::R_link_optical();
  est[m->header.stamp.toSec()] = T_odom_link * T_link_opt;
}
void gtCb(const nav_msgs::OdometryConstPtr& m)
{
  std::lock_guard<std::mutex> l(mtx);
  gt[m->header.stamp.toSec()] = poseOf(m->pose.pose);
}
void diagCb(const diagnostic_msgs::DiagnosticArrayConstPtr& m)
{
  std::lock_guard<std::mutex> l(mtx);
  for (const auto& s : m->status)
    if (s.name.find("stereo_odometry") != std::string::npos || s.hardware_id == "stereo_visual_odometry")
      diags.push_back(s);
}
}  // namespace

TEST(VoNodelet, ReplayMatchesGroundTruth)
{
  ros::NodeHandle nh, pnh("~");
  std::string world = "course";
  int frames = 75;
  double rate = 0.5;
  pnh.param("world", world, world);
  pnh.param("frames", frames, frames);
  pnh.param("play_rate", rate, rate);
  const assistive_sim::RenderedBag rendered(world, frames, "vo_rostest");
  const std::string& bag = rendered.path();
  ASSERT_FALSE(bag.empty()) << "render_bag failed (world " << world << ")";

  // wait until the nodelet subscribes to the images
  for (int i = 0; i < 200; ++i)
  {
    if (ros::topic::waitForMessage<diagnostic_msgs::DiagnosticArray>("/diagnostics", nh, ros::Duration(0.1)))
      break;
  }
  ros::Duration(1.0).sleep();
  // stdin from /dev/null: rosbag play reads keys from its stdin, and a space pauses it for good
  const std::string play = "rosbag play -q -r " + std::to_string(rate) + " " + bag + " < /dev/null";
  ASSERT_EQ(std::system(play.c_str()), 0);
  ros::Duration(2.0).sleep();

  std::lock_guard<std::mutex> l(mtx);
  EXPECT_EQ(nan_poses, 0);
  ASSERT_GE(static_cast<int>(gt.size()), frames * 9 / 10);
  // at least 80 % of the frames must have produced an odometry message
  EXPECT_GE(static_cast<int>(est.size()), frames * 8 / 10);
  // compare relative to the first common stamp (first-pose alignment)
  bool first = true;
  Eigen::Isometry3d E0, G0;
  double path = 0, max_err = 0;
  Eigen::Vector3d last_g;
  Eigen::Isometry3d last_rel_e = Eigen::Isometry3d::Identity();
  double max_step = 0;
  int matched = 0;
  for (const auto& [t, E] : est)
  {
    auto it = gt.lower_bound(t - 1e-4);
    if (it == gt.end() || std::abs(it->first - t) > 1e-3)
      continue;
    const Eigen::Isometry3d& G = it->second;
    if (first)
    {
      E0 = E;
      G0 = G;
      last_g = G.translation();
      first = false;
    }
    const Eigen::Isometry3d re = E0.inverse() * E, rg = G0.inverse() * G;
    path += (G.translation() - last_g).norm();
    last_g = G.translation();
    max_err = std::max(max_err, (re.translation() - rg.translation()).norm());
    max_step = std::max(max_step, (re.translation() - last_rel_e.translation()).norm());
    last_rel_e = re;
    ++matched;
  }
  ASSERT_GE(matched, frames * 8 / 10);
  EXPECT_GT(path, 2.0);
  // 5 s of walking: the error stays within 3 % of the distance walked, no pose jumps
  EXPECT_LT(max_err, 0.03 * path) << "path " << path << " m";
  EXPECT_LT(max_step, 0.25);  // 1.1 m/s at 15 Hz is 7 cm per frame; frames may be dropped
  // diagnostics: tracking reported
  bool tracking = false;
  for (const auto& d : diags)
    for (const auto& kv : d.values)
      if (kv.key == "state" && kv.value == "tracking")
        tracking = true;
  EXPECT_TRUE(tracking);
}

TEST(VoNodelet, UnsynchronisedInputIsReportedWithoutCrash)
{
  ros::NodeHandle nh;
  ros::Publisher li = nh.advertise<sensor_msgs::Image>("/stereo/left/image_rect", 5);
  ros::Publisher ri = nh.advertise<sensor_msgs::Image>("/stereo/right/image_rect", 5);
  ros::Publisher lc = nh.advertise<sensor_msgs::CameraInfo>("/stereo/left/camera_info", 5);
  ros::Publisher rc = nh.advertise<sensor_msgs::CameraInfo>("/stereo/right/camera_info", 5);
  {
    std::lock_guard<std::mutex> l(mtx);
    diags.clear();
  }
  ros::Duration(1.0).sleep();
  sensor_msgs::Image img;
  img.width = 64;
  img.height = 48;
  img.encoding = "mono8";
  img.step = 64;
  img.data.assign(64 * 48, 100);
  sensor_msgs::CameraInfo ci;
  ci.width = 64;
  ci.height = 48;
  ci.P = {50, 0, 32, 0, 0, 50, 24, 0, 0, 0, 1, 0};
  bool reported = false;
  for (int i = 0; i < 150 && !reported; ++i)
  {
    const ros::Time t = ros::Time::now();
    img.header.stamp = ci.header.stamp = t;
    li.publish(img);
    lc.publish(ci);
    img.header.stamp = ci.header.stamp = t + ros::Duration(0.013);  // right stamps differ
    sensor_msgs::CameraInfo cr = ci;
    cr.P[3] = -50 * 0.1;
    ri.publish(img);
    rc.publish(cr);
    ros::Duration(0.066).sleep();
    std::lock_guard<std::mutex> l(mtx);
    for (const auto& d : diags)
      if (d.level == diagnostic_msgs::DiagnosticStatus::ERROR && d.message.find("synchronised") != std::string::npos)
        reported = true;
  }
  EXPECT_TRUE(reported);
  std::lock_guard<std::mutex> l(mtx);
  EXPECT_EQ(nan_poses, 0);
}

// The IMU and image subscriptions connect independently, so the first images can arrive before any
// IMU sample. A second nodelet instance (`late_imu_odometry`, on /late/...) gets 5 stereo frames of
// a rendered walk without IMU, then the IMU and the rest: it must wait for the IMU rather than
// start with a level camera (the head is pitched 10-30 deg down on the course), so its first pose
// has the true gravity direction.
std::mutex late_mtx;
std::map<double, Eigen::Isometry3d> late_est;
void lateOdomCb(const nav_msgs::OdometryConstPtr& m)
{
  std::lock_guard<std::mutex> l(late_mtx);
  Eigen::Isometry3d T_link_opt = Eigen::Isometry3d::Identity();
  T_link_opt.linear() = assistive_vo::R_link_optical();
  late_est[m->header.stamp.toSec()] = poseOf(m->pose.pose) * T_link_opt;
}

TEST(VoNodelet, WaitsForTheImuBeforeFixingGravity)
{
  ros::NodeHandle nh;
  const assistive_sim::RenderedBag rendered("course", 20, "vo_rostest");
  const std::string& bag_path = rendered.path();
  ASSERT_FALSE(bag_path.empty()) << "render_bag failed";
  ros::Publisher li = nh.advertise<sensor_msgs::Image>("/late/left/image_rect", 5);
  ros::Publisher ri = nh.advertise<sensor_msgs::Image>("/late/right/image_rect", 5);
  ros::Publisher lc = nh.advertise<sensor_msgs::CameraInfo>("/late/left/camera_info", 5);
  ros::Publisher rc = nh.advertise<sensor_msgs::CameraInfo>("/late/right/camera_info", 5);
  ros::Publisher imu = nh.advertise<sensor_msgs::Imu>("/late/imu/data", 2000);
  ros::Subscriber sub = nh.subscribe("/late/odom", 100, lateOdomCb);
  for (int i = 0; i < 100 && (li.getNumSubscribers() == 0 || imu.getNumSubscribers() == 0); ++i)
    ros::Duration(0.1).sleep();
  ASSERT_GT(imu.getNumSubscribers(), 0u);
  ros::Duration(0.5).sleep();

  rosbag::Bag bag(bag_path);
  std::vector<sensor_msgs::ImuConstPtr> imus;
  std::map<double, std::vector<rosbag::MessageInstance>> frames;  // stamp -> left/right image + info
  std::map<double, Eigen::Isometry3d> truth;
  for (const rosbag::MessageInstance& m : rosbag::View(bag))
  {
    if (auto i = m.instantiate<sensor_msgs::Imu>())
      imus.push_back(i);
    else if (auto o = m.instantiate<nav_msgs::Odometry>())
      truth[o->header.stamp.toSec()] = poseOf(o->pose.pose);
    else if (auto im = m.instantiate<sensor_msgs::Image>())
      frames[im->header.stamp.toSec()].push_back(m);
    else if (auto ci = m.instantiate<sensor_msgs::CameraInfo>())
      frames[ci->header.stamp.toSec()].push_back(m);
  }
  ASSERT_GE(frames.size(), 15u);
  double imu_from = -1;
  size_t next_imu = 0, k = 0;
  for (const auto& f : frames)
  {
    if (k++ == 5)
      imu_from = f.first;
    if (imu_from > 0)  // from the 6th frame: every IMU sample up to this frame first
      for (; next_imu < imus.size() && imus[next_imu]->header.stamp.toSec() <= f.first + 1e-6; ++next_imu)
        imu.publish(imus[next_imu]);
    for (const auto& m : f.second)
    {
      const bool left = m.getTopic().find("left") != std::string::npos;
      if (auto im = m.instantiate<sensor_msgs::Image>())
        (left ? li : ri).publish(im);
      else if (auto ci = m.instantiate<sensor_msgs::CameraInfo>())
        (left ? lc : rc).publish(ci);
    }
    ros::Duration(0.1).sleep();
  }
  ros::Duration(1.0).sleep();

  std::lock_guard<std::mutex> l(late_mtx);
  ASSERT_FALSE(late_est.empty()) << "no odometry once the IMU came";
  const double first = late_est.begin()->first;
  EXPECT_GE(first, imu_from - 1e-6) << "odometry started before any IMU sample";
  ASSERT_TRUE(truth.count(first));
  // gravity (up) in the optical frame: estimate against truth; the start is already walking, so
  // the accelerometer mean carries some forward acceleration (a few degrees)
  const Eigen::Vector3d up_est = late_est.begin()->second.linear().transpose() * Eigen::Vector3d::UnitZ();
  const Eigen::Vector3d up_true = truth[first].linear().transpose() * Eigen::Vector3d::UnitZ();
  const double tilt_err = std::acos(std::clamp(up_est.dot(up_true), -1.0, 1.0)) * 180.0 / M_PI;
  const double head_pitch = std::asin(std::clamp(-up_true.z(), -1.0, 1.0)) * 180.0 / M_PI;  // optical z forward: > 0 down
  EXPECT_GT(std::abs(head_pitch), 8.0) << "the walk must start with the head pitched for this test to mean anything";
  EXPECT_LT(tilt_err, 6.0) << "head pitch " << head_pitch << " deg down";
  std::printf("late IMU start: first pose %.3f s after the first image, tilt error %.2f deg, head pitch %.1f deg\n",
              first - frames.begin()->first, tilt_err, head_pitch);
}

/// One nodelet instance's inputs under a namespace ("/fs"): both images and camera infos and the IMU.
struct StereoImuInputs
{
  ros::Publisher li, ri, lc, rc, imu;
  StereoImuInputs(ros::NodeHandle& nh, const std::string& ns)
    : li(nh.advertise<sensor_msgs::Image>(ns + "/left/image_rect", 5))
    , ri(nh.advertise<sensor_msgs::Image>(ns + "/right/image_rect", 5))
    , lc(nh.advertise<sensor_msgs::CameraInfo>(ns + "/left/camera_info", 5))
    , rc(nh.advertise<sensor_msgs::CameraInfo>(ns + "/right/camera_info", 5))
    , imu(nh.advertise<sensor_msgs::Imu>(ns + "/imu/data", 2000))
  {
  }
  /// Waits up to 10 s until the nodelet subscribes to all five; true when it has.
  bool connect() const
  {
    for (int i = 0; i < 100 && !connected(); ++i)
      ros::Duration(0.1).sleep();
    return connected();
  }
  bool connected() const
  {
    return li.getNumSubscribers() > 0 && ri.getNumSubscribers() > 0 && lc.getNumSubscribers() > 0 &&
           rc.getNumSubscribers() > 0 && imu.getNumSubscribers() > 0;
  }
};

/// A bag's IMU samples in order, and its camera messages grouped by stamp (one entry per frame).
void readImuAndFrames(const rosbag::Bag& bag, std::vector<sensor_msgs::ImuConstPtr>& imus,
                      std::map<double, std::vector<rosbag::MessageInstance>>& frames)
{
  for (const rosbag::MessageInstance& m : rosbag::View(bag))
  {
    if (auto i = m.instantiate<sensor_msgs::Imu>())
      imus.push_back(i);
    else if (auto im = m.instantiate<sensor_msgs::Image>())
      frames[im->header.stamp.toSec()].push_back(m);
    else if (auto ci = m.instantiate<sensor_msgs::CameraInfo>())
      frames[ci->header.stamp.toSec()].push_back(m);
  }
}

// Fail-safe (README "Published topics"): a third instance (`failsafe_odometry`, on /fs/..., frames
// fs_odom -> fs_camera_link) gets 8 frames of a rendered walk, then black frames with the IMU going
// on. Once lost beyond coast_max, every frame still publishes vo/odom, with the last trusted pose,
// 9999 variances and zero twist, and no tf.
std::mutex fs_mtx;
std::map<double, nav_msgs::Odometry> fs_odom;
std::set<double> fs_tf;
void fsOdomCb(const nav_msgs::OdometryConstPtr& m)
{
  std::lock_guard<std::mutex> l(fs_mtx);
  fs_odom[m->header.stamp.toSec()] = *m;
}
void fsTfCb(const tf2_msgs::TFMessageConstPtr& m)
{
  std::lock_guard<std::mutex> l(fs_mtx);
  for (const auto& t : m->transforms)
    if (t.header.frame_id == "fs_odom" && t.child_frame_id == "fs_camera_link")
      fs_tf.insert(t.header.stamp.toSec());
}

TEST(VoNodelet, UntrustedFramesPublishNullCovarianceAndNoTf)
{
  ros::NodeHandle nh;
  // 8 good frames, then 52 black ones (3.5 s at 15 Hz): longer than any coasting allows
  // (imu_coast_max 2.5 s with a fitted velocity, coast_max 0.3 s without), whichever applies.
  const assistive_sim::RenderedBag rendered("course", 60, "vo_rostest");
  const std::string& bag_path = rendered.path();
  ASSERT_FALSE(bag_path.empty()) << "render_bag failed";
  StereoImuInputs in(nh, "/fs");
  ros::Publisher &li = in.li, &ri = in.ri, &lc = in.lc, &rc = in.rc, &imu = in.imu;
  ros::Subscriber sub = nh.subscribe("/fs/odom", 100, fsOdomCb);
  ros::Subscriber tsub = nh.subscribe("/tf", 1000, fsTfCb);
  in.connect();
  ASSERT_GT(imu.getNumSubscribers(), 0u);
  ros::Duration(0.5).sleep();

  rosbag::Bag bag(bag_path);
  std::vector<sensor_msgs::ImuConstPtr> imus;
  std::map<double, std::vector<rosbag::MessageInstance>> frames;
  readImuAndFrames(bag, imus, frames);
  ASSERT_GE(frames.size(), 58u);
  const int n_good = 8;
  size_t next_imu = 0, k = 0;
  std::vector<double> stamps;
  for (const auto& f : frames)
  {
    for (; next_imu < imus.size() && imus[next_imu]->header.stamp.toSec() <= f.first + 1e-6; ++next_imu)
      imu.publish(imus[next_imu]);
    for (const auto& m : f.second)
    {
      const bool left = m.getTopic().find("left") != std::string::npos;
      if (auto im = m.instantiate<sensor_msgs::Image>())
      {
        sensor_msgs::Image out = *im;
        if (static_cast<int>(k) >= n_good)
          std::fill(out.data.begin(), out.data.end(), 0);  // the camera goes black
        (left ? li : ri).publish(out);
      }
      else if (auto ci = m.instantiate<sensor_msgs::CameraInfo>())
        (left ? lc : rc).publish(ci);
    }
    stamps.push_back(f.first);
    ++k;
    ros::Duration(0.1).sleep();
  }
  ros::Duration(1.0).sleep();

  std::lock_guard<std::mutex> l(fs_mtx);
  int trusted = 0, untrusted = 0;
  geometry_msgs::Pose last_trusted;
  // The first frame(s) may wait for the IMU (not processed, nothing published); from the first
  // odometry on, every frame publishes.
  size_t first = 0;
  while (first < stamps.size() && !fs_odom.count(stamps[first]))
    ++first;
  ASSERT_LE(first, 2u) << "odometry started late";
  for (size_t i = first; i < stamps.size(); ++i)
  {
    const auto it = fs_odom.find(stamps[i]);
    ASSERT_NE(it, fs_odom.end()) << "no vo/odom for frame " << i << ": every processed frame publishes";
    const nav_msgs::Odometry& o = it->second;
    const bool is_untrusted = o.pose.covariance[0] >= 9999.0 - 1e-9;
    if (!is_untrusted)
    {
      ++trusted;
      last_trusted = o.pose.pose;
      EXPECT_TRUE(fs_tf.count(stamps[i])) << "trusted frame " << i << " without tf";
      continue;
    }
    ++untrusted;
    EXPECT_GE(static_cast<int>(i), n_good) << "a good frame untrusted";
    for (int a = 0; a < 6; ++a)
      for (int b = 0; b < 6; ++b)
      {
        const size_t j = static_cast<size_t>(a * 6 + b);
        EXPECT_EQ(o.pose.covariance[j], a == b ? 9999.0 : 0.0);
        EXPECT_EQ(o.twist.covariance[j], a == b ? 9999.0 : 0.0);
      }
    EXPECT_EQ(o.twist.twist.linear.x, 0.0);
    EXPECT_EQ(o.twist.twist.angular.z, 0.0);
    // the last trusted pose, not extrapolated
    EXPECT_EQ(o.pose.pose.position.x, last_trusted.position.x);
    EXPECT_EQ(o.pose.pose.position.y, last_trusted.position.y);
    EXPECT_FALSE(fs_tf.count(stamps[i])) << "tf broadcast for untrusted frame " << i;
  }
  EXPECT_GE(trusted, n_good - static_cast<int>(first));
  // Black frames coast at most imu_coast_max (2.5 s: 38 frames at 15 Hz), the rest are untrusted.
  EXPECT_GE(untrusted, static_cast<int>(stamps.size()) - n_good - 39);
  EXPECT_GE(untrusted, 10);
}

// The IMU behind the images (issue 34: in the closed-loop trial the images come from a nodelet in
// the same manager, the IMU from another process): a fourth instance (`imu_behind_odometry`, on
// /ib/...) gets each frame first and its IMU samples 30 ms later. The frame waits for them
// (imu_sync_wait), so it has its gyro and accelerometer: when the camera goes black after 8 frames,
// the first black frames coast, trusted; without the wait they went without the gyro and were
// untrusted at once.
std::mutex ib_mtx;
std::map<double, nav_msgs::Odometry> ib_odom;
void ibOdomCb(const nav_msgs::OdometryConstPtr& m)
{
  std::lock_guard<std::mutex> l(ib_mtx);
  ib_odom[m->header.stamp.toSec()] = *m;
}

TEST(VoNodelet, FramesWaitForAnImuBehindThem)
{
  ros::NodeHandle nh;
  const assistive_sim::RenderedBag rendered("course", 16, "vo_rostest_ib");
  const std::string& bag_path = rendered.path();
  ASSERT_FALSE(bag_path.empty()) << "render_bag failed";
  StereoImuInputs in(nh, "/ib");
  ros::Publisher &li = in.li, &ri = in.ri, &lc = in.lc, &rc = in.rc, &imu = in.imu;
  ros::Subscriber sub = nh.subscribe("/ib/odom", 100, ibOdomCb);
  in.connect();
  ASSERT_GT(imu.getNumSubscribers(), 0u);
  ros::Duration(0.5).sleep();

  rosbag::Bag bag(bag_path);
  std::vector<sensor_msgs::ImuConstPtr> imus;
  std::map<double, std::vector<rosbag::MessageInstance>> frames;
  readImuAndFrames(bag, imus, frames);
  ASSERT_GE(frames.size(), 14u);
  const int n_good = 8;
  size_t next_imu = 0, k = 0;
  std::vector<double> stamps;
  for (const auto& f : frames)
  {
    for (const auto& m : f.second)
    {
      const bool left = m.getTopic().find("left") != std::string::npos;
      if (auto im = m.instantiate<sensor_msgs::Image>())
      {
        sensor_msgs::Image out = *im;
        if (static_cast<int>(k) >= n_good)
          std::fill(out.data.begin(), out.data.end(), 0);  // the camera goes black
        (left ? li : ri).publish(out);
      }
      else if (auto ci = m.instantiate<sensor_msgs::CameraInfo>())
        (left ? lc : rc).publish(ci);
    }
    ros::Duration(0.03).sleep();  // the IMU up to this frame comes 30 ms after it
    for (; next_imu < imus.size() && imus[next_imu]->header.stamp.toSec() <= f.first + 1e-6; ++next_imu)
      imu.publish(imus[next_imu]);
    stamps.push_back(f.first);
    ++k;
    ros::Duration(0.1).sleep();
  }
  ros::Duration(1.0).sleep();

  std::lock_guard<std::mutex> l(ib_mtx);
  size_t first = 0;
  while (first < stamps.size() && !ib_odom.count(stamps[first]))
    ++first;
  ASSERT_LE(first, 2u) << "odometry started late";
  for (size_t i = first; i < stamps.size(); ++i)
  {
    const auto it = ib_odom.find(stamps[i]);
    ASSERT_NE(it, ib_odom.end()) << "no vo/odom for frame " << i;
    const bool trusted = it->second.pose.covariance[0] < 9999.0 - 1e-9;
    if (static_cast<int>(i) < n_good + 4)  // good frames, and black ones within coast_max (0.3 s)
    {
      EXPECT_TRUE(trusted) << "frame " << i << (static_cast<int>(i) >= n_good ? " (black: coasting needs the gyro)" : "");
    }
  }
}

int main(int argc, char** argv)
{
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "test_vo_nodelet");
  // One executable with test_vo_replay.cpp (CMakeLists.txt): vo_replay.test runs its tests alone
  // (--gtest_filter=VoReplay.*), as their own main() did: one spinner thread, none of these
  // subscribers.
  if (GTEST_FLAG_GET(filter) == "VoReplay.*")
  {
    ros::AsyncSpinner spinner(1);
    spinner.start();
    return RUN_ALL_TESTS();
  }
  ros::NodeHandle nh;
  ros::Subscriber s1 = nh.subscribe("/vo/odom", 100, odomCb);
  ros::Subscriber s2 = nh.subscribe("/ground_truth/odom", 100, gtCb);
  ros::Subscriber s3 = nh.subscribe("/diagnostics", 100, diagCb);
  ros::AsyncSpinner spinner(2);
  spinner.start();
  return RUN_ALL_TESTS();
}
