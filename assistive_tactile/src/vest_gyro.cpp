#include "assistive_tactile/vest_gyro.h"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <limits>
#include <sstream>

namespace assistive_tactile
{
void VestGyro::add(double t, const Eigen::Vector3d& rate, const Eigen::Vector3d& accel)
{
  const double g = accel.norm();
  if (!rate.allFinite() || !accel.allFinite() || g < 1.0)
    return;  // (a free fall or a broken sample says nothing about up)
  const double dt = t - last_sample_;
  if (!(dt > 0.0))
    return;  // out of order, repeated or no time: ignored
  if (!have_up_)
  {
    up_ = accel / g;
    have_up_ = true;
  }
  else if (dt <= max_gap_s_)
  {
    up_ = (up_ + std::min(1.0, dt / up_tau_s_) * (accel / g - up_)).normalized();
    const double r = rate.dot(up_);
    turn_ += (r - offset_) * dt;  // the rate held over the interval since the last sample
    watchStill(r, g, dt);
  }
  if (!(dt <= max_gap_s_))
  {
    gap_ = true;
    part_ = Sums();
    parts_filled_ = 0;  // (a window spans no gap)
  }
  last_sample_ = t;
}

void VestGyro::Sums::add(double rate_up, double accel_norm, double dt)
{
  t += dt;
  r += rate_up * dt;
  rr += rate_up * rate_up * dt;
  a += accel_norm * dt;
  aa += accel_norm * accel_norm * dt;
}

VestGyro::Sums& VestGyro::Sums::operator+=(const Sums& o)
{
  t += o.t;
  r += o.r;
  rr += o.rr;
  a += o.a;
  aa += o.aa;
  return *this;
}

void VestGyro::watchStill(double rate_up, double accel_norm, double dt)
{
  part_.add(rate_up, accel_norm, dt);
  if (part_.t < still_window_s_ / kStillParts)
    return;
  parts_[size_t(next_part_)] = part_;
  next_part_ = (next_part_ + 1) % kStillParts;
  parts_filled_ = std::min(parts_filled_ + 1, kStillParts);
  part_ = Sums();
  if (parts_filled_ < kStillParts)
    return;
  Sums w;
  for (const Sums& p : parts_) w += p;
  const double r = w.r / w.t, a = w.a / w.t;
  const double r_sd = std::sqrt(std::max(0.0, w.rr / w.t - r * r));
  const double a_sd = std::sqrt(std::max(0.0, w.aa / w.t - a * a));
  if (a_sd < kStillAccelSd && r_sd < kStillRateSd && std::fabs(r) < kMaxOffset)
  {
    offset_ = r;
    ++captures_;
  }
}

double VestGyro::take(double now)
{
  const bool fresh = have_up_ && now - last_sample_ <= max_gap_s_ && now > last_take_ &&
                     now - last_take_ <= max_gap_s_ + 1.0 && !gap_;
  const double r = fresh ? turn_ / (now - last_take_) : std::numeric_limits<double>::quiet_NaN();
  turn_ = 0.0;
  gap_ = false;
  last_take_ = now;
  return r;
}

bool loadOffset(const std::string& path, double* offset, std::string* why)
{
  std::ifstream in(path);
  if (!in)
  {
    *why = path + ": " + std::strerror(errno);
    return false;
  }
  std::string line;
  while (std::getline(in, line))
  {
    const std::string key = "offset_rad_s:";
    if (line.compare(0, key.size(), key) != 0)
      continue;
    std::istringstream v(line.substr(key.size()));
    double x = 0.0;
    if (!(v >> x) || !std::isfinite(x) || std::fabs(x) >= VestGyro::kMaxOffset)
    {
      *why = path + ": not an offset within " + std::to_string(std::lround(VestGyro::kMaxOffset * 180.0 / M_PI)) +
             " deg/s: '" + line + "'";
      return false;
    }
    *offset = x;
    return true;
  }
  *why = path + ": no line 'offset_rad_s: X'";
  return false;
}

bool saveOffset(const std::string& path, double offset, std::string* why)
{
  // written beside and renamed over: a run stopped mid-write leaves the last whole file
  const std::string tmp = path + ".tmp";
  {
    std::ofstream out(tmp, std::ios::trunc);
    out.precision(9);
    out << "# the vest gyro's offset about up, captured standing still (assistive_tactile cue_logic)\n"
        << "offset_rad_s: " << offset << "\n";
    if (!out.flush())
    {
      *why = tmp + ": " + std::strerror(errno);
      return false;
    }
  }
  if (std::rename(tmp.c_str(), path.c_str()) != 0)
  {
    *why = path + ": " + std::strerror(errno);
    return false;
  }
  return true;
}

}  // namespace assistive_tactile
