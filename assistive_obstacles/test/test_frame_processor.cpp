// ObstacleFrameProcessor: the stage's whole frame step on exact synthetic disparities (a floor and
// a wall seen by a camera at 1.6 m pitched 30 deg down), against known answers and against the
// core pieces run by hand in the documented order.
#include <cmath>
#include <limits>

#include <gtest/gtest.h>

#include <assistive_obstacles/frame_processor.h>

#include "synthetic.h"

using namespace assistive_obstacles;

// Named: the core tests are one unity build, whose anonymous namespaces are shared.
namespace frame_processor_test
{
constexpr double kPitch = 30.0 * M_PI / 180.0;

Eigen::Isometry3d cameraPose(double x)
{
  Eigen::Isometry3d T = synthetic::cameraAt(x, 0.0, 1.6).cast<double>();
  T.linear() = T.linear() * Eigen::AngleAxisd(-kPitch, Eigen::Vector3d::UnitX()).toRotationMatrix();  // look down
  return T;
}

/// Exact disparity at the matcher's scale of a floor (z = 0) and, with `wall`, a wall at x = 2.0
/// (y in [-1, 1], 1.2 m high), seen from `T_world_cam`; -1 where neither is in view.
cv::Mat sceneDisparity(const StereoModel& m, const ObstaclesParams& p, const Eigen::Isometry3d& T_world_cam, bool wall)
{
  const double sc = p.disparity_scale;
  const int w = static_cast<int>(std::lround(m.width * sc)), h = static_cast<int>(std::lround(m.height * sc));
  const double fx = m.fx * sc, fy = m.fy * sc, cx = (m.cx + 0.5) * sc - 0.5, cy = (m.cy + 0.5) * sc - 0.5;
  cv::Mat d(h, w, CV_32F, cv::Scalar(-1.f));
  const Eigen::Vector3d o = T_world_cam.translation();
  for (int v = 0; v < h; ++v)
    for (int u = 0; u < w; ++u)
    {
      const Eigen::Vector3d ray = T_world_cam.linear() * Eigen::Vector3d((u - cx) / fx, (v - cy) / fy, 1.0);
      double t = std::numeric_limits<double>::infinity();  // optical depth (the ray's z is 1)
      if (ray.z() < 0) t = -o.z() / ray.z();
      if (wall && ray.x() > 0)
      {
        const double tw = (2.0 - o.x()) / ray.x();
        const Eigen::Vector3d q = o + tw * ray;
        if (tw > 0 && tw < t && std::abs(q.y()) <= 1.0 && q.z() >= 0.0 && q.z() <= 1.2) t = tw;
      }
      if (std::isfinite(t)) d.at<float>(v, u) = static_cast<float>(fx * m.baseline / t);
    }
  return d;
}

int8_t codeAt(const GridData& g, double x, double y)
{
  const int ix = static_cast<int>(std::floor((x - g.origin_x) / g.resolution));
  const int iy = static_cast<int>(std::floor((y - g.origin_y) / g.resolution));
  if (ix < 0 || iy < 0 || ix >= g.width || iy >= g.height) return -2;
  return g.data[iy * g.width + ix];
}

struct WallScene
{
  ObstaclesParams params;
  StereoModel model;
  cv::Mat left, right;
  WallScene()
  {
    params.movers = false;  // a textureless image has no scene flow; the movers' own test is test_mover_pipeline
    left = cv::Mat(model.height, model.width, CV_8UC1, cv::Scalar(0));
    right = left.clone();
  }
  ObstacleFrame frame(double stamp, const cv::Mat& disp, double x = 0.0) const
  {
    ObstacleFrame f;
    f.stamp = stamp;
    f.left = left;
    f.right = right;
    f.model = model;
    f.T_world_cam = cameraPose(x);
    f.disparity = &disp;
    return f;
  }
};

/// A ranger on the camera, looking along the world's +x.
bool rangerOnCamera(const RangeSample&, Eigen::Isometry3f& T)
{
  T = Eigen::Isometry3f::Identity();
  T.translation() = Eigen::Vector3f(0.f, 0.f, 1.2f);
  return true;
}
}  // namespace frame_processor_test
using namespace frame_processor_test;

