// assistive_sim/renderer: renders the simulated stereo pair online, for the world's scripted walk
// (publishing IMU and ground truth too), for a pose on tf, or for a pose topic. Glue only: the
// rendering is StereoRenderer (assistive_sim_core).
#include <algorithm>
#include <cmath>
#include <fstream>
#include <limits>
#include <memory>
#include <mutex>
#include <optional>

#include <diagnostic_updater/diagnostic_updater.h>
#include <diagnostic_updater/publisher.h>
#include <geometry_msgs/PoseStamped.h>
#include <nav_msgs/Odometry.h>
#include <nodelet/nodelet.h>
#include <pluginlib/class_list_macros.hpp>
#include <ros/ros.h>
#include <std_msgs/Float64MultiArray.h>
#include <tf2_eigen/tf2_eigen.h>
#include <tf2_ros/buffer.h>
#include <tf2_ros/transform_broadcaster.h>
#include <tf2_ros/transform_listener.h>

#include <assistive_eval/conversions.h>
#include <assistive_sim/motion.h>
#include <assistive_sim/renderer.h>
#include <assistive_sim/people_msg.h>
#include <assistive_sim/renderer_params.h>
#include <assistive_sim/ultrasonic.h>
#include <assistive_sim/world.h>

namespace assistive_sim
{
using assistive_eval::toCameraInfo;  // the bag topics' message conversions
using assistive_eval::toDepthMsg;
using assistive_eval::toImageMsg;
using assistive_eval::toMsg;
using assistive_eval::toRangeMsg;

class RendererNodelet : public nodelet::Nodelet
{
public:
  ~RendererNodelet() override
  {
    timer_.stop();
    sonar_timer_.stop();
  }

private:
  void onInit() override
  {
    ros::NodeHandle& nh = getNodeHandle();
    ros::NodeHandle& pnh = getPrivateNodeHandle();
    RendererNodeParams& p = p_;
    pnh.param("world", p.world, p.world);
    pnh.param("pose_source", p.pose_source, p.pose_source);
    pnh.param("world_frame", p.world_frame, p.world_frame);
    pnh.param("camera_frame", p.camera_frame, p.camera_frame);
    pnh.param("left_frame", p.left_frame, p.left_frame);
    pnh.param("right_frame", p.right_frame, p.right_frame);
    pnh.param("imu_frame", p.imu_frame, p.imu_frame);
    pnh.param("rate", p.rate, p.rate);
    pnh.param("imu_rate", p.imu_rate, p.imu_rate);
    pnh.param("sonar_rate", p.sonar_rate, p.sonar_rate);
    pnh.param("sonar_frame", p.sonar_frame, p.sonar_frame);
    pnh.param("width", p.width, p.width);
    pnh.param("height", p.height, p.height);
    pnh.param("focal", p.focal, p.focal);
    pnh.param("baseline", p.baseline, p.baseline);
    pnh.param("noise_sigma", p.noise_sigma, p.noise_sigma);
    pnh.param("exposure_time", p.exposure_time, p.exposure_time);
    pnh.param("seed", p.seed, p.seed);
    pnh.param("loop", p.loop, p.loop);
    pnh.param("render_on_pose", p.render_on_pose, p.render_on_pose);
    pnh.param("people_time_origin", p.people_time_origin, p.people_time_origin);
    pnh.param("projector", p.projector, p.projector);
    const RendererNodeParams def;
    auto clamp = [&](auto& v, auto lo, auto hi, const char* name, auto d) {
      if (v < lo || v > hi)
      {
        NODELET_WARN_STREAM("renderer: " << name << " = " << v << " outside [" << lo << ", " << hi << "], using "
                                         << d);
        v = d;
      }
    };
    clamp(p.rate, 0.1, 200.0, "rate", def.rate);
    clamp(p.imu_rate, 1.0, 2000.0, "imu_rate", def.imu_rate);
    clamp(p.sonar_rate, 0.0, 100.0, "sonar_rate", def.sonar_rate);
    clamp(p.width, 16, 4096, "width", def.width);
    clamp(p.height, 16, 4096, "height", def.height);
    clamp(p.focal, 10.0, 10000.0, "focal", def.focal);
    clamp(p.baseline, 0.01, 2.0, "baseline", def.baseline);
    clamp(p.noise_sigma, 0.0, 50.0, "noise_sigma", def.noise_sigma);
    clamp(p.exposure_time, 0.0, 0.2, "exposure_time", def.exposure_time);
    if (p.pose_source != "script" && p.pose_source != "tf" && p.pose_source != "topic")
    {
      NODELET_WARN_STREAM("renderer: pose_source '" << p.pose_source << "' unknown (script, tf, topic), using script");
      p.pose_source = "script";
    }

    CameraParams cam;
    cam.calib.width = p.width;
    cam.calib.height = p.height;
    cam.calib.fx = cam.calib.fy = p.focal;
    cam.calib.cx = (p.width - 1) / 2.0;
    cam.calib.cy = (p.height - 1) / 2.0;
    cam.calib.baseline = p.baseline;
    cam.noise_sigma = p.noise_sigma;
    cam.exposure_time = p.exposure_time;
    cam.seed = static_cast<uint32_t>(p.seed);
    cam.projector.enabled = p.projector;
    try
    {
      std::string dir = ASSISTIVE_SIM_SHARE_WORLDS;
      if (!std::ifstream(dir + "/course.yaml").good()) dir = ASSISTIVE_SIM_SOURCE_WORLDS;
      world_ = World::load(resolveWorldPath(p.world, dir));
      // every person's give-way track (empty: its script), shared by the renderer's and the
      // ranger's copies; filled from `people_give_way` (the mobility trials, issue 37)
      for (Person& person : world_.people)
        person.give_way = std::make_shared<GiveWayTrack>();
      renderer_.reset(new StereoRenderer(world_, cam));
      motion_.reset(new WearerMotion(world_.trajectory, static_cast<uint32_t>(p.seed)));
    }
    catch (const std::exception& e)
    {
      NODELET_ERROR_STREAM("renderer: cannot load world '" << p.world << "': " << e.what());
      return;
    }
    NODELET_INFO_STREAM("renderer: world " << world_.name << ", " << p.width << "x" << p.height << " f " << p.focal
                                           << " B " << p.baseline << " at " << p.rate << " Hz, pose from "
                                           << p.pose_source);

    start_ = ros::Time::now();  // before any timer can fire
    pub_left_ = nh.advertise<sensor_msgs::Image>("left/image_rect", 2);
    pub_right_ = nh.advertise<sensor_msgs::Image>("right/image_rect", 2);
    pub_left_info_ = nh.advertise<sensor_msgs::CameraInfo>("left/camera_info", 2);
    pub_right_info_ = nh.advertise<sensor_msgs::CameraInfo>("right/camera_info", 2);
    pub_depth_ = nh.advertise<sensor_msgs::Image>("ground_truth/depth", 2);
    if (p.projector)
    {
      // the reference camera's emitter-on pairs (issue 35)
      pub_proj_left_ = nh.advertise<sensor_msgs::Image>("projected/left/image_rect", 2);
      pub_proj_right_ = nh.advertise<sensor_msgs::Image>("projected/right/image_rect", 2);
      pub_proj_left_info_ = nh.advertise<sensor_msgs::CameraInfo>("projected/left/camera_info", 2);
      pub_proj_right_info_ = nh.advertise<sensor_msgs::CameraInfo>("projected/right/camera_info", 2);
    }
    pub_occ_ = nh.advertise<nav_msgs::OccupancyGrid>("ground_truth/occupancy", 1, true);
    if (!world_.people.empty()) pub_people_ = nh.advertise<assistive_msgs::MoverArray>("ground_truth/people", 5);
    pub_occ_.publish(toMsg(computeOccupancy(world_), p.world_frame, ros::Time::now()));
    if (p.pose_source == "script")
    {
      pub_imu_ = nh.advertise<sensor_msgs::Imu>("imu/data", 50);
      pub_odom_ = nh.advertise<nav_msgs::Odometry>("ground_truth/odom", 10);
      ImuParams ip;
      ip.rate = p.imu_rate;
      imu_.reset(new ImuSimulator(ip, static_cast<uint32_t>(p.seed)));
      tf_broadcaster_.reset(new tf2_ros::TransformBroadcaster);
      imu_timer_ = nh.createTimer(ros::Duration(1.0 / p.imu_rate), &RendererNodelet::imuTick, this);
    }
    else if (p.pose_source == "tf")
    {
      tf_buffer_.reset(new tf2_ros::Buffer);
      tf_listener_.reset(new tf2_ros::TransformListener(*tf_buffer_));
    }
    else
    {
      sub_pose_ = nh.subscribe("pose", 1, &RendererNodelet::poseCb, this);
      if (!world_.people.empty())
        sub_give_way_ = nh.subscribe("people_give_way", 10, &RendererNodelet::giveWayCb, this);
    }

    if (p.sonar_rate > 0)
    {
      UltrasonicParams up;
      up.rate = p.sonar_rate;
      sonar_.reset(new UltrasonicRanger(world_, up, static_cast<uint32_t>(p.seed)));
      pub_sonar_ = nh.advertise<sensor_msgs::Range>("sonar/front", 10);
      sonar_timer_ = nh.createTimer(ros::Duration(1.0 / p.sonar_rate), &RendererNodelet::sonarTick, this);
    }

    updater_.reset(new diagnostic_updater::Updater(nh, pnh, getName()));
    updater_->setHardwareID("simulated stereo camera");
    min_freq_ = max_freq_ = p.rate;
    freq_.reset(new diagnostic_updater::FrequencyStatus(
        diagnostic_updater::FrequencyStatusParam(&min_freq_, &max_freq_, 0.2, 10)));
    updater_->add(*freq_);
    updater_->add("pose input", this, &RendererNodelet::poseDiag);
    // render_on_pose: every pose is rendered at once, stamped with its stamp (lock-step trials)
    if (!(p.pose_source == "topic" && p.render_on_pose))
      timer_ = nh.createTimer(ros::Duration(1.0 / p.rate), &RendererNodelet::tick, this);
  }

