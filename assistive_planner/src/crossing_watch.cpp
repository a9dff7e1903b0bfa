#include "assistive_planner/crossing_watch.h"

#include <cmath>
#include <iterator>

namespace assistive_planner
{
namespace ac = assistive_common;

CrossingWatch::CrossingWatch(const PlannerParams& p, const CrossingParams& cp) : p_(p), predictor_(cp) {}

void CrossingWatch::setMovers(double stamp, std::vector<MoverState> movers)
{
  if (!std::isfinite(stamp))
  {
    clearMovers();
    return;
  }
  have_movers_ = true;
  movers_stamp_ = stamp;
  movers_.clear();
  for (MoverState& m : movers)
    if (m.x.allFinite() && m.P.allFinite())
      movers_.push_back(std::move(m));
}

void CrossingWatch::clearMovers()
{
  have_movers_ = false;
  movers_.clear();
}

void CrossingWatch::addPose(double t, const Point2& p)
{
  if (!std::isfinite(t) || !std::isfinite(p.x) || !std::isfinite(p.y))
    return;
  if (!poses_.empty() && t < poses_.back().first)
    poses_.clear();  // time went back (a bag loop, a reset): the old poses are another walk
  poses_.emplace_back(t, p);
  // keep the newest pose that is at least a window old (the base of the speed) and everything after
  while (poses_.size() > 2 && t - poses_[1].first >= p_.crossing_speed_window_s)
    poses_.pop_front();
}

double CrossingWatch::speed() const
{
  if (poses_.size() < 2)
    return 0.0;
  const auto& now = poses_.back();
  // the oldest pose within the window
  for (const auto& q : poses_)
  {
    const double dt = now.first - q.first;
    if (dt > p_.crossing_speed_window_s + 1e-9)
      continue;
    if (dt < 0.5 * p_.crossing_speed_window_s)
      return 0.0;
    return std::hypot(now.second.x - q.second.x, now.second.y - q.second.y) / dt;
  }
  return 0.0;
}

CrossingAdvice CrossingWatch::keepSide(double t, int id, CrossingAdvice side, bool left_blocked, bool right_blocked)
{
  // A head-on walker straight ahead, or a track's velocity jittering, can tip the predictor from
  // one side to the other between cycles: the wearer, a reaction time into stepping one way, would
  // be sent back the other. The side once advised for a person stays while the warning goes on.
  for (auto it = sides_.begin(); it != sides_.end();)
    it = t - it->second.second > p_.crossing_sticky_s || t < it->second.second ? sides_.erase(it) : std::next(it);
  if (side != CrossingAdvice::LEFT && side != CrossingAdvice::RIGHT)
    return side;  // (STOP: the side is kept for when it ends)
  const auto it = sides_.find(id);
  if (p_.crossing_sticky_s > 0.0 && it != sides_.end() && it->second.first != side)
  {
    const bool kept_blocked = it->second.first == CrossingAdvice::LEFT ? left_blocked : right_blocked;
    if (!kept_blocked)
      side = it->second.first;
  }
  sides_[id] = { side, t };
  return side;
}

CrossingResult CrossingWatch::check(double t, const Point2& wearer, double heading, double free_left,
                                    double free_right)
{
  CrossingResult r;
  if (!have_movers_ || !std::isfinite(t) || std::abs(t - movers_stamp_) > p_.crossing_max_age_s ||
      !std::isfinite(wearer.x) || !std::isfinite(wearer.y) || !std::isfinite(heading))
    return r;  // no news, or old news: no warning rather than a stale one
  r.movers_fresh = true;
  r.movers = int(movers_.size());
  ac::Wearer w;
  w.position = Eigen::Vector2d(wearer.x, wearer.y);
  w.heading = heading;
  w.speed = speed();
  r.wearer_speed = w.speed;
  w.left_blocked = !(free_left >= p_.crossing_side_free_m);
  w.right_blocked = !(free_right >= p_.crossing_side_free_m);

  // carry the movers to the cycle's time (constant velocity, covariance propagated without noise)
  const double dt = t - movers_stamp_;
  std::vector<MoverState> now = movers_;
  if (dt != 0.0)
    for (MoverState& m : now)
    {
      Eigen::Matrix4d F = Eigen::Matrix4d::Identity();
      F(0, 2) = F(1, 3) = dt;
      m.x = F * m.x;
      m.P = F * m.P * F.transpose();
    }
  const std::vector<ac::CrossingPrediction> pred = predictor_.predict(w, now);
  const ac::CrossingPrediction* best = CrossingPredictor::mostUrgent(pred);
  if (!best)
    return r;
  const MoverState& m = now[size_t(best - pred.data())];
  if (best->side == CrossingAdvice::NONE)
    return r;
  r.advice = keepSide(t, best->track_id, best->side, w.left_blocked, w.right_blocked);
  r.id = best->track_id;
  r.time = best->t_closest;
  r.distance = best->d_closest;
  r.mover = { m.x(0), m.x(1) };
  r.mover_at_closest = { m.x(0) + m.x(2) * r.time, m.x(1) + m.x(3) * r.time };
  r.wearer_at_closest = { wearer.x + w.speed * std::cos(heading) * r.time,
                          wearer.y + w.speed * std::sin(heading) * r.time };
  return r;
}
}  // namespace assistive_planner
