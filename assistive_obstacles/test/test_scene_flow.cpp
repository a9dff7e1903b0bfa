// The scene-flow source (scene_flow.h) on exact synthetic images, and the nodelet-free mover
// pipeline (flow -> segmentation -> tracker -> map, mover_pipeline.h) on a synthetic person crossing
// a static scene in front of a standing wearer.
#include <cmath>
#include <set>

#include <gtest/gtest.h>
#include <opencv2/imgproc.hpp>

#include <assistive_obstacles/cell_values.h>
#include <assistive_obstacles/mover_pipeline.h>
#include <assistive_obstacles/obstacle_map.h>
#include <assistive_obstacles/scene_flow.h>

#include "synthetic.h"

using namespace assistive_obstacles;

namespace
{
/// Smooth random texture (blurred uniform noise, contrast stretched): corners everywhere.
cv::Mat texture(int w, int h, unsigned seed)
{
  cv::Mat t(h, w, CV_8U);
  cv::RNG rng(seed);
  rng.fill(t, cv::RNG::UNIFORM, 0, 256);
  cv::GaussianBlur(t, t, cv::Size(0, 0), 1.5);
  cv::normalize(t, t, 0, 255, cv::NORM_MINMAX);
  return t;
}

/// Walls and clothes as in the generated worlds: a smooth pattern of low contrast (the texture
/// blurred again at 2 px, over 56 grey levels).
cv::Mat smooth(int w, int h, unsigned seed)
{
  cv::Mat t = texture(w, h, seed);
  cv::GaussianBlur(t, t, cv::Size(0, 0), 2.0);
  cv::normalize(t, t, 100, 156, cv::NORM_MINMAX);
  return t;
}
}  // namespace

TEST(SceneFlow, DisparityAtIsBilinearAndRejectsEdges)
{
  // A ramp d = 4 + 0.1 u_s + 0.05 v_s at scale 0.5: bilinear interpolation is exact on it.
  cv::Mat d(40, 60, CV_32F);
  for (int v = 0; v < d.rows; ++v)
    for (int u = 0; u < d.cols; ++u) d.at<float>(v, u) = 4.f + 0.1f * u + 0.05f * v;
  // Full-resolution pixel (41.3, 30.7) -> scale coordinates (20.9, 15.1); full-res disparity = 2 d.
  const double us = (41.3 + 0.5) * 0.5 - 0.5, vs = (30.7 + 0.5) * 0.5 - 0.5;
  EXPECT_NEAR(disparityAt(d, 0.5, 41.3, 30.7, 1.0), 2.0 * (4.0 + 0.1 * us + 0.05 * vs), 1e-5);
  // A 3x3 range above the limit (a depth edge), an invalid neighbour, the border: no depth.
  EXPECT_LT(disparityAt(d, 0.5, 41.3, 30.7, 0.1), 0.0);
  d.at<float>(16, 21) = -1.f;
  EXPECT_LT(disparityAt(d, 0.5, 41.3, 30.7, 1.0), 0.0);
  EXPECT_LT(disparityAt(d, 0.5, 0.0, 30.0, 1.0), 0.0);
}

TEST(SceneFlow, ShiftedTextureGivesExactFlowAndDepth)
{
  // A fronto-parallel textured wall at Z = 5 m (full-resolution disparity 12 px = 500 * 0.12 / 5;
  // 6 px at the matcher's scale 0.5), the image shifted by exactly (+5, -3) px between frames: every
  // point moves by (5, -3) px * Z / f = (0.05, -0.03) m and keeps its depth.
  const StereoModel m;
  const cv::Mat big = texture(700, 540, 7);
  const cv::Mat a = big(cv::Rect(30, 30, 640, 480)).clone();
  const cv::Mat b = big(cv::Rect(25, 33, 640, 480)).clone();  // content moves +5 in u, -3 in v
  const cv::Mat disp(240, 320, CV_32F, cv::Scalar(6.0));
  SceneFlowExtractor sf;
  EXPECT_TRUE(sf.process(a, disp, m).empty());  // first frame: nothing to pair with
  const std::vector<SceneFlowPoint>& flow = sf.process(b, disp, m);
  EXPECT_GT(sf.detected(), 300);
  ASSERT_GT(flow.size(), 250u);
  // Lucas-Kanade stops after 10 iterations or 0.03 px steps (speed): its error in px, each point
  // below the forward-backward bound (0.5 px), 0.1 px on average (1 mm at 5 m).
  double sum = 0.0;
  for (const SceneFlowPoint& f : flow)
  {
    EXPECT_DOUBLE_EQ(f.prev.z(), 5.0);
    EXPECT_DOUBLE_EQ(f.cur.z(), 5.0);
    const double ex = (f.cur.x() - f.prev.x()) * m.fx / 5.0 - 5.0, ey = (f.cur.y() - f.prev.y()) * m.fy / 5.0 + 3.0;
    EXPECT_LT(std::hypot(ex, ey), 0.5);
    sum += std::hypot(ex, ey);
  }
  EXPECT_LT(sum / flow.size(), 0.1);
  // A blank image has no corner: no flow, no crash; a wrong input type resets.
  sf.process(cv::Mat(480, 640, CV_8U, cv::Scalar(128)), disp, m);
  EXPECT_TRUE(sf.process(cv::Mat(480, 640, CV_8U, cv::Scalar(128)), disp, m).empty());
  EXPECT_TRUE(sf.process(cv::Mat(480, 640, CV_32F), disp, m).empty());
}

