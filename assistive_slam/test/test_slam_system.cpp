// Keyframe policy, stereo features with exact depth on a shifted texture, bounded submaps, the
// bounded worker queue and the loop closer thread.
#include <algorithm>
#include <cmath>
#include <random>
#include <gtest/gtest.h>
#include <opencv2/imgproc.hpp>
#include "assistive_slam/map_file.h"
#include "assistive_slam/slam_system.h"
#include "synthetic_camera.h"

using namespace assistive_slam;
using slam_test::camera;

namespace
{
/// A fronto-parallel textured plane, 640 + disp px wide.
cv::Mat planeTexture(int disp)
{
  cv::Mat big(480, 640 + disp, CV_8U);
  cv::RNG rng(5);
  rng.fill(big, cv::RNG::UNIFORM, 0, 255);
  cv::GaussianBlur(big, big, cv::Size(0, 0), 1.5);
  cv::Mat blocks(480 / 8, (640 + disp) / 8 + 1, CV_8U);
  rng.fill(blocks, cv::RNG::UNIFORM, 0, 255);
  cv::resize(blocks, blocks, cv::Size(blocks.cols * 8, blocks.rows * 8), 0, 0, cv::INTER_NEAREST);
  return big / 2 + blocks(cv::Rect(0, 0, big.cols, big.rows)) / 2;
}
/// The plane seen at disparity `disp`: the right image is the left shifted by `disp` px.
void texturePair(int disp, cv::Mat& left, cv::Mat& right)
{
  const cv::Mat big = planeTexture(disp);
  // a point at column X of `big` is at X in the left image and X - disp in the right one
  left = big(cv::Rect(0, 0, 640, 480)).clone();
  right = big(cv::Rect(disp, 0, 640, 480)).clone();
}
/// texturePair(16)'s plane (3 m away) seen from `scale` times closer on the same optical axis:
/// the texture magnified about the principal point (320, 240), disparity 16 x scale px.
void scaledPlanePair(double scale, cv::Mat& left, cv::Mat& right)
{
  cv::Mat big;
  cv::resize(planeTexture(16), big, cv::Size(), scale, scale, cv::INTER_LINEAR);
  const int disp = static_cast<int>(std::lround(16 * scale));
  const int x0 = static_cast<int>(std::lround(320 * (scale - 1))), y0 = static_cast<int>(std::lround(240 * (scale - 1)));
  left = big(cv::Rect(x0, y0, 640, 480)).clone();
  right = big(cv::Rect(x0 + disp, y0, 640, 480)).clone();
}
Eigen::Isometry3d along(double z)
{
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.translation().z() = z;
  return T;
}
}  // namespace

TEST(KeyframePolicy, ReplenishmentNeedsMotionAndDistanceForcesOne)
{
  SlamParams p;
  KeyframePolicy k(p);
  EXPECT_TRUE(k.take(along(0), false));                              // the first frame
  EXPECT_FALSE(k.take(along(0.1), true));                            // replenished but too close
  EXPECT_TRUE(k.take(along(p.keyframe_min_distance_m + 0.01), true));  // replenished and moved
  EXPECT_FALSE(k.take(along(p.keyframe_min_distance_m + 0.5), false));  // no replenishment, not far
  EXPECT_TRUE(k.take(along(p.keyframe_min_distance_m + 0.02 + p.keyframe_max_distance_m), false));
}

