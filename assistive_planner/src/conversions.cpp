#include "assistive_planner/conversions.h"

#include <cstdint>
#include <cstdio>
#include <type_traits>
#include <assistive_msgs/NavigationState.h>
#include <nav_msgs/OccupancyGrid.h>

#include <algorithm>
#include <cmath>

namespace assistive_planner
{
// The navigation status (assistive_common/codes.h) is assistive_msgs/NavigationState.status.
static_assert(static_cast<int>(PlanStatus::OK) == static_cast<int>(assistive_msgs::NavigationState::OK), "NavigationState.OK");
static_assert(static_cast<int>(PlanStatus::NO_POSE) == static_cast<int>(assistive_msgs::NavigationState::NO_POSE), "NavigationState.NO_POSE");
static_assert(static_cast<int>(PlanStatus::NO_MAP) == static_cast<int>(assistive_msgs::NavigationState::NO_MAP), "NavigationState.NO_MAP");
static_assert(static_cast<int>(PlanStatus::IN_UNKNOWN) == static_cast<int>(assistive_msgs::NavigationState::IN_UNKNOWN), "NavigationState.IN_UNKNOWN");
static_assert(static_cast<int>(PlanStatus::NO_PATH) == static_cast<int>(assistive_msgs::NavigationState::NO_PATH), "NavigationState.NO_PATH");
static_assert(static_cast<int>(PlanStatus::NO_WAYPOINT) == static_cast<int>(assistive_msgs::NavigationState::NO_WAYPOINT), "NavigationState.NO_WAYPOINT");
// The crossing advice (assistive_common/codes.h) is assistive_msgs/NavigationState.crossing.
static_assert(static_cast<int>(CrossingAdvice::NONE) == static_cast<int>(assistive_msgs::NavigationState::CROSSING_NONE), "NavigationState.CROSSING_NONE");
static_assert(static_cast<int>(CrossingAdvice::LEFT) == static_cast<int>(assistive_msgs::NavigationState::CROSSING_LEFT), "NavigationState.CROSSING_LEFT");
static_assert(static_cast<int>(CrossingAdvice::RIGHT) == static_cast<int>(assistive_msgs::NavigationState::CROSSING_RIGHT), "NavigationState.CROSSING_RIGHT");
static_assert(static_cast<int>(CrossingAdvice::STOP) == static_cast<int>(assistive_msgs::NavigationState::CROSSING_STOP), "NavigationState.CROSSING_STOP");

namespace
{
geometry_msgs::Point toPoint(const Point2& p, double z = 0.0)
{
  geometry_msgs::Point q;
  q.x = p.x;
  q.y = p.y;
  q.z = z;
  return q;
}
float finiteOr(double v, float fallback = 0.0f)
{
  return std::isfinite(v) ? float(v) : fallback;
}
}  // namespace

assistive_msgs::NavigationState toMsg(const PlanOutput& out, const std_msgs::Header& header, const ros::Time& source_stamp)
{
  assistive_msgs::NavigationState s;
  s.header = header;
  s.source_stamp = source_stamp;
  s.status = uint8_t(out.status);
  s.message = out.message;
  s.wearer = toPoint(out.wearer);
  s.heading = finiteOr(out.heading);
  s.head_yaw = finiteOr(out.head_yaw);
  s.waypoint = out.has_waypoint ? toPoint(out.waypoint) : toPoint(out.wearer);
  s.waypoint_distance = out.has_waypoint ? finiteOr(out.waypoint_distance) : 0.0f;
  s.path_heading = out.status == PlanStatus::OK ? finiteOr(out.path_heading) : finiteOr(out.heading);
  s.path_length = out.status == PlanStatus::OK ? finiteOr(out.path_length) : 0.0f;
  s.free_distance_ahead = finiteOr(out.free_ahead);
  s.free_distance_left = finiteOr(out.free_left);
  s.free_distance_right = finiteOr(out.free_right);
  const bool ok = out.status == PlanStatus::OK;
  s.steer_point = ok ? toPoint(out.steer_point) : toPoint(out.wearer);
  s.steer_heading = ok ? finiteOr(out.steer_heading) : finiteOr(out.walk_heading);
  s.walk_heading = finiteOr(out.walk_heading);
  s.walking_speed = finiteOr(out.walking_speed);
  s.free_distance_steer = ok ? finiteOr(out.free_steer) : 0.0f;
  const bool passage = ok && std::isfinite(out.passage_distance) && out.passage_distance >= 0.0;
  s.passage_distance = passage ? float(out.passage_distance) : -1.0f;
  s.passage_heading = passage ? finiteOr(out.passage_heading) : 0.0f;
  s.passage_width = passage ? finiteOr(out.passage_width) : 0.0f;
  s.passage_point = passage ? toPoint(out.passage_point) : toPoint(out.wearer);
  s.passage_axis = passage ? finiteOr(out.passage_axis) : 0.0f;
  const CrossingResult& c = out.crossing;
  const bool warn = c.advice != CrossingAdvice::NONE && std::isfinite(c.time) && std::isfinite(c.distance);
  s.crossing = uint8_t(warn ? c.advice : CrossingAdvice::NONE);
  s.crossing_id = warn ? uint32_t(std::max(0, c.id)) : 0u;
  s.crossing_time = warn ? float(c.time) : 0.0f;
  s.crossing_distance = warn ? float(c.distance) : 0.0f;
  for (const Point2& q : pathAhead(out))
    s.path_ahead.push_back(toPoint(q));
  return s;
}

nav_msgs::Path toPathMsg(const PlanOutput& out, const std_msgs::Header& header)
{
  nav_msgs::Path p;
  p.header = header;
  if (out.status != PlanStatus::OK)
    return p;
  p.poses.reserve(out.path.size());
  for (size_t i = 0; i < out.path.size(); ++i)
  {
    geometry_msgs::PoseStamped ps;
    ps.header = header;
    ps.pose.position = toPoint(out.path[i]);
    const size_t j = i + 1 < out.path.size() ? i + 1 : i;
    const size_t k = j == i && i > 0 ? i - 1 : i;
    const double yaw = (j != i) ? std::atan2(out.path[j].y - out.path[i].y, out.path[j].x - out.path[i].x)
                                : std::atan2(out.path[i].y - out.path[k].y, out.path[i].x - out.path[k].x);
    ps.pose.orientation.z = std::sin(0.5 * yaw);
    ps.pose.orientation.w = std::cos(0.5 * yaw);
    p.poses.push_back(ps);
  }
  return p;
}

std::vector<MoverState> fromMsg(const assistive_msgs::MoverArray& msg)
{
  std::vector<MoverState> out;
  out.reserve(msg.movers.size());
  for (const assistive_msgs::Mover& m : msg.movers)
  {
    MoverState t;
    t.id = int(m.id);
    t.x << m.position.x, m.position.y, m.velocity.x, m.velocity.y;
    for (int i = 0; i < 16; ++i)
      t.P(i / 4, i % 4) = m.covariance[size_t(i)];
    if (t.x.allFinite() && t.P.allFinite())
      out.push_back(t);
  }
  return out;
}

geometry_msgs::PointStamped toWaypointMsg(const PlanOutput& out, const std_msgs::Header& header)
{
  geometry_msgs::PointStamped p;
  p.header = header;
  p.point = toPoint(out.waypoint);
  return p;
}

namespace
{
/// A marker of `ns` / `id`, added or deleted, its pose the identity (the points carry it).
visualization_msgs::Marker marker(const std_msgs::Header& header, const char* ns, int id, int type, bool add)
{
  visualization_msgs::Marker m;
  m.header = header;
  m.ns = ns;
  m.id = id;
  m.type = type;
  m.action = add ? visualization_msgs::Marker::ADD : visualization_msgs::Marker::DELETE;
  m.pose.orientation.w = 1.0;
  return m;
}

/// The passage ahead (a doorway, a narrowed aisle): an arrow along its axis through its middle,
/// 0.6 m either side, 0.8 m above the floor (the cue logic squares the wearer up on it); deleted
/// when there is none.
visualization_msgs::Marker passageMarker(const PlanOutput& out, const std_msgs::Header& header)
{
  const bool shown = out.status == PlanStatus::OK && out.passage_distance >= 0.0 && std::isfinite(out.passage_axis);
  visualization_msgs::Marker m = marker(header, "passage", 5, visualization_msgs::Marker::ARROW, shown);
  if (shown)
  {
    const double cx = std::cos(out.passage_axis), sy = std::sin(out.passage_axis);
    // at hip height: drawn on the floor it hides under the map's floor voxels
    m.points.push_back(toPoint({ out.passage_point.x - 0.6 * cx, out.passage_point.y - 0.6 * sy }, 0.8));
    m.points.push_back(toPoint({ out.passage_point.x + 0.6 * cx, out.passage_point.y + 0.6 * sy }, 0.8));
  }
  m.scale.x = 0.05;
  m.scale.y = 0.12;
  m.scale.z = 0.15;
  m.color.g = 1.0f;
  m.color.a = 1.0f;
  return m;
}
}  // namespace

visualization_msgs::MarkerArray toMarkers(const PlanOutput& out, const std_msgs::Header& header)
{
  visualization_msgs::MarkerArray ma;
  visualization_msgs::Marker arrow = marker(header, "motion_vector", 0, visualization_msgs::Marker::ARROW, true);
  arrow.points.push_back(toPoint(out.wearer, 0.05));
  arrow.points.push_back(toPoint({ out.wearer.x + std::cos(out.heading), out.wearer.y + std::sin(out.heading) }, 0.05));
  arrow.scale.x = 0.06;
  arrow.scale.y = 0.12;
  arrow.scale.z = 0.15;
  arrow.color.r = 1.0f;
  arrow.color.g = 0.8f;
  arrow.color.a = 1.0f;
  ma.markers.push_back(arrow);

  visualization_msgs::Marker tri = marker(header, "search_triangle", 1, visualization_msgs::Marker::LINE_STRIP, true);
  for (int i = 0; i < 4; ++i)
    tri.points.push_back(toPoint(out.triangle[size_t(i % 3)], 0.03));
  tri.scale.x = 0.03;
  tri.color.b = 1.0f;
  tri.color.g = 0.6f;
  tri.color.a = 0.8f;
  ma.markers.push_back(tri);

  visualization_msgs::Marker wp = marker(header, "waypoint", 2, visualization_msgs::Marker::SPHERE, out.has_waypoint);
  wp.pose.position = toPoint(out.waypoint, 0.1);
  wp.scale.x = wp.scale.y = wp.scale.z = 0.25;
  wp.color.r = 1.0f;
  wp.color.b = 0.8f;
  wp.color.a = 1.0f;
  ma.markers.push_back(wp);

  // The crossing warning: the warned mover's predicted path to the closest approach (red arrow)
  // and the advice in words above the meeting point.
  const CrossingResult& c = out.crossing;
  const bool warn = c.advice != CrossingAdvice::NONE;
  visualization_msgs::Marker cross = marker(header, "crossing", 3, visualization_msgs::Marker::ARROW, warn);
  if (warn)
  {
    cross.points.push_back(toPoint(c.mover, 0.1));
    cross.points.push_back(toPoint(c.mover_at_closest, 0.1));
  }
  cross.scale.x = 0.08;
  cross.scale.y = 0.18;
  cross.scale.z = 0.2;
  cross.color.r = 1.0f;
  cross.color.a = 1.0f;
  ma.markers.push_back(cross);

  visualization_msgs::Marker text = marker(header, "crossing", 4, visualization_msgs::Marker::TEXT_VIEW_FACING, warn);
  text.pose.position = toPoint(c.wearer_at_closest, 1.0);
  if (warn)
  {
    char buf[64];
    std::snprintf(buf, sizeof(buf), "person %d: %s in %.1f s (%.2f m)", c.id, crossingName(c.advice), c.time,
                  c.distance);
    text.text = buf;
  }
  text.scale.z = 0.25;
  text.color.r = 1.0f;
  text.color.g = 0.3f;
  text.color.b = 0.3f;
  text.color.a = 1.0f;
  ma.markers.push_back(text);
  ma.markers.push_back(passageMarker(out, header));
  return ma;
}
}  // namespace assistive_planner
