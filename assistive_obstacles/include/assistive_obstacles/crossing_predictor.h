#pragma once
// Crossing prediction (issue 22): the predictor lives in assistive_common/crossing_predictor.h (one
// place for its two users: the planner, which warns the wearer, and this package's benchmark, which
// scores the warnings; the planner cannot depend on this package: its tests need the simulator,
// whose trials need the planner). The names stay available here, for MoverTrack as the track type.
#include <assistive_common/crossing_predictor.h>

#include <assistive_obstacles/mover_tracker.h>

namespace assistive_obstacles
{
using assistive_common::AvoidSide;
using assistive_common::CrossingParams;
using assistive_common::CrossingPrediction;
using assistive_common::CrossingPredictor;
using assistive_common::Wearer;
}  // namespace assistive_obstacles