TEST(StereoFeatureExtractor, DepthOfShiftedPlaneIsExact)
{
  const int disp = 16;
  cv::Mat l, r;
  texturePair(disp, l, r);
  Keyframe kf;
  StereoFeatureExtractor(SlamParams()).extract(l, r, camera(), kf);
  ASSERT_GT(kf.points.size(), 200u);
  const double z = 400 * 0.12 / disp;  // 3 m
  // ORB finds corners per pyramid level: at the finest level the shift is exact; a level l
  // position is rounded on an image 1.2^l times smaller
  int level0 = 0, within = 0;
  for (size_t i = 0; i < kf.points.size(); ++i)
  {
    const double d = kf.keypoints[i].pt.x - kf.u_right[i];
    if (kf.keypoints[i].octave == 0)
    {
      ++level0;
      EXPECT_NEAR(d, disp, 1e-3);
      EXPECT_NEAR(kf.points[i].z(), z, 1e-3 * z);
    }
    within += std::abs(d - disp) <= std::pow(1.2, kf.keypoints[i].octave);
  }
  EXPECT_GT(level0, 100);
  EXPECT_GT(within, 0.95 * kf.points.size());
  EXPECT_EQ(kf.descriptors.rows, static_cast<int>(kf.points.size()));
}

TEST(SlamSystem, SubmapsAreBoundedAndLinked)
{
  SlamParams p;
  p.loop_closure = false;
  p.submap_max_keyframes = 3;
  p.ba_iterations = 0;  // the same images at every pose: only the bookkeeping is tested here
  cv::Mat l, r;
  texturePair(16, l, r);
  SlamSystem s(p, camera(), false);
  for (int i = 0; i < 10; ++i)
  {
    SlamFrame f;
    f.stamp = i;
    f.left = l;
    f.right = r;
    f.T_odom_cam = along(0.5 * i);  // farther than keyframe_min_distance each time
    f.vo_replenished = true;
    EXPECT_TRUE(s.addFrame(f));
  }
  EXPECT_EQ(s.stats().keyframes, 10);
  EXPECT_EQ(s.stats().submaps, 4);  // 3 + 3 + 3 + 1
  const auto links = s.links();
  ASSERT_EQ(links.size(), 3u);
  // consecutive submap origins 3 keyframes = 1.5 m apart along z (the same images: BA may not move them far)
  EXPECT_NEAR(links[0].T_from_to.translation().z(), 1.5, 0.05);
  for (const SubmapInfo& m : s.submaps())
    EXPECT_LE(m.keyframes.size(), 3u);
}

TEST(SlamSystem, WorkerQueueStaysBounded)
{
  SlamParams p;
  p.queue_size = 2;
  p.loop_closure = false;
  cv::Mat l, r;
  texturePair(16, l, r);
  SlamSystem s(p, camera(), true);
  int queued = 0;
  for (int i = 0; i < 40; ++i)
  {
    SlamFrame f;
    f.stamp = i;
    f.left = l;
    f.right = r;
    f.T_odom_cam = along(1.1 * i);
    queued += s.addFrame(f);
    EXPECT_LE(s.stats().queue_depth, 2);
  }
  s.waitIdle();
  const SlamStats st = s.stats();
  EXPECT_EQ(queued, 40);
  EXPECT_EQ(st.keyframes + st.dropped, 40);
  EXPECT_EQ(st.queue_depth, 0);
}

namespace
{
struct RunResult
{
  std::vector<Keyframe> keyframes;
  std::vector<LoopEvent> events;
  Eigen::Isometry3d T_map_odom = Eigen::Isometry3d::Identity();
  SlamStats stats;
};
/// Out and back along z with the same images everywhere: the way back closes loops on the
/// keyframes of the way out. `threaded`: worker and loop closer, awaited after every keyframe.
RunResult outAndBack(bool threaded)
{
  SlamParams p;
  p.submap_max_keyframes = 2;
  p.loop_skip_submaps = 1;
  p.ba_iterations = 0;
  cv::Mat l, r;
  texturePair(16, l, r);
  SlamSystem s(p, camera(), threaded);
  std::vector<double> zs;
  for (int i = 0; i <= 7; ++i)
    zs.push_back(0.5 * i);
  for (int i = 6; i >= 0; --i)
    zs.push_back(0.5 * i + 0.01);
  for (size_t i = 0; i < zs.size(); ++i)
  {
    SlamFrame f;
    f.stamp = static_cast<double>(i);
    f.left = l;
    f.right = r;
    f.T_odom_cam = along(zs[i]);
    f.vo_replenished = true;
    if (s.addFrame(f))
      s.waitIdle();
  }
  s.waitIdle();
  return {s.keyframes(), s.loopEvents(), s.mapToOdom(), s.stats()};
}
}  // namespace

