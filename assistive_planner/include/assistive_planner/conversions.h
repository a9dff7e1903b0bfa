#pragma once
// Message conversions (nodelet target only; the core stays ROS-free).

#include <vector>

#include <assistive_msgs/MoverArray.h>
#include <assistive_msgs/NavigationState.h>
#include <geometry_msgs/PointStamped.h>
#include <nav_msgs/OccupancyGrid.h>
#include <nav_msgs/Path.h>
#include <visualization_msgs/MarkerArray.h>

#include <assistive_common/code_grid_msg.h>

#include "assistive_planner/grid.h"
#include "assistive_planner/planner.h"

namespace assistive_planner
{
/// Grid <-> OccupancyGrid: the one conversion of the shared grid (code_grid_msg.h). fromMsg(msg, out)
/// returns false (and leaves `out` empty) if the grid is malformed or rotated (the planner needs a
/// grid aligned with its frame); toMsg(grid, header) for tests and tools.
using assistive_common::fromMsg;
using assistive_common::toMsg;
/// Planner output -> NavigationState (header: world frame and stamp; source_stamp: the grid's stamp).
assistive_msgs::NavigationState toMsg(const PlanOutput& out, const std_msgs::Header& header, const ros::Time& source_stamp);
nav_msgs::Path toPathMsg(const PlanOutput& out, const std_msgs::Header& header);
geometry_msgs::PointStamped toWaypointMsg(const PlanOutput& out, const std_msgs::Header& header);
/// MoverArray -> tracks for the crossing warning (position, velocity, covariance; movers with a
/// non-finite value are dropped). The frame is the caller's to check.
std::vector<MoverState> fromMsg(const assistive_msgs::MoverArray& msg);
/// Motion vector (arrow), search triangle (line strip), waypoint (sphere), and the crossing warning
/// (the warned mover's predicted path to the closest approach and the advice as text; deleted when none).
visualization_msgs::MarkerArray toMarkers(const PlanOutput& out, const std_msgs::Header& header);
}  // namespace assistive_planner
