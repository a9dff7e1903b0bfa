#pragma once
// Tracks of movers on the ground plane (issue 22): one constant-velocity Kalman filter per track,
// state (x, y, vx, vy) in the world frame, white acceleration noise, position measurements (the
// mover detections' centroids). Association: gated greedy nearest neighbour by Mahalanobis
// distance (confirmed tracks first, then the smallest distance pairs first). A track is born from
// an unassociated detection; its second hit sets the velocity from the two positions (two-point
// initialisation: exact on a noise-free constant-velocity path); it is confirmed after birth_hits
// hits. A tentative track ends at its first miss, a confirmed one after death_misses consecutive
// misses (it coasts at constant velocity meanwhile). ROS-free; not wired into the nodelet yet.
#include <vector>

#include <Eigen/Core>

namespace assistive_obstacles
{
struct MoverTrackerParams
{
  double accel_sigma = 1.0;     ///< m/s^2, white acceleration noise (a walker starting, stopping, turning)
  double meas_sigma = 0.1;      ///< m, a detection's centroid error per axis
  double init_speed_sigma = 1.5;  ///< m/s, velocity sigma of a track born from one detection (walking speeds)
  double gate = 4.0;            ///< Mahalanobis distance beyond which a detection is not the track's (2 dof: 0.03 % of true detections fall outside)
  int birth_hits = 3;           ///< hits before a track is confirmed (reported)
  int death_misses = 8;         ///< consecutive misses that end a track (bridges short occlusions and the head's scan: 0.53 s at 15 Hz)
};

struct MoverTrack
{
  int id = 0;                                       ///< unique, from 1, never reused
  Eigen::Vector4d x = Eigen::Vector4d::Zero();      ///< x, y (m), vx, vy (m/s), world frame
  Eigen::Matrix4d P = Eigen::Matrix4d::Identity();  ///< covariance of x
  int hits = 0;                                     ///< detections associated, total
  int misses = 0;                                   ///< consecutive frames without a detection
  bool confirmed = false;                           ///< hits >= birth_hits (stays so until death)
  double born = 0.0, last_seen = 0.0;               ///< s
  Eigen::Vector2d last_z = Eigen::Vector2d::Zero(); ///< m, the last associated detection

  Eigen::Vector2d position() const { return x.head<2>(); }
  Eigen::Vector2d velocity() const { return x.tail<2>(); }
};

class MoverTracker
{
public:
  explicit MoverTracker(const MoverTrackerParams& p = MoverTrackerParams()) : params_(p) {}
  void setParams(const MoverTrackerParams& p) { params_ = p; }
  const MoverTrackerParams& params() const { return params_; }

  /// One frame at time `t` (s, increasing) with its detections' ground positions (world x, y):
  /// predict every track to t, associate, update, give birth and end tracks. Returns, per
  /// detection, the id of the track it went to (0: not finite, ignored).
  std::vector<int> update(double t, const std::vector<Eigen::Vector2d>& detections);
  /// Every live track (tentative ones included).
  const std::vector<MoverTrack>& tracks() const { return tracks_; }
  /// The confirmed tracks only (what is reported).
  std::vector<MoverTrack> confirmed() const;
  /// A live track by id (nullptr when it does not exist).
  const MoverTrack* find(int id) const;
  void reset();

  /// Kalman steps, public for the tests: constant-velocity prediction over dt with white
  /// acceleration noise, and a position update.
  static void predict(MoverTrack& tr, double dt, double accel_sigma);
  static void correct(MoverTrack& tr, const Eigen::Vector2d& z, double meas_sigma);
  /// Squared Mahalanobis distance of detection z from the track's predicted position.
  static double mahalanobis2(const MoverTrack& tr, const Eigen::Vector2d& z, double meas_sigma);

private:
  MoverTrackerParams params_;
  std::vector<MoverTrack> tracks_;
  int next_id_ = 1;
  double last_t_ = 0.0;
  bool started_ = false;
};

}  // namespace assistive_obstacles
