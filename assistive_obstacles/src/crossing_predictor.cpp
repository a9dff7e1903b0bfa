// The crossing predictor is header only (assistive_common/crossing_predictor.h, issue 22); this file
// keeps the forwarding header compiled with the core library.
#include <assistive_obstacles/crossing_predictor.h>
