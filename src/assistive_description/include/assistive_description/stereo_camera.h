#pragma once
// The ROS-free driver core: frame source -> split -> stamp -> mono8 -> rectify, with the
// retry timer for a missing or failed device. The nodelet calls grab() in its capture thread.
#include <assistive_description/camera_calibration.h>
#include <assistive_description/frame_source.h>
#include <assistive_description/params.h>
#include <assistive_description/rectifier.h>
#include <assistive_description/stereo_self_calibration.h>
#include <memory>
#include <string>
#include <vector>

namespace assistive_description
{
enum class GrabStatus
{
  OK,                ///< a stereo pair in the output
  WAITING_TO_RETRY,  ///< the device is closed and the retry period has not passed yet
  OPEN_FAILED,       ///< tried to open the device and failed (lastError())
  READ_FAILED,       ///< the device stopped delivering; closed, reopened after retry_period
  BAD_FRAME,         ///< a frame that cannot be split (odd width, unknown type); dropped
  STALE_STAMP,       ///< a frame whose stamp is not after the previous one; dropped
};
const char* toString(GrabStatus s);

struct StereoOutput
{
  double stamp = 0.0;          ///< wall-clock seconds, identical for both eyes
  cv::Mat left_raw, right_raw; ///< the halves as delivered (views into one frame)
  cv::Mat left_mono, right_mono;   ///< mono8, unrectified
  cv::Mat left_rect, right_rect;   ///< mono8, rectified (empty when !rectified)
  bool rectified = false;
  /// `emitter: alternate`: this pair was exposed with the projector's emitter on (judged by its
  /// dots, EmitterPhase); always false otherwise.
  bool emitter_on = false;
};

/// Stamps: source stamp + offset, strictly increasing; measures the frame rate.
class FrameStamper
{
public:
  explicit FrameStamper(double offset = 0.0) : offset_(offset) {}
  /// False (frame to drop) when the stamp is not after the previous accepted one.
  bool stamp(double source_stamp, double& out);
  /// Frames per second over the recent intervals (exponential average); 0 before two frames.
  double rate() const { return mean_interval_ > 0.0 ? 1.0 / mean_interval_ : 0.0; }
  void reset() { last_ = -1.0; mean_interval_ = 0.0; }

private:
  double offset_;
  double last_ = -1.0;
  double mean_interval_ = 0.0;
};

class StereoCamera
{
public:
  /// `emitter`: the switch `emitter: alternate` toggles after every frame (null: the frames are
  /// still told apart by their dots, the emitter left as the camera alternates it).
  StereoCamera(std::unique_ptr<FrameSource> source, const StereoCameraParams& params,
               std::unique_ptr<EmitterControl> emitter = nullptr);

  /// Build both rectifiers (once per calibration). Hard errors (uncalibrated, unknown model,
  /// left/right sizes differ) return false; doubtful pairs (right P(0,3) >= 0, different fx)
  /// succeed with messages in `warnings`.
  bool setCalibration(const CameraCalibration& left, const CameraCalibration& right,
                      std::string* error = nullptr, std::vector<std::string>* warnings = nullptr);
  bool calibrated() const { return left_.configured() && right_.configured(); }
  const Rectifier& leftRectifier() const { return left_; }
  const Rectifier& rightRectifier() const { return right_; }
  /// The online estimate of the right camera's rotation (null when `self_calibration` is off).
  const StereoSelfCalibration* selfCalibration() const { return self_cal_.get(); }
  /// Start from a correction kept from an earlier run (rad about the left optical x, y, z); the
  /// right maps are rebuilt with it. Ignored when self-calibration is off or not calibrated.
  void restoreSelfCalibration(const cv::Vec3d& w);
  /// Feeds a rectified pair from grab() to the self-calibration (after it was published: the
  /// estimate's few milliseconds stay out of the images' latency); a new correction goes into the
  /// right maps for the next frame. Nothing when `self_calibration` is off or `out` is not rectified.
  void selfCalibrate(const StereoOutput& out);
  /// True once after selfCalibrate() changed the correction in the right maps (to keep it).
  bool takeSelfCalibrationChange();

  /// One step of the capture loop. `now` is a monotonic time in seconds, used only for the
  /// retry timer. On OK, `out` holds the pair; when the calibration does not fit the frame,
  /// out.rectified is false and lastWarning() says why.
  GrabStatus grab(double now, StereoOutput& out);

  bool isOpen() const { return source_->isOpen(); }
  const FrameSource& source() const { return *source_; }
  FrameSource& source() { return *source_; }
  /// `emitter: alternate`: the judge of which frames had the emitter on.
  const EmitterPhase& emitterPhase() const { return phase_; }
  /// Why the last emitter switch failed (empty: it worked, or there is none).
  const std::string& emitterError() const { return emitter_error_; }
  const std::string& lastError() const { return last_error_; }
  const std::string& lastWarning() const { return last_warning_; }
  double frameRate() const { return stamper_.rate(); }
  unsigned long long frames() const { return frames_; }
  double nextRetry() const { return next_retry_; }

private:
  std::unique_ptr<FrameSource> source_;
  StereoCameraParams params_;
  std::unique_ptr<EmitterControl> emitter_;
  bool emitter_commanded_ = false;
  std::string emitter_error_;
  EmitterPhase phase_;
  Rectifier left_, right_;
  CameraCalibration right_loaded_;        // the right calibration as given, before any correction
  std::unique_ptr<StereoSelfCalibration> self_cal_;
  cv::Vec3d right_correction_ = cv::Vec3d::all(0);  // folded into right_'s maps
  bool self_cal_changed_ = false;
  bool rebuildRight(const cv::Vec3d& w);
  FrameStamper stamper_;
  double next_retry_ = -1e300;
  unsigned long long frames_ = 0;
  std::string last_error_, last_warning_;
  cv::Mat frame_;
};

}  // namespace assistive_description
