// Round trip through StereoBagWriter / StereoBagReader (no roscore).
#include <assistive_sim/conversions.h>
#include <assistive_sim/stereo_bag.h>

#include <cstdio>

#include <gtest/gtest.h>

using namespace assistive_sim;

namespace
{
StereoFrame makeFrame(int i)
{
  StereoFrame f;
  f.stamp = 10.0 + i / 15.0;
  f.calib.width = 32;
  f.calib.height = 24;
  f.calib.fx = 480.0;
  f.calib.fy = 490.0;
  f.calib.cx = 15.5;
  f.calib.cy = 11.5;
  f.calib.baseline = 0.12;
  f.left = cv::Mat(24, 32, CV_8UC1, cv::Scalar(i));
  f.right = cv::Mat(24, 32, CV_8UC1, cv::Scalar(100 + i));
  f.left.at<uint8_t>(3, 5) = 255;
  f.has_gt_pose = true;
  f.gt_pose = Eigen::Translation3d(i * 0.1, 0.5, 1.6) * Eigen::AngleAxisd(0.1 * i, Eigen::Vector3d::UnitZ()) *
              linkToLeftOptical();
  f.gt_velocity = Eigen::Vector3d(1.0, 0.2, 0.0);
  for (int k = 0; k < 3; ++k)
  {
    ImuSample s;
    s.stamp = f.stamp - (2 - k) * 0.02;
    s.gyro = Eigen::Vector3d(0.01 * i, 0.02, k);
    s.accel = Eigen::Vector3d(0, 0, 9.81);
    f.imu.push_back(s);
  }
  return f;
}
}  // namespace

TEST(StereoBag, RoundTrip)
{
  const std::string path = std::string(::testing::TempDir()) + "assistive_sim_test_roundtrip.bag";
  OccupancyGrid grid;
  grid.origin_x = -1.0;
  grid.origin_y = -2.0;
  grid.resolution = 0.2;
  grid.width = 4;
  grid.height = 3;
  grid.data = {0, 0, 100, -1, 50, 0, 0, 0, 100, 100, 0, 0};
  {
    StereoBagWriter w(path);
    for (int i = 0; i < 5; ++i) w.writeFrame(makeFrame(i));
    w.writeOccupancy(grid, 10.0);
  }
  StereoBagReader r(path);
  EXPECT_EQ(r.size(), 5u);
  EXPECT_TRUE(r.hasGroundTruth());
  EXPECT_EQ(r.imuSamples().size(), 15u);
  StereoFrame f;
  int n = 0;
  while (r.next(f))
  {
    const StereoFrame e = makeFrame(n);
    EXPECT_NEAR(f.stamp, e.stamp, 1e-6);
    EXPECT_EQ(f.left.type(), CV_8UC1);
    EXPECT_EQ(f.left.at<uint8_t>(0, 0), n);
    EXPECT_EQ(f.left.at<uint8_t>(3, 5), 255);
    EXPECT_EQ(f.right.at<uint8_t>(0, 0), 100 + n);
    EXPECT_DOUBLE_EQ(f.calib.fx, 480.0);
    EXPECT_DOUBLE_EQ(f.calib.fy, 490.0);
    EXPECT_DOUBLE_EQ(f.calib.cx, 15.5);
    EXPECT_DOUBLE_EQ(f.calib.cy, 11.5);
    EXPECT_NEAR(f.calib.baseline, 0.12, 1e-12);
    EXPECT_EQ(f.calib.width, 32);
    ASSERT_TRUE(f.has_gt_pose);
    EXPECT_TRUE(f.gt_pose.isApprox(e.gt_pose, 1e-9));
    EXPECT_TRUE(f.gt_velocity.isApprox(e.gt_velocity, 1e-9));
    ASSERT_EQ(f.imu.size(), 3u);
    EXPECT_NEAR(f.imu[2].gyro.z(), 2.0, 1e-12);
    EXPECT_NEAR(f.imu[0].gyro.x(), 0.01 * n, 1e-12);
    ++n;
  }
  EXPECT_EQ(n, 5);
  OccupancyGrid g;
  ASSERT_TRUE(r.readOccupancy(g));
  EXPECT_EQ(g.width, 4);
  EXPECT_EQ(g.height, 3);
  EXPECT_NEAR(g.resolution, 0.2, 1e-6);
  EXPECT_DOUBLE_EQ(g.origin_x, -1.0);
  EXPECT_EQ(g.data, grid.data);
  EXPECT_EQ(g.atWorld(-1.0 + 0.45, -2.0 + 0.05), 100);
  EXPECT_EQ(g.atWorld(-1.0 + 0.05, -2.0 + 0.25), 50);
  EXPECT_EQ(g.atWorld(100.0, 0.0), CELL_UNKNOWN);

  r.rewind();
  ASSERT_TRUE(r.next(f));
  EXPECT_EQ(f.left.at<uint8_t>(0, 0), 0);
  std::remove(path.c_str());
}

