#include <assistive_obstacles/temporal_filter.h>

#include <algorithm>

#include <assistive_obstacles/column_clearance.h>

namespace assistive_obstacles
{
void TemporalFilter::setParams(const ObstaclesParams& p)
{
  params_ = p;
  presumed_clear_ = 0;
  const std::vector<float> h = columnBandHeights(p);
  for (size_t i = 0; i < h.size(); ++i)
    if (h[i] < p.column_strict_from) presumed_clear_ = static_cast<uint8_t>(presumed_clear_ | (1u << i));
}

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

CellCounters& TemporalFilter::claim(int gx, int gy)
{
  CellCounters& c = cells_[slot(gx, gy)];
  if (!c.used || c.gx != gx || c.gy != gy)
  {
    c = CellCounters();
    c.clear = presumed_clear_;
    c.used = true;
    c.gx = gx;
    c.gy = gy;
  }
  return c;
}

bool TemporalFilter::columnClear(int gx, int gy) const
{
  if (params_.column_bands <= 0) return true;
  const CellCounters* c = find(gx, gy);
  const uint8_t all = allBands(params_.column_bands);
  return ((c ? c->clear : presumed_clear_) & all) == all;
}

void TemporalFilter::setMoverCells(const std::vector<std::pair<int, int>>& cells)
{
  movers_.clear();
  for (const auto& c : cells) movers_.insert(key(c.first, c.second));
}

void TemporalFilter::observeColumn(int gx, int gy, uint8_t seen_clear, uint8_t seen_occupied)
{
  if (n_ == 0 || params_.column_bands <= 0 || moverCell(gx, gy)) return;
  if (!seen_clear && !seen_occupied && !find(gx, gy)) return;  // nothing to remember
  CellCounters& c = claim(gx, gy);
  c.clear = static_cast<uint8_t>((c.clear | seen_clear) & ~seen_occupied);
}

void TemporalFilter::vote(int gx, int gy, FrameLabel label, int weight, bool observed)
{
  if (n_ == 0 || label == FrameLabel::NONE || moverCell(gx, gy)) return;
  CellCounters& c = claim(gx, gy);
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