// Loop closing on its own thread (loop_closing_thread), awaited after every keyframe as
// slam_benchmark does, builds the inline run's map exactly: the benchmarks' figures do not move.
TEST(SlamSystem, LoopClosingThreadAwaitedGivesTheInlineMap)
{
  const RunResult a = outAndBack(false), b = outAndBack(true);
  EXPECT_GT(a.stats.loops_accepted, 0);
  EXPECT_GT(a.stats.pose_graph_runs, 0);
  EXPECT_EQ(b.stats.loops_accepted, a.stats.loops_accepted);
  EXPECT_EQ(b.stats.loops_rejected, a.stats.loops_rejected);
  EXPECT_EQ(b.stats.pose_graph_runs, a.stats.pose_graph_runs);
  EXPECT_EQ(b.stats.loop_queue_depth, 0);
  ASSERT_EQ(a.keyframes.size(), b.keyframes.size());
  for (size_t i = 0; i < a.keyframes.size(); ++i)
    EXPECT_TRUE(a.keyframes[i].T_map_cam.matrix() == b.keyframes[i].T_map_cam.matrix()) << "keyframe " << i;
  ASSERT_EQ(a.events.size(), b.events.size());
  for (size_t i = 0; i < a.events.size(); ++i)
  {
    EXPECT_EQ(a.events[i].keyframe_new, b.events[i].keyframe_new);
    EXPECT_EQ(a.events[i].keyframe_old, b.events[i].keyframe_old);
    EXPECT_EQ(a.events[i].accepted, b.events[i].accepted);
  }
  EXPECT_TRUE(a.T_map_odom.matrix() == b.T_map_odom.matrix());
}

TEST(SlamSystem, PlacesRideOnTheirKeyframe)
{
  SlamParams p;
  p.loop_closure = false;
  cv::Mat l, r;
  texturePair(16, l, r);
  SlamSystem s(p, camera(), false);
  std::string err;
  Eigen::Isometry3d T;
  EXPECT_FALSE(s.tagPlace("door", along(0), 0, nullptr, &err));  // no keyframe yet
  EXPECT_NE(err.find("no keyframe"), std::string::npos);
  EXPECT_FALSE(s.placePose("", &T, &err));
  SlamFrame f;
  f.left = l;
  f.right = r;
  f.vo_replenished = true;
  ASSERT_TRUE(s.addFrame(f));  // keyframe 0 at the odom origin: map = odom until a closure
  Eigen::Isometry3d door = along(0.1);
  door.linear() = Eigen::AngleAxisd(0.3, Eigen::Vector3d::UnitY()).toRotationMatrix();
  Place tagged;
  ASSERT_TRUE(s.tagPlace("door", door, 1.0, &tagged, &err)) << err;
  EXPECT_EQ(tagged.keyframe, 0u);
  f.stamp = 2;
  f.T_odom_cam = along(1.2);
  ASSERT_TRUE(s.addFrame(f));  // keyframe 1
  ASSERT_TRUE(s.tagPlace("", along(1.5), 3.0, &tagged, &err));
  EXPECT_EQ(tagged.name, "place2");
  EXPECT_EQ(tagged.keyframe, 1u);
  EXPECT_TRUE(tagged.T_kf_place.isApprox(along(0.3), 1e-12));  // the VO's motion since keyframe 1
  ASSERT_TRUE(s.placePose("door", &T, &err));
  EXPECT_TRUE(T.isApprox(door, 1e-12));
  ASSERT_TRUE(s.placePose("", &T, &err));  // the last tagged
  EXPECT_TRUE(T.isApprox(along(1.5), 1e-12));
  EXPECT_FALSE(s.placePose("lift", &T, &err));
  EXPECT_NE(err.find("lift"), std::string::npos);
  ASSERT_TRUE(s.tagPlace("door", along(1.4), 4.0, nullptr, &err));  // tagged again: moved, now the last
  const auto places = s.places();
  ASSERT_EQ(places.size(), 2u);
  EXPECT_EQ(places[0].first.name, "place2");
  EXPECT_EQ(places[1].first.name, "door");
  EXPECT_TRUE(places[1].second.isApprox(along(1.4), 1e-12));
}

