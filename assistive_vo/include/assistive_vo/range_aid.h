#pragma once
// A forward ranger aiding an IMU coast (issue 34): a plain wall that blinds the camera is what the
// vest's ultrasonic ranger sees best. While the wearer walks at it, the range to it shortens by
// the walk along the ranger's axis, so the coast's position along that axis is measured: the
// larger part of a coast's error (the VO's scale error in the fitted velocity, a stop the fit
// cannot follow) lies along the walk, and the walk is along the axis. The range's rate, a mean over
// its window, is compared with the coast's mean velocity over the same window: their difference
// corrects the velocity, and an echo that does not close as the coast walks aids nothing. ROS-free.
#include <deque>
#include <Eigen/Core>
#include "assistive_vo/inertial_coasting.h"

namespace assistive_vo
{
struct RangeAidOptions
{
  double sigma_m = 0.02;          ///< a range's noise, m (an HC-SR04 class ranger: about 1 cm + 0.5 %)
  /// Error of reading the range's change as the walk along the axis (a surface at an angle, the
  /// head's small turns), as a fraction of the change; and of its rate as the speed along it.
  double model_rel = 0.08;
  double max_axis_change_deg = 10.0;  ///< the axis turned further from the anchor's: a new anchor
  double rate_window_s = 0.35;    ///< ranges fitted by a line (their rate: the window's mean)
  double max_range_age_s = 0.1;   ///< the newest range at most this old (carried to the frame on the rate)
  int rate_min_ranges = 5;        ///< ... at least this many (20 Hz: 7 in the window)
  double max_fit_rms_m = 0.04;    ///< ... scattered less than this about the line (one surface)
  double gate_sigmas = 3.0;       ///< an innovation beyond this many sigmas: another surface, re-anchored
  /// A ranger hears surfaces up to about this far from facing it (a specular echo): turning the
  /// axis by d_psi changes the range to such a surface by up to r tan(40 deg) d_psi, walked or not.
  /// The head's scan (+-8 deg, up to 7 deg/s) turns the ranger: that much is added to the noise of
  /// the range's change (the turn since the anchor) and of its rate (the turn rate over the window).
  double max_incidence_deg = 40.0;
};

class RangeAid
{
public:
  using Options = RangeAidOptions;
  explicit RangeAid(const Options& o = Options()) : o_(o) {}
  void setOptions(const Options& o) { o_ = o; }
  /// A range (m, finite and within the ranger's limits) at `stamp` (s), stamp order.
  void addRange(double stamp, double range);
  /// Forgets the anchor and the velocity corrected (a coast starts); the ranges stay.
  void resetAnchor()
  {
    anchored_ = false;
    dv_total_.setZero();
  }
  /// Forgets everything (a time jump).
  void clear();

  struct Step
  {
    bool aided = false;
    Eigen::Vector3d dpos = Eigen::Vector3d::Zero();  ///< position correction (odom), to add
    Eigen::Vector3d dv = Eigen::Vector3d::Zero();    ///< velocity correction (odom), to add
    /// The coasted position's variance on its worst axis after the correction (m^2): what the trust
    /// rule compares with imu_coast_max_sigma^2 instead of InertialCoaster::positionVariance.
    double gate_var = 0.0;
  };
  /// One coasted frame at `stamp`, after `coast.step` moved the pose by `dpos` (odom): `axis_odom`
  /// the ranger's axis in odom (unit; its horizontal part is what the range measures on an upright
  /// surface). Anchors at the first frame with a range line, then corrects along the axis.
  Step step(double stamp, const Eigen::Vector3d& axis_odom, const Eigen::Vector3d& dpos, const InertialCoaster& coast);

private:
  /// The range at `stamp` (the newest reading carried on the rate) and the rate (the line fitted to
  /// the window: its mean over it), with their variances; false without a line.
  bool rangeAt(double stamp, double& r, double& r_var, double& rate, double& rate_var) const;
  /// The coast's horizontal position covariance (odom x, y) after `tau` s; `iso_out`: its isotropic
  /// part per axis (InertialCoaster::positionVarianceSplit).
  Eigen::Matrix2d covariance(const InertialCoaster& c, double tau, double* iso_out = nullptr) const;

  Options o_;
  std::deque<std::pair<double, double>> ranges_;
  bool anchored_ = false;
  double r_a_ = 0.0, r_a_var_ = 0.0, tau_a_ = 0.0;
  Eigen::Vector2d u_a_ = Eigen::Vector2d::Zero();
  struct Sample
  {
    double t;
    Eigen::Vector2d axis, v;  ///< the axis (unit) and the coasted velocity (odom) at a frame
  };
  std::deque<Sample> track_;  ///< the last frames within the rate window
  double d_ = 0.0;  ///< the coast's displacement along u_a_ since the anchor, without the position corrections
  Eigen::Vector2d dp_total_ = Eigen::Vector2d::Zero();  ///< position corrected since the anchor
  Eigen::Vector2d dv_total_ = Eigen::Vector2d::Zero();  ///< velocity corrected so far in this coast
};
}  // namespace assistive_vo
