#include <assistive_sim/motion.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace assistive_sim
{
namespace
{
constexpr double DEG = M_PI / 180.0;
constexpr double G = 9.81;

// 5-point Gauss-Legendre on [0, 1].
const double GL_X[5] = {0.04691007703066800, 0.23076534494715845, 0.5, 0.76923465505284155, 0.95308992296933200};
const double GL_W[5] = {0.11846344252809454, 0.23931433524968324, 0.28444444444444444, 0.23931433524968324,
                        0.11846344252809454};

/// Quintic smoothstep and its integral.
double smooth5(double x)
{
  x = std::clamp(x, 0.0, 1.0);
  return x * x * x * (10 + x * (-15 + 6 * x));
}
}  // namespace

WearerMotion::Leg WearerMotion::buildLeg(const std::vector<Eigen::Vector2d>& poly, double corner_radius)
{
  Leg leg;
  // Densify: points near each corner (corner_radius before/after) and every <= 0.8 m between.
  std::vector<Eigen::Vector2d> dense;
  const size_t n = poly.size();
  std::vector<double> rin(n, 0.0), rout(n, 0.0);
  for (size_t i = 1; i + 1 < n; ++i)
  {
    const double a = (poly[i] - poly[i - 1]).norm(), b = (poly[i + 1] - poly[i]).norm();
    rin[i] = std::min(corner_radius, 0.4 * a);
    rout[i] = std::min(corner_radius, 0.4 * b);
  }
  for (size_t i = 0; i + 1 < n; ++i)
  {
    const Eigen::Vector2d d = (poly[i + 1] - poly[i]).normalized();
    const Eigen::Vector2d s = poly[i] + d * rout[i], e = poly[i + 1] - d * rin[i + 1];
    if (i == 0) dense.push_back(poly[0]);
    else dense.push_back(poly[i]), dense.push_back(s);
    const double len = (e - s).norm();
    const int k = std::max(2, static_cast<int>(std::ceil(len / 0.8)));
    for (int j = 1; j <= k; ++j) dense.push_back(s + (e - s) * (static_cast<double>(j) / k));
  }
  dense.push_back(poly.back());
  // Remove near-duplicates.
  std::vector<Eigen::Vector2d> clean;
  for (const auto& p : dense)
    if (clean.empty() || (p - clean.back()).norm() > 1e-3) clean.push_back(p);
  // Phantom end points so the curve starts/ends exactly at the first/last waypoint.
  leg.ctrl.push_back(2 * clean[0] - clean[1]);
  leg.ctrl.insert(leg.ctrl.end(), clean.begin(), clean.end());
  leg.ctrl.push_back(2 * clean.back() - clean[clean.size() - 2]);
  const int spans = static_cast<int>(leg.ctrl.size()) - 3;
  leg.span_s.assign(spans + 1, 0.0);
  for (int j = 0; j < spans; ++j) leg.span_s[j + 1] = leg.span_s[j] + spanLength(leg, j, 0.0, 1.0);
  leg.length = leg.span_s.back();
  const Eigen::Vector2d d0 = spline(leg, 0.0, 1), d1 = spline(leg, spans, 1);
  leg.heading_in = std::atan2(d0.y(), d0.x());
  leg.heading_out = std::atan2(d1.y(), d1.x());
  return leg;
}

WearerMotion::WearerMotion(const TrajectoryScript& script, uint32_t seed) : script_(script)
{
  if (script_.waypoints.size() < 2) throw std::invalid_argument("trajectory needs at least 2 waypoints");
  // Waypoint polyline, repeated for loops (closing back to the first point between loops).
  std::vector<Eigen::Vector2d> poly;
  for (int l = 0; l < script_.loops; ++l)
    for (const auto& p : script_.waypoints)
      if (poly.empty() || (p - poly.back()).norm() > 1e-6) poly.push_back(p);
  if (poly.size() < 2) throw std::invalid_argument("trajectory needs at least 2 distinct waypoints");
  // Split into legs at corners sharper than turn_on_spot_above: nobody walks a hairpin as a
  // smooth curve (its tangent would flip 180 deg between two frames); they stop and turn.
  std::vector<std::vector<Eigen::Vector2d>> pieces(1, std::vector<Eigen::Vector2d>{poly[0]});
  for (size_t i = 1; i < poly.size(); ++i)
  {
    pieces.back().push_back(poly[i]);
    if (i + 1 == poly.size()) break;
    const Eigen::Vector2d a = poly[i] - poly[i - 1], b = poly[i + 1] - poly[i];
    const double turn = std::abs(std::atan2(a.x() * b.y() - a.y() * b.x(), a.dot(b)));
    if (turn > script_.turn_on_spot_above) pieces.push_back({poly[i]});
  }
  // A milder corner between short segments can still make the rounded curve too tight to walk:
  // split where the curve would turn the body faster than max_walk_turn_rate.
  const double v_max = script_.speed * (1 + script_.speed_variation);
  for (size_t k = 0; k < pieces.size(); ++k)
  {
    const std::vector<Eigen::Vector2d>& piece = pieces[k];
    if (piece.size() < 3) continue;
    const Leg leg = buildLeg(piece, script_.corner_radius);
    double kappa_max = 0.0;
    Eigen::Vector2d at = piece[0];
    const int spans = static_cast<int>(leg.ctrl.size()) - 3;
    for (double u = 0.0; u <= spans; u += 0.02)
    {
      const Eigen::Vector2d d1 = spline(leg, u, 1), d2 = spline(leg, u, 2);
      const double n = d1.norm();
      if (n < 1e-9) continue;
      const double kappa = std::abs(d1.x() * d2.y() - d1.y() * d2.x()) / (n * n * n);
      if (kappa > kappa_max) kappa_max = kappa, at = spline(leg, u, 0);
    }
    if (kappa_max * v_max <= script_.max_walk_turn_rate) continue;
    size_t split = 1;
    for (size_t i = 2; i + 1 < piece.size(); ++i)
      if ((piece[i] - at).norm() < (piece[split] - at).norm()) split = i;
    std::vector<Eigen::Vector2d> tail(piece.begin() + static_cast<long>(split), piece.end());
    pieces[k].resize(split + 1);
    pieces.insert(pieces.begin() + static_cast<long>(k) + 1, tail);
    --k;  // check the shortened piece again
  }

  // Timing: each leg accelerates from rest; a leg that ends in a turn on the spot slows to a stop.
  for (const auto& piece : pieces) legs_.push_back(buildLeg(piece, script_.corner_radius));
  const double v0 = script_.speed;
  double t = script_.start_still, s0 = 0.0;
  for (size_t k = 0; k < legs_.size(); ++k)
  {
    Leg& leg = legs_[k];
    leg.t0 = t;
    leg.s0 = s0;
    leg.stops = k + 1 < legs_.size();
    if (leg.stops)
    {
      // Legs shorter than accelerate + decelerate use a shorter ramp (peak speed v0, briefly).
      leg.t_ramp = std::min(t_ramp_, leg.length / v0);
      double lo = 0.0, hi = leg.length / (0.5 * v0) + 10;
      for (int it = 0; it < 100; ++it)
      {
        const double mid = 0.5 * (lo + hi);
        leg.t_cruise = mid;
        (legDistance(leg, leg.t_ramp + mid + leg.t_ramp) < leg.length ? lo : hi) = mid;
      }
      leg.t_cruise = hi;
      leg.t1 = leg.t0 + 2 * leg.t_ramp + leg.t_cruise;
    }
    else
    {
      leg.t_ramp = t_ramp_;
      double lo = leg.t0, hi = leg.t0 + t_ramp_ + leg.length / (0.5 * v0) + 10;
      for (int it = 0; it < 100; ++it)
      {
        const double mid = 0.5 * (lo + hi);
        (legDistance(leg, mid - leg.t0) < leg.length ? lo : hi) = mid;
      }
      leg.t1 = hi;
    }
    t = leg.t1;
    s0 += leg.length;
    if (leg.stops)
    {
      // Pause, turn (quintic profile, peak rate turn_rate), pause.
      double dh = std::remainder(legs_[k + 1].heading_in - leg.heading_out, 2 * M_PI);
      if (std::abs(dh) > M_PI - 1e-9) dh = M_PI;
      leg.turn = dh;
      leg.turn_at = t + 0.3;
      leg.turn_duration = std::max(0.8, 1.875 * std::abs(dh) / script_.turn_rate);
      t = leg.turn_at + leg.turn_duration + 0.3;
    }
  }
  length_ = s0;
  t_walk_ = script_.start_still;
  t_end_ = legs_.back().t1;

  // Phases and head turns.
  std::mt19937 rng(seed * 977u + 5u);
  std::uniform_real_distribution<double> U(0.0, 1.0);
  phase_pitch_ = U(rng) * 2 * M_PI;
  phase_scan_ = U(rng) * 2 * M_PI;
  turns_ = script_.head_turns;
  if (script_.auto_head_turns)
  {
    // Bands (peak rate deg/s, amplitude deg): slow < 5, medium 5-20, fast 20-30, jerks faster.
    struct Band { double rate_lo, rate_hi, amp_lo, amp_hi; };
    const Band bands[4] = {{2.5, 4.5, 8, 14}, {8, 18, 20, 35}, {21, 29, 25, 40}, {60, 90, 15, 25}};
    double t = t_walk_ + 2.0 + 2.0 * U(rng);
    int k = static_cast<int>(U(rng) * 4);
    while (true)
    {
      const Band& b = bands[k % 4];
      const double amp = (b.amp_lo + U(rng) * (b.amp_hi - b.amp_lo)) * DEG * (U(rng) < 0.5 ? -1 : 1);
      const double rate = (b.rate_lo + U(rng) * (b.rate_hi - b.rate_lo)) * DEG;
      const double dur = 1.875 * std::abs(amp) / rate;
      const double hold = 0.5 + U(rng);
      const Band& rb = bands[(k + 1 + static_cast<int>(U(rng) * 2)) % 4];
      const double rrate = (rb.rate_lo + U(rng) * (rb.rate_hi - rb.rate_lo)) * DEG;
      const double rdur = 1.875 * std::abs(amp) / rrate;
      if (t + dur + hold + rdur > t_end_ - 0.5) break;
      turns_.push_back({t, amp, rate});
      turns_.push_back({t + dur + hold, -amp, rrate});
      t += dur + hold + rdur + 1.5 + 2.5 * U(rng);
      ++k;
    }
  }
}

Eigen::Vector2d WearerMotion::spline(const Leg& leg, double u, int deriv)
{
  const int spans = static_cast<int>(leg.ctrl.size()) - 3;
  int j = static_cast<int>(std::floor(u));
  j = std::clamp(j, 0, spans - 1);
  const double x = u - j;
  const Eigen::Vector2d &p0 = leg.ctrl[j], &p1 = leg.ctrl[j + 1], &p2 = leg.ctrl[j + 2], &p3 = leg.ctrl[j + 3];
  if (deriv == 0)
  {
    const double x2 = x * x, x3 = x2 * x;
    return ((1 - x) * (1 - x) * (1 - x) * p0 + (3 * x3 - 6 * x2 + 4) * p1 + (-3 * x3 + 3 * x2 + 3 * x + 1) * p2 +
            x3 * p3) / 6.0;
  }
  if (deriv == 1)
    return (-(1 - x) * (1 - x) * p0 + (3 * x * x - 4 * x) * p1 + (-3 * x * x + 2 * x + 1) * p2 + x * x * p3) / 2.0;
  return (1 - x) * p0 + (3 * x - 2) * p1 + (-3 * x + 1) * p2 + x * p3;
}

double WearerMotion::spanLength(const Leg& leg, int j, double u0, double u1)
{
  // Composite Gauss-Legendre over 4 pieces.
  double sum = 0.0;
  const double h = (u1 - u0) / 4;
  for (int p = 0; p < 4; ++p)
    for (int i = 0; i < 5; ++i) sum += GL_W[i] * spline(leg, j + u0 + h * (p + GL_X[i]), 1).norm();
  return sum * h;
}

double WearerMotion::uOfS(const Leg& leg, double s)
{
  s = std::clamp(s, 0.0, leg.length);
  const int spans = static_cast<int>(leg.span_s.size()) - 1;
  int j = static_cast<int>(std::upper_bound(leg.span_s.begin(), leg.span_s.end(), s) - leg.span_s.begin()) - 1;
  j = std::clamp(j, 0, spans - 1);
  const double target = s - leg.span_s[j];
  const double sl = leg.span_s[j + 1] - leg.span_s[j];
  double x = sl > 0 ? target / sl : 0.0;
  for (int it = 0; it < 8; ++it)
  {
    const double f = spanLength(leg, j, 0.0, x) - target;
    const double d = spline(leg, j + x, 1).norm();
    if (d < 1e-9) break;
    const double step = f / d;
    x = std::clamp(x - step, 0.0, 1.0);
    if (std::abs(step) < 1e-12) break;
  }
  return j + x;
}

double WearerMotion::legDistance(const Leg& leg, double tau) const
{
  // Speed: quintic ramp up from rest over t_ramp, cruise v0 (1 + a sin^2(w t)), and for a leg that
  // stops, a quintic ramp down from the cruise speed reached (the acceleration steps by at most
  // v0 a w ~ 0.02 m/s^2 where the ramp down starts, well below the IMU noise).
  const double v0 = script_.speed, a = script_.speed_variation, w = M_PI / 10.0, tr = leg.t_ramp;
  if (tau <= 0) return 0.0;
  auto rampInt = [](double x) { return x * x * x * x * (2.5 + x * (-3 + x)); };  // integral of smooth5
  auto cruise = [&](double tp) { return v0 * tr * 0.5 + v0 * (tp + a * (tp / 2 - std::sin(2 * w * tp) / (4 * w))); };
  if (tau < tr) return std::min(v0 * tr * rampInt(tau / tr), leg.length);
  const double tp = tau - tr;
  if (!leg.stops || tp <= leg.t_cruise) return std::min(cruise(tp), leg.length);
  const double vc = v0 * (1 + a * std::pow(std::sin(w * leg.t_cruise), 2));
  const double y = std::min((tp - leg.t_cruise) / tr, 1.0);
  return std::min(cruise(leg.t_cruise) + vc * tr * (y - rampInt(y)), leg.length);
}

size_t WearerMotion::legAt(double t) const
{
  size_t k = 0;
  while (k + 1 < legs_.size() && t >= legs_[k + 1].t0) ++k;
  return k;
}

double WearerMotion::distance(double t) const
{
  const Leg& leg = legs_[legAt(t)];
  return leg.s0 + legDistance(leg, t - leg.t0);
}

double WearerMotion::speed(double t) const
{
  const double h = 1e-4;
  return (distance(t + h) - distance(t - h)) / (2 * h);
}

Eigen::Vector2d WearerMotion::pathPoint(double s) const
{
  size_t k = 0;
  while (k + 1 < legs_.size() && s >= legs_[k + 1].s0) ++k;
  return spline(legs_[k], uOfS(legs_[k], s - legs_[k].s0), 0);
}

double WearerMotion::headYawOffset(double t) const
{
  double y = 0.0;
  for (const HeadTurn& h : turns_)
  {
    const double dur = 1.875 * std::abs(h.yaw) / h.rate;
    if (dur <= 0) continue;
    y += h.yaw * smooth5((t - h.at) / dur);
  }
  return y;
}

Eigen::Isometry3d WearerMotion::linkPose(double t) const
{
  const TrajectoryScript& sc = script_;
  const Leg& leg = legs_[legAt(t)];
  const double s = leg.s0 + legDistance(leg, t - leg.t0);
  const double u = uOfS(leg, s - leg.s0);
  const Eigen::Vector2d p = spline(leg, u, 0);
  double heading;
  if (t < leg.t1 || !leg.stops)
  {
    const Eigen::Vector2d d1 = spline(leg, u, 1);
    heading = std::atan2(d1.y(), d1.x());
  }
  else  // standing at the leg's end, turning on the spot
    heading = leg.heading_out + leg.turn * smooth5((t - leg.turn_at) / leg.turn_duration);
  const Eigen::Vector2d normal(-std::sin(heading), std::cos(heading));
  // Gait: amplitude grows smoothly over the first 0.6 m.
  const double amp = smooth5(s / 0.6);
  const double bob = -sc.bob_amplitude * amp * std::cos(2 * M_PI * s / sc.step_length);
  const double sway = sc.sway_amplitude * amp * std::sin(M_PI * s / sc.step_length);
  // Head.
  const double mid = 0.5 * (sc.pitch_min + sc.pitch_max), half = 0.5 * (sc.pitch_max - sc.pitch_min);
  const double nod = 0.6 * DEG * amp * std::sin(2 * M_PI * s / sc.step_length + 0.7);
  const double pitch = mid + std::max(0.0, half - 0.7 * DEG) * std::sin(2 * M_PI * t / 13.0 + phase_pitch_) + nod;
  const double scan_on = smooth5(t / 2.0);
  const double yaw = heading + headYawOffset(t) +
                     scan_on * sc.scan_amplitude * std::sin(2 * M_PI * t / sc.scan_period + phase_scan_);
  const double roll = 1.2 * DEG * amp * std::sin(M_PI * s / sc.step_length + 0.3);
  const Eigen::Matrix3d R = (Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()) *
                             Eigen::AngleAxisd(pitch, Eigen::Vector3d::UnitY()) *
                             Eigen::AngleAxisd(roll, Eigen::Vector3d::UnitX())).toRotationMatrix();
  // The head turns about the neck, 0.10 m below and 0.09 m behind the camera.
  const Eigen::Vector2d xy = p + normal * sway;
  const Eigen::Vector3d neck(xy.x(), xy.y(), sc.eye_height - 0.10 + bob);
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = R;
  T.translation() = neck + R * Eigen::Vector3d(0.09, 0.0, 0.10);
  return T;
}