TEST(SlamSystem, LoadedMapRelocalisesOnAStoredPlace)
{
  SlamParams p;
  p.loop_closure = false;
  p.submap_max_keyframes = 2;
  // The same images at every pose: every verified relative pose is the identity, so two
  // consecutive queries 0.3 m apart in odom agree on map -> odom only within 0.4 m.
  p.loop_confirm_m = 0.5;
  cv::Mat l, r;
  texturePair(16, l, r);
  SlamFrame f;
  f.left = l;
  f.right = r;
  f.vo_replenished = true;
  MapData m;
  {
    SlamSystem first(p, camera(), false);
    for (int i = 0; i < 4; ++i)
    {
      f.stamp = i;
      f.T_odom_cam = along(0.5 * i);
      ASSERT_TRUE(first.addFrame(f));
    }
    std::string err;
    ASSERT_TRUE(first.tagPlace("door", along(1.6), 3.5, nullptr, &err)) << err;
    m = exportMap(first);
  }
  ASSERT_EQ(m.keyframes.size(), 4u);
  ASSERT_EQ(m.places.size(), 1u);

  SlamSystem second(p, camera(), false);
  std::string err;
  MapData broken = m;
  broken.submaps[0].keyframes.push_back(3);  // a keyframe listed by a submap that does not hold it
  EXPECT_FALSE(second.loadMap(broken, &err));
  ASSERT_TRUE(second.loadMap(m, &err)) << err;
  EXPECT_FALSE(second.localised());
  Eigen::Isometry3d T;
  EXPECT_FALSE(second.tagPlace("lift", along(0), 10, nullptr, &err));  // not localised: no new place
  EXPECT_NE(err.find("not localised"), std::string::npos);
  // the new session's odom starts elsewhere: 5 m further along z
  f.stamp = 10;
  f.T_odom_cam = along(5.0);
  ASSERT_TRUE(second.addFrame(f));
  EXPECT_FALSE(second.localised());  // one verified keyframe is not enough
  EXPECT_EQ(second.stats().keyframes, 4);
  f.stamp = 11;
  f.T_odom_cam = along(5.4);
  ASSERT_TRUE(second.addFrame(f));
  ASSERT_TRUE(second.localised());
  const SlamStats st = second.stats();
  EXPECT_EQ(st.relocalised_stamp, 11);
  EXPECT_EQ(st.relocalisation_queries, 2);
  EXPECT_EQ(st.keyframes, 5);  // the relocalising keyframe is mapped, in a new submap
  EXPECT_EQ(st.submaps, 3);
  // map -> odom: the odom pose 5.3 sits on a stored keyframe (identity relative pose)
  const Eigen::Vector3d x = (second.mapToOdom() * along(5.4)).translation();
  bool on_stored = false;
  for (const Keyframe& k : m.keyframes)
    on_stored = on_stored || (k.T_map_cam.translation() - x).norm() < 1e-6;
  EXPECT_TRUE(on_stored) << x.transpose();
  ASSERT_TRUE(second.placePose("door", &T, &err));
  EXPECT_TRUE(T.isApprox(along(1.6), 1e-12));  // the stored place, in the stored map
  const auto ev = second.loopEvents();
  ASSERT_EQ(ev.size(), 1u);
  EXPECT_TRUE(ev[0].relocalisation);
  EXPECT_FALSE(second.loadMap(m, &err));  // only before the first frame
}

