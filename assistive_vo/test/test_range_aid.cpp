#include <gtest/gtest.h>
#include <cmath>
#include <cstdio>
#include "assistive_vo/inertial_coasting.h"
#include "assistive_vo/range_aid.h"

using namespace assistive_vo;

namespace
{
/// A wearer walking at 1 m/s along x towards a wall 4 m ahead, tracked by a VO whose path is 10 %
/// too long (its scale error: the fitted velocity 1.1 m/s), then blind: the IMU coasts on.
struct WallApproach
{
  double speed = 1.0, vo_scale = 1.1, wall_x = 4.0, rate = 15.0;
  static ImuDelta still(double h)
  {
    ImuDelta d;  // no acceleration: the specific force is gravity's reaction, camera_link = odom axes
    d.dt = h;
    d.dv = Eigen::Vector3d(0, 0, 9.81) * h;
    d.dp = Eigen::Vector3d(0, 0, 9.81) * 0.5 * h * h;
    return d;
  }
  /// Tracked frames for 1.5 s; returns the coast's start time.
  double track(InertialCoaster& c) const
  {
    const double h = 1.0 / rate;
    double t = 0;
    for (int k = 0; k <= 22; ++k, t = k * h)
    {
      Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
      T.translation() = Eigen::Vector3d(vo_scale * speed * t, 0, 1.6);
      const ImuDelta d = still(h);
      c.addTracked(t, T, k == 0 ? nullptr : &d);
    }
    return 22 * h;
  }
  /// The wall's normal turned by this from the walk (rad), and the ranger's axis turning at this
  /// rate (rad/s) from -0.15 rad at the coast's start (the head's scan); the range along the axis.
  double wall_angle = 0.0, scan_rate = 0.0, coast_start = 22.0 / 15.0;
  double yaw(double t) const { return scan_rate > 0 ? -0.15 + scan_rate * (t - coast_start) : 0.0; }
  double range(double t) const
  {
    return std::cos(wall_angle) * (wall_x - speed * t) / std::cos(yaw(t) - wall_angle);
  }
};

/// Coasts `n` frames from `t0` with ranges at 20 Hz (`ranges` false: none); the coasted
/// displacement's error along x against the truth and the last gate variance.
struct CoastResult
{
  double err = 0, gate_var = 0;
  int aided = 0, rejected_jump = 0;
};
CoastResult coastToWall(const WallApproach& w, bool ranges, double person_at = -1.0,
                        const RangeAid::Options& o = RangeAid::Options())
{
  InertialCoaster c;
  const double t0 = w.track(c);
  EXPECT_TRUE(c.start());
  RangeAid aid(o);
  const double h = 1.0 / w.rate;
  double next_range = 0.0, coasted = 0.0;
  CoastResult out;
  for (int k = 1; k <= 22; ++k)
  {
    const double t = t0 + k * h;
    for (; next_range <= t; next_range += 0.05)
      if (ranges)
        aid.addRange(next_range, person_at >= 0 && next_range >= person_at ? 0.8 : w.range(next_range));
    Eigen::Vector3d dpos = c.step(Eigen::Matrix3d::Identity(), WallApproach::still(h));
    const RangeAid::Step s = aid.step(t, Eigen::Vector3d(std::cos(w.yaw(t)), std::sin(w.yaw(t)), 0), dpos, c);
    if (person_at >= 0 && t >= person_at && t < person_at + 0.1 && s.dpos.norm() > 0.05)
      ++out.rejected_jump;  // counts a correction that followed the person's echo
    dpos += s.dpos;
    c.correctVelocity(s.dv);
    coasted += dpos.x();
    out.aided += s.aided;
    out.gate_var = s.gate_var;
  }
  out.err = coasted - w.speed * 22 * h;
  return out;
}
}  // namespace

TEST(RangeAid, AWallAheadMeasuresTheCoastsWalkAlongTheRangersAxis)
{
  const WallApproach w;
  const CoastResult blind = coastToWall(w, false);
  const CoastResult aided = coastToWall(w, true);
  // without the ranger the VO's 10 % scale error carries on: 0.15 m over 1.5 s, beyond the
  // 0.15 m trust limit's variance
  EXPECT_NEAR(blind.err, 0.147, 0.01);
  EXPECT_EQ(blind.aided, 0);
  EXPECT_GT(blind.gate_var, 0.15 * 0.15);
  // with it: the walk along the axis is the range's change, and the worst axis stays well within
  EXPECT_LT(std::abs(aided.err), 0.03);
  EXPECT_GE(aided.aided, 18);  // every frame after the anchor and the first line fit
  // (its variance is mostly the model's: 8 % of the 1.4 m the range closed)
  EXPECT_LT(aided.gate_var, 0.5 * blind.gate_var);
  EXPECT_LT(aided.gate_var, 0.15 * 0.15);
}

TEST(RangeAid, AnEchoFromSomethingElseIsNoWalk)
{
  // a person steps into the beam and stays there: the range drops by a metre at once (the line fit
  // over the window rejects the mix) and then stays put while the IMU says the wearer walks on.
  const WallApproach w;
  const CoastResult blind = coastToWall(w, false);
  // at the coast's start: nothing corrects the coast, it carries on as without a ranger (a range
  // that stands still would otherwise pull it towards standing: -1.4 m)
  const CoastResult at_once = coastToWall(w, true, 1.4667);
  EXPECT_EQ(at_once.aided, 0);
  EXPECT_NEAR(at_once.err, blind.err, 0.005);
  // 0.5 s in: the wall's ranges have corrected most of the error by then; the person's echo moves nothing
  const CoastResult later = coastToWall(w, true, 1.4667 + 0.5);
  EXPECT_EQ(later.rejected_jump, 0);
  EXPECT_LT(std::abs(later.err), 0.5 * blind.err);
  EXPECT_LT(later.aided, 9);
}

TEST(RangeAid, TheHeadsTurnIsNoWalk)
{
  // a wall at 30 deg to the walk and the head scanning at 7 deg/s: turning the ranger changes its
  // range by up to r tan(incidence) per radian, walked or not; here the range closes 20 % faster than
  // the walk, the same way as the VO's 10 % error. The aid cannot tell, but its variance must say so.
  WallApproach w;
  w.wall_angle = 30.0 * M_PI / 180.0;
  w.scan_rate = 7.0 * M_PI / 180.0;
  const CoastResult aided = coastToWall(w, true);
  RangeAid::Options no_turn;
  no_turn.max_incidence_deg = 0.0;  // the turn's share not counted: every range change read as the walk
  const CoastResult naive = coastToWall(w, true, -1.0, no_turn);
  std::printf("aided err %.3f sigma %.3f, naive err %.3f sigma %.3f\n", aided.err, std::sqrt(aided.gate_var),
              naive.err, std::sqrt(naive.gate_var));
  EXPECT_LT(std::abs(aided.err), 2.0 * std::sqrt(aided.gate_var));
  EXPECT_GT(std::abs(naive.err), 2.0 * std::sqrt(naive.gate_var));
}
