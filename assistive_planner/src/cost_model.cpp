#include "assistive_planner/cost_model.h"

#include <algorithm>
#include <opencv2/imgproc.hpp>

#include "assistive_planner/cost_grid.h"

namespace assistive_planner
{
double unknownWeight(const Grid& grid, const PlannerParams& p)
{
  const double max_known = 1.0 + std::max(0.0, p.step_cost) + std::max(0.0, p.clearance_weight);
  const double n = double(grid.width) * double(grid.height);
  return std::ceil(2.0 * n * max_known + 1.0);  // > any simple known path (n cells, <= sqrt2 * max_known each)
}

cv::Mat obstacleDistanceCells(const Grid& grid)
{
  cv::Mat free_mask(grid.height, grid.width, CV_8UC1);
  for (int y = 0; y < grid.height; ++y)
    for (int x = 0; x < grid.width; ++x)
      free_mask.at<uint8_t>(y, x) = isObstacleCode(grid.at(x, y)) ? 0 : 255;
  cv::Mat dist;
  cv::distanceTransform(free_mask, dist, cv::DIST_L2, cv::DIST_MASK_PRECISE);
  return dist;
}

std::vector<double> cellWeights(const Grid& grid, const PlannerParams& p, const cv::Mat* known_dist)
{
  const size_t n = grid.data.size();
  std::vector<double> w(n, 1.0);
  const double unknown = p.unknown_traversable ? unknownWeight(grid, p) : COST_INF;
  bool any_obstacle = false;
  for (size_t i = 0; i < n; ++i)
  {
    const int8_t c = grid.data[i];
    if (isObstacleCode(c))
    {
      w[i] = COST_INF;
      any_obstacle = true;
    }
    else if (isUnknownCode(c))
      w[i] = unknown;
    else if (c == CELL_STEP || c > CELL_FREE)
      w[i] = 1.0 + std::max(0.0, p.step_cost);
  }
  if (any_obstacle && ((p.clearance_weight > 0.0 && p.clearance_radius > 0.0) || p.inflation_radius > 0.0))
  {
    const cv::Mat dist = known_dist ? *known_dist : obstacleDistanceCells(grid);
    const double r = std::max(1e-9, p.clearance_radius / grid.resolution);
    // the body's radius: closer than it (plus half a cell: the obstacle's surface may lie anywhere
    // in its cell) the body would touch, whatever the cost
    const double lethal = p.inflation_radius > 0.0 ? p.inflation_radius / grid.resolution + 0.5 : 0.0;
    for (int y = 0; y < grid.height; ++y)
      for (int x = 0; x < grid.width; ++x)
      {
        const size_t i = size_t(grid.index(x, y));
        if (w[i] == COST_INF || isUnknownCode(grid.data[i]))
          continue;
        const double d = dist.at<float>(y, x);
        if (d < lethal - 1e-6)
        {
          w[i] = COST_INF;
          continue;
        }
        if (!(p.clearance_weight > 0.0 && p.clearance_radius > 0.0))
          continue;
        const double f = std::clamp((r + 1.0 - d) / r, 0.0, 1.0);
        w[i] += p.clearance_weight * f;
      }
  }
  return w;
}
}  // namespace assistive_planner