TEST(ObstacleFrameProcessor, WallIsObstacleFloorFreeGridFromTheFifthFrame)
{
  WallScene s;
  const cv::Mat disp = sceneDisparity(s.model, s.params, cameraPose(0.0), true);
  ObstacleFrameProcessor proc(s.params);
  for (int i = 0; i < 8; ++i)
  {
    const ObstacleFrameResult& r = proc.process(s.frame(0.1 * i, disp));
    ASSERT_TRUE(r.disparity_ok);
    EXPECT_EQ(r.cleared, i == 0);  // the first frame starts the map
    EXPECT_TRUE(r.map_updated);
    // rebuild_frames = 5: the grid from the fifth fresh frame on.
    EXPECT_EQ(r.verdict, i < 4 ? FrameGate::Verdict::REBUILDING : FrameGate::Verdict::FRESH) << i;
    EXPECT_EQ(r.has_grid, i >= 4) << i;
    EXPECT_EQ(r.octomap_inserted, i == 4);  // octomap_insert_every = 5 frames
  }
  const GridData& g = proc.last().grid;
  EXPECT_EQ(codeAt(g, 2.1, 0.1), CELL_OBSTACLE);  // the wall's cells
  EXPECT_EQ(codeAt(g, 2.1, -0.5), CELL_OBSTACLE);
  EXPECT_EQ(codeAt(g, 1.5, 0.1), CELL_FREE);      // the floor in front of it
  EXPECT_EQ(codeAt(g, 1.3, -0.3), CELL_FREE);
  EXPECT_EQ(codeAt(g, 3.0, 0.1), CELL_UNKNOWN);   // behind the wall
  EXPECT_EQ(codeAt(g, -1.0, 0.0), CELL_UNKNOWN);  // behind the wearer
  EXPECT_EQ(proc.counters().frames, 8);
  EXPECT_EQ(proc.points().size(), proc.map().stats().points_in);
}

TEST(ObstacleFrameProcessor, SameGridAsTheCorePiecesInTheNodeletsOrder)
{
  WallScene s;
  const cv::Mat disp = sceneDisparity(s.model, s.params, cameraPose(0.0), true);
  ObstacleFrameProcessor proc(s.params);
  DisparityEstimator est(s.params);
  ObstacleMap map(s.params);
  std::vector<Eigen::Vector3f> pts, normals;
  for (int i = 0; i < 6; ++i)
  {
    const ObstacleFrameResult& r = proc.process(s.frame(0.1 * i, disp));
    est.toPoints(disp, s.model, pts, &normals);  // surface_push_normal: normals from the disparity
    map.update(pts, cameraPose(0.0).cast<float>(), &s.model, &disp, &normals);
    GridData g;
    map.grid(g);
    if (!r.has_grid) continue;
    EXPECT_EQ(r.grid.data, g.data);
    EXPECT_EQ(r.grid.origin_x, g.origin_x);
    EXPECT_EQ(r.grid.origin_y, g.origin_y);
  }
}

TEST(ObstacleFrameProcessor, FrameWithoutDepthLeavesTheMapAndWithholdsTheGrid)
{
  WallScene s;
  const cv::Mat disp = sceneDisparity(s.model, s.params, cameraPose(0.0), true);
  const cv::Mat none(disp.size(), CV_32F, cv::Scalar(-1.f));  // a covered lens
  ObstacleFrameProcessor proc(s.params);
  for (int i = 0; i < 6; ++i) proc.process(s.frame(0.1 * i, disp));
  const std::vector<int8_t> before = proc.last().grid.data;
  // Two readings stamped before the dark frame wait in the queue for the next frame with depth.
  proc.queueRange({ 0.55, 1.5, 0.2, 4.0, 0.26, "sonar" });
  proc.queueRange({ 0.58, std::numeric_limits<double>::infinity(), 0.2, 4.0, 0.26, "sonar" });
  const ObstacleFrameResult& r = proc.process(s.frame(0.6, none), rangerOnCamera);
  EXPECT_EQ(r.verdict, FrameGate::Verdict::NO_DEPTH);
  EXPECT_FALSE(r.map_updated);
  EXPECT_FALSE(r.has_grid);
  EXPECT_TRUE(r.ranges.empty());
  EXPECT_EQ(proc.counters().frames, 6);
  EXPECT_EQ(proc.gate().noDepthFrames(), 1);
  const ObstacleFrameResult& r2 = proc.process(s.frame(0.7, disp), rangerOnCamera);
  EXPECT_FALSE(r2.cleared);  // no depth is not a gap
  EXPECT_TRUE(r2.has_grid);
  ASSERT_EQ(r2.ranges.size(), 2u);
  EXPECT_EQ(r2.ranges[0].check, RangeCheck::ECHO);
  EXPECT_EQ(r2.ranges[1].check, RangeCheck::NO_ECHO);
  EXPECT_EQ(proc.counters().ranges_echo, 1);
  EXPECT_EQ(proc.counters().ranges_no_echo, 1);
  EXPECT_EQ(r2.grid.data.size(), before.size());
}

