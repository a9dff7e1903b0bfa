#include <assistive_obstacles/crossing_predictor.h>

#include <algorithm>
#include <cmath>

namespace assistive_obstacles
{
namespace
{
double cross2(const Eigen::Vector2d& a, const Eigen::Vector2d& b) { return a.x() * b.y() - a.y() * b.x(); }
}  // namespace

CrossingPrediction CrossingPredictor::predict(const Wearer& w, const MoverTrack& track) const
{
  CrossingPrediction out;
  out.track_id = track.id;
  const Eigen::Vector2d h(std::cos(w.heading), std::sin(w.heading));
  const Eigen::Vector2d r0 = track.position() - w.position;
  const Eigen::Vector2d vm = track.velocity();
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
  const Eigen::Matrix2d C = track.P.topLeftCorner<2, 2>() + t * (track.P.topRightCorner<2, 2>() + track.P.bottomLeftCorner<2, 2>()) +
                            t * t * track.P.bottomRightCorner<2, 2>();
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

  // Side: pass behind a crosser (step towards where it comes from); step away from a head-on or
  // overtaking mover's side of passing.
  const double lateral_speed = cross2(h, vm);  // > 0: the mover walks towards the wearer's left
  bool go_left;
  if (std::abs(lateral_speed) >= params_.cross_speed)
    go_left = lateral_speed < 0.0;  // it walks to the right: pass behind it on the left
  else
  {
    const double offset = cross2(h, rc);  // > 0: it passes on the wearer's left
    go_left = std::abs(offset) > 1e-6 ? offset < 0.0 : !params_.keep_right;
  }
  if (out.t_closest < params_.stop_time || (go_left ? w.left_blocked : w.right_blocked))
    out.side = AvoidSide::STOP;
  else
    out.side = go_left ? AvoidSide::LEFT : AvoidSide::RIGHT;
  return out;
}

std::vector<CrossingPrediction> CrossingPredictor::predict(const Wearer& w, const std::vector<MoverTrack>& tracks) const
{
  std::vector<CrossingPrediction> out;
  out.reserve(tracks.size());
  for (const MoverTrack& t : tracks) out.push_back(predict(w, t));
  return out;
}

const CrossingPrediction* CrossingPredictor::mostUrgent(const std::vector<CrossingPrediction>& predictions)
{
  const CrossingPrediction* best = nullptr;
  for (const CrossingPrediction& p : predictions)
    if (p.warn && (!best || p.t_closest < best->t_closest)) best = &p;
  return best;
}

}  // namespace assistive_obstacles