  /// The people's clock for a frame or ping at `stamp` (RendererNodeParams::people_time_origin).
  double peopleTime(const ros::Time& stamp) const
  {
    if (p_.people_time_origin >= 0.0) return stamp.toSec() - p_.people_time_origin;
    if (p_.pose_source == "script") return scriptTime(stamp);
    return (stamp - start_).toSec();
  }

  double scriptTime(const ros::Time& now) const
  {
    double t = (now - start_).toSec();
    if (p_.loop && motion_->duration() > 0) t = std::fmod(t, motion_->duration());
    return std::min(t, motion_->duration());
  }

  void imuTick(const ros::TimerEvent&)
  {
    // Publish the IMU samples due by now (script mode), stamped on the ROS clock.
    const double t = (ros::Time::now() - start_).toSec();
    if (t - imu_->nextTime() > 1.0)
    {
      NODELET_WARN_THROTTLE(5.0, "renderer: IMU fell %.1f s behind; skipping ahead", t - imu_->nextTime());
      imu_->skipTo(t);
    }
    while (imu_->nextTime() <= t)
    {
      const double ti = imu_->nextTime();
      ImuSample s = imu_->next(*motion_, 0.0, scriptTime(start_ + ros::Duration(ti)));
      s.stamp = (start_ + ros::Duration(ti)).toSec();
      pub_imu_.publish(toMsg(s, p_.imu_frame));
    }
  }