TEST(ObstacleFrameProcessor, GapOrUntrustedPoseClearsTheMapAndWithholdsTheGridAgain)
{
  WallScene s;
  const cv::Mat wall = sceneDisparity(s.model, s.params, cameraPose(0.0), true);
  const cv::Mat floor = sceneDisparity(s.model, s.params, cameraPose(0.0), false);
  for (const bool gap : { true, false })
  {
    ObstacleFrameProcessor proc(s.params);
    for (int i = 0; i < 6; ++i) proc.process(s.frame(0.1 * i, wall));
    ASSERT_EQ(codeAt(proc.last().grid, 2.1, 0.1), CELL_OBSTACLE);
    // The wall is gone after a gap of 1 s (> max_frame_gap_s), or after the VO lost its pose.
    ObstacleFrame f = s.frame(gap ? 1.5 : 0.6, floor);
    f.pose_trusted = gap;
    const double t0 = f.stamp;
    const ObstacleFrameResult& r = proc.process(f);
    EXPECT_TRUE(r.cleared);
    EXPECT_FALSE(r.gate_reason.empty());
    EXPECT_FALSE(r.has_grid);
    EXPECT_EQ(proc.gate().clears(), 1);
    for (int i = 1; i < 5; ++i) proc.process(s.frame(t0 + 0.1 * i, floor));
    ASSERT_TRUE(proc.last().has_grid);
    // The new map never saw the wall: its cells are what the floor behind it says (never obstacle).
    EXPECT_NE(codeAt(proc.last().grid, 2.1, 0.1), CELL_OBSTACLE);
  }
}

TEST(ObstacleFrameProcessor, RangerReadingsStaleAfterAClearWithoutPoseOrLaterWait)
{
  WallScene s;
  const cv::Mat disp = sceneDisparity(s.model, s.params, cameraPose(0.0), true);
  ObstacleFrameProcessor proc(s.params);
  proc.process(s.frame(0.0, disp), rangerOnCamera);
  proc.queueRange({ 0.05, 1.5, 0.2, 4.0, 0.26, "sonar" });  // before the next clear: stale
  proc.queueRange({ 2.0, 1.5, 0.2, 4.0, 0.26, "sonar" });   // at the new frame: applied
  proc.queueRange({ 2.01, 0.1, 0.2, 4.0, 0.26, "sonar" });  // after it: waits; below min_range: rejected later
  const ObstacleFrameResult& r = proc.process(s.frame(2.0, disp), rangerOnCamera);
  EXPECT_TRUE(r.cleared);
  ASSERT_EQ(r.ranges.size(), 1u);
  EXPECT_EQ(r.ranges[0].sample.stamp, 2.0);
  EXPECT_EQ(proc.counters().ranges_stale, 1);
  // No pose for it: not used.
  proc.queueRange({ 2.05, 1.5, 0.2, 4.0, 0.26, "sonar" });
  const ObstacleFrameResult& r2 = proc.process(s.frame(2.1, disp), [](const RangeSample& q, Eigen::Isometry3f& T) {
    return q.stamp < 2.02 && rangerOnCamera(q, T);
  });
  ASSERT_EQ(r2.ranges.size(), 1u);
  EXPECT_EQ(r2.ranges[0].check, RangeCheck::OUT_OF_LIMITS);
  EXPECT_EQ(proc.counters().ranges_rejected, 1);
  EXPECT_EQ(proc.counters().last_rejection, rangeCheckName(RangeCheck::OUT_OF_LIMITS));
  EXPECT_EQ(proc.counters().ranges_no_pose, 1);
  EXPECT_EQ(proc.counters().ranges_echo, 1);
  // The queue keeps the latest MaxQueuedRanges readings.
  for (size_t i = 0; i < ObstacleFrameProcessor::MaxQueuedRanges + 7; ++i)
    proc.queueRange({ 2.11 + 0.001 * static_cast<double>(i), 1.5, 0.2, 4.0, 0.26, "sonar" });
  const ObstacleFrameResult& r3 = proc.process(s.frame(2.3, disp), rangerOnCamera);
  ASSERT_EQ(r3.ranges.size(), ObstacleFrameProcessor::MaxQueuedRanges);
  EXPECT_DOUBLE_EQ(r3.ranges.front().sample.stamp, 2.11 + 0.007);
  // With the ranger off, readings are not even queued (the nodelet does not subscribe).
  ObstaclesParams off = s.params;
  off.sonar_enabled = false;
  ObstacleFrameProcessor quiet(off);
  quiet.queueRange({ 0.0, 1.5, 0.2, 4.0, 0.26, "sonar" });
  EXPECT_TRUE(quiet.process(s.frame(0.0, disp), rangerOnCamera).ranges.empty());
}

