// People who give way to the wearer (people_give_way.h).
#include <assistive_sim/people_give_way.h>

#include <algorithm>
#include <cmath>
#include <memory>

namespace assistive_sim
{
PeopleGiveWay::PeopleGiveWay(World& world, const GiveWayParams& p) : world_(world), p_(p)
{
  for (Person& person : world_.people)
    person.give_way = std::make_shared<GiveWayTrack>();
}

double PeopleGiveWay::minimalPredictedDistance(const Eigen::Vector2d& p, const Eigen::Vector2d& v,
                                               const Eigen::Vector2d& w, const Eigen::Vector2d& u, double* tau)
{
  const Eigen::Vector2d r = p - w, dv = v - u;
  const double vv = dv.squaredNorm();
  const double t = vv > 1e-9 ? std::max(0.0, -r.dot(dv) / vv) : 0.0;
  if (tau) *tau = t;
  return (r + dv * t).norm();
}

void PeopleGiveWay::step(double t, double dt, const Eigen::Vector2d& xy, const Eigen::Vector2d& velocity)
{
  const double sin_dev = std::sin(p_.deviation_deg * M_PI / 180.0);
  for (size_t i = 0; i < world_.people.size(); ++i)
  {
    Person& person = world_.people[i];
    GiveWayTrack& track = *person.give_way;
    double delay = 0.0;
    const Eigen::Vector2d offset = track.at(t, nullptr, &delay);
    // where it means to walk: its script, as far as it has got
    const PersonState script = personScriptAt(person, t - delay);
    const double speed = script.velocity.norm();
    if (speed < p_.min_speed)
      continue;  // standing: stays where it stands (beside its path or on it)
    const Eigen::Vector2d pos = script.position + offset;
    double tau = 0.0;
    const double mpd = minimalPredictedDistance(pos, script.velocity, xy, velocity, &tau);
    const Eigen::Vector2d left(-script.velocity.y() / speed, script.velocity.x() / speed);
    const double step = speed * sin_dev * dt;
    Eigen::Vector2d next = offset;
    double next_delay = delay;
    if (tau > 0.0 && mpd < p_.mpd_m && tau <= p_.horizon_s)  // (tau 0: already parting)
    {
      // aside, to the side it would pass the wearer on (its right when head-on)
      const Eigen::Vector2d apart = pos + (script.velocity - velocity) * tau - xy;
      const double side = apart.dot(left) > 1e-3 ? 1.0 : -1.0;
      next = offset + side * step * left;
      const double gap = (pos - xy).norm() - person.radius - p_.wearer_radius_m;
      // (never a step towards the wearer once close: aside means away)
      const bool nearer = (script.position + next - xy).norm() < (pos - xy).norm();
      if (next.norm() > p_.max_offset_m || (nearer && gap < p_.stop_gap_m)) next = offset;
      if (offset.norm() < 1e-9) ++episodes_;  // it leaves its path (not each time it judges again)
      // about to walk into the wearer: it stands (its script waits) while it steps aside
      // (its own walk towards the wearer: one walked into from behind or the side walks on out of the way)
      const bool closing = script.velocity.dot(xy - pos) > 0.0;
      if (closing && gap < p_.stop_gap_m) next_delay = delay + dt;
    }
    else if (offset.norm() > 1e-9)
    {
      // back to its path once that keeps the passing distance (the wearer behind it, or far off)
      const double back = std::min(step, offset.norm());
      const Eigen::Vector2d cand = offset - back * offset.normalized();
      double tau2 = 0.0;
      const double mpd2 = minimalPredictedDistance(script.position + cand, script.velocity, xy, velocity, &tau2);
      if (mpd2 >= p_.mpd_m || tau2 > p_.horizon_s) next = cand;
    }
    if ((next - offset).squaredNorm() > 0.0 || next_delay != delay)
    {
      // a knot now, where it was (unless the last step left one here), and one a step on
      track.append(t, offset, delay);
      track.append(t + dt, next, next_delay);
    }
  }
}

}  // namespace assistive_sim
