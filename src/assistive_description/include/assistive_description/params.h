#pragma once
// Parameters of the side-by-side stereo camera driver: ONE table (assistive_common/param_table.h).
// Each row is the field, its ROS parameter name, default, range, unit and text; the nodelet
// reads every row, then calls clamp(); README.md lists them (test_params).
#include <string>
#include <vector>

#include <assistive_common/param_table.h>

namespace assistive_description
{
// clang-format off
// X(type, field, ROS name, default, lo, hi, unit, text)
#define ASSISTIVE_STEREO_CAMERA_PARAMS(X) \
  X(std::string, device, "device", "/dev/video0", {}, {}, "", "V4L2 path, a bare index (`0`), or `synthetic` (a built-in textured plane at `synthetic_disparity`, paced at `fps`; for demos and tests); empty: /dev/video0") \
  X(int, width, "width", 1280, 2, 8192, "px", "full side-by-side frame width (both eyes; an odd width is made even); `interleaved`: each eye's") \
  X(int, height, "height", 480, 1, 8192, "px", "frame height") \
  X(double, fps, "fps", 30.0, 0.5, 240.0, "Hz", "requested rate; also the expected rate in diagnostics") \
  X(std::string, fourcc, "fourcc", "MJPG", {}, {}, "", "pixel format asked from the camera, 4 characters (MJPG gives the full rate on USB 2; another length: MJPG)") \
  X(bool, swap_halves, "swap_halves", false, {}, {}, "", "true when the camera puts the left eye in the right half (a positive right `P[3]` in the calibration is reported as a hint)") \
  /* An active camera (issue 35, the D4xx class): its infrared pair interleaved, its emitter per frame */ \
  X(std::string, layout, "layout", "side_by_side", {}, {}, "", "`side_by_side` (both eyes in one wide frame) or `interleaved` (Y8I: each pixel's low byte the left eye, its high byte the right; use `fourcc` `Y8I `); another: side_by_side") \
  X(std::string, emitter, "emitter", "none", {}, {}, "", "`none` (a passive pair, or the emitter left as the camera has it) or `alternate` (the driver switches the projector's emitter every frame; the frames judged emitter-on by their dots go to `projected/{left,right}/image_rect`, the others to `{left,right}/image_rect`); another: none") \
  X(int, emitter_xu_unit, "emitter_xu_unit", 3, 0, 255, "", "`alternate`: the UVC extension unit that switches the emitter (the D4xx's depth unit)") \
  X(int, emitter_xu_selector, "emitter_xu_selector", 2, 0, 255, "", "`alternate`: its control (one byte: 1 on, 0 off; the D4xx's emitter enabled)") \
  /* Stamps are the driver's V4L2 buffer time (monotonic clock) moved to the wall clock, or the */ \
  /* wall clock at capture when the driver gives none. Frames whose stamp is not after the */ \
  /* previous one are dropped. */ \
  X(double, time_offset, "time_offset", 0.0, -1.0, 1.0, "s", "added to every capture stamp (negative: extra latency)") \
  X(double, retry_period, "retry_period", 2.0, 0.1, 3600.0, "s", "a missing, refusing or failed device is (re)opened this often") \
  X(std::string, left_frame_id, "left_frame_id", "camera_left_optical_frame", {}, {}, "", "frame of the left image") \
  X(std::string, right_frame_id, "right_frame_id", "camera_right_optical_frame", {}, {}, "", "frame of the right image") \
  X(std::string, left_camera_name, "left_camera_name", "left", {}, {}, "", "camera_info_manager name (checked in the calibration file)") \
  X(std::string, right_camera_name, "right_camera_name", "right", {}, {}, "", "camera_info_manager name of the right eye") \
  /* The shipped config/{left,right}.yaml are EXAMPLES for a 640x480-per-eye camera with a 0.12 m */ \
  /* baseline, not a calibration of your camera. */ \
  X(std::string, left_camera_info_url, "left_camera_info_url", "", {}, {}, "", "calibration file (camera_info_manager URL, e.g. package://...)") \
  X(std::string, right_camera_info_url, "right_camera_info_url", "", {}, {}, "", "calibration file of the right eye") \
  X(double, synthetic_disparity, "synthetic_disparity", 16.0, 0.0, width / 4.0, "px", "disparity between the halves of `device:=synthetic`") \
  /* Online self-calibration (issue 36): the right camera's small rotation against the rectified */ \
  /* rig, from matched features' vertical offsets, folded into the right rectification map. */ \
  X(bool, self_calibration, "self_calibration", true, {}, {}, "", "estimate the right camera's rotation online and undo it in the rectification (README: self-calibration); a perfect rig is left untouched") \
  X(int, self_calibration_every, "self_calibration_every", 5, 1, 1000, "frames", "one pair in this many feeds the estimate (about 7 ms each: 4-5 % of a core at 30 pairs a second)") \
  X(std::string, self_calibration_file, "self_calibration_file", "", {}, {}, "", "where the correction is kept across runs (YAML); empty: `$ROS_HOME/self_calibration_<right_camera_name>.yaml`; `none`: not kept")
// clang-format on

struct StereoCameraParams
{
  ASSISTIVE_PARAMS_BODY(ASSISTIVE_STEREO_CAMERA_PARAMS)

  /// Clamps by the table, then the rules a range cannot say (even width, 4-character fourcc,
  /// non-empty device); returns one human-readable message per change.
  std::vector<std::string> clamp();
};

}  // namespace assistive_description
