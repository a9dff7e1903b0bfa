#include <assistive_sim/ultrasonic.h>

#include <algorithm>
#include <cmath>
#include <limits>

namespace assistive_sim
{
namespace
{
/// Ray against a yawed box: slab test in the box's frame; the entry face's normal.
std::optional<RayHit> hitBox(const Solid& s, const Eigen::Vector3d& o, const Eigen::Vector3d& d)
{
  const double c = std::cos(s.yaw), sn = std::sin(s.yaw);
  const Eigen::Vector3d lo((o.x() - s.center.x()) * c + (o.y() - s.center.y()) * sn,
                           -(o.x() - s.center.x()) * sn + (o.y() - s.center.y()) * c, o.z());
  const Eigen::Vector3d ld(d.x() * c + d.y() * sn, -d.x() * sn + d.y() * c, d.z());
  const double bmin[3] = {-s.half.x(), -s.half.y(), s.z0}, bmax[3] = {s.half.x(), s.half.y(), s.z1};
  double t0 = -std::numeric_limits<double>::infinity(), t1 = std::numeric_limits<double>::infinity();
  int axis = -1;
  double sign = 0.0;
  for (int i = 0; i < 3; ++i)
  {
    if (std::abs(ld[i]) < 1e-12)
    {
      if (lo[i] < bmin[i] || lo[i] > bmax[i]) return std::nullopt;
      continue;
    }
    double ta = (bmin[i] - lo[i]) / ld[i], tb = (bmax[i] - lo[i]) / ld[i];
    double sgn = -1.0;  // entering through the min face: normal -axis
    if (ta > tb) std::swap(ta, tb), sgn = 1.0;
    if (ta > t0) t0 = ta, axis = i, sign = sgn;
    t1 = std::min(t1, tb);
  }
  if (t0 > t1 || t1 < 0 || t0 < 0 || axis < 0) return std::nullopt;  // miss, behind, or inside
  Eigen::Vector3d n_local = Eigen::Vector3d::Zero();
  n_local[axis] = sign;
  RayHit h;
  h.t = t0;
  h.normal = Eigen::Vector3d(n_local.x() * c - n_local.y() * sn, n_local.x() * sn + n_local.y() * c, n_local.z());
  return h;
}

/// Ray against a vertical cylinder with flat caps.
std::optional<RayHit> hitCylinder(const Solid& s, const Eigen::Vector3d& o, const Eigen::Vector3d& d)
{
  std::optional<RayHit> best;
  const Eigen::Vector2d p(o.x() - s.center.x(), o.y() - s.center.y());
  const Eigen::Vector2d v(d.x(), d.y());
  const double a = v.squaredNorm(), b = 2 * p.dot(v), cc = p.squaredNorm() - s.radius * s.radius;
  if (a > 1e-12)
  {
    const double disc = b * b - 4 * a * cc;
    if (disc >= 0)
    {
      const double t = (-b - std::sqrt(disc)) / (2 * a);
      const double z = o.z() + t * d.z();
      if (t >= 0 && z >= s.z0 && z <= s.z1)
      {
        RayHit h;
        h.t = t;
        const Eigen::Vector2d q = p + t * v;
        h.normal = Eigen::Vector3d(q.x(), q.y(), 0).normalized();
        best = h;
      }
    }
  }
  for (const double zc : {s.z0, s.z1})
  {
    if (std::abs(d.z()) < 1e-12) continue;
    const double t = (zc - o.z()) / d.z();
    if (t < 0 || (best && t >= best->t)) continue;
    if ((p + t * v).squaredNorm() > s.radius * s.radius) continue;
    if ((zc == s.z0) != (d.z() > 0)) continue;  // only the cap facing the ray
    RayHit h;
    h.t = t;
    h.normal = Eigen::Vector3d(0, 0, d.z() > 0 ? -1.0 : 1.0);
    best = h;
  }
  return best;
}
}  // namespace

std::optional<RayHit> castRay(const World& w, const Eigen::Vector3d& origin, const Eigen::Vector3d& dir, double t_max,
                              double time)
{
  std::optional<RayHit> best;
  if (dir.z() < -1e-12)
  {
    const double t = -origin.z() / dir.z();
    if (t >= 0 && t <= t_max) best = RayHit{t, Eigen::Vector3d::UnitZ(), -1};
  }
  for (size_t i = 0; i < w.solids.size(); ++i)
  {
    const Solid& s = w.solids[i];
    const std::optional<RayHit> h = s.shape == Solid::BOX ? hitBox(s, origin, dir) : hitCylinder(s, origin, dir);
    if (h && h->t <= t_max && (!best || h->t < best->t))
    {
      best = h;
      best->solid = static_cast<int>(i);
    }
  }
  if (!std::isnan(time))
    for (size_t i = 0; i < w.people.size(); ++i)
    {
      // The body as rendered: a cylinder to the shoulders and the head's above it.
      const Person& p = w.people[i];
      const PersonState st = personAt(p, time);
      Solid body;
      body.shape = Solid::CYLINDER;
      body.center = st.position;
      body.radius = p.radius;
      body.z0 = 0.0;
      body.z1 = p.height - PERSON_HEAD_HEIGHT;
      Solid head = body;
      head.radius = PERSON_HEAD_RADIUS * p.radius;
      head.z0 = body.z1;
      head.z1 = p.height;
      for (const Solid* s : {&body, &head})
      {
        const std::optional<RayHit> h = hitCylinder(*s, origin, dir);
        if (h && h->t <= t_max && (!best || h->t < best->t))
        {
          best = h;
          best->person = static_cast<int>(i);
        }
      }
    }
  return best;
}

UltrasonicRanger::UltrasonicRanger(const World& world, const UltrasonicParams& p, uint32_t seed)
  : world_(world), p_(p), rng_(seed * 2654435761ULL + 91ULL)
{
}

std::optional<double> UltrasonicRanger::idealRange(const Eigen::Isometry3d& sensor, double time) const
{
  const Eigen::Vector3d o = sensor.translation();
  const Eigen::Matrix3d R = sensor.linear();
  std::optional<double> nearest;
  const double half = 0.5 * p_.beam_width;
  const int rings = std::max(0, p_.rings);
  for (int ring = 0; ring <= rings; ++ring)
  {
    const double off = rings > 0 ? half * ring / rings : 0.0;
    const int n = ring == 0 ? 1 : 8 * ring;
    for (int k = 0; k < n; ++k)
    {
      const double phi = 2 * M_PI * k / n;
      const Eigen::Vector3d d_local(std::cos(off), std::sin(off) * std::cos(phi), std::sin(off) * std::sin(phi));
      const Eigen::Vector3d d = R * d_local;
      const std::optional<RayHit> h = castRay(world_, o, d, p_.max_range, time);
      if (!h || h->t < p_.min_range) continue;
      // Specular: the echo comes back only from a surface facing the sensor closely enough.
      if (std::acos(std::clamp(-h->normal.dot(d), -1.0, 1.0)) > p_.max_incidence) continue;
      if (!nearest || h->t < *nearest) nearest = h->t;
    }
  }
  return nearest;
}

std::optional<double> UltrasonicRanger::ping(const Eigen::Isometry3d& sensor, double time)
{
  std::uniform_real_distribution<double> U(0.0, 1.0);
  std::normal_distribution<double> N(0.0, 1.0);
  const double u = U(rng_), n = N(rng_);  // always drawn: the sequence does not depend on the scene
  std::optional<double> r = idealRange(sensor, time);
  if (!r || u < p_.dropout) return std::nullopt;
  const double noisy = *r + (p_.noise_sigma + p_.noise_relative * *r) * n;
  if (noisy < p_.min_range || noisy > p_.max_range) return std::nullopt;
  return noisy;
}
}  // namespace assistive_sim