  void sonarTick(const ros::TimerEvent&)
  {
    // One ping from the wearer's pose now: the script's, else the last rendered camera pose.
    const ros::Time now = ros::Time::now();
    Eigen::Isometry3d link;
    if (p_.pose_source == "script")
      link = motion_->linkPose(scriptTime(now));
    else
    {
      std::lock_guard<std::mutex> lock(mutex_);
      if (!have_rendered_) return;  // no pose yet: no range rather than a guess
      link = last_rendered_ * linkToLeftOptical().inverse();
    }
    std::optional<double> r;
    {
      std::lock_guard<std::mutex> lock(people_mutex_);  // (the people's tracks grow meanwhile)
      r = sonar_->ping(link * linkToSonar(), peopleTime(now));
    }
    const UltrasonicParams& up = sonar_->params();
    const double range = r ? *r : std::numeric_limits<double>::infinity();  // REP-117: no echo
    const sensor_msgs::Range m = toRangeMsg(range, up.beam_width, up.min_range, up.max_range, p_.sonar_frame, now);
    pub_sonar_.publish(m);
  }

  /// The people's give-way offsets at a time (issue 37; the mobility trials' RosChain): [t, then
  /// per person x, y (m) and the script's delay (s)], appended to their tracks in time order.
  void giveWayCb(const std_msgs::Float64MultiArrayConstPtr& msg)
  {
    const std::vector<double>& d = msg->data;
    if (d.size() != 1 + 3 * world_.people.size())
    {
      NODELET_ERROR_THROTTLE(5.0, "renderer: people_give_way has %zu values, expected 1 + 3 x %zu people; ignored",
                             d.size(), world_.people.size());
      return;
    }
    if (!std::all_of(d.begin(), d.end(), [](double v) { return std::isfinite(v); }))
    {
      NODELET_ERROR_THROTTLE(5.0, "renderer: people_give_way has values that are not finite; ignored (the people "
                                  "keep their last offsets)");
      return;
    }
    std::lock_guard<std::mutex> lock(people_mutex_);
    for (size_t i = 0; i < world_.people.size(); ++i)  // (an old or repeated t adds nothing)
      world_.people[i].give_way->append(d[0], { d[1 + 3 * i], d[2 + 3 * i] }, d[3 + 3 * i]);
  }

