#include <assistive_eval/stereo_bag.h>

#include <assistive_eval/conversions.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <iostream>
#include <map>
#include <set>
#include <stdexcept>

#include <cv_bridge/cv_bridge.h>
#include <geometry_msgs/PoseStamped.h>
#include <geometry_msgs/TransformStamped.h>
#include <nav_msgs/OccupancyGrid.h>
#include <nav_msgs/Odometry.h>
#include <rosbag/bag.h>
#include <rosbag/view.h>
#include <sensor_msgs/CameraInfo.h>
#include <sensor_msgs/Image.h>
#include <sensor_msgs/Imu.h>
#include <sensor_msgs/image_encodings.h>
#include <std_msgs/String.h>
#include <tf2_eigen/tf2_eigen.h>
#include <tf2_msgs/TFMessage.h>

namespace assistive_eval
{
namespace
{
ros::Time toRos(double s)
{
  if (s <= 0.0) s = 1e-9;  // ros::Time(0) is "unset"; bags need positive times
  return ros::Time(s);
}

geometry_msgs::TransformStamped makeTf(const Eigen::Isometry3d& t, const std::string& parent,
                                       const std::string& child, const ros::Time& stamp)
{
  geometry_msgs::TransformStamped ts = tf2::eigenToTransform(t);
  ts.header.stamp = stamp;
  ts.header.frame_id = parent;
  ts.child_frame_id = child;
  return ts;
}

int64_t key(const ros::Time& t) { return static_cast<int64_t>(t.toNSec()); }

std::string stampText(const ros::Time& t)
{
  char b[48];
  std::snprintf(b, sizeof(b), "t = %.6f s", t.toSec());
  return b;
}

/// The image as CV_8UC1. mono8 as is; 8-bit colour and mono16 converted (one warning per
/// encoding: `warned` holds those seen); anything else (float depth, Bayer, unknown, malformed)
/// a std::runtime_error naming the topic, the stamp and the encoding.
cv::Mat toMono(const sensor_msgs::ImageConstPtr& msg, const std::string& topic, std::set<std::string>& warned)
{
  namespace enc = sensor_msgs::image_encodings;
  const std::string& e = msg->encoding;
  const std::string where = topic + " at " + stampText(msg->header.stamp);
  const bool convertible = e == enc::RGB8 || e == enc::BGR8 || e == enc::RGBA8 || e == enc::BGRA8 || e == enc::MONO16;
  if (e != enc::MONO8 && !convertible)
    throw std::runtime_error(where + ": image encoding '" + e +
                             "' is not supported (stereo bags hold mono8 images; rgb8, bgr8, rgba8, bgra8 and "
                             "mono16 are converted)");
  const size_t min_step = static_cast<size_t>(msg->width) * static_cast<size_t>(enc::numChannels(e) * enc::bitDepth(e) / 8);
  if (msg->width == 0 || msg->height == 0 || msg->step < min_step ||
      msg->data.size() != static_cast<size_t>(msg->step) * msg->height)
    throw std::runtime_error(where + ": malformed " + e + " image: " + std::to_string(msg->width) + "x" +
                             std::to_string(msg->height) + ", step " + std::to_string(msg->step) + ", " +
                             std::to_string(msg->data.size()) + " bytes of data");
  try
  {
    if (e == enc::MONO8)
      return cv_bridge::toCvCopy(msg)->image;
    if (warned.insert(e).second)
      std::fprintf(stderr, "StereoBagReader: warning: %s images (%s), converting to mono8 (stereo bags hold mono8)\n",
                   e.c_str(), topic.c_str());
    return cv_bridge::toCvCopy(msg, enc::MONO8)->image;
  }
  catch (const cv_bridge::Exception& ex)
  {
    throw std::runtime_error(where + ": cannot convert the " + e + " image to mono8: " + ex.what());
  }
}

/// Throws unless the calibration is usable: finite, fx, fy > 0, baseline > 0.
void checkCalib(const StereoCalib& c, const sensor_msgs::CameraInfo& left, const sensor_msgs::CameraInfo* right,
                const StereoBagTopics& topics)
{
  const std::string at = " at " + stampText(left.header.stamp);
  if (!(std::isfinite(c.fx) && std::isfinite(c.fy) && std::isfinite(c.cx) && std::isfinite(c.cy) && c.fx > 0.0 &&
        c.fy > 0.0))
    throw std::runtime_error(topics.left_info + at + ": invalid intrinsics fx " + std::to_string(c.fx) + ", fy " +
                             std::to_string(c.fy) + ", cx " + std::to_string(c.cx) + ", cy " + std::to_string(c.cy) +
                             " (P or K must be finite with fx, fy > 0)");
  // fromCameraInfos keeps a default baseline when the right P is unusable: check the message itself.
  const double b = (right && right->P[0] > 0.0) ? -right->P[3] / right->P[0] : std::nan("");
  if (!(std::isfinite(b) && b > 0.0))
    throw std::runtime_error(topics.right_info + at + ": invalid stereo baseline (right P[0] " +
                             std::to_string(right ? right->P[0] : 0.0) + ", P[3] " +
                             std::to_string(right ? right->P[3] : 0.0) + "; need P[0] > 0 and P[3] = -fx * baseline < 0)");
}

}  // namespace

// ---------------------------------------------------------------------------------- writer
StereoBagWriter::StereoBagWriter(const std::string& path, const StereoBagTopics& topics)
  : bag_(new rosbag::Bag), topics_(topics), link_to_left_(linkToLeftOptical())
{
  try
  {
    bag_->open(path, rosbag::bagmode::Write);
  }
  catch (const rosbag::BagException& e)
  {
    throw std::runtime_error("cannot open bag '" + path + "' for writing: " + e.what());
  }
}

StereoBagWriter::~StereoBagWriter() { close(); }

void StereoBagWriter::close()
{
  if (bag_ && bag_->isOpen()) bag_->close();
}

void StereoBagWriter::writeFrame(const StereoFrame& f)
{
  const ros::Time t = toRos(f.stamp);
  for (const ImuSample& s : f.imu) writeImu(s);
  auto li = toCameraInfo(f.calib, false, topics_.left_frame, t);
  auto ri = toCameraInfo(f.calib, true, topics_.right_frame, t);
  li.header.seq = ri.header.seq = seq_;
  if (f.left.type() != CV_8UC1 || f.right.type() != CV_8UC1)
    throw std::runtime_error("StereoBagWriter: images must be CV_8UC1");
  auto lm = toImageMsg(f.left, topics_.left_frame, t);
  auto rm = toImageMsg(f.right, topics_.right_frame, t);
  lm.header.seq = rm.header.seq = seq_;
  ++seq_;
  bag_->write(topics_.left_image, t, lm);
  bag_->write(topics_.left_info, t, li);
  bag_->write(topics_.right_image, t, rm);
  bag_->write(topics_.right_info, t, ri);
  if (!f.gt_depth.empty()) bag_->write(topics_.gt_depth, t, toDepthMsg(f.gt_depth, topics_.left_frame, t));
  if (f.has_gt_pose) writeGroundTruth(f.stamp, f.gt_pose, f.gt_velocity);
}

void StereoBagWriter::writeProjectedFrame(const StereoFrame& f)
{
  const ros::Time t = toRos(f.stamp);
  if (f.left.type() != CV_8UC1 || f.right.type() != CV_8UC1)
    throw std::runtime_error("StereoBagWriter: images must be CV_8UC1");
  auto li = toCameraInfo(f.calib, false, topics_.left_frame, t);
  auto ri = toCameraInfo(f.calib, true, topics_.right_frame, t);
  auto lm = toImageMsg(f.left, topics_.left_frame, t);
  auto rm = toImageMsg(f.right, topics_.right_frame, t);
  li.header.seq = ri.header.seq = lm.header.seq = rm.header.seq = projected_seq_++;
  bag_->write(topics_.projected_left_image, t, lm);
  bag_->write(topics_.projected_left_info, t, li);
  bag_->write(topics_.projected_right_image, t, rm);
  bag_->write(topics_.projected_right_info, t, ri);
}

bool bagHasTopic(const std::string& path, const std::string& topic)
{
  try
  {
    rosbag::Bag bag(path, rosbag::bagmode::Read);
    return rosbag::View(bag, rosbag::TopicQuery(topic)).size() > 0;
  }
  catch (const rosbag::BagException&)
  {
    return false;
  }
}

void StereoBagWriter::writeGroundTruth(double stamp, const Eigen::Isometry3d& T_wl,
                                       const Eigen::Vector3d& velocity)
{
  const ros::Time t = toRos(stamp);
  nav_msgs::Odometry odom;
  odom.header.stamp = t;
  odom.header.frame_id = topics_.gt_world_frame;
  odom.child_frame_id = topics_.gt_left_frame;
  odom.pose.pose = tf2::toMsg(T_wl);
  // Twist is expressed in the child frame (nav_msgs/Odometry convention).
  const Eigen::Vector3d v_child = T_wl.linear().transpose() * velocity;
  odom.twist.twist.linear.x = v_child.x();
  odom.twist.twist.linear.y = v_child.y();
  odom.twist.twist.linear.z = v_child.z();
  bag_->write(topics_.gt_odom, t, odom);

  tf2_msgs::TFMessage tfm;
  const Eigen::Isometry3d T_w_link = T_wl * link_to_left_.inverse();
  tfm.transforms.push_back(makeTf(T_w_link, topics_.gt_world_frame, topics_.gt_link_frame, t));
  tfm.transforms.push_back(makeTf(link_to_left_, topics_.gt_link_frame, topics_.gt_left_frame, t));
  bag_->write(topics_.tf, t, tfm);
}

void StereoBagWriter::writeImu(const ImuSample& s)
{
  ImuSample c = s;
  c.stamp = toRos(s.stamp).toSec();
  bag_->write(topics_.imu, toRos(s.stamp), toMsg(c, topics_.imu_frame));
}

void StereoBagWriter::writeRange(double stamp, double range, double field_of_view, double min_range,
                                  double max_range)
{
  const ros::Time t = toRos(stamp);
  bag_->write(topics_.sonar, t, toRangeMsg(range, field_of_view, min_range, max_range, topics_.sonar_frame, t));
}

void StereoBagWriter::writeOccupancy(const OccupancyGrid& g, double stamp)
{
  const ros::Time t = toRos(stamp);
  bag_->write(topics_.gt_occupancy, t, toMsg(g, topics_.gt_world_frame, t));
}

void StereoBagWriter::writeString(const std::string& topic, const std::string& text, double stamp)
{
  std_msgs::String m;
  m.data = text;
  bag_->write(topic, toRos(stamp), m);
}

// ---------------------------------------------------------------------------------- reader
struct StereoBagReader::Impl
{
  rosbag::Bag bag;
  std::unique_ptr<rosbag::View> view;
  rosbag::View::iterator it;
  std::map<int64_t, cv::Mat> pending_left, pending_right;
  std::set<std::string> warned;  ///< image encodings already warned about (converted to mono8)
};

StereoBagReader::StereoBagReader(const std::string& path, const StereoBagTopics& topics)
  : impl_(new Impl), topics_(topics)
{
  try
  {
    impl_->bag.open(path, rosbag::bagmode::Read);
  }
  catch (const rosbag::BagException& e)
  {
    throw std::runtime_error("cannot open bag '" + path + "': " + e.what());
  }
  {
    rosbag::View left(impl_->bag, rosbag::TopicQuery(topics_.left_image));
    n_left_ = left.size();
    rosbag::View depth(impl_->bag, rosbag::TopicQuery(topics_.gt_depth));
    has_depth_ = depth.size() > 0;
  }
  if (n_left_ == 0) throw std::runtime_error("bag '" + path + "' has no " + topics_.left_image);
  {
    rosbag::View right(impl_->bag, rosbag::TopicQuery(topics_.right_image));
    if (right.size() == 0) throw std::runtime_error("bag '" + path + "' has no " + topics_.right_image);
  }

  // One pass over the small topics: camera infos, IMU and ground truth.
  std::map<int64_t, sensor_msgs::CameraInfo> left_infos, right_infos;
  rosbag::View small(impl_->bag, rosbag::TopicQuery({topics_.left_info, topics_.right_info,
                                                     topics_.imu, topics_.gt_odom, topics_.gt_pose}));
  std::vector<std::pair<double, Eigen::Isometry3d>> sim_gt;  // gt_pose: used when there is no gt_odom
  for (const rosbag::MessageInstance& m : small)
  {
    if (m.getTopic() == topics_.left_info || m.getTopic() == topics_.right_info)
    {
      auto info = m.instantiate<sensor_msgs::CameraInfo>();
      if (!info)
        throw std::runtime_error("bag '" + path + "': " + m.getTopic() + " is " + m.getDataType() +
                                 ", not sensor_msgs/CameraInfo");
      (m.getTopic() == topics_.left_info ? left_infos : right_infos)[key(info->header.stamp)] = *info;
    }
    else if (m.getTopic() == topics_.imu)
    {
      auto imu = m.instantiate<sensor_msgs::Imu>();
      if (!imu) continue;
      imu_.push_back(fromMsg(*imu));
    }
    else if (m.getTopic() == topics_.gt_odom)
    {
      auto od = m.instantiate<nav_msgs::Odometry>();
      if (!od) continue;
      Eigen::Isometry3d T;
      tf2::fromMsg(od->pose.pose, T);
      gt_.emplace_back(od->header.stamp.toSec(), T);
      const Eigen::Vector3d v_child(od->twist.twist.linear.x, od->twist.twist.linear.y,
                                    od->twist.twist.linear.z);
      gt_vel_.push_back(T.linear() * v_child);
    }
    else if (m.getTopic() == topics_.gt_pose)
    {
      auto ps = m.instantiate<geometry_msgs::PoseStamped>();
      if (!ps) continue;
      Eigen::Isometry3d T;
      tf2::fromMsg(ps->pose, T);
      sim_gt.emplace_back(ps->header.stamp.toSec(), T);
    }
  }
  if (gt_.empty() && !sim_gt.empty())
  {
    std::stable_sort(sim_gt.begin(), sim_gt.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
    gt_ = sim_gt;
    for (size_t i = 0; i < gt_.size(); ++i)
    {
      const size_t a = i > 0 ? i - 1 : i, b = i + 1 < gt_.size() ? i + 1 : i;
      const double dt = gt_[b].first - gt_[a].first;
      gt_vel_.push_back(dt > 1e-9 ? Eigen::Vector3d((gt_[b].second.translation() - gt_[a].second.translation()) / dt)
                                  : Eigen::Vector3d::Zero());
    }
  }
  std::stable_sort(imu_.begin(), imu_.end(),
                   [](const ImuSample& a, const ImuSample& b) { return a.stamp < b.stamp; });
  {
    std::vector<size_t> idx(gt_.size());
    for (size_t i = 0; i < idx.size(); ++i) idx[i] = i;
    std::stable_sort(idx.begin(), idx.end(),
                     [&](size_t a, size_t b) { return gt_[a].first < gt_[b].first; });
    decltype(gt_) g;
    decltype(gt_vel_) v;
    for (size_t i : idx)
    {
      g.push_back(gt_[i]);
      v.push_back(gt_vel_[i]);
    }
    gt_.swap(g);
    gt_vel_.swap(v);
  }
  // No calibration, no stereo: never fall back to a default calibration.
  for (const auto* t : {&topics_.left_info, &topics_.right_info})
    if ((t == &topics_.left_info ? left_infos : right_infos).empty())
      throw std::runtime_error("bag '" + path + "' has no " + *t +
                               " (sensor_msgs/CameraInfo): the stereo calibration is unknown");
  for (const auto& kv : left_infos)
  {
    auto r = right_infos.find(kv.first);
    const sensor_msgs::CameraInfo* rp = r != right_infos.end() ? &r->second : &right_infos.begin()->second;
    const StereoCalib c = fromCameraInfos(kv.second, rp);
    checkCalib(c, kv.second, rp, topics_);
    calibs_.emplace_back(kv.first * 1e-9, c);
  }
  rewind();
}

StereoBagReader::~StereoBagReader() = default;

void StereoBagReader::rewind()
{
  impl_->view.reset(new rosbag::View(impl_->bag,
                                     rosbag::TopicQuery({topics_.left_image, topics_.right_image})));
  impl_->it = impl_->view->begin();
  impl_->pending_left.clear();
  impl_->pending_right.clear();
  imu_next_ = 0;
  first_ = true;
}

bool StereoBagReader::next(StereoFrame& f)
{
  Impl& d = *impl_;
  while (d.it != d.view->end())
  {
    const rosbag::MessageInstance& m = *d.it;
    const std::string topic = m.getTopic();  // m refers into the iterator: read it before ++
    const bool is_left = topic == topics_.left_image;
    auto img = m.instantiate<sensor_msgs::Image>();
    ++d.it;
    if (!img) continue;
    const int64_t k = key(img->header.stamp);
    auto& mine = is_left ? d.pending_left : d.pending_right;
    auto& other = is_left ? d.pending_right : d.pending_left;
    auto o = other.find(k);
    if (o == other.end())
    {
      mine[k] = toMono(img, topic, d.warned);
      continue;
    }
    cv::Mat this_img = toMono(img, topic, d.warned);
    f.left = is_left ? this_img : o->second;
    f.right = is_left ? o->second : this_img;
    // Frames come in stamp order: anything older never gets its partner.
    other.erase(other.begin(), std::next(o));
    mine.erase(mine.begin(), mine.lower_bound(k));
    f.stamp = k * 1e-9;

    // Calibration: the latest camera_info at or before the frame, else the first one.
    {
      auto c = std::upper_bound(calibs_.begin(), calibs_.end(), f.stamp + 1e-6,
                                [](double s, const std::pair<double, StereoCalib>& p) { return s < p.first; });
      f.calib = (c == calibs_.begin()) ? calibs_.front().second : std::prev(c)->second;
    }
    const std::string at = " at " + stampText(img->header.stamp);
    if (f.left.size() != f.right.size())
      throw std::runtime_error("stereo pair" + at + ": " + topics_.left_image + " is " + std::to_string(f.left.cols) +
                               "x" + std::to_string(f.left.rows) + " but " + topics_.right_image + " is " +
                               std::to_string(f.right.cols) + "x" + std::to_string(f.right.rows));
    if (f.calib.width > 0 && f.calib.height > 0 && (f.calib.width != f.left.cols || f.calib.height != f.left.rows))
      throw std::runtime_error("stereo pair" + at + ": images are " + std::to_string(f.left.cols) + "x" +
                               std::to_string(f.left.rows) + " but " + topics_.left_info + " says " +
                               std::to_string(f.calib.width) + "x" + std::to_string(f.calib.height));
    f.calib.width = f.left.cols;
    f.calib.height = f.left.rows;
    if (filter_)
      filter_(f);

    // Ground truth at the same stamp (within 1 ms).
    f.has_gt_pose = false;
    if (!gt_.empty())
    {
      auto g = std::lower_bound(gt_.begin(), gt_.end(), f.stamp - 1e-3,
                                [](const std::pair<double, Eigen::Isometry3d>& p, double s) { return p.first < s; });
      if (g != gt_.end() && std::abs(g->first - f.stamp) <= 1e-3)
      {
        f.has_gt_pose = true;
        f.gt_pose = g->second;
        f.gt_velocity = gt_vel_[g - gt_.begin()];
      }
    }

    // Optional depth at the same stamp.
    f.gt_depth.release();
    if (has_depth_)
    {
      const ros::Time t(f.stamp);
      rosbag::View dv(d.bag, rosbag::TopicQuery(topics_.gt_depth), t - ros::Duration(1e-6), t + ros::Duration(1e-6));
      for (const rosbag::MessageInstance& m : dv)
      {
        auto dm = m.instantiate<sensor_msgs::Image>();
        if (dm && dm->encoding == sensor_msgs::image_encodings::TYPE_32FC1)
          f.gt_depth = cv_bridge::toCvCopy(dm)->image;
      }
    }

    // IMU samples up to this frame.
    f.imu.clear();
    while (imu_next_ < imu_.size() && imu_[imu_next_].stamp <= f.stamp + 1e-9)
      f.imu.push_back(imu_[imu_next_++]);
    first_ = false;
    return true;
  }
  return false;
}

bool StereoBagReader::readOccupancy(OccupancyGrid& g) const
{
  rosbag::View v(impl_->bag, rosbag::TopicQuery(topics_.gt_occupancy));
  bool found = false;
  for (const rosbag::MessageInstance& m : v)
  {
    auto msg = m.instantiate<nav_msgs::OccupancyGrid>();
    if (!msg) continue;
    g = fromMsg(*msg);
    found = true;
  }
  return found;
}

bool StereoBagReader::readRanges(std::vector<RangeSample>& out) const
{
  out.clear();
  rosbag::View v(impl_->bag, rosbag::TopicQuery(topics_.sonar));
  for (const rosbag::MessageInstance& m : v)
  {
    auto msg = m.instantiate<sensor_msgs::Range>();
    if (!msg) continue;
    out.push_back({ msg->header.stamp.toSec(), msg->range, msg->field_of_view, msg->min_range, msg->max_range,
                    msg->header.frame_id });
  }
  std::stable_sort(out.begin(), out.end(), [](const RangeSample& a, const RangeSample& b) { return a.stamp < b.stamp; });
  return !out.empty();
}

std::unique_ptr<StereoBagReader> openStereoBag(const std::string& program, const std::string& path,
                                               const StereoBagTopics& topics)
{
  try
  {
    return std::make_unique<StereoBagReader>(path, topics);
  }
  catch (const std::exception& e)
  {
    std::cerr << program << ": cannot read " << path << ": " << e.what() << "\n";
    return nullptr;
  }
}

bool nextFrameOrExit(StereoBagReader& reader, StereoFrame& frame, const std::string& program, const std::string& path)
{
  try
  {
    return reader.next(frame);
  }
  catch (const std::exception& e)
  {
    std::cerr << program << ": " << path << ": " << e.what() << "\n";
    std::exit(1);
  }
}

std::string readBagString(const std::string& path, const std::string& topic)
{
  std::string out;
  try
  {
    rosbag::Bag bag(path, rosbag::bagmode::Read);
    rosbag::View v(bag, rosbag::TopicQuery(topic));
    for (const rosbag::MessageInstance& m : v)
      if (auto msg = m.instantiate<std_msgs::String>())
        out = msg->data;
  }
  catch (const std::exception&)
  {
    return std::string();
  }
  return out;
}

std::string rightRotationAgainstTruth(const std::string& camera_errors_json, const double applied_deg[3])
{
  const size_t key = camera_errors_json.find("\"right_rotation_deg\"");
  const size_t open = key == std::string::npos ? key : camera_errors_json.find('[', key);
  double t[3];
  if (open == std::string::npos ||
      std::sscanf(camera_errors_json.c_str() + open, "[%lf, %lf, %lf]", &t[0], &t[1], &t[2]) != 3)
    return std::string();
  char buf[200];
  std::snprintf(buf, sizeof buf, "; truth %.4f / %.4f / %.4f, error of the applied %.4f / %.4f / %.4f", t[0], t[1],
                t[2], applied_deg[0] - t[0], applied_deg[1] - t[1], applied_deg[2] - t[2]);
  return buf;
}

double rollingShutterReadout(const std::string& camera_errors_json)
{
  const size_t key = camera_errors_json.find("\"rolling_shutter_ms\"");
  double ms = 0;
  if (key == std::string::npos || std::sscanf(camera_errors_json.c_str() + key, "\"rolling_shutter_ms\": %lf", &ms) != 1 ||
      !(ms >= 0))
    return -1.0;
  return ms * 1e-3;
}

}  // namespace assistive_eval