TEST(ObstacleFrameProcessor, RangerReadingsFromBeforeTimeWentBackAreDropped)
{
  // A bag loop (issue 31): readings queued at 4.6-4.7 s, then the clock restarts at 0. The old
  // ones would block the queue (stamped after every new frame) and later be placed at new poses.
  WallScene s;
  const cv::Mat disp = sceneDisparity(s.model, s.params, cameraPose(0.0), true);
  ObstacleFrameProcessor proc(s.params);
  proc.process(s.frame(4.5, disp), rangerOnCamera);
  proc.queueRange({ 4.6, 1.5, 0.2, 4.0, 0.26, "sonar" });
  proc.queueRange({ 4.7, 1.5, 0.2, 4.0, 0.26, "sonar" });
  proc.queueRange({ 0.0, 1.5, 0.2, 4.0, 0.26, "sonar" });  // time went back
  const ObstacleFrameResult& r = proc.process(s.frame(0.0, disp), rangerOnCamera);
  EXPECT_TRUE(r.cleared);
  ASSERT_EQ(r.ranges.size(), 1u);
  EXPECT_EQ(r.ranges[0].sample.stamp, 0.0);
  // nothing from the old walk is left to come out later
  EXPECT_TRUE(proc.process(s.frame(5.0, disp), rangerOnCamera).ranges.empty());
}

TEST(ObstacleFrameProcessor, FrameWithoutPoseOrUnusableImagesUpdatesNothing)
{
  WallScene s;
  const cv::Mat disp = sceneDisparity(s.model, s.params, cameraPose(0.0), true);
  ObstacleFrameProcessor proc(s.params);
  ObstacleFrame f = s.frame(0.0, disp);
  f.has_pose = false;
  const ObstacleFrameResult& r = proc.process(f);
  EXPECT_TRUE(r.disparity_ok);  // the disparity is still published
  EXPECT_FALSE(r.has_pose);
  EXPECT_FALSE(r.map_updated);
  EXPECT_EQ(proc.counters().no_pose, 1);
  EXPECT_EQ(proc.counters().frames, 0);
  EXPECT_GT(proc.points().size(), 1000u);
  // The matcher refuses an empty pair.
  ObstacleFrame bad = s.frame(0.1, disp);
  bad.disparity = nullptr;
  bad.left = cv::Mat();
  EXPECT_FALSE(proc.process(bad).disparity_ok);
  EXPECT_EQ(proc.counters().bad_input, 1);
}

TEST(ObstacleFrameProcessor, MoversReportedEveryFrameTheMapTakesAlsoEmpty)
{
  WallScene s;
  s.params.movers = true;
  const cv::Mat disp = sceneDisparity(s.model, s.params, cameraPose(0.0), true);
  ObstacleFrameProcessor proc(s.params);
  EXPECT_EQ(proc.movers(), nullptr);
  const ObstacleFrameResult& r = proc.process(s.frame(0.0, disp));
  EXPECT_TRUE(r.movers_enabled);
  EXPECT_TRUE(r.movers.empty());  // a static scene: no one
  EXPECT_NEAR(r.feet_z, 1.6 - s.params.camera_height, 1e-6);
  ASSERT_NE(proc.movers(), nullptr);
  // The movers' own pose, absent: no scene flow this frame.
  ObstacleFrame f = s.frame(0.1, disp);
  f.own_mover_pose = true;
  EXPECT_TRUE(proc.process(f).movers.empty());
}