// With the two frames' poses each corner starts where the ego-motion puts a static point: a 60 px
// image motion (beyond the pyramid's capture range from the old pixel) is tracked exactly.
TEST(SceneFlow, EgoMotionPredictionStartsTheTracks)
{
  const StereoModel m;
  const cv::Mat big = texture(760, 540, 9);
  const cv::Mat a = big(cv::Rect(30, 30, 640, 480)).clone();
  const cv::Mat b = big(cv::Rect(90, 30, 640, 480)).clone();  // content moves -60 px in u
  const cv::Mat disp(240, 320, CV_32F, cv::Scalar(6.0));      // Z = 5 m
  // The camera moved 0.6 m along its x axis (60 px * 5 m / 500 px).
  const Eigen::Isometry3d Ta = Eigen::Isometry3d::Identity();
  Eigen::Isometry3d Tb = Eigen::Isometry3d::Identity();
  Tb.translation().x() = 0.6;
  SceneFlowExtractor sf;
  sf.process(a, disp, m, &Ta);
  const std::vector<SceneFlowPoint>& flow = sf.process(b, disp, m, &Tb);
  ASSERT_GT(flow.size(), 200u);
  const Eigen::Isometry3d T_cur_prev = Tb.inverse() * Ta;
  double worst = 0.0;
  for (const SceneFlowPoint& f : flow) worst = std::max(worst, (f.cur - T_cur_prev * f.prev).norm());
  EXPECT_LT(worst, 0.01) << "every point static: its residual within 1 mm per 0.1 px at 5 m";
}

// Kept tracks (issue 37, the movers' cost): a feature tracked with depth goes on from its new
// pixel, where its depth was matched as the current end; new corners only fill the buckets left
// empty. A wall at 5 m, the content moving 4 px a frame: most features are kept, each kept one's
// previous end is exactly the last frame's current end, and the flow stays exact.
TEST(SceneFlow, KeptTracksGoOnFromTheirNewPixelWithTheDepthFoundThere)
{
  const StereoModel m;
  const cv::Mat big = texture(760, 540, 13);
  const cv::Mat disp(240, 320, CV_32F, cv::Scalar(6.0));  // Z = 5 m
  SceneFlowExtractor sf;
  std::vector<Eigen::Vector3d> last_cur;
  for (int k = 0; k < 5; ++k)
  {
    const cv::Mat img = big(cv::Rect(30 + 4 * k, 30, 640, 480)).clone();  // content moves -4 px in u
    Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
    T.translation().x() = 0.04 * k;  // 4 px * 5 m / 500 px
    const std::vector<SceneFlowPoint>& flow = sf.process(img, disp, m, &T);
    if (k == 0)
    {
      EXPECT_TRUE(flow.empty());
      continue;
    }
    ASSERT_GT(flow.size(), 250u);
    if (k == 1)
    {
      EXPECT_EQ(sf.kept(), 0);
    }
    int from_last = 0;
    for (const SceneFlowPoint& f : flow)
    {
      EXPECT_LT((f.cur - f.prev - Eigen::Vector3d(-0.04, 0.0, 0.0)).norm(), 0.01);
      for (const Eigen::Vector3d& c : last_cur)
        if (c == f.prev)
        {
          ++from_last;
          break;
        }
    }
    if (k >= 2)
    {
      EXPECT_GT(sf.kept(), sf.detected() / 2) << "frame " << k;
      EXPECT_GE(from_last, sf.kept() * 9 / 10) << "a kept track's previous end is the last frame's current end";
    }
    last_cur.clear();
    for (const SceneFlowPoint& f : flow) last_cur.push_back(f.cur);
  }
  // Without: every feature is a new corner.
  SceneFlowParams fresh;
  fresh.keep_tracks = false;
  SceneFlowExtractor sf2(fresh);
  for (int k = 0; k < 3; ++k)
  {
    Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
    T.translation().x() = 0.04 * k;
    sf2.process(big(cv::Rect(30 + 4 * k, 30, 640, 480)).clone(), disp, m, &T);
  }
  EXPECT_EQ(sf2.kept(), 0);
  EXPECT_GT(sf2.detected(), 300);
}

