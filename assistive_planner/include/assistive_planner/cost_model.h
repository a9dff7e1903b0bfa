#pragma once

#include <vector>

#include "assistive_planner/grid.h"
#include "assistive_planner/params.h"

namespace assistive_planner
{
/// Cell weights for the planner from grid codes: obstacle -> COST_INF; free -> 1; step/curb -> 1 + step_cost;
/// plus clearance_weight * (1 - (d - 1) / R) within R = clearance_radius of an obstacle (d: distance in cells);
/// unknown -> unknownWeight() (above any known path) or COST_INF if unknown_traversable is false.
std::vector<double> cellWeights(const Grid& grid, const PlannerParams& p);
/// Weight of an unknown cell: larger than the cost of any path through known cells of the grid,
/// so a path only crosses unknown space when no known path exists.
double unknownWeight(const Grid& grid, const PlannerParams& p);
}  // namespace assistive_planner
