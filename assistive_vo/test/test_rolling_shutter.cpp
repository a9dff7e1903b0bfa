// RollingShutter: observations of a rolling-shutter camera moved to the stamp, against the exact
// projection of known points (each row's camera posed at its own exposure time).
#include <random>
#include <gtest/gtest.h>
#include <Eigen/Geometry>
#include "assistive_vo/rolling_shutter.h"
#include "synthetic.h"

using namespace assistive_vo;

namespace
{
struct Observation
{
  double u, v, d;
};

/// Where a rolling shutter sees X (stamp's optical frame): the row v whose camera, turned by
/// exp(omega dt(v)) and moved by velocity dt(v), projects X onto row v (fixed point).
Observation rollingObservation(const StereoCamera& cam, double readout, const Eigen::Vector3d& omega,
                               const Eigen::Vector3d& velocity, const Eigen::Vector3d& X)
{
  double v = cam.projectLeft(X).y();
  Observation o{0, 0, 0};
  for (int it = 0; it < 50; ++it)
  {
    const double dt = (v / (cam.height - 1) - 0.5) * readout;
    const Eigen::Vector3d a = omega * dt;
    const Eigen::Matrix3d R = Eigen::AngleAxisd(a.norm(), a.norm() > 0 ? a.normalized() : Eigen::Vector3d::UnitX())
                                  .toRotationMatrix();
    const Eigen::Vector3d Xr = R.transpose() * (X - velocity * dt);
    const Eigen::Vector2d p = cam.projectLeft(Xr);
    o = Observation{p.x(), p.y(), p.x() - cam.projectRightU(Xr)};
    v = p.y();
  }
  return o;
}
}  // namespace

TEST(RollingShutter, MovesEachObservationToTheStampExactly)
{
  const StereoCamera cam = test::makeCamera();
  const double readout = 0.033;
  // a head turning at 60 deg/s while walking at 1.4 m/s
  const Eigen::Vector3d omega = Eigen::Vector3d(0.2, 1.0, 0.1).normalized() * (60.0 * M_PI / 180.0);
  const Eigen::Vector3d velocity(0.1, 0.05, 1.4);
  const RollingShutter rs(cam, readout, omega, velocity);
  ASSERT_TRUE(rs.active());
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> ux(-3, 3), uy(-2, 2), uz(1.0, 8.0);
  double moved_max = 0, err_max = 0, disp_err_max = 0;
  int n = 0;
  while (n < 200)
  {
    const Eigen::Vector3d X(ux(rng), uy(rng), uz(rng));
    const Eigen::Vector2d g = cam.projectLeft(X);
    if (g.x() < 0 || g.y() < 0 || g.x() >= cam.width || g.y() >= cam.height)
      continue;
    ++n;
    const Observation o = rollingObservation(cam, readout, omega, velocity, X);
    moved_max = std::max(moved_max, std::hypot(o.u - g.x(), o.v - g.y()));
    double u = o.u, v = o.v, d = o.d;
    rs.undo(u, v, d);
    err_max = std::max(err_max, std::hypot(u - g.x(), v - g.y()));
    disp_err_max = std::max(disp_err_max, std::abs(d - (g.x() - cam.projectRightU(X))));
  }
  EXPECT_GT(moved_max, 5.0);  // the shutter bent the image by pixels
  EXPECT_LT(err_max, 1e-6);
  EXPECT_LT(disp_err_max, 1e-6);
}

TEST(RollingShutter, WithoutDisparityTheRotationAloneIsUndone)
{
  const StereoCamera cam = test::makeCamera();
  const Eigen::Vector3d omega(0.0, 1.2, 0.3);  // rad/s
  const RollingShutter turning(cam, 0.03, omega, Eigen::Vector3d::Zero());
  const Observation o = rollingObservation(cam, 0.03, omega, Eigen::Vector3d::Zero(), Eigen::Vector3d(1.0, -1.2, 4.0));
  double u = o.u, v = o.v, d = -1.0;
  turning.undo(u, v, d);
  const Eigen::Vector2d g = cam.projectLeft(Eigen::Vector3d(1.0, -1.2, 4.0));
  EXPECT_GT(std::hypot(o.u - g.x(), o.v - g.y()), 3.0);
  EXPECT_LT(std::hypot(u - g.x(), v - g.y()), 1e-6);
  EXPECT_EQ(d, -1.0);
  // the middle row is exposed at the stamp: nothing moves there
  EXPECT_NEAR(turning.rowTime((cam.height - 1) / 2.0), 0.0, 1e-12);
  EXPECT_NEAR(turning.rowTime(0), -0.015, 1e-12);
}

TEST(RollingShutter, GlobalShutterOrNoMotionLeavesObservations)
{
  const StereoCamera cam = test::makeCamera();
  for (const RollingShutter& rs : {RollingShutter(), RollingShutter(cam, 0.0, Eigen::Vector3d(0, 1, 0), Eigen::Vector3d::Zero()),
                                   RollingShutter(cam, 0.03, Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero()),
                                   RollingShutter(cam, 0.03, Eigen::Vector3d(NAN, 0, 0), Eigen::Vector3d::Zero())})
  {
    EXPECT_FALSE(rs.active());
    double u = 12.5, v = 400.25, d = 7.0;
    rs.undo(u, v, d);
    EXPECT_EQ(u, 12.5);
    EXPECT_EQ(v, 400.25);
    EXPECT_EQ(d, 7.0);
  }
}
