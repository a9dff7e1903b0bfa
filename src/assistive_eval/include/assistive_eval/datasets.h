#pragma once
// Readers for real stereo datasets, turned into rectified StereoFrames for import_dataset
// (issue 9): KITTI raw sync drives, EuRoC MAV folders, rectified pairs with ROS camera_info yaml.
// ROS-free (OpenCV, Eigen, yaml-cpp); library assistive_eval_datasets.
#include <assistive_eval/types.h>

#include <Eigen/Geometry>
#include <map>
#include <memory>
#include <string>
#include <vector>

namespace assistive_eval
{
/// A dataset on disk, read frame by frame. Every error is a std::runtime_error naming the file.
class DatasetSource
{
public:
  virtual ~DatasetSource() = default;
  virtual std::string kind() const = 0;
  virtual size_t size() const = 0;
  virtual bool hasGroundTruth() const = 0;
  /// Frame i: rectified mono8 left/right, calibration, stamp and (if known) the ground-truth pose
  /// of the rectified left optical frame in a gravity-aligned, z-up gt_world.
  virtual StereoFrame frame(size_t i) const = 0;
  /// One line on what the ground truth is (empty when there is none or nothing to say).
  virtual std::string truthNote() const { return std::string(); }
};
/// Which instant the KITTI ground truth describes (import_dataset --truth).
enum class KittiTruth
{
  ImageStamp,  ///< the OXTS pose moved to each left image's stamp with the OXTS velocity and rates
  Devkit       ///< the devkit convention: OXTS sample i as it is, for image i (up to 5 ms apart)
};
/// "image_stamp" / "devkit"; throws std::runtime_error on anything else.
KittiTruth parseKittiTruth(const std::string& s);
const char* toString(KittiTruth t);

struct DatasetOptions
{
  KittiTruth kitti_truth = KittiTruth::ImageStamp;
};
/// kind: "kitti", "euroc" or "pairs".
std::unique_ptr<DatasetSource> openDataset(const std::string& kind, const std::string& dir,
                                           const DatasetOptions& options = DatasetOptions());

// ---------------------------------------------------------------------------------------- KITTI
/// "KEY: v1 v2 ..." files (calib_*.txt). Non-numeric values (calib_time) are skipped.
std::map<std::string, std::vector<double>> readKittiCalibFile(const std::string& path);
/// "2011-09-26 13:02:25.967790592" -> seconds since the epoch (UTC).
double parseKittiTimestamp(const std::string& s);

struct OxtsPacket
{
  double lat = 0.0, lon = 0.0, alt = 0.0;      ///< deg, deg, m
  double roll = 0.0, pitch = 0.0, yaw = 0.0;   ///< rad
  double vf = 0.0, vl = 0.0, vu = 0.0;         ///< m/s, forward/left/up of the level (heading) frame
  double wf = 0.0, wl = 0.0, wu = 0.0;         ///< rad/s about the level frame's forward/left/up axes
};
/// oxts/data/*.txt in name order (30 values each).
std::vector<OxtsPacket> readOxtsFolder(const std::string& oxts_dir);
/// KITTI devkit convertOxtsToPose: Mercator with scale cos(lat0), R = Rz(yaw) Ry(pitch) Rx(roll);
/// absolute IMU poses in the Mercator frame (x east, y north, z up). Not relative.
std::vector<Eigen::Isometry3d> oxtsToImuPoses(const std::vector<OxtsPacket>& oxts);
/// The IMU poses of oxtsToImuPoses (same Mercator frame, scale from oxts[0]) at the image stamps:
/// for each stamp the nearest OXTS sample k (at most `max_offset_s` away, else std::runtime_error)
/// is moved by dt = stamp - oxts_stamps[k] with its own velocity (vf, vl, vu) and rates (wf, wl,
/// wu) held constant over dt: rotation Exp(dt w) * R_k, horizontal position along the arc of
/// constant speed and yaw rate wu, vertical at vu. Exact for constant velocity and turn rate; the
/// error of a constant acceleration a is a dt^2 / 2 (< 0.02 mm at 1 m/s^2, |dt| <= 5 ms),
/// against a dt (T - dt) / 2 (0.24 mm) for interpolating between neighbouring samples T = 0.1 s
/// apart, which also needs a sample on both sides of every stamp (not true at a clip's ends).
std::vector<Eigen::Isometry3d> oxtsToImuPosesAt(const std::vector<OxtsPacket>& oxts,
                                                const std::vector<double>& oxts_stamps,
                                                const std::vector<double>& stamps, double max_offset_s = 0.05);
/// "YYYY-MM-DD hh:mm:ss.f" lines of a timestamps.txt -> seconds (empty lines skipped).
std::vector<double> readKittiTimestamps(const std::string& path);

struct KittiRawCalib
{
  StereoCalib calib;                                         ///< from P_rect_00 / P_rect_01
  Eigen::Isometry3d T_cam0_imu = Eigen::Isometry3d::Identity();  ///< R_rect_00 * T_cam0_velo * T_velo_imu
};
/// Reads calib_cam_to_cam.txt (+ calib_velo_to_cam.txt and calib_imu_to_velo.txt when
/// `with_imu`) from a drive folder or its parent.
KittiRawCalib readKittiRawCalib(const std::string& dir, bool with_imu);

/// Ground truth of the rectified cam0 in the devkit convention: poses relative to frame 0,
/// expressed in cam0 (x right, y down, z forward). cam_i = T_cam_imu * imu0^-1 * imu_i * T_imu_cam.
std::vector<Eigen::Isometry3d> kittiCam0PosesDevkit(const std::vector<Eigen::Isometry3d>& imu_poses,
                                                    const Eigen::Isometry3d& T_cam0_imu);
/// The same poses in a gravity-aligned gt_world (z up, x = the camera's horizontal heading at
/// frame 0, origin `cam_height` m below the camera at frame 0).
std::vector<Eigen::Isometry3d> kittiCam0PosesWorld(const std::vector<Eigen::Isometry3d>& imu_poses,
                                                   const Eigen::Isometry3d& T_cam0_imu, double cam_height = 1.65);

// ---------------------------------------------------------------------------------------- EuRoC
struct EurocCamera
{
  Eigen::Isometry3d T_BS = Eigen::Isometry3d::Identity();  ///< sensor -> body
  int width = 0, height = 0;
  double fu = 0, fv = 0, cu = 0, cv = 0;
  std::vector<double> dist;  ///< radial-tangential k1 k2 p1 p2
};
EurocCamera readEurocSensorYaml(const std::string& path);

/// Stereo rectification of a calibrated pair (OpenCV stereoRectify, alpha 0, zero disparity).
struct StereoRectifier
{
  StereoCalib calib;                                           ///< rectified
  Eigen::Matrix3d R_rect_raw0 = Eigen::Matrix3d::Identity();   ///< rectified cam0 <- raw cam0 (R1)
  cv::Mat map0x, map0y, map1x, map1y;
  void rectify(const cv::Mat& raw0, const cv::Mat& raw1, cv::Mat& out0, cv::Mat& out1) const;
};
/// `T_c1_c0` maps cam0 coordinates to cam1 coordinates.
StereoRectifier makeStereoRectifier(const cv::Mat& K0, const cv::Mat& D0, const cv::Mat& K1, const cv::Mat& D1,
                                    const cv::Size& size, const Eigen::Isometry3d& T_c1_c0);

}  // namespace assistive_eval