Eigen::Vector3d WearerMotion::velocity(double t) const
{
  const double h = 1e-3;
  return (linkPose(t + h).translation() - linkPose(t - h).translation()) / (2 * h);
}

Eigen::Vector3d WearerMotion::acceleration(double t) const
{
  const double h = 2e-3;
  return (linkPose(t + h).translation() - 2 * linkPose(t).translation() + linkPose(t - h).translation()) / (h * h);
}

Eigen::Vector3d WearerMotion::angularVelocity(double t) const
{
  const double h = 1e-4;
  const Eigen::Matrix3d Ra = linkPose(t - h).linear(), Rb = linkPose(t + h).linear();
  const Eigen::AngleAxisd aa(Ra.transpose() * Rb);
  return aa.axis() * aa.angle() / (2 * h);
}

ImuSample WearerMotion::idealImu(double t) const
{
  ImuSample s;
  s.stamp = t;
  const Eigen::Isometry3d T = linkPose(t);
  s.gyro = angularVelocity(t);
  s.accel = T.linear().transpose() * (acceleration(t) + Eigen::Vector3d(0, 0, G));
  s.orientation = Eigen::Quaterniond(T.linear());
  return s;
}

ImuSimulator::ImuSimulator(const ImuParams& p, uint32_t seed) : p_(p), rng_(seed * 1315423911ULL + 77ULL)
{
  for (int i = 0; i < 3; ++i) bg_[i] = p_.gyro_bias_initial * n_(rng_);
  for (int i = 0; i < 3; ++i) ba_[i] = p_.accel_bias_initial * n_(rng_);
}

ImuSample ImuSimulator::next(const WearerMotion& motion, double t0, double motion_time)
{
  const double t = k_ / p_.rate;
  ++k_;
  ImuSample s = motion.idealImu(motion_time >= 0.0 ? motion_time : t);
  const double dt = 1.0 / p_.rate;
  const double sg = p_.gyro_noise_density * std::sqrt(p_.rate), sa = p_.accel_noise_density * std::sqrt(p_.rate);
  for (int i = 0; i < 3; ++i)
  {
    bg_[i] += p_.gyro_bias_walk * std::sqrt(dt) * n_(rng_);
    ba_[i] += p_.accel_bias_walk * std::sqrt(dt) * n_(rng_);
    s.gyro[i] += bg_[i] + sg * n_(rng_);
    s.accel[i] += ba_[i] + sa * n_(rng_);
  }
  s.stamp = t0 + t;
  s.has_orientation = false;
  return s;
}

}  // namespace assistive_sim
