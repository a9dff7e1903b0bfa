#include <assistive_description/side_by_side.h>
#include <assistive_description/stereo_camera.h>

#include <cmath>
#include <sstream>

namespace assistive_description
{
const char* toString(GrabStatus s)
{
  switch (s)
  {
    case GrabStatus::OK: return "OK";
    case GrabStatus::WAITING_TO_RETRY: return "WAITING_TO_RETRY";
    case GrabStatus::OPEN_FAILED: return "OPEN_FAILED";
    case GrabStatus::READ_FAILED: return "READ_FAILED";
    case GrabStatus::BAD_FRAME: return "BAD_FRAME";
    case GrabStatus::STALE_STAMP: return "STALE_STAMP";
  }
  return "?";
}

bool FrameStamper::stamp(double source_stamp, double& out)
{
  const double s = source_stamp + offset_;
  if (!std::isfinite(s) || (last_ >= 0.0 && s <= last_)) return false;
  if (last_ >= 0.0)
  {
    const double dt = s - last_;
    // Exponential average over ~10 frames; a gap of more than 5 s restarts it.
    if (mean_interval_ <= 0.0 || dt > 5.0)
      mean_interval_ = dt;
    else
      mean_interval_ += 0.1 * (dt - mean_interval_);
  }
  last_ = s;
  out = s;
  return true;
}

StereoCamera::StereoCamera(std::unique_ptr<FrameSource> source, const StereoCameraParams& params,
                           std::unique_ptr<EmitterControl> emitter)
  : source_(std::move(source)), params_(params), emitter_(std::move(emitter)), stamper_(params.time_offset)
{
  if (params_.self_calibration)
  {
    StereoSelfCalibration::Options o;
    o.every_n_frames = params_.self_calibration_every;
    self_cal_ = std::make_unique<StereoSelfCalibration>(o);
  }
}

bool StereoCamera::rebuildRight(const cv::Vec3d& w)
{
  CameraCalibration c = right_loaded_;
  c.R = StereoSelfCalibration::correctionRotation(w) * c.R;
  Rectifier r;
  if (!r.configure(c))
    return false;
  right_ = r;
  right_correction_ = w;
  return true;
}

void StereoCamera::restoreSelfCalibration(const cv::Vec3d& w)
{
  if (!self_cal_ || !calibrated())
    return;
  self_cal_->setApplied(w);
  rebuildRight(w);
}

bool StereoCamera::takeSelfCalibrationChange()
{
  const bool changed = self_cal_changed_;
  self_cal_changed_ = false;
  return changed;
}

bool StereoCamera::setCalibration(const CameraCalibration& left, const CameraCalibration& right,
                                  std::string* error, std::vector<std::string>* warnings)
{
  std::string err;
  Rectifier l, r;
  if (!l.configure(left, &err))
  {
    if (error) *error = "left: " + err;
    return false;
  }
  if (!r.configure(right, &err))
  {
    if (error) *error = "right: " + err;
    return false;
  }
  if (left.width != right.width || left.height != right.height)
  {
    if (error) *error = "left and right calibrations are for different image sizes";
    return false;
  }
  if (warnings)
  {
    if (!(right.P(0, 3) < 0.0))
      warnings->push_back("right P[3] (= -fx * baseline) is not negative: halves swapped "
                          "(swap_halves) or left/right calibration files exchanged?");
    if (std::abs(left.P(0, 0) - right.P(0, 0)) > 1e-6 || std::abs(left.P(1, 2) - right.P(1, 2)) > 1e-6)
      warnings->push_back("left and right rectified P differ in fx or cy: not a rectified pair");
    if (left.P(0, 3) != 0.0)
      warnings->push_back("left P[3] is not 0: the left camera should be the reference");
  }
  left_ = l;
  right_ = r;
  // A new calibration (a checkerboard's) replaces whatever was learnt against the old one.
  if (right != right_loaded_ && self_cal_)
  {
    self_cal_->reset();
    self_cal_->setApplied(cv::Vec3d::all(0));
  }
  right_loaded_ = right;
  right_correction_ = cv::Vec3d::all(0);
  return true;
}

void StereoCamera::selfCalibrate(const StereoOutput& out)
{
  if (!self_cal_ || !out.rectified)
    return;
  const CameraCalibration& rc = right_.rectifiedCalibration();
  const RectifiedModel model{rc.P(0, 0), rc.P(1, 1), rc.P(0, 2), rc.P(1, 2)};
  self_cal_->addFrame(out.left_rect, out.right_rect, model);
  // A new correction goes into the right maps from the next frame on.
  if (self_cal_->applied() != right_correction_ && rebuildRight(self_cal_->applied()))
    self_cal_changed_ = true;
}

GrabStatus StereoCamera::grab(double now, StereoOutput& out)
{
  out.rectified = false;
  if (!source_->isOpen())
  {
    if (now < next_retry_) return GrabStatus::WAITING_TO_RETRY;
    if (!source_->open())
    {
      last_error_ = source_->lastError();
      next_retry_ = now + params_.retry_period;
      return GrabStatus::OPEN_FAILED;
    }
    stamper_.reset();
    phase_.reset();
  }
  double stamp = 0.0;
  if (!source_->read(frame_, stamp))
  {
    last_error_ = source_->lastError();
    source_->close();
    next_retry_ = now + params_.retry_period;
    return GrabStatus::READ_FAILED;
  }
  std::string err;
  const bool split = params_.layout == "interleaved"
                         ? splitInterleaved(frame_, params_.width, params_.height, out.left_raw, out.right_raw, &err)
                         : splitSideBySide(frame_, params_.swap_halves, out.left_raw, out.right_raw, &err);
  if (!split || !toMono8(out.left_raw, out.left_mono, &err) || !toMono8(out.right_raw, out.right_mono, &err))
  {
    last_error_ = err;
    return GrabStatus::BAD_FRAME;
  }
  out.emitter_on = false;
  if (params_.emitter == "alternate")
  {
    // which exposure this was, by its dots; then the emitter for a later one (the switch reaches
    // the sensor some frames on: the judge, not the command, says which frame had it)
    out.emitter_on = phase_.classify(dotEnergy(out.left_mono));
    emitter_commanded_ = !emitter_commanded_;
    emitter_error_ = emitter_ && !emitter_->set(emitter_commanded_) ? emitter_->lastError() : std::string();
  }
  if (!stamper_.stamp(stamp, out.stamp))
  {
    std::ostringstream s;
    s.precision(17);
    s << "frame stamp " << stamp << " is not after the previous frame's; dropped";
    last_error_ = s.str();
    return GrabStatus::STALE_STAMP;
  }
  ++frames_;
  last_warning_.clear();
  if (!calibrated())
  {
    last_warning_ = "not calibrated: no rectified images (see README: calibration)";
  }
  else if (!left_.rectify(out.left_mono, out.left_rect) ||
           !right_.rectify(out.right_mono, out.right_rect))
  {
    std::ostringstream s;
    s << "calibration is for " << left_.size().width << "x" << left_.size().height
      << " per eye but the camera delivers " << out.left_mono.cols << "x" << out.left_mono.rows
      << ": no rectified images";
    last_warning_ = s.str();
    out.left_rect.release();
    out.right_rect.release();
  }
  else
  {
    out.rectified = true;
  }
  return GrabStatus::OK;
}

}  // namespace assistive_description