// New corners fill only the buckets the kept tracks leave, within what is left of the budget.
TEST(SceneFlow, DetectCornersLeavesTheTakenBucketsAndBudget)
{
  const cv::Mat img = texture(640, 480, 17);
  SceneFlowParams p;
  p.half_resolution_corners = false;
  p.max_features = 400;
  std::vector<cv::KeyPoint> scratch;
  std::vector<cv::Point2f> all, fresh;
  detectCorners(img, p, scratch, all);
  ASSERT_EQ(all.size(), 400u);
  const std::vector<cv::Point2f> taken(all.begin(), all.begin() + 150);
  detectCorners(img, p, scratch, fresh, nullptr, nullptr, nullptr, &taken);
  EXPECT_EQ(fresh.size(), 250u);
  std::set<std::pair<int, int>> taken_buckets;
  for (const cv::Point2f& t : taken) taken_buckets.insert({static_cast<int>(t.x) / 8, static_cast<int>(t.y) / 8});
  for (const cv::Point2f& f : fresh)
    EXPECT_EQ(taken_buckets.count({static_cast<int>(f.x) / 8, static_cast<int>(f.y) / 8}), 0u) << f;
  const std::vector<cv::Point2f> full(all.begin(), all.end());
  detectCorners(img, p, scratch, fresh, nullptr, nullptr, nullptr, &full);
  EXPECT_TRUE(fresh.empty()) << "the budget is used up";
}

namespace
{
/// The crossing scene: a standing wearer (camera 1.6 m above the floor at the origin, looking
/// along +x), a textured wall 6 m ahead filling the view, a static post at (1.7, 0.9), and a
/// person (0.5 m wide, 1.7 m tall, fronto-parallel, own texture) walking across at x = 2.2 m from
/// y = -1.2 to +1.2 at 1.2 m/s, at 15 Hz.
struct CrossingScene
{
  StereoModel m;
  cv::Mat wall = texture(640, 480, 11), body = texture(122, 268, 12);
  // The body's centre walks at x = 2.2; the camera sees its front face 0.15 m nearer (the offset
  // MoverPipeline assumes for a body's seen surface).
  static constexpr double kX = 2.2, kFront = 2.05, kSpeed = 1.2, kY0 = -1.2, kHalfWidth = 0.25;
  double personY(double t) const { return kY0 + kSpeed * t; }

  /// Left image and disparity (matcher scale 0.5) at time t.
  void render(double t, cv::Mat& img, cv::Mat& disp) const
  {
    img = wall.clone();
    const double u_left = m.cx - m.fx * (personY(t) + kHalfWidth) / kFront;  // world +y is image left
    const double v_top = m.cy - m.fy * (1.7 - 1.6) / kFront;
    const cv::Mat A = (cv::Mat_<double>(2, 3) << 1, 0, u_left, 0, 1, v_top);
    cv::warpAffine(body, img, A, img.size(), cv::INTER_LINEAR, cv::BORDER_TRANSPARENT);
    disp = cv::Mat(240, 320, CV_32F, cv::Scalar(m.fx * m.baseline / 6.0 * 0.5));
    const float dp = static_cast<float>(m.fx * m.baseline / kFront * 0.5);
    for (int v = 0; v < disp.rows; ++v)
      for (int u = 0; u < disp.cols; ++u)
      {
        const double uf = (u + 0.5) / 0.5 - 0.5, vf = (v + 0.5) / 0.5 - 0.5;
        if (uf >= u_left && uf < u_left + body.cols && vf >= v_top && vf < v_top + body.rows) disp.at<float>(v, u) = dp;
      }
  }

