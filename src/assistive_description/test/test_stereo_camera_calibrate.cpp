// Rostest: set_camera_info (what camera_calibration's COMMIT calls) makes the uncalibrated driver
// rectify with the new calibration and writes the calibration files.
#include <gtest/gtest.h>
#include <ros/ros.h>
#include <sensor_msgs/CameraInfo.h>
#include <sensor_msgs/Image.h>
#include <sensor_msgs/SetCameraInfo.h>

#include <cstdio>
#include <fstream>
#include <sstream>
#include <vector>

// One executable with test_stereo_camera_nodelet.cpp, which holds main() (issue 31: CMakeLists.txt); this
// file's names in a namespace of their own, apart from that file's.
namespace stereo_camera_calibrate_test
{

namespace
{
template <typename M>
struct Collector
{
  std::vector<typename M::ConstPtr> msgs;
  void cb(const typename M::ConstPtr& m) { msgs.push_back(m); }
};

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

sensor_msgs::CameraInfo makeInfo(double tx)
{
  sensor_msgs::CameraInfo c;
  c.width = 640;
  c.height = 480;
  c.distortion_model = "plumb_bob";
  c.D = {-0.02, 0.0, 0.0, 0.0, 0.0};
  c.K = {400, 0, 320, 0, 400, 240, 0, 0, 1};
  c.R = {1, 0, 0, 0, 1, 0, 0, 0, 1};
  c.P = {400, 0, 320, tx, 0, 400, 240, 0, 0, 0, 1, 0};
  return c;
}

std::string readFile(const std::string& path)
{
  std::ifstream f(path);
  std::stringstream s;
  s << f.rdbuf();
  return s.str();
}
}  // namespace

TEST(StereoCameraCalibrate, SetCameraInfoEnablesRectification)
{
  ros::NodeHandle nh, pnh("~");
  std::string dir;
  ASSERT_TRUE(pnh.getParam("dir", dir));
  Collector<sensor_msgs::Image> raw, rect;
  Collector<sensor_msgs::CameraInfo> rinfo;
  auto s1 = nh.subscribe("/stereo/left/image_raw", 10, &Collector<sensor_msgs::Image>::cb, &raw);
  auto s2 = nh.subscribe("/stereo/left/image_rect", 10, &Collector<sensor_msgs::Image>::cb, &rect);
  auto s3 = nh.subscribe("/stereo/right/camera_info", 10, &Collector<sensor_msgs::CameraInfo>::cb, &rinfo);

  // Uncalibrated: raw images flow, no rectified ones.
  ASSERT_TRUE(spinUntil([&] { return raw.msgs.size() >= 10; }));
  EXPECT_EQ(rect.msgs.size(), 0u);
  EXPECT_EQ(rinfo.msgs.size(), 0u);

  for (const char* side : {"left", "right"})
  {
    const std::string name = std::string("/stereo/") + side + "/set_camera_info";
    ASSERT_TRUE(ros::service::waitForService(name, 20000)) << name;
    sensor_msgs::SetCameraInfo srv;
    srv.request.camera_info = makeInfo(std::string(side) == "left" ? 0.0 : -400.0 * 0.1);
    ASSERT_TRUE(ros::service::call(name, srv)) << name;
    EXPECT_TRUE(srv.response.success) << srv.response.status_message;
  }

  ASSERT_TRUE(spinUntil([&] { return rect.msgs.size() >= 3 && !rinfo.msgs.empty(); }));
  EXPECT_EQ(rect.msgs.back()->width, 640u);
  EXPECT_EQ(rinfo.msgs.back()->P[0], 400.0);
  EXPECT_NEAR(rinfo.msgs.back()->P[3], -40.0, 1e-9);
  for (double d : rinfo.msgs.back()->D) EXPECT_EQ(d, 0.0);

  const std::string left = readFile(dir + "/left.yaml"), right = readFile(dir + "/right.yaml");
  EXPECT_NE(left.find("camera_name: left"), std::string::npos) << left;
  EXPECT_NE(right.find("camera_name: right"), std::string::npos) << right;
  EXPECT_NE(right.find("-40"), std::string::npos) << right;
  // A new calibration clears what the self-calibration kept against the old one.
  const std::string kept = readFile(dir + "/self_calibration_right.yaml");
  EXPECT_NE(kept.find("rotation_deg: [ 0., 0., 0. ]"), std::string::npos) << kept;
  std::remove((dir + "/left.yaml").c_str());
  std::remove((dir + "/right.yaml").c_str());
  std::remove((dir + "/self_calibration_right.yaml").c_str());
  std::remove(dir.c_str());
}
}  // namespace stereo_camera_calibrate_test