TEST(StereoBag, MissingBagThrows)
{
  EXPECT_THROW(StereoBagReader("/nonexistent/x.bag"), std::runtime_error);
}

TEST(Conversions, RoundTrip)
{
  StereoCalib c;
  c.width = 320;
  c.height = 240;
  c.fx = 251.0;
  c.fy = 252.0;
  c.cx = 160.5;
  c.cy = 120.25;
  c.baseline = 0.095;
  const auto li = toCameraInfo(c, false, "l", ros::Time(5.0));
  const auto ri = toCameraInfo(c, true, "r", ros::Time(5.0));
  EXPECT_DOUBLE_EQ(ri.P[3], -251.0 * 0.095);
  const StereoCalib b = fromCameraInfos(li, &ri);
  EXPECT_DOUBLE_EQ(b.fx, c.fx);
  EXPECT_DOUBLE_EQ(b.fy, c.fy);
  EXPECT_DOUBLE_EQ(b.cx, c.cx);
  EXPECT_DOUBLE_EQ(b.cy, c.cy);
  EXPECT_NEAR(b.baseline, c.baseline, 1e-12);
  EXPECT_EQ(b.width, 320);

  OccupancyGrid g;
  g.origin_x = 1.0;
  g.origin_y = -3.0;
  g.width = 2;
  g.height = 2;
  g.data = {0, 50, 100, -1};
  const OccupancyGrid g2 = fromMsg(toMsg(g, "gt_world", ros::Time(1.0)));
  EXPECT_EQ(g2.data, g.data);
  EXPECT_DOUBLE_EQ(g2.origin_y, -3.0);
  EXPECT_NEAR(g2.resolution, 0.2, 1e-6);

  ImuSample s;
  s.stamp = 12.5;
  s.gyro = {0.1, -0.2, 0.3};
  s.accel = {0.0, 0.5, 9.7};
  const ImuSample s2 = fromMsg(toMsg(s, "camera_link"));
  EXPECT_NEAR(s2.stamp, 12.5, 1e-9);
  EXPECT_EQ(s2.gyro, s.gyro);
  EXPECT_EQ(s2.accel, s.accel);
  EXPECT_FALSE(s2.has_orientation);

  cv::Mat img(3, 4, CV_8UC1);
  for (int i = 0; i < 12; ++i) img.data[i] = static_cast<uint8_t>(i * 20);
  const auto m = toImageMsg(img, "l", ros::Time(1.0));
  EXPECT_EQ(m.encoding, "mono8");
  EXPECT_EQ(m.data[7], 140);
  EXPECT_THROW(toImageMsg(cv::Mat(2, 2, CV_32F), "l", ros::Time(1.0)), std::invalid_argument);
}

int main(int argc, char** argv)
{
  ::testing::InitGoogleTest(&argc, argv);
  return RUN_ALL_TESTS();
}