  /// The map's points (camera frame): floor, the post, the person's body.
  std::vector<Eigen::Vector3f> points(double t, const Eigen::Isometry3f& T_world_cam) const
  {
    synthetic::Points w;
    synthetic::patch(w, 0.6, 3.4, -2.0, 2.0, 0.0);
    synthetic::pole(w, 1.7, 0.9, 0.05, 1.2);
    const double y = personY(t);
    for (double dx = -0.15; dx <= 0.15 + 1e-9; dx += 0.05)
      for (double dy = -0.2; dy <= 0.2 + 1e-9; dy += 0.05)
        for (double z = 0.05; z <= 1.7; z += 0.05)
          w.emplace_back(static_cast<float>(kX + dx), static_cast<float>(y + dy), static_cast<float>(z));
    return synthetic::toCamera(w, T_world_cam);
  }
};

struct CrossingOutcome
{
  int frames = 0, tracked_frames = 0;
  double max_pos_err = 0.0, max_vel_err = 0.0;   ///< confirmed track vs truth (velocity after 0.5 s)
  std::set<std::pair<int, int>> ghost_cells;     ///< path cells reported obstacle after the person left them
  bool permanent_on_path = false;
  bool post_obstacle = false;                    ///< the post's cell at the end
  int false_tracks = 0;                          ///< confirmed tracks farther than 0.5 m from the person
};

/// `body`, `wall`: other textures than the scene's; `p`: the stage's parameters.
CrossingOutcome crossing(bool movers, const cv::Mat* body = nullptr, const cv::Mat* wall = nullptr,
                         ObstaclesParams p = ObstaclesParams())
{
  CrossingScene sc;
  if (body) sc.body = *body;
  if (wall) sc.wall = *wall;
  p.column_bands = 0;  // no camera model given to update()
  ObstacleMap map(p);
  MoverPipeline pipe(moverPipelineParams(p, sc.m));
  const Eigen::Isometry3f T = synthetic::cameraAt(0.0, 0.0, 1.6);
  CrossingOutcome out;
  const double dt = 1.0 / 15.0;
  for (int k = 0; k * dt <= 2.0 + 1e-9; ++k)
  {
    const double t = k * dt;
    cv::Mat img, disp;
    sc.render(t, img, disp);
    const std::vector<MoverFootprint>& fp = pipe.process(t, img, disp, sc.m, T.cast<double>());
    if (movers) map.setMovers(fp);
    map.update(sc.points(t, T), T);
    ++out.frames;
    const Eigen::Vector2d truth(CrossingScene::kX, sc.personY(t));
    for (const ReportedMover& r : pipe.confirmed())
    {
      const double e = (r.track.position() - truth).norm();
      if (e > 0.5)
      {
        ++out.false_tracks;
        continue;
      }
      ++out.tracked_frames;
      out.max_pos_err = std::max(out.max_pos_err, e);
      if (t - r.track.born >= 0.5)
        out.max_vel_err = std::max(out.max_vel_err, (r.track.velocity() - Eigen::Vector2d(0, CrossingScene::kSpeed)).norm());
    }
    // Cells of the path x in [2.0, 2.4) the person has fully left (its body spans y +-0.2).
    GridData g;
    map.grid(g);
    for (int gy = -7; gy <= 7; ++gy)
      for (int gx = 10; gx <= 11; ++gx)
      {
        const double yc = (gy + 0.5) * 0.2;
        if (yc > sc.personY(t) - 0.5) continue;  // not yet left behind (0.1 m half cell + 0.2 m body + margin)
        const int ex = static_cast<int>(std::floor(((gx + 0.5) * 0.2 - g.origin_x) / g.resolution));
        const int ey = static_cast<int>(std::floor((yc - g.origin_y) / g.resolution));
        if (g.data[static_cast<size_t>(ey) * g.width + ex] == CELL_OBSTACLE) out.ghost_cells.insert({gx, gy});
        const CellCounters* c = map.temporal().find(gx, gy);
        out.permanent_on_path = out.permanent_on_path || (c && c->permanent);
      }
    const int px = static_cast<int>(std::floor((1.7 - g.origin_x) / g.resolution));
    const int py = static_cast<int>(std::floor((0.9 - g.origin_y) / g.resolution));
    out.post_obstacle = g.data[static_cast<size_t>(py) * g.width + px] == CELL_OBSTACLE;
  }
  return out;
}
}  // namespace

TEST(MoverPipelineImages, CrossingPersonTrackedNoGhostPostKept)
{
  const CrossingOutcome o = crossing(true);
  // Reported from its third detection (the first frame has no flow) to the end: its points and
  // its centre move the same way from the start.
  EXPECT_GE(o.tracked_frames, o.frames - 3);
  EXPECT_EQ(o.false_tracks, 0);
  EXPECT_LT(o.max_pos_err, 0.15);
  EXPECT_LT(o.max_vel_err, 0.3);
  EXPECT_TRUE(o.ghost_cells.empty()) << o.ghost_cells.size() << " ghost cells";
  EXPECT_FALSE(o.permanent_on_path);
  EXPECT_TRUE(o.post_obstacle);  // the static post stays an obstacle
  // The same walk with the map unaware of movers leaves a trail of obstacle cells behind the person.
  const CrossingOutcome blind = crossing(false);
  EXPECT_FALSE(blind.ghost_cells.empty());
  EXPECT_TRUE(blind.post_obstacle);
}

TEST(MoverPipelineImages, PersonInSmoothClothesIsTracked)
{
  // Issue 37: in generated busy worlds FAST at 12 grey levels found corners only on people's
  // silhouettes (which have no depth) and missed people in plain view: the default finds the
  // corners of smooth clothes before a smooth wall too.
  // (Full resolution only: the half resolution's corners would find this person at 12 too.)
  const cv::Mat body = smooth(122, 268, 12), wall = smooth(640, 480, 11);
  ObstaclesParams full_only;
  full_only.mover_half_resolution_corners = false;
  const CrossingOutcome o = crossing(true, &body, &wall, full_only);
  EXPECT_GE(o.tracked_frames, o.frames - 5);
  EXPECT_EQ(o.false_tracks, 0);
  EXPECT_LT(o.max_vel_err, 0.3);
  EXPECT_TRUE(o.ghost_cells.empty()) << o.ghost_cells.size() << " ghost cells";
  ObstaclesParams coarse_fast = full_only;
  coarse_fast.mover_fast_threshold = 12;
  const CrossingOutcome coarse = crossing(true, &body, &wall, coarse_fast);
  EXPECT_LT(coarse.tracked_frames, o.frames / 2) << "the old threshold finds this person too: the test shows nothing";
}

