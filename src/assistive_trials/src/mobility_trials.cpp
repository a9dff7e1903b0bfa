// mobility_trials: a simulated wearer walks a world's course closed loop (issue 19, seed 5.4-5.5).
//   rosrun assistive_trials mobility_trials --world W [--trials N] [--mode truth|cane|vision|floor] [--seed S]
//       [--plot FILE.png] [--no-cues] [--reaction S] [--turn-rate DEG_S]
//   rosrun assistive_trials mobility_trials --generated N [--kind K[,K...]] [--seed-base B] [--keep DIR] [...]
// Prints one row per trial (per world for a generated set), a summary table, and as the last line
// the JSON keys of SPEC.md (for a set: means over the worlds and `_worst` variants).
#include <netinet/in.h>
#include <signal.h>
#include <sys/socket.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <fstream>
#include <map>
#include <sstream>
#include <thread>

#include <cmath>
#include <cstdio>
#include <initializer_list>
#include <iostream>
#include <numeric>
#include <string>
#include <vector>

#include <opencv2/imgcodecs.hpp>

#include <ros/ros.h>

#include <assistive_eval/plots.h>
#include <assistive_tactile/cue_logic.h>
#include <assistive_trials/ros_chain.h>
#include <assistive_trials/trials.h>
#include <assistive_sim/world_generator.h>

using namespace assistive_sim;
using namespace assistive_trials;

