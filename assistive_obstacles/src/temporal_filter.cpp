#include <assistive_obstacles/temporal_filter.h>

#include <algorithm>

namespace assistive_obstacles
{
void TemporalFilter::resize(int n)
{
  if (n == n_) return;
  n_ = std::max(1, n);
  cells_.assign(static_cast<size_t>(n_) * n_, CellCounters());
}

void TemporalFilter::clear() { cells_.assign(cells_.size(), CellCounters()); }

void TemporalFilter::retain(int ox, int oy, int n)
{
  for (CellCounters& c : cells_)
    if (c.used && (c.gx < ox || c.gy < oy || c.gx >= ox + n || c.gy >= oy + n)) c = CellCounters();
}

int TemporalFilter::slot(int gx, int gy) const
{
  const int x = ((gx % n_) + n_) % n_;
  const int y = ((gy % n_) + n_) % n_;
  return y * n_ + x;
}

const CellCounters* TemporalFilter::find(int gx, int gy) const
{
  if (n_ == 0) return nullptr;
  const CellCounters& c = cells_[slot(gx, gy)];
  return (c.used && c.gx == gx && c.gy == gy) ? &c : nullptr;
}

void TemporalFilter::vote(int gx, int gy, FrameLabel label, int weight, bool observed)
{
  if (n_ == 0 || label == FrameLabel::NONE) return;
  CellCounters& c = cells_[slot(gx, gy)];
  if (!c.used || c.gx != gx || c.gy != gy)
  {
    c = CellCounters();
    c.used = true;
    c.gx = gx;
    c.gy = gy;
  }
  if (c.permanent) return;
  const uint16_t w = static_cast<uint16_t>(std::clamp(weight, 1, MAX_VOTE_WEIGHT));
  if (label == FrameLabel::OBSTACLE)
    c.o = static_cast<uint16_t>(c.o + w);
  else
  {
    c.s = static_cast<uint16_t>(c.s + w);
    if (label == FrameLabel::STEP) c.step = static_cast<uint16_t>(c.step + w);
  }
  if (observed && c.votes < 60000) ++c.votes;
  if (c.o + c.s > params_.max_count * MAX_VOTE_WEIGHT)
  {
    c.o = static_cast<uint16_t>((c.o + 1) / 2);
    c.s = static_cast<uint16_t>((c.s + 1) / 2);
    c.step = static_cast<uint16_t>((c.step + 1) / 2);
  }
  if (c.votes < params_.min_observations) return;
  const double ratio = static_cast<double>(c.o) / (c.o + c.s);
  const int8_t next = ratio > params_.obstacle_ratio ? CELL_OBSTACLE : CELL_FREE;
  if (c.state != CELL_UNKNOWN && next != c.state) ++c.flips;
  c.state = next;
  if (c.flips >= params_.permanent_flips)
  {
    c.permanent = true;
    c.state = CELL_OBSTACLE;
  }
}

int8_t TemporalFilter::code(int gx, int gy) const
{
  const CellCounters* c = find(gx, gy);
  if (!c || c->state == CELL_UNKNOWN) return CELL_UNKNOWN;
  if (c->state == CELL_OBSTACLE) return CELL_OBSTACLE;
  return (2 * c->step > c->s) ? CELL_STEP : CELL_FREE;
}

}  // namespace assistive_obstacles