TEST(MoverPipelineImages, PersonSeenCloseUpGetsCornersAtHalfResolution)
{
  // Close up (within 2 m) the clothes' smooth pattern is magnified past FAST's 3 px circle: a
  // person with thousands of depth points had no corner (generated street 6104). Here the pattern
  // and the wall are blurred at 3 px: corners show only at half the resolution.
  cv::Mat body = texture(122, 268, 12), wall = texture(640, 480, 11);
  for (cv::Mat* m : {&body, &wall})
  {
    cv::GaussianBlur(*m, *m, cv::Size(0, 0), 3.0);
    cv::normalize(*m, *m, 96, 160, cv::NORM_MINMAX);
  }
  // Without kept tracks: each frame's corners are the detector's alone (a track kept from the
  // odd full-resolution corner would carry the person through the frames without one).
  ObstaclesParams detected_each_frame;
  detected_each_frame.mover_keep_tracks = false;
  const CrossingOutcome o = crossing(true, &body, &wall, detected_each_frame);
  EXPECT_GE(o.tracked_frames, o.frames - 5);
  EXPECT_EQ(o.false_tracks, 0);
  EXPECT_LT(o.max_vel_err, 0.3);
  ObstaclesParams full_only = detected_each_frame;
  full_only.mover_half_resolution_corners = false;
  const CrossingOutcome fine = crossing(true, &body, &wall, full_only);
  EXPECT_LT(fine.tracked_frames, o.frames / 2) << "full resolution alone finds this person too: the test shows nothing";
}

TEST(MoverPipelineImages, PersonInSmoothClothesBeforeATexturedWallGetsCorners)
{
  // The corner budget (mover_max_features) is spread over the image first: ranked by strength
  // alone, the textured wall's strong corners took all 600 and the person in smooth clothes
  // walking before it had none.
  const cv::Mat body = smooth(122, 268, 12);
  ObstaclesParams spread;
  spread.mover_half_resolution_corners = false;
  const CrossingOutcome o = crossing(true, &body, nullptr, spread);
  EXPECT_GE(o.tracked_frames, o.frames - 5);
  EXPECT_EQ(o.false_tracks, 0);
  ObstaclesParams by_strength = spread;
  by_strength.mover_spread_blocks = 1;
  const CrossingOutcome ranked = crossing(true, &body, nullptr, by_strength);
  EXPECT_LT(ranked.tracked_frames, o.frames / 2) << "ranked by strength the person gets corners too: the test shows nothing";
}

namespace
{
/// A static scene whose flow fails the same way frame after frame (issue 31), as along the
/// course's thin column: a textured wall 2.5 m ahead of a standing wearer, and in it a 0.6 x 0.3 m
/// patch whose disparity is off by +-0.7 px (full resolution) with a sign that changes at random
/// from frame to frame (the depth of the wrong side of a silhouette): 0.14 m back or forth, above
/// the stereo noise (3 sigma 0.13 m) and below a mismatch (3 m/s). Its points' residuals point
/// back and forth along the ray while their cluster stays where it is. Returns the frames with a
/// detection and those with a reported mover, over 3 s at 15 Hz.
std::pair<int, int> flickeringDepth(const MoverPipelineParams& mp)
{
  const StereoModel m;
  const cv::Mat wall = texture(640, 480, 21);
  const float d0 = static_cast<float>(m.fx * m.baseline / 2.5 * 0.5);
  MoverPipeline pipe(mp);
  const Eigen::Isometry3d T = synthetic::cameraAt(0.0, 0.0, 1.6).cast<double>();
  cv::RNG rng(5);
  int detected = 0, reported = 0;
  for (int k = 0; k < 45; ++k)
  {
    cv::Mat disp(240, 320, CV_32F, cv::Scalar(d0));
    disp(cv::Rect(130, 100, 60, 30)).setTo(d0 + (rng.uniform(0, 2) ? 0.35f : -0.35f));
    pipe.process(k / 15.0, wall, disp, m, T);
    detected += !pipe.detections().empty();
    reported += !pipe.confirmed().empty();
  }
  return { detected, reported };
}
}  // namespace

TEST(MoverPipelineImages, StaticSurfaceWithFailingFlowIsNeverAMover)
{
  ObstaclesParams p;
  MoverPipelineParams mp = moverPipelineParams(p, StereoModel());
  const std::pair<int, int> now = flickeringDepth(mp);
  EXPECT_GT(now.first, 15) << "the patch's flow fails in many frames (a detection)";
  EXPECT_EQ(now.second, 0) << "but it never moves: never reported";
  // Without the "seen moving" test it was a mover from its third hit until the stationary rule
  // (0.5 s) caught it: the cause of the course's false crossing warnings.
  mp.confirm_sigmas = 0.0;
  EXPECT_GT(flickeringDepth(mp).second, 0);
}