  void poseCb(const geometry_msgs::PoseStampedConstPtr& msg)
  {
    if (msg->header.frame_id != p_.world_frame && !msg->header.frame_id.empty())
    {
      NODELET_WARN_THROTTLE(5.0, "renderer: pose in frame '%s', expected '%s'; ignored",
                            msg->header.frame_id.c_str(), p_.world_frame.c_str());
      return;
    }
    Eigen::Isometry3d T;
    tf2::fromMsg(msg->pose, T);
    if (!T.matrix().allFinite())
    {
      NODELET_WARN_THROTTLE(5.0, "renderer: non-finite pose ignored");
      return;
    }
    {
      std::lock_guard<std::mutex> lock(mutex_);
      pose_ = T;
      have_pose_ = true;
      last_pose_time_ = ros::Time::now();
    }
    if (p_.render_on_pose)
      renderAndPublish(T, msg->header.stamp.isZero() ? ros::Time::now() : msg->header.stamp, Eigen::Vector3d::Zero());
  }

  void tick(const ros::TimerEvent&)
  {
    const ros::Time now = ros::Time::now();
    Eigen::Isometry3d T;
    Eigen::Vector3d omega_opt = Eigen::Vector3d::Zero();
    if (p_.pose_source == "script")
    {
      const double t = scriptTime(now);
      T = motion_->leftOpticalPose(t);
      omega_opt = linkToLeftOptical().linear().transpose() * motion_->angularVelocity(t);
      have_pose_ = true;
      last_pose_time_ = now;
      nav_msgs::Odometry odom;
      odom.header.stamp = now;
      odom.header.frame_id = p_.world_frame;
      odom.child_frame_id = "gt_camera_left_optical_frame";
      odom.pose.pose = tf2::toMsg(T);
      pub_odom_.publish(odom);
      geometry_msgs::TransformStamped ts = tf2::eigenToTransform(T * linkToLeftOptical().inverse());
      ts.header.stamp = now;
      ts.header.frame_id = p_.world_frame;
      ts.child_frame_id = "gt_camera_link";
      geometry_msgs::TransformStamped ts2 = tf2::eigenToTransform(linkToLeftOptical());
      ts2.header.stamp = now;
      ts2.header.frame_id = "gt_camera_link";
      ts2.child_frame_id = "gt_camera_left_optical_frame";
      tf_broadcaster_->sendTransform({ts, ts2});
    }
    else if (p_.pose_source == "tf")
    {
      try
      {
        T = tf2::transformToEigen(tf_buffer_->lookupTransform(p_.world_frame, p_.camera_frame, ros::Time(0)));
        have_pose_ = true;
        last_pose_time_ = now;
      }
      catch (const tf2::TransformException& e)
      {
        NODELET_WARN_THROTTLE(5.0, "renderer: no pose %s -> %s on tf: %s", p_.world_frame.c_str(),
                              p_.camera_frame.c_str(), e.what());
        updater_->update();
        return;
      }
    }
    else
    {
      std::lock_guard<std::mutex> lock(mutex_);
      if (!have_pose_)
      {
        NODELET_WARN_THROTTLE(5.0, "renderer: waiting for a pose on %s", sub_pose_.getTopic().c_str());
        updater_->update();
        return;
      }
      T = pose_;
    }
    renderAndPublish(T, now, omega_opt);
  }

