#include <assistive_obstacles/mover_tracker.h>

#include <algorithm>
#include <tuple>

#include <Eigen/Dense>

namespace assistive_obstacles
{
void MoverTracker::predict(MoverTrack& tr, double dt, double accel_sigma)
{
  if (!(dt > 0.0)) return;
  Eigen::Matrix4d F = Eigen::Matrix4d::Identity();
  F(0, 2) = F(1, 3) = dt;
  // Discrete white-acceleration noise per axis: q * [dt^4/4 dt^3/2; dt^3/2 dt^2].
  const double q = accel_sigma * accel_sigma;
  Eigen::Matrix4d Q = Eigen::Matrix4d::Zero();
  for (int a = 0; a < 2; ++a)
  {
    Q(a, a) = q * dt * dt * dt * dt / 4.0;
    Q(a, a + 2) = Q(a + 2, a) = q * dt * dt * dt / 2.0;
    Q(a + 2, a + 2) = q * dt * dt;
  }
  tr.x = F * tr.x;
  tr.P = F * tr.P * F.transpose() + Q;
}

void MoverTracker::correct(MoverTrack& tr, const Eigen::Vector2d& z, double meas_sigma)
{
  Eigen::Matrix<double, 2, 4> H = Eigen::Matrix<double, 2, 4>::Zero();
  H(0, 0) = H(1, 1) = 1.0;
  const Eigen::Matrix2d S = H * tr.P * H.transpose() + meas_sigma * meas_sigma * Eigen::Matrix2d::Identity();
  const Eigen::Matrix<double, 4, 2> K = tr.P * H.transpose() * S.inverse();
  tr.x += K * (z - H * tr.x);
  // Joseph form: stays symmetric and positive definite.
  const Eigen::Matrix4d IKH = Eigen::Matrix4d::Identity() - K * H;
  tr.P = IKH * tr.P * IKH.transpose() + K * (meas_sigma * meas_sigma) * K.transpose();
  tr.P = 0.5 * (tr.P + tr.P.transpose());
}

double MoverTracker::mahalanobis2(const MoverTrack& tr, const Eigen::Vector2d& z, double meas_sigma)
{
  const Eigen::Matrix2d S = tr.P.topLeftCorner<2, 2>() + meas_sigma * meas_sigma * Eigen::Matrix2d::Identity();
  const Eigen::Vector2d y = z - tr.x.head<2>();
  return y.dot(S.ldlt().solve(y));
}

void MoverTracker::reset()
{
  tracks_.clear();
  next_id_ = 1;
  started_ = false;
  last_t_ = 0.0;
}

std::vector<MoverTrack> MoverTracker::confirmed() const
{
  std::vector<MoverTrack> out;
  for (const MoverTrack& t : tracks_)
    if (t.confirmed) out.push_back(t);
  return out;
}

const MoverTrack* MoverTracker::find(int id) const
{
  for (const MoverTrack& t : tracks_)
    if (t.id == id) return &t;
  return nullptr;
}

std::vector<int> MoverTracker::update(double t, const std::vector<Eigen::Vector2d>& detections)
{
  const double dt = started_ ? std::max(0.0, t - last_t_) : 0.0;
  started_ = true;
  last_t_ = std::max(last_t_, t);
  for (MoverTrack& tr : tracks_) predict(tr, dt, params_.accel_sigma);

  // Gated pairs, confirmed tracks first, then by distance (ties by index: deterministic).
  const double gate2 = params_.gate * params_.gate;
  std::vector<std::tuple<int, double, size_t, size_t>> pairs;  // (tentative?, d2, track, detection)
  for (size_t i = 0; i < tracks_.size(); ++i)
    for (size_t j = 0; j < detections.size(); ++j)
    {
      if (!detections[j].allFinite()) continue;
      const double d2 = mahalanobis2(tracks_[i], detections[j], params_.meas_sigma);
      if (d2 <= gate2) pairs.emplace_back(tracks_[i].confirmed ? 0 : 1, d2, i, j);
    }
  std::sort(pairs.begin(), pairs.end());
  std::vector<int> assigned(detections.size(), 0);
  std::vector<char> track_used(tracks_.size(), 0), det_used(detections.size(), 0);
  for (const auto& pr : pairs)
  {
    const size_t i = std::get<2>(pr), j = std::get<3>(pr);
    if (track_used[i] || det_used[j]) continue;
    track_used[i] = det_used[j] = 1;
    MoverTrack& tr = tracks_[i];
    const Eigen::Vector2d& z = detections[j];
    const double since = t - tr.last_seen;
    if (tr.hits == 1 && since > 0.0)
    {
      // Two-point initialisation: v = (z2 - z1) / dt, with the covariance of that difference.
      const double r = params_.meas_sigma * params_.meas_sigma;
      tr.x << z, (z - tr.last_z) / since;
      tr.P.setZero();
      for (int a = 0; a < 2; ++a)
      {
        tr.P(a, a) = r;
        tr.P(a, a + 2) = tr.P(a + 2, a) = r / since;
        tr.P(a + 2, a + 2) = 2.0 * r / (since * since);
      }
    }
    else
      correct(tr, z, params_.meas_sigma);
    ++tr.hits;
    tr.misses = 0;
    tr.last_seen = t;
    tr.last_z = z;
    if (tr.hits >= params_.birth_hits) tr.confirmed = true;
    assigned[j] = tr.id;
  }

  // Misses: a tentative track ends at once, a confirmed one coasts until death_misses.
  std::vector<MoverTrack> kept;
  kept.reserve(tracks_.size() + detections.size());
  for (size_t i = 0; i < tracks_.size(); ++i)
  {
    MoverTrack& tr = tracks_[i];
    if (!track_used[i])
    {
      ++tr.misses;
      if (!tr.confirmed || tr.misses >= params_.death_misses) continue;
    }
    kept.push_back(tr);
  }
  // Births.
  for (size_t j = 0; j < detections.size(); ++j)
  {
    if (det_used[j] || !detections[j].allFinite()) continue;  // NaN / Inf: ignored (id 0)
    MoverTrack tr;
    tr.id = next_id_++;
    tr.x << detections[j], 0.0, 0.0;
    const double r = params_.meas_sigma * params_.meas_sigma, v = params_.init_speed_sigma * params_.init_speed_sigma;
    tr.P = Eigen::Vector4d(r, r, v, v).asDiagonal();
    tr.hits = 1;
    tr.confirmed = params_.birth_hits <= 1;
    tr.born = tr.last_seen = t;
    tr.last_z = detections[j];
    assigned[j] = tr.id;
    kept.push_back(tr);
  }
  tracks_.swap(kept);
  return assigned;
}

}  // namespace assistive_obstacles
