// The body's collider against a world's solids and people (body_collider.h).
#include <assistive_sim/body_collider.h>

#include <algorithm>
#include <cmath>
#include <limits>

namespace assistive_sim
{
const char* kindName(ObstacleKind k)
{
  switch (k)
  {
    case ObstacleKind::WALL: return "wall";
    case ObstacleKind::OVERHANG: return "overhang";
    case ObstacleKind::GLASS: return "glass";
    case ObstacleKind::FURNITURE: return "furniture";
    case ObstacleKind::PERSON: return "people";
    default: return "?";
  }
}

// ---------------------------------------------------------------- BodyCollider
BodyCollider::BodyCollider(const World& world, double radius, double height, double overhang_min_z)
  : radius_(radius), height_(height), overhang_min_z_(overhang_min_z)
{
  for (const Solid& s : world.solids)
    if (!s.walkable && s.z1 > 0.05 && s.z0 < height) solids_.push_back(s);
  people_ = world.people;
}

std::vector<size_t> BodyCollider::personContacts(const Eigen::Vector2d& xy) const
{
  std::vector<size_t> out;
  if (std::isnan(time_)) return out;
  for (size_t i = 0; i < people_.size(); ++i)
    if ((personAt(people_[i], time_).position - xy).norm() < radius_ + people_[i].radius) out.push_back(i);
  return out;
}

double BodyCollider::personClearance(const Eigen::Vector2d& xy) const
{
  double best = std::numeric_limits<double>::infinity();
  if (std::isnan(time_)) return best;
  for (const Person& p : people_)
    best = std::min(best, (personAt(p, time_).position - xy).norm() - radius_ - p.radius);
  return best;
}

double BodyCollider::distance(const Solid& s, const Eigen::Vector2d& xy) const
{
  const Eigen::Vector2d d = xy - s.center;
  if (s.shape == Solid::CYLINDER) return d.norm() - s.radius;
  const double c = std::cos(s.yaw), sn = std::sin(s.yaw);
  const double lx = std::abs(c * d.x() + sn * d.y()) - s.half.x();
  const double ly = std::abs(-sn * d.x() + c * d.y()) - s.half.y();
  if (lx <= 0.0 && ly <= 0.0) return std::max(lx, ly);
  return std::hypot(std::max(lx, 0.0), std::max(ly, 0.0));
}

ObstacleKind BodyCollider::classify(const Solid& s) const
{
  if (s.glass || s.glazing) return ObstacleKind::GLASS;  // the panel, its frame and bands
  if (s.z0 >= overhang_min_z_) return ObstacleKind::OVERHANG;  // a lintel too: it hits the head
  if (s.source.find("(wall)") != std::string::npos) return ObstacleKind::WALL;
  return ObstacleKind::FURNITURE;
}

std::vector<BodyCollider::Contact> BodyCollider::contacts(const Eigen::Vector2d& xy) const
{
  std::vector<Contact> out;
  for (const Solid& s : solids_)
    if (distance(s, xy) < radius_)
    {
      bool seen = false;
      for (const Contact& c : out) seen = seen || c.object == s.source;
      if (!seen) out.push_back({s.source, classify(s)});
    }
  return out;
}

double BodyCollider::clearance(const Eigen::Vector2d& xy) const
{
  double best = std::numeric_limits<double>::infinity();
  for (const Solid& s : solids_) best = std::min(best, distance(s, xy) - radius_);
  return best;
}

bool BodyCollider::occupied(const Eigen::Vector2d& xy, double z0, double z1, bool with_people) const
{
  for (const Solid& s : solids_)
    if (s.z0 < z1 && s.z1 > z0 && distance(s, xy) <= 0.0) return true;
  if (with_people && !std::isnan(time_))
    for (const Person& p : people_)
      if (z0 < p.height && (personAt(p, time_).position - xy).norm() <= p.radius) return true;
  return false;
}

int BodyCollider::totalCollisions() const
{
  int n = 0;
  for (int c : counts_) n += c;
  return n;
}

void BodyCollider::release(const Eigen::Vector2d& xy)
{
  for (auto it = touching_.begin(); it != touching_.end();)
  {
    double d = std::numeric_limits<double>::infinity();
    for (const Solid& s : solids_)
      if (s.source == *it) d = std::min(d, distance(s, xy));
    it = d > radius_ + 0.05 ? touching_.erase(it) : std::next(it);
  }
}

Eigen::Vector2d BodyCollider::move(const Eigen::Vector2d& from, const Eigen::Vector2d& to, bool& bumped)
{
  bumped = false;
  const double len = (to - from).norm();
  const int n = std::max(1, int(std::ceil(len / 0.02)));
  Eigen::Vector2d at = from;
  for (int i = 1; i <= n; ++i)
  {
    const Eigen::Vector2d next = from + (to - from) * (double(i) / n);
    const std::vector<Contact> hit = contacts(next);
    if (!hit.empty())
    {
      // A body brushing a wall slides along it: keep the part of the step that does not go in
      // (one axis at a time); the contact still counts.
      const Eigen::Vector2d d = (to - from) / n;
      for (const Eigen::Vector2d& alt : { Eigen::Vector2d(at.x() + d.x(), at.y()), Eigen::Vector2d(at.x(), at.y() + d.y()) })
        if ((alt - at).norm() > 1e-9 && contacts(alt).empty() && (alt - at).norm() > 0.3 * d.norm())
        {
          at = alt;
          break;
        }
      bumped = true;
      for (const Contact& c : hit)
        if (touching_.insert(c.object).second)
        {
          ++counts_[size_t(c.kind)];
          places_.push_back(next);
        }
      break;
    }
    at = next;
  }
  release(at);
  // People: counted once per encounter where the body ends the step, never blocking.
  if (!std::isnan(time_))
  {
    for (auto it = touching_people_.begin(); it != touching_people_.end();)
    {
      const Person& p = people_[*it];
      it = (personAt(p, time_).position - at).norm() > radius_ + p.radius + 0.05 ? touching_people_.erase(it)
                                                                                : std::next(it);
    }
    for (size_t i : personContacts(at))
      if (touching_people_.insert(i).second)  // a new encounter: the walker bumps (once)
      {
        bumped = true;
        ++counts_[size_t(ObstacleKind::PERSON)];
        places_.push_back(at);
      }
  }
  return at;
}
}  // namespace assistive_sim
