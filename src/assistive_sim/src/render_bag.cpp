// render_bag: render a world's scripted walk into a stereo bag with ground truth (no roscore).
//   rosrun assistive_sim render_bag --world course --out course.bag [--seed N] [--frames N]
//       [--width W --height H] [--rate HZ] [--noise SIGMA] [--exposure-time S] [--imu-rate HZ]
//       [--imperfect [--errors-seed N]] [--baseline-error X] [--focal-error X] [--right-rotation-deg RX,RY,RZ]
//       [--distortion K1[,K2]] [--rolling-shutter S] [--ae-step X] [--ae-interval S]
// The camera imperfections (README "Camera imperfections"): the images come from the imperfect rig,
// the bag's camera_info keeps the nominal calibration; what was applied is written to the bag
// (/sim/camera_errors, std_msgs/String, JSON) and to the summary's JSON line.
#include <chrono>
#include <cmath>
#include <ctime>
#include <cstdio>
#include <cstring>
#include <iostream>
#include <limits>
#include <optional>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include <rosbag/bag.h>

#include <assistive_sim/motion.h>
#include <assistive_sim/people_msg.h>
#include <assistive_sim/renderer.h>
#include <assistive_sim/ultrasonic.h>
#include <assistive_eval/stereo_bag.h>
#include <assistive_sim/world.h>

using namespace assistive_sim;
using assistive_eval::StereoBagWriter;

namespace
{
void usage(std::ostream& os = std::cerr)
{
  os << "usage: render_bag --world WORLD --out FILE.bag [--seed N] [--frames N] [--width W --height H]\n"
               "                  [--rate HZ] [--noise SIGMA] [--exposure-time S] [--exposure-variation X] [--imu-rate HZ]\n"
               "                  [--depth]  (also write the left ground-truth depth, /ground_truth/left/depth)\n"
               "                  [--truth-resolution M]  the ground-truth grid's cell (default 0.2 m; the map's cell_size)\n"
               "                  [--no-sonar]  (no /sonar/front: the vest's forward ultrasonic ranger, 20 Hz)\n"
               "                  [--passive]  a passive pair only; default: the reference camera, an active pair whose\n"
               "                    pattern projector's emitter is on for a second pair half a frame after each\n"
               "                    (/stereo/projected/{left,right}/{image_rect,camera_info}; /stereo/* keep the emitter-off pairs)\n"
               "                  [--lux L]  the scene's ambient light (default: the world's; 300 indoors, 10000 outdoors)\n"
               "                  [--imperfect]  random camera errors inside the published ranges, drawn from the seed\n"
               "                  [--errors-seed N]  draw them from N instead (the walk and noise keep --seed)\n"
               "                  [--baseline-error X] [--focal-error X]  true = nominal * (1 + X); camera_info stays nominal\n"
               "                  [--right-rotation-deg RX,RY,RZ]  right camera rotated against the rectified rig\n"
               "                  [--distortion K1[,K2]]  residual radial distortion   [--rolling-shutter S]  readout time\n"
               "                  [--ae-step X] [--ae-interval S]  auto-exposure gain steps (1+X)^+-1, per camera\n"
               "                  (explicit options override the --imperfect draw; README \"Camera imperfections\")\n"
               "  WORLD: a shipped world (course, corridor, parking, glass, plaza) or a world YAML path\n";
}

std::string worldsDir()
{
  for (const char* d : {ASSISTIVE_SIM_SHARE_WORLDS, ASSISTIVE_SIM_SOURCE_WORLDS})
  {
    std::FILE* f = std::fopen((std::string(d) + "/course.yaml").c_str(), "r");
    if (f)
    {
      std::fclose(f);
      return d;
    }
  }
  return ASSISTIVE_SIM_SOURCE_WORLDS;
}

/// CPU time of this thread (s): the one-core cost of rendering, independent of other load.
double threadCpuSeconds()
{
  timespec ts;
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return ts.tv_sec + 1e-9 * ts.tv_nsec;
}

void progress(int done, int total, double fps)
{
  const int width = 40;
  const int filled = total > 0 ? done * width / total : 0;
  std::fprintf(stderr, "\r[%.*s%*s] %d/%d  %.1f frames/s", filled, "########################################",
               width - filled, "", done, total, fps);
  std::fflush(stderr);
}
}  // namespace

