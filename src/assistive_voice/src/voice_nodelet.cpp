// The voice nodelet: glue between ROS and the core (commands.h, controller.h, reply_policy.h,
// recognizer.h, speaker.h). Buttons, recognised speech, command_text and the script all become
// Commands for the VoiceController; its Effects are performed here (service calls on a worker
// thread, the pause topic, replies through the ReplyPolicy).
#include <atomic>
#include <cmath>
#include <condition_variable>
#include <cstdio>
#include <deque>
#include <filesystem>
#include <functional>
#include <memory>
#include <mutex>
#include <sstream>
#include <thread>

#include <assistive_common/ros_params.h>
#include <assistive_msgs/GuideToPlace.h>
#include <assistive_msgs/TactileCue.h>
#include <assistive_msgs/TagPlace.h>
#include <nodelet/nodelet.h>
#include <pluginlib/class_list_macros.hpp>
#include <ros/ros.h>
#include <sensor_msgs/Joy.h>
#include <std_msgs/Bool.h>
#include <std_msgs/String.h>
#include <tf2_ros/buffer.h>
#include <tf2_ros/transform_listener.h>

#include "assistive_voice/audio.h"
#include "assistive_voice/commands.h"
#include "assistive_voice/controller.h"
#include "assistive_voice/params.h"
#include "assistive_voice/audio_cleaner.h"
#include "assistive_voice/recognizer.h"
#include "assistive_voice/reply_policy.h"
#include "assistive_voice/speaker.h"

namespace assistive_voice
{
static_assert(CUE_ALERT == assistive_msgs::TactileCue::ALERT && CUE_UNSURE == assistive_msgs::TactileCue::UNSURE &&
                  CUE_IDLE == assistive_msgs::TactileCue::IDLE && CUE_GUIDANCE == assistive_msgs::TactileCue::GUIDANCE &&
                  CUE_PROXIMITY == assistive_msgs::TactileCue::PROXIMITY,
              "controller.h's cue modes follow assistive_msgs/TactileCue");

/// "3 save place; 60.5 take me back" -> {(3, "save place"), (60.5, "take me back")}
std::vector<std::pair<double, std::string>> parseScript(const std::string& script)
{
  std::vector<std::pair<double, std::string>> out;
  std::stringstream ss(script);
  std::string item;
  while (std::getline(ss, item, ';'))
  {
    std::istringstream in(item);
    double t;
    if (!(in >> t))
      continue;
    std::string text;
    std::getline(in, text);
    out.emplace_back(t, text);
  }
  return out;
}

class VoiceNodelet : public nodelet::Nodelet
{
public:
  ~VoiceNodelet() override
  {
    running_ = false;
    jobs_cv_.notify_all();
    if (worker_.joinable())
      worker_.join();
    if (audio_.joinable())
      audio_.join();
    if (mic_)
      pclose(mic_);
  }

private:
  void onInit() override
  {
    ros::NodeHandle& nh = getNodeHandle();
    ros::NodeHandle& pnh = getPrivateNodeHandle();
    for (const std::string& m : assistive_common::readParams(pnh, p_))
      NODELET_WARN("%s", m.c_str());
    ReplyPolicyConfig rc;
    rc.min_interval_s = p_.min_interval_s;
    rc.repeat_s = p_.repeat_s;
    rc.max_age_s = p_.max_age_s;
    rc.silence_on_alert = p_.silence_on_alert;
    rc.alert_hold_s = p_.alert_hold_s;
    policy_ = ReplyPolicy(rc);
    controller_ = VoiceController(p_.unsure_warn_s, p_.confirm_s);
    script_ = parseScript(p_.script);

    reply_pub_ = nh.advertise<std_msgs::String>("reply", 10);
    command_pub_ = nh.advertise<std_msgs::String>("command", 10);
    pause_pub_ = nh.advertise<std_msgs::Bool>("pause_cues", 1, true);
    pause_pub_.publish(makeBool(false));
    joy_sub_ = nh.subscribe("buttons", 10, &VoiceNodelet::joyCb, this);
    cue_sub_ = nh.subscribe("cue", 10, &VoiceNodelet::cueCb, this);
    text_sub_ = nh.subscribe("command_text", 10, &VoiceNodelet::textCb, this);
    tag_client_ = nh.serviceClient<assistive_msgs::TagPlace>("tag_place");
    guide_client_ = nh.serviceClient<assistive_msgs::GuideToPlace>("guide_to_place");
    tf_ = std::make_unique<tf2_ros::Buffer>();
    tf_listener_ = std::make_unique<tf2_ros::TransformListener>(*tf_);

    if (p_.speech)
    {
      std::string err;
      wav_dir_ = p_.speech_output == "default" ? "" : p_.speech_output;
      std::error_code ec;
      if (!wav_dir_.empty())
        std::filesystem::create_directories(wav_dir_, ec);
      const bool ok = wav_dir_.empty() ? Speaker::openPlayback(&err) : Speaker::openSynthesis(&err);
      if (!ok || !Speaker::setVoice(p_.voice, p_.speech_rate_wpm))
      {
        NODELET_WARN("voice: no speech (%s, voice %s): replies go to the reply topic only", err.c_str(), p_.voice.c_str());
        p_.speech = false;
      }
    }
    if (p_.listen_mode != "off" && !p_.audio_input.empty())
    {
      const RecognizerConfig c = recognizerConfig(p_);
      try
      {
        cleaner_ = std::make_unique<AudioCleaner>(p_.audio_cleanup);
        recognizer_ = std::make_unique<Recognizer>(c);
        audio_ = std::thread(&VoiceNodelet::audioLoop, this);
      }
      catch (const std::exception& e)
      {
        NODELET_ERROR("voice: no recognition: %s", e.what());
      }
    }
    worker_ = std::thread(&VoiceNodelet::workerLoop, this);
    timer_ = nh.createWallTimer(ros::WallDuration(0.05), &VoiceNodelet::timerCb, this);
    NODELET_INFO("voice: listen_mode %s, audio_input '%s', keyphrase '%s', speech %s (%s), %zu scripted commands",
                 p_.listen_mode.c_str(), p_.audio_input.c_str(), p_.keyphrase.c_str(), p_.speech ? "on" : "off",
                 p_.speech_output.c_str(), script_.size());
  }

