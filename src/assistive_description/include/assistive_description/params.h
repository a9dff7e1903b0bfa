#pragma once
// Parameters of the side-by-side stereo camera driver. The initializers are the only defaults;
// the nodelet reads every field as `pnh.param(name, p.x, p.x)` and then calls clamp().
#include <string>
#include <vector>

namespace assistive_description
{
struct StereoCameraParams
{
  /// V4L2 device path ("/dev/video0"), a bare index ("0"), or "synthetic" (built-in test pattern).
  std::string device = "/dev/video0";
  int width = 1280;               ///< full side-by-side frame width, px (both eyes)
  int height = 480;               ///< frame height, px
  double fps = 30.0;              ///< requested frame rate, Hz
  std::string fourcc = "MJPG";    ///< requested pixel format (4 characters, e.g. MJPG, YUYV)
  bool swap_halves = false;       ///< true when the camera puts the left eye in the right half
  double time_offset = 0.0;       ///< s, added to every capture stamp (negative = extra latency)
  double retry_period = 2.0;      ///< s between attempts to (re)open a missing or failed device
  std::string left_frame_id = "camera_left_optical_frame";
  std::string right_frame_id = "camera_right_optical_frame";
  std::string left_camera_name = "left";    ///< camera_info_manager names (checked in the YAML)
  std::string right_camera_name = "right";
  std::string left_camera_info_url;         ///< camera_info_manager URL, e.g. package://...
  std::string right_camera_info_url;
  double synthetic_disparity = 16.0;        ///< px, shift between the halves of "synthetic"

  /// Clamp out-of-range values to usable ones; returns one human-readable message per change.
  std::vector<std::string> clamp();
};

}  // namespace assistive_description
