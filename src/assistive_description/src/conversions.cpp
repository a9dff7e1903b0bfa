#include <assistive_description/conversions.h>

namespace assistive_description
{
sensor_msgs::CameraInfo toMsg(const CameraCalibration& c)
{
  sensor_msgs::CameraInfo m;
  m.width = static_cast<uint32_t>(c.width);
  m.height = static_cast<uint32_t>(c.height);
  m.distortion_model = c.distortion_model;
  m.D = c.D;
  for (int i = 0; i < 9; ++i)
  {
    m.K[i] = c.K(i / 3, i % 3);
    m.R[i] = c.R(i / 3, i % 3);
  }
  for (int i = 0; i < 12; ++i) m.P[i] = c.P(i / 4, i % 4);
  return m;
}

CameraCalibration fromMsg(const sensor_msgs::CameraInfo& m)
{
  CameraCalibration c;
  c.width = static_cast<int>(m.width);
  c.height = static_cast<int>(m.height);
  c.distortion_model = m.distortion_model;
  c.D = m.D;
  for (int i = 0; i < 9; ++i)
  {
    c.K(i / 3, i % 3) = m.K[i];
    c.R(i / 3, i % 3) = m.R[i];
  }
  for (int i = 0; i < 12; ++i) c.P(i / 4, i % 4) = m.P[i];
  return c;
}

}  // namespace assistive_description