  static std_msgs::Bool makeBool(bool b)
  {
    std_msgs::Bool m;
    m.data = b;
    return m;
  }

  // ------------------------------------------------------------------ inputs
  void joyCb(const sensor_msgs::Joy::ConstPtr& m)
  {
    for (size_t i = 0; i < m->buttons.size() && i < 2; ++i)
    {
      const int press = m->buttons[i];
      if (press == PRESS_NONE)
        continue;
      bool answering = false;
      {
        std::lock_guard<std::mutex> lock(mutex_);
        answering = controller_.awaitingConfirmation();  // any press confirms
      }
      if (!answering && p_.listen_mode == "push_to_talk" && i == BUTTON_B && press == PRESS_LONG &&
          recognizer_)
      {
        std::lock_guard<std::mutex> lock(rec_mutex_);
        recognizer_->listen();
        NODELET_INFO("voice: listening (push to talk)");
        continue;
      }
      std::lock_guard<std::mutex> lock(mutex_);
      apply(controller_.onButton(static_cast<int>(i), press, now()), "button");
    }
  }

  void cueCb(const assistive_msgs::TactileCue::ConstPtr& m)
  {
    std::lock_guard<std::mutex> lock(mutex_);
    const double t = now();
    if (m->mode == assistive_msgs::TactileCue::ALERT && policy_.alert(t) && p_.speech)
      Speaker::stop();  // the vest keeps priority over speech
    apply(controller_.onCue(m->mode, m->reason, t), "cue");
  }

  void textCb(const std_msgs::String::ConstPtr& m) { command(m->data, "text"); }

  /// A command as text; `source` "voice": recognised speech (consequential ones are confirmed
  /// first), else typed or scripted (acted on at once).
  void command(const std::string& text, const char* source)
  {
    const Command c = parseCommand(text);
    if (c.action == Action::NONE)
    {
      NODELET_INFO("voice: '%s' (%s) is no command", text.c_str(), source);
      return;
    }
    std::lock_guard<std::mutex> lock(mutex_);
    const bool voice = std::string(source) == "voice";
    apply(voice ? controller_.onVoiceCommand(c, now()) : controller_.onCommand(c, now()), source);
  }