TEST(MoverPipeline, FitMotionIsExactOnALineAndScalesWithScatter)
{
  std::deque<TrackDetection> d;
  for (int k = 0; k < 7; ++k)
    d.push_back({ 10.0 + k / 15.0, Eigen::Vector2d(1.0 + 1.2 * k / 15.0, 2.0 - 0.3 * k / 15.0), Eigen::Vector2d(1.2, -0.3) });
  MotionFit f = fitMotion(d, 0.1);
  EXPECT_EQ(f.n, 7);
  EXPECT_NEAR(f.span, 0.4, 1e-12);
  EXPECT_NEAR(f.velocity.x(), 1.2, 1e-9);
  EXPECT_NEAR(f.velocity.y(), -0.3, 1e-9);
  EXPECT_NEAR(f.scatter, 0.0, 1e-9);
  // 0.1 m / sqrt(sum (t - mean t)^2) with sum = 28 / 225 s^2
  EXPECT_NEAR(f.sigma_v, 0.1 / std::sqrt(28.0 / 225.0), 1e-9);
  MoverPipelineParams p;
  EXPECT_TRUE(seenMoving(d, p)) << "points and centres agree on 1.24 m/s";
  EXPECT_FALSE(seenMoving(std::deque<TrackDetection>(d.begin(), d.begin() + 2), p)) << "two detections";
  // The points say 1.24 m/s, the centres stand still: a texture sliding over a static surface,
  // not a walker; within 0.4 s 0.1 m of centre noise cannot tell, after 0.73 s it can.
  std::deque<TrackDetection> still;
  for (int k = 0; k < 12; ++k) still.push_back({ k / 15.0, Eigen::Vector2d(1.0, 2.0), Eigen::Vector2d(1.2, -0.3) });
  EXPECT_FALSE(seenMoving(still, p));
  // Points moving back and forth (a flickering depth): no mean motion.
  for (size_t k = 0; k < still.size(); ++k) still[k].v_flow = Eigen::Vector2d(k % 2 ? 1.5 : -1.5, 0.0);
  EXPECT_FALSE(seenMoving(still, p));
  // Jitter in place (+-0.2 m alternating): no velocity, a scatter that raises sigma_v above the floor.
  d.clear();
  for (int k = 0; k < 8; ++k) d.push_back({ k / 15.0, Eigen::Vector2d(k % 2 ? 0.2 : -0.2, 0.0), Eigen::Vector2d::Zero() });
  f = fitMotion(d, 0.1);
  EXPECT_LT(f.velocity.norm(), 0.6);
  EXPECT_GT(f.scatter, 0.1);
  EXPECT_GT(f.sigma_v, 0.1 / std::sqrt(42.0 / 225.0));
  EXPECT_EQ(fitMotion({}, 0.1).n, 0);
}

TEST(SceneFlow, DepthEdgeNearSeesEdgesWithinTheWindow)
{
  // Matcher scale 0.5: a step from 6 to 9 px at column 30; a gentle ramp elsewhere (a floor).
  cv::Mat d(40, 60, CV_32F);
  for (int v = 0; v < d.rows; ++v)
    for (int u = 0; u < d.cols; ++u) d.at<float>(v, u) = (u < 30 ? 6.f : 9.f) + 0.05f * v;
  // Full-resolution u = 2 us + 0.5: the step lies between u 59.5 and 61.5.
  EXPECT_TRUE(depthEdgeNear(d, 0.5, 56.0, 40.0, 11, 1.0)) << "5 px from the step: inside an 11 px window";
  EXPECT_FALSE(depthEdgeNear(d, 0.5, 50.0, 40.0, 11, 1.0)) << "10 px away: outside it";
  EXPECT_FALSE(depthEdgeNear(d, 0.5, 56.0, 40.0, 3, 1.0)) << "a 3 px window does not reach the step";
  EXPECT_FALSE(depthEdgeNear(d, 0.5, 20.0, 40.0, 11, 1.0)) << "the ramp (0.05 px a row) is no edge";
  // Invalid pixels are not an edge by themselves.
  d(cv::Rect(20, 15, 4, 4)).setTo(-1.f);
  EXPECT_FALSE(depthEdgeNear(d, 0.5, 42.0, 34.0, 11, 1.0));
  EXPECT_FALSE(depthEdgeNear(d, 0.5, 0.0, 0.0, 11, 1.0)) << "clipped at the border";
}

