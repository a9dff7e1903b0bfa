#pragma once
// The simulator renders into the evaluation package's plain types (assistive_eval/types.h): one
// contract for the stereo frame, the occupancy grid and its cell codes between the renderer, the
// bag reader/writer and every benchmark. Named here so the simulator's code reads as before.
#include <assistive_eval/types.h>

namespace assistive_sim
{
using assistive_eval::CELL_FREE;
using assistive_eval::CELL_OBSTACLE;
using assistive_eval::CELL_STEP;
using assistive_eval::CELL_UNKNOWN;
using assistive_eval::ImuSample;
using assistive_eval::linkToLeftOptical;
using assistive_eval::OccupancyGrid;
using assistive_eval::StereoCalib;
using assistive_eval::StereoFrame;
}  // namespace assistive_sim
