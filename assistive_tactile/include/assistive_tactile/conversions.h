#pragma once

#include <array>

#include <assistive_msgs/NavigationState.h>
#include <assistive_msgs/TactileCue.h>
#include <ros/time.h>

#include "assistive_tactile/cue_logic.h"

namespace assistive_tactile
{
/// Planner state -> cue logic input (source_time from source_stamp; NaN when it is zero).
NavInput fromMsg(const assistive_msgs::NavigationState& msg);

/// Cue -> message; stamp = decision time, source_stamp copied from the planner state.
assistive_msgs::TactileCue toMsg(const Cue& cue, const ros::Time& stamp, const ros::Time& source_stamp,
                                 const std::string& frame_id);

/// Message -> cue (mode, intensities clamped to 0..1, NaN -> 0, reason).
Cue fromMsg(const assistive_msgs::TactileCue& msg);

}  // namespace assistive_tactile
