// Closed-loop mobility trials (trials.h): truth mode (world occupancy -> planner core -> cue logic
// core -> vest wearer) and the cane-only baseline; the heat map.
#include <assistive_sim/trials.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <random>
#include <stdexcept>

#include <opencv2/imgproc.hpp>

#include <assistive_planner/planner.h>
#include <assistive_tactile/cue_logic.h>
#include <assistive_tactile/vest_protocol.h>

namespace assistive_sim
{
namespace
{
constexpr double DEG = M_PI / 180.0;

assistive_planner::Grid toPlannerGrid(const OccupancyGrid& g)
{
  assistive_planner::Grid out;
  out.width = g.width;
  out.height = g.height;
  out.resolution = g.resolution;
  out.origin_x = g.origin_x;
  out.origin_y = g.origin_y;
  out.data = g.data;
  return out;
}

/// Random start near the course's start, facing roughly the first place, not touching anything.
BodyState randomStart(const World& world, const TrialOptions& opt, const BodyCollider& body, std::mt19937& rng)
{
  const std::vector<Eigen::Vector2d> c = courseOf(world);
  const Eigen::Vector2d a = c.front(), b = c.size() > 1 ? c[1] : c.front() + Eigen::Vector2d(1, 0);
  const double yaw0 = std::atan2(b.y() - a.y(), b.x() - a.x());
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  BodyState s;
  if (std::isfinite(opt.fixed_start_yaw_deg))
  {
    s.xy = a;
    s.yaw = yaw0 + opt.fixed_start_yaw_deg * DEG;
    s.head_yaw = s.yaw;
    return s;
  }
  for (int tries = 0; tries < 200; ++tries)
  {
    const double r = opt.start_jitter_m * std::sqrt(std::abs(u(rng))), th = M_PI * u(rng);
    s.xy = a + r * Eigen::Vector2d(std::cos(th), std::sin(th));
    s.yaw = yaw0 + opt.start_yaw_deg * DEG * u(rng);
    if (tries > 100) s.xy = a;  // the script's start is collision-free by construction
    if (body.clearance(s.xy) >= 0.05) break;
  }
  s.head_yaw = s.yaw;
  return s;
}
}  // namespace

int TrialResult::totalCollisions() const
{
  int n = 0;
  for (int c : collisions) n += c;
  return n;
}

std::vector<Eigen::Vector2d> courseOf(const World& world)
{
  std::vector<Eigen::Vector2d> c = world.trajectory.waypoints;
  if (c.empty()) c.push_back(Eigen::Vector2d::Zero());
  return c;
}

namespace
{
/// Truth mode's chain: the world's occupancy (what a perfect obstacle stage would report) to the
/// planner and cue logic cores, no ROS, no latency.
class TruthChain : public CueChain
{
public:
  TruthChain(const World& world, const TrialOptions& opt)
    : world_(world), opt_(opt), planner_(opt.planner), cues_(opt.cues)
  {
    OccupancyParams op;
    op.head_above_eye = 0.12;
    grid_ = toPlannerGrid(computeOccupancy(world, op));
    trace_ = std::getenv("MOBILITY_TRIALS_TRACE") != nullptr;  // per-cycle state on stderr
  }
  void setGoal(const Eigen::Vector2d& g) override { planner_.setGoal({ g.x(), g.y() }); }
  void setNextGoal(const Eigen::Vector2d* n) override
  {
    if (n)
      planner_.setNextGoal({ n->x(), n->y() });
    else
      planner_.clearNextGoal();
  }
  ChainCue frame(double t, const BodyState& s) override
  {
    // The world's people are not in grid_ (computeOccupancy leaves movers out): a perfect tracker
    // hands the planner every person, standing ones too, exactly (the ROS truth chain publishes
    // the same on obstacles/movers).
    if (!world_.people.empty())
    {
      std::vector<assistive_planner::MoverState> movers(world_.people.size());
      for (size_t i = 0; i < world_.people.size(); ++i)
      {
        const PersonState p = personAt(world_, i, t);
        movers[i].id = int(i + 1);
        movers[i].x << p.position, p.velocity;
      }
      planner_.setMovers(t, std::move(movers));
    }
    const assistive_planner::PlanOutput out =
        planner_.update(gridWithStandingPeople(t), { s.xy.x(), s.xy.y() }, s.head_yaw, t);
    assistive_tactile::NavInput in;
    in.status = out.status;
    in.message = out.message;
    in.heading = out.heading;
    in.path_heading = out.path_heading;
    in.waypoint_distance = out.waypoint_distance;
    in.free_ahead = out.free_ahead;
    in.free_left = out.free_left;
    in.free_right = out.free_right;
    in.steer_heading = out.steer_heading;
    in.walk_heading = out.walk_heading;
    in.walking_speed = out.walking_speed;
    in.head_yaw = out.head_yaw;
    in.crossing = out.crossing.advice;
    in.crossing_id = out.crossing.id;
    in.crossing_time = out.crossing.time;
    in.crossing_distance = out.crossing.distance;
    in.source_time = t;  // truth: the occupancy is current
    const assistive_tactile::Cue cue = cues_.update(in, t);
    if (trace_)
      std::fprintf(stderr, "t %.2f xy %.2f %.2f yaw %.0f head %.0f | st %d wp %.2f %.2f d %.2f ph %.0f h %.0f fa %.2f fl %.2f fr %.2f | %s %s\n",
                   t, s.xy.x(), s.xy.y(), s.yaw / DEG, s.head_yaw / DEG, int(out.status), out.waypoint.x,
                   out.waypoint.y, out.waypoint_distance, out.path_heading / DEG, out.heading / DEG, out.free_ahead,
                   out.free_left, out.free_right, assistive_tactile::modeName(cue.mode), cue.reason.c_str());
    ChainCue c;
    c.motors = cue.intensity;
    c.mode = int(cue.mode);
    c.pattern_id = cue.pattern.id;
    c.pulse_on_ms = 10 * cue.pattern.on_10ms;
    c.pulse_off_ms = 10 * cue.pattern.off_10ms;
    c.pulse_count = cue.pattern.count;
    c.instruction = int(cue.instruction);
    c.level = cue.level;
    return c;
  }

private:
  /// The static grid plus every person standing still now (speed under 0.2 m/s): what the obstacle
  /// stage's map holds (a person standing still is an ordinary obstacle; walking ones are movers
  /// only). Cells whose square the body's disc overlaps become obstacles.
  const assistive_planner::Grid& gridWithStandingPeople(double t)
  {
    if (world_.people.empty()) return grid_;
    now_ = grid_;
    for (size_t i = 0; i < world_.people.size(); ++i)
    {
      const PersonState p = personAt(world_, i, t);
      if (p.velocity.norm() >= 0.2) continue;
      Solid body;  // the person's footprint, tested against cells the way computeOccupancy does
      body.shape = Solid::CYLINDER;
      body.center = p.position;
      body.radius = world_.people[i].radius;
      const double r = body.radius, h = 0.5 * now_.resolution;
      int x0, y0, x1, y1;
      now_.worldToCell(p.position.x() - r, p.position.y() - r, x0, y0);
      now_.worldToCell(p.position.x() + r, p.position.y() + r, x1, y1);
      for (int y = std::max(0, y0); y <= std::min(now_.height - 1, y1); ++y)
        for (int x = std::max(0, x0); x <= std::min(now_.width - 1, x1); ++x)
          if (body.overlapsRect(now_.cellX(x) - h, now_.cellY(y) - h, now_.cellX(x) + h, now_.cellY(y) + h))
            now_.data[size_t(now_.index(x, y))] = 100;
    }
    return now_;
  }

