#pragma once

#include <vector>

#include <opencv2/core.hpp>

#include "assistive_planner/grid.h"
#include "assistive_planner/params.h"

namespace assistive_planner
{
/// Cell weights for the planner from grid codes: obstacle -> COST_INF; free -> 1; step/curb -> 1 + step_cost;
/// plus clearance_weight * (1 - (d - 1) / R) within R = clearance_radius of an obstacle (d: distance in cells);
/// unknown -> unknownWeight() (above any known path) or COST_INF if unknown_traversable is false.
/// `dist`: obstacleDistanceCells(grid) when the caller has it already (else computed here).
std::vector<double> cellWeights(const Grid& grid, const PlannerParams& p, const cv::Mat* dist = nullptr);
/// Distance (cells, centre to centre, CV_32F) of every cell to the nearest obstacle cell.
cv::Mat obstacleDistanceCells(const Grid& grid);
/// Weight of an unknown cell: larger than the cost of any path through known cells of the grid,
/// so a path only crosses unknown space when no known path exists.
double unknownWeight(const Grid& grid, const PlannerParams& p);
}  // namespace assistive_planner