TEST(SlamSystem, LoadedMapRelocalisesWhereTheAppearanceModelDoesNotPoint)
{
  // The appearance model ranks the stored submaps for a relocalisation query; on renders of the
  // parking walk its words barely match between two views of one place (1-5 of 800 observations),
  // so its ranking says little, and the stored place in view was verified only when it happened to
  // be among its appearance_candidates best, two queries in a row (the 11-25 map: by chance; on main
  // 83 keyframes). Here the model is misled on purpose: decoy submaps hold the query's own
  // descriptors (the model's best, every time) with scrambled points (verification fails); the
  // stored place is seen from 0.33 m closer. It is still found: the stored submaps are verified in
  // turn besides the model's (relocalisation_sweep), and a verified submap first on the next query.
  SlamParams p;
  p.loop_closure = false;
  p.submap_max_keyframes = 2;
  p.loop_confirm_m = 0.5;  // the same images at every stored pose (see LoadedMapRelocalisesOnAStoredPlace)
  cv::Mat l, r, ql, qr;
  texturePair(16, l, r);
  scaledPlanePair(1.125, ql, qr);  // the same plane 2.67 m away: disparity 18
  SlamFrame f;
  f.vo_replenished = true;
  MapData m;
  {
    SlamSystem first(p, camera(), false);
    f.left = l;
    f.right = r;
    for (int i = 0; i < 4; ++i)
    {
      f.stamp = i;
      f.T_odom_cam = along(0.5 * i);
      ASSERT_TRUE(first.addFrame(f));
    }
    m = exportMap(first);
  }
  ASSERT_EQ(m.submaps.size(), 2u);
  Keyframe q;
  StereoFeatureExtractor(p).extract(ql, qr, camera(), q);
  ASSERT_GT(q.points.size(), 100u);
  const uint32_t true_submaps = static_cast<uint32_t>(m.submaps.size());
  for (uint32_t d = 0; d < 4; ++d)  // four decoy submaps of two keyframes each
  {
    SubmapInfo s;
    s.id = static_cast<uint32_t>(m.submaps.size());
    s.T_map_origin = along(20.0 + 5.0 * d);
    for (int k = 0; k < 2; ++k)
    {
      Keyframe c = q;
      std::rotate(c.points.begin(), c.points.begin() + c.points.size() / 2, c.points.end());
      c.id = static_cast<uint32_t>(m.keyframes.size());
      c.submap = s.id;
      c.stamp = 4 + m.keyframes.size();
      c.T_map_cam = c.T_odom_cam = along(20.0 + 5.0 * d + 0.5 * k);
      c.path_m = m.keyframes.back().path_m + 0.5;
      c.landmark.assign(c.keypoints.size(), -1);
      s.keyframes.push_back(c.id);
      m.keyframes.push_back(c);
    }
    m.submaps.push_back(s);
  }

  SlamSystem second(p, camera(), false);
  std::string err;
  ASSERT_TRUE(second.loadMap(m, &err)) << err;
  f.left = ql;
  f.right = qr;
  for (int i = 0; i < 8 && !second.localised(); ++i)
  {
    f.stamp = 10 + i;
    f.T_odom_cam = along(5.0 + 0.4 * i);
    ASSERT_TRUE(second.addFrame(f));
  }
  ASSERT_TRUE(second.localised()) << "not relocalised in 8 queries";
  const SlamStats st = second.stats();
  EXPECT_LE(st.relocalisation_queries, 3);
  const auto ev = second.loopEvents();
  ASSERT_EQ(ev.size(), 1u);
  EXPECT_TRUE(ev[0].relocalisation);
  EXPECT_LT(ev[0].submap_old, true_submaps);  // a stored place, not a decoy
  // the query camera 0.33 m nearer the plane than the stored keyframe it was verified on
  EXPECT_NEAR(ev[0].T_old_new.translation().z(), 3.0 - 8.0 / 3.0, 0.05);
  EXPECT_NEAR(ev[0].T_old_new.translation().head<2>().norm(), 0.0, 0.05);
}