  const World& world_;
  assistive_planner::Grid now_;
  TrialOptions opt_;
  assistive_planner::Grid grid_;
  assistive_planner::Planner planner_;
  assistive_tactile::CueLogic cues_;
  bool trace_ = false;
};
}  // namespace

BodyState trialStart(const World& world, const TrialOptions& opt, uint32_t seed)
{
  std::mt19937 rng(seed);
  BodyCollider body(world, opt.wearer.body_radius, opt.wearer.eye_height + 0.12);
  return randomStart(world, opt, body, rng);
}

TrialResult runTrial(const World& world, const TrialOptions& opt, uint32_t seed, int index, CueChain* chain)
{
  TrialResult r;
  r.index = index;
  r.seed = seed;
  std::mt19937 rng(seed);
  const double body_height = opt.wearer.eye_height + 0.12;
  BodyCollider body(world, opt.wearer.body_radius, body_height);
  r.start = randomStart(world, opt, body, rng);
  std::vector<Eigen::Vector2d> route = courseOf(world);
  route.erase(route.begin());
  if (route.empty()) route.push_back(r.start.xy + Eigen::Vector2d(cos(r.start.yaw), sin(r.start.yaw)) * 5.0);
  // The trial ends within goal_radius of the exit: so does the guide's walk (its last metre is
  // not walked, at cruise speed).
  r.guide_time_s = sightedGuideTime(world, opt.wearer, r.start.xy, route);
  if (r.guide_time_s > 0.0)
    r.guide_time_s = std::max(0.5 * r.guide_time_s, r.guide_time_s - opt.goal_radius_m / opt.wearer.walk_speed);
  const double timeout = opt.timeout_factor * std::max(r.guide_time_s, 5.0) + 20.0;

  const bool vest = opt.mode != TrialMode::CANE;
  std::unique_ptr<TruthChain> truth;
  if (vest && !chain)
  {
    if (opt.mode == TrialMode::VISION) throw std::invalid_argument("runTrial: vision mode needs a ROS chain");
    truth = std::make_unique<TruthChain>(world, opt);
    chain = truth.get();
  }
  VestWearer wearer(opt.wearer, r.start, seed ^ 0x9e3779b9u);
  CaneWalker cane(opt.wearer, opt.cane, r.start, seed ^ 0x7f4a7c15u);

  size_t next = 0;
  if (vest)
  {
    chain->reset(r.start);
    chain->setGoal(route[0]);
    chain->setNextGoal(route.size() > 1 ? &route[1] : nullptr);
  }
  // The vest as the firmware drives it: the last cue's pattern, from when its id first came.
  ChainCue playing;
  double playing_since = 0.0;
  auto drive = [&](double now) {
    std::array<float, 4> m{ { 0.f, 0.f, 0.f, 0.f } };
    vest_pattern_t pat{ playing.pattern_id, uint8_t(std::min(255, playing.pulse_on_ms / 10)),
                        uint8_t(std::min(255, playing.pulse_off_ms / 10)), uint8_t(playing.pulse_count) };
    if (opt.cues_enabled && vest_pattern_on(&pat, uint32_t(std::max(0.0, now - playing_since) * 1000.0 + 0.5)))
      m = playing.motors;
    return m;
  };
  const double period = 1.0 / opt.rate_hz;
  double next_plan = 0.0, clear_sum = 0.0;
  r.min_clearance_m = 1e9;
  r.min_person_clearance_m = std::numeric_limits<double>::infinity();
  long steps = 0;
  const bool trace = std::getenv("MOBILITY_TRIALS_TRACE") != nullptr;
  int reported = 0;
  double t = 0.0;
  for (; t < timeout; t += opt.dt)
  {
    const BodyState& s = vest ? wearer.state() : cane.state();
    // The people (issue 22) where they are at the end of this step: the collider counts contacts
    // with them and the cane feels them; they follow their scripts on the trial's clock.
    body.setTime(t + opt.dt);
    // progress along the course: the experimenter's route (the system's explicit goal)
    while (next < route.size() && (s.xy - route[next]).norm() < opt.goal_radius_m)
    {
      ++next;
      if (next < route.size() && vest)
      {
        chain->setGoal(route[next]);
        chain->setNextGoal(next + 1 < route.size() ? &route[next + 1] : nullptr);
      }
    }
    if (next >= route.size())
    {
      r.completed = true;
      break;
    }
    if (vest)
    {
      if (t + 1e-9 >= next_plan)
      {
        next_plan += period;
        const ChainCue cue = chain->frame(t, s);
        if (cue.received)
        {
          ++r.cue_modes[size_t(std::min(4, std::max(0, cue.mode)))];
          if (cue.pattern_id != playing.pattern_id || cue.pattern_id == 0) playing_since = t;
          playing = cue;
        }
        else
          ++r.missed_cues;
        if (cue.latency_ms >= 0.0) r.latency_ms.push_back(cue.latency_ms);
      }
      wearer.step(t, opt.dt, drive(t), &body);
      chain->observe(t + opt.dt, wearer.state());
    }
    else
    {
      cane.step(t, opt.dt, route[next], body);
    }
    const BodyState& now = vest ? wearer.state() : cane.state();
    if (trace && int(body.collisionPlaces().size()) > reported)
    {
      reported = int(body.collisionPlaces().size());
      // the nearest person's surface (issue 22: who walked into whom)
      std::string who = "-";
      double gap = std::numeric_limits<double>::infinity();
      for (size_t i = 0; i < world.people.size(); ++i)
      {
        const PersonState p = personAt(world, i, t + opt.dt);
        const double g = (p.position - now.xy).norm() - world.people[i].radius - opt.wearer.body_radius;
        if (g < gap)
        {
          gap = g;
          who = world.people[i].name + " v " + std::to_string(p.velocity.norm()).substr(0, 4);
        }
      }
      std::fprintf(stderr, "COLLISION t %.2f at %.2f %.2f yaw %.0f speed %.2f | nearest person %s gap %.2f\n", t,
                   now.xy.x(), now.xy.y(), now.yaw / DEG, now.speed, who.c_str(), gap);
    }
    r.path.push_back(now.xy);
    const double c = body.clearance(now.xy);
    r.min_person_clearance_m = std::min(r.min_person_clearance_m, body.personClearance(now.xy));
    clear_sum += c;
    r.min_clearance_m = std::min(r.min_clearance_m, c);
    ++steps;
  }
  r.time_s = t;
  r.ppws_pct = r.completed && r.time_s > 0.0 ? 100.0 * r.guide_time_s / r.time_s : 0.0;
  r.collisions = body.collisions();
  r.collision_places = body.collisionPlaces();
  r.mean_clearance_m = steps ? clear_sum / double(steps) : 0.0;
  if (!steps) r.min_clearance_m = 0.0;
  return r;
}

cv::Mat heatMap(const World& world, const std::vector<TrialResult>& trials, double dt, const std::string& title,
                double px_per_m)
{
  const double x0 = world.floor_min.x(), y1 = world.floor_max.y();
  const int W = std::max(1, int(std::ceil((world.floor_max.x() - x0) * px_per_m)));
  const int H = std::max(1, int(std::ceil((y1 - world.floor_min.y()) * px_per_m)));
  const int top = 28;
  auto px = [&](const Eigen::Vector2d& p) {
    return cv::Point(int(std::lround((p.x() - x0) * px_per_m)), top + int(std::lround((y1 - p.y()) * px_per_m)));
  };
  cv::Mat img(H + top, W, CV_8UC3, cv::Scalar(20, 20, 20));
  // obstacles at body height, from above (grey; glass blue; overhangs hatched lighter)
  for (const Solid& s : world.solids)
  {
    if (s.walkable || s.z0 >= 2.0) continue;
    const cv::Scalar col = s.glass || s.glazing ? cv::Scalar(200, 120, 40) : s.z0 >= 1.0 ? cv::Scalar(170, 170, 170)
                                                                            : cv::Scalar(110, 110, 110);
    if (s.shape == Solid::CYLINDER)
    {
      cv::circle(img, px(s.center), std::max(1, int(s.radius * px_per_m)), col, cv::FILLED);
      continue;
    }
    const double c = std::cos(s.yaw), sn = std::sin(s.yaw);
    std::vector<cv::Point> poly;
    for (int k = 0; k < 4; ++k)
    {
      const double lx = (k == 0 || k == 3 ? 1 : -1) * s.half.x(), ly = (k < 2 ? 1 : -1) * s.half.y();
      poly.push_back(px(s.center + Eigen::Vector2d(c * lx - sn * ly, sn * lx + c * ly)));
    }
    cv::fillConvexPoly(img, poly, col);
  }
  // time spent per 5 cm cell, summed over the trials
  const double cell = 0.05;
  const int cw = int(std::ceil(W / (cell * px_per_m))) + 1, ch = int(std::ceil(H / (cell * px_per_m))) + 1;
  std::vector<double> acc(size_t(cw) * ch, 0.0);
  for (const TrialResult& t : trials)
    for (const Eigen::Vector2d& p : t.path)
    {
      const int cx = int((p.x() - x0) / cell), cy = int((y1 - p.y()) / cell);
      if (cx >= 0 && cy >= 0 && cx < cw && cy < ch) acc[size_t(cy) * cw + cx] += dt;
    }
  double mx = 0.0;
  for (double v : acc) mx = std::max(mx, v);
  if (mx > 0.0)
  {
    cv::Mat heat(ch, cw, CV_32F, cv::Scalar(0));
    for (int y = 0; y < ch; ++y)
      for (int x = 0; x < cw; ++x) heat.at<float>(y, x) = float(std::log1p(acc[size_t(y) * cw + x]) / std::log1p(mx));
    cv::Mat big;
    cv::resize(heat, big, cv::Size(int(cw * cell * px_per_m), int(ch * cell * px_per_m)), 0, 0, cv::INTER_NEAREST);
    cv::GaussianBlur(big, big, cv::Size(0, 0), 0.08 * px_per_m);
    double bmax;
    cv::minMaxLoc(big, nullptr, &bmax);
    for (int y = 0; y < H; ++y)
      for (int x = 0; x < W && x < big.cols && y < big.rows; ++x)
      {
        const float v = bmax > 0 ? float(big.at<float>(y, x) / bmax) : 0.f;
        if (v < 0.02f) continue;
        cv::Vec3b& d = img.at<cv::Vec3b>(y + top, x);
        d[2] = cv::saturate_cast<uchar>(d[2] * (1 - v) + 255 * std::sqrt(v));
        d[1] = cv::saturate_cast<uchar>(d[1] * (1 - v) + 60 * v * v);
        d[0] = cv::saturate_cast<uchar>(d[0] * (1 - v));
      }
  }
  for (const Eigen::Vector2d& p : courseOf(world)) cv::circle(img, px(p), 4, cv::Scalar(60, 220, 60), cv::FILLED);
  for (const TrialResult& t : trials)
    for (const Eigen::Vector2d& p : t.collision_places)
    {
      const cv::Point q = px(p);
      cv::line(img, q + cv::Point(-5, -5), q + cv::Point(5, 5), cv::Scalar(0, 255, 255), 2);
      cv::line(img, q + cv::Point(-5, 5), q + cv::Point(5, -5), cv::Scalar(0, 255, 255), 2);
    }
  cv::putText(img, title, cv::Point(6, 20), cv::FONT_HERSHEY_SIMPLEX, 0.5, cv::Scalar(240, 240, 240), 1, cv::LINE_AA);
  return img;
}

}  // namespace assistive_sim
