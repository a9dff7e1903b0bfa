// The simulated wearer of the mobility trials: body collider, vest wearer, cane walker, sighted
// guide (wearer.h).
#include <assistive_trials/wearer.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <queue>

namespace assistive_trials
{
// The simulator's world and body (assistive_sim), named as the trials always did.
using assistive_sim::BodyCollider;
using assistive_sim::World;

namespace
{
constexpr double DEG = M_PI / 180.0;
double wrap(double a) { return std::atan2(std::sin(a), std::cos(a)); }
}  // namespace

// ---------------------------------------------------------------- VestWearer
VestWearer::VestWearer(const WearerParams& p, const BodyState& start, uint32_t seed) : p_(p), s_(start), rng_(seed)
{
  scan_phase_ = std::uniform_real_distribution<double>(0.0, 2.0 * M_PI)(rng_);
  s_.head_yaw = s_.yaw;
  s_.speed = 0.0;  // standing, until the vest says go
}

std::array<float, 4> VestWearer::felt(double t) const
{
  std::array<float, 4> m{ { 0.f, 0.f, 0.f, 0.f } };
  for (const auto& h : history_)
  {
    if (h.first > t - p_.reaction_s + 1e-9) break;
    m = h.second;
  }
  return m;
}

int VestWearer::perceivedLevel(float intensity)
{
  // The protocol's three levels (0.4 / 0.7 / 1.0) as this wearer feels them: the drive on a log
  // scale (vibrotactile magnitude follows a power law) with noise such that `intensity_levels`
  // evenly spaced levels over the same range are told apart about 95 % of the time.
  const double lo = std::log(0.4), hi = 0.0;
  const double spacing = (hi - lo) / std::max(1, p_.intensity_levels - 1);
  const double felt = std::log(std::max(1e-3f, intensity)) + std::normal_distribution<double>(0.0, spacing / 4.0)(rng_);
  const double k = (felt - lo) / (0.5 * (hi - lo));  // 0, 1, 2 at the protocol's levels
  return std::max(1, std::min(3, int(std::lround(k)) + 1));
}

void VestWearer::perceive(double t, double dt, const std::array<float, 4>& m)
{
  const float on = 0.01f;
  const bool ls = m[0] > on, rs = m[1] > on, lw = m[2] > on, rw = m[3] > on;
  if (ls || rs || lw || rw) last_felt_ = t;
  auto drawGain = [&]() {
    return p_.turn_gain * std::exp(std::normal_distribution<double>(0.0, p_.turn_gain_sd)(rng_));
  };
  if (ls && rs && lw && rw)
  {
    percept_ = STOP;
    go_ = false;
    turn_left_ = 0.0;
    spot_side_ = 0;
    shoulder_side_ = 0;
    return;
  }
  if (lw && rw)
  {
    percept_ = UNSURE;  // the UNSURE pattern: stop, use the cane, wait for the vest
    go_ = false;
    turn_left_ = 0.0;
    spot_side_ = 0;
    return;
  }
  if (lw != rw)
  {
    percept_ = lw ? SIDESTEP_LEFT : SIDESTEP_RIGHT;
    go_ = false;  // a side-step ends standing: the walk-on that follows says go
    turn_left_ = 0.0;
    spot_side_ = 0;
    return;
  }
  // shoulders: a tick on both = walk on; one side: two short pulses = veer, a long buzz = turn
  const int side = ls && rs ? 2 : ls ? +1 : rs ? -1 : 0;
  if (side != 0 && shoulder_side_ == 0)
  {
    shoulder_side_ = side;
    shoulder_since_ = t;
    shoulder_peak_ = 0.f;
    shoulder_used_ = false;
  }
  if (side != 0 && side == shoulder_side_)
  {
    shoulder_peak_ = std::max(shoulder_peak_, side == -1 ? m[1] : m[0]);
    if (side != 2 && !shoulder_used_ && t - shoulder_since_ >= 0.25)
    {
      // a long buzz (longer than a veer's 0.15 s pulses): stop and turn towards it while it lasts
      shoulder_used_ = true;
      percept_level_ = perceivedLevel(shoulder_peak_);
      percept_ = side > 0 ? TURN_LEFT : TURN_RIGHT;
      turn_left_ = 0.0;  // a veer under way gives way to the turn
      spot_side_ = side;
      go_ = false;  // after the turn: stand until the walk-on says go
    }
    return;
  }
  if (shoulder_side_ != 0)
  {
    spot_side_ = 0;  // a turn's buzz ended: stop turning
    // the pulse ended (or changed side)
    const double len = t - shoulder_since_;
    if (!shoulder_used_ && len + 1e-9 >= p_.min_pulse_s)
    {
      if (shoulder_side_ == 2)
      {
        percept_ = WALK_ON;
        go_ = true;
      }
      else if (!(last_veer_side_ == shoulder_side_ && shoulder_since_ - last_veer_end_ < 0.4))
      {
        // the first pulse of a veer's pair (the second one belongs to the same cue)
        percept_level_ = perceivedLevel(shoulder_peak_);
        percept_ = shoulder_side_ > 0 ? VEER_LEFT : VEER_RIGHT;
        // each burst asks for this much more (a second one before the first is done adds to it)
        turn_left_ += shoulder_side_ * percept_level_ * 15.0 * DEG * drawGain();
        go_ = true;
      }
      if (shoulder_side_ != 2)
      {
        last_veer_side_ = shoulder_side_;
        last_veer_end_ = t;
      }
    }
    shoulder_side_ = 0;
    if (side != 0) perceive(t, dt, m);  // the other side began at once
    return;
  }
  if (t - last_felt_ > p_.silence_stop_s && go_)
  {
    percept_ = NOTHING;  // the vest has gone silent: stop, use the cane
    go_ = false;
    turn_left_ = 0.0;
    spot_side_ = 0;
  }
}

void VestWearer::step(double t, double dt, const std::array<float, 4>& motors, BodyCollider* collider)
{
  history_.emplace_back(t, motors);
  while (history_.size() > 2 && history_[1].first <= t - p_.reaction_s + 1e-9) history_.pop_front();
  const std::array<float, 4> m = felt(t);
  perceive(t, dt, m);
  auto pickSide = [&]() { return std::bernoulli_distribution(0.5)(rng_) ? +1 : -1; };
  auto stop = [&]() { s_.speed = std::max(0.0, s_.speed - p_.stopDecel() * dt); };
  Eigen::Vector2d side_move = Eigen::Vector2d::Zero();
  const bool waist = (m[2] > 0.01f) != (m[3] > 0.01f) && !(m[0] > 0.01f && m[1] > 0.01f);

  if (t < explore_until_)
  {
    // after a bump: stop and feel around (turning on the spot)
    action_ = EXPLORE;
    stop();
    s_.yaw = wrap(s_.yaw + explore_side_ * p_.explore_rate_deg * DEG * dt);
  }
  else if (waist)
  {
    action_ = SIDESTEP;
    stop();
    const double sgn = m[2] > 0.01f ? +1.0 : -1.0;
    side_move = sgn * p_.sidestep_speed * dt * Eigen::Vector2d(-std::sin(s_.yaw), std::cos(s_.yaw));
  }
  else if (spot_side_ != 0)
  {
    // stop, and turn on the spot while the buzz is felt
    action_ = TURN;
    stop();
    s_.yaw = wrap(s_.yaw + spot_side_ * p_.turn_rate_deg * DEG * dt);
  }
  else if (!go_)
  {
    action_ = STOPPED;
    stop();
  }
  else
  {
    action_ = turn_left_ != 0.0 ? VEER : WALK;
    s_.speed = std::min(p_.walk_speed, s_.speed + p_.accel * dt);
    if (turn_left_ != 0.0)
    {
      const double d = std::min(std::fabs(turn_left_), p_.veer_rate_deg * DEG * dt);
      const double sgn = turn_left_ > 0.0 ? 1.0 : -1.0;
      s_.yaw = wrap(s_.yaw + sgn * d);
      turn_left_ -= sgn * d;
      if (std::fabs(turn_left_) < 1e-9) turn_left_ = 0.0;
    }
    // veering: walking "straight" without sight, the heading wanders (a random walk in distance)
    const double ds = s_.speed * dt;
    if (ds > 0.0 && p_.veer_sigma_deg > 0.0)
      s_.yaw = wrap(s_.yaw + std::normal_distribution<double>(0.0, p_.veer_sigma_deg * DEG * std::sqrt(ds))(rng_));
    s_.yaw = wrap(s_.yaw + p_.veer_bias_deg_per_m * DEG * ds);
  }
  const Eigen::Vector2d target =
      s_.xy + s_.speed * dt * Eigen::Vector2d(std::cos(s_.yaw), std::sin(s_.yaw)) + side_move;
  if (collider)
  {
    bool bumped = false;
    s_.xy = collider->move(s_.xy, target, bumped);
    if (bumped)
    {
      // A person who bumps into something stops and feels around before going on.
      s_.speed = 0.0;
      turn_left_ = 0.0;
      spot_side_ = 0;
      if (t >= explore_until_) explore_side_ = pickSide();
      explore_until_ = t + p_.bump_explore_s;
    }
  }
  else
  {
    s_.xy = target;
  }
  s_.head_yaw = wrap(s_.yaw + p_.scan_amplitude_deg * DEG * std::sin(2.0 * M_PI * t / p_.scan_period_s + scan_phase_));
}

// ---------------------------------------------------------------- CaneWalker
CaneWalker::CaneWalker(const WearerParams& wp, const CaneParams& cp, const BodyState& start, uint32_t seed)
  : wp_(wp), cp_(cp), s_(start), rng_(seed)
{
  bias_ = std::normal_distribution<double>(0.0, cp_.heading_noise_deg * DEG)(rng_);
  s_.head_yaw = s_.yaw;
}

bool CaneWalker::caneContact(const BodyCollider& collider, double yaw) const
{
  double lo, hi;
  return caneContact(collider, yaw, lo, hi);
}

bool CaneWalker::caneContact(const BodyCollider& collider, double yaw, double& lo_deg, double& hi_deg,
                             bool with_people) const
{
  lo_deg = 1e9;
  hi_deg = -1e9;
  for (double a = -cp_.sweep_deg; a <= cp_.sweep_deg + 1e-9; a += 2.0)
  {
    const Eigen::Vector2d dir(std::cos(yaw + a * DEG), std::sin(yaw + a * DEG));
    for (double r = collider.radius(); r <= cp_.reach + 1e-9; r += 0.04)
      if (collider.occupied(s_.xy + r * dir, 0.0, cp_.tip_height, with_people))
      {
        lo_deg = std::min(lo_deg, a);
        hi_deg = std::max(hi_deg, a);
        break;
      }
  }
  return hi_deg >= lo_deg;
}

void CaneWalker::step(double t, double dt, const Eigen::Vector2d& target, BodyCollider& collider)
{
  auto pickSide = [&]() { return std::bernoulli_distribution(0.5)(rng_) ? +1 : -1; };
  if (t < pause_until_)
  {
    s_.speed = 0.0;
    return;
  }
  const double bearing = std::atan2(target.y() - s_.xy.y(), target.x() - s_.xy.x()) + bias_;
  double lo, hi;
  const bool touch = caneContact(collider, s_.yaw, lo, hi);
  // Only a person in the cane's reach: stand and let them pass (up to person_wait_s), then treat
  // them as an obstacle. (Static worlds: never taken, the walk is as before.)
  bool waiting = false;
  if (touch)
  {
    double slo, shi;
    if (!caneContact(collider, s_.yaw, slo, shi, false))
    {
      if (wait_since_ < 0.0) wait_since_ = t;
      waiting = t - wait_since_ < cp_.person_wait_s;
    }
  }
  else
    wait_since_ = -1.0;
  if (waiting)
  {
    s_.speed = 0.0;
  }
  else if (touch)
  {
    // Blocked: stop, keep to the side chosen (wall following); a contact only on one side of the
    // sweep says which way is open, one across the middle (blocked) leaves a choice at random.
    if (side_ == 0)
    {
      side_ = lo > 10.0 ? -1 : hi < -10.0 ? +1 : pickSide();
      turned_ = 0.0;
      ++contacts_;
    }
    s_.speed = 0.0;
    const double d = 90.0 * DEG * dt;
    s_.yaw = wrap(s_.yaw + side_ * d);
    turned_ += d;
    if (turned_ > 160.0 * DEG)  // a corner, a trap: try the other way
    {
      side_ = -side_;
      turned_ = 0.0;
    }
    follow_left_ = cp_.follow_m;
  }
  else
  {
    s_.speed = std::min(wp_.walk_speed, s_.speed + wp_.accel * dt);
    if (follow_left_ > 0.0)
    {
      follow_left_ -= s_.speed * dt;
    }
    else
    {
      const double err = wrap(bearing - s_.yaw);
      const double d = std::clamp(err, -cp_.heading_rate_deg * DEG * dt, cp_.heading_rate_deg * DEG * dt);
      // Turning back towards the route: the cane must be clear that way first.
      if (!caneContact(collider, s_.yaw + d)) s_.yaw = wrap(s_.yaw + d);
      if (std::abs(err) < 20.0 * DEG)
      {
        side_ = 0;
        turned_ = 0.0;
      }
    }
  }
  bool bumped = false;
  s_.xy = collider.move(s_.xy, s_.xy + s_.speed * dt * Eigen::Vector2d(std::cos(s_.yaw), std::sin(s_.yaw)), bumped);
  if (bumped)
  {
    // Hit something the cane did not feel (head height, a table top): stop, step round it.
    s_.speed = 0.0;
    pause_until_ = t + 0.5;
    if (side_ == 0) side_ = pickSide();
    s_.yaw = wrap(s_.yaw + side_ * cp_.avoid_step_deg * DEG);
    follow_left_ = cp_.follow_m;
  }
  s_.head_yaw = s_.yaw;
}

// ---------------------------------------------------------------- sighted guide
namespace
{
/// Shortest collision-free polyline between two points on a 0.1 m grid (8-connected Dijkstra),
/// shortened by line of sight. Empty when there is none.
std::vector<Eigen::Vector2d> guidePath(const World& w, const BodyCollider& body, const Eigen::Vector2d& a,
                                       const Eigen::Vector2d& b)
{
  const double res = 0.1, margin = 0.05;
  const double x0 = w.floor_min.x(), y0 = w.floor_min.y();
  const int W = int(std::ceil((w.floor_max.x() - x0) / res)), H = int(std::ceil((w.floor_max.y() - y0) / res));
  auto cellOf = [&](const Eigen::Vector2d& p, int& x, int& y) {
    x = std::clamp(int(std::floor((p.x() - x0) / res)), 0, W - 1);
    y = std::clamp(int(std::floor((p.y() - y0) / res)), 0, H - 1);
  };
  auto centre = [&](int x, int y) { return Eigen::Vector2d(x0 + (x + 0.5) * res, y0 + (y + 0.5) * res); };
  std::vector<char> ok(size_t(W) * H);
  for (int y = 0; y < H; ++y)
    for (int x = 0; x < W; ++x) ok[size_t(y) * W + x] = body.clearance(centre(x, y)) >= margin;
  int sx, sy, gx, gy;
  cellOf(a, sx, sy);
  cellOf(b, gx, gy);
  ok[size_t(sy) * W + sx] = ok[size_t(gy) * W + gx] = 1;
  std::vector<double> dist(ok.size(), 1e300);
  std::vector<int> prev(ok.size(), -1);
  using Q = std::pair<double, int>;
  std::priority_queue<Q, std::vector<Q>, std::greater<Q>> q;
  const int s = sy * W + sx, g = gy * W + gx;
  dist[size_t(s)] = 0.0;
  q.push({ 0.0, s });
  while (!q.empty())
  {
    const auto [d, i] = q.top();
    q.pop();
    if (d > dist[size_t(i)]) continue;
    if (i == g) break;
    const int x = i % W, y = i / W;
    for (int dy = -1; dy <= 1; ++dy)
      for (int dx = -1; dx <= 1; ++dx)
      {
        const int nx = x + dx, ny = y + dy;
        if ((!dx && !dy) || nx < 0 || ny < 0 || nx >= W || ny >= H || !ok[size_t(ny) * W + nx]) continue;
        const int j = ny * W + nx;
        const double nd = d + res * std::hypot(dx, dy);
        if (nd < dist[size_t(j)])
        {
          dist[size_t(j)] = nd;
          prev[size_t(j)] = i;
          q.push({ nd, j });
        }
      }
  }
  if (dist[size_t(g)] >= 1e299) return {};
  std::vector<Eigen::Vector2d> cells;
  for (int i = g; i >= 0; i = prev[size_t(i)]) cells.push_back(centre(i % W, i / W));
  std::reverse(cells.begin(), cells.end());
  cells.front() = a;
  cells.back() = b;
  auto visible = [&](const Eigen::Vector2d& p, const Eigen::Vector2d& q2) {
    const int n = std::max(1, int(std::ceil((q2 - p).norm() / 0.05)));
    for (int k = 1; k < n; ++k)
      if (body.clearance(p + (q2 - p) * (double(k) / n)) < 0.0) return false;
    return true;
  };
  std::vector<Eigen::Vector2d> out{ cells.front() };
  size_t i = 0;
  while (i + 1 < cells.size())
  {
    size_t j = cells.size() - 1;
    while (j > i + 1 && !visible(cells[i], cells[j])) --j;
    out.push_back(cells[j]);
    i = j;
  }
  return out;
}
}  // namespace

double sightedGuideTime(const World& world, const WearerParams& p, const Eigen::Vector2d& start,
                        const std::vector<Eigen::Vector2d>& route, std::vector<Eigen::Vector2d>* path)
{
  BodyCollider body(world, p.body_radius, p.eye_height + 0.12);
  double len = 0.0;
  Eigen::Vector2d from = start;
  if (path) path->assign(1, start);
  for (const Eigen::Vector2d& to : route)
  {
    const std::vector<Eigen::Vector2d> seg = guidePath(world, body, from, to);
    if (seg.empty()) return -1.0;
    for (size_t i = 1; i < seg.size(); ++i)
    {
      len += (seg[i] - seg[i - 1]).norm();
      if (path) path->push_back(seg[i]);
    }
    from = to;
  }
  // Walked at cruise speed after speeding up from standing (no stops: the guide sees the way).
  const double ramp = p.walk_speed / p.accel;
  const double ramp_len = 0.5 * p.accel * ramp * ramp;
  return len <= ramp_len ? std::sqrt(2.0 * len / p.accel) : ramp + (len - ramp_len) / p.walk_speed;
}

namespace
{
/// Time lost against cruising at v by a turn of `angle` (rad) on the spot begun at v: braking while
/// the buzz turns the body, the tick, then speeding up again (the way walked meanwhile counts).
double brakingTurnLoss(const WearerParams& p, double angle)
{
  const double v = p.walk_speed, dec = p.stopDecel();
  const double t_brake = std::fabs(angle) / (p.turn_rate_deg * DEG) + p.min_pulse_s;
  const double v1 = std::max(0.0, v - dec * t_brake);
  const double t_stop = std::min(t_brake, v / dec);
  const double d_brake = v * t_stop - 0.5 * dec * t_stop * t_stop;
  const double t_up = (v - v1) / p.accel;
  const double d_up = v1 * t_up + 0.5 * p.accel * t_up * t_up;
  return t_brake + t_up - (d_brake + d_up) / v;
}

/// Time lost against cruising at v by braking to `vb` (a stop, then the tick at vb) and speeding up
/// again.
double brakeLoss(const WearerParams& p, double vb)
{
  const double v = p.walk_speed, t = (v - vb) / p.stopDecel() + (v - vb) / p.accel;
  return t * (v - vb) / (2.0 * v);
}

/// True when a veer at radius R (speed / veer rate) turns the corner `b` between legs a->b
/// and b->c with the body clear: the arc tangent to both legs, pushed out along the bisector to
/// pass through b (the guide's path touches the obstacle the corner turns round).
bool veerFits(const BodyCollider& body, double R, const Eigen::Vector2d& a, const Eigen::Vector2d& b,
              const Eigen::Vector2d& c)
{
  const Eigen::Vector2d u = (b - a).normalized(), w = (c - b).normalized();
  const double turn = std::atan2(u.x() * w.y() - u.y() * w.x(), u.dot(w));  // + = left
  const double half = 0.5 * std::fabs(turn);
  const double tangent = R * std::tan(half);
  // the walk never gets room for the arc when a leg is shorter than its tangent
  if (tangent > (b - a).norm() || tangent > (c - b).norm()) return false;
  const Eigen::Vector2d inward = (w - u).normalized();  // towards the arc's centre
  const Eigen::Vector2d push = -inward * R * (1.0 / std::cos(half) - 1.0);
  const Eigen::Vector2d normal = turn > 0.0 ? Eigen::Vector2d(-u.y(), u.x()) : Eigen::Vector2d(u.y(), -u.x());
  const Eigen::Vector2d centre = b - u * tangent + normal * R + push;
  const double a0 = std::atan2(-normal.y(), -normal.x());
  const int n = std::max(2, int(std::ceil(R * std::fabs(turn) / 0.05)));
  for (int k = 0; k <= n; ++k)
  {
    const double ang = a0 + turn * double(k) / n;
    if (body.clearance(centre + R * Eigen::Vector2d(std::cos(ang), std::sin(ang))) < 0.0) return false;
  }
  return true;
}
}  // namespace

WalkFloor wearerFloor(const World& world, const WearerParams& p, const BodyState& start,
                      const std::vector<Eigen::Vector2d>& route)
{
  WalkFloor f;
  std::vector<Eigen::Vector2d> path;
  f.guide_time_s = sightedGuideTime(world, p, start.xy, route, &path);
  if (f.guide_time_s < 0.0) return f;
  BodyCollider body(world, p.body_radius, p.eye_height + 0.12);
  // drop repeated points (a route's place on the path's last point)
  std::vector<Eigen::Vector2d> pts;
  for (const Eigen::Vector2d& q : path)
    if (pts.empty() || (q - pts.back()).norm() > 1e-6) pts.push_back(q);
  f.start_s = p.reaction_s + p.min_pulse_s;
  if (pts.size() >= 2)
  {
    const Eigen::Vector2d d = pts[1] - pts[0];
    const double off = std::fabs(std::remainder(std::atan2(d.y(), d.x()) - start.yaw, 2.0 * M_PI));
    if (off > 20.0 * DEG) f.start_s += 0.25 + off / (p.turn_rate_deg * DEG);
  }
  for (size_t i = 1; i + 1 < pts.size(); ++i)
  {
    const Eigen::Vector2d u = pts[i] - pts[i - 1], w = pts[i + 1] - pts[i];
    const double turn = std::atan2(u.x() * w.y() - u.y() * w.x(), u.dot(w));
    // a bend a veer's smallest ask covers is walked whatever room it has (the guide's 0.1 m cells
    // leave such bends where its path curves)
    if (std::fabs(turn) <= 15.0 * DEG) continue;
    ++f.corners;
    // veered at cruise speed, or braked to a speed whose arc fits first (a stop, the tick at that
    // speed and the veer), or turned on the spot while braking: the cheapest
    double loss = brakingTurnLoss(p, turn);
    for (double vb = p.walk_speed; vb > 0.1; vb -= 0.05)
      if (veerFits(body, vb / (p.veer_rate_deg * DEG), pts[i - 1], pts[i], pts[i + 1]))
      {
        if (vb == p.walk_speed) ++f.in_stride;
        loss = std::min(loss, brakeLoss(p, vb));
        break;
      }
    f.turns_s += loss;
  }
  f.time_s = f.guide_time_s + f.start_s + f.turns_s;
  return f;
}

}  // namespace assistive_trials
