// Round trip through StereoBagWriter / StereoBagReader (no roscore).
#include <assistive_eval/conversions.h>
#include <assistive_eval/stereo_bag.h>

#include <cmath>
#include <cstdio>
#include <functional>
#include <utility>

#include <geometry_msgs/PoseStamped.h>
#include <gtest/gtest.h>
#include <rosbag/bag.h>
#include <rosbag/view.h>
#include <sensor_msgs/CameraInfo.h>
#include <sensor_msgs/Image.h>
#include <sensor_msgs/image_encodings.h>
#include <tf2_eigen/tf2_eigen.h>

using namespace assistive_eval;

namespace
{
StereoFrame makeFrame(int i)
{
  StereoFrame f;
  f.stamp = 10.0 + i / 15.0;
  f.calib = StereoCalib{32, 24, 480.0, 490.0, 15.5, 11.5, 0.12};  // width height fx fy cx cy baseline
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

TEST(StereoBag, AClosedLoopTrialsCameraPoseIsTheTruthWhenThereIsNoOdometry)
{
  // mobility_trials --record: the truth is the renderer's /sim/camera_pose (left optical frame in
  // gt_world, one per frame), not /ground_truth/odom
  const std::string path = std::string(::testing::TempDir()) + "assistive_sim_test_sim_pose.bag";
  {
    StereoBagWriter w(path);
    for (int i = 0; i < 5; ++i)
    {
      StereoFrame f = makeFrame(i);
      f.has_gt_pose = false;
      w.writeFrame(f);
    }
  }
  {
    rosbag::Bag b(path, rosbag::bagmode::Append);
    for (int i = 4; i >= 0; --i)  // out of order: the reader sorts
    {
      geometry_msgs::PoseStamped p;
      p.header.stamp = ros::Time(makeFrame(i).stamp);
      p.header.frame_id = "gt_world";
      p.pose = tf2::toMsg(makeFrame(i).gt_pose);
      b.write("/sim/camera_pose", p.header.stamp, p);
    }
  }
  StereoBagReader r(path);
  EXPECT_TRUE(r.hasGroundTruth());
  StereoFrame f;
  int n = 0;
  while (r.next(f))
  {
    ASSERT_TRUE(f.has_gt_pose) << "frame " << n;
    EXPECT_TRUE(f.gt_pose.isApprox(makeFrame(n).gt_pose, 1e-6));
    // velocity: central differences (one-sided at the ends)
    const int a = std::max(0, n - 1), b = std::min(4, n + 1);
    const Eigen::Vector3d v = (makeFrame(b).gt_pose.translation() - makeFrame(a).gt_pose.translation()) /
                              (makeFrame(b).stamp - makeFrame(a).stamp);
    EXPECT_LT((f.gt_velocity - v).norm(), 1e-3) << "frame " << n;
    ++n;
  }
  EXPECT_EQ(n, 5);
  std::remove(path.c_str());
}

TEST(StereoBag, MissingBagThrows)
{
  EXPECT_THROW(StereoBagReader("/nonexistent/x.bag"), std::runtime_error);
}

namespace
{
/// A copy of a good 3-frame bag with every message passed through `edit` (topic, image or
/// camera_info to change in place; return false to drop the message). Returns the path.
std::string brokenBag(const std::string& name,
                      const std::function<bool(const std::string&, sensor_msgs::Image*, sensor_msgs::CameraInfo*)>& edit)
{
  const std::string good = std::string(::testing::TempDir()) + "assistive_sim_test_good.bag";
  {
    StereoBagWriter w(good);
    for (int i = 0; i < 3; ++i) w.writeFrame(makeFrame(i));
  }
  const std::string path = std::string(::testing::TempDir()) + "assistive_sim_test_" + name + ".bag";
  rosbag::Bag in(good, rosbag::bagmode::Read), out(path, rosbag::bagmode::Write);
  for (const rosbag::MessageInstance& m : rosbag::View(in))
  {
    if (auto img = m.instantiate<sensor_msgs::Image>())
    {
      sensor_msgs::Image c = *img;
      if (edit(m.getTopic(), &c, nullptr)) out.write(m.getTopic(), m.getTime(), c);
    }
    else if (auto info = m.instantiate<sensor_msgs::CameraInfo>())
    {
      sensor_msgs::CameraInfo c = *info;
      if (edit(m.getTopic(), nullptr, &c)) out.write(m.getTopic(), m.getTime(), c);
    }
    else if (edit(m.getTopic(), nullptr, nullptr))
      out.write(m.getTopic(), m.getTime(), m);
  }
  in.close();
  out.close();
  std::remove(good.c_str());
  return path;
}

/// The std::runtime_error message of constructing a reader on `path` and reading every frame.
std::string readError(const std::string& path)
{
  try
  {
    StereoBagReader r(path);
    StereoFrame f;
    while (r.next(f))
    {
    }
  }
  catch (const std::runtime_error& e)
  {
    return e.what();
  }
  return "";
}

void toRgb8(sensor_msgs::Image* img)
{
  std::vector<uint8_t> d;
  for (uint8_t v : img->data) d.insert(d.end(), {v, v, v});
  img->data = d;
  img->encoding = sensor_msgs::image_encodings::RGB8;
  img->step = img->width * 3;
}
}  // namespace

TEST(StereoBag, NoCameraInfoIsAnErrorNotADefaultCalibration)
{
  for (const std::string topic : {"/stereo/left/camera_info", "/stereo/right/camera_info"})
  {
    const std::string path = brokenBag("noinfo", [&](const std::string& t, sensor_msgs::Image*, sensor_msgs::CameraInfo*) {
      return t != topic;
    });
    const std::string e = readError(path);
    EXPECT_NE(e.find("has no " + topic), std::string::npos) << e;
    std::remove(path.c_str());
  }
}

TEST(StereoBag, UnusableCalibrationIsAnError)
{
  // NaN focal length (P and K), zero intrinsics, a right P without a baseline
  const std::string nan = brokenBag("nan", [](const std::string&, sensor_msgs::Image*, sensor_msgs::CameraInfo* c) {
    if (c) c->P[0] = c->K[0] = std::nan("");
    return true;
  });
  EXPECT_NE(readError(nan).find("invalid intrinsics fx nan"), std::string::npos) << readError(nan);
  const std::string zero = brokenBag("zero", [](const std::string&, sensor_msgs::Image*, sensor_msgs::CameraInfo* c) {
    if (c) c->P.fill(0.0), c->K.fill(0.0);
    return true;
  });
  EXPECT_NE(readError(zero).find("invalid intrinsics"), std::string::npos) << readError(zero);
  const std::string nob = brokenBag("nobaseline", [](const std::string&, sensor_msgs::Image*, sensor_msgs::CameraInfo* c) {
    if (c) c->P[3] = 0.0;
    return true;
  });
  EXPECT_NE(readError(nob).find("/stereo/right/camera_info"), std::string::npos) << readError(nob);
  EXPECT_NE(readError(nob).find("baseline"), std::string::npos) << readError(nob);
  for (const auto& p : {nan, zero, nob}) std::remove(p.c_str());
}

TEST(StereoBag, ColourImagesAreConvertedToMono8)
{
  const std::string path = brokenBag("rgb8", [](const std::string&, sensor_msgs::Image* img, sensor_msgs::CameraInfo*) {
    if (img) toRgb8(img);
    return true;
  });
  StereoBagReader r(path);
  StereoFrame f;
  int n = 0;
  while (r.next(f))
  {
    ASSERT_EQ(f.left.type(), CV_8UC1);
    EXPECT_EQ(f.left.at<uint8_t>(0, 0), n);
    EXPECT_EQ(f.left.at<uint8_t>(3, 5), 255);
    EXPECT_EQ(f.right.at<uint8_t>(0, 0), 100 + n);
    ++n;
  }
  EXPECT_EQ(n, 3);
  std::remove(path.c_str());
}

TEST(StereoBag, UnsupportedOrMalformedImagesAreErrorsNamingTopicAndEncoding)
{
  const std::string fl = brokenBag("float", [](const std::string& t, sensor_msgs::Image* img, sensor_msgs::CameraInfo*) {
    if (img && t == "/stereo/right/image_rect")
    {
      img->encoding = sensor_msgs::image_encodings::TYPE_32FC1;
      img->step = img->width * 4;
      img->data.resize(img->step * img->height);
    }
    return true;
  });
  const std::string e = readError(fl);
  EXPECT_NE(e.find("/stereo/right/image_rect"), std::string::npos) << e;
  EXPECT_NE(e.find("'32FC1' is not supported"), std::string::npos) << e;
  const std::string sh = brokenBag("short", [](const std::string&, sensor_msgs::Image* img, sensor_msgs::CameraInfo*) {
    if (img) img->data.resize(img->data.size() / 2);
    return true;
  });
  EXPECT_NE(readError(sh).find("malformed mono8 image"), std::string::npos) << readError(sh);
  for (const auto& p : {fl, sh}) std::remove(p.c_str());
}

TEST(StereoBag, SizeMismatchesAreErrors)
{
  auto crop = [](sensor_msgs::Image* img) {  // keep the top-left 16x12
    std::vector<uint8_t> d;
    for (uint32_t y = 0; y < 12; ++y)
      d.insert(d.end(), img->data.begin() + y * img->step, img->data.begin() + y * img->step + 16);
    img->data = d;
    img->width = img->step = 16;
    img->height = 12;
  };
  const std::string lr = brokenBag("lr", [&](const std::string& t, sensor_msgs::Image* img, sensor_msgs::CameraInfo*) {
    if (img && t == "/stereo/right/image_rect") crop(img);
    return true;
  });
  EXPECT_NE(readError(lr).find("/stereo/left/image_rect is 32x24 but /stereo/right/image_rect is 16x12"),
            std::string::npos)
      << readError(lr);
  const std::string both = brokenBag("both", [&](const std::string&, sensor_msgs::Image* img, sensor_msgs::CameraInfo*) {
    if (img) crop(img);
    return true;
  });
  EXPECT_NE(readError(both).find("images are 16x12 but /stereo/left/camera_info says 32x24"), std::string::npos)
      << readError(both);
  for (const auto& p : {lr, both}) std::remove(p.c_str());
}

TEST(Conversions, RoundTrip)
{
  const StereoCalib c{320, 240, 251.0, 252.0, 160.5, 120.25, 0.095};  // width height fx fy cx cy baseline
  const auto li = toCameraInfo(c, false, "l", ros::Time(5.0));
  const auto ri = toCameraInfo(c, true, "r", ros::Time(5.0));
  EXPECT_DOUBLE_EQ(ri.P[3], -251.0 * 0.095);
  const StereoCalib b = fromCameraInfos(li, &ri);
  for (const auto& [got, want] : {std::make_pair(b.fx, c.fx), std::make_pair(b.fy, c.fy), std::make_pair(b.cx, c.cx),
                                  std::make_pair(b.cy, c.cy)})
    EXPECT_DOUBLE_EQ(got, want);
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
