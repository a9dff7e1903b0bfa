#pragma once
// Reading and writing stereo bags (README "Topics of a stereo bag"). Library assistive_eval_bag.
// The writer is used by render_bag and import_dataset; the reader by every stage's benchmark.
//
//   assistive_eval::StereoBagReader reader("run.bag");
//   assistive_eval::StereoFrame f;
//   while (reader.next(f)) { ... f.left, f.right, f.calib, f.gt_pose, f.imu ... }
//   assistive_eval::OccupancyGrid truth;
//   if (reader.readOccupancy(truth)) { ... }
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include <assistive_eval/types.h>

namespace rosbag
{
class Bag;
class View;
class MessageInstance;
}  // namespace rosbag

namespace assistive_eval
{
/// Topic and frame names (defaults = the README contract).
struct StereoBagTopics
{
  std::string left_image = "/stereo/left/image_rect";
  std::string right_image = "/stereo/right/image_rect";
  std::string left_info = "/stereo/left/camera_info";
  std::string right_info = "/stereo/right/camera_info";
  std::string imu = "/imu/data";
  std::string gt_odom = "/ground_truth/odom";
  /// The closed-loop trials' truth (`mobility_trials --record`): geometry_msgs/PoseStamped of the left
  /// optical frame in gt_world, one per rendered frame; read when the bag has no gt_odom (velocity by
  /// central differences).
  std::string gt_pose = "/sim/camera_pose";
  std::string gt_occupancy = "/ground_truth/occupancy";
  std::string gt_depth = "/ground_truth/left/depth";  ///< optional, 32FC1 (m)
  std::string tf = "/tf";
  std::string left_frame = "camera_left_optical_frame";
  std::string right_frame = "camera_right_optical_frame";
  std::string imu_frame = "camera_link";
  std::string sonar = "/sonar/front";       ///< sensor_msgs/Range of the vest's forward ranger
  std::string sonar_frame = "sonar_front";
  std::string gt_world_frame = "gt_world";
  std::string gt_link_frame = "gt_camera_link";
  std::string gt_left_frame = "gt_camera_left_optical_frame";
  /// An active camera's emitter-on pairs (issue 35: the pattern projector's dots, for disparity);
  /// the topics above carry its emitter-off pairs (for tracking), as a passive camera's.
  std::string projected_left_image = "/stereo/projected/left/image_rect";
  std::string projected_right_image = "/stereo/projected/right/image_rect";
  std::string projected_left_info = "/stereo/projected/left/camera_info";
  std::string projected_right_info = "/stereo/projected/right/camera_info";
  /// The same names with the emitter-on pairs as the stereo images (a reader of those frames).
  StereoBagTopics projected() const
  {
    StereoBagTopics t = *this;
    t.left_image = projected_left_image;
    t.right_image = projected_right_image;
    t.left_info = projected_left_info;
    t.right_info = projected_right_info;
    return t;
  }
};

/// Does the bag at `path` hold any message on `topic`? (false when it cannot be opened)
bool bagHasTopic(const std::string& path, const std::string& topic);

/// One ranger reading of `/sonar/front` (sensor_msgs/Range): range in m, +Inf = no echo.
struct RangeSample
{
  double stamp = 0.0;
  double range = 0.0;
  double field_of_view = 0.0;  ///< rad
  double min_range = 0.0, max_range = 0.0;
  std::string frame_id;
};

/// Writes stereo bags. Messages are written with bag time = their stamp.
class StereoBagWriter
{
public:
  /// Opens (truncates) `path`; throws std::runtime_error on failure.
  explicit StereoBagWriter(const std::string& path, const StereoBagTopics& topics = {});
  ~StereoBagWriter();
  StereoBagWriter(const StereoBagWriter&) = delete;
  StereoBagWriter& operator=(const StereoBagWriter&) = delete;

  /// Left/right mono8 images + both camera_infos (+ frame.gt_depth on gt_depth when not empty) (rectified: D = 0, R = I, right P[3] = -fx*B).
  /// When frame.has_gt_pose, also writes /ground_truth/odom and the gt tf chain
  /// (gt_world -> gt_camera_link -> gt_camera_left_optical_frame). frame.imu is written too.
  void writeFrame(const StereoFrame& frame);
  /// An emitter-on pair: its images and camera_infos on the `projected_*` topics (nothing else:
  /// the IMU and the truth run on the emitter-off frames' clock).
  void writeProjectedFrame(const StereoFrame& frame);
  /// Ground truth only (odom + tf) for a stamp; pose of the left optical frame in gt_world.
  void writeGroundTruth(double stamp, const Eigen::Isometry3d& T_world_left_optical,
                        const Eigen::Vector3d& velocity = Eigen::Vector3d::Zero());
  void writeImu(const ImuSample& sample);
  /// One ranger ping as sensor_msgs/Range (ULTRASOUND): `range` in m, or +Inf for "no echo
  /// within max_range" (REP-117); field of view in rad, limits in m.
  void writeRange(double stamp, double range, double field_of_view, double min_range, double max_range);
  /// Ground-truth occupancy (written once per bag, latched semantics).
  void writeOccupancy(const OccupancyGrid& grid, double stamp);
  /// A std_msgs/String on `topic` (e.g. render_bag's /sim/camera_errors: what the simulator applied).
  void writeString(const std::string& topic, const std::string& text, double stamp);
  void close();

