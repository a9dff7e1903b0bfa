#include <assistive_obstacles/sonar_fusion.h>

#include <algorithm>
#include <cmath>
#include <unordered_set>

namespace assistive_obstacles
{
const char* rangeCheckName(RangeCheck c)
{
  switch (c)
  {
    case RangeCheck::ECHO:
      return "echo";
    case RangeCheck::NO_ECHO:
      return "no echo";
    case RangeCheck::NOT_A_NUMBER:
      return "NaN range or limits";
    case RangeCheck::OUT_OF_LIMITS:
      return "range outside the sensor's limits";
    case RangeCheck::BAD_FOV:
      return "field of view not in (0, 90 deg)";
  }
  return "?";
}

RangeCheck SonarFusion::check(const RangeReading& r)
{
  if (std::isnan(r.range) || std::isnan(r.min_range) || std::isnan(r.max_range) || std::isnan(r.field_of_view))
    return RangeCheck::NOT_A_NUMBER;
  if (!(r.field_of_view > 0.0 && r.field_of_view < M_PI / 2)) return RangeCheck::BAD_FOV;
  if (!(r.min_range >= 0.0 && r.max_range > r.min_range && std::isfinite(r.max_range))) return RangeCheck::OUT_OF_LIMITS;
  if (r.range == std::numeric_limits<double>::infinity()) return RangeCheck::NO_ECHO;
  if (!(r.range >= r.min_range && r.range <= r.max_range)) return RangeCheck::OUT_OF_LIMITS;  // -inf too
  if (!r.T_world_sensor.matrix().allFinite()) return RangeCheck::NOT_A_NUMBER;
  return RangeCheck::ECHO;
}

void SonarFusion::conePoints(const RangeReading& r, double dist, double half_angle, std::vector<Eigen::Vector3f>& out) const
{
  out.clear();
  // Angular step: half a cell at this distance, so every cell the surface crosses gets a sample.
  const double step = std::max(1e-3, 0.5 * params_.cell_size / std::max(dist, 0.05));
  const int k = std::max(1, static_cast<int>(std::ceil(half_angle / step)));
  const double s = half_angle / k;
  const Eigen::Matrix3f R = r.T_world_sensor.linear();
  const Eigen::Vector3f o = r.T_world_sensor.translation();
  for (int i = -k; i <= k; ++i)
    for (int j = -k; j <= k; ++j)
    {
      const double a = i * s, e = j * s;
      if (a * a + e * e > half_angle * half_angle * (1.0 + 1e-9)) continue;
      Eigen::Vector3f d(1.f, static_cast<float>(std::tan(a)), static_cast<float>(std::tan(e)));
      d.normalize();
      out.push_back(o + R * (static_cast<float>(dist) * d));
    }
}

RangeCheck SonarFusion::apply(const RangeReading& r, const Window& window, float feet, float z_top, TemporalFilter& filter,
                              bool camera_surface)
{
  stats_ = SonarStats();
  stats_.held = holds_.size();
  const RangeCheck verdict = check(r);
  if (verdict != RangeCheck::ECHO || window.n <= 0) return verdict;
  const float z_low = feet + static_cast<float>(params_.step_height);
  const double half = 0.5 * r.field_of_view;

  // The arc: where the echo came from (somewhere on it). Where it dips below the step height it
  // may be the floor's echo, but only if the cone holds a ray steep enough for the floor to send
  // the echo back (specular: sonar_floor_echo_deg below the horizontal); shallower, the floor
  // returns nothing and the arc's part under it is simply not in the world.
  const Eigen::Vector3f axis = r.T_world_sensor.linear().col(0);
  const double steepest = std::asin(std::clamp(-static_cast<double>(axis.z()) / std::max(1e-6f, axis.norm()), -1.0, 1.0)) + half;
  const bool floor_can_echo = steepest >= params_.sonar_floor_echo_deg * M_PI / 180.0;
  conePoints(r, r.range, half, scratch_);
  std::unordered_set<int64_t> arc;
  std::vector<std::pair<int, int>> arc_cells;
  for (const Eigen::Vector3f& p : scratch_)
  {
    if (p.z() < z_low)
    {
      if (floor_can_echo)
      {
        stats_.floor_ambiguous = true;
        return verdict;
      }
      continue;
    }
    if (p.z() > z_top) continue;  // above the head: cannot touch the wearer
    const int gx = static_cast<int>(std::floor(p.x() / window.res)), gy = static_cast<int>(std::floor(p.y() / window.res));
    if (arc.insert(key(gx, gy)).second) arc_cells.push_back({ gx, gy });
  }
  // An echo the camera's map already explains (an obstacle cell not held by the ranger itself where the arc is, or half a cell
  // beyond it: a face on a cell border) adds nothing: the arc's other cells are most likely the
  // free space in front of an oblique wall (up to 2 r sin(incidence) sin(half angle) in front of
  // it). Only an echo with no mapped obstacle at its range is what the camera cannot see (glass).
  // "Mapped" includes a cell whose obstacle votes lead before the filter has decided it (a wall
  // seen for the first time); the ranger's own holds do not count.
  const auto solid = [&](int gx, int gy) {
    if (held(gx, gy)) return false;
    if (filter.code(gx, gy) == CELL_OBSTACLE) return true;
    const CellCounters* cc = filter.find(gx, gy);
    return cc && cc->o > cc->s;
  };
  bool explained = camera_surface;
  for (const auto& c : arc_cells)
    explained = explained || solid(c.first, c.second);
  if (!explained)
  {
    conePoints(r, r.range + 0.5 * params_.cell_size, half, scratch_);
    for (const Eigen::Vector3f& p : scratch_)
    {
      const int gx = static_cast<int>(std::floor(p.x() / window.res)), gy = static_cast<int>(std::floor(p.y() / window.res));
      if (p.z() >= z_low && p.z() <= z_top && solid(gx, gy))
      {
        explained = true;
        break;
      }
    }
  }
  stats_.explained = explained;
  for (const auto& c : arc_cells)
  {
    if (explained) break;
    const int lx = c.first - window.ox, ly = c.second - window.oy;
    if (lx < 0 || ly < 0 || lx >= window.n || ly >= window.n) continue;
    for (int v = 0; v < params_.sonar_hit_votes; ++v)
      filter.vote(c.first, c.second, FrameLabel::OBSTACLE, TemporalFilter::MAX_VOTE_WEIGHT, true);
    holds_[key(c.first, c.second)] = 0;  // a fresh hit restarts the see-through count
    ++stats_.arc_cells;
  }

  // Seen through: the echo came from beyond these cells (inner half of the cone only: its rim may
  // graze a panel whose echo went elsewhere).
  if (!holds_.empty())
  {
    std::unordered_set<int64_t> through;
    const double step = 0.5 * params_.cell_size;
    for (double d = std::max(r.min_range, step); d < r.range - params_.sonar_release_margin; d += step)
    {
      conePoints(r, d, 0.5 * half, scratch_);
      for (const Eigen::Vector3f& p : scratch_)
      {
        const int64_t k = key(static_cast<int>(std::floor(p.x() / window.res)), static_cast<int>(std::floor(p.y() / window.res)));
        if (!arc.count(k)) through.insert(k);
      }
    }
    for (const int64_t k : through)
    {
      auto it = holds_.find(k);
      if (it == holds_.end()) continue;
      if (++it->second >= params_.sonar_release_readings)
      {
        holds_.erase(it);
        ++stats_.released;
      }
    }
  }
  stats_.held = holds_.size();
  return verdict;
}

void SonarFusion::retain(const Window& w)
{
  for (auto it = holds_.begin(); it != holds_.end();)
  {
    const uint64_t k = static_cast<uint64_t>(it->first);
    const int gx = static_cast<int32_t>(static_cast<uint32_t>(k >> 32)), gy = static_cast<int32_t>(static_cast<uint32_t>(k));
    if (gx < w.ox || gy < w.oy || gx >= w.ox + w.n || gy >= w.oy + w.n)
      it = holds_.erase(it);
    else
      ++it;
  }
}

}  // namespace assistive_obstacles
