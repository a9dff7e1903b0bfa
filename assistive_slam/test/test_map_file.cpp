// The map file: a round trip keeps every field; truncated, corrupted, foreign and other-version
// files are rejected with a message saying which, and the map passed in stays untouched.
#include <cstdio>
#include <fstream>
#include <iterator>
#include <gtest/gtest.h>
#include "assistive_slam/map_file.h"

using namespace assistive_slam;

namespace
{
Eigen::Isometry3d pose(double x, double yaw)
{
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  T.translation() = Eigen::Vector3d(x, 2 * x, -x);
  return T;
}
MapData sample()
{
  MapData m;
  for (uint32_t k = 0; k < 3; ++k)
  {
    Keyframe kf;
    kf.id = k;
    kf.submap = k / 2;
    kf.stamp = 10.5 + k;
    kf.T_odom_cam = pose(k, 0.1 * k);
    kf.T_map_cam = pose(k + 0.25, 0.1 * k + 0.01);
    kf.path_m = 1.5 * k;
    kf.descriptors.create(5, 32, CV_8U);
    cv::randu(kf.descriptors, 0, 255);
    for (int i = 0; i < 5; ++i)
    {
      kf.keypoints.emplace_back(10.f * i + 0.5f, 20.f * i + 0.25f, 31.f, 45.f * i, 0.f, i % 3);
      kf.u_right.push_back(10.f * i - 3.f);
      kf.points.emplace_back(0.1 * i, -0.2 * i, 3.0 + i);
      kf.landmark.push_back(-1);
    }
    m.keyframes.push_back(kf);
  }
  m.submaps.push_back({0, pose(0, 0), {0, 1}});
  m.submaps.push_back({1, pose(2.25, 0.2), {2}});
  SubmapLinkInfo l;
  l.from = 0;
  l.to = 1;
  l.T_from_to = pose(2, 0.2);
  l.covariance = Matrix6d::Identity() * 0.01;
  l.loop_closure = true;
  m.loop_links.push_back(l);
  m.places.push_back({"entrance", 0, pose(0.5, 1.0), 12.5});
  m.places.push_back({"lift", 2, pose(-3, -2.0), 40.25});
  return m;
}
std::string bytes(const std::string& path)
{
  std::ifstream f(path, std::ios::binary);
  return std::string((std::istreambuf_iterator<char>(f)), std::istreambuf_iterator<char>());
}
void write(const std::string& path, const std::string& b)
{
  std::ofstream(path, std::ios::binary | std::ios::trunc) << b;
}
std::string tmp(const char* name)
{
  return testing::TempDir() + "assistive_slam_" + name + ".map";
}
}  // namespace

TEST(MapFile, RoundTripKeepsEverything)
{
  const MapData m = sample();
  const std::string path = tmp("roundtrip");
  std::string err;
  ASSERT_TRUE(saveMapFile(path, m, &err)) << err;
  MapData r;
  ASSERT_TRUE(loadMapFile(path, r, &err)) << err;
  ASSERT_EQ(r.keyframes.size(), 3u);
  for (size_t k = 0; k < 3; ++k)
  {
    const Keyframe &a = m.keyframes[k], &b = r.keyframes[k];
    EXPECT_EQ(a.id, b.id);
    EXPECT_EQ(a.submap, b.submap);
    EXPECT_EQ(a.stamp, b.stamp);
    EXPECT_EQ(a.path_m, b.path_m);
    EXPECT_TRUE(a.T_odom_cam.isApprox(b.T_odom_cam, 0));
    EXPECT_TRUE(a.T_map_cam.isApprox(b.T_map_cam, 0));
    ASSERT_EQ(b.keypoints.size(), 5u);
    EXPECT_EQ(cv::norm(a.descriptors, b.descriptors, cv::NORM_HAMMING), 0);
    for (size_t i = 0; i < 5; ++i)
    {
      EXPECT_EQ(a.keypoints[i].pt, b.keypoints[i].pt);
      EXPECT_EQ(a.keypoints[i].octave, b.keypoints[i].octave);
      EXPECT_EQ(a.keypoints[i].angle, b.keypoints[i].angle);
      EXPECT_EQ(a.u_right[i], b.u_right[i]);
      EXPECT_EQ(a.points[i], b.points[i]);
    }
  }
  ASSERT_EQ(r.submaps.size(), 2u);
  EXPECT_EQ(r.submaps[0].keyframes, (std::vector<uint32_t>{0, 1}));
  EXPECT_TRUE(r.submaps[1].T_map_origin.isApprox(m.submaps[1].T_map_origin, 0));
  ASSERT_EQ(r.loop_links.size(), 1u);
  EXPECT_TRUE(r.loop_links[0].T_from_to.isApprox(m.loop_links[0].T_from_to, 0));
  EXPECT_EQ(r.loop_links[0].covariance, m.loop_links[0].covariance);
  ASSERT_EQ(r.places.size(), 2u);
  EXPECT_EQ(r.places[1].name, "lift");
  EXPECT_EQ(r.places[1].keyframe, 2u);
  EXPECT_EQ(r.places[1].stamp, 40.25);
  EXPECT_TRUE(r.places[1].T_kf_place.isApprox(m.places[1].T_kf_place, 0));
  EXPECT_EQ(r.places[0].name, "entrance");
  std::remove(path.c_str());
}

TEST(MapFile, RejectsDamagedFiles)
{
  const std::string path = tmp("good"), bad = tmp("bad");
  std::string err;
  ASSERT_TRUE(saveMapFile(path, sample(), &err));
  const std::string good = bytes(path);
  MapData keep;
  keep.places.push_back({"untouched", 0, Eigen::Isometry3d::Identity(), 0});
  auto rejects = [&](const std::string& b, const std::string& expect) {
    write(bad, b);
    MapData m = keep;
    std::string e;
    EXPECT_FALSE(loadMapFile(bad, m, &e));
    EXPECT_NE(e.find(expect), std::string::npos) << "message: " << e << " (expected: " << expect << ")";
    ASSERT_EQ(m.places.size(), 1u);
    EXPECT_EQ(m.places[0].name, "untouched");
  };
  // truncated anywhere: in the header, in the payload, in the checksum
  for (size_t n : {size_t(10), size_t(20), good.size() / 2, good.size() - 1})
    rejects(good.substr(0, n), "truncated");
  // one byte changed in the payload, in the checksum
  for (size_t i : {size_t(30), good.size() / 2, good.size() - 2})
  {
    std::string b = good;
    b[i] = static_cast<char>(b[i] ^ 0x5a);
    rejects(b, "corrupted");
  }
  rejects(good + "x", "corrupted");
  std::string other = good;
  other[8] = static_cast<char>(kMapFileVersion + 1);  // version field
  rejects(other, "version " + std::to_string(kMapFileVersion + 1));
  std::string v1 = good;
  v1[8] = 1;  // the first format (places not on keyframes)
  rejects(v1, "version 1");
  rejects("PNG\x1a not a map at all, long enough to hold a header", "not an assistive_slam map file");
  MapData m;
  EXPECT_FALSE(loadMapFile(tmp("missing_file"), m, &err));
  EXPECT_NE(err.find("cannot be opened"), std::string::npos);
  std::remove(path.c_str());
  std::remove(bad.c_str());
}
