#pragma once
// Trajectory error metrics: APE/ATE, evo-style RPE, KITTI-devkit-style segment drift, end-point
// drift, largest single-frame error jump, yaw error per head-rotation speed band.
// Inputs are index-aligned (see match()): gt[i] and est[i] are the same instant, same body frame.
#include <assistive_eval/benchmark.h>  // jsonNumber() of reportJson()
#include <assistive_eval/trajectory.h>

#include <limits>
#include <string>
#include <vector>

namespace assistive_eval
{
/// Statistics of a set of errors, as evo/TUM report them (std = population std, median = numpy).
/// With no samples every figure is NaN and n == 0.
struct ErrorStats
{
  size_t n = 0;
  double rmse = std::numeric_limits<double>::quiet_NaN();
  double mean = std::numeric_limits<double>::quiet_NaN();
  double median = std::numeric_limits<double>::quiet_NaN();
  double std = std::numeric_limits<double>::quiet_NaN();
  double min = std::numeric_limits<double>::quiet_NaN();
  double max = std::numeric_limits<double>::quiet_NaN();
  double sse = std::numeric_limits<double>::quiet_NaN();
};
ErrorStats computeStats(const std::vector<double>& errors);

/// Translational APE: |p_gt - p_est_aligned| per pose, after `mode` alignment of est onto gt.
/// `alignment_out` (optional) receives the transform used.
std::vector<double> apeErrors(const Trajectory& gt, const Trajectory& est, AlignMode mode,
                              Alignment* alignment_out = nullptr);
ErrorStats ape(const Trajectory& gt, const Trajectory& est, AlignMode mode,
               Alignment* alignment_out = nullptr);

/// evo RPE, translation part, "consecutive pairs" by path length delta_m (evo_rpe --delta d
/// --delta_unit m): walk the ESTIMATE's positions, mark index i when the accumulated path is
/// >= delta_m and reset; pair consecutive marks (i, j); error = |trans((Q_i^-1 Q_j)^-1 (P_i^-1 P_j))|
/// with Q = gt, P = est. No alignment (RPE is invariant to it).
std::vector<double> rpeTranslationErrors(const Trajectory& gt, const Trajectory& est, double delta_m);

/// KITTI devkit style segment error for one segment length.
struct SegmentDrift
{
  double length_m = 0.0;
  size_t segments = 0;
  double t_err_pct = std::numeric_limits<double>::quiet_NaN();        ///< mean |t err| / length * 100
  double r_err_deg_per_m = std::numeric_limits<double>::quiet_NaN();  ///< mean rot err / length
};
struct DriftResult
{
  std::vector<SegmentDrift> per_length;  ///< lengths that had at least one segment
  size_t segments = 0;                   ///< over all lengths
  double drift_pct = std::numeric_limits<double>::quiet_NaN();        ///< mean over all segments
  double drift_deg_per_m = std::numeric_limits<double>::quiet_NaN();  ///< mean over all segments
  /// drift_deg_per_m split into the rotation error about the world's up axis (yaw) and about the
  /// horizontal axes (tilt: roll / pitch), each the mean over all segments: where rotation drift
  /// comes from (a gyro bounds both, gravity only tilt).
  double drift_deg_per_m_yaw = std::numeric_limits<double>::quiet_NaN();
  double drift_deg_per_m_tilt = std::numeric_limits<double>::quiet_NaN();
};
/// For every start frame (step `step`) and each length L: the end frame is the first frame with
/// gt path distance >= L from the start. Error pose E = (Q_i^-1 Q_j)^-1 (P_i^-1 P_j);
/// t_err = |trans(E)| / d, r_err = angle(E) / d with d the true path length of the segment
/// (>= L; so a pure k % scale error reads exactly k %). `up`: the world's up axis in gt's world
/// frame, for the yaw / tilt split of the rotation error.
DriftResult segmentDrift(const Trajectory& gt, const Trajectory& est, const std::vector<double>& lengths_m,
                         size_t step = 1, const Eigen::Vector3d& up = Eigen::Vector3d::UnitZ());

/// End-point drift: |p_est_end - p_gt_end| / true path length * 100, after FIRST_POSE alignment.
double endpointDriftPct(const Trajectory& gt, const Trajectory& est);

/// Largest change of the position error between consecutive frames (m), after FIRST_POSE
/// alignment: max_i |e_i - e_{i-1}|, e_i = p_est_i - p_gt_i.
double maxErrorJump(const Trajectory& gt, const Trajectory& est);

/// Yaw error per head-rotation speed band. Yaw is the heading of the body's `forward` axis
/// projected on the plane normal to the world's `up` axis. For every consecutive pair of frames
/// the true yaw rate |dyaw_gt| / dt picks the band; the error is |dyaw_est - dyaw_gt| (deg).
/// Both worlds must share the up axis (gravity-aligned); no alignment is needed.
struct YawBandParams
{
  std::vector<double> edges_deg_s{5.0, 20.0, 30.0};  ///< bands: <5, 5-20, 20-30, >30
  Eigen::Vector3d up{0.0, 0.0, 1.0};                 ///< world up (gt_world: z)
  Eigen::Vector3d forward{0.0, 0.0, 1.0};            ///< body forward (optical frame: z)
};
struct YawBand
{
  double lo_deg_s = 0.0, hi_deg_s = 0.0;  ///< hi = +inf for the last band
  std::string name;                       ///< "lt5", "5_20", "20_30", "gt30"
  size_t pairs = 0;
  double true_rotation_deg = 0.0;  ///< sum of |dyaw_gt|
  double mean_err_deg = std::numeric_limits<double>::quiet_NaN();  ///< per frame pair
  double rms_err_deg = std::numeric_limits<double>::quiet_NaN();
  double max_err_deg = std::numeric_limits<double>::quiet_NaN();
  double err_pct_of_rotation = std::numeric_limits<double>::quiet_NaN();  ///< sum err / sum rot * 100
  double err_deg_per_s = std::numeric_limits<double>::quiet_NaN();       ///< sum err / time in band
};
std::vector<YawBand> yawErrorByBand(const Trajectory& gt, const Trajectory& est,
                                    const YawBandParams& p = YawBandParams());
double headingDeg(const Eigen::Isometry3d& pose, const YawBandParams& p);

/// Tilt against gravity per frame, without any alignment: the angle (deg) between the up axis
/// seen from the body in gt's world and in est's world, acos((R_gt^T up) . (R_est^T up)). Both
/// worlds must be gravity-aligned with the same `up` (the odometry's odom frame and a simulated
/// bag's world): it is how far the estimate's floor is from level, which a segment metric cannot
/// show (it sees an absolute tilt only while it changes).
std::vector<double> tiltErrorsDeg(const Trajectory& gt, const Trajectory& est,
                                  const Eigen::Vector3d& up = Eigen::Vector3d::UnitZ());

/// What the gyro alone gives: `rel[i]` is the gyro's integrated rotation from frame i-1 to frame i
/// in gt's body frame (rel[0] unused). Each is corrected by the constant bias that fits the ground
/// truth best (per-axis median of log(rel_i^T dR_gt_i) / dt, so `bias_out` is the gyro's bias in the
/// body frame: rel ~ dR_gt exp(b dt)) and chained from the first true pose; positions are the true
/// ones. The rotational drift of this trajectory is the floor set by the gyro's angle random walk:
/// vision must beat the gyro over a segment to bring the drift below it. Empty when gt and rel do
/// not have the same size (>= 2) or a stamp step is not positive.
Trajectory gyroOnlyTrajectory(const Trajectory& gt, const std::vector<Eigen::Matrix3d>& rel,
                              Eigen::Vector3d* bias_out = nullptr);

/// Everything the stage benchmarks need in one call.
struct TrajectoryEvalParams
{
  AlignMode ate_align = AlignMode::SE3;
  std::vector<double> drift_lengths_m{1.0, 2.0, 5.0, 10.0};
  double rpe_delta_m = 10.0;
  YawBandParams yaw;
};
struct TrajectoryReport
{
  size_t poses = 0;
  double path_length_m = 0.0;
  ErrorStats ate;          ///< APE translation after p.ate_align
  Alignment alignment;     ///< used for the ATE
  ErrorStats rpe;          ///< evo consecutive pairs over p.rpe_delta_m
  DriftResult drift;       ///< segment drift (drift_pct / drift_deg_per_m)
  double endpoint_drift_pct = std::numeric_limits<double>::quiet_NaN();
  double max_jump_m = std::numeric_limits<double>::quiet_NaN();
  ErrorStats tilt_deg;             ///< tiltErrorsDeg about p.yaw.up (no alignment)
  std::vector<YawBand> yaw_bands;  ///< on the estimate aligned as for the ATE (p.ate_align)
};
TrajectoryReport evaluateTrajectory(const Trajectory& gt, const Trajectory& est,
                                    const TrajectoryEvalParams& p = TrajectoryEvalParams());

/// A readable table and a JSON object (no trailing newline) of a report; keys follow docs/design.md
/// (ate_rmse_m, drift_pct, drift_deg_per_m, max_jump_m, ...).
std::string reportTable(const TrajectoryReport& r);
std::string reportJson(const TrajectoryReport& r);

}  // namespace assistive_eval
