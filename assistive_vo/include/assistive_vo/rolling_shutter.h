#pragma once
// A rolling shutter exposes the rows one after another: row v at stamp + (v / (H - 1) - 0.5) *
// readout (the middle row at the stamp, as the simulator's and Kalibr's model). The head turns
// and walks meanwhile, so a 30 deg/s turn over a 33 ms readout bends the image by 9 px at 640 x
// 480: every geometric use of an observation (triangulation, the motion, the bundle adjustment)
// then sees a camera that is not rigid. RollingShutter moves an observation to where a global
// shutter at the stamp would have seen it, from the camera's rate and velocity at the stamp,
// first order in the readout. The two cameras of the pair read their rows together (one clock),
// so a stereo match stays on its row. ROS-free.
#include <Eigen/Core>
#include "assistive_vo/stereo_camera.h"

namespace assistive_vo
{
class RollingShutter
{
public:
  /// A global shutter: nothing moves.
  RollingShutter() = default;
  /// `readout_s` first -> last row; `omega_opt` the camera's rate (rad/s) and `velocity_opt` its
  /// velocity (m/s), both in its own optical axes at the stamp.
  RollingShutter(const StereoCamera& cam, double readout_s, const Eigen::Vector3d& omega_opt,
                 const Eigen::Vector3d& velocity_opt);
  bool active() const { return active_; }
  /// Exposure time of image row v against the stamp (s).
  double rowTime(double v) const;
  /// A left observation (u, v) with disparity `d` (<= 0: none) moved to the stamp: with a
  /// disparity the point is moved in 3D (rotation and translation) and projected into both
  /// cameras again, `d` becoming the new disparity; without one the rotation alone moves it.
  void undo(double& u, double& v, double& d) const;

private:
  StereoCamera cam_;
  double readout_s_ = 0.0;
  Eigen::Vector3d omega_ = Eigen::Vector3d::Zero(), velocity_ = Eigen::Vector3d::Zero();
  bool active_ = false;
};
}  // namespace assistive_vo
