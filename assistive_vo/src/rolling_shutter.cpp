#include "assistive_vo/rolling_shutter.h"
#include <Eigen/Geometry>

namespace assistive_vo
{
RollingShutter::RollingShutter(const StereoCamera& cam, double readout_s, const Eigen::Vector3d& omega_opt,
                               const Eigen::Vector3d& velocity_opt)
  : cam_(cam), readout_s_(readout_s), omega_(omega_opt), velocity_(velocity_opt)
{
  active_ = readout_s > 0 && cam.valid() && cam.height > 1 && omega_opt.allFinite() && velocity_opt.allFinite() &&
            (omega_opt.squaredNorm() > 0 || velocity_opt.squaredNorm() > 0);
}

double RollingShutter::rowTime(double v) const
{
  return (v / (cam_.height - 1) - 0.5) * readout_s_;
}

void RollingShutter::undo(double& u, double& v, double& d) const
{
  if (!active_)
    return;
  const double dt = rowTime(v);
  // The row's camera is the stamp's turned by exp(omega dt) and moved by velocity dt (body axes):
  // a point X_row in its axes is R X_row + velocity dt in the stamp's.
  const Eigen::Vector3d a = omega_ * dt;
  const Eigen::Matrix3d R =
      a.norm() > 1e-12 ? Eigen::AngleAxisd(a.norm(), a.normalized()).toRotationMatrix() : Eigen::Matrix3d::Identity();
  if (d > 0)
  {
    const Eigen::Vector3d X = R * cam_.triangulate(u, v, d) + velocity_ * dt;
    if (X.z() <= 1e-6)
      return;
    const Eigen::Vector2d p = cam_.projectLeft(X);
    u = p.x();
    v = p.y();
    d = p.x() - cam_.projectRightU(X);
    return;
  }
  const Eigen::Vector3d b = R * Eigen::Vector3d((u - cam_.cx) / cam_.fx, (v - cam_.cy) / cam_.fy, 1.0);
  if (b.z() <= 1e-6)
    return;
  u = cam_.fx * b.x() / b.z() + cam_.cx;
  v = cam_.fy * b.y() / b.z() + cam_.cy;
}
}  // namespace assistive_vo
