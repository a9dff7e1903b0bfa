// Segmentation -> tracker -> crossing predictor on a synthetic 10 Hz walk: the wearer walks +x at
// 1 m/s (exact ego-motion), static floor and wall around, one person per scenario.
#include <cmath>
#include <functional>

#include <gtest/gtest.h>

#include <assistive_obstacles/crossing_predictor.h>
#include <assistive_obstacles/mover_segmentation.h>
#include <assistive_obstacles/mover_tracker.h>

using namespace assistive_obstacles;

namespace
{
Eigen::Isometry3d cameraPose(double x, double y)
{
  Eigen::Matrix3d look;
  look << 0, 0, 1,
      -1, 0, 0,
       0, -1, 0;
  Eigen::Isometry3d t = Eigen::Isometry3d::Identity();
  t.linear() = look;
  t.translation() = Eigen::Vector3d(x, y, 1.6);
  return t;
}

struct Outcome
{
  double first_warning = -1.0;  ///< s, time of the first warning (-1: none)
  int warned_frames = 0;
  int detections = 0, frames = 0;
  double last_speed_err = 1e9;
  AvoidSide first_side = AvoidSide::NONE;
};

/// `person(t)`: the person's ground position at time t (a 0.4 x 0.3 m box of points, 1.7 m tall).
Outcome walk(const std::function<Eigen::Vector2d(double)>& person, const Eigen::Vector2d& person_v, double seconds)
{
  const double dt = 0.1, wearer_speed = 1.0;
  MoverSegmentation seg;
  MoverTracker trk;
  CrossingPredictor cp;
  Outcome out;
  for (int k = 1; k * dt <= seconds + 1e-9; ++k)
  {
    const double t = k * dt;
    const Eigen::Isometry3d T_prev = cameraPose(wearer_speed * (t - dt), 0.0), T_cur = cameraPose(wearer_speed * t, 0.0);
    std::vector<SceneFlowPoint> flow;
    auto add = [&](const Eigen::Vector3d& now, const Eigen::Vector3d& before) {
      SceneFlowPoint f;
      f.prev = T_prev.inverse() * before;
      f.cur = T_cur.inverse() * now;
      if (f.prev.z() > 0.3 && f.cur.z() > 0.3 && f.cur.z() < 8.0) flow.push_back(f);
    };
    for (double x = wearer_speed * t + 1.05; x < wearer_speed * t + 6.0; x += 0.2)
      for (double y = -3.0; y <= 3.0; y += 0.2) add(Eigen::Vector3d(x, y, 0.0), Eigen::Vector3d(x, y, 0.0));
    const Eigen::Vector2d pc = person(t), pp = person(t - dt);
    for (double dx = -0.15; dx < 0.2; dx += 0.1)
      for (double dy = -0.1; dy < 0.15; dy += 0.1)
        for (double z = 0.1; z < 1.8; z += 0.2)
          add(Eigen::Vector3d(pc.x() + dx, pc.y() + dy, z), Eigen::Vector3d(pp.x() + dx, pp.y() + dy, z));
    const std::vector<MoverDetection>& d = seg.segment(flow, T_cur.inverse() * T_prev, T_cur);
    std::vector<Eigen::Vector2d> z;
    for (const MoverDetection& m : d) z.push_back(m.centroid);
    out.detections += static_cast<int>(z.size());
    ++out.frames;
    trk.update(t, z);
    Wearer w;
    w.position = Eigen::Vector2d(wearer_speed * t, 0.0);
    w.speed = wearer_speed;
    const std::vector<MoverTrack> tracks = trk.confirmed();
    const std::vector<CrossingPrediction> p = cp.predict(w, tracks);
    if (const CrossingPrediction* u = CrossingPredictor::mostUrgent(p))
    {
      ++out.warned_frames;
      if (out.first_warning < 0)
      {
        out.first_warning = t;
        out.first_side = u->side;
      }
    }
    if (!tracks.empty()) out.last_speed_err = (tracks[0].velocity() - person_v).norm();
  }
  return out;
}
}  // namespace

TEST(MoverPipeline, CrosserOnCollisionCourseWarnedEarly)
{
  // From 3 m to the left at 1.2 m/s, meeting the wearer at (3, 0) at t = 3 s (in view from
  // the start: 3 m ahead, 3.6 m to the left at t = 0).
  const Eigen::Vector2d v(0.0, -1.2);
  const Outcome o = walk([&](double t) -> Eigen::Vector2d { return Eigen::Vector2d(3.0, 3.6) + v * t; }, v, 2.5);
  EXPECT_EQ(o.detections, o.frames);  // found in every frame
  ASSERT_GT(o.first_warning, 0.0);
  EXPECT_GE(3.0 - o.first_warning, 1.5);  // warned at least 1.5 s before the closest approach
  EXPECT_EQ(o.first_side, AvoidSide::LEFT);
  EXPECT_LT(o.last_speed_err, 1e-6);
}

TEST(MoverPipeline, AlongsideAndAwayNeverWarn)
{
  // Alongside 1 m to the left at the wearer's pace, and ahead walking away at 1.4 m/s.
  const Eigen::Vector2d v(1.0, 0.0), va(1.4, 0.0);
  const Outcome along = walk([&](double t) -> Eigen::Vector2d { return Eigen::Vector2d(2.0, 1.0) + v * t; }, v, 6.0);
  EXPECT_EQ(along.warned_frames, 0);
  EXPECT_EQ(along.detections, along.frames);  // silent although seen and tracked
  EXPECT_LT(along.last_speed_err, 1e-6);
  const Outcome away = walk([&](double t) -> Eigen::Vector2d { return Eigen::Vector2d(2.5, 0.1) + va * t; }, va, 6.0);
  EXPECT_EQ(away.warned_frames, 0);
  EXPECT_EQ(away.detections, away.frames);
  EXPECT_LT(away.last_speed_err, 0.05);
}