TEST(SceneFlow, MatchDisparityFindsTheFeaturesOwnMatch)
{
  // A door jamb over a plain bright background: texture left of column 300, plain 235 right of it.
  cv::Mat left = texture(640, 480, 31);
  left(cv::Rect(300, 0, 340, 480)).setTo(235);
  // The right image: the jamb 13.1 px to the left (exact subpixel shift), the plain area the same.
  const double d_true = 13.1;
  cv::Mat right;
  const cv::Mat A = (cv::Mat_<double>(2, 3) << 1, 0, -d_true, 0, 1, 0);
  cv::warpAffine(left, right, A, left.size(), cv::INTER_LINEAR, cv::BORDER_REPLICATE);
  // On the edge, the dense matcher's value came from the plain area's fill (12.0): the window's own
  // match is the jamb's.
  EXPECT_NEAR(matchDisparity(left, right, 298.0, 200.0, 12.0, 11, 3.0, 0.8), d_true, 0.1);
  EXPECT_NEAR(matchDisparity(left, right, 150.0, 200.0, 14.5, 11, 3.0, 0.8), d_true, 0.1);
  // Plain window: no texture, no depth. Truth beyond the search: no depth (the best is at its end).
  EXPECT_LT(matchDisparity(left, right, 450.0, 200.0, 12.0, 11, 3.0, 0.8), 0.0);
  EXPECT_LT(matchDisparity(left, right, 150.0, 200.0, 8.0, 11, 3.0, 0.8), 0.0);
  // Out of the image.
  EXPECT_LT(matchDisparity(left, right, 3.0, 200.0, 12.0, 11, 3.0, 0.8), 0.0);
}

namespace
{
/// A plane parallel to the image at depth `Z` (m, from the camera's start) showing `tex` with its
/// top-left corner at pixel `at` of the start view.
struct Layer
{
  cv::Mat tex;
  cv::Point2d at;
  double Z = 1.0;
  double fill = -1.0;  ///< > 0: the matcher's disparity (matcher px) on this layer is this constant (a plain area's fill)
  bool draw = true;    ///< false: the layer is in the disparity only (the matcher's error over a drawn layer)
};

/// The left (or right) image and the matcher-scale (0.5) disparity of `layers` (far to near) with
/// the camera moved `c` m forward along its axis. Exact images; the disparity is the layers' own,
/// or their fill, and the matcher's foreground fattening: `fatten` px (matcher scale) of each
/// nearer layer's disparity spill over the farther ones around its silhouette.
void renderLayers(const std::vector<Layer>& layers, double c, bool right, cv::Mat& img, cv::Mat* disp = nullptr,
                  int fatten = 0)
{
  const StereoModel m;
  cv::Mat acc(m.height, m.width, CV_32F, cv::Scalar(0.f));
  if (disp) *disp = cv::Mat(m.height / 2, m.width / 2, CV_32F, cv::Scalar(-1.f));
  for (const Layer& l : layers)
  {
    const double s = l.Z / (l.Z - c), d = m.fx * m.baseline / (l.Z - c);
    const cv::Mat A = (cv::Mat_<double>(2, 3) << s, 0, m.cx + (l.at.x - m.cx) * s - (right ? d : 0.0), 0, s,
                       m.cy + (l.at.y - m.cy) * s);
    // Over the layers behind, with the pixel's covered fraction (anti-aliased silhouettes: edges
    // at their exact sub-pixel place in both images).
    if (l.draw)
    {
    cv::Mat tex, cover, warped, alpha;
    l.tex.convertTo(tex, CV_32F);
    cv::copyMakeBorder(tex, tex, 1, 1, 1, 1, cv::BORDER_REPLICATE);
    cover = cv::Mat::zeros(tex.size(), CV_32F);
    cover(cv::Rect(1, 1, l.tex.cols, l.tex.rows)).setTo(1.f);
    cv::Mat A1 = A.clone();
    A1.at<double>(0, 2) -= s;
    A1.at<double>(1, 2) -= s;
    cv::warpAffine(tex, warped, A1, acc.size(), cv::INTER_LINEAR, cv::BORDER_CONSTANT, cv::Scalar(0));
    cv::warpAffine(cover, alpha, A1, acc.size(), cv::INTER_LINEAR, cv::BORDER_CONSTANT, cv::Scalar(0));
    acc = acc.mul(1.f - alpha) + warped.mul(alpha);
    }
    if (!disp) continue;
    const double u0 = m.cx + (l.at.x - m.cx) * s, v0 = m.cy + (l.at.y - m.cy) * s;
    const double u1 = u0 + l.tex.cols * s, v1 = v0 + l.tex.rows * s;
    const float value = static_cast<float>(l.fill > 0.0 ? l.fill : 0.5 * d);
    for (int v = 0; v < disp->rows; ++v)
      for (int u = 0; u < disp->cols; ++u)
      {
        const double uf = (u + 0.5) / 0.5 - 0.5, vf = (v + 0.5) / 0.5 - 0.5, mg = 2.0 * fatten;
        if (uf >= u0 - mg && uf < u1 + mg && vf >= v0 - mg && vf < v1 + mg) disp->at<float>(v, u) = value;
      }
  }
  acc.convertTo(img, CV_8U);
}

/// Frames with a detection and with a reported mover while the wearer walks 2 s at 1 m/s (15 Hz)
/// towards a static scene.
std::pair<int, int> walkTowards(const std::vector<Layer>& layers, const MoverPipelineParams& mp, int fatten,
                                bool with_right)
{
  const StereoModel m;
  MoverPipeline pipe(mp);
  int detected = 0, reported = 0;
  for (int k = 0; k <= 30; ++k)
  {
    const double c = k / 15.0;
    cv::Mat left, right, disp;
    renderLayers(layers, c, false, left, &disp, fatten);
    renderLayers(layers, c, true, right);
    const Eigen::Isometry3d T = synthetic::cameraAt(c, 0.0, 1.6).cast<double>();
    pipe.process(k / 15.0, left, disp, m, T, with_right ? &right : nullptr);
    detected += !pipe.detections().empty();
    reported += !pipe.confirmed().empty();
  }
  return { detected, reported };
}
}  // namespace