  void renderAndPublish(const Eigen::Isometry3d& T, const ros::Time& now, const Eigen::Vector3d& omega_opt)
  {
    const double people_t = peopleTime(now);
    {
      std::lock_guard<std::mutex> lock(people_mutex_);  // (the people's tracks grow meanwhile)
      renderer_->setPeopleTime(people_t);
      renderer_->render(T, (now - start_).toSec(), frame_++, out_, omega_opt);
      if (!world_.people.empty()) pub_people_.publish(peopleMessage(world_, people_t, now, p_.world_frame));
    }
    {
      std::lock_guard<std::mutex> lock(mutex_);
      last_rendered_ = T;
      have_rendered_ = true;
    }
    const StereoCalib& c = renderer_->params().calib;
    pub_left_.publish(toImageMsg(out_.left, p_.left_frame, now));
    pub_right_.publish(toImageMsg(out_.right, p_.right_frame, now));
    pub_left_info_.publish(toCameraInfo(c, false, p_.left_frame, now));
    pub_right_info_.publish(toCameraInfo(c, true, p_.right_frame, now));
    if (pub_depth_.getNumSubscribers() > 0) pub_depth_.publish(toDepthMsg(out_.depth_left, p_.left_frame, now));
    if (p_.projector)
    {
      // The emitter-on pair of the same pose, with the same stamp (the device's comes half a frame
      // later; here the pose is all there is, and the map's tf is the VO's at this stamp)
      renderer_->setEmitter(true);
      renderer_->render(T, (now - start_).toSec(), (frame_ - 1) + (1ull << 32), out_, omega_opt);
      renderer_->setEmitter(false);
      pub_proj_left_.publish(toImageMsg(out_.left, p_.left_frame, now));
      pub_proj_right_.publish(toImageMsg(out_.right, p_.right_frame, now));
      pub_proj_left_info_.publish(toCameraInfo(c, false, p_.left_frame, now));
      pub_proj_right_info_.publish(toCameraInfo(c, true, p_.right_frame, now));
    }
    freq_->tick();
    updater_->update();
  }

  void poseDiag(diagnostic_updater::DiagnosticStatusWrapper& stat)
  {
    if (!have_pose_)
      stat.summary(diagnostic_msgs::DiagnosticStatus::WARN, "no pose yet");
    else if ((ros::Time::now() - last_pose_time_).toSec() > 1.0)
      stat.summary(diagnostic_msgs::DiagnosticStatus::WARN, "pose input stale");
    else
      stat.summary(diagnostic_msgs::DiagnosticStatus::OK, "rendering");
    stat.add("world", world_.name);
    stat.add("pose_source", p_.pose_source);
    stat.add("frames", frame_);
  }

  RendererNodeParams p_;
  World world_;
  std::unique_ptr<StereoRenderer> renderer_;
  std::unique_ptr<WearerMotion> motion_;
  std::unique_ptr<ImuSimulator> imu_;
  std::unique_ptr<UltrasonicRanger> sonar_;
  RenderOutput out_;
  ros::Publisher pub_proj_left_, pub_proj_right_, pub_proj_left_info_, pub_proj_right_info_;
  ros::Publisher pub_left_, pub_right_, pub_left_info_, pub_right_info_, pub_depth_, pub_occ_, pub_imu_, pub_odom_,
      pub_sonar_, pub_people_;
  ros::Subscriber sub_pose_, sub_give_way_;
  std::mutex people_mutex_;  ///< the people's give-way tracks (giveWayCb) against rendering and pings
  ros::Timer timer_, imu_timer_, sonar_timer_;
  std::unique_ptr<tf2_ros::Buffer> tf_buffer_;
  std::unique_ptr<tf2_ros::TransformListener> tf_listener_;
  std::unique_ptr<tf2_ros::TransformBroadcaster> tf_broadcaster_;
  std::unique_ptr<diagnostic_updater::Updater> updater_;
  std::unique_ptr<diagnostic_updater::FrequencyStatus> freq_;
  double min_freq_ = 15.0, max_freq_ = 15.0;
  std::mutex mutex_;
  Eigen::Isometry3d pose_ = Eigen::Isometry3d::Identity();
  bool have_pose_ = false;
  Eigen::Isometry3d last_rendered_ = Eigen::Isometry3d::Identity();  ///< left optical pose, last frame
  bool have_rendered_ = false;
  ros::Time last_pose_time_, start_;
  uint64_t frame_ = 0;
};

}  // namespace assistive_sim

PLUGINLIB_EXPORT_CLASS(assistive_sim::RendererNodelet, nodelet::Nodelet)
