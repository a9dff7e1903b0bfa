#pragma once
// Cue logic and vest bridge parameters: ONE table each (assistive_common/param_table.h). Each
// row is the field, its ROS parameter name, default, range, unit and text; the nodelets read
// every row, clamp by the ranges and README.md lists them (test_params).
#include <string>
#include <vector>

#include <assistive_common/param_table.h>

namespace assistive_tactile
{
// clang-format off
// X(type, field, ROS name, default, lo, hi, unit, text)
#define ASSISTIVE_CUE_PARAMS(X) \
  /* Guidance while walking (shoulder motors; the protocol page in README.md, issue 33) */ \
  X(double, guidance_min_waypoint_m, "guidance_min_waypoint_m", 0.3, 0.0, 20.0, "m", "guidance only when the waypoint is at least this far (the steering point runs on to the next place of a route, so guidance goes on up to the place itself)") \
  X(double, walking_speed_mps, "walking_speed_mps", 0.25, 0.0, 2.0, "m/s", "the wearer counts as walking above this speed (the planner's `walking_speed`): veer cues while walking, stop-and-turn cues while standing") \
  X(double, veer_on_deg, "veer_on_deg", 10.0, 1.0, 90.0, "deg", "a veer cue when the steering point lies further than this off the walking direction") \
  X(double, veer_step_deg, "veer_step_deg", 15.0, 1.0, 60.0, "deg", "a veer burst at level k (1..3) asks for k x this (15 / 30 / 45 deg: slightly, bear, sharply)") \
  X(double, turn_on_deg, "turn_on_deg", 60.0, 10.0, 170.0, "deg", "above this (while walking; standing: above `stand_turn_deg`) the cue is stop-and-turn") \
  X(double, stand_turn_deg, "stand_turn_deg", 15.0, 1.0, 170.0, "deg", "a standing wearer is turned on the spot when the steering point lies further than this off the body") \
  X(double, corner_veer_deg, "corner_veer_deg", 0.0, 0.0, 90.0, "deg", "a walker nearing a corner of the path ahead (the state's `path_ahead`) turning by more than this, up to 90 deg, whose leg out runs on 1.2 m or more, is walked on to it and asked to veer round it in stride, timed so that the arc (its speed over `veer_rate_deg`) begins where it meets the leg out, when that walk sweeps the body clear (0 = off, the default: on, shops and offices collided more, trials README \"A corner taken walking\")") \
  X(double, turn_step_deg, "turn_step_deg", 45.0, 10.0, 90.0, "deg", "a stop-and-turn buzz's strength: level k (1..3) for turns of about k x this (its length sets the angle: the wearer turns while it buzzes)") \
  X(double, stand_turn_near_deg, "stand_turn_near_deg", 12.0, 1.0, 170.0, "deg", "in a tight spot (the way ahead under `stand_near_m`, or a side under `side_free_m`) a standing wearer is turned on the spot until the steering point lies within this, before the tick says go") \
  X(double, go_clear_m, "go_clear_m", 1.0, 0.0, 5.0, "m", "a standing wearer whose walk along its facing would sweep the body into an obstacle within this (a shelf's corner, a jamb beside the walk's line) is turned to face the steering point first, when that way sweeps clear for longer, however few degrees off it stands (0 = off)") \
  X(double, go_side_m, "go_side_m", 0.3, 0.0, 2.0, "m", "a standing wearer with one side's free distance under this and the other at least 0.3 m freer side-steps away (short steps, three at most) before the go (0 = off)") \
  X(double, turn_go_clear_m, "turn_go_clear_m", 0.5, 0.0, 10.0, "m", "a standing wearer's stop-and-turn whose new way sweeps the body clear for this long, even when the turn comes out `turn_go_spread` off (or 8 deg at least), is followed by the walk-on tick at once (the wearer turns, then walks, and is not left standing while the turn is judged; a walk shorter than `short_walk_m` gets its timed stop); 0 = off, every turn waits to be judged") \
  X(double, turn_go_spread, "turn_go_spread", 0.25, 0.0, 1.0, "", "the part of a turn it may come out off by, for `turn_go_clear_m` (the population's turns spread by 15 %, lognormal, and its rates are learnt)") \
  X(double, stand_near_m, "stand_near_m", 2.5, 0.0, 10.0, "m", "the way ahead of a standing wearer counts as tight under this") \
  X(double, settle_timeout_s, "settle_timeout_s", 2.5, 0.2, 10.0, "s", "after a veer burst the next one waits until the veer was seen in the head's turn rate and steadied, or this long") \
  X(double, drift_aim_s, "drift_aim_s", 1.0, 0.0, 5.0, "s", "a veer is asked for the steering error expected when it is carried out (the walk's learnt drift over the wearer's reaction) plus the drift over this much more walking (the next error then lies on the other side)") \
  X(double, body_turn_rate_deg, "body_turn_rate_deg", 15.0, 1.0, 90.0, "deg/s", "the head turning faster than this is the body turning (a turn on the spot, a veer: 40-90 deg/s); slower is the head's own scan (+-8 deg over about 7 s: at most about 7 deg/s), which the body's facing leaves out") \
  X(double, body_walk_tau_s, "body_walk_tau_s", 0.5, 0.01, 10.0, "s", "walking, the body's facing fades to the walk chord within about this") \
  X(double, body_stand_tau_s, "body_stand_tau_s", 6.0, 0.0, 60.0, "s", "standing, the body's facing fades to the head's yaw within about this (the scan's mean; 0 = the head's yaw itself, as before)") \
  X(double, body_gyro_tau_s, "body_gyro_tau_s", 5.0, 0.01, 60.0, "s", "with the vest's gyro (`body_yaw_rate`), walking: the body's facing fades to the walk chord within about this (the gyro's bias)") \
  X(double, body_gyro_bias_tau_s, "body_gyro_bias_tau_s", 3.0, 0.0, 60.0, "s", "with the vest's gyro: its bias is learnt within about this of standing still (not walking, the head steady, no turn for 1 s, the gyro within 2 deg/s of its bias), and walking from the walk chord's pull (gain 1 / (4 `body_gyro_tau_s`^2)); 0 = not learnt") \
  X(double, turn_timeout_s, "turn_timeout_s", 4.0, 0.5, 20.0, "s", "after a stop-and-turn buzz the next cue waits until the buzz has ended and the head is still, or this long") \
  /* Doorways and gaps (the planner's passage_*): stop before, face the middle, walk straight through */ \
  X(double, passage_align_m, "passage_align_m", 0.9, 0.0, 5.0, "m", "a walker whose straight walk would miss a passage's middle by more than the room it has is stopped (a turn buzz towards the middle) so that it stands about this far before the middle (0 = off: ordinary steering through passages)") \
  X(double, passage_stand_m, "passage_stand_m", 2.0, 0.0, 10.0, "m", "a standing wearer this close to a passage's middle is turned on the spot until the middle lies within `passage_align_deg`, before the tick says go") \
  X(double, passage_align_deg, "passage_align_deg", 4.0, 0.5, 30.0, "deg", "standing before a passage: the middle must lie within this of the body's facing (`body_stand_tau_s`), or within what passes it inside half the passage's room") \
  X(double, passage_body_m, "passage_body_m", 0.35, 0.0, 1.0, "m", "the room to miss a passage's middle by is half its width less this: the body's half-width (0.18-0.26 m) and the middle's error on the 0.2 m cells (up to half a cell: the planner's width is honest, its middle is the free cells'); 0.25 with the free cells' width (0.2 m short) gave the same room; measured on homes 3001-3010 x6 and course seed 7 x20 (collisions per trial / completed): 0.25 3.07 / 45 %, 0.90 / 80 %; 0.30 2.85 / 43 %, 0.75 / 85 %; 0.35 2.60 / 38 %, 0.75 / 85 %; 0.40 2.75 / 38 %, 0.60 / 80 %") \
  X(double, passage_inside_m, "passage_inside_m", 0.6, 0.0, 2.0, "m", "closer than this to the middle the wearer is in the passage: ordinary steering again (a turn just beyond the passage is cued at once; a veer acts a reaction time later, past the jambs)") \
  X(double, passage_square_deg, "passage_square_deg", 20.0, 0.0, 90.0, "deg", "a passage is walked through within this of its axis (across its jamb-to-jamb line): a standing wearer further off the axis (seen from the middle) first walks to the point `passage_stage_m` before the middle on the axis, a walker crossing it more on the slant is stopped (through a 0.85 m doorway in a 0.15 m wall at 35 deg, a 0.25 m shoulder radius keeps 5 cm; 0 = off: the middle is faced from wherever the wearer stands)") \
  X(double, passage_stage_m, "passage_stage_m", 0.6, 0.2, 2.0, "m", "the point on a passage's axis a wearer off it walks to first, this far before the middle (nearer when that point lies closer than the body's radius to an obstacle)") \
  X(double, passage_clear_m, "passage_clear_m", 0.45, 0.0, 2.0, "m", "past a passage's middle by this the body has left its jambs: until then a walker in it is kept on its axis (a turn beyond waits, a stop is timed so that it stands clear) and a wearer standing in it faces the axis and steps out first (0 = off)") \
  X(double, short_walk_m, "short_walk_m", 2.5, 0.0, 10.0, "m", "a standing wearer told to go with less free floor ahead than this gets a stop timed from the go (it lands after the same walk whatever the wearer's reaction: it starts and stops a reaction late) so that it stands `alert_m` short of the obstacle (0 = off)") \
  X(double, start_accel, "start_accel", 1.2, 0.3, 5.0, "m/s^2", "a walker told to go speeds up at about this until its starts have shown its own (learnt from the walk's speed after a go), for the stop timed from a go; the fast end of gait initiation (0.5-1.2 m/s^2), so that an unknown wearer is stopped early") \
  X(double, min_intensity, "min_intensity", 0.4, 0.0, 1.0, "", "level 1's drive; levels 2 and 3 lie evenly up to 1 (0.4 / 0.7 / 1.0: steps of 1.4-1.75x, each well above the vibrotactile intensity JND)") \
  X(double, tick_period_s, "tick_period_s", 2.0, 0.5, 10.0, "s", "clear-walk-on: a tick on both shoulders this often while no other cue is due (a vest silent for two periods means stop)") \
  /* Lost at a blank view (issue 34): the VO cannot track a plain wall; a standing wearer is turned to look elsewhere */ \
  X(double, lost_turn_after_s, "lost_turn_after_s", 3.0, 0.0, 60.0, "s", "after this long of `NO_POSE` on fresh camera images (the wearer has stopped on the UNSURE pattern: a reaction of at most 1.5 s and its stop) a stop-and-turn buzz asks for a turn on the spot of `lost_turn_deg`, so that the camera sees something other than the plain wall or floor it lost itself on; 0 = off (UNSURE stays silent until the pose returns)") \
  X(double, lost_turn_deg, "lost_turn_deg", 180.0, 30.0, 180.0, "deg", "the first such turn, to the left, unless a stop-and-turn came shortly before the loss: then back to the facing before it, where the camera tracked and SLAM's keyframes look (180: the way back); each further one 90 deg more, the same way, `lost_turn_wait_s` after the last buzz ended") \
  X(double, lost_turn_wait_s, "lost_turn_wait_s", 6.0, 0.5, 60.0, "s", "a further look-elsewhere turn waits this long after the last buzz ended (the wearer's reaction, its turn, the VO's re-initialisation, the map's rebuilding and SLAM's search for the wearer in its map)") \
  X(int, lost_turns_max, "lost_turns_max", 3, 0, 20, "", "look-elsewhere turns per loss at most (with 180 first: the way back, a side, then the first view again); then UNSURE stays silent") \
  /* The body's predicted sweep (issue 33; needs the planner's grid) */ \
  X(double, sweep_radius_m, "sweep_radius_m", 0.24, 0.0, 1.0, "m", "the body's disc for the predicted sweep: its centre must stay this far from every obstacle cell's centre (a jamb's face lies inside the cell it fills, half a cell in on average); the population's shoulder radius is 0.18-0.26 m (0 = the sweep off: the rays alone, as before)") \
  X(double, sweep_spread_m, "sweep_spread_m", 0.1, 0.0, 1.0, "m/m", "the predicted sweep keeps the disc this much further from the obstacle cells per metre of the predicted walk (never more than the clearance the body has now less 3 cm): the walk strays from the prediction as it goes (heading noise of 1-3 deg/sqrt(m), a drift of up to 6 deg/m learnt only in part, veers carried out at the wrong size), and in 100 shop trials 37 of the 77 collisions after a stop came sooner after it than the wearer could react; 0 = the radius alone, as before") \
  X(double, sweep_cycle_s, "sweep_cycle_s", 0.1, 0.0, 1.0, "s", "the predictive stop: a walker is stopped when its committed walk, with a stop asked this much later (the next cycle) and felt its reaction later, would sweep the body into an obstacle") \
  X(double, veer_rate_deg, "veer_rate_deg", 60.0, 10.0, 180.0, "deg/s", "how fast a veer turns the walk, for the predicted sweep (a veer turns the head at 40-90 deg/s)") \
  /* Proximity (waist motors) and alert (all four) */ \
  X(double, alert_m, "alert_m", 0.5, 0.0, 10.0, "m", "free distance ahead under which all four motors fire") \
  X(double, proximity_m, "proximity_m", 1.0, alert_m, 10.0, "m", "free distance ahead under which proximity mode starts") \
  X(double, alert_reaction_s, "alert_reaction_s", 0.6, 0.0, 3.0, "s", "both distances grow by the walking speed times this (the walk during the wearer's reaction, 0.3-1.2 s in the wearer population, before the stop begins) and by the stop itself (v^2 / 2 `stop_decel`)") \
  X(double, stop_decel, "stop_decel", 2.0, 0.5, 10.0, "m/s^2", "how quickly a walker stops, for the distances above, until its stops on all four have shown its own (learnt from the walk's speed)") \
  X(double, hysteresis_m, "hysteresis_m", 0.1, 0.0, 1.0, "m", "a mode entered at d is left only above d + hysteresis_m") \
  X(double, side_free_m, "side_free_m", 0.6, 0.0, 10.0, "m", "free distance to a side that counts as room to side-step") \
  X(double, side_switch_m, "side_switch_m", 0.2, 0.0, 10.0, "m", "the other side must be this much freer to switch waist motor") \
  /* People crossing (NavigationState.crossing, issue 22): a waist cue or a stop, over the above */ \
  X(double, crossing_hold_s, "crossing_hold_s", 0.5, 0.0, 5.0, "s", "a crossing cue, once raised, lasts at least this long, and a side-step is not turned into the other side's sooner (the advice blinking off for a frame or flipping sides does not make the vest flicker)") \
  X(double, crossing_release_s, "crossing_release_s", 0.1, 0.0, 5.0, "s", "after the hold, the cue ends once the planner has advised nothing for this long (one frame without advice at 15 Hz is bridged)") \
  X(double, crossing_near_s, "crossing_near_s", 1.0, 0.0, 10.0, "s", "closest approach this soon or sooner: the crossing's waist cue at full intensity") \
  X(double, crossing_far_s, "crossing_far_s", 3.0, crossing_near_s, 10.0, "s", "closest approach this far off or farther: the crossing's waist cue at `min_intensity` (linear in between)") \
  /* Freshness of the planner state */ \
  X(double, state_timeout_s, "state_timeout_s", 0.5, 0.05, 10.0, "s", "no planner state for this long -> UNSURE, motors off") \
  /* 0.4 s keeps UNSURE within 0.5 s of a fault that only staleness reveals (a desynchronised pair */ \
  /* never reaches the VO): the last good image is up to a frame older than the fault, and the check */ \
  /* runs every 20 ms (0.5 gave 0.44-0.45 s in the fault suite). Clean cues: 0.014 s old (median). */ \
  X(double, max_input_age_s, "max_input_age_s", 0.4, 0.05, 10.0, "s", "a state whose `source_stamp` (camera image) is older than this at the current ROS time, or zero -> UNSURE; the heartbeat stops repeating the last cue then") \
  X(double, heartbeat_hz, "heartbeat_hz", 10.0, 1.0, 100.0, "Hz", "cue re-published at least this often (bridge stale guard)") \
  X(std::string, body_frame, "body_frame", "torso", {}, {}, "", "frame of the cue and of the markers' text")

#define ASSISTIVE_BRIDGE_PARAMS(X) \
  X(std::string, port, "port", "/dev/ttyUSB0", {}, {}, "", "serial device or the simulated vest's link") \
  X(int, baud, "baud", 57600, 9600, 921600, "bit/s", "a standard rate (another: 57600)") \
  X(double, resend_hz, "resend_hz", 20.0, 1.0, 200.0, "Hz", "COMMAND re-sent at this rate") \
  X(double, stale_s, "stale_s", 0.3, 0.05, 5.0, "s", "a cue drives the motors until `header.stamp + stale_s`, then all off; an older cue is ignored") \
  X(double, max_source_age_s, "max_source_age_s", 0.5, 0.05, 5.0, "s", "a motor-driving cue drives only until `source_stamp + max_source_age_s`; an older one is ignored") \
  X(double, reopen_s, "reopen_s", 1.0, 0.05, 60.0, "s", "retry period while the port is closed") \
  X(double, link_timeout_s, "link_timeout_s", 1.0, 0.1, 60.0, "s", "no STATUS from the vest for this long -> link WARN") \
  /* the forward ultrasonic ranger (RANGE packets, protocol version 3): HC-SR04 class limits */ \
  X(double, sonar_min_range, "sonar_min_range", 0.2, 0.0, 10.0, "m", "a range below this is rejected (not published), with a throttled diagnostic") \
  X(double, sonar_max_range, "sonar_max_range", 4.0, sonar_min_range, 20.0, "m", "a range above this is rejected (the vest reports no echo as its own status: published as +Inf)") \
  X(double, sonar_fov_deg, "sonar_fov_deg", 15.0, 1.0, 89.0, "deg", "the cone's full angle (`field_of_view` of `sonar/front`)") \
  X(double, sonar_timeout_s, "sonar_timeout_s", 0.5, 0.05, 60.0, "s", "no RANGE from a version-3 vest for this long -> ranger silent (ERROR)") \
  /* the vest's IMU (IMU packets, protocol version 5): the torso's turns for the cue logic */ \
  X(double, imu_timeout_s, "imu_timeout_s", 0.5, 0.05, 60.0, "s", "no IMU packet from a version-5 vest for this long -> IMU silent (WARN: the cue logic takes the body's turns from the head)") \
  /* without the right (CAP_SYS_NICE or an rtprio limit for the user, e.g. `@audio - rtprio 20` in */ \
  /* limits.conf) the bridge warns and runs the thread normally */ \
  X(int, realtime_priority, "realtime_priority", 10, 0, 99, "", "SCHED_FIFO priority of the housekeeping thread that sends the all-off at a cue's expiry (0 = normal scheduling)")
// clang-format on

/// Cue logic parameters. The table's initializers are the only defaults.
struct CueParams
{
  ASSISTIVE_PARAMS_BODY(ASSISTIVE_CUE_PARAMS)
};

/// Vest bridge parameters.
struct BridgeParams
{
  ASSISTIVE_PARAMS_BODY(ASSISTIVE_BRIDGE_PARAMS)
};

/// Clamps by the table, then a baud rate the serial port cannot set -> 57600. One message per
/// change (the nodelet logs them).
std::vector<std::string> clampParams(BridgeParams& p);

}  // namespace assistive_tactile
