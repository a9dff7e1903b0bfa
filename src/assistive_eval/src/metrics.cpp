#include <assistive_eval/metrics.h>

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <sstream>

namespace assistive_eval
{
namespace
{
constexpr double RAD2DEG = 180.0 / M_PI;

double rotationAngle(const Eigen::Matrix3d& R)
{
  const double c = std::max(-1.0, std::min(1.0, 0.5 * (R.trace() - 1.0)));
  return std::acos(c);
}

Eigen::Isometry3d relativeError(const Trajectory& gt, const Trajectory& est, size_t i, size_t j)
{
  const Eigen::Isometry3d dq = gt[i].pose.inverse() * gt[j].pose;
  const Eigen::Isometry3d dp = est[i].pose.inverse() * est[j].pose;
  return dq.inverse() * dp;
}

double wrapPi(double a)
{
  while (a > M_PI)
    a -= 2.0 * M_PI;
  while (a < -M_PI)
    a += 2.0 * M_PI;
  return a;
}
}  // namespace

ErrorStats computeStats(const std::vector<double>& e)
{
  ErrorStats s;
  s.n = e.size();
  if (e.empty())
    return s;
  double sum = 0.0, sse = 0.0;
  for (double v : e)
  {
    sum += v;
    sse += v * v;
  }
  const double n = static_cast<double>(e.size());
  s.sse = sse;
  s.mean = sum / n;
  s.rmse = std::sqrt(sse / n);
  double var = 0.0;
  for (double v : e)
    var += (v - s.mean) * (v - s.mean);
  s.std = std::sqrt(var / n);
  std::vector<double> sorted = e;
  std::sort(sorted.begin(), sorted.end());
  s.min = sorted.front();
  s.max = sorted.back();
  const size_t m = sorted.size() / 2;
  s.median = (sorted.size() % 2) ? sorted[m] : 0.5 * (sorted[m - 1] + sorted[m]);
  return s;
}

std::vector<double> apeErrors(const Trajectory& gt, const Trajectory& est, AlignMode mode, Alignment* alignment_out)
{
  const size_t n = std::min(gt.size(), est.size());
  const Alignment a = computeAlignment(gt, est, mode);
  if (alignment_out)
    *alignment_out = a;
  const Eigen::Matrix3d R = a.transform.linear();
  std::vector<double> e(n);
  for (size_t i = 0; i < n; ++i)
  {
    const Eigen::Vector3d p = a.scale * (R * est[i].pose.translation()) + a.transform.translation();
    e[i] = (p - gt[i].pose.translation()).norm();
  }
  return e;
}

ErrorStats ape(const Trajectory& gt, const Trajectory& est, AlignMode mode, Alignment* alignment_out)
{
  return computeStats(apeErrors(gt, est, mode, alignment_out));
}

std::vector<double> rpeTranslationErrors(const Trajectory& gt, const Trajectory& est, double delta_m)
{
  const size_t n = std::min(gt.size(), est.size());
  std::vector<size_t> ids;
  double path = 0.0;
  for (size_t i = 0; i < n; ++i)
  {
    if (i > 0)
      path += (est[i].pose.translation() - est[i - 1].pose.translation()).norm();
    if (path >= delta_m)
    {
      ids.push_back(i);
      path = 0.0;
    }
  }
  std::vector<double> e;
  for (size_t k = 1; k < ids.size(); ++k)
    e.push_back(relativeError(gt, est, ids[k - 1], ids[k]).translation().norm());
  return e;
}

DriftResult segmentDrift(const Trajectory& gt, const Trajectory& est, const std::vector<double>& lengths_m, size_t step,
                         const Eigen::Vector3d& up)
{
  const Eigen::Vector3d u = up.normalized();
  DriftResult r;
  const size_t n = std::min(gt.size(), est.size());
  if (n < 2 || step == 0)
    return r;
  Trajectory g(gt.begin(), gt.begin() + static_cast<std::ptrdiff_t>(n));
  const std::vector<double> dist = pathDistances(g);
  double t_all = 0.0, r_all = 0.0, yaw_all = 0.0, tilt_all = 0.0;
  for (double L : lengths_m)
  {
    if (!(L > 0.0))
      continue;
    SegmentDrift sd;
    sd.length_m = L;
    double t_sum = 0.0, r_sum = 0.0;
    size_t j = 0;
    for (size_t i = 0; i < n; i += step)
    {
      j = std::max(j, i + 1);
      while (j < n && dist[j] - dist[i] < L)
        ++j;
      if (j >= n)
        break;
      const double d = dist[j] - dist[i];
      const Eigen::Isometry3d E = relativeError(gt, est, i, j);
      t_sum += E.translation().norm() / d;
      r_sum += rotationAngle(E.linear()) * RAD2DEG / d;
      // the error rotation as a vector in world axes (E is in gt frame j), split about `up`
      const Eigen::AngleAxisd aa(E.linear());
      const Eigen::Vector3d w = g[j].pose.linear() * (aa.angle() * aa.axis());
      const double wz = w.dot(u);
      yaw_all += std::abs(wz) * RAD2DEG / d;
      tilt_all += (w - wz * u).norm() * RAD2DEG / d;
      ++sd.segments;
    }
    if (sd.segments == 0)
      continue;
    sd.t_err_pct = 100.0 * t_sum / static_cast<double>(sd.segments);
    sd.r_err_deg_per_m = r_sum / static_cast<double>(sd.segments);
    t_all += 100.0 * t_sum;
    r_all += r_sum;
    r.segments += sd.segments;
    r.per_length.push_back(sd);
  }
  if (r.segments > 0)
  {
    r.drift_pct = t_all / static_cast<double>(r.segments);
    r.drift_deg_per_m = r_all / static_cast<double>(r.segments);
    r.drift_deg_per_m_yaw = yaw_all / static_cast<double>(r.segments);
    r.drift_deg_per_m_tilt = tilt_all / static_cast<double>(r.segments);
  }
  return r;
}

std::vector<double> tiltErrorsDeg(const Trajectory& gt, const Trajectory& est, const Eigen::Vector3d& up)
{
  const Eigen::Vector3d u = up.normalized();
  std::vector<double> e;
  const size_t n = std::min(gt.size(), est.size());
  e.reserve(n);
  for (size_t i = 0; i < n; ++i)
  {
    const double c = (gt[i].pose.linear().transpose() * u).dot(est[i].pose.linear().transpose() * u);
    e.push_back(std::acos(std::clamp(c, -1.0, 1.0)) * RAD2DEG);
  }
  return e;
}

Trajectory gyroOnlyTrajectory(const Trajectory& gt, const std::vector<Eigen::Matrix3d>& rel, Eigen::Vector3d* bias_out)
{
  const size_t n = gt.size();
  if (n < 2 || rel.size() != n)
    return {};
  std::vector<double> b[3];
  for (size_t i = 1; i < n; ++i)
  {
    const double dt = gt[i].t - gt[i - 1].t;
    if (!(dt > 0.0))
      return {};
    const Eigen::AngleAxisd aa(rel[i].transpose() * (gt[i - 1].pose.linear().transpose() * gt[i].pose.linear()));
    const Eigen::Vector3d w = -aa.angle() * aa.axis() / dt;
    for (int k = 0; k < 3; ++k)
      b[k].push_back(w[k]);
  }
  Eigen::Vector3d bias;
  for (int k = 0; k < 3; ++k)
  {
    std::nth_element(b[k].begin(), b[k].begin() + static_cast<std::ptrdiff_t>(b[k].size() / 2), b[k].end());
    bias[k] = b[k][b[k].size() / 2];
  }
  if (bias_out)
    *bias_out = bias;
  Trajectory out(gt);
  Eigen::Matrix3d R = gt[0].pose.linear();
  for (size_t i = 1; i < n; ++i)
  {
    const Eigen::Vector3d bdt = bias * (gt[i].t - gt[i - 1].t);
    const Eigen::Matrix3d corr =
        bdt.norm() > 0.0 ? Eigen::AngleAxisd(-bdt.norm(), bdt.normalized()).toRotationMatrix() : Eigen::Matrix3d::Identity();
    R = R * rel[i] * corr;
    // re-orthonormalise (long chains of products drift off SO(3) at 1e-16 per step)
    R = Eigen::Quaterniond(R).normalized().toRotationMatrix();
    out[i].pose.linear() = R;
  }
  return out;
}

double endpointDriftPct(const Trajectory& gt, const Trajectory& est)
{
  const size_t n = std::min(gt.size(), est.size());
  if (n < 2)
    return std::numeric_limits<double>::quiet_NaN();
  Trajectory g(gt.begin(), gt.begin() + static_cast<std::ptrdiff_t>(n));
  const double len = pathLength(g);
  if (!(len > 0.0))
    return std::numeric_limits<double>::quiet_NaN();
  const Eigen::Isometry3d T = gt[0].pose * est[0].pose.inverse();
  const Eigen::Vector3d p = T * est[n - 1].pose.translation();
  return 100.0 * (p - gt[n - 1].pose.translation()).norm() / len;
}

double maxErrorJump(const Trajectory& gt, const Trajectory& est)
{
  const size_t n = std::min(gt.size(), est.size());
  if (n < 2)
    return std::numeric_limits<double>::quiet_NaN();
  const Eigen::Isometry3d T = gt[0].pose * est[0].pose.inverse();
  double best = 0.0;
  Eigen::Vector3d prev = Eigen::Vector3d::Zero();
  for (size_t i = 0; i < n; ++i)
  {
    const Eigen::Vector3d e = T * est[i].pose.translation() - gt[i].pose.translation();
    if (i > 0)
      best = std::max(best, (e - prev).norm());
    prev = e;
  }
  return best;
}

double headingDeg(const Eigen::Isometry3d& pose, const YawBandParams& p)
{
  const Eigen::Vector3d up = p.up.normalized();
  Eigen::Vector3d e1 = up.unitOrthogonal();
  const Eigen::Vector3d e2 = up.cross(e1);
  const Eigen::Vector3d f = pose.linear() * p.forward.normalized();
  return std::atan2(f.dot(e2), f.dot(e1)) * RAD2DEG;
}

std::vector<YawBand> yawErrorByBand(const Trajectory& gt, const Trajectory& est, const YawBandParams& p)
{
  std::vector<YawBand> bands;
  double lo = 0.0;
  for (size_t k = 0; k <= p.edges_deg_s.size(); ++k)
  {
    YawBand b;
    b.lo_deg_s = lo;
    b.hi_deg_s = k < p.edges_deg_s.size() ? p.edges_deg_s[k] : std::numeric_limits<double>::infinity();
    std::ostringstream name;
    if (k == 0)
      name << "lt" << b.hi_deg_s;
    else if (k == p.edges_deg_s.size())
      name << "gt" << b.lo_deg_s;
    else
      name << b.lo_deg_s << "_" << b.hi_deg_s;
    b.name = name.str();
    lo = b.hi_deg_s;
    bands.push_back(b);
  }
  const size_t n = std::min(gt.size(), est.size());
  std::vector<double> sum_err(bands.size(), 0.0), sum_sq(bands.size(), 0.0), max_err(bands.size(), 0.0),
      time(bands.size(), 0.0);
  for (size_t i = 1; i < n; ++i)
  {
    const double dt = gt[i].t - gt[i - 1].t;
    if (!(dt > 0.0))
      continue;
    const double dg = wrapPi((headingDeg(gt[i].pose, p) - headingDeg(gt[i - 1].pose, p)) / RAD2DEG) * RAD2DEG;
    const double de = wrapPi((headingDeg(est[i].pose, p) - headingDeg(est[i - 1].pose, p)) / RAD2DEG) * RAD2DEG;
    const double rate = std::abs(dg) / dt;
    size_t k = 0;
    while (k + 1 < bands.size() && rate >= bands[k].hi_deg_s)
      ++k;
    const double err = std::abs(wrapPi((de - dg) / RAD2DEG)) * RAD2DEG;
    bands[k].pairs++;
    bands[k].true_rotation_deg += std::abs(dg);
    sum_err[k] += err;
    sum_sq[k] += err * err;
    max_err[k] = std::max(max_err[k], err);
    time[k] += dt;
  }
  for (size_t k = 0; k < bands.size(); ++k)
  {
    YawBand& b = bands[k];
    if (b.pairs == 0)
      continue;
    b.mean_err_deg = sum_err[k] / static_cast<double>(b.pairs);
    b.rms_err_deg = std::sqrt(sum_sq[k] / static_cast<double>(b.pairs));
    b.max_err_deg = max_err[k];
    if (b.true_rotation_deg > 0.0)
      b.err_pct_of_rotation = 100.0 * sum_err[k] / b.true_rotation_deg;
    b.err_deg_per_s = sum_err[k] / time[k];
  }
  return bands;
}

TrajectoryReport evaluateTrajectory(const Trajectory& gt, const Trajectory& est, const TrajectoryEvalParams& p)
{
  TrajectoryReport r;
  const size_t n = std::min(gt.size(), est.size());
  const Trajectory g(gt.begin(), gt.begin() + static_cast<std::ptrdiff_t>(n));
  const Trajectory e(est.begin(), est.begin() + static_cast<std::ptrdiff_t>(n));
  r.poses = n;
  r.path_length_m = pathLength(g);
  r.ate = ape(g, e, p.ate_align, &r.alignment);
  r.rpe = computeStats(rpeTranslationErrors(g, e, p.rpe_delta_m));
  r.drift = segmentDrift(g, e, p.drift_lengths_m, 1, p.yaw.up);
  r.endpoint_drift_pct = endpointDriftPct(g, e);
  r.max_jump_m = maxErrorJump(g, e);
  r.tilt_deg = computeStats(tiltErrorsDeg(g, e, p.yaw.up));
  // yaw about the truth's up axis: the estimate brought into the truth's world first
  r.yaw_bands = yawErrorByBand(g, applyAlignment(e, r.alignment), p.yaw);
  return r;
}

std::string reportTable(const TrajectoryReport& r)
{
  std::ostringstream os;
  os << std::fixed << std::setprecision(6);
  os << "poses                 " << r.poses << "\n";
  os << "path length           " << r.path_length_m << " m\n";
  os << "ATE (APE translation) n=" << r.ate.n << "  rmse " << r.ate.rmse << "  mean " << r.ate.mean << "  median "
     << r.ate.median << "  std " << r.ate.std << "  min " << r.ate.min << "  max " << r.ate.max << " m"
     << (r.alignment.scale != 1.0 ? "  (scale " + std::to_string(r.alignment.scale) + ")" : std::string()) << "\n";
  os << "RPE (consecutive)     n=" << r.rpe.n << "  rmse " << r.rpe.rmse << "  mean " << r.rpe.mean << "  median "
     << r.rpe.median << "  max " << r.rpe.max << " m\n";
  os << "segment drift         ";
  for (const auto& s : r.drift.per_length)
    os << s.length_m << " m: " << s.t_err_pct << " % " << s.r_err_deg_per_m << " deg/m (n=" << s.segments << ")  ";
  os << "\n";
  os << "drift (all segments)  " << r.drift.drift_pct << " %  " << r.drift.drift_deg_per_m << " deg/m\n";
  os << "end-point drift       " << r.endpoint_drift_pct << " % of distance\n";
  os << "max error jump        " << r.max_jump_m << " m\n";
  os << "tilt vs gravity       mean " << r.tilt_deg.mean << "  max " << r.tilt_deg.max
     << " deg (no alignment; meaningful when both worlds are z-up)\n";
  os << "yaw band (deg/s)   pairs  true_rot_deg  mean_err_deg  rms_err_deg  err_%_of_rot\n";
  for (const auto& b : r.yaw_bands)
    os << "  " << std::left << std::setw(16) << b.name << std::right << std::setw(6) << b.pairs << std::setw(14)
       << b.true_rotation_deg << std::setw(14) << b.mean_err_deg << std::setw(13) << b.rms_err_deg << std::setw(14)
       << b.err_pct_of_rotation << "\n";
  return os.str();
}

std::string reportJson(const TrajectoryReport& r)
{
  std::ostringstream os;
  os << "{\"frames\": " << r.poses << ", \"path_length_m\": " << jsonNumber(r.path_length_m)
     << ", \"ate_rmse_m\": " << jsonNumber(r.ate.rmse) << ", \"ate_mean_m\": " << jsonNumber(r.ate.mean)
     << ", \"ate_median_m\": " << jsonNumber(r.ate.median) << ", \"ate_max_m\": " << jsonNumber(r.ate.max)
     << ", \"rpe_pairs\": " << r.rpe.n << ", \"rpe_rmse_m\": " << jsonNumber(r.rpe.rmse)
     << ", \"drift_pct\": " << jsonNumber(r.drift.drift_pct)
     << ", \"drift_deg_per_m\": " << jsonNumber(r.drift.drift_deg_per_m)
     << ", \"endpoint_drift_pct\": " << jsonNumber(r.endpoint_drift_pct)
     << ", \"max_jump_m\": " << jsonNumber(r.max_jump_m) << ", \"tilt_err_deg_mean\": " << jsonNumber(r.tilt_deg.mean)
     << ", \"tilt_err_deg_max\": " << jsonNumber(r.tilt_deg.max);
  for (const auto& b : r.yaw_bands)
    os << ", \"yaw_err_deg_" << b.name << "\": " << jsonNumber(b.mean_err_deg);
  os << "}";
  return os.str();
}

}  // namespace assistive_eval
