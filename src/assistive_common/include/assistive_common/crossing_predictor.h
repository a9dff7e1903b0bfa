#pragma once
// Crossing prediction (issue 22): the wearer and each tracked mover walk on at constant velocity;
// their closest approach within a horizon decides whether the wearer is warned, and to which side
// to step. ROS-free, header only (Eigen). One place for both of its users: the planner, which
// warns the wearer (assistive_planner CrossingWatch, on obstacles/movers), and the obstacle stage's
// benchmark, which scores those warnings against the people's truth. It lives here, the lowest
// package both use: the stages do not depend on one another at run time (.ci/check_core, rule 3).
//
// Relative position r0 = p_mover - p_wearer, relative velocity vr = v_mover - v_wearer.
// Closest approach time t* = clamp(-r0.vr / |vr|^2, 0, horizon), distance d* = |r0 + vr t*|.
// A mover is a threat only when it closes in (closing speed -r0.vr / |r0| > min_closing_speed),
// so people walking alongside or away never warn. Warning when
//   d* - sigma_scale * sigma* < warn_distance                    (a crossing), or
//   d* < head_on_distance and the mover walks against the wearer  (head-on: its velocity within
//                                                                  head_on_angle of -heading),
// sigma* = the track's position sigma propagated to t*, across the line of closest approach.
// Side: a mover ahead crossing the wearer's path (lateral speed >= cross_speed, not head-on) is
// passed behind: step to the side it comes from; otherwise (head-on, overtaking) step away from
// the side it passes on (the right on a dead-centre course: keep_right). STOP when a crosser's
// approach is nearer than stop_time (no time to sidestep) or the chosen side is blocked.
#include <algorithm>
#include <cmath>
#include <vector>

#include <Eigen/Core>

#include <assistive_common/codes.h>

namespace assistive_common
{
struct CrossingParams
{
  double horizon = 3.0;            ///< s, prediction horizon
  double warn_distance = 0.5;      ///< m, closest approach that warns
  double head_on_distance = 1.0;   ///< m, closest approach that warns for a mover walking against the wearer
  double head_on_angle = 0.785398; ///< rad (45 deg), mover heading within this of the wearer's reverse = head-on
  double min_closing_speed = 0.1;  ///< m/s, movers closing in slower than this never warn (alongside, away)
  double sigma_scale = 0.0;        ///< sigmas of track uncertainty subtracted from d* (0: the mean path only)
  double cross_speed = 0.3;        ///< m/s, lateral speed (relative to the wearer's heading) that makes a crossing
  double stop_time = 1.0;          ///< s, closest approach sooner than this: STOP instead of a side
  bool keep_right = true;          ///< dead-centre head-on course: step right (else left)
};

/// The side to step to: the planner's advice itself (NavigationState.crossing), one enum.
using AvoidSide = CrossingAdvice;

/// A mover as the predictor needs it (what a tracker reports): any type with `id`, `position()`,
/// `velocity()` and the 4x4 covariance `P` of (x, y, vx, vy) will do (assistive_obstacles::MoverTrack).
struct MoverState
{
  int id = 0;
  Eigen::Vector4d x = Eigen::Vector4d::Zero();      ///< x, y (m), vx, vy (m/s), world frame
  Eigen::Matrix4d P = Eigen::Matrix4d::Zero();      ///< covariance of x (zeros: exact)

  Eigen::Vector2d position() const { return x.head<2>(); }
  Eigen::Vector2d velocity() const { return x.tail<2>(); }
};

struct Wearer
{
  Eigen::Vector2d position = Eigen::Vector2d::Zero();  ///< m, world
  double heading = 0.0;                                ///< rad, world yaw of the walking direction
  double speed = 0.0;                                  ///< m/s
  bool left_blocked = false, right_blocked = false;    ///< the map has no room on that side (from the planner)
};

struct CrossingPrediction
{
  int track_id = 0;
  double t_closest = 0.0;   ///< s, in [0, horizon]
  double d_closest = 0.0;   ///< m, mean path
  double sigma = 0.0;       ///< m, position sigma at t_closest across the line of closest approach
  double closing_speed = 0.0;  ///< m/s, now (> 0: approaching)
  bool head_on = false;
  bool warn = false;
  AvoidSide side = AvoidSide::NONE;
};

class CrossingPredictor
{
public:
  explicit CrossingPredictor(const CrossingParams& p = CrossingParams()) : params_(p) {}
  void setParams(const CrossingParams& p) { params_ = p; }
  const CrossingParams& params() const { return params_; }

