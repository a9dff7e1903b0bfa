#pragma once
// ROS glue of the evaluation CLIs: nav_msgs/Odometry and nav_msgs/OccupancyGrid from bags into
// the ROS-free evaluation types.
#include <assistive_eval/map_score.h>
#include <assistive_eval/trajectory.h>

#include <string>
#include <vector>

namespace assistive_eval
{
namespace cli
{
/// All nav_msgs/Odometry of `topic`, in bag order. `child_frame` receives the first message's
/// child_frame_id. Throws when the bag cannot be opened or the topic is absent / of another type.
Trajectory readOdometry(const std::string& bag, const std::string& topic, std::string* child_frame = nullptr);

/// Live mode: subscribes to two nav_msgs/Odometry topics (needs a ROS master) and collects poses
/// until `duration_s` of wall time passed since the first message (<= 0: until Ctrl-C). Calls
/// ros::init itself. Child frames are returned like readOdometry's.
void collectLive(int argc, char** argv, const std::string& gt_topic, const std::string& est_topic, double duration_s,
                 Trajectory& gt, Trajectory& est, std::string* gt_child, std::string* est_child);

/// A grid message with its stamp, frame, and the full pose of its origin.
struct StampedGrid
{
  double stamp = 0.0;
  std::string frame_id;
  Eigen::Isometry2d origin = Eigen::Isometry2d::Identity();  ///< pose of cell (0,0)'s corner in frame_id
  Grid grid;  ///< origin_x = origin_y = 0: coordinates relative to `origin`
};
/// All nav_msgs/OccupancyGrid of `topic` (at most `max_count` evenly spaced ones when > 0).
std::vector<StampedGrid> readGrids(const std::string& bag, const std::string& topic, size_t max_count = 0);
/// Topics of a bag with their types.
std::vector<std::pair<std::string, std::string>> bagTopics(const std::string& bag);

}  // namespace cli
}  // namespace assistive_eval