namespace
{
void usage(std::ostream& os = std::cerr)
{
  os << "usage: mobility_trials --world W [--trials N] [--mode truth|cane|vision|floor] [--seed S] [--plot FILE.png]\n"
        "       (--mode floor: no cues, the fastest each trial's wearer could walk the guide's path if every cue came\n"
        "       at the best moment: an optimistic estimate of the PPWS no guidance passes, issue 33)\n"
        "       mobility_trials --generated N [--kind K[,K...]] [--seed-base B] [--keep DIR] [the same options]\n"
        "                       [--no-cues] [--reaction S] [--turn-rate DEG_S] [--turn-on DEG]\n"
        "                       [--people N] (--generated: N people in each world whose walks cross the wearer's,\n"
        "                       as generate_world --people N)\n"
        "                       [--people-scripted] (people walk their scripts through the wearer; default: they\n"
        "                       step aside as walkers do, truth and cane modes; assistive_sim/people_give_way.h)\n"
        "                       [--body-half-width M] [--chord-min M] (planner: free_ahead strip, heading chord; truth)\n"
        "                       [--timeout-factor X] (a trial ends unfinished after X x the guide's time + 20 s; 4)\n"
        "                       [--wearer population|typical] [--slowest-decile] [--unsure-at S [--unsure-for S]]\n"
        "                       [--timelines PREFIX] (one cue timeline PNG per trial: PREFIX<k>.png)\n"
        "                       [--causes] (a line per collision and per unfinished trial: what the wearer did, where)\n"
        "                       [--vest-gyro] (truth, vision: the vest has its own gyro, the head IMU's noise and bias;\n"
        "                       --vest-gyro-perfect: without either; --vest-gyro-bias DEG_S: the offset's sigma, analysis)\n"
        "                       [--grid-resolution M] (truth: the perfect map's cell, 0.02-1 m; default 0.2, the\n"
        "                       obstacle stage's cell_size; analysis: what a finer map is worth)\n"
        "                       [--ros-params FILE.yaml] (vision: loaded at the root before each trial's pipeline,\n"
        "                       e.g. {cue_logic: {lost_turn_after_s: 0}, slam: {reset_fixed_rotation: false}})\n"
        "                       [--active] (vision: the reference camera, the pattern projector's emitter-on pairs\n"
        "                       mapped; issue 35)\n"
        "                       [--record DIR] (vision: each trial's sensor input, truth and chain output to\n"
        "                       DIR/<world>_trial<k>.bag, to replay it offline; about 9 MB per simulated second)\n"
        "                       [--lead-from-reaction oracle] (analysis: steer_lead_s = the wearer's true\n"
        "                       reaction + 0.15 s, never to make the guidance look good)\n"
        "  --wearer: each trial's wearer drawn from the population (default; docs/wearer_population.md) or the\n"
        "            typical adult of WearerParams; --slowest-decile: every wearer from the slowest-reacting 10 %.\n"
        "  --unsure-at: a scripted UNSURE episode (no pose) at that trial time (truth mode): unsure_walked_m.\n"
        "  W: a shipped world's name (course corridor parking glass plaza) or a world YAML.\n"
        "  truth: the world's occupancy -> planner core -> cue logic core -> simulated vest wearer (no ROS);\n"
        "  cane: the cane-only walker. --no-cues removes the cue stage (the vest stays silent).\n"
        "  vision: the renderer and the whole pipeline.launch in one nodelet manager (a private roscore and\n"
        "          roslaunch assistive_trials mobility_vision.launch per trial), lock-stepped on simulated time.\n"
        "  Heat map: --plot (default mobility_<world>_<mode>.png in the current folder).\n"
        "  --generated N: score a generated set instead of one world: N worlds (generate_world seeds B .. B+N-1,\n"
        "          --seed-base B, default 1001; --kind K or K1,K2,... cycled over the seeds, default: the seed\n"
        "          chooses as generate_world does), --trials per world; one row per world, then the set's mean\n"
        "          and worst world. Heat maps PREFIX_<world>.png (PREFIX: --plot without .png, default\n"
        "          mobility_generated_<kind>_<mode>); --keep DIR keeps the world files (default: a temporary folder).\n";
}

// The shipped worlds: assistive_sim's (its CMake config's assistive_sim_WORLDS_DIR: the source
// folder in a devel space, share/assistive_sim/worlds once installed).
std::string worldsDir()
{
  struct stat st;
  return stat(ASSISTIVE_SIM_WORLDS_DIR, &st) == 0 ? ASSISTIVE_SIM_WORLDS_DIR : ".";
}

int freePort()
{
  const int fd = socket(AF_INET, SOCK_STREAM, 0);
  sockaddr_in a{};
  a.sin_family = AF_INET;
  a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  a.sin_port = 0;
  socklen_t len = sizeof(a);
  int port = 11411;
  if (fd >= 0 && bind(fd, reinterpret_cast<sockaddr*>(&a), sizeof(a)) == 0 &&
      getsockname(fd, reinterpret_cast<sockaddr*>(&a), &len) == 0)
    port = ntohs(a.sin_port);
  if (fd >= 0) close(fd);
  return port;
}

/// The children's process groups (roscore, roslaunch): each runs in its own group, so a Ctrl-C or
/// a kill of this CLI would not reach them and left a private roscore and a whole pipeline running.
/// The handler ends them with it (kill() is async-signal-safe).
volatile sig_atomic_t g_child_groups[4] = { 0, 0, 0, 0 };

void endChildrenAndExit(int sig)
{
  for (volatile sig_atomic_t& g : g_child_groups)
    if (g > 0)
      kill(-pid_t(g), SIGINT);  // roslaunch and roscore shut their nodes down on SIGINT
  signal(sig, SIG_DFL);
  raise(sig);
}

void trackChild(pid_t pid, bool add)
{
  for (volatile sig_atomic_t& g : g_child_groups)
    if (add ? g == 0 : g == pid)
    {
      g = add ? pid : 0;
      return;
    }
}

/// A child process in its own process group, output to `log`.
pid_t spawn(const std::vector<std::string>& args, const std::string& log)
{
  static const bool handlers = [] {
    signal(SIGINT, endChildrenAndExit);
    signal(SIGTERM, endChildrenAndExit);
    signal(SIGHUP, endChildrenAndExit);
    return true;
  }();
  (void)handlers;
  const pid_t pid = fork();
  if (pid > 0)
    trackChild(pid, true);
  if (pid == 0)
  {
    setpgid(0, 0);
    FILE* f = std::fopen(log.c_str(), "w");
    if (f)
    {
      dup2(fileno(f), 1);
      dup2(fileno(f), 2);
    }
    std::vector<char*> av;
    for (const std::string& a : args) av.push_back(const_cast<char*>(a.c_str()));
    av.push_back(nullptr);
    execvp(av[0], av.data());
    _exit(127);
  }
  return pid;
}

void stopChild(pid_t pid, double timeout_s = 20.0)
{
  if (pid <= 0) return;
  trackChild(pid, false);
  kill(-pid, SIGINT);
  const auto until = std::chrono::steady_clock::now() + std::chrono::duration<double>(timeout_s);
  int st;
  while (std::chrono::steady_clock::now() < until)
  {
    if (waitpid(pid, &st, WNOHANG) == pid) return;
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
  }
  kill(-pid, SIGKILL);
  waitpid(pid, &st, 0);
}

bool topicPublished(const std::string& name)
{
  ros::master::V_TopicInfo topics;
  if (!ros::master::getTopics(topics)) return false;
  for (const auto& t : topics)
    if (t.name == name) return true;
  return false;
}

std::string num(double v, int prec = 3)
{
  if (!std::isfinite(v)) return "null";
  char b[64];
  std::snprintf(b, sizeof(b), "%.*f", prec, v);
  return b;
}

/// The private roscore of a vision run (one for all its trials and worlds).
struct VisionContext
{
  pid_t core = -1;
  std::string log_dir;
  std::string ros_params;  ///< a YAML loaded at the root before each trial's pipeline (--ros-params)
  std::string record_dir;  ///< each trial's chain recorded to DIR/<world>_trial<k>.bag (--record)
  bool active = false;     ///< the reference camera with its pattern projector (--active)
};

bool startVision(VisionContext& vc)
{
  const int port = freePort();
  const std::string uri = "http://localhost:" + std::to_string(port);
  setenv("ROS_MASTER_URI", uri.c_str(), 1);
  char tmpl[] = "/tmp/mobility_vision_XXXXXX";
  vc.log_dir = mkdtemp(tmpl) ? tmpl : "/tmp";
  vc.core = spawn({ "roscore", "-p", std::to_string(port) }, vc.log_dir + "/roscore.log");
  int rargc = 1;
  char name[] = "mobility_trials";
  char* rargv[] = { name, nullptr };
  ros::init(rargc, rargv, "mobility_trials", ros::init_options::NoSigintHandler);
  // 90 s: on a loaded machine (load 17 on 2 cores, test_mobility_vision under .ci/repeat) roscore's
  // start-up (its rosversion subprocesses) took over 30 s
  const auto until = std::chrono::steady_clock::now() + std::chrono::seconds(90);
  while (!ros::master::check() && std::chrono::steady_clock::now() < until)
    std::this_thread::sleep_for(std::chrono::milliseconds(200));
  if (!ros::master::check())
  {
    std::cerr << "mobility_trials: the private roscore did not come up within 90 s (" << vc.log_dir << "/roscore.log)\n";
    stopChild(vc.core);
    return false;
  }
  ros::start();
  std::cerr << "mobility_trials: vision mode, master " << uri << ", logs in " << vc.log_dir << "\n";
  return true;
}

void stopVision(VisionContext& vc)
{
  if (vc.core <= 0) return;
  ros::shutdown();
  stopChild(vc.core);
  vc.core = -1;
}

/// The trials of one world (seeds 1000 seed + k). `rows`: print one row per trial on stdout;
/// `label`: what the progress bar on stderr names. False when a vision trial could not run.
/// --timelines PREFIX: one cue timeline per trial (PREFIX<world>_<k>.png); who the wearers were.
/// A heat map or timeline to `path`; an error message (no exception) when it cannot be written.
bool writePlot(const std::string& path, const cv::Mat& img)
{
  std::string error;
  if (assistive_eval::writePng(path, img, &error))
    return true;
  std::cerr << "mobility_trials: " << error << "\n";
  return false;
}

std::string g_timelines, g_wearers = "population";
/// --causes: one line per collision and per unfinished trial (what the wearer did, where, why).
bool g_causes = false;

/// The collisions by cause and the unfinished trials by cause, over a set of trials (truth mode
/// knows where the doorways are; other modes count doorway collisions as elsewhere).
void reportCauses(const std::vector<TrialResult>& res)
{
  std::array<int, size_t(CollisionCause::NUM_CAUSES)> c{};
  std::map<std::string, int> ends;
  for (const TrialResult& r : res)
  {
    for (const CollisionEvent& e : r.collision_events) ++c[size_t(e.cause)];
    if (!r.end_cause.empty()) ++ends[r.end_cause];
  }
  std::printf("  collision causes    ");
  for (size_t i = 0; i < c.size(); ++i) std::printf(" %s %d", collisionCauseName(CollisionCause(i)), c[i]);
  std::printf("\n  unfinished trials   ");
  if (ends.empty()) std::printf(" none");
  for (const auto& e : ends) std::printf(" %s %d", e.first.c_str(), e.second);
  std::printf("\n");
}

bool runWorld(const World& world, const std::string& world_arg, const TrialOptions& opt, int trials, long seed,
              VisionContext& vc, bool rows, const std::string& label, std::vector<TrialResult>& res)
{
  const bool tty = isatty(2);
  for (int k = 0; k < trials; ++k)
  {
    const uint32_t s = uint32_t(seed * 1000 + k);
    if (opt.mode == TrialMode::VISION)
    {
      const std::string log = vc.log_dir + "/trial" + std::to_string(k) + ".log";
      RosChain::Options ro;
      ro.kind = RosChain::VISION;
      ro.eye_height = world.trajectory.eye_height;
      if (opt.vest_gyro)
        ro.vest_gyro = std::make_shared<VestGyroSim>(opt.vest_gyro_errors, s);
      // A fresh chain per trial: its t = 0 is at start_time + warmup_s of simulated time; the
      // renderer puts the people where they are on the trial's clock.
      std::vector<std::string> args{ "roslaunch", "assistive_trials", "mobility_vision.launch", "world:=" + world_arg,
                                     "people_time_origin:=" + num(ro.start_time + ro.warmup_s, 6) };
      if (!vc.ros_params.empty())
        args.push_back("params:=" + vc.ros_params);
      if (vc.active)
        args.push_back("active:=true");
      if (!vc.record_dir.empty())
        args.push_back("record:=" + vc.record_dir + "/" + world.name + "_trial" + std::to_string(k) + ".bag");
      const pid_t launch = spawn(args, log);
      ros::NodeHandle nh;
      RosChain chain(nh, world, ro);
      // the pipeline is up when the cue logic publishes and the renderer listens for poses
      const auto until = std::chrono::steady_clock::now() + std::chrono::seconds(120);
      auto up = [] {
        return topicPublished("/tactile/cue") && topicPublished("/planner/state") && topicPublished("/stereo/left/image_rect");
      };
      while (std::chrono::steady_clock::now() < until && !up())
        std::this_thread::sleep_for(std::chrono::milliseconds(250));
      if (!up())  // e.g. the renderer could not load the world: no trial to score
      {
        std::cerr << "mobility_trials: the vision pipeline did not come up within 120 s (log: " << log << ")\n";
        stopChild(launch);
        return false;
      }
      std::this_thread::sleep_for(std::chrono::seconds(3));  // subscriptions connect, nodelets finish loading
      ros::spinOnce();
      try
      {
        res.push_back(runTrial(world, opt, s, k, &chain));
      }
      catch (const std::exception& e)
      {
        std::cerr << "mobility_trials: trial " << k << ": " << e.what() << "\n";
        stopChild(launch);
        return false;
      }
      stopChild(launch);
    }
    else
      res.push_back(runTrial(world, opt, s, k));
    const TrialResult& r = res.back();
    if (!g_timelines.empty())
    {
      char t[200];
      std::snprintf(t, sizeof(t), "%s trial %d: speed %.2f m/s, reaction %.2f s, turn gain %.2f, %d levels%s", world.name.c_str(),
                    k, r.wearer.walk_speed, r.wearer.reaction_s, r.wearer.turn_gain, r.wearer.intensity_levels,
                    r.completed ? "" : ", NOT completed");
      writePlot(g_timelines + world.name + "_" + std::to_string(k) + ".png", timelinePlot(r, t));
    }
    if (g_causes)
    {
      static const char* actions[] = { "walk", "turn", "sidestep", "explore", "stopped", "veer" };
      for (const CollisionEvent& e : r.collision_events)
        std::printf("CAUSE %s trial %d t %.1f at %.2f %.2f %s: %s while %s at %.2f m/s, cue %d, %.2f m from a passage middle\n",
                    world.name.c_str(), k, e.t, e.xy.x(), e.xy.y(), collisionCauseName(e.cause),
                    assistive_sim::kindName(ObstacleKind(e.kind)), e.action >= 0 && e.action < 6 ? actions[e.action] : "?",
                    e.speed, e.instruction, e.door_m);
      if (!r.end_cause.empty())
        std::printf("UNFINISHED %s trial %d (reaction %.2f s, speed %.2f) at %.2f %.2f %s: %s\n", world.name.c_str(), k,
                    r.wearer.reaction_s, r.wearer.walk_speed, r.path.back().x(), r.path.back().y(), r.end_cause.c_str(),
                    r.end_detail.c_str());
    }
    if (rows)
    {
      std::printf("%-5d %-7u %-9s %-8.1f %-8.1f %-6.0f %-5d %d/%-6d %-6d %-7d %-7d %-9.2f\n", k, s,
                  r.completed ? "yes" : "NO", r.time_s, r.guide_time_s, r.ppws_pct, r.totalCollisions(), r.collisions[0],
                  r.collisions[1], r.collisions[2], r.collisions[3], r.collisions[size_t(ObstacleKind::PERSON)],
                  r.mean_clearance_m);
      std::fflush(stdout);
    }
    const int w = 30, done = (k + 1) * w / trials;
    std::fprintf(stderr, "%s%s[%s%s] %d/%d trials", tty ? "\r" : "", label.c_str(), std::string(size_t(done), '#').c_str(),
                 std::string(size_t(w - done), '.').c_str(), k + 1, trials);
    if (!tty || k + 1 == trials) std::fprintf(stderr, "\n");
  }
  return true;
}

/// The figures of a set of trials (one world's).
struct Summary
{
  double n = 0, coll = 0, worst = 0, comp = 0, ppws = 0, nppws = 0, clear = 0, tmean = 0;
  std::array<double, size_t(ObstacleKind::NUM_KINDS)> kinds{};
  std::array<double, 5> modes{};
  std::array<double, 7> unsure_status{};  ///< UNSURE cycles per planner status (TrialResult::unsure_by_status)
  std::vector<double> lat;
  long missed = 0;
  double people_closest = 0;
  double give_way = 0;      ///< times people began to step aside for the wearer
  bool giving_way = false;  ///< and they did (truth and cane modes)
  double ppws_worst = NAN;  ///< the worst trial's PPWS (0 = not completed)
  double unsure_max = NAN;  ///< metres walked after a scripted UNSURE began, most of any trial
  std::array<double, 6> action{};  ///< seconds per VestWearer::Action over the trials
  std::array<double, 3> standing{};  ///< the standing part of it, per TrialResult::Standing
  std::array<double, 7> begun{};   ///< cue patterns begun per Instruction
  double doorway_turns = 0;

