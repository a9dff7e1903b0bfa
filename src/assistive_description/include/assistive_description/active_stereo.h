#pragma once
// An active stereo camera (issue 35; the RealSense D4xx class): its infrared pair arrives over UVC
// as one interleaved 8-bit greyscale frame (Y8I), and its pattern projector's emitter is switched
// per frame, so that tracking gets frames without the projector's dots (they move with the head,
// not with the world) and disparity gets frames with them (plain walls and floors gain depth).
#include <memory>
#include <string>

#include <opencv2/core.hpp>

namespace assistive_description
{
/// Y8I: one 16-bit pixel per position, the left imager's 8 bits in the low byte and the right's
/// in the high byte. `frame` is either `height` x `width` of CV_8UC2 or CV_16UC1, or the raw
/// buffer of 2 x width x height bytes in any continuous CV_8UC1 shape (OpenCV's V4L2 back-end
/// hands a format it does not know over raw). `left`, `right`: new mono8 images. False with a
/// message for another size or type.
bool splitInterleaved(const cv::Mat& frame, int width, int height, cv::Mat& left, cv::Mat& right,
                      std::string* error = nullptr);

/// The fine texture of a mono8 image: the mean absolute Laplacian (3x3). The projector's dots
/// (a pixel or two across, a few pixels apart) raise it several times on plain surfaces.
double dotEnergy(const cv::Mat& mono8);

/**
 * Which frames were exposed with the emitter on, when the driver toggles the emitter every frame.
 * The toggle reaches the sensor an unknown number of frames later and a dropped frame shifts the
 * phase, so the commanded state is no guide: each frame is judged by its dot energy. Once frames
 * of both kinds have been seen with their energies apart by `contrast` (locked()), a frame is "on"
 * when its energy lies above the geometric middle of the two running levels (a dropped frame is
 * re-synchronised at once); before that, a jump by `contrast` against the previous frame decides,
 * and without one the phase simply alternates (in daylight the dots are washed out and both kinds
 * of frame look alike: either serves either purpose).
 */
class EmitterPhase
{
public:
  explicit EmitterPhase(double contrast = 1.3) : contrast_(contrast) {}
  /// This frame's dot energy -> was the emitter on?
  bool classify(double energy);
  bool locked() const;
  /// Frames whose judged state broke the alternation (drops, a lost phase), since the start.
  unsigned long long resyncs() const { return resyncs_; }
  void reset() { *this = EmitterPhase(contrast_); }

private:
  double contrast_;
  bool started_ = false, prev_on_ = false;
  double prev_energy_ = 0.0;
  double level_on_ = 0.0, level_off_ = 0.0;  ///< running energies of each kind (0: none yet)
  int seen_on_ = 0, seen_off_ = 0;
  unsigned long long resyncs_ = 0;
};

/// Switches a camera's emitter (the next exposure it reaches).
class EmitterControl
{
public:
  virtual ~EmitterControl() = default;
  /// False (and lastError()) when the device refused.
  virtual bool set(bool on) = 0;
  const std::string& lastError() const { return last_error_; }

protected:
  std::string last_error_;
};

/// The emitter through a UVC extension unit control (UVCIOC_CTRL_QUERY, SET_CUR of one byte: 1 on,
/// 0 off), as the D4xx's depth extension unit carries it (unit 3, selector 2 "emitter enabled" in
/// the public librealsense sources). The device node is opened on its own (the capture keeps
/// its own); a refused query is reported once and retried on the next call.
class V4l2EmitterControl : public EmitterControl
{
public:
  V4l2EmitterControl(std::string device, int unit, int selector);
  ~V4l2EmitterControl() override;
  bool set(bool on) override;

private:
  std::string device_;
  int unit_, selector_;
  int fd_ = -1;
};

}  // namespace assistive_description