  /// Feeds the recognizer from the microphone command or the WAV list, in 20 ms chunks.
  void audioLoop()
  {
    std::vector<int16_t> buf(320);
    auto feed = [&](const int16_t* s, size_t n) {
      std::vector<Recognition> rs;
      {
        std::lock_guard<std::mutex> lock(rec_mutex_);
        const std::vector<int16_t> clean = cleaner_->process(s, n);  // the benchmark's chain
        rs = recognizer_->feed(clean.data(), clean.size());
      }
      for (const Recognition& r : rs)
      {
        if (r.keyword)
          NODELET_INFO("voice: keyphrase heard");
        else if (r.rejected)
        {
          NODELET_INFO("voice: '%s' rejected (confidence %.1f): say again", r.text.c_str(),
                       r.confidence);
          std::lock_guard<std::mutex> lock(mutex_);
          apply(controller_.onRejected(now()), "voice");
        }
        else if (!r.text.empty())
          command(r.text, "voice");
        else
          NODELET_INFO("voice: no command understood");
      }
    };
    if (p_.audio_input == "mic")
    {
      mic_ = popen(p_.mic_command.c_str(), "r");
      if (!mic_)
      {
        NODELET_ERROR("voice: cannot run '%s'", p_.mic_command.c_str());
        return;
      }
      while (running_ && ros::ok())
      {
        const size_t n = fread(buf.data(), 2, buf.size(), mic_);
        if (n == 0)
        {
          NODELET_ERROR("voice: the microphone command ended");
          return;
        }
        feed(buf.data(), n);
      }
      return;
    }
    // a WAV file or a list of them, at wall-clock rate, with audio_gap_s of silence around each
    const std::vector<int16_t> gap(static_cast<size_t>(p_.audio_gap_s * RECOGNIZER_RATE), 0);
    auto play = [&](const std::vector<int16_t>& s) {
      ros::WallTime next = ros::WallTime::now();
      for (size_t i = 0; i < s.size() && running_ && ros::ok(); i += 320)
      {
        feed(s.data() + i, std::min<size_t>(320, s.size() - i));
        next += ros::WallDuration(0.02);
        const ros::WallDuration left = next - ros::WallTime::now();
        if (left > ros::WallDuration(0))
          left.sleep();
      }
    };
    for (const std::string& f : wavList(p_.audio_input))
    {
      Audio a;
      std::string err;
      if (!readWav(f, &a, &err))
      {
        NODELET_ERROR("voice: %s", err.c_str());
        continue;
      }
      play(gap);
      play(resample(a, RECOGNIZER_RATE).samples);
    }
    play(gap);
    NODELET_INFO("voice: audio input %s played", p_.audio_input.c_str());
  }

  // ------------------------------------------------------------------ effects
  /// Replies live on the wall clock: speech is heard in real time, and a replay's clock stops at
  /// the end of the bag while the wearer may still be answered.
  double now() const { return ros::WallTime::now().toSec(); }

  std::optional<Pose2> pose()
  {
    try
    {
      const geometry_msgs::TransformStamped T = tf_->lookupTransform(p_.map_frame, p_.head_frame, ros::Time(0));
      const auto& q = T.transform.rotation;
      Pose2 p;
      p.x = T.transform.translation.x;
      p.y = T.transform.translation.y;
      // heading of the head's x axis on the map's ground plane
      p.yaw = std::atan2(2.0 * (q.w * q.z + q.x * q.y), 1.0 - 2.0 * (q.y * q.y + q.z * q.z));
      return p;
    }
    catch (const tf2::TransformException&)
    {
      return std::nullopt;
    }
  }