  explicit Summary(const std::vector<TrialResult>& res)
  {
    n = double(res.size());
    for (const TrialResult& r : res)
    {
      const double p = r.completed ? r.ppws_pct : 0.0;
      ppws_worst = std::isnan(ppws_worst) ? p : std::min(ppws_worst, p);
      if (std::isfinite(r.unsure_walked_m))
        unsure_max = std::isnan(unsure_max) ? r.unsure_walked_m : std::max(unsure_max, r.unsure_walked_m);
      coll += r.totalCollisions();
      worst = std::max(worst, double(r.totalCollisions()));
      comp += r.completed;
      if (r.completed)
      {
        ppws += r.ppws_pct;
        tmean += r.time_s;
        ++nppws;
      }
      clear += r.mean_clearance_m;
      for (size_t i = 0; i < kinds.size(); ++i) kinds[i] += r.collisions[i];
      for (size_t i = 0; i < modes.size(); ++i) modes[i] += r.cue_modes[i];
      for (size_t i = 0; i < unsure_status.size(); ++i) unsure_status[i] += r.unsure_by_status[i];
      lat.insert(lat.end(), r.latency_ms.begin(), r.latency_ms.end());
      missed += r.missed_cues;
      people_closest += r.min_person_clearance_m;
      give_way += r.give_way_episodes;
      giving_way = giving_way || r.people_give_way;
      for (size_t i = 0; i < action.size(); ++i) action[i] += r.action_s[i];
      for (size_t i = 0; i < standing.size(); ++i) standing[i] += r.standing_s[i];
      for (size_t i = 0; i < begun.size(); ++i) begun[i] += r.cues_begun[i];
      doorway_turns += r.doorway_turns;
    }
    std::sort(lat.begin(), lat.end());
  }
  double cycles() const { return std::accumulate(modes.begin(), modes.end(), 0.0); }
  double collisionsPerTrial() const { return coll / n; }
  double completion() const { return comp / n; }
  double ppwsMean() const { return nppws ? ppws / nppws : NAN; }  ///< over the completed trials
  double timeMean() const { return nppws ? tmean / nppws : NAN; }
  double clearance() const { return clear / n; }
  double unsurePct() const { return cycles() > 0 ? 100 * modes[4] / cycles() : NAN; }
  double actionTotal() const { return std::accumulate(action.begin(), action.end(), 0.0); }
  double actionPct(std::initializer_list<VestWearer::Action> a) const
  {
    const double all = actionTotal();
    double t = 0;
    for (VestWearer::Action x : a) t += action[size_t(x)];
    return all > 0 ? 100 * t / all : NAN;
  }
  /// The standing part of the wearer's time, per TrialResult::Standing (% of all of it)
  double standingPct(TrialResult::Standing w) const
  {
    const double all = actionTotal();
    return all > 0 ? 100 * standing[size_t(w)] / all : NAN;
  }
  double walkingPct() const { return actionPct({ VestWearer::WALK, VestWearer::VEER }); }
  double begunPerTrial(assistive_tactile::Instruction i) const { return begun[size_t(i)] / n; }
  double latency(double q) const
  {
    if (lat.empty()) return double(NAN);
    return lat[std::min(lat.size() - 1, size_t(std::floor(q * double(lat.size() - 1) + 0.5)))];
  }
};

/// What the unsure cues stood for (the planner's status behind them), in % of all cycles: a lost
/// pose is the VO's or SLAM's, the rest the map's or the planner's.
void reportUnsure(const Summary& S)
{
  const double cycles = S.cycles();
  if (!(cycles > 0) || S.modes[4] <= 0) return;
  const auto pct = [&](size_t i) { return 100 * S.unsure_status[i] / cycles; };
  std::printf("    unsure for         no pose %.1f %%, no map %.1f %%, in unknown space %.1f %%, no path %.1f %%, "
              "no waypoint %.1f %%, other %.1f %%\n",
              pct(1), pct(2), pct(3), pct(4), pct(5), pct(0) + pct(6));
}

/// Where the wearer's time went and what the vest asked of it (issue 33: why a trial was slow).
void reportTime(const Summary& S)
{
  using assistive_tactile::Instruction;
  if (!(S.walkingPct() >= 0.0)) return;  // the cane walker: no vest
  std::printf("  wearer's time        walking %.0f %% (veering %.0f %%), turning on the spot %.0f %%, standing %.0f %%, "
              "side-stepping %.0f %%, feeling around %.0f %%\n",
              S.walkingPct(), S.actionPct({ VestWearer::VEER }), S.actionPct({ VestWearer::TURN }),
              S.actionPct({ VestWearer::STOPPED }), S.actionPct({ VestWearer::SIDESTEP }),
              S.actionPct({ VestWearer::EXPLORE }));
  std::printf("  standing for         a turn to begin %.0f %%, the go after a turn %.0f %%, other stops %.0f %%\n",
              S.standingPct(TrialResult::BEFORE_TURN), S.standingPct(TrialResult::AFTER_TURN),
              S.standingPct(TrialResult::OTHER_STAND));
  std::printf("  cues begun / trial   %.1f stop-and-turn (%.1f by the doorway routine), %.1f stop, %.1f veer, %.1f side-step, "
              "%.1f walk-on\n",
              S.begunPerTrial(Instruction::TURN), S.doorway_turns / S.n, S.begunPerTrial(Instruction::STOP),
              S.begunPerTrial(Instruction::VEER), S.begunPerTrial(Instruction::SIDESTEP),
              S.begunPerTrial(Instruction::WALK_ON));
}

/// Mode floor: what the floor's time beyond the guide's is made of, per trial (issue 33).
void reportFloor(const std::vector<TrialResult>& res)
{
  double start = 0, turns = 0, guide = 0, corners = 0, stride = 0, n = 0;
  for (const TrialResult& r : res)
    if (r.completed)
    {
      start += r.floor.start_s;
      turns += r.floor.turns_s;
      guide += r.guide_time_s;
      corners += r.floor.corners;
      stride += r.floor.in_stride;
      ++n;
    }
  if (n == 0) return;
  std::printf("  floor / trial        guide %.1f s + first go %.1f s + corners %.1f s (braking for a veer or a turn on the "
              "spot); %.1f corners over 15 deg, %.1f of them veered in stride\n",
              guide / n, start / n, turns / n, corners / n, stride / n);
}

/// One world's report: the summary table and the JSON line of SPEC.md (issue 19).
void reportWorld(const World& world, const std::string& mode, const std::string& label, bool cues, int trials, long seed,
                 const Summary& S, const std::string& plot, bool wrote)
{
  const double n = S.n;
  std::printf("\nmobility_trials %s, mode %s, %d trials (seed %ld)\n", world.name.c_str(), label.c_str(), trials, seed);
  std::printf("  completion           %.0f %%\n", 100.0 * S.comp / n);
  const double people_coll = S.kinds[size_t(ObstacleKind::PERSON)] / n;
  std::printf("  collisions / trial   %.2f (worst trial %.0f): wall %.2f, overhang %.2f, glass %.2f, furniture %.2f, "
              "people %.2f\n",
              S.coll / n, S.worst, S.kinds[0] / n, S.kinds[1] / n, S.kinds[2] / n, S.kinds[3] / n, people_coll);
  if (!world.people.empty() && S.giving_way)
    std::printf("  people               %zu scripted, stepping aside for the wearer (%.1f times a trial); closest "
                "approach %.2f m (body surfaces, mean over trials)\n",
                world.people.size(), S.give_way / n, S.people_closest / n);
  else if (!world.people.empty())
    std::printf("  people               %zu scripted (they do not react to the wearer); closest approach %.2f m "
                "(body surfaces, mean over trials)\n",
                world.people.size(), S.people_closest / n);
  std::printf("  time to completion   %s s (mean of completed), PPWS %s %% (sighted guide = 100)\n",
              num(S.timeMean(), 1).c_str(), num(S.ppwsMean(), 1).c_str());
  std::printf("  mean clearance       %.2f m (body surface to the nearest obstacle)\n", S.clear / n);
  std::printf("  wearers              %s; PPWS of the worst trial %s %% (0 = not completed)\n", g_wearers.c_str(),
              num(S.ppws_worst, 1).c_str());
  if (std::isfinite(S.unsure_max))
    std::printf("  UNSURE episode       walked at most %.2f m after it began\n", S.unsure_max);
  const double cycles = S.cycles();
  if (cycles > 0)
    std::printf("  cues                 idle %.0f %%, guidance %.0f %%, proximity %.0f %%, alert %.0f %%, unsure %.0f %%\n",
                100 * S.modes[0] / cycles, 100 * S.modes[1] / cycles, 100 * S.modes[2] / cycles, 100 * S.modes[3] / cycles,
                100 * S.modes[4] / cycles);
  reportUnsure(S);
  reportTime(S);
  const double lat_med = S.latency(0.5), lat_p99 = S.latency(0.99);
  if (S.lat.empty())
    std::printf("  latency              n/a in %s mode (no camera pipeline)\n", mode.c_str());
  else
    std::printf("  latency              image -> /tactile/cue (wall clock; the vest bridge is not in pipeline.launch): "
                "median %.1f ms, p99 %.1f ms over %zu frames; %ld frames without their cue\n",
                lat_med, lat_p99, S.lat.size(), S.missed);
  std::printf("  heat map             %s%s\n", plot.c_str(), wrote ? "" : " (could not write)");
  std::printf("{\"world\": \"%s\", \"mode\": \"%s\", \"cues\": %s, \"trials\": %d, \"collisions_per_trial\": %s, "
              "\"collisions_worst\": %.0f, \"completion_rate\": %s, \"time_s_mean\": %s, \"ppws_pct\": %s, "
              "\"mean_clearance_m\": %s, \"latency_ms_median\": %s, \"latency_ms_p99\": %s, "
              "\"wall_collisions_per_trial\": %s, \"overhang_collisions_per_trial\": %s, "
              "\"glass_collisions_per_trial\": %s, \"furniture_collisions_per_trial\": %s, \"people_collisions_per_trial\": %s, "
              "\"unsure_cue_pct\": %s, \"frames_without_cue\": %ld, \"ppws_pct_worst\": %s, \"unsure_walked_m_max\": %s, "
              "\"walking_pct\": %s, \"stop_turns_per_trial\": %s, \"stops_per_trial\": %s, \"wearers\": \"%s\"}\n",
              world.name.c_str(), mode.c_str(), cues ? "true" : "false", trials, num(S.coll / n).c_str(), S.worst,
              num(S.comp / n).c_str(), num(S.timeMean(), 2).c_str(), num(S.ppwsMean(), 1).c_str(), num(S.clear / n).c_str(),
              num(lat_med, 1).c_str(), num(lat_p99, 1).c_str(), num(S.kinds[0] / n).c_str(), num(S.kinds[1] / n).c_str(),
              num(S.kinds[2] / n).c_str(), num(S.kinds[3] / n).c_str(), num(people_coll).c_str(),
              cycles > 0 ? num(100 * S.modes[4] / cycles, 1).c_str() : "null", S.missed, num(S.ppws_worst, 1).c_str(),
              num(S.unsure_max, 3).c_str(), num(S.walkingPct(), 1).c_str(),
              num(S.begunPerTrial(assistive_tactile::Instruction::TURN), 2).c_str(),
              num(S.begunPerTrial(assistive_tactile::Instruction::STOP), 2).c_str(), g_wearers.c_str());
}

/// One world of a generated set.
struct SetWorld
{
  std::string name, kind;
  uint32_t seed = 0;
  double walk_m = 0, gen_s = 0, trials_s = 0;
  std::vector<TrialResult> res;
};

/// Mean and worst over the worlds of one figure (worlds where it is NaN are left out).
struct SetFigure
{
  double mean = NAN, worst = NAN;
  std::string worst_world;
  int worlds = 0;
};
SetFigure overWorlds(const std::vector<SetWorld>& set, const std::vector<double>& v, bool higher_is_worse)
{
  SetFigure f;
  double sum = 0;
  for (size_t i = 0; i < v.size(); ++i)
  {
    if (!std::isfinite(v[i])) continue;
    sum += v[i];
    ++f.worlds;
    if (!std::isfinite(f.worst) || (higher_is_worse ? v[i] > f.worst : v[i] < f.worst))
    {
      f.worst = v[i];
      f.worst_world = set[i].name;
    }
  }
  if (f.worlds) f.mean = sum / f.worlds;
  return f;
}

std::string jsonStr(const std::string& s)
{
  std::string o = "\"";
  for (char c : s)
  {
    if (c == '"' || c == '\\') o += '\\';
    o += c;
  }
  return o + "\"";
}

/// "name=value" -> (name, value); throws std::invalid_argument without '=' or a number.
std::pair<std::string, double> keyValue(const std::string& s)
{
  const size_t eq = s.find('=');
  if (eq == std::string::npos) throw std::invalid_argument(s);
  return { s.substr(0, eq), std::stod(s.substr(eq + 1)) };
}

std::vector<std::string> splitComma(const std::string& s)
{
  std::vector<std::string> out;
  std::stringstream ss(s);
  std::string item;
  while (std::getline(ss, item, ','))
    if (!item.empty()) out.push_back(item);
  return out;
}
/// The absolute path of an existing file or folder ("" when there is none).
std::string absolutePath(const std::string& path)
{
  char* full = realpath(path.c_str(), nullptr);
  if (!full)
    return "";
  std::string out(full);
  std::free(full);
  return out;
}
/// Creates `dir` if missing and replaces it by its absolute path; false when it cannot be made.
bool makeAbsoluteDir(std::string& dir)
{
  mkdir(dir.c_str(), 0755);
  const std::string full = absolutePath(dir);
  if (full.empty())
    return false;
  dir = full;
  return true;
}
}  // namespace

