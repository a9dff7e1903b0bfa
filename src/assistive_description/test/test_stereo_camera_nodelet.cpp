// Rostest: the stereo_camera nodelet on the synthetic source publishes mono8 rectified pairs with
// one stamp per pair, rectified camera_info (D = 0, R = I, right P[3] = -fx * baseline), raw
// halves on demand that hold the right halves of the frame, and diagnostics.
#include <assistive_description/active_stereo.h>
#include <assistive_description/frame_source.h>

#include <cv_bridge/cv_bridge.h>
#include <diagnostic_msgs/DiagnosticArray.h>
#include <gtest/gtest.h>
#include <ros/ros.h>
#include <sensor_msgs/CameraInfo.h>
#include <sensor_msgs/Image.h>

#include <map>
#include <vector>

using assistive_description::SyntheticFrameSource;

namespace
{
template <typename M>
struct Collector
{
  std::vector<typename M::ConstPtr> msgs;
  void cb(const typename M::ConstPtr& m) { msgs.push_back(m); }
};

// Spin until `done` or a generous guard expires (a failure guard, not a timing assertion).
template <typename F>
bool spinUntil(F done, double guard = 30.0)
{
  const ros::WallTime end = ros::WallTime::now() + ros::WallDuration(guard);
  while (ros::ok() && !done() && ros::WallTime::now() < end)
  {
    ros::spinOnce();
    ros::WallDuration(0.01).sleep();
  }
  return done();
}
}  // namespace

TEST(StereoCameraNodelet, PublishesRectifiedPairsWithOneStamp)
{
  ros::NodeHandle nh;
  Collector<sensor_msgs::Image> li, ri;
  Collector<sensor_msgs::CameraInfo> lc, rc;
  auto s1 = nh.subscribe("/stereo/left/image_rect", 10, &Collector<sensor_msgs::Image>::cb, &li);
  auto s2 = nh.subscribe("/stereo/right/image_rect", 10, &Collector<sensor_msgs::Image>::cb, &ri);
  auto s3 = nh.subscribe("/stereo/left/camera_info", 10, &Collector<sensor_msgs::CameraInfo>::cb, &lc);
  auto s4 = nh.subscribe("/stereo/right/camera_info", 10, &Collector<sensor_msgs::CameraInfo>::cb, &rc);
  ASSERT_TRUE(spinUntil([&] {
    return li.msgs.size() >= 5 && ri.msgs.size() >= 5 && lc.msgs.size() >= 5 && rc.msgs.size() >= 5;
  })) << li.msgs.size() << " " << ri.msgs.size() << " " << lc.msgs.size() << " " << rc.msgs.size();

  std::map<double, int> stamps;  // stamp -> topics seen with it
  for (const auto& m : li.msgs)
  {
    EXPECT_EQ(m->encoding, "mono8");
    EXPECT_EQ(m->width, 640u);
    EXPECT_EQ(m->height, 480u);
    EXPECT_EQ(m->header.frame_id, "camera_left_optical_frame");
    stamps[m->header.stamp.toSec()] |= 1;
  }
  for (const auto& m : ri.msgs)
  {
    EXPECT_EQ(m->encoding, "mono8");
    EXPECT_EQ(m->header.frame_id, "camera_right_optical_frame");
    stamps[m->header.stamp.toSec()] |= 2;
  }
  int pairs = 0;
  for (const auto& s : stamps) pairs += s.second == 3;
  EXPECT_GE(pairs, 3) << "left and right images must carry identical stamps";
  for (std::size_t i = 1; i < li.msgs.size(); ++i)
    EXPECT_GT(li.msgs[i]->header.stamp, li.msgs[i - 1]->header.stamp);

  for (const auto* c : {&lc, &rc})
    for (const auto& m : c->msgs)
    {
      EXPECT_EQ(m->width, 640u);
      for (double d : m->D) EXPECT_EQ(d, 0.0);
      for (int i = 0; i < 9; ++i) EXPECT_EQ(m->R[i], i % 4 == 0 ? 1.0 : 0.0);
      EXPECT_EQ(m->K[0], m->P[0]);
    }
  // config/right.yaml: fx 420, baseline 0.12.
  EXPECT_NEAR(rc.msgs.back()->P[3], -420.0 * 0.12, 1e-9);
  EXPECT_EQ(lc.msgs.back()->P[3], 0.0);
  EXPECT_EQ(lc.msgs.back()->header.frame_id, "camera_left_optical_frame");
}

