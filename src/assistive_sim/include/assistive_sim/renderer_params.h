#pragma once
// Parameters of the online renderer nodelet (assistive_sim/renderer). The initializers are the
// only defaults; README.md lists them.
#include <string>

#include <assistive_sim/renderer.h>

namespace assistive_sim
{
struct RendererNodeParams
{
  std::string world = "course";  ///< shipped world name or a world YAML path
  std::string pose_source = "script";  ///< script (the world's walk), tf, or topic (`pose`)
  std::string world_frame = "gt_world";  ///< frame of the world (tf / topic poses are in it)
  /// tf mode: frame whose pose is rendered (a left optical frame: z forward, x right, y down).
  std::string camera_frame = "sim_camera_left_optical_frame";
  std::string left_frame = "camera_left_optical_frame";    ///< frame_id of the left outputs
  std::string right_frame = "camera_right_optical_frame";  ///< frame_id of the right outputs
  std::string imu_frame = "camera_link";
  double rate = 15.0;        ///< Hz, frames per second
  double imu_rate = 200.0;   ///< Hz (script mode)
  double sonar_rate = 20.0;  ///< Hz, the forward ultrasonic ranger (`sonar/front`); 0 = off
  std::string sonar_frame = "sonar_front";
  int width = 640;           ///< px
  int height = 480;          ///< px
  double focal = 500.0;      ///< px (fx = fy); principal point at the image centre
  double baseline = 0.12;    ///< m
  double noise_sigma = 2.0;  ///< gray levels
  double exposure_time = 0.0;  ///< s (motion blur when > 0)
  int seed = 1;
  bool loop = true;          ///< script mode: restart the walk at its end
  /// topic mode: render each pose as it arrives, stamped with the pose's stamp (no timer; the
  /// mobility trials' lock-step), instead of the latest pose at `rate`
  bool render_on_pose = false;
  /// People (issue 22) are rendered and heard where they are at this clock: < 0, the script's time
  /// (script mode) or the time since the nodelet started; >= 0, the frame's stamp (sim s) minus
  /// this (the mobility trials: the simulated time of a trial's t = 0).
  double people_time_origin = -1.0;
  /// The reference camera (issue 35): after each pair, the same pose's emitter-on pair (the
  /// pattern projector's dots) with the same stamp on `projected/{left,right}/{image_rect,camera_info}`.
  bool projector = false;
};

}  // namespace assistive_sim