  /// Performs the controller's effects (mutex_ held).
  void apply(const Effects& e, const char* source)
  {
    const double t = now();
    if (e.command.action != Action::NONE)
    {
      std_msgs::String m;
      m.data = std::string(actionName(e.command.action)) + (e.command.name.empty() ? "" : " " + e.command.name);
      command_pub_.publish(m);
      NODELET_INFO("voice: %s (%s)", m.data.c_str(), source);
    }
    if (e.pause)
      pause_pub_.publish(makeBool(*e.pause));
    if (e.listen && recognizer_)
    {
      std::lock_guard<std::mutex> lock(rec_mutex_);
      recognizer_->listen(true);  // the answer: yes / no
    }
    if (e.reply)
      policy_.offer(e.reply->text, e.reply->priority, t);
    if (e.tag)
    {
      const std::string name = *e.tag;
      post([this, name] {
        assistive_msgs::TagPlace srv;
        srv.request.name = name;
        const bool ok = tag_client_.call(srv) && srv.response.success;
        if (!ok)
          NODELET_WARN("voice: tag_place failed: %s", srv.response.message.c_str());
        const std::optional<Pose2> where = pose();
        std::lock_guard<std::mutex> lock(mutex_);
        apply(controller_.onTagResult(ok, srv.response.name, where, now()), "tag_place");
      });
    }
    if (e.guide)
    {
      const std::string name = *e.guide;
      post([this, name] {
        assistive_msgs::GuideToPlace srv;
        srv.request.name = name;
        const bool ok = guide_client_.call(srv) && srv.response.success;
        if (!ok)
          NODELET_WARN("voice: guide_to_place failed: %s", srv.response.message.c_str());
        std::lock_guard<std::mutex> lock(mutex_);
        apply(controller_.onGuideResult(ok, name, now()), "guide_to_place");
      });
    }
  }

  void post(std::function<void()> job)
  {
    std::lock_guard<std::mutex> lock(jobs_mutex_);
    jobs_.push_back(std::move(job));
    jobs_cv_.notify_one();
  }

  /// Service calls block: they run here, never in a callback of the manager.
  void workerLoop()
  {
    while (running_)
    {
      std::function<void()> job;
      {
        std::unique_lock<std::mutex> lock(jobs_mutex_);
        jobs_cv_.wait(lock, [&] { return !jobs_.empty() || !running_; });
        if (!running_)
          return;
        job = std::move(jobs_.front());
        jobs_.pop_front();
      }
      job();
    }
  }

  void timerCb(const ros::WallTimerEvent&)
  {
    const double t = now();
    // the script runs on ROS time (a replay's bag time), from its first non-zero tick
    const double ros_t = ros::Time::now().toSec();
    if (ros_t > 0 && script_t0_ < 0)
      script_t0_ = ros_t;
    while (script_t0_ >= 0 && script_next_ < script_.size() && ros_t - script_t0_ >= script_[script_next_].first)
      command(script_[script_next_++].second, "script");
    std::optional<Reply> r;
    {
      std::lock_guard<std::mutex> lock(mutex_);
      controller_.setPose(pose());
      apply(controller_.onTime(t), "timer");
      if (p_.speech && wav_dir_.empty() && Speaker::speaking())
        return;  // one reply at a time
      r = policy_.next(t);
    }
    if (!r)
      return;
    std_msgs::String m;
    m.data = r->text;
    reply_pub_.publish(m);
    NODELET_INFO("voice: says '%s'", r->text.c_str());
    if (!p_.speech)
      return;
    if (wav_dir_.empty())
      Speaker::say(r->text);
    else
    {
      char name[64];
      std::snprintf(name, sizeof name, "/reply_%03d.wav", replies_++);
      if (!writeWav(wav_dir_ + name, Speaker::synth(r->text)))
        NODELET_WARN("voice: cannot write %s%s", wav_dir_.c_str(), name);
    }
  }

  VoiceParams p_;
  ReplyPolicy policy_;
  VoiceController controller_;
  std::mutex mutex_;      // policy_, controller_
  std::mutex rec_mutex_;  // recognizer_
  std::unique_ptr<Recognizer> recognizer_;
  std::unique_ptr<AudioCleaner> cleaner_;  // audio thread only
  std::vector<std::pair<double, std::string>> script_;
  size_t script_next_ = 0;
  double script_t0_ = -1;
  std::string wav_dir_;
  int replies_ = 0;
  FILE* mic_ = nullptr;
  std::atomic<bool> running_{true};
  std::thread audio_, worker_;
  std::mutex jobs_mutex_;
  std::condition_variable jobs_cv_;
  std::deque<std::function<void()>> jobs_;
  ros::Publisher reply_pub_, command_pub_, pause_pub_;
  ros::Subscriber joy_sub_, cue_sub_, text_sub_;
  ros::ServiceClient tag_client_, guide_client_;
  std::unique_ptr<tf2_ros::Buffer> tf_;
  std::unique_ptr<tf2_ros::TransformListener> tf_listener_;
  ros::WallTimer timer_;
};
}  // namespace assistive_voice

PLUGINLIB_EXPORT_CLASS(assistive_voice::VoiceNodelet, nodelet::Nodelet)
