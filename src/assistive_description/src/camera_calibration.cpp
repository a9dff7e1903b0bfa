#include <assistive_description/camera_calibration.h>

namespace assistive_description
{
bool CameraCalibration::isCalibrated() const
{
  return width > 0 && height > 0 && K(0, 0) > 0.0 && K(1, 1) > 0.0 && P(0, 0) > 0.0 &&
         P(1, 1) > 0.0 && K(2, 2) == 1.0;
}

CameraCalibration CameraCalibration::rectified() const
{
  CameraCalibration r;
  r.width = width;
  r.height = height;
  r.distortion_model = "plumb_bob";
  r.D.assign(5, 0.0);
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) r.K(i, j) = P(i, j);
  r.R = cv::Matx33d::eye();
  r.P = P;
  return r;
}

double CameraCalibration::baseline() const
{
  return P(0, 0) > 0.0 ? -P(0, 3) / P(0, 0) : 0.0;
}

bool CameraCalibration::operator==(const CameraCalibration& o) const
{
  return width == o.width && height == o.height && distortion_model == o.distortion_model &&
         D == o.D && K == o.K && R == o.R && P == o.P;
}

}  // namespace assistive_description
