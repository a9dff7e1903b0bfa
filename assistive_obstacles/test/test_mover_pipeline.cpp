// Segmentation -> tracker -> crossing predictor on a synthetic 10 Hz walk: the wearer walks +x at
// 1 m/s (exact ego-motion), static floor and wall around, one person per scenario.
#include <cmath>
#include <functional>

#include <gtest/gtest.h>

#include <assistive_common/crossing_predictor.h>
#include <assistive_obstacles/mover_segmentation.h>
#include <assistive_obstacles/mover_tracker.h>
#include <assistive_obstacles/obstacle_map.h>

#include "synthetic.h"

using namespace assistive_common;
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

TEST(MoverPipeline, SegmentedMoversLeaveNoGhostInTheMap)
{
  // The ghost-free hook fed by the segmentation instead of the truth: a person (0.15 m column,
  // 1.7 m) pacing across x = 2.3 in front of a standing wearer; the map takes the person's points,
  // the segmentation their scene flow (0.2 m per frame). No cell of the walk flips or locks; once
  // the person has gone they are free.
  const Eigen::Isometry3f T = synthetic::cameraAt(0.0, 0.0, 1.6);
  const Eigen::Isometry3d Td = T.cast<double>();
  synthetic::Points floor;
  synthetic::patch(floor, 0.6, 4.0, -1.4, 1.4, 0.0);
  const std::vector<double> path = {-0.5, -0.3, -0.1, 0.1, 0.3, 0.5, 0.7, 0.5, 0.3, 0.1, -0.1, -0.3};
  const double px = 2.3;
  ObstacleMap map;
  MoverSegmentation seg;
  int frames_with_mover = 0;
  for (int i = 1; i <= 240; ++i)
  {
    const double py = path[i % path.size()], py_prev = path[(i - 1) % path.size()];
    synthetic::Points person, person_prev;
    synthetic::pole(person, px, py, 0.15, 1.7);
    synthetic::pole(person_prev, px, py_prev, 0.15, 1.7);
    std::vector<SceneFlowPoint> flow;
    for (size_t k = 0; k < person.size(); ++k)
    {
      SceneFlowPoint f;
      f.prev = Td.inverse() * person_prev[k].cast<double>();
      f.cur = Td.inverse() * person[k].cast<double>();
      flow.push_back(f);
    }
    for (size_t k = 0; k < floor.size(); k += 7)
    {
      SceneFlowPoint f;
      f.prev = f.cur = Td.inverse() * floor[k].cast<double>();
      flow.push_back(f);
    }
    std::vector<MoverFootprint> fp;
    for (const MoverDetection& d : seg.segment(flow, Eigen::Isometry3d::Identity(), Td))
      fp.push_back(MoverFootprint{d.centroid.x(), d.centroid.y(), d.radius});
    frames_with_mover += !fp.empty();
    map.setMovers(fp);
    synthetic::Points w = floor;
    w.insert(w.end(), person.begin(), person.end());
    map.update(synthetic::toCamera(w, T), T);
  }
  EXPECT_EQ(frames_with_mover, 240);
  int flipped = 0, locked = 0;
  for (int gx = 9; gx <= 13; ++gx)
    for (int gy = -4; gy <= 5; ++gy)
      if (const CellCounters* c = map.temporal().find(gx, gy))
      {
        flipped += c->flips > 0;
        locked += c->permanent;
      }
  EXPECT_EQ(flipped, 0);
  EXPECT_EQ(locked, 0);
  for (int i = 0; i < 10; ++i) map.update(synthetic::toCamera(floor, T), T);
  GridData g;
  map.grid(g);
  for (double y = -0.7; y <= 0.9; y += 0.2)
  {
    const int ix = static_cast<int>(std::floor((px - g.origin_x) / g.resolution));
    const int iy = static_cast<int>(std::floor((y - g.origin_y) / g.resolution));
    EXPECT_EQ(g.data[iy * g.width + ix], CELL_FREE) << "y " << y;
  }
}