int main(int argc, char** argv)
{
  std::string world_arg, mode = "truth", plot, kind_arg, keep_dir, ros_params, record_dir;
  bool active = false;
  int trials = 20, generated = 0;
  long seed = 1, seed_base = 1001;
  int people = 0;  // --generated: people in each generated world (generate_world --people)
  TrialOptions opt;
  bool grid_resolution_given = false;  // truth mode's alone: refused elsewhere rather than ignored
  for (int i = 1; i < argc; ++i)
  {
    const std::string a = argv[i];
    auto val = [&]() -> std::string {
      if (i + 1 >= argc)
      {
        std::cerr << "mobility_trials: " << a << " needs a value\n";
        usage();
        std::exit(2);
      }
      return argv[++i];
    };
    try
    {
      if (a == "--world") world_arg = val();
      else if (a == "--generated") generated = std::stoi(val());
      else if (a == "--kind") kind_arg = val();
      else if (a == "--seed-base") seed_base = std::stol(val());
      else if (a == "--people") people = std::stoi(val());
      else if (a == "--keep") keep_dir = val();
      else if (a == "--trials") trials = std::stoi(val());
      else if (a == "--mode") mode = val();
      else if (a == "--seed") seed = std::stol(val());
      else if (a == "--plot") plot = val();
      else if (a == "--no-cues") opt.cues_enabled = false;
      else if (a == "--people-scripted") opt.people_give_way = false;  // people walk through the wearer (before)
      else if (a == "--reaction") opt.wearer.reaction_s = std::stod(val());
      else if (a == "--turn-rate") opt.wearer.turn_rate_deg = std::stod(val());
      else if (a == "--turn-on") opt.cues.turn_on_deg = std::stod(val());
      else if (a == "--body-half-width") opt.planner.body_half_width = std::stod(val());
      else if (a == "--chord-min") opt.planner.heading_chord_min = std::stod(val());
      else if (a == "--timeout-factor") opt.timeout_factor = std::stod(val());
      else if (a == "--active") active = true;
      else if (a == "--record") record_dir = val();
      else if (a == "--ros-params")
      {
        ros_params = absolutePath(val());
        if (ros_params.empty())
          throw std::invalid_argument("--ros-params: no such file");
      }
      else if (a == "--wearer")
      {
        const std::string w = val();
        if (w == "population") opt.population = true;
        else if (w == "typical") opt.population = false;
        else throw std::invalid_argument("--wearer");
      }
      else if (a == "--slowest-decile") opt.slowest_decile = true;
      else if (a == "--lookahead")  // min,max,seconds (tuning)
      {
        const std::string v = val();
        if (std::sscanf(v.c_str(), "%lf,%lf,%lf", &opt.planner.steer_lookahead_min, &opt.planner.steer_lookahead_max,
                        &opt.planner.steer_lookahead_s) != 3)
          throw std::invalid_argument("--lookahead");
      }
      else if (a == "--lead") opt.planner.steer_lead_s = std::stod(val());
      else if (a == "--lead-from-reaction")  // analysis: oracle = the drawn wearer's true reaction
      {
        if (val() != "oracle") throw std::invalid_argument("--lead-from-reaction");
        opt.lead_from_true_reaction = true;
      }
      else if (a == "--fix")  // analysis: name=value replaces a drawn trait (reaction, gain, sigma, bias, levels)
      {
        const auto [k, x] = keyValue(val());
        if (k == "reaction") opt.fix_reaction_s = x;
        else if (k == "gain") opt.fix_turn_gain = x;
        else if (k == "sigma") opt.fix_veer_sigma = x;
        else if (k == "bias") opt.fix_veer_bias = x;
        else if (k == "levels") opt.fix_levels = int(x);
        else throw std::invalid_argument("--fix");
      }
      else if (a == "--cue")  // analysis: name=value of a cue parameter (any by its ROS name, or veer_step, veer_on, alert_reaction, turn_on, settle, passage, passage_align, body_stand_tau, short_walk, passage_body, stop_decel, start_accel, sweep_radius, sweep_cycle, veer_rate, turn_go_clear)
      {
        const std::string kv = val();
        const size_t eq = kv.find('=');
        const std::string k = kv.substr(0, eq);
        if (eq != std::string::npos && assistive_common::has(opt.cues, k))
        {
          // any cue parameter by its ROS name, parsed as its own type
          if (!assistive_common::setFromText(opt.cues, k, kv.substr(eq + 1)))
            throw std::invalid_argument("--cue");
          continue;
        }
        const double x = keyValue(kv).second;
        if (k == "veer_step") opt.cues.veer_step_deg = x;
        else if (k == "veer_on") opt.cues.veer_on_deg = x;
        else if (k == "alert_reaction") opt.cues.alert_reaction_s = x;
        else if (k == "turn_on") opt.cues.turn_on_deg = x;
        else if (k == "settle") opt.cues.settle_timeout_s = x;
        else if (k == "passage") opt.cues.passage_align_m = x;  // 0: doorways steered as before (issue 33)
        else if (k == "passage_align") opt.cues.passage_align_deg = x;
        else if (k == "body_stand_tau") opt.cues.body_stand_tau_s = x;  // 0: standing, the head's yaw is the facing (before)
        else if (k == "short_walk") opt.cues.short_walk_m = x;  // 0: no timed stop after a go
        else if (k == "passage_body") opt.cues.passage_body_m = x;
        else if (k == "stop_decel") opt.cues.stop_decel = x;   // the prior until a stop is learnt
        else if (k == "start_accel") opt.cues.start_accel = x; // the prior until a start is learnt
        else if (k == "sweep_radius") opt.cues.sweep_radius_m = x;  // 0: no predicted sweep (the rays alone, before)
        else if (k == "sweep_cycle") opt.cues.sweep_cycle_s = x;
        else if (k == "veer_rate") opt.cues.veer_rate_deg = x;
        else if (k == "turn_go_clear") opt.cues.turn_go_clear_m = x;  // 0: every turn judged before the go (before)
        else throw std::invalid_argument("--cue");
      }
      else if (a == "--unsure-at") opt.unsure_at_s = std::stod(val());
      else if (a == "--unsure-for") opt.unsure_for_s = std::stod(val());
      else if (a == "--timelines") g_timelines = val();
      else if (a == "--causes") g_causes = true;
      else if (a == "--vest-gyro") opt.vest_gyro = true;
      else if (a == "--grid-resolution")  // analysis: the perfect map's cell in truth mode
      {
        opt.truth_grid_resolution = std::stod(val());
        grid_resolution_given = true;
        if (!(opt.truth_grid_resolution >= 0.02 && opt.truth_grid_resolution <= 1.0)) throw std::invalid_argument(a);
      }
      else if (a == "--vest-gyro-bias")  // analysis: the vest gyro's offset at power-up, sigma in deg/s
      {
        opt.vest_gyro = true;
        opt.vest_gyro_errors.gyro_bias_initial = std::stod(val()) * M_PI / 180.0;
      }
      else if (a == "--vest-gyro-perfect")  // analysis: the torso's yaw rate without noise or bias
      {
        opt.vest_gyro = true;
        opt.vest_gyro_errors.gyro_noise_density = opt.vest_gyro_errors.gyro_bias_initial =
            opt.vest_gyro_errors.gyro_bias_walk = 0.0;
      }
      else if (a == "-h" || a == "--help")
      {
        usage(std::cout);
        return 0;
      }
      else
      {
        std::cerr << "mobility_trials: unknown option " << a << "\n";
        usage();
        return 2;
      }
    }
    catch (const std::exception&)
    {
      std::cerr << "mobility_trials: bad value for " << a << "\n";
      return 2;
    }
  }
  const bool set_mode = generated > 0;
  if (trials < 1 || generated < 0 || (world_arg.empty() == !set_mode) || seed_base < 0 ||
      seed_base + generated - 1 > 0xffffffffL)
  {
    if (!world_arg.empty() && set_mode) std::cerr << "mobility_trials: --world and --generated exclude each other\n";
    usage();
    return 2;
  }
  if (!set_mode && (!kind_arg.empty() || !keep_dir.empty() || people != 0))
  {
    std::cerr << "mobility_trials: --kind, --keep and --people go with --generated\n";
    return 2;
  }
  if (!set_mode && !plot.empty() && !cv::haveImageWriter(plot))
  {
    // checked now, not after the trials: a run's summary is not lost to a misspelt file name
    std::cerr << "mobility_trials: --plot " << plot << ": no image writer for that extension (FILE.png)\n";
    return 2;
  }
  if (people < 0 || people > 100)
  {
    std::cerr << "mobility_trials: --people takes 0 .. 100\n";
    return 2;
  }
  const std::vector<std::string> kinds = splitComma(kind_arg);
  for (const std::string& k : kinds)
    if (std::find(WorldGenerator::kinds().begin(), WorldGenerator::kinds().end(), k) == WorldGenerator::kinds().end())
    {
      std::cerr << "mobility_trials: unknown --kind " << k << "\n";
      return 2;
    }
  g_wearers = !opt.population ? "typical" : opt.slowest_decile ? "slowest_decile" : "population";
  if (mode == "truth") opt.mode = TrialMode::TRUTH;
  else if (mode == "cane") opt.mode = TrialMode::CANE;
  else if (mode == "vision") opt.mode = TrialMode::VISION;
  else if (mode == "floor") opt.mode = TrialMode::FLOOR;
  else
  {
    std::cerr << "mobility_trials: --mode must be truth, cane, vision or floor\n";
    return 2;
  }
  if (opt.vest_gyro && opt.mode == TrialMode::CANE)
  {
    std::cerr << "mobility_trials: --vest-gyro goes with --mode truth or vision\n";
    return 2;
  }
  if (!record_dir.empty())
  {
    if (opt.mode != TrialMode::VISION)
    {
      std::cerr << "mobility_trials: --record goes with --mode vision (the chain's topics)\n";
      return 2;
    }
    if (!makeAbsoluteDir(record_dir))  // roslaunch runs the recorder in its own folder
    {
      std::cerr << "mobility_trials: --record: cannot create " << record_dir << "\n";
      return 2;
    }
  }
  // The renderer nodelet loads the world in roslaunch's folder (~/.ros), not ours.
  if (!keep_dir.empty() && !makeAbsoluteDir(keep_dir))
  {
    std::cerr << "mobility_trials: --keep: cannot create " << keep_dir << "\n";
    return 2;
  }
  if (const std::string full = absolutePath(world_arg); !world_arg.empty() && !full.empty())
    world_arg = full;  // a world file (else a shipped world's name)
  if (grid_resolution_given && opt.mode != TrialMode::TRUTH)
  {
    std::cerr << "mobility_trials: --grid-resolution goes with --mode truth (the perfect map's cell)\n";
    return 2;
  }
  const std::string label = mode + (opt.cues_enabled ? "" : " (no cues)");
  // vision: one private roscore for the run (started below), a fresh pipeline (roslaunch) per trial
  VisionContext vc;
  vc.ros_params = ros_params;
  vc.record_dir = record_dir;
  vc.active = active;

  if (!set_mode)
  {
    World world;
    try
    {
      world = World::load(resolveWorldPath(world_arg, worldsDir()));
    }
    catch (const std::exception& e)
    {
      std::cerr << "mobility_trials: " << e.what() << "\n";
      return 2;
    }
    opt.wearer.eye_height = world.trajectory.eye_height;
    opt.wearer.walk_speed = world.trajectory.speed;
    std::vector<TrialResult> res;
    std::printf("%-5s %-7s %-9s %-8s %-8s %-6s %-5s %-8s %-6s %-7s %-7s %-9s\n", "trial", "seed", "completed", "time_s",
                "guide_s", "ppws", "coll", "wall/ovh", "glass", "furn", "people", "clear_m");
    if (opt.mode == TrialMode::VISION && !startVision(vc)) return 1;
    const bool ok = runWorld(world, world_arg, opt, trials, seed, vc, true, "", res);
    stopVision(vc);
    if (!ok) return 1;
    const Summary S(res);
    if (plot.empty()) plot = "mobility_" + world.name + "_" + mode + (opt.cues_enabled ? "" : "_nocues") + ".png";
    const cv::Mat img = heatMap(world, res, opt.dt,
                                world.name + ": " + label + ", " + std::to_string(trials) + " trials, " +
                                    num(S.coll / S.n, 2) + " collisions/trial");
    const bool wrote = writePlot(plot, img);
    if (opt.mode == TrialMode::FLOOR) reportFloor(res);
    reportCauses(res);
    reportWorld(world, mode, label, opt.cues_enabled, trials, seed, S, plot, wrote);
    return 0;
  }

  // ---- a generated set: worlds seeds seed_base .. seed_base + generated - 1
  const std::string kind_label = kinds.empty() ? "any" : kind_arg;
  std::string prefix = plot;
  if (prefix.size() > 4 && prefix.compare(prefix.size() - 4, 4, ".png") == 0) prefix.resize(prefix.size() - 4);
  if (prefix.empty())
  {
    std::string kl = kinds.empty() ? "any" : kind_arg;
    std::replace(kl.begin(), kl.end(), ',', '-');
    prefix = "mobility_generated_" + kl + "_" + mode + (opt.cues_enabled ? "" : "_nocues");
  }
  // The world files: the vision chain's renderer loads them; kept with --keep.
  std::string dir = keep_dir;
  if (dir.empty())
  {
    char tmpl[] = "/tmp/mobility_generated_XXXXXX";
    if (!mkdtemp(tmpl))
    {
      std::cerr << "mobility_trials: cannot create a temporary folder\n";
      return 1;
    }
    dir = tmpl;
  }
  if (opt.mode == TrialMode::VISION && !startVision(vc)) return 1;
  std::printf("%-22s %-8s %-6s %-7s %-5s %-9s %-6s %-5s %-6s %-7s %-7s %-7s\n", "world", "kind", "walk_m", "trials",
              "done", "coll/tr", "worst", "wall", "furn", "ppws", "clear_m", "time_s");
  std::vector<SetWorld> set;
  int failed = 0;
  double gen_total = 0, trials_total = 0;
  const auto wall_start = std::chrono::steady_clock::now();
  for (int i = 0; i < generated; ++i)
  {
    SetWorld sw;
    sw.seed = uint32_t(seed_base + i);
    const std::string kind = kinds.empty() ? "" : kinds[size_t(i) % kinds.size()];
    const auto t0 = std::chrono::steady_clock::now();
    GeneratedWorld g;
    try
    {
      g = WorldGenerator(sw.seed, kind, people).generate();
    }
    catch (const std::exception& e)
    {
      std::cerr << "mobility_trials: world " << i + 1 << "/" << generated << " (seed " << sw.seed << "): " << e.what() << "\n";
      std::printf("%-22s %-8s generation failed\n", ("seed " + std::to_string(sw.seed)).c_str(),
                  kind.empty() ? "-" : kind.c_str());
      ++failed;
      continue;
    }
    const std::string path = dir + "/" + g.world.name + ".yaml";
    {
      std::ofstream f(path, std::ios::binary);
      f << g.yaml;
    }
    sw.gen_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    gen_total += sw.gen_s;
    sw.name = g.world.name;
    sw.kind = g.kind;
    sw.walk_m = g.walk_length;
    std::cerr << "[mobility_trials] world " << i + 1 << "/" << generated << " " << sw.name << ": generated in "
              << num(sw.gen_s, 2) << " s, walk " << num(sw.walk_m, 1) << " m, " << g.world.trajectory.waypoints.size()
              << " places; " << path << "\n";
    TrialOptions wo = opt;
    wo.wearer.eye_height = g.world.trajectory.eye_height;
    wo.wearer.walk_speed = g.world.trajectory.speed;
    const auto t1 = std::chrono::steady_clock::now();
    const std::string bar = "[mobility_trials] world " + std::to_string(i + 1) + "/" + std::to_string(generated) + " ";
    if (!runWorld(g.world, path, wo, trials, seed, vc, false, bar, sw.res))
    {
      stopVision(vc);
      return 1;
    }
    sw.trials_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t1).count();
    trials_total += sw.trials_s;
    const Summary S(sw.res);
    const std::string png = prefix + "_" + sw.name + ".png";
    const cv::Mat img = heatMap(g.world, sw.res, wo.dt,
                                sw.name + ": " + label + ", " + std::to_string(trials) + " trials, " +
                                    num(S.collisionsPerTrial(), 2) + " collisions/trial");
    writePlot(png, img);
    std::printf("%-22s %-8s %-6.1f %-7d %-5.0f %-9.2f %-6.0f %-5.2f %-6.2f %-7s %-7.2f %-7.1f\n", sw.name.c_str(),
                sw.kind.c_str(), sw.walk_m, trials, S.comp, S.collisionsPerTrial(), S.worst, S.kinds[0] / S.n,
                S.kinds[3] / S.n, num(S.ppwsMean(), 1).c_str(), S.clearance(), sw.gen_s + sw.trials_s);
    std::fflush(stdout);
    set.push_back(std::move(sw));
  }
  stopVision(vc);
  if (keep_dir.empty())
  {
    for (const SetWorld& sw : set) std::remove((dir + "/" + sw.name + ".yaml").c_str());
    rmdir(dir.c_str());
  }
  const double wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - wall_start).count();
  if (set.empty())
  {
    std::cerr << "mobility_trials: no world of the set could be generated\n";
    return 1;
  }
  // Per world figures, then mean and worst over the worlds.
  std::vector<double> coll, comp, ppws, clear, kinds_pw[size_t(ObstacleKind::NUM_KINDS)];
  std::vector<TrialResult> all;
  int never = 0;
  for (const SetWorld& sw : set)
  {
    const Summary S(sw.res);
    coll.push_back(S.collisionsPerTrial());
    comp.push_back(S.completion());
    ppws.push_back(S.ppwsMean());
    clear.push_back(S.clearance());
    for (size_t k = 0; k < size_t(ObstacleKind::NUM_KINDS); ++k) kinds_pw[k].push_back(S.kinds[k] / S.n);
    never += S.nppws == 0;
    all.insert(all.end(), sw.res.begin(), sw.res.end());
  }
  const SetFigure f_coll = overWorlds(set, coll, true), f_comp = overWorlds(set, comp, false),
                  f_ppws = overWorlds(set, ppws, false), f_clear = overWorlds(set, clear, false);
  const Summary A(all);  // pooled over every trial: the worst trial, time, latency, cue modes
  std::vector<double> kind_mean(size_t(ObstacleKind::NUM_KINDS));
  for (size_t k = 0; k < kind_mean.size(); ++k) kind_mean[k] = overWorlds(set, kinds_pw[k], true).mean;
  const int n_worlds = int(set.size());
  std::printf("\nmobility_trials over %d generated worlds (kind %s, seeds %ld-%ld%s%s), mode %s, %d trials per world "
              "(trial seeds %ld000 + k)\n",
              n_worlds, kind_label.c_str(), seed_base, seed_base + generated - 1,
              people ? (", " + std::to_string(people) + " people each").c_str() : "",
              failed ? (", " + std::to_string(failed) + " not generated").c_str() : "", label.c_str(), trials, seed);
  std::printf("                       mean over worlds   worst world\n");
  std::printf("  completion           %6.0f %%           %5.0f %% (%s)\n", 100 * f_comp.mean, 100 * f_comp.worst,
              f_comp.worst_world.c_str());
  std::printf("  collisions / trial   %6.2f             %5.2f (%s); worst trial %.0f\n", f_coll.mean, f_coll.worst,
              f_coll.worst_world.c_str(), A.worst);
  std::printf("    by kind            wall %.2f, overhang %.2f, glass %.2f, furniture %.2f, people %.2f\n", kind_mean[0],
              kind_mean[1], kind_mean[2], kind_mean[3], kind_mean[size_t(ObstacleKind::PERSON)]);
  std::printf("  PPWS                 %6s %%           %5s %% (%s); %d of %d worlds without a completed trial\n",
              num(f_ppws.mean, 1).c_str(), num(f_ppws.worst, 1).c_str(), f_ppws.worlds ? f_ppws.worst_world.c_str() : "-",
              never, n_worlds);
  std::printf("  mean clearance       %6.2f m           %5.2f m (%s)\n", f_clear.mean, f_clear.worst,
              f_clear.worst_world.c_str());
  std::printf("  time to completion   %s s (mean of the completed trials)\n", num(A.timeMean(), 1).c_str());
  const double cycles = A.cycles();
  if (cycles > 0)
    std::printf("  cues                 idle %.0f %%, guidance %.0f %%, proximity %.0f %%, alert %.0f %%, unsure %.0f %%\n",
                100 * A.modes[0] / cycles, 100 * A.modes[1] / cycles, 100 * A.modes[2] / cycles, 100 * A.modes[3] / cycles,
                100 * A.modes[4] / cycles);
  reportUnsure(A);
  reportTime(A);
  std::printf("  wall time            %.1f s: generation %.1f s, trials %.1f s\n", wall_s, gen_total, trials_total);
  std::printf("  heat maps            %s_<world>.png\n", prefix.c_str());
  if (opt.mode == TrialMode::FLOOR) reportFloor(all);
  reportCauses(all);
  std::printf("{\"world\": \"generated\", \"kind\": %s, \"worlds\": %d, \"worlds_failed\": %d, \"seed_base\": %ld, "
              "\"mode\": \"%s\", \"cues\": %s, \"trials\": %d, \"trials_per_world\": %d, "
              "\"collisions_per_trial\": %s, \"collisions_per_trial_worst\": %s, \"collisions_per_trial_worst_world\": %s, "
              "\"collisions_worst\": %.0f, \"completion_rate\": %s, \"completion_rate_worst\": %s, "
              "\"completion_rate_worst_world\": %s, \"time_s_mean\": %s, \"ppws_pct\": %s, \"ppws_pct_worst\": %s, "
              "\"ppws_pct_worst_world\": %s, \"worlds_without_completion\": %d, \"mean_clearance_m\": %s, "
              "\"mean_clearance_m_worst\": %s, \"latency_ms_median\": %s, \"latency_ms_p99\": %s, "
              "\"wall_collisions_per_trial\": %s, \"overhang_collisions_per_trial\": %s, "
              "\"glass_collisions_per_trial\": %s, \"furniture_collisions_per_trial\": %s, \"people_collisions_per_trial\": %s, "
              "\"unsure_cue_pct\": %s, \"frames_without_cue\": %ld, \"walking_pct\": %s, \"stop_turns_per_trial\": %s, "
              "\"stops_per_trial\": %s, \"generate_s\": %s, \"trials_s\": %s}\n",
              jsonStr(kind_label).c_str(), n_worlds, failed, seed_base, mode.c_str(), opt.cues_enabled ? "true" : "false",
              int(A.n), trials, num(f_coll.mean).c_str(), num(f_coll.worst).c_str(), jsonStr(f_coll.worst_world).c_str(),
              A.worst, num(f_comp.mean).c_str(), num(f_comp.worst).c_str(), jsonStr(f_comp.worst_world).c_str(),
              num(A.timeMean(), 2).c_str(), num(f_ppws.mean, 1).c_str(), num(f_ppws.worst, 1).c_str(),
              f_ppws.worlds ? jsonStr(f_ppws.worst_world).c_str() : "null", never, num(f_clear.mean).c_str(),
              num(f_clear.worst).c_str(), num(A.latency(0.5), 1).c_str(), num(A.latency(0.99), 1).c_str(),
              num(kind_mean[0]).c_str(), num(kind_mean[1]).c_str(), num(kind_mean[2]).c_str(), num(kind_mean[3]).c_str(),
              num(kind_mean[size_t(ObstacleKind::PERSON)]).c_str(), num(A.unsurePct(), 1).c_str(), A.missed,
              num(A.walkingPct(), 1).c_str(), num(A.begunPerTrial(assistive_tactile::Instruction::TURN), 2).c_str(),
              num(A.begunPerTrial(assistive_tactile::Instruction::STOP), 2).c_str(), num(gen_total, 2).c_str(),
              num(trials_total, 2).c_str());
  return 0;
}