  /// One mover against the wearer.
  template <class Track>
  CrossingPrediction predict(const Wearer& w, const Track& track) const
  {
    return predictOne(w, track.id, track.position(), track.velocity(), track.P);
  }
  /// Every track; the result is in the tracks' order.
  template <class Track>
  std::vector<CrossingPrediction> predict(const Wearer& w, const std::vector<Track>& tracks) const
  {
    std::vector<CrossingPrediction> out;
    out.reserve(tracks.size());
    for (const Track& t : tracks) out.push_back(predict(w, t));
    return out;
  }
  /// The most urgent warning (smallest t_closest among the warned), or nullptr when none warns.
  static const CrossingPrediction* mostUrgent(const std::vector<CrossingPrediction>& predictions)
  {
    const CrossingPrediction* best = nullptr;
    for (const CrossingPrediction& p : predictions)
      if (p.warn && (!best || p.t_closest < best->t_closest)) best = &p;
    return best;
  }

private:
  static double cross2(const Eigen::Vector2d& a, const Eigen::Vector2d& b) { return a.x() * b.y() - a.y() * b.x(); }

  CrossingPrediction predictOne(const Wearer& w, int id, const Eigen::Vector2d& pm, const Eigen::Vector2d& vm,
                                const Eigen::Matrix4d& P) const
  {
    CrossingPrediction out;
    out.track_id = id;
    const Eigen::Vector2d h(std::cos(w.heading), std::sin(w.heading));
    const Eigen::Vector2d r0 = pm - w.position;
    const Eigen::Vector2d vr = vm - w.speed * h;
    const double vr2 = vr.squaredNorm();
    const double horizon = std::max(0.0, params_.horizon);
    out.t_closest = vr2 > 1e-12 ? std::clamp(-r0.dot(vr) / vr2, 0.0, horizon) : 0.0;
    const Eigen::Vector2d rc = r0 + vr * out.t_closest;  // mover relative to the wearer at t*
    out.d_closest = rc.norm();
    const double r0n = r0.norm();
    out.closing_speed = r0n > 1e-9 ? -r0.dot(vr) / r0n : std::sqrt(vr2);

    // Track uncertainty at t*: Cov(p + v t) = Ppp + t (Ppv + Pvp) + t^2 Pvv, across the miss line.
    const double t = out.t_closest;
    const Eigen::Matrix2d C = P.topLeftCorner<2, 2>() + t * (P.topRightCorner<2, 2>() + P.bottomLeftCorner<2, 2>()) +
                              t * t * P.bottomRightCorner<2, 2>();
    const Eigen::Vector2d dir = out.d_closest > 1e-9 ? Eigen::Vector2d(rc / out.d_closest)
                                                     : (vr2 > 1e-12 ? Eigen::Vector2d(-vr.y(), vr.x()) / std::sqrt(vr2) : h);
    out.sigma = std::sqrt(std::max(0.0, dir.dot(C * dir)));

    const double vm_n = vm.norm();
    out.head_on = vm_n > 1e-9 && vm.dot(-h) >= vm_n * std::cos(params_.head_on_angle);
    if (out.closing_speed <= params_.min_closing_speed) return out;  // alongside, away, or standing by
    const bool crossing = out.d_closest - params_.sigma_scale * out.sigma < params_.warn_distance;
    const bool head_on = out.head_on && out.d_closest < params_.head_on_distance;
    out.warn = crossing || head_on;
    if (!out.warn) return out;

    // Side: pass behind a crosser ahead (step towards where it comes from); step away from a
    // head-on or overtaking mover's side of passing. A head-on mover is judged by its side even when
    // the wearer's heading gives it a lateral speed (a wearer veering while sidestepping), and so is
    // one coming from behind: passing behind either means nothing.
    const double lateral_speed = cross2(h, vm);  // > 0: the mover walks towards the wearer's left
    const bool crosser = !out.head_on && r0.dot(h) > 0.0 && std::abs(lateral_speed) >= params_.cross_speed;
    bool go_left;
    if (crosser)
      go_left = lateral_speed < 0.0;  // it walks to the right: pass behind it on the left
    else
    {
      const double offset = cross2(h, rc);  // > 0: it passes on the wearer's left
      go_left = std::abs(offset) > 1e-6 ? offset < 0.0 : !params_.keep_right;
    }
    // Too late to sidestep a crosser: stop and let it pass. Stopping does not let a head-on or
    // overtaking mover pass (it walks on into the wearer): keep the side, stop only when blocked.
    if ((crosser && out.t_closest < params_.stop_time) || (go_left ? w.left_blocked : w.right_blocked))
      out.side = AvoidSide::STOP;
    else
      out.side = go_left ? AvoidSide::LEFT : AvoidSide::RIGHT;
    return out;
  }

  CrossingParams params_;
};

}  // namespace assistive_common