TEST(StereoCameraNodelet, RawHalvesOnDemand)
{
  ros::NodeHandle nh;
  Collector<sensor_msgs::Image> l, r;
  auto s1 = nh.subscribe("/stereo/left/image_raw", 10, &Collector<sensor_msgs::Image>::cb, &l);
  auto s2 = nh.subscribe("/stereo/right/image_raw", 10, &Collector<sensor_msgs::Image>::cb, &r);
  ASSERT_TRUE(spinUntil([&] { return !l.msgs.empty() && !r.msgs.empty(); }));
  const cv::Mat lm = cv_bridge::toCvShare(l.msgs.back(), "mono8")->image;
  const cv::Mat rm = cv_bridge::toCvShare(r.msgs.back(), "mono8")->image;
  ASSERT_EQ(lm.cols, 640);
  ASSERT_EQ(rm.rows, 480);
  int bad = 0;
  for (int y = 0; y < 480; y += 7)
    for (int x = 0; x < 640; x += 5)
    {
      bad += lm.at<uchar>(y, x) != SyntheticFrameSource::pattern(x, y);
      bad += rm.at<uchar>(y, x) != SyntheticFrameSource::pattern(x + 16, y);  // disparity 16
    }
  EXPECT_EQ(bad, 0);
}

TEST(StereoCameraNodelet, ReportsDiagnostics)
{
  ros::NodeHandle nh;
  diagnostic_msgs::DiagnosticStatus camera;
  bool found = false;
  boost::function<void(const diagnostic_msgs::DiagnosticArray::ConstPtr&)> cb =
      [&](const diagnostic_msgs::DiagnosticArray::ConstPtr& a) {
        for (const auto& s : a->status)
          if (s.name.find("Camera") != std::string::npos && s.level == s.OK)
          {
            camera = s;
            found = true;
          }
      };
  auto sub = nh.subscribe<diagnostic_msgs::DiagnosticArray>("/diagnostics", 10, cb);
  ASSERT_TRUE(spinUntil([&] { return found; })) << "no OK Camera status on /diagnostics";
  EXPECT_EQ(camera.message, "streaming");
  EXPECT_EQ(camera.hardware_id, "synthetic");
}

int main(int argc, char** argv)
{
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "test_stereo_camera_nodelet");
  return RUN_ALL_TESTS();
}

// stereo_camera_active.test (issue 35): the synthetic active camera; each emitter-on pair (the
// projector's dots) on /stereo/projected, each other pair on /stereo, never both, alternating.
TEST(StereoCameraActive, EmitterOnPairsGoToProjectedTheOthersToTheStereoTopics)
{
  ros::NodeHandle nh;
  Collector<sensor_msgs::Image> off, on;
  Collector<sensor_msgs::CameraInfo> on_info;
  auto s1 = nh.subscribe("/stereo/left/image_rect", 20, &Collector<sensor_msgs::Image>::cb, &off);
  auto s2 = nh.subscribe("/stereo/projected/left/image_rect", 20, &Collector<sensor_msgs::Image>::cb, &on);
  auto s3 = nh.subscribe("/stereo/projected/left/camera_info", 20, &Collector<sensor_msgs::CameraInfo>::cb, &on_info);
  ASSERT_TRUE(spinUntil([&] { return off.msgs.size() >= 10 && on.msgs.size() >= 10 && on_info.msgs.size() >= 5; }))
      << off.msgs.size() << " " << on.msgs.size() << " " << on_info.msgs.size();
  auto energy = [](const sensor_msgs::ImageConstPtr& m) {
    return assistive_description::dotEnergy(cv_bridge::toCvShare(m, "mono8")->image);
  };
  double max_off = 0.0, min_on = 1e9;
  std::map<double, char> kind;
  // (the first frames come before the switch first reaches the synthetic sensor: judged from the
  // fifth of each on)
  for (size_t i = 4; i < off.msgs.size(); ++i) max_off = std::max(max_off, energy(off.msgs[i])), kind[off.msgs[i]->header.stamp.toSec()] = 'f';
  for (size_t i = 4; i < on.msgs.size(); ++i) min_on = std::min(min_on, energy(on.msgs[i])), kind[on.msgs[i]->header.stamp.toSec()] = 'n';
  EXPECT_GT(min_on, 1.5 * max_off) << "the projected pairs carry the dots";
  for (const auto& m : off.msgs)
    for (const auto& n : on.msgs) ASSERT_NE(m->header.stamp, n->header.stamp);
  // alternating: no two pairs of the same kind in a row among the later frames
  int repeats = 0;
  char last = 0;
  for (const auto& k : kind)
  {
    repeats += k.second == last;
    last = k.second;
  }
  EXPECT_LE(repeats, 1);
  EXPECT_EQ(on_info.msgs.back()->width, 640u);
}
