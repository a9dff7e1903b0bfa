#include <assistive_obstacles/people_score.h>

#include <algorithm>
#include <cmath>
#include <tuple>

#include <assistive_obstacles/cell_values.h>

namespace assistive_obstacles
{
PeopleFrameScore scorePeopleFrame(const std::vector<PersonState>& truth, const std::vector<PersonState>& tracks,
                                  const Eigen::Vector2d& wearer, const PeopleScoreParams& p)
{
  PeopleFrameScore s;
  const double reach = p.radius + p.gate;
  auto in = [&](const PersonState& q, double r) { return (q.position - wearer).norm() <= r; };
  std::vector<std::tuple<double, size_t, size_t>> pairs;  // (distance, truth, track)
  for (size_t i = 0; i < truth.size(); ++i)
  {
    if (!in(truth[i], reach)) continue;
    for (size_t j = 0; j < tracks.size(); ++j)
    {
      if (!in(tracks[j], reach)) continue;
      const double d = (truth[i].position - tracks[j].position).norm();
      if (d <= p.gate) pairs.emplace_back(d, i, j);
    }
  }
  std::sort(pairs.begin(), pairs.end());
  std::vector<int> truth_of(tracks.size(), -1), track_of(truth.size(), -1);
  for (const auto& pr : pairs)
  {
    const size_t i = std::get<1>(pr), j = std::get<2>(pr);
    if (track_of[i] >= 0 || truth_of[j] >= 0) continue;
    track_of[i] = static_cast<int>(j);
    truth_of[j] = static_cast<int>(i);
    s.track_to_truth[tracks[j].id] = truth[i].id;
  }
  for (size_t i = 0; i < truth.size(); ++i)
    if (in(truth[i], p.radius))
    {
      ++s.truth_in_range;
      if (track_of[i] >= 0) ++s.truth_matched;
    }
  for (size_t j = 0; j < tracks.size(); ++j)
    if (in(tracks[j], p.radius))
    {
      ++s.tracks_in_range;
      if (truth_of[j] < 0) continue;
      ++s.tracks_matched;
      if (tracks[j].age >= p.min_age)
      {
        s.velocity_err_sum += (tracks[j].velocity - truth[static_cast<size_t>(truth_of[j])].velocity).norm();
        ++s.velocity_n;
      }
    }
  return s;
}

bool heldByMap(const GridData& est, const PersonState& person)
{
  if (!(est.resolution > 0.0)) return false;
  const double reach = person.radius + est.resolution * std::sqrt(0.5);
  const int x0 = static_cast<int>(std::floor((person.position.x() - reach - est.origin_x) / est.resolution));
  const int y0 = static_cast<int>(std::floor((person.position.y() - reach - est.origin_y) / est.resolution));
  const int x1 = static_cast<int>(std::floor((person.position.x() + reach - est.origin_x) / est.resolution));
  const int y1 = static_cast<int>(std::floor((person.position.y() + reach - est.origin_y) / est.resolution));
  for (int ey = std::max(0, y0); ey <= std::min(est.height - 1, y1); ++ey)
    for (int ex = std::max(0, x0); ex <= std::min(est.width - 1, x1); ++ex)
    {
      const Eigen::Vector2d c(est.origin_x + (ex + 0.5) * est.resolution, est.origin_y + (ey + 0.5) * est.resolution);
      if ((c - person.position).norm() < reach && est.data[static_cast<size_t>(ey) * est.width + ex] == CELL_OBSTACLE)
        return true;
    }
  return false;
}

GhostCount countGhostCells(const GridData& truth, const GridData& est, const Eigen::Vector2d& wearer, double radius,
                           const std::vector<PersonState>& people)
{
  GhostCount g;
  const double r2 = radius * radius;
  for (int cy = 0; cy < truth.height; ++cy)
    for (int cx = 0; cx < truth.width; ++cx)
    {
      if (truth.data[static_cast<size_t>(cy) * truth.width + cx] != CELL_FREE) continue;
      const Eigen::Vector2d c(truth.origin_x + (cx + 0.5) * truth.resolution, truth.origin_y + (cy + 0.5) * truth.resolution);
      if ((c - wearer).squaredNorm() > r2) continue;
      // Under a person now: the cell's disc (half diagonal) overlaps the footprint.
      const double half_diag = truth.resolution * std::sqrt(0.5);
      bool under = false;
      for (const PersonState& q : people)
        under = under || (c - q.position).norm() < q.radius + half_diag;
      if (under) continue;
      const int ex = static_cast<int>(std::floor((c.x() - est.origin_x) / est.resolution));
      const int ey = static_cast<int>(std::floor((c.y() - est.origin_y) / est.resolution));
      if (ex < 0 || ey < 0 || ex >= est.width || ey >= est.height) continue;
      const int8_t e = est.data[static_cast<size_t>(ey) * est.width + ex];
      if (e == CELL_UNKNOWN) continue;
      ++g.free_known;
      if (e == CELL_OBSTACLE) ++g.ghost;
    }
  return g;
}

void CrossingScore::addFrame(double t, const Eigen::Vector2d& wearer, const std::vector<PersonState>& truth,
                             const std::set<int>& warned_tracks, const std::map<int, int>& track_to_truth)
{
  if (!started_) t_first_ = t;
  started_ = true;
  t_last_ = t;
  for (const PersonState& q : truth)
  {
    const double d = (q.position - wearer).norm();
    auto it = closest_.find(q.id);
    if (it == closest_.end() || d < it->second.d) closest_[q.id] = {d, t, q.velocity.norm()};
  }
  for (const auto& kv : track_to_truth) matched_at_[kv.second].push_back(t);
  for (const int id : warned_tracks)
  {
    const auto m = track_to_truth.find(id);
    const int who = m == track_to_truth.end() ? 0 : m->second;
    if (who) warned_at_[who].push_back(t);
    if (!warned_prev_.count(id)) onsets_.push_back({t, who});
  }
  warned_prev_ = warned_tracks;
}

void CrossingScore::addVisible(double t, const std::set<int>& truth_ids)
{
  for (const int id : truth_ids) visible_at_[id].push_back(t);
}

bool CrossingScore::visibleInTime(int id, double tc) const
{
  const auto it = visible_at_.find(id);
  if (it == visible_at_.end()) return false;
  int n = 0;
  for (const double t : it->second) n += t >= tc - params_.lookback && t <= tc - params_.lead;
  return n >= params_.min_visible_frames;
}

bool CrossingScore::warnedInTime(int id, double tc) const
{
  const auto w = warned_at_.find(id);
  if (w == warned_at_.end()) return false;
  for (const double t : w->second)
    if (t >= tc - params_.lookback && t <= tc - params_.lead) return true;
  return false;
}

std::vector<CrossingScore::CrossingDetail> CrossingScore::details() const
{
  std::vector<CrossingDetail> out;
  for (const auto& kv : closest_)
  {
    if (!isCrossing(kv.second)) continue;
    CrossingDetail d{kv.first, kv.second.t, kv.second.d, NAN, NAN, NAN, visibleInTime(kv.first, kv.second.t)};
    auto first = [&](const std::map<int, std::vector<double>>& m) {
      const auto it = m.find(kv.first);
      if (it != m.end())
        for (const double t : it->second)
          if (t >= kv.second.t - params_.lookback && t <= kv.second.t) return t;
      return static_cast<double>(NAN);
    };
    d.first_tracked = first(matched_at_);
    d.first_warned = first(warned_at_);
    d.first_visible = first(visible_at_);
    out.push_back(d);
  }
  return out;
}

int CrossingScore::crossings() const
{
  int n = 0;
  for (const auto& kv : closest_) n += isCrossing(kv.second);
  return n;
}

int CrossingScore::crossingsWarned() const
{
  int n = 0;
  for (const auto& kv : closest_) n += isCrossing(kv.second) && warnedInTime(kv.first, kv.second.t);
  return n;
}

int CrossingScore::crossingsVisible() const
{
  int n = 0;
  for (const auto& kv : closest_) n += isCrossing(kv.second) && visibleInTime(kv.first, kv.second.t);
  return n;
}

int CrossingScore::crossingsWarnedVisible() const
{
  int n = 0;
  for (const auto& kv : closest_)
    n += isCrossing(kv.second) && visibleInTime(kv.first, kv.second.t) && warnedInTime(kv.first, kv.second.t);
  return n;
}

double CrossingScore::warnedPct() const
{
  const int n = crossings();
  return n ? 100.0 * crossingsWarned() / n : NAN;
}

int CrossingScore::falseWarnings() const
{
  int n = 0;
  for (const Onset& o : onsets_)
  {
    if (o.truth_id == 0)
    {
      ++n;
      continue;
    }
    const auto c = closest_.find(o.truth_id);
    if (c != closest_.end() && c->second.d >= params_.far_distance) ++n;
  }
  return n;
}

double CrossingScore::falseWarningsPerMin() const
{
  const double m = minutes();
  return m > 0.0 ? falseWarnings() / m : NAN;
}

}  // namespace assistive_obstacles
