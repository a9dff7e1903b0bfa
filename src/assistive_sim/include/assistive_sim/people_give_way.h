#pragma once
// People who give way to the wearer (issue 37): the scripted people of a world walk their scripts
// and, like real walkers, step aside when they are about to pass too close to someone. ROS-free.
//
// The model (src/assistive_sim/README.md, "People who give way"): walkers adapt only when the
// minimal predicted distance (MPD: how close the two would pass if both kept their velocities) is
// under about 1 m, and then raise it before the crossing (Olivier, Marin, Cretual & Pettre 2012,
// Gait & Posture 36:399-404). A walker avoiding a non-reactive one (the blind wearer is one, as is
// a wearer standing still) adjusts its path (Huber et al. 2014, PLoS ONE 9(2):e89589). Here the
// person leaves its path sideways, towards the side it would already pass on, at its walking speed
// times sin(`deviation_deg`), until the MPD is back over `mpd_m`, and returns to its path once the
// wearer is behind it (and the return does not bring the MPD under it again). One about to walk
// into the wearer (closing, its body within `stop_gap_m` of the wearer's) stands and waits while
// it steps aside, as walkers who cannot pass in front slow down (Huber et al.: speed and path
// adjustments at 45-90 deg crossings). Standing people do not move. The deviation's size and the
// stop's gap are chosen, not sourced (see the README).
#include <vector>

#include <Eigen/Core>

#include <assistive_sim/world.h>

namespace assistive_sim
{
struct GiveWayParams
{
  double mpd_m = 1.0;          ///< m, centre to centre: adapt under this (Olivier et al. 2012)
  double horizon_s = 4.0;      ///< s: a closest approach further ahead than this is not acted on yet
  double deviation_deg = 20.0; ///< deg off its path while stepping aside or back (chosen)
  double max_offset_m = 1.2;   ///< m beside its path at most
  double min_speed = 0.2;      ///< m/s: slower people count as standing and do not move
  double stop_gap_m = 0.3;     ///< m between the bodies: closing within this, the person stands (chosen)
  double wearer_radius_m = 0.25;  ///< m, the wearer's body as people judge it
};

/// Attaches a give-way track to every person of a world (copies of the world's people share it:
/// the collider's, the planner's truth) and moves the people aside as the wearer walks.
class PeopleGiveWay
{
public:
  /// Fresh tracks for every person of `world` (replacing any it had).
  PeopleGiveWay(World& world, const GiveWayParams& p = GiveWayParams());
  /// The wearer at `xy` moving at `velocity` (m/s) at time `t`: each person's offset from `t` to
  /// `t + dt`. Call once per step, in time order.
  void step(double t, double dt, const Eigen::Vector2d& xy, const Eigen::Vector2d& velocity);
  /// Times a person left its path to step aside (for the trial's summary).
  int episodes() const { return episodes_; }
  /// The minimal predicted distance between a person at `p` moving at `v` and the wearer at `w`
  /// moving at `u`, and the time to it (s, >= 0) in `tau`.
  static double minimalPredictedDistance(const Eigen::Vector2d& p, const Eigen::Vector2d& v, const Eigen::Vector2d& w,
                                         const Eigen::Vector2d& u, double* tau = nullptr);

private:
  World& world_;
  GiveWayParams p_;
  int episodes_ = 0;
};

}  // namespace assistive_sim