namespace
{
/// The scene of the tests below: a textured wall 6 m ahead; a plain bright background (the sky)
/// the matcher fills with a constant 6 px (matcher scale: 5 m); a textured wall 4.5 m ahead whose
/// left edge (u = 420 at the start) stands against that background, its first 8 px taking the
/// fill too (as a door jamb over the sky did in generated street 104); a plain dark post 2.5 m
/// ahead (a bollard) whose disparity the matcher spreads 2 px around it.
std::vector<Layer> jambAndPost()
{
  std::vector<Layer> layers;
  layers.push_back({ cv::Mat(1400, 1600, CV_8U, cv::Scalar(235)), { -480, -460 }, 30.0, 6.0 });
  layers.push_back({ texture(500, 1400, 41), { -200, -460 }, 6.0 });
  const cv::Mat jamb = texture(400, 1400, 42);
  layers.push_back({ jamb, { 420, -460 }, 4.5 });
  layers.push_back({ jamb.colRange(0, 8).clone(), { 420, -460 }, 4.5, 6.0, false });
  layers.push_back({ cv::Mat(300, 40, CV_8U, cv::Scalar(70)), { 200, 180 }, 2.5 });
  return layers;
}
}  // namespace

TEST(SceneFlow, OwnStereoMatchGivesAJambItsDepthNotThePlainFill)
{
  // One step of 1/15 m towards the jamb. With the matcher's fill the jamb's edge corners keep
  // their depth (5 m) while the wearer walks up: they recede by the step along the ray. With
  // their own match they are static.
  const std::vector<Layer> layers = jambAndPost();
  const StereoModel m;
  auto edgeResiduals = [&](bool with_right, int& n) {
    SceneFlowExtractor sf;
    const Eigen::Isometry3d T0 = synthetic::cameraAt(0.0, 0.0, 1.6).cast<double>(),
                            T1 = synthetic::cameraAt(1.0 / 15.0, 0.0, 1.6).cast<double>();
    cv::Mat l0, r0, d0, l1, r1, d1;
    renderLayers(layers, 0.0, false, l0, &d0, 2);
    renderLayers(layers, 0.0, true, r0);
    renderLayers(layers, 1.0 / 15.0, false, l1, &d1, 2);
    renderLayers(layers, 1.0 / 15.0, true, r1);
    sf.process(l0, d0, m, &T0, with_right ? &r0 : nullptr);
    const std::vector<SceneFlowPoint>& flow = sf.process(l1, d1, m, &T1, with_right ? &r1 : nullptr);
    const Eigen::Isometry3d T10 = T1.inverse() * T0;
    const double edge = m.cx + (420 - m.cx) * 4.5 / (4.5 - 1.0 / 15.0);
    double worst = 0.0;
    n = 0;
    for (size_t i = 0; i < flow.size(); ++i)
    {
      const double u = sf.pixels()[i].x;
      if (u < edge - 3.0 || u > edge + 6.0) continue;
      ++n;
      worst = std::max(worst, (flow[i].cur - T10 * flow[i].prev).norm());
      if (std::getenv("FLOW_DEBUG"))
        std::printf("u %.1f v %.1f Z0 %.3f Z1 %.3f r %.3f\n", u, sf.pixels()[i].y, flow[i].prev.z(), flow[i].cur.z(),
                    (flow[i].cur - T10 * flow[i].prev).norm());
    }
    return worst;
  };
  int n_fill = 0, n_own = 0;
  const double fill = edgeResiduals(false, n_fill), own = edgeResiduals(true, n_own);
  ASSERT_GT(n_fill, 3) << "corners on the jamb's edge";
  EXPECT_GT(fill, 0.05) << "the fill's depth: the edge seems to recede with the wearer";
  ASSERT_GT(n_own, 3);
  EXPECT_LT(own, 0.02) << "own match: static within 2 cm";
}

TEST(MoverPipelineImages, StaticDepthEdgesFromAWalkingCameraAreNeverMovers)
{
  // 2 s of walking at 1 m/s towards the jamb and the post (jambAndPost()), the default pipeline
  // with the right image: no detection holds, nothing is reported.
  const std::vector<Layer> layers = jambAndPost();
  ObstaclesParams p;
  const MoverPipelineParams mp = moverPipelineParams(p, StereoModel());
  const std::pair<int, int> now = walkTowards(layers, mp, 2, true);
  EXPECT_EQ(now.second, 0) << "never reported (" << now.first << " frames with a detection)";
  EXPECT_LE(now.first, 2);
}