  /// camera_link -> left optical transform used for the gt tf chain (default linkToLeftOptical()).
  void setLinkToLeftOptical(const Eigen::Isometry3d& t) { link_to_left_ = t; }

private:
  std::unique_ptr<rosbag::Bag> bag_;
  StereoBagTopics topics_;
  Eigen::Isometry3d link_to_left_;
  uint32_t seq_ = 0;
  uint32_t projected_seq_ = 0;
};

/// Iterates the stereo frames of a bag in stamp order. Left and right images are paired by
/// exact header stamp; calibration comes from the camera_infos (the latest one at or before the
/// frame, else the first one); the gt pose from /ground_truth/odom at the same stamp (within
/// 1 ms); IMU samples are those after the previous frame up to this frame.
/// Images must be mono8; rgb8, bgr8, rgba8, bgra8 and mono16 are converted to mono8 with one
/// warning line per encoding on stderr. There is no default calibration.
class StereoBagReader
{
public:
  /// Throws std::runtime_error when the bag cannot be opened, has no left or right image topic,
  /// no left or right camera_info, or a camera_info with an unusable calibration (non-finite or
  /// non-positive fx, fy; right P without a positive baseline).
  explicit StereoBagReader(const std::string& path, const StereoBagTopics& topics = {});
  ~StereoBagReader();
  StereoBagReader(const StereoBagReader&) = delete;
  StereoBagReader& operator=(const StereoBagReader&) = delete;

  /// Next stereo frame; false at the end of the bag. Throws std::runtime_error (naming the topic
  /// and stamp) on an image that is malformed or of an unsupported encoding, on left/right images
  /// of different sizes, and on images of another size than the camera_info's width x height.
  bool next(StereoFrame& frame);
  /// Restart from the first frame.
  void rewind();
  /// Number of left images in the bag (an upper bound on the number of frames).
  size_t size() const { return n_left_; }
  /// Whether the bag holds ground-truth odometry / per-frame depth.
  bool hasGroundTruth() const { return !gt_.empty(); }
  bool hasDepth() const { return has_depth_; }
  /// Reads the (last) ground-truth occupancy grid; false when the bag has none.
  bool readOccupancy(OccupancyGrid& grid) const;
  /// All ranger readings (`topics.sonar`) in stamp order; false when the bag has none.
  bool readRanges(std::vector<RangeSample>& out) const;
  /// All IMU samples of the bag in stamp order.
  const std::vector<ImuSample>& imuSamples() const { return imu_; }
  /// All ground-truth poses (stamp, pose of the left optical frame in gt_world).
  const std::vector<std::pair<double, Eigen::Isometry3d>>& groundTruth() const { return gt_; }
  /// Called on every frame before next() returns it: what the device's camera driver does to a
  /// pair before the stages see it (the benchmarks' `--self-calibrate`: the driver's correction of
  /// the right camera's rotation, issue 36).
  void setFrameFilter(std::function<void(StereoFrame&)> filter) { filter_ = std::move(filter); }

private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
  StereoBagTopics topics_;
  size_t n_left_ = 0;
  std::vector<ImuSample> imu_;
  std::vector<std::pair<double, Eigen::Isometry3d>> gt_;
  std::vector<Eigen::Vector3d> gt_vel_;
  std::vector<std::pair<double, StereoCalib>> calibs_;
  size_t imu_next_ = 0;
  std::function<void(StereoFrame&)> filter_;
  bool has_depth_ = false;
  bool first_ = true;
};

/// For the benchmark CLIs: the reader of `path`, or null after "<program>: cannot read <path>:
/// <why>" on stderr (the CLI then exits with status 1).
std::unique_ptr<StereoBagReader> openStereoBag(const std::string& program, const std::string& path,
                                               const StereoBagTopics& topics = {});
/// The last std_msgs/String on `topic` in the bag at `path` (render_bag's `/sim/camera_errors`:
/// the rig's true errors as one JSON object); empty when there is none.
std::string readBagString(const std::string& path, const std::string& topic = "/sim/camera_errors");
/// For the benchmarks' `--self-calibrate`: "; truth ..., error of the applied ..." (deg, pitch /
/// yaw / roll) against the right camera's rotation in `camera_errors_json` (render_bag's
/// `/sim/camera_errors`); empty when it does not give one.
std::string rightRotationAgainstTruth(const std::string& camera_errors_json, const double applied_deg[3]);
/// The rolling shutter's readout (s) in `camera_errors_json` (render_bag's `/sim/camera_errors`:
/// the sensor's, as a data sheet gives it; 0 for a global shutter); -1 when it does not give one.
double rollingShutterReadout(const std::string& camera_errors_json);
/// reader.next(frame) for the benchmark CLIs: a malformed image (encoding, size) prints
/// "<program>: <path>: <why>" on stderr and exits with status 1 (a clear error, not an abort).
bool nextFrameOrExit(StereoBagReader& reader, StereoFrame& frame, const std::string& program,
                     const std::string& path);
}  // namespace assistive_eval
