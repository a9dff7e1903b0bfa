// mobility_trials: a simulated wearer walks a world's course closed loop (issue 19, seed 5.4-5.5).
//   rosrun assistive_sim mobility_trials --world W [--trials N] [--mode truth|cane|vision] [--seed S]
//       [--plot FILE.png] [--no-cues] [--reaction S] [--turn-rate DEG_S]
// Prints one row per trial, a summary table, and as the last line the JSON keys of SPEC.md.
#include <netinet/in.h>
#include <signal.h>
#include <sys/socket.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <thread>

#include <cmath>
#include <cstdio>
#include <iostream>
#include <numeric>
#include <string>
#include <vector>

#include <opencv2/imgcodecs.hpp>

#include <ros/ros.h>

#include <assistive_sim/ros_chain.h>
#include <assistive_sim/trials.h>

using namespace assistive_sim;

namespace
{
void usage(std::ostream& os = std::cerr)
{
  os << "usage: mobility_trials --world W [--trials N] [--mode truth|cane|vision] [--seed S] [--plot FILE.png]\n"
        "                       [--no-cues] [--reaction S] [--turn-rate DEG_S] [--turn-on DEG]\n"
        "                       [--body-half-width M] [--chord-min M] (planner: free_ahead strip, heading chord; truth)\n"
        "                       [--timeout-factor X] (a trial ends unfinished after X x the guide's time + 20 s; 4)\n"
        "                       [--wearer population|typical] [--slowest-decile] [--unsure-at S [--unsure-for S]]\n"
        "                       [--timelines PREFIX] (one cue timeline PNG per trial: PREFIX<k>.png)\n"
        "  --wearer: each trial's wearer drawn from the population (default; docs/wearer_population.md) or the\n"
        "            typical adult of WearerParams; --slowest-decile: every wearer from the slowest-reacting 10 %.\n"
        "  --unsure-at: a scripted UNSURE episode (no pose) at that trial time (truth mode): unsure_walked_m.\n"
        "  W: a shipped world's name (course corridor parking glass plaza) or a world YAML.\n"
        "  truth: the world's occupancy -> planner core -> cue logic core -> simulated vest wearer (no ROS);\n"
        "  cane: the cane-only walker. --no-cues removes the cue stage (the vest stays silent).\n"
        "  vision: the renderer and the whole pipeline.launch in one nodelet manager (a private roscore and\n"
        "          roslaunch assistive_sim mobility_vision.launch per trial), lock-stepped on simulated time.\n"
        "  Heat map: --plot (default mobility_<world>_<mode>.png in the current folder).\n";
}

std::string worldsDir()
{
  for (const char* d : { ASSISTIVE_SIM_SOURCE_WORLDS, ASSISTIVE_SIM_SHARE_WORLDS })
  {
    struct stat st;
    if (stat(d, &st) == 0) return d;
  }
  return ".";
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

/// A child process in its own process group, output to `log`.
pid_t spawn(const std::vector<std::string>& args, const std::string& log)
{
  const pid_t pid = fork();
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
}  // namespace

int main(int argc, char** argv)
{
  std::string world_arg, mode = "truth", plot, timelines;
  int trials = 20;
  long seed = 1;
  TrialOptions opt;
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
      else if (a == "--trials") trials = std::stoi(val());
      else if (a == "--mode") mode = val();
      else if (a == "--seed") seed = std::stol(val());
      else if (a == "--plot") plot = val();
      else if (a == "--no-cues") opt.cues_enabled = false;
      else if (a == "--reaction") opt.wearer.reaction_s = std::stod(val());
      else if (a == "--turn-rate") opt.wearer.turn_rate_deg = std::stod(val());
      else if (a == "--turn-on") opt.cues.turn_on_deg = std::stod(val());
      else if (a == "--body-half-width") opt.planner.body_half_width = std::stod(val());
      else if (a == "--chord-min") opt.planner.heading_chord_min = std::stod(val());
      else if (a == "--timeout-factor") opt.timeout_factor = std::stod(val());
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
      else if (a == "--fix")  // analysis: name=value replaces a drawn trait (reaction, gain, sigma, bias, levels)
      {
        const std::string v = val();
        const size_t eq = v.find('=');
        if (eq == std::string::npos) throw std::invalid_argument("--fix");
        const std::string k = v.substr(0, eq);
        const double x = std::stod(v.substr(eq + 1));
        if (k == "reaction") opt.fix_reaction_s = x;
        else if (k == "gain") opt.fix_turn_gain = x;
        else if (k == "sigma") opt.fix_veer_sigma = x;
        else if (k == "bias") opt.fix_veer_bias = x;
        else if (k == "levels") opt.fix_levels = int(x);
        else throw std::invalid_argument("--fix");
      }
      else if (a == "--cue")  // analysis: name=value of a cue parameter (veer_step, veer_on, alert_reaction, turn_on)
      {
        const std::string v = val();
        const size_t eq = v.find('=');
        if (eq == std::string::npos) throw std::invalid_argument("--cue");
        const std::string k = v.substr(0, eq);
        const double x = std::stod(v.substr(eq + 1));
        if (k == "veer_step") opt.cues.veer_step_deg = x;
        else if (k == "veer_on") opt.cues.veer_on_deg = x;
        else if (k == "alert_reaction") opt.cues.alert_reaction_s = x;
        else if (k == "turn_on") opt.cues.turn_on_deg = x;
        else if (k == "settle") opt.cues.settle_timeout_s = x;
        else throw std::invalid_argument("--cue");
      }
      else if (a == "--unsure-at") opt.unsure_at_s = std::stod(val());
      else if (a == "--unsure-for") opt.unsure_for_s = std::stod(val());
      else if (a == "--timelines") timelines = val();
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
  if (world_arg.empty() || trials < 1)
  {
    usage();
    return 2;
  }
  if (mode == "truth") opt.mode = TrialMode::TRUTH;
  else if (mode == "cane") opt.mode = TrialMode::CANE;
  else if (mode == "vision") opt.mode = TrialMode::VISION;
  else
  {
    std::cerr << "mobility_trials: --mode must be truth, cane or vision\n";
    return 2;
  }
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
  opt.wearer.walk_speed = world.trajectory.speed;  // the typical wearer's; a drawn one walks at its own
  const std::string label = mode + (opt.cues_enabled ? "" : " (no cues)");

  std::vector<TrialResult> res;
  const bool tty = isatty(2);
  std::printf("%-5s %-7s %-9s %-8s %-8s %-6s %-5s %-8s %-6s %-7s %-7s %-9s\n", "trial", "seed", "completed", "time_s",
              "guide_s", "ppws", "coll", "wall/ovh", "glass", "furn", "people", "clear_m");
  // vision: a private roscore for the run, a fresh pipeline (roslaunch) for each trial
  pid_t core = -1;
  std::string vision_log_dir;
  if (opt.mode == TrialMode::VISION)
  {
    const int port = freePort();
    const std::string uri = "http://localhost:" + std::to_string(port);
    setenv("ROS_MASTER_URI", uri.c_str(), 1);
    char tmpl[] = "/tmp/mobility_vision_XXXXXX";
    vision_log_dir = mkdtemp(tmpl) ? tmpl : "/tmp";
    core = spawn({ "roscore", "-p", std::to_string(port) }, vision_log_dir + "/roscore.log");
    int rargc = 1;
    char name[] = "mobility_trials";
    char* rargv[] = { name, nullptr };
    ros::init(rargc, rargv, "mobility_trials", ros::init_options::NoSigintHandler);
    const auto until = std::chrono::steady_clock::now() + std::chrono::seconds(30);
    while (!ros::master::check() && std::chrono::steady_clock::now() < until)
      std::this_thread::sleep_for(std::chrono::milliseconds(200));
    if (!ros::master::check())
    {
      std::cerr << "mobility_trials: the private roscore did not come up (" << vision_log_dir << "/roscore.log)\n";
      stopChild(core);
      return 1;
    }
    ros::start();
    std::cerr << "mobility_trials: vision mode, master " << uri << ", logs in " << vision_log_dir << "\n";
  }
  for (int k = 0; k < trials; ++k)
  {
    const uint32_t s = uint32_t(seed * 1000 + k);
    if (opt.mode == TrialMode::VISION)
    {
      const std::string log = vision_log_dir + "/trial" + std::to_string(k) + ".log";
      RosChain::Options ro;
      ro.kind = RosChain::VISION;
      ro.eye_height = world.trajectory.eye_height;
      // A fresh chain per trial: its t = 0 is at start_time + warmup_s of simulated time; the
      // renderer puts the people where they are on the trial's clock.
      const pid_t launch = spawn({ "roslaunch", "assistive_sim", "mobility_vision.launch", "world:=" + world_arg,
                                   "people_time_origin:=" + num(ro.start_time + ro.warmup_s, 6) },
                                 log);
      ros::NodeHandle nh;
      RosChain chain(nh, world, ro);
      // the pipeline is up when the cue logic publishes and the renderer listens for poses
      const auto until = std::chrono::steady_clock::now() + std::chrono::seconds(120);
      while (std::chrono::steady_clock::now() < until &&
             !(topicPublished("/tactile/cue") && topicPublished("/planner/state") && topicPublished("/stereo/left/image_rect")))
        std::this_thread::sleep_for(std::chrono::milliseconds(250));
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
        stopChild(core);
        return 1;
      }
      stopChild(launch);
    }
    else
      res.push_back(runTrial(world, opt, s, k));
    const TrialResult& r = res.back();
    if (!timelines.empty())
    {
      char t[160];
      std::snprintf(t, sizeof(t), "%s trial %d: speed %.2f m/s, reaction %.2f s, turn gain %.2f, %d levels%s", world.name.c_str(),
                    k, r.wearer.walk_speed, r.wearer.reaction_s, r.wearer.turn_gain, r.wearer.intensity_levels,
                    r.completed ? "" : ", NOT completed");
      cv::imwrite(timelines + std::to_string(k) + ".png", timelinePlot(r, t));
    }
    std::printf("%-5d %-7u %-9s %-8.1f %-8.1f %-6.0f %-5d %d/%-6d %-6d %-7d %-7d %-9.2f\n", k, s,
                r.completed ? "yes" : "NO", r.time_s, r.guide_time_s, r.ppws_pct, r.totalCollisions(), r.collisions[0],
                r.collisions[1], r.collisions[2], r.collisions[3], r.collisions[size_t(ObstacleKind::PERSON)],
                r.mean_clearance_m);
    std::fflush(stdout);
    const int w = 30, done = (k + 1) * w / trials;
    std::fprintf(stderr, "%s[%s%s] %d/%d trials", tty ? "\r" : "", std::string(size_t(done), '#').c_str(),
                 std::string(size_t(w - done), '.').c_str(), k + 1, trials);
    if (!tty || k + 1 == trials) std::fprintf(stderr, "\n");
  }
  const double n = double(res.size());
  double coll = 0, comp = 0, ppws = 0, nppws = 0, clear = 0, tmean = 0, worst = 0, ppws_worst = NAN, unsure_max = NAN;
  for (const TrialResult& r : res)
  {
    const double p = r.completed ? r.ppws_pct : 0.0;
    ppws_worst = std::isnan(ppws_worst) ? p : std::min(ppws_worst, p);
    if (std::isfinite(r.unsure_walked_m)) unsure_max = std::isnan(unsure_max) ? r.unsure_walked_m : std::max(unsure_max, r.unsure_walked_m);
  }
  std::array<double, size_t(ObstacleKind::NUM_KINDS)> kinds{};
  std::array<double, 5> modes{};
  for (const TrialResult& r : res)
  {
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
  }
  const double cycles = std::accumulate(modes.begin(), modes.end(), 0.0);
  std::vector<double> lat;
  long missed = 0;
  for (const TrialResult& r : res)
  {
    lat.insert(lat.end(), r.latency_ms.begin(), r.latency_ms.end());
    missed += r.missed_cues;
  }
  std::sort(lat.begin(), lat.end());
  auto pct = [&](double q) {
    if (lat.empty()) return double(NAN);
    return lat[std::min(lat.size() - 1, size_t(std::floor(q * double(lat.size() - 1) + 0.5)))];
  };
  const double lat_med = pct(0.5), lat_p99 = pct(0.99);
  if (core > 0)
  {
    ros::shutdown();
    stopChild(core);
  }
  const double ppws_mean = nppws ? ppws / nppws : NAN, t_mean = nppws ? tmean / nppws : NAN;
  if (plot.empty()) plot = "mobility_" + world.name + "_" + mode + (opt.cues_enabled ? "" : "_nocues") + ".png";
  const cv::Mat img = heatMap(world, res, opt.dt,
                              world.name + ": " + label + ", " + std::to_string(trials) + " trials, " +
                                  num(coll / n, 2) + " collisions/trial");
  const bool wrote = cv::imwrite(plot, img);

  std::printf("\nmobility_trials %s, mode %s, %d trials (seed %ld)\n", world.name.c_str(), label.c_str(), trials, seed);
  std::printf("  completion           %.0f %%\n", 100.0 * comp / n);
  const double people_coll = kinds[size_t(ObstacleKind::PERSON)] / n;
  std::printf("  collisions / trial   %.2f (worst trial %.0f): wall %.2f, overhang %.2f, glass %.2f, furniture %.2f, "
              "people %.2f\n",
              coll / n, worst, kinds[0] / n, kinds[1] / n, kinds[2] / n, kinds[3] / n, people_coll);
  if (!world.people.empty())
  {
    double closest = 0.0;
    for (const TrialResult& r : res) closest += r.min_person_clearance_m;
    std::printf("  people               %zu scripted (they do not react to the wearer); closest approach %.2f m "
                "(body surfaces, mean over trials)\n",
                world.people.size(), closest / n);
  }
  std::printf("  time to completion   %s s (mean of completed), PPWS %s %% (sighted guide = 100)\n", num(t_mean, 1).c_str(),
              num(ppws_mean, 1).c_str());
  std::printf("  mean clearance       %.2f m (body surface to the nearest obstacle)\n", clear / n);
  std::printf("  wearers              %s; PPWS of the worst trial %s %% (0 = not completed)\n",
              !opt.population ? "the typical adult (--wearer typical)" :
              opt.slowest_decile ? "the slowest-reacting 10 % of the population" : "drawn from the population",
              num(ppws_worst, 1).c_str());
  if (std::isfinite(unsure_max))
    std::printf("  UNSURE episode       at %.1f s for %.1f s: walked at most %.2f m after it began\n", opt.unsure_at_s,
                opt.unsure_for_s, unsure_max);
  if (cycles > 0)
    std::printf("  cues                 idle %.0f %%, guidance %.0f %%, proximity %.0f %%, alert %.0f %%, unsure %.0f %%\n",
                100 * modes[0] / cycles, 100 * modes[1] / cycles, 100 * modes[2] / cycles, 100 * modes[3] / cycles,
                100 * modes[4] / cycles);
  if (lat.empty())
    std::printf("  latency              n/a in %s mode (no camera pipeline)\n", mode.c_str());
  else
    std::printf("  latency              image -> /tactile/cue (wall clock; the vest bridge is not in pipeline.launch): "
                "median %.1f ms, p99 %.1f ms over %zu frames; %ld frames without their cue\n",
                lat_med, lat_p99, lat.size(), missed);
  std::printf("  heat map             %s%s\n", plot.c_str(), wrote ? "" : " (could not write)");
  std::printf("{\"world\": \"%s\", \"mode\": \"%s\", \"cues\": %s, \"trials\": %d, \"collisions_per_trial\": %s, "
              "\"collisions_worst\": %.0f, \"completion_rate\": %s, \"time_s_mean\": %s, \"ppws_pct\": %s, "
              "\"mean_clearance_m\": %s, \"latency_ms_median\": %s, \"latency_ms_p99\": %s, "
              "\"wall_collisions_per_trial\": %s, \"overhang_collisions_per_trial\": %s, "
              "\"glass_collisions_per_trial\": %s, \"furniture_collisions_per_trial\": %s, \"people_collisions_per_trial\": %s, "
              "\"unsure_cue_pct\": %s, \"frames_without_cue\": %ld, \"ppws_pct_worst\": %s, \"unsure_walked_m_max\": %s, "
              "\"wearers\": \"%s\"}\n",
              world.name.c_str(), mode.c_str(), opt.cues_enabled ? "true" : "false", trials, num(coll / n).c_str(), worst,
              num(comp / n).c_str(), num(t_mean, 2).c_str(), num(ppws_mean, 1).c_str(), num(clear / n).c_str(),
              num(lat_med, 1).c_str(), num(lat_p99, 1).c_str(), num(kinds[0] / n).c_str(), num(kinds[1] / n).c_str(), num(kinds[2] / n).c_str(), num(kinds[3] / n).c_str(),
              num(people_coll).c_str(), cycles > 0 ? num(100 * modes[4] / cycles, 1).c_str() : "null", missed,
              num(ppws_worst, 1).c_str(), num(unsure_max, 3).c_str(),
              !opt.population ? "typical" : opt.slowest_decile ? "slowest_decile" : "population");
  return 0;
}
