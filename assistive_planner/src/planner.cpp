#include "assistive_planner/planner.h"

#include <cstdio>

#include <algorithm>
#include <array>
#include <cmath>
#include <queue>

#include <opencv2/imgproc.hpp>

#include "assistive_planner/cost_model.h"

namespace assistive_planner
{
namespace
{
/// IN_UNKNOWN for unmapped floor closer ahead than unknown_ahead_m: no path, no target.
void unmappedAhead(PlanOutput& out)
{
  char buf[96];
  std::snprintf(buf, sizeof(buf), "unmapped floor %.2f m ahead: cannot tell what is there", out.free_ahead);
  out.status = PlanStatus::IN_UNKNOWN;
  out.message = buf;
  if (!out.vouch_note.empty())
    out.message += " (" + out.vouch_note + ")";
  out.path.clear();
  out.steer_path.clear();
  out.has_waypoint = false;
}

/// NO_MAP / NO_POSE for an empty grid or a pose that is not finite; false then.
bool usableInputs(const Grid& input, const Point2& wearer, double head_yaw, PlanOutput& out)
{
  if (!input.empty() && input.resolution > 0.0 && std::isfinite(wearer.x) && std::isfinite(wearer.y) &&
      std::isfinite(head_yaw))
    return true;
  out.status = input.empty() ? PlanStatus::NO_MAP : PlanStatus::NO_POSE;
  out.message = input.empty() ? "no traversability grid" : "invalid wearer pose";
  return false;
}

/// The free distances ahead (the body's strip), left and right of `yaw` from the wearer.
void judgeFreeSpace(const Grid& grid, const Point2& wearer, double yaw, const PlannerParams& p, PlanOutput& out,
                    bool& ahead_unknown)
{
  out.free_ahead = Planner::freeStrip(grid, wearer, yaw, p.free_ray_max, p.body_half_width, ahead_unknown);
  out.free_left = Planner::freeDistance(grid, wearer, yaw + M_PI_2, p.free_ray_max);
  out.free_right = Planner::freeDistance(grid, wearer, yaw - M_PI_2, p.free_ray_max);
}

/// Moves (cx, cy) to the cell within 3 cells of it, inside the grid, of the lowest
/// cost(x, y, dx, dy) (infinite: no candidate); unchanged when there is none.
template <class Cost>
void nearestCellBy(const Grid& grid, int& cx, int& cy, Cost cost)
{
  double best = 1e300;
  const int ox = cx, oy = cy;
  for (int dy = -3; dy <= 3; ++dy)
    for (int dx = -3; dx <= 3; ++dx)
    {
      const int x = ox + dx, y = oy + dy;
      if (!grid.inside(x, y))
        continue;
      const double d = cost(x, y, dx, dy);
      if (d < best)
      {
        best = d;
        cx = x;
        cy = y;
      }
    }
}

/// A goal outside the window or not traversable: the free cell reachable from the wearer nearest
/// to it; (gx, gy) unchanged when there is none.
void nearestReachableFree(const Grid& grid, const Point2& wearer, const Point2& goal, int& gx, int& gy)
{
  const TriangleSearch all = searchTriangle(grid, wearer, 0.0, 0.0, 0.0);
  double best = 1e300;
  for (int y = 0; y < grid.height; ++y)
    for (int x = 0; x < grid.width; ++x)
      if (all.reached[size_t(grid.index(x, y))] && grid.at(x, y) == CELL_FREE)
      {
        const double d = std::hypot(grid.cellX(x) - goal.x, grid.cellY(y) - goal.y);
        if (d < best)
        {
          best = d;
          gx = x;
          gy = y;
        }
      }
}

/// The free cell nearest `goal` among those the body can reach from (sx, sy) by the search's own
/// moves (cost-grid weights, no corner cutting), at least `min_gain` from the start and that much
/// nearer the goal; false when there is none (the wearer is as near as it can get: a target a
/// step away would only turn it on the spot, to and fro as the map's edge moves with its view).
bool nearestBodyReachableFree(const Grid& grid, const CostGrid& costs, int sx, int sy, const Point2& goal,
                              double min_gain, int& gx, int& gy)
{
  const std::vector<double> reach = dijkstraCostToGoal(costs, sx, sy);  // symmetric edges: from the start
  const double x0 = grid.cellX(sx), y0 = grid.cellY(sy);
  double best = std::hypot(x0 - goal.x, y0 - goal.y) - min_gain;
  bool found = false;
  for (int y = 0; y < grid.height; ++y)
    for (int x = 0; x < grid.width; ++x)
    {
      const int u = grid.index(x, y);
      if (reach[size_t(u)] == COST_INF || grid.at(x, y) != CELL_FREE ||
          std::hypot(grid.cellX(x) - x0, grid.cellY(y) - y0) < min_gain)
        continue;
      const double d = std::hypot(grid.cellX(x) - goal.x, grid.cellY(y) - goal.y);
      if (d < best)
      {
        best = d;
        gx = x;
        gy = y;
        found = true;
      }
    }
  return found;
}

/// The straight walk from a to b crosses only cells the body fits in (weight not COST_INF), the
/// wearer's own neighbourhood aside (it may stand in the inflation); false when it leaves the grid.
bool bodyFitsAlong(const Grid& grid, const std::vector<double>& w, const Point2& wearer, const Point2& a,
                   const Point2& b)
{
  int sx0, sy0;
  grid.worldToCell(wearer.x, wearer.y, sx0, sy0);
  const double len = std::hypot(b.x - a.x, b.y - a.y);
  for (double d = 0.5 * grid.resolution; d < len; d += 0.25 * grid.resolution)
  {
    int x, y;
    if (!grid.worldToCell(a.x + (b.x - a.x) * d / len, a.y + (b.y - a.y) * d / len, x, y))
      return false;
    if (std::abs(x - sx0) <= 1 && std::abs(y - sy0) <= 1)
      continue;
    if (w[size_t(grid.index(x, y))] == COST_INF)
      return false;
  }
  return true;
}
}  // namespace

Planner::Planner(const PlannerParams& p) : p_(p), motion_(p), waypoints_(p), crossing_(p) {}

std::vector<Point2> pathAhead(const PlanOutput& out, double max_m)
{
  std::vector<Point2> ahead;
  if (out.status != PlanStatus::OK)
    return ahead;
  double run = 0.0;
  for (const Point2& q : out.steer_path)
  {
    if (!ahead.empty())
      run += std::hypot(q.x - ahead.back().x, q.y - ahead.back().y);
    ahead.push_back(q);
    if (run >= max_m)
      break;
  }
  return ahead;
}

int markWalkedFloor(Grid& grid, const std::vector<Point2>& walked, double radius)
{
  if (grid.empty() || !(radius > 0.0))
    return 0;
  int changed = 0;
  const int r = int(std::ceil(radius / grid.resolution)) + 1;
  for (const Point2& p : walked)
  {
    int cx, cy;
    grid.worldToCell(p.x, p.y, cx, cy);  // may lie outside: its neighbours may not
    if (cx < -r || cy < -r || cx >= grid.width + r || cy >= grid.height + r)
      continue;
    for (int y = cy - r; y <= cy + r; ++y)
      for (int x = cx - r; x <= cx + r; ++x)
      {
        if (!grid.inside(x, y) || !isUnknownCode(grid.at(x, y)))
          continue;
        if (std::hypot(grid.cellX(x) - p.x, grid.cellY(y) - p.y) > radius + 1e-9)
          continue;
        grid.data[size_t(grid.index(x, y))] = CELL_FREE;
        ++changed;
      }
  }
  return changed;
}

void Planner::setGoal(const Point2& goal)
{
  has_goal_ = true;
  goal_ = goal;
}

double Planner::freeDistance(const Grid& grid, const Point2& from, double yaw, double max_range)
{
  bool ends_unknown;
  return freeDistance(grid, from, yaw, max_range, ends_unknown);
}

double Planner::freeDistance(const Grid& grid, const Point2& from, double yaw, double max_range, bool& ends_unknown)
{
  ends_unknown = false;
  int x0, y0;
  if (grid.empty() || !grid.worldToCell(from.x, from.y, x0, y0))
    return 0.0;
  const double step = 0.25 * grid.resolution, c = std::cos(yaw), s = std::sin(yaw);
  double d = 0.0;
  while (d + step <= max_range)
  {
    const double nd = d + step;
    int x, y;
    if (!grid.worldToCell(from.x + nd * c, from.y + nd * s, x, y))
      return d;
    if (!(x == x0 && y == y0) && grid.at(x, y) != CELL_FREE)
    {
      ends_unknown = isUnknownCode(grid.at(x, y));
      return d;
    }
    d = nd;
  }
  return d;
}

double Planner::freeStrip(const Grid& grid, const Point2& from, double yaw, double max_range, double half_width,
                          bool& ends_unknown)
{
  ends_unknown = false;
  if (!(half_width > 0.0))
    return freeDistance(grid, from, yaw, max_range, ends_unknown);
  // The centre line first (the window's edge and what lies straight ahead), then every cell that is
  // not free whose centre lies inside the strip AHEAD of the body's front arc: a cell beside the
  // body or under it is contact, not something the next steps run into (on 0.2 m cells the strip
  // would otherwise stop the wearer beside every piece of furniture it passes).
  double best = freeDistance(grid, from, yaw, max_range, ends_unknown);
  int x0, y0;
  if (grid.empty() || !grid.worldToCell(from.x, from.y, x0, y0))
    return best;
  const double c = std::cos(yaw), s = std::sin(yaw), res = grid.resolution;
  const int reach = int(std::ceil((best + half_width) / res)) + 1;
  for (int y = y0 - reach; y <= y0 + reach; ++y)
    for (int x = x0 - reach; x <= x0 + reach; ++x)
    {
      if (!grid.inside(x, y) || (x == x0 && y == y0) || grid.at(x, y) == CELL_FREE)
        continue;
      const double dx = grid.cellX(x) - from.x, dy = grid.cellY(y) - from.y;
      const double f = dx * c + dy * s, l = -dx * s + dy * c;
      if (std::abs(l) > half_width || f <= std::sqrt(half_width * half_width - l * l))
        continue;  // outside the strip, or beside / under the body
      const double d = std::max(0.0, f - 0.5 * res);
      if (d < best)
      {
        best = d;
        ends_unknown = isUnknownCode(grid.at(x, y));
      }
    }
  return best;
}

std::vector<int> Planner::cheapestPath(const CostGrid& costs, int from, int to)
{
  const size_t n = costs.w.size();
  if (from < 0 || to < 0 || size_t(from) >= n || size_t(to) >= n || costs.w[size_t(from)] == COST_INF ||
      costs.w[size_t(to)] == COST_INF)
    return {};
  const int tx = to % costs.width, ty = to / costs.width;
  std::vector<double> g(n, COST_INF);
  std::vector<int> parent(n, -1);
  using Item = std::pair<double, int>;
  std::priority_queue<Item, std::vector<Item>, std::greater<Item>> open;
  g[size_t(from)] = 0.0;
  open.push({ octile(from % costs.width - tx, from / costs.width - ty), from });
  while (!open.empty())
  {
    const auto [f, u] = open.top();
    open.pop();
    if (u == to)
      break;
    const int ux = u % costs.width, uy = u / costs.width;
    if (f > g[size_t(u)] + octile(ux - tx, uy - ty) + 1e-9)
      continue;  // stale entry
    for (int k = 0; k < 8; ++k)
    {
      const double c = costs.edgeCost(ux, uy, k);
      if (c == COST_INF)
        continue;
      const int v = costs.index(ux + NB_DX[k], uy + NB_DY[k]);
      if (g[size_t(u)] + c < g[size_t(v)])
      {
        g[size_t(v)] = g[size_t(u)] + c;
        parent[size_t(v)] = u;
        open.push({ g[size_t(v)] + octile(ux + NB_DX[k] - tx, uy + NB_DY[k] - ty), v });
      }
    }
  }
  if (g[size_t(to)] == COST_INF)
    return {};
  std::vector<int> cells;
  for (int c = to; c >= 0; c = parent[size_t(c)])
    cells.push_back(c);
  std::reverse(cells.begin(), cells.end());
  return cells;
}

double Planner::projectOnto(const std::vector<Point2>& path, const Point2& q, double max_along)
{
  double best = 1e300, at = 0.0, run = 0.0;
  for (size_t i = 1; i < path.size() && run <= max_along; ++i)
  {
    const double dx = path[i].x - path[i - 1].x, dy = path[i].y - path[i - 1].y, l2 = dx * dx + dy * dy;
    const double u = l2 > 1e-12 ? std::clamp(((q.x - path[i - 1].x) * dx + (q.y - path[i - 1].y) * dy) / l2, 0.0, 1.0) : 0.0;
    const double d = std::hypot(path[i - 1].x + u * dx - q.x, path[i - 1].y + u * dy - q.y);
    const double l = std::sqrt(l2);
    if (d < best)
    {
      best = d;
      at = run + u * l;
    }
    run += l;
  }
  return at;
}

Point2 Planner::pointAlong(const std::vector<Point2>& path, double dist)
{
  if (path.empty())
    return {};
  double left = dist;
  for (size_t i = 1; i < path.size(); ++i)
  {
    const double dx = path[i].x - path[i - 1].x, dy = path[i].y - path[i - 1].y, l = std::hypot(dx, dy);
    if (l >= left && l > 1e-12)
      return { path[i - 1].x + dx * left / l, path[i - 1].y + dy * left / l };
    left -= l;
  }
  return path.back();
}

void Planner::smoothPath(const Grid& grid, const std::vector<double>& weights, const cv::Mat& dist,
                         std::vector<Point2>& path)
{
  if (path.size() < 3 || grid.empty() || weights.size() != grid.data.size() || dist.rows != grid.height ||
      dist.cols != grid.width)
    return;
  auto cellOf = [&](const Point2& q, int& x, int& y) { return grid.worldToCell(q.x, q.y, x, y); };
  // clearance (cells) of a point's cell; -1 outside or blocked
  auto clear = [&](const Point2& q) -> double {
    int x, y;
    if (!cellOf(q, x, y) || weights[size_t(grid.index(x, y))] == COST_INF)
      return -1.0;
    return dist.at<float>(y, x);
  };
  const double step = 0.25 * grid.resolution;
  std::vector<Point2> out{ path.front() };
  size_t i = 0;
  const size_t n = path.size();
  while (i + 1 < n)
  {
    // the least clearance of the stretch i..j as the path walks it, and the farthest j whose
    // straight line keeps it (and every cell it crosses passable)
    int ix, iy;
    cellOf(path[i], ix, iy);
    double stretch_min = std::max(0.0, clear(path[i]));
    size_t best = i + 1;
    for (size_t j = i + 1; j < n && j <= i + 40; ++j)
    {
      stretch_min = std::min(stretch_min, std::max(0.0, clear(path[j])));
      const double dx = path[j].x - path[i].x, dy = path[j].y - path[i].y, len = std::hypot(dx, dy);
      bool ok = true;
      for (double d = step; d < len && ok; d += step)
      {
        const Point2 q{ path[i].x + dx * d / len, path[i].y + dy * d / len };
        int qx, qy;
        if (cellOf(q, qx, qy) && qx == ix && qy == iy)
          continue;  // the start's own cell (the wearer may stand in the inflation)
        const double c = clear(q);
        ok = c >= 0.0 && c + 0.05 >= stretch_min;
      }
      if (ok)
        best = j;
    }
    out.push_back(path[best]);
    i = best;
  }
  path.swap(out);
}

namespace
{
/// The obstacle cells of `grid` at 5 cm over a box (each cell 4 x 4 pixels, so distances run to
/// the cell's square, as a body's surface would) and its distance field, sampled bilinearly.
struct FineField
{
  cv::Mat dist;
  double bx = 0.0, by = 0.0, fine = 0.05;
  bool any = false;
  FineField(const Grid& grid, double minx, double miny, double maxx, double maxy)
  {
    const int f = std::max(1, int(std::lround(grid.resolution / 0.05)));
    fine = grid.resolution / f;
    int x0, y0, x1, y1;
    grid.worldToCell(minx, miny, x0, y0);
    grid.worldToCell(maxx, maxy, x1, y1);
    x0 = std::max(0, x0);
    y0 = std::max(0, y0);
    x1 = std::min(grid.width - 1, x1);
    y1 = std::min(grid.height - 1, y1);
    if (x1 < x0 || y1 < y0)
      return;
    cv::Mat mask((y1 - y0 + 1) * f, (x1 - x0 + 1) * f, CV_8UC1, cv::Scalar(255));
    for (int y = y0; y <= y1; ++y)
      for (int x = x0; x <= x1; ++x)
        if (isObstacleCode(grid.at(x, y)))
        {
          mask(cv::Rect((x - x0) * f, (y - y0) * f, f, f)).setTo(0);
          any = true;
        }
    if (!any)
      return;
    cv::distanceTransform(mask, dist, cv::DIST_L2, cv::DIST_MASK_PRECISE);
    // world -> fine pixel (pixel centres at (i + 0.5) * fine from the box's corner)
    bx = grid.cellX(x0) - 0.5 * grid.resolution;
    by = grid.cellY(y0) - 0.5 * grid.resolution;
  }
  /// Distance (m) from (wx, wy) to the nearest obstacle cell's square (clamped to the box).
  double operator()(double wx, double wy) const
  {
    const double u = (wx - bx) / fine - 0.5, v = (wy - by) / fine - 0.5;
    const int iu = std::clamp(int(std::floor(u)), 0, dist.cols - 2), iv = std::clamp(int(std::floor(v)), 0, dist.rows - 2);
    const double a = std::clamp(u - iu, 0.0, 1.0), b = std::clamp(v - iv, 0.0, 1.0);
    const double d = (1 - a) * (1 - b) * dist.at<float>(iv, iu) + a * (1 - b) * dist.at<float>(iv, iu + 1) +
                     (1 - a) * b * dist.at<float>(iv + 1, iu) + a * b * dist.at<float>(iv + 1, iu + 1);
    return d * fine;
  }
};

/// The bounding box of `pts` grown by `margin`.
std::array<double, 4> boxOf(const std::vector<Point2>& pts, double margin)
{
  std::array<double, 4> b{ { 1e300, 1e300, -1e300, -1e300 } };
  for (const Point2& q : pts)
  {
    b[0] = std::min(b[0], q.x);
    b[1] = std::min(b[1], q.y);
    b[2] = std::max(b[2], q.x);
    b[3] = std::max(b[3], q.y);
  }
  return { { b[0] - margin, b[1] - margin, b[2] + margin, b[3] + margin } };
}

/// A passage's axis (Passage::axis) at its middle, on the 5 cm obstacle distance field; NaN when
/// no chord through the middle closes on both sides near twice its clearance (no passage).
double passageAxis(const FineField& field, const Point2& middle, double clearance, double path_dir, double max_chord)
{
  // The door's line is the shortest chord of free floor through its middle (jamb to jamb; any
  // other direction runs out into the rooms or along the aisle); the axis is across it, the way
  // the path goes. A path that crosses a doorway on the slant still gets the doorway's own axis.
  auto chord = [&](double th) {
    const double ux = std::cos(th), uy = std::sin(th);
    double len = 0.0;
    for (int side : { -1, 1 })
    {
      double o = 0.0;
      while (o < 0.5 * max_chord && field(middle.x + side * o * ux, middle.y + side * o * uy) > 1e-6)
        o += 0.005;
      if (o >= 0.5 * max_chord)
        return 1e300;  // open on this side: no chord
      len += o;
    }
    return len;
  };
  // every degree; the chords within 2 cm of the shortest are the jamb-to-jamb line give or take
  // the quantisation (a chord tilted by a few degrees is longer by less than a step): their
  // middle direction (a mean of the doubled angles: a line has no sign)
  std::array<double, 180> len{};
  double best_len = 1e300;
  for (int k = 0; k < 180; ++k)
  {
    len[size_t(k)] = chord(k * M_PI / 180.0);
    best_len = std::min(best_len, len[size_t(k)]);
  }
  double sx = 0.0, sy = 0.0;
  for (int k = 0; k < 180; ++k)
    if (len[size_t(k)] <= best_len + 0.02)
    {
      sx += std::cos(2.0 * k * M_PI / 180.0);
      sy += std::sin(2.0 * k * M_PI / 180.0);
    }
  const double best = 0.5 * std::atan2(sy, sx);
  // no chord ends on both sides within reach, or the shortest is no jamb-to-jamb line through the
  // middle (twice its clearance): no passage (a path along a hall past a doorway's mouth found a
  // middle in the mouth, whose chords run out into the room and along the hall)
  if (!(best_len < 2.0 * clearance + 0.15))
    return std::numeric_limits<double>::quiet_NaN();
  double axis = best + 0.5 * M_PI;
  if (std::cos(axis - path_dir) < 0.0)
    axis += M_PI;
  return std::atan2(std::sin(axis), std::cos(axis));
}

}  // namespace

void Planner::refinePath(const Grid& grid, std::vector<Point2>& path, double clearance)
{
  if (path.size() < 3 || grid.empty() || !(clearance > 0.0))
    return;
  const std::array<double, 4> box = boxOf(path, clearance + 2.0 * grid.resolution);
  const FineField sample(grid, box[0], box[1], box[2], box[3]);
  if (!sample.any || sample.dist.rows < 2 || sample.dist.cols < 2)
    return;
  const double fine = sample.fine;
  const double max_shift = 0.5 * grid.resolution, step = 0.25 * fine, h = fine;
  for (size_t i = 1; i + 1 < path.size(); ++i)
  {
    Point2 q = path[i];
    for (int it = 0; it < 64; ++it)
    {
      if (sample(q.x, q.y) >= clearance)
        break;
      const double gx = sample(q.x + h, q.y) - sample(q.x - h, q.y), gy = sample(q.x, q.y + h) - sample(q.x, q.y - h);
      const double g = std::hypot(gx, gy);
      if (g < 1e-6)
        break;
      const Point2 n{ q.x + step * gx / g, q.y + step * gy / g };
      if (sample(n.x, n.y) <= sample(q.x, q.y) ||
          std::hypot(n.x - path[i].x, n.y - path[i].y) > max_shift)
        break;  // on the ridge (the middle), or as far as a point may move
      q = n;
    }
    path[i] = q;
  }
}

Passage Planner::findPassage(const Grid& grid, const std::vector<Point2>& path, double from_along, double range,
                             double max_width)
{
  Passage out;
  if (path.size() < 2 || grid.empty() || !(range > 0.0) || !(max_width > 0.0))
    return out;
  // the path every 5 cm over the range, with its direction there
  std::vector<Point2> pts;
  std::vector<double> along;
  for (double s = from_along; s <= from_along + range + 1e-9; s += 0.05)
  {
    pts.push_back(pointAlong(path, s));
    along.push_back(s);
    if (pts.size() > 1 && std::hypot(pts.back().x - pts[pts.size() - 2].x, pts.back().y - pts[pts.size() - 2].y) < 1e-6)
      break;  // the path ended
  }
  if (pts.size() < 2)
    return out;
  const double reach = 0.5 * max_width + 0.15;  // how far across the path the middle is searched
  const std::array<double, 4> box = boxOf(pts, reach + 2.0 * grid.resolution);
  const FineField field(grid, box[0], box[1], box[2], box[3]);
  if (!field.any || field.dist.rows < 2 || field.dist.cols < 2)
    return out;
  // at each point: the middle across the path (the ridge of the distance field within `reach`);
  // a passage is where the width there is under max_width (a wall on one side only leaves a
  // middle farther off; in front of a wall with a doorway it starts before the doorway); its
  // middle is its narrowest point within 1.2 m of its start. The width: the field runs to the
  // obstacle cells' squares, but a jamb fills every cell it touches, so its face lies anywhere
  // in the cell next to the free ones, half a cell in on average: twice the clearance plus a
  // cell (a 0.80 m doorway leaves 0.6 m of free cells; 0.85 m, 0.6 or 0.8 m).
  const double hidden = grid.resolution;  // the two half cells the jambs' faces lie inside
  bool inside = false;
  double entry = 0.0, best = 1e300;
  for (size_t i = 0; i < pts.size(); ++i)
  {
    const Point2& a = pts[i > 0 ? i - 1 : 0];
    const Point2& b = pts[i > 0 ? i : 1];
    const double len = std::max(1e-9, std::hypot(b.x - a.x, b.y - a.y));
    const double nx = -(b.y - a.y) / len, ny = (b.x - a.x) / len;
    double c = -1.0;
    Point2 mid = pts[i];
    for (double o = -reach; o <= reach + 1e-9; o += 0.025)
    {
      const double d = field(pts[i].x + o * nx, pts[i].y + o * ny);
      if (d > c + 1e-9 || (std::fabs(d - c) <= 1e-9 && std::fabs(o) < 1e-9))
      {
        c = d;
        mid = { pts[i].x + o * nx, pts[i].y + o * ny };
      }
    }
    const bool narrow = 2.0 * c + hidden < max_width;
    if (narrow && !inside)
    {
      inside = true;
      entry = along[i];
    }
    if (!inside)
      continue;
    if (!narrow || along[i] > entry + 1.2)
      break;
    if (c < best)
    {
      best = c;
      out.found = true;
      out.along = along[i] - from_along;
      out.middle = mid;
      out.width = 2.0 * c + hidden;
      out.axis = std::atan2(b.y - a.y, b.x - a.x);
    }
  }
  if (out.found)
  {
    out.axis = passageAxis(field, out.middle, best, out.axis, 2.0 * reach);
    if (!std::isfinite(out.axis))
      return Passage();
  }
  return out;
}

void Planner::syncCosts(const Grid& grid, PlanOutput& out)
{
  obstacle_dist_ = obstacleDistanceCells(grid);  // once a cycle: the costs and the path's smoothing
  const std::vector<double> w = cellWeights(grid, p_, &obstacle_dist_);
  const bool same_shape = have_grid_ && grid.width == last_grid_.width && grid.height == last_grid_.height &&
                          std::abs(grid.resolution - last_grid_.resolution) < 1e-9;
  int dx = 0, dy = 0;
  bool aligned = false;
  if (same_shape)
  {
    const double fx = (grid.origin_x - last_grid_.origin_x) / grid.resolution;
    const double fy = (grid.origin_y - last_grid_.origin_y) / grid.resolution;
    dx = int(std::lround(fx));
    dy = int(std::lround(fy));
    aligned = std::abs(fx - dx) < 1e-3 && std::abs(fy - dy) < 1e-3 && std::abs(dx) < grid.width &&
              std::abs(dy) < grid.height;
  }
  if (!aligned)
  {
    CostGrid cg(grid.width, grid.height);
    cg.w = w;
    dstar_.reset(cg);
    out.changed_cells = w.size();
  }
  else if (dx != 0 || dy != 0)
  {
    dstar_.scroll(dx, dy, w);  // new cell (x, y) = old (x + dx, y + dy)
    out.scrolled = true;
  }
  else
  {
    out.changed_cells = dstar_.setCosts(w);
  }
  have_grid_ = true;
  last_grid_.width = grid.width;
  last_grid_.height = grid.height;
  last_grid_.resolution = grid.resolution;
  last_grid_.origin_x = grid.origin_x;
  last_grid_.origin_y = grid.origin_y;
}

PlanOutput Planner::update(const Grid& input, const Point2& wearer, double head_yaw, double t)
{
  PlanOutput out;
  out.wearer = wearer;
  out.head_yaw = wrapAngle(head_yaw);
  if (!usableInputs(input, wearer, head_yaw, out))
    return out;
  recordWalkedFloor(input, wearer);
  vouchForBlindZone(wearer, out.head_yaw, t, out);
  blockHeldUnseenFloor(wearer);
  freeCrossedSteps(wearer);
  out.unseen_held_cells = static_cast<int>(unseen_.size());
  out.crossed_step_cells = static_cast<int>(crossed_.size());
  out.grid = std::make_shared<const Grid>(work_);
  const Grid& grid = work_;
  syncCosts(grid, out);
  const bool motion_changed = motion_.update(wearer, head_yaw);
  out.heading = motion_.heading();
  out.motion_anchor = motion_.anchor();
  measureWalk(wearer, t, out);
  const bool walking = out.walking_speed >= 0.25;
  // what lies ahead of the body: along its walk while it walks, else along the motion vector
  // (the waypoint search and the crossing watch keep the seed's motion vector)
  const double h = out.heading;
  bool ahead_unknown = false;
  judgeFreeSpace(grid, wearer, walking ? out.walk_heading : out.heading, p_, out, ahead_unknown);
  // People crossing: judged on every cycle with a pose and a grid, whatever the status below (the
  // cue logic acts on it only when the status is OK: never on a guess).
  if (std::isfinite(t))
  {
    crossing_.addPose(t, wearer);
    out.crossing = crossing_.check(t, wearer, h, out.free_left, out.free_right);
  }

  int wx, wy;
  if (!grid.worldToCell(wearer.x, wearer.y, wx, wy))
  {
    out.status = PlanStatus::NO_MAP;
    out.message = "the wearer is outside the traversability grid";
    return out;
  }
  const int8_t here = grid.at(wx, wy);
  if (isUnknownCode(here) && !ever_planned_)
  {
    out.status = PlanStatus::IN_UNKNOWN;
    out.message = "the wearer stands in unmapped space: no path until a mapped region is reached";
    return out;
  }
  if (walking && ahead_unknown && out.free_ahead < p_.unknown_ahead_m)
  {
    // The floor just ahead is unmapped, not blocked (after a map reset it lies below the camera's
    // view until the wearer has walked on): "stop" or "step aside" would be a guess.
    unmappedAhead(out);
    return out;
  }
  int gx, gy;
  if (!chooseTarget(grid, wearer, h, motion_changed, out, gx, gy) || !searchPath(grid, wx, wy, gx, gy, out))
    return out;
  shapePath(grid, h, out);
  extendPastGoal(grid, gx, gy, out);
  placeSteeringPoint(grid, walking, out);
  markPassage(grid, out);
  if (!walking)
  {
    // A standing wearer will be sent along the steering heading: what lies ahead is judged there
    // (its motion vector may still point at the wall it stopped in front of).
    judgeFreeSpace(grid, wearer, out.steer_heading, p_, out, ahead_unknown);
    double judged_yaw = out.steer_heading;
    if (ahead_unknown && out.free_ahead < p_.unknown_ahead_m)
    {
      // (standing: judged along the way it will be sent, not the way it faces.) A way outside the
      // sector the blind zone is vouched for starts with a turn on the spot (the cue logic turns a
      // standing wearer whose way lies more than its `stand_turn_deg` off its facing): nobody steps
      // onto that floor before facing it, and it is judged then; until then what lies ahead is what
      // the wearer faces. Otherwise (or facing unmapped floor too): cannot tell.
      const bool turn_first =
          p_.blind_zone_m > 0.0 &&
          std::fabs(wrapAngle(out.steer_heading - out.head_yaw)) > p_.blind_zone_half_angle_deg * M_PI / 180.0;
      if (turn_first)
      {
        judged_yaw = out.head_yaw;
        judgeFreeSpace(grid, wearer, out.head_yaw, p_, out, ahead_unknown);
      }
      if (!turn_first || (ahead_unknown && out.free_ahead < p_.unknown_ahead_m))
      {
        holdUnseenFloorAhead(grid, t, judged_yaw, out);
        unmappedAhead(out);
        return out;
      }
    }
    crossStepAhead(grid, t, judged_yaw, out);
  }
  ever_planned_ = true;
  unseen_clock_.reset();
  out.status = PlanStatus::OK;
  out.message = out.path_through_unknown ? "path crosses unmapped cells (no known free path)"
                : isObstacleCode(here)   ? "the wearer's cell is an obstacle: path from the nearest free cell"
                                         : "ok";
  if (out.unseen_held_cells > 0)
    out.message += "; " + std::to_string(out.unseen_held_cells) + " cells of unseen floor held as obstacles";
  if (out.crossed_step_cells > 0)
    out.message += "; " + std::to_string(out.crossed_step_cells) + " step cells crossed after a stop";
  return out;
}

void Planner::recordWalkedFloor(const Grid& input, const Point2& wearer)
{
  // The wearer stands on the floor under its feet even before the camera has seen it (at the start
  // it lies below the view): the footprint, and every place stood on since, is free floor. Only
  // places the body has been; unseen floor ahead stays unknown.
  if (walked_.empty() || std::hypot(wearer.x - walked_.back().x, wearer.y - walked_.back().y) >= 0.05)
  {
    walked_.push_back(wearer);
    if (walked_.size() > 20000)
      walked_.erase(walked_.begin(), walked_.begin() + 10000);
  }
  work_ = input;
  markWalkedFloor(work_, walked_, p_.footprint_radius_m);
}

void Planner::blockHeldUnseenFloor(const Point2& wearer)
{
  // Held floor is an obstacle while unmapped and near (planned around, and what lies ahead ends at
  // it): once the wearer is as far from it as the camera's nearest floor, facing it shows it.
  const double reach = std::max(p_.blind_zone_m, p_.unknown_ahead_m);
  auto dropped = [&](const Point2& q) {
    int x, y;
    if (std::hypot(q.x - wearer.x, q.y - wearer.y) >= reach || !work_.worldToCell(q.x, q.y, x, y) ||
        !isUnknownCode(work_.at(x, y)))
      return true;
    work_.data[size_t(work_.index(x, y))] = CELL_OBSTACLE;
    return false;
  };
  unseen_.erase(std::remove_if(unseen_.begin(), unseen_.end(), dropped), unseen_.end());
}

double Planner::StandstillClock::lasted(double t)
{
  constexpr double kGapS = 0.5;  // longer between two such cycles: not the same standstill
  if (since < 0.0 || t < last || t - last > kGapS)
    since = t;
  last = t;
  return t - since;
}

void Planner::holdUnseenFloorAhead(const Grid& grid, double t, double judged_yaw, PlanOutput& out)
{
  // A standing wearer never sees the unmapped floor just ahead (below the camera's view, or behind
  // what it stopped at): told UNSURE it stood there for good (vision trial on `plaza`, 65 s beside
  // a sign). After unseen_hold_s that floor is planned around, over known floor if there is a way.
  if (!(p_.unseen_hold_s > 0.0) || !std::isfinite(t))
    return;
  // (a cycle with another status between, such as a lost pose, starts the wait afresh)
  if (unseen_clock_.lasted(t) < p_.unseen_hold_s)
    return;
  auto hold = [&](const Point2& q) {
    int x, y;
    if (std::hypot(q.x - out.wearer.x, q.y - out.wearer.y) > p_.unknown_ahead_m || !grid.worldToCell(q.x, q.y, x, y) ||
        !isUnknownCode(grid.at(x, y)))
      return;
    const Point2 c{ grid.cellX(x), grid.cellY(y) };
    for (const Point2& u : unseen_)
      if (std::hypot(u.x - c.x, u.y - c.y) < 0.5 * grid.resolution)
        return;
    unseen_.push_back(c);
  };
  // the path's cells and the ray the status was judged on
  for (size_t i = 1; i < out.path.size(); ++i)
    hold(out.path[i]);
  const double step = 0.5 * grid.resolution;
  for (double d = step; d <= p_.unknown_ahead_m; d += step)
    hold({ out.wearer.x + d * std::cos(judged_yaw), out.wearer.y + d * std::sin(judged_yaw) });
}

void Planner::freeCrossedSteps(const Point2& wearer)
{
  // A step the wearer was stopped at and then sent over no longer ends what lies ahead (its cost
  // stays in the plan's weights only where it is not crossed); an obstacle mapped there stays one.
  const double reach = p_.step_cross_m + 1.0;
  auto dropped = [&](const Point2& q) {
    if (std::hypot(q.x - wearer.x, q.y - wearer.y) > reach)
      return true;
    int x, y;
    if (work_.worldToCell(q.x, q.y, x, y) && work_.at(x, y) == CELL_STEP)
      work_.data[size_t(work_.index(x, y))] = CELL_FREE;
    return false;
  };
  crossed_.erase(std::remove_if(crossed_.begin(), crossed_.end(), dropped), crossed_.end());
}

void Planner::crossStepAhead(const Grid& grid, double t, double judged_yaw, PlanOutput& out)
{
  // A step or curb is floor the wearer can climb (obstacles/README: a level change of at most
  // step_height between walkable neighbours). The stop before it is the warning; a wearer standing
  // there is sent over it after step_stand_s, and its cane finds the edge. Held for good, a plain
  // floor's phantom steps (stereo noise) stood wearers there until the trial's end.
  if (!(p_.step_stand_s > 0.0) || !std::isfinite(t) || !(out.free_ahead < p_.step_cross_m))
  {
    step_clock_.reset();
    return;
  }
  Grid stepless = grid;
  for (int8_t& c : stepless.data)
    if (c == CELL_STEP)
      c = CELL_FREE;
  bool unknown = false;
  const double without =
      freeStrip(stepless, out.wearer, judged_yaw, p_.free_ray_max, p_.body_half_width, unknown);
  if (!(without > out.free_ahead + 0.5 * grid.resolution))
  {
    step_clock_.reset();  // an obstacle or unmapped floor ends the way, not a step
    return;
  }
  if (step_clock_.lasted(t) < p_.step_stand_s)
    return;
  const double c = std::cos(judged_yaw), s = std::sin(judged_yaw);
  for (int y = 0; y < grid.height; ++y)
    for (int x = 0; x < grid.width; ++x)
    {
      if (grid.at(x, y) != CELL_STEP)
        continue;
      const Point2 q{ grid.cellX(x), grid.cellY(y) };
      const double dx = q.x - out.wearer.x, dy = q.y - out.wearer.y;
      if (std::hypot(dx, dy) > p_.step_cross_m || dx * c + dy * s <= 0.0)
        continue;  // only what lies ahead, within reach
      if (std::none_of(crossed_.begin(), crossed_.end(), [&](const Point2& u) {
            return std::hypot(u.x - q.x, u.y - q.y) < 0.5 * grid.resolution;
          }))
        crossed_.push_back(q);
    }
  step_clock_.reset();
  out.crossed_step_cells = static_cast<int>(crossed_.size());
}

void Planner::vouchForBlindZone(const Point2& wearer, double facing, double t, PlanOutput& out)
{
  // The floor just ahead lies below the camera's view (README, the blind zone): vouched for only
  // on the ranger's fresh "nothing nearer" along the way the head faces, and the camera's view past it.
  if (!(p_.blind_zone_m > 0.0))
    return;
  char buf[128];
  const double half = p_.blind_zone_half_angle_deg * M_PI / 180.0;
  if (!ranger_.valid())
  {
    out.vouch_note = "no ranger reading to vouch for the blind zone";
    return;
  }
  if (!std::isfinite(t) || std::fabs(t - ranger_.stamp) > p_.ranger_max_age_s)
  {
    std::snprintf(buf, sizeof(buf), "the ranger's reading is %.2f s from the frame: the blind zone is not vouched for",
                  std::isfinite(t) ? std::fabs(t - ranger_.stamp) : std::numeric_limits<double>::infinity());
    out.vouch_note = buf;
    return;
  }
  const double off = std::fabs(wrapAngle(ranger_.yaw - facing));
  if (off > half)
  {
    std::snprintf(buf, sizeof(buf), "the ranger points %.0f deg off the head: the blind zone is not vouched for",
                  off * 180.0 / M_PI);
    out.vouch_note = buf;
    return;
  }
  out.vouched_cells = vouchBlindZone(work_, wearer, facing, ranger_, p_.blind_zone_m, half, p_.blind_zone_view_m);
  if (std::isfinite(ranger_.range) && ranger_.range < p_.blind_zone_m + work_.resolution)
  {
    std::snprintf(buf, sizeof(buf), "the ranger hears an echo %.2f m ahead", ranger_.range);
    out.vouch_note = buf;
  }
  else if (out.vouched_cells == 0)
    out.vouch_note = "nothing seen past the blind zone to vouch for it";
}

void Planner::measureWalk(const Point2& wearer, double t, PlanOutput& out)
{
  // The walk: the chord over the last walk_window_s (what the body does now, for steering and
  // for what lies ahead of it); the head's yaw while standing.
  out.walk_heading = out.head_yaw;
  if (!std::isfinite(t))
    return;
  if (!recent_.empty() && t < recent_.back().first)
    recent_.clear();
  recent_.push_back({ t, wearer });
  while (recent_.size() > 2 && recent_[1].first <= t - p_.walk_window_s)
    recent_.erase(recent_.begin());
  const double dt = t - recent_.front().first;
  const double cx = wearer.x - recent_.front().second.x, cy = wearer.y - recent_.front().second.y;
  const double chord = std::hypot(cx, cy);
  if (dt >= 0.5 * p_.walk_window_s && dt < 4.0 * p_.walk_window_s)
  {
    out.walking_speed = chord / dt;
    if (chord >= 0.05)
      out.walk_heading = std::atan2(cy, cx);
  }
}

bool Planner::chooseTarget(const Grid& grid, const Point2& wearer, double heading, bool motion_changed,
                           PlanOutput& out, int& gx, int& gy)
{
  // target: explicit goal, else the automatic waypoint
  gx = gy = -1;
  if (has_goal_ && std::hypot(goal_.x - wearer.x, goal_.y - wearer.y) <= p_.reached_distance)
    has_goal_ = has_next_ = false;  // reached
  if (has_goal_)
  {
    out.explicit_goal = true;
    int cx, cy;
    if (grid.worldToCell(goal_.x, goal_.y, cx, cy) && isTraversableCode(grid.at(cx, cy)))
    {
      gx = cx;
      gy = cy;
    }
    else
      nearestReachableFree(grid, wearer, goal_, gx, gy);
    out.triangle = { wearer, wearer, wearer };
  }
  else
  {
    waypoints_.update(grid, wearer, heading, motion_changed || !waypoints_.has());
    out.triangle = waypoints_.lastSearch().corners;
    if (waypoints_.has())
      grid.worldToCell(waypoints_.waypoint().x, waypoints_.waypoint().y, gx, gy);
  }
  if (gx < 0 && !has_goal_ && waypoints_.lastSearch().free_behind_unknown > 0)
  {
    // free floor beyond unmapped floor: "no path" (an ALERT) would be a guess
    out.status = PlanStatus::IN_UNKNOWN;
    out.message = "free floor ahead beyond unmapped floor: cannot tell whether it can be reached";
    out.has_waypoint = false;
    return false;
  }
  if (gx < 0 && !has_goal_ && waypoints_.lastSearch().unreachable_free > 0)
  {
    out.status = PlanStatus::NO_PATH;
    out.message = "free space ahead but no free path to it";
    return false;
  }
  if (gx < 0)
  {
    out.status = PlanStatus::NO_WAYPOINT;
    out.message = has_goal_ ? "no reachable free cell near the goal" : "nothing traversable inside the search triangle";
    return false;
  }
  out.has_waypoint = true;
  out.waypoint = { grid.cellX(gx), grid.cellY(gy) };
  out.waypoint_distance = std::hypot(out.waypoint.x - wearer.x, out.waypoint.y - wearer.y);
  return true;
}

bool Planner::searchPath(const Grid& grid, int wx, int wy, int& gx, int& gy, PlanOutput& out)
{
  // D* Lite: a new goal restarts the search, otherwise the repaired search continues
  // a wearer standing on an obstacle cell (map noise, closing at a wall) starts from the nearest
  // passable cell within 3 cells instead of getting no path at all
  // (or within the body's radius of one: the inflated cells, e.g. beside a wall)
  const std::vector<double>& weight = dstar_.costs().w;
  auto blocked = [&](int x, int y) { return weight[size_t(grid.index(x, y))] == COST_INF; };
  const double skip = std::numeric_limits<double>::infinity();
  int sx = wx, sy = wy;
  if (blocked(wx, wy))
    nearestCellBy(grid, sx, sy, [&](int x, int y, int, int) {
      return blocked(x, y) ? skip
                           : std::hypot(grid.cellX(x) - out.wearer.x, grid.cellY(y) - out.wearer.y) +
                                 (isUnknownCode(grid.at(x, y)) ? 100.0 : 0.0);
    });
  // the waypoint reported is the cell planned to: the cue logic's "waypoint near, walk on" reads its distance
  auto planTo = [&](int x, int y) {
    out.waypoint = { grid.cellX(x), grid.cellY(y) };
    out.waypoint_distance = std::hypot(out.waypoint.x - out.wearer.x, out.waypoint.y - out.wearer.y);
  };
  if (blocked(gx, gy))  // a target within the body's radius of an obstacle: the nearest cell the body fits in
  {
    nearestCellBy(grid, gx, gy, [&](int x, int y, int dx, int dy) {
      return blocked(x, y) || isUnknownCode(grid.at(x, y)) ? skip : std::hypot(double(dx), double(dy));
    });
    planTo(gx, gy);
  }
  dstar_.resetExpansions();
  dstar_.setGoal(gx, gy);
  dstar_.setStart(sx, sy);
  bool ok = dstar_.plan();
  if (!ok && has_goal_ && nearestBodyReachableFree(grid, dstar_.costs(), sx, sy, goal_, p_.reached_distance, gx, gy))
  {
    // The free cell nearest the goal was found by a flood that ignores the body (through a gap
    // in a wall narrower than the body, a wall's unseen corner): no path to it ever came, and the
    // wearer stood on "no path" for good (vision trial on `glass`: 40 s until the timeout). Go as
    // near the goal as the body can; the map ahead is seen again on the way.
    dstar_.setGoal(gx, gy);
    ok = dstar_.plan();
    planTo(gx, gy);
  }
  out.expansions = dstar_.expansions();
  if (!ok)
  {
    out.status = PlanStatus::NO_PATH;
    out.message = isObstacleCode(grid.at(wx, wy)) ? "the wearer's cell is an obstacle" : "no free path to the waypoint";
  }
  return ok;
}

void Planner::shapePath(const Grid& grid, double heading, PlanOutput& out) const
{
  const Point2& wearer = out.wearer;
  const std::vector<int> cells = dstar_.path();
  out.path.reserve(cells.size() + 1);
  out.path.push_back(wearer);
  for (size_t i = 1; i < cells.size(); ++i)
  {
    const int x = cells[i] % grid.width, y = cells[i] / grid.width;
    out.path.push_back({ grid.cellX(x), grid.cellY(y) });
    if (isUnknownCode(grid.at(x, y)))
      out.path_through_unknown = true;
  }
  if (out.path.size() < 2)
    out.path.push_back(out.waypoint);
  double len = 0.0;
  bool heading_set = false;
  for (size_t i = 1; i < out.path.size(); ++i)
  {
    len += std::hypot(out.path[i].x - out.path[i - 1].x, out.path[i].y - out.path[i - 1].y);
    if (!heading_set && (len >= p_.path_lookahead || i + 1 == out.path.size()))
    {
      const double dx = out.path[i].x - wearer.x, dy = out.path[i].y - wearer.y;
      out.path_heading = (std::hypot(dx, dy) > 1e-6) ? std::atan2(dy, dx) : heading;
      heading_set = true;
    }
  }
  out.path_length = len;
  // Pure pursuit on the path refined towards the middle of narrow passages: the steering point lies
  // a fraction of a second of walking ahead (regulated pure pursuit), within [min, max].
  smoothPath(grid, dstar_.costs().w, obstacle_dist_, out.path);
  refinePath(grid, out.path, p_.path_refine_m);
  out.steer_path = out.path;
}

void Planner::extendPastGoal(const Grid& grid, int gx, int gy, PlanOutput& out) const
{
  int nx, ny;
  if (!has_goal_ || !has_next_ || !grid.worldToCell(next_.x, next_.y, nx, ny))
    return;
  // on round the goal to the next place (steering only: the goal stays the goal)
  std::vector<int> on = cheapestPath(dstar_.costs(), grid.index(gx, gy), grid.index(nx, ny));
  if (on.size() <= 1)
    return;
  std::vector<Point2> more{ out.path.back() };
  for (size_t i = 1; i < on.size(); ++i)
    more.push_back({ grid.cellX(on[i] % grid.width), grid.cellY(on[i] / grid.width) });
  smoothPath(grid, dstar_.costs().w, obstacle_dist_, more);
  refinePath(grid, more, p_.path_refine_m);
  out.steer_path.insert(out.steer_path.end(), more.begin() + 1, more.end());
}

void Planner::placeSteeringPoint(const Grid& grid, bool walking, PlanOutput& out) const
{
  const Point2& wearer = out.wearer;
  out.steer_lookahead =
      std::clamp(out.walking_speed * p_.steer_lookahead_s, p_.steer_lookahead_min, p_.steer_lookahead_max);
  // from where the walk takes the wearer by the time a cue acts (its projection on the path)
  Point2 lead = wearer;
  if (walking)
  {
    const double ahead = out.walking_speed * p_.steer_lead_s;
    lead = { wearer.x + ahead * std::cos(out.walk_heading), wearer.y + ahead * std::sin(out.walk_heading) };
  }
  // the projection is searched over the path's first stretch only (a path folding back on itself
  // must not send the wearer to its far end)
  const double along = projectOnto(out.steer_path, lead, 2.0 * p_.steer_lookahead_max + 1.0);
  out.steer_point = pointAlong(out.steer_path, along + out.steer_lookahead);
  // never a steering point behind a corner: the straight walk to it (from the wearer and from
  // where the walk takes it) must cross only cells the body fits in, else it comes closer along
  // the path (pure pursuit cuts corners; a jamb or a box's edge is where it would)
  const std::vector<double>& w = dstar_.costs().w;
  double ahead = out.steer_lookahead;
  while (ahead > 0.2 && !(bodyFitsAlong(grid, w, wearer, wearer, out.steer_point) &&
                          bodyFitsAlong(grid, w, wearer, lead, out.steer_point)))
  {
    ahead -= 0.1;
    out.steer_point = pointAlong(out.steer_path, along + ahead);
  }
  const double dx = out.steer_point.x - lead.x, dy = out.steer_point.y - lead.y;
  out.steer_heading = std::hypot(dx, dy) > 0.05 ? std::atan2(dy, dx) : out.path_heading;
  out.free_steer = freeDistance(grid, wearer, out.steer_heading, p_.free_ray_max);
}

void Planner::markPassage(const Grid& grid, PlanOutput& out) const
{
  // a doorway or gap narrower than passage_width_m on the path just ahead: its middle, for the
  // cue logic's stop-and-align (the path's cells are 0.2 m; the middle is found on 5 cm)
  out.passage_distance = -1.0;
  if (!(p_.passage_width_m > 0.0) || out.steer_path.size() < 2)
    return;
  const double from = projectOnto(out.steer_path, out.wearer, 2.0 * p_.passage_range_m + 1.0);
  const Passage ps = findPassage(grid, out.steer_path, from, p_.passage_range_m, p_.passage_width_m);
  if (!ps.found)
    return;
  out.passage_distance = ps.along;
  out.passage_point = ps.middle;
  out.passage_width = ps.width;
  out.passage_axis = ps.axis;
  const double dx = ps.middle.x - out.wearer.x, dy = ps.middle.y - out.wearer.y;
  out.passage_heading = std::hypot(dx, dy) > 1e-6 ? std::atan2(dy, dx) : ps.axis;
}
}  // namespace assistive_planner
