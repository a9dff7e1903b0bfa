#include <gtest/gtest.h>

#include <assistive_obstacles/conversions.h>

using namespace assistive_obstacles;

TEST(Conversions, GridRoundTrip)
{
  GridData g;
  g.origin_x = -5.2;
  g.origin_y = 3.4;
  g.resolution = 0.2;
  g.width = 3;
  g.height = 2;
  g.data = {-1, 0, 50, 100, 0, -1};
  const nav_msgs::OccupancyGrid m = toMsg(g, "odom", ros::Time(12.5));
  EXPECT_EQ(m.header.frame_id, "odom");
  EXPECT_EQ(m.info.width, 3u);
  EXPECT_NEAR(m.info.origin.position.x, -5.2, 1e-9);
  EXPECT_EQ(m.data[2], 50);
  const GridData back = fromMsg(m);
  EXPECT_EQ(back.data, g.data);
  EXPECT_NEAR(back.origin_y, 3.4, 1e-9);
  EXPECT_NEAR(back.resolution, 0.2, 1e-6);
}

TEST(Conversions, CameraInfosToStereoModel)
{
  sensor_msgs::CameraInfo l, r;
  l.width = r.width = 640;
  l.height = r.height = 480;
  l.P = {500, 0, 319.5, 0, 0, 500, 239.5, 0, 0, 0, 1, 0};
  r.P = {500, 0, 319.5, -60, 0, 500, 239.5, 0, 0, 0, 1, 0};
  StereoModel m;
  ASSERT_TRUE(fromMsg(l, r, m));
  EXPECT_NEAR(m.baseline, 0.12, 1e-9);
  EXPECT_NEAR(m.cx, 319.5, 1e-9);
  r.P[3] = 0;  // no baseline
  EXPECT_FALSE(fromMsg(l, r, m));
}

TEST(Conversions, CloudRoundTripAndDisparityMsg)
{
  std::vector<Eigen::Vector3f> pts = {{1, 2, 3}, {-1, 0.5f, 4}};
  std_msgs::Header h;
  h.frame_id = "camera_left_optical_frame";
  const auto c = toCloudMsg(pts, h);
  EXPECT_EQ(c.width, 2u);
  const auto back = fromCloudMsg(c);
  ASSERT_EQ(back.size(), 2u);
  EXPECT_FLOAT_EQ(back[1].y(), 0.5f);
  StereoModel m;
  cv::Mat d(240, 320, CV_32F, cv::Scalar(12.0f));
  const auto dm = toDisparityMsg(d, m, 64, h);
  EXPECT_FLOAT_EQ(dm.f, 250.f);  // half-scale focal length
  EXPECT_EQ(dm.image.width, 320u);
  EXPECT_EQ(dm.image.encoding, "32FC1");
}

TEST(Conversions, MarkersGroupedBySize)
{
  const auto arr = toMarkers({{0, 0, 0}, {1, 0, 1}, {2, 0, 0}}, {0.1f, 0.2f, 0.1f}, "odom", ros::Time(1));
  ASSERT_EQ(arr.markers.size(), 2u);
  EXPECT_EQ(arr.markers[0].points.size(), 2u);
  EXPECT_EQ(arr.markers[1].points.size(), 1u);
}

TEST(Conversions, MoversToMessageAndMarkers)
{
  ReportedMover r;
  r.track.id = 7;
  r.track.x << 1.0, -2.0, 0.5, 1.2;
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j) r.track.P(i, j) = 10 * i + j;
  r.radius = 0.35;
  r.height = 1.6;
  const assistive_msgs::MoverArray a = toMoverArray({r}, 0.1, "odom", ros::Time(3.5));
  EXPECT_EQ(a.header.frame_id, "odom");
  EXPECT_EQ(a.header.stamp, ros::Time(3.5));
  ASSERT_EQ(a.movers.size(), 1u);
  EXPECT_EQ(a.movers[0].id, 7u);
  EXPECT_DOUBLE_EQ(a.movers[0].position.y, -2.0);
  EXPECT_DOUBLE_EQ(a.movers[0].position.z, 0.1);
  EXPECT_DOUBLE_EQ(a.movers[0].velocity.y, 1.2);
  EXPECT_DOUBLE_EQ(a.movers[0].covariance[6], 12.0);  // row 1, column 2
  EXPECT_FLOAT_EQ(a.movers[0].radius, 0.35f);
  EXPECT_TRUE(toMoverArray({}, 0.0, "odom", ros::Time(1)).movers.empty());
  const visualization_msgs::MarkerArray m = toMoverMarkers({r}, 0.1, 3.0, "odom", ros::Time(3.5));
  ASSERT_EQ(m.markers.size(), 4u);  // DELETEALL, cylinder, arrow, path
  EXPECT_EQ(m.markers[0].action, visualization_msgs::Marker::DELETEALL);
  EXPECT_EQ(m.markers[1].type, visualization_msgs::Marker::CYLINDER);
  EXPECT_DOUBLE_EQ(m.markers[1].scale.x, 0.7);
  EXPECT_EQ(m.markers[3].type, visualization_msgs::Marker::LINE_STRIP);
  EXPECT_DOUBLE_EQ(m.markers[3].points.back().x, 1.0 + 0.5 * 3.0);  // 3 s ahead
  EXPECT_DOUBLE_EQ(m.markers[3].points.back().y, -2.0 + 1.2 * 3.0);
}