int main(int argc, char** argv)
{
  std::string world_name, out;
  uint32_t seed = 1;
  int frames = -1;
  CameraParams cam;
  ImuParams imu_p;
  UltrasonicParams sonar_p;
  bool with_sonar = true;
  OccupancyParams truth_op;  // the truth grid written to the bag (its cell: the map's cell_size it is scored against)
  double rate = 15.0;
  bool write_depth = false, imperfect = false, exposure_given = false, passive = false;
  double lux = -1.0;
  long errors_seed = -1;  // --errors-seed: the imperfections' draw (default: --seed)
  // Explicit imperfections (applied over the --imperfect draw): name -> value(s)
  std::vector<std::pair<std::string, std::vector<double>>> explicit_errors;
  auto numbers = [](const std::string& s) {
    std::vector<double> v;
    std::stringstream ss(s);
    std::string part;
    while (std::getline(ss, part, ',')) v.push_back(std::stod(part));
    return v;
  };
  for (int i = 1; i < argc; ++i)
  {
    const std::string a = argv[i];
    auto val = [&]() -> std::string {
      if (i + 1 >= argc)
      {
        std::cerr << "render_bag: " << a << " needs a value\n";
        usage();
        std::exit(2);
      }
      return argv[++i];
    };
    try
    {
      if (a == "--world") world_name = val();
      else if (a == "--out") out = val();
      else if (a == "--seed") seed = static_cast<uint32_t>(std::stoul(val()));
      else if (a == "--frames") frames = std::stoi(val());
      else if (a == "--width") cam.calib.width = std::stoi(val());
      else if (a == "--height") cam.calib.height = std::stoi(val());
      else if (a == "--rate") rate = std::stod(val());
      else if (a == "--noise") cam.noise_sigma = std::stod(val());
      else if (a == "--exposure-time")
      {
        cam.exposure_time = std::stod(val());
        exposure_given = true;
      }
      else if (a == "--imperfect") imperfect = true;
      else if (a == "--errors-seed")
      {
        errors_seed = std::stol(val());
        if (errors_seed < 0) throw std::invalid_argument(a);
      }
      else if (a == "--baseline-error" || a == "--focal-error" || a == "--right-rotation-deg" || a == "--distortion" ||
               a == "--rolling-shutter" || a == "--ae-step" || a == "--ae-interval")
      {
        const std::vector<double> v = numbers(val());
        const size_t want = a == "--right-rotation-deg" ? 3 : 1;
        if (v.size() != want && !(a == "--distortion" && (v.size() == 1 || v.size() == 2)))
          throw std::invalid_argument(a);
        explicit_errors.emplace_back(a, v);
      }
      else if (a == "--exposure-variation") cam.exposure_variation = std::stod(val());
      else if (a == "--imu-rate") imu_p.rate = std::stod(val());
      else if (a == "--depth") write_depth = true;
      else if (a == "--no-sonar") with_sonar = false;
      else if (a == "--truth-resolution")
      {
        truth_op.resolution = std::stod(val());
        if (!(truth_op.resolution >= 0.02 && truth_op.resolution <= 2.0)) throw std::invalid_argument(a);  // cell_size's range
      }
      else if (a == "--passive") passive = true;
      else if (a == "--lux")
      {
        lux = std::stod(val());
        if (!(lux > 0.0)) throw std::invalid_argument(a);
      }
      else if (a == "-h" || a == "--help")
      {
        usage(std::cout);
        return 0;
      }
      else
      {
        std::cerr << "render_bag: unknown argument " << a << "\n";
        usage();
        return 2;
      }
    }
    catch (const std::exception&)
    {
      std::cerr << "render_bag: bad value for " << a << "\n";
      usage();
      return 2;
    }
  }
  if (world_name.empty() || out.empty())
  {
    std::cerr << "render_bag: --world and --out are required\n";
    usage();
    return 2;
  }
  if (cam.calib.width < 8 || cam.calib.height < 8 || rate <= 0 || imu_p.rate <= 0 || cam.noise_sigma < 0 ||
      cam.exposure_time < 0 || cam.exposure_variation < 0 || cam.exposure_variation >= 1)
  {
    std::cerr << "render_bag: width/height >= 8, rate > 0, noise >= 0, exposure time >= 0, exposure variation in [0, 1) required\n";
    return 2;
  }
  // Keep the principal point at the image centre and the focal length at 500 px per 640 px.
  cam.calib.fx = cam.calib.fy = 500.0 * cam.calib.width / 640.0;
  cam.calib.cx = (cam.calib.width - 1) / 2.0;
  cam.calib.cy = (cam.calib.height - 1) / 2.0;
  cam.seed = seed;
  if (imperfect)
  {
    double exposure = 0.0;
    cam.errors = CameraErrors::random(errors_seed >= 0 ? static_cast<uint32_t>(errors_seed) : seed, &exposure);
    if (!exposure_given) cam.exposure_time = exposure;  // motion blur drawn too unless given
  }
  for (const auto& [name, v] : explicit_errors)
  {
    CameraErrors& e = cam.errors;
    if (name == "--baseline-error") e.baseline_scale = v[0];
    else if (name == "--focal-error") e.focal_scale = v[0];
    else if (name == "--right-rotation-deg") e.right_rotation = Eigen::Vector3d(v[0], v[1], v[2]) * M_PI / 180.0;
    else if (name == "--distortion") e.k1 = v[0], e.k2 = v.size() > 1 ? v[1] : 0.0;
    else if (name == "--rolling-shutter") e.rolling_shutter_s = v[0];
    else if (name == "--ae-step") e.ae_step = v[0];
    else if (name == "--ae-interval") e.ae_interval_s = v[0];
  }
  {
    const CameraErrors& e = cam.errors;
    if (std::abs(e.baseline_scale) >= 0.5 || std::abs(e.focal_scale) >= 0.5 || e.right_rotation.norm() > 0.2 ||
        e.rolling_shutter_s < 0 || e.rolling_shutter_s > 0.2 || e.ae_step < 0 || e.ae_step >= 1 || e.ae_interval_s <= 0)
    {
      std::cerr << "render_bag: camera errors out of range (|baseline, focal error| < 0.5, rotation <= 11 deg,\n"
                   "  rolling shutter in [0, 0.2] s, ae step in [0, 1), ae interval > 0)\n";
      return 2;
    }
  }
  const std::string errors_json = cam.errors.json(cam.exposure_time);
  cam.projector.enabled = !passive;

  try
  {
    const std::string path = resolveWorldPath(world_name, worldsDir());
    World world = World::load(path);
    if (lux > 0.0) world.illuminance_lux = lux;
    const WearerMotion motion(world.trajectory, seed);
    StereoRenderer renderer(world, cam);
    ImuSimulator imu(imu_p, seed);
    UltrasonicRanger sonar(world, sonar_p, seed);
    int sonar_k = 0;
    const int total = static_cast<int>(std::floor(motion.duration() * rate)) + 1;
    const int n = frames > 0 ? std::min(frames, total) : total;
    const double t0 = 100.0;  // bag stamps start here (ros::Time 0 means "unset")

    StereoBagWriter writer(out);
    writer.writeOccupancy(computeOccupancy(world, truth_op), t0);
    writer.writeString("/sim/camera_errors", errors_json, t0);
    RenderOutput ro;
    std::vector<assistive_msgs::MoverArray> people_truth;  // /ground_truth/people, one per frame
    double render_s = 0.0, render_cpu_s = 0.0;
    int projected = 0;
    const auto wall0 = std::chrono::steady_clock::now();
    const Eigen::Matrix3d R_lo = linkToLeftOptical().linear();
    for (int k = 0; k < n; ++k)
    {
      const double t = k / rate;
      StereoFrame f;
      while (imu.nextTime() <= t + 1e-9) f.imu.push_back(imu.next(motion, t0));
      for (double ts = sonar_k / sonar_p.rate; with_sonar && ts <= t + 1e-9; ts = ++sonar_k / sonar_p.rate)
      {
        const std::optional<double> r = sonar.ping(motion.linkPose(ts) * linkToSonar(), ts);
        writer.writeRange(t0 + ts, r ? *r : std::numeric_limits<double>::infinity(), sonar_p.beam_width,
                          sonar_p.min_range, sonar_p.max_range);
      }
      const Eigen::Isometry3d T = motion.leftOpticalPose(t);
      const Eigen::Vector3d omega_opt = R_lo.transpose() * motion.angularVelocity(t);
      const auto r0 = std::chrono::steady_clock::now();
      const double c0 = threadCpuSeconds();
      renderer.render(T, t, static_cast<uint64_t>(k), ro, omega_opt, motion.velocity(t));
      render_cpu_s += threadCpuSeconds() - c0;
      render_s += std::chrono::duration<double>(std::chrono::steady_clock::now() - r0).count();
      f.stamp = t0 + t;
      f.left = ro.left;
      f.right = ro.right;
      f.calib = cam.calib;
      f.has_gt_pose = true;
      f.gt_pose = T;
      f.gt_velocity = motion.velocity(t);
      if (write_depth) f.gt_depth = ro.depth_left;
      writer.writeFrame(f);
      if (cam.projector.enabled)
      {
        // The emitter-on pair half a frame later (the pair runs at twice the rate, the emitter on
        // every other frame); its noise is its own (a frame index no emitter-off pair uses).
        const double tp = t + 0.5 / rate;
        const double c1 = threadCpuSeconds();
        const auto w1 = std::chrono::steady_clock::now();
        renderer.setEmitter(true);
        renderer.render(motion.leftOpticalPose(tp), tp, static_cast<uint64_t>(k) + (1ull << 32), ro,
                        R_lo.transpose() * motion.angularVelocity(tp), motion.velocity(tp));
        renderer.setEmitter(false);
        render_cpu_s += threadCpuSeconds() - c1;
        render_s += std::chrono::duration<double>(std::chrono::steady_clock::now() - w1).count();
        StereoFrame fp;
        fp.stamp = t0 + tp;
        fp.left = ro.left;
        fp.right = ro.right;
        fp.calib = cam.calib;
        writer.writeProjectedFrame(fp);
        ++projected;
      }
      if (!world.people.empty()) people_truth.push_back(peopleMessage(world, t, ros::Time(t0 + t), "gt_world"));
      if (k % 5 == 0 || k + 1 == n) progress(k + 1, n, (k + 1) / std::max(render_cpu_s, 1e-9));
    }
    writer.close();
    if (!people_truth.empty())
    {
      // The stereo bag writer has no mover topic: append the people truth to the closed bag.
      rosbag::Bag bag(out, rosbag::bagmode::Append);
      for (const auto& m : people_truth) bag.write("/ground_truth/people", m.header.stamp, m);
      bag.close();
    }
    std::fprintf(stderr, "\n");
    const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - wall0).count();
    const double render_fps = (n + projected) / std::max(render_cpu_s, 1e-9);
    const double render_fps_wall = (n + projected) / std::max(render_s, 1e-9);
    const double t_last = (n - 1) / rate;
    std::printf("world            %s (%s)\n", world.name.c_str(), path.c_str());
    std::printf("output           %s\n", out.c_str());
    std::printf("frames           %d of %d (%.1f s of %.1f s walk, %.1f m path)\n", n, total, t_last,
                motion.duration(), motion.pathLength());
    std::printf("image            %dx%d at %.1f Hz, seed %u, %zu triangles\n", cam.calib.width, cam.calib.height,
                rate, seed, renderer.triangleCount());
    if (cam.projector.enabled)
      std::printf("projector        %zu dots, emitter on for %d pairs half a frame after each (/stereo/projected), %.0f lux\n",
                  renderer.dotCount(), projected, world.ambientLux());
    else
      std::printf("projector        none (--passive)\n");
    std::printf("render_fps       %.1f stereo frames/s (rendering only, per second of this thread's CPU time)\n",
                render_fps);
    std::printf("render_fps_wall  %.1f stereo frames/s (rendering only, wall clock; lower when the machine is shared)\n",
                render_fps_wall);
    std::printf("total_fps        %.1f frames/s (with IMU, ground truth and bag writing)\n", n / wall);
    if (!world.people.empty()) std::printf("people           %zu (/ground_truth/people)\n", world.people.size());
    std::printf("camera_errors    %s%s\n", errors_json.c_str(), cam.errors.any() ? "" : " (ideal rig)");
    std::printf("{\"frames\": %d, \"render_fps\": %.2f, \"render_fps_wall\": %.2f, \"total_fps\": %.2f, \"world\": \"%s\", \"seed\": %u, "
                "\"width\": %d, \"height\": %d, \"rate_hz\": %.3f, \"duration_s\": %.3f, \"path_length_m\": %.3f, "
                "\"projected_frames\": %d, \"lux\": %.1f, \"camera_errors\": %s}\n",
                n, render_fps, render_fps_wall, n / wall, world.name.c_str(), seed, cam.calib.width, cam.calib.height, rate, t_last,
                motion.pathLength(), projected, world.ambientLux(), errors_json.c_str());
  }
  catch (const std::exception& e)
  {
    std::fprintf(stderr, "\nrender_bag: %s\n", e.what());
    return 1;
  }
  return 0;
}
