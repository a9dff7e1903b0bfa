#pragma once

#include <array>
#include <cstdint>
#include <limits>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include <opencv2/core.hpp>

#include "assistive_planner/blind_zone.h"
#include "assistive_planner/cost_grid.h"
#include "assistive_planner/crossing_watch.h"
#include "assistive_planner/dstar_lite.h"
#include "assistive_planner/grid.h"
#include "assistive_planner/motion_vector.h"
#include "assistive_planner/params.h"
#include "assistive_planner/waypoint_selector.h"

namespace assistive_planner
{
/// The navigation status (assistive_common/codes.h; the values of assistive_msgs/NavigationState).
using PlanStatus = assistive_common::NavStatus;

struct PlanOutput
{
  PlanStatus status = PlanStatus::NO_MAP;
  std::string message;
  Point2 wearer;
  double heading = 0.0;    ///< motion vector yaw (rad)
  double head_yaw = 0.0;   ///< rad
  bool has_waypoint = false;
  bool explicit_goal = false;  ///< the target is the explicit goal, not the automatic waypoint
  Point2 waypoint;
  double waypoint_distance = 0.0;
  double path_heading = 0.0;
  double path_length = 0.0;
  /// Pure pursuit: the point on the (refined) path `steer_lookahead` ahead, and its yaw from the wearer.
  Point2 steer_point;
  double steer_heading = 0.0;
  double steer_lookahead = 0.0;  ///< m
  double free_steer = 0.0;       ///< free distance along steer_heading (m)
  /// The walk: the chord of the wearer's positions over `walk_window_s` (the head's yaw while the
  /// chord is shorter than 5 cm: standing); speed in m/s (0 without times).
  double walk_heading = 0.0;
  double walking_speed = 0.0;
  double free_ahead = 0.0, free_left = 0.0, free_right = 0.0;
  /// A passage narrower than `passage_width_m` (a doorway, a gap) on the path within
  /// `passage_range_m` ahead: metres along the path to its middle (< 0: none), its middle (on a
  /// 5 cm field, across the path's cells), the yaw from the wearer to it, its width and the path's
  /// direction through it.
  double passage_distance = -1.0;
  Point2 passage_point;
  double passage_heading = 0.0;
  double passage_width = 0.0;
  double passage_axis = 0.0;
  std::vector<Point2> path;   ///< wearer -> waypoint: cell centres moved towards the middle of narrow passages
  /// The path the steering point runs on: `path`, then on to the next goal when one is set.
  std::vector<Point2> steer_path;
  bool path_through_unknown = false;
  std::array<Point2, 3> triangle;  ///< search triangle (apex, left, right)
  Point2 motion_anchor;            ///< previous position of the motion vector
  /// People crossing (CrossingWatch): the most urgent advice; NONE when the cycle had no time
  /// (update() without `t`), no fresh movers, or the wearer's pose or grid was unusable.
  CrossingResult crossing;
  /// The blind zone (blind_zone.h): unknown cells vouched for as floor this cycle, and why none
  /// were when the ranger could not vouch (empty otherwise).
  int vouched_cells = 0;
  std::string vouch_note;
  /// Unseen floor beside a standing wearer held as obstacles (`unseen_hold_s`): cells held now.
  int unseen_held_cells = 0;
  /// Step cells a standing wearer was sent over (`step_stand_s`): free in `grid` for what lies ahead.
  int crossed_step_cells = 0;
  /// The grid this cycle planned on (the input with the walked floor and the vouched blind zone
  /// marked; null before a usable grid): the cue logic sweeps the body's predicted walk over it
  /// (the nodelet publishes it as `planner/grid`, nav_msgs/OccupancyGrid).
  std::shared_ptr<const Grid> grid;
  size_t expansions = 0;           ///< D* Lite expansions in this update
  size_t changed_cells = 0;        ///< cells whose weight changed since the last update
  bool scrolled = false;
};

/// A narrow passage on a path (Planner::findPassage).
struct Passage
{
  bool found = false;
  double along = 0.0;  ///< m along the path from the search's start to the middle
  Point2 middle;       ///< the middle across the path at the passage's narrowest point
  /// Its width (m): twice the middle's distance to the nearest obstacle cell's square plus one
  /// cell (the jambs' faces lie inside the cells they fill, half a cell in on average).
  double width = 0.0;
  /// The passage's axis (rad): across its shortest chord of free floor through the middle (a
  /// doorway's jamb-to-jamb line, an aisle's width), pointing the way the path goes; the path's
  /// direction there when no chord closes within reach.
  double axis = 0.0;
};

/// The floor the wearer has stood on: unknown cells whose centre lies within `radius` of a point
/// of `walked` become free (obstacles and steps stay). Returns the number of cells changed.
int markWalkedFloor(Grid& grid, const std::vector<Point2>& walked, double radius);

/// The steering path's first `max_m` metres (NavigationState `path_ahead`; the cue logic takes its
/// corners walking): empty unless the status is OK.
std::vector<Point2> pathAhead(const PlanOutput& out, double max_m = 8.0);

/// The planning stage without ROS: grid + wearer pose in, waypoint, D* Lite path and free distances out.
class Planner
{
public:
  explicit Planner(const PlannerParams& p = PlannerParams());
  /// One planning cycle on a new grid (or the same grid with a new pose). `t`: the camera time (s)
  /// of the grid and pose, for the crossing warning (the movers' age, the walking speed); without it
  /// (NaN) there is no crossing advice.
  PlanOutput update(const Grid& grid, const Point2& wearer, double head_yaw,
                    double t = std::numeric_limits<double>::quiet_NaN());
  /// The movers (confirmed tracks, world frame) at camera time `stamp` (CrossingWatch::setMovers).
  void setMovers(double stamp, std::vector<MoverState> movers)
  {
    crossing_.setMovers(stamp, std::move(movers));
  }
  void clearMovers() { crossing_.clearMovers(); }
  /// The forward ranger's newest reading (its axis in the planner's frame): with the camera's view
  /// past the blind zone it vouches for the unmapped floor just ahead (vouchBlindZone), while its
  /// stamp lies within `ranger_max_age_s` of the cycle's time `t` (never without `t`).
  void setRanger(const RangerReading& r) { ranger_ = r; }
  const CrossingWatch& crossingWatch() const { return crossing_; }
  /// Explicit target (e.g. a tagged place); replaces the automatic waypoint until reached or cleared.
  void setGoal(const Point2& goal);
  void clearGoal()
  {
    has_goal_ = false;
    has_next_ = false;
  }
  /// The place after the goal (a route of places): the steering point runs on round the goal
  /// towards it, so a turn at the goal is cued before the goal is reached. Cleared with the goal.
  void setNextGoal(const Point2& next)
  {
    has_next_ = true;
    next_ = next;
  }
  void clearNextGoal() { has_next_ = false; }
  bool hasGoal() const { return has_goal_; }
  const PlannerParams& params() const { return p_; }
  const DStarLite& dstar() const { return dstar_; }
  const MotionVector& motion() const { return motion_; }
  const WaypointSelector& waypoints() const { return waypoints_; }
  /// The places the wearer has stood since construction (the planner is rebuilt on a reset).
  const std::vector<Point2>& walked() const { return walked_; }

  /// Free distance from `from` along `yaw` until a cell that is not free (obstacle, step, unknown) or the
  /// grid edge, up to max_range (m).
  static double freeDistance(const Grid& grid, const Point2& from, double yaw, double max_range);
  /// The same; `ends_unknown` tells whether the ray stopped at an unknown cell (not at an obstacle,
  /// a step or the window edge).
  static double freeDistance(const Grid& grid, const Point2& from, double yaw, double max_range, bool& ends_unknown);

  /// Free length of the strip of half-width `half_width` either side of the line from `from`
  /// along `yaw` (the strip the body sweeps walking on): the smaller of the line's free distance and,
  /// over the cells that are not free whose centre lies inside the strip ahead of the body's front
  /// arc (not beside or under the body), the distance to the cell's near edge. `ends_unknown`: that
  /// nearest cell is unknown. half_width 0 = the line (freeDistance).
  static double freeStrip(const Grid& grid, const Point2& from, double yaw, double max_range, double half_width,
                          bool& ends_unknown);

  /// Moves each inner point of `path` (at most half a cell) up the obstacle distance field of
  /// `grid` (obstacle cells, 5 cm resolution) until it lies `clearance` from the nearest obstacle
  /// cell or on the ridge between two: the middle of a doorway or aisle.
  static void refinePath(const Grid& grid, std::vector<Point2>& path, double clearance);
  /// The first passage narrower than `max_width` on `path` between `from_along` and
  /// `from_along + range` (m along it): where the middle across the path (the ridge of the 5 cm
  /// obstacle distance field within half of max_width + 0.15 m either side of the path) is
  /// narrower than max_width (Passage::width: the free cells' gap plus one cell for the jambs'
  /// faces inside the cells they fill); its middle is that middle at the narrowest point of the
  /// passage's first 1.2 m. A wall on one side only is no passage.
  static Passage findPassage(const Grid& grid, const std::vector<Point2>& path, double from_along, double range,
                             double max_width);
  /// String pulling: drops the path's points a straight line can skip without passing closer to
  /// an obstacle cell than the skipped stretch did (the middle of a passage stays the middle) and
  /// without crossing a blocked cell of `weights` (obstacles and the body's inflation); `dist` is
  /// obstacleDistanceCells(grid). Keeps the first and last point.
  static void smoothPath(const Grid& grid, const std::vector<double>& weights, const cv::Mat& dist,
                         std::vector<Point2>& path);
  /// Cheapest path between two cells on `costs` (A*, 8-connected, the same edge costs as D* Lite):
  /// cell indices from `from` to `to`; empty when there is none.
  static std::vector<int> cheapestPath(const CostGrid& costs, int from, int to);
  /// Arc length along the polyline of the point of it nearest to `q` (among its first `max_along` m).
  static double projectOnto(const std::vector<Point2>& path, const Point2& q, double max_along = 1e300);
  /// The point `dist` along the polyline from its first point (its end when shorter).
  static Point2 pointAlong(const std::vector<Point2>& path, double dist);

private:
  void syncCosts(const Grid& grid, PlanOutput& out);
  // The steps of update(), in order; a bool step returns false when it has set the status.
  void recordWalkedFloor(const Grid& input, const Point2& wearer);  // walked_, work_
  void vouchForBlindZone(const Point2& wearer, double facing, double t, PlanOutput& out);  // work_
  void blockHeldUnseenFloor(const Point2& wearer);  // work_ (unseen_ dropped once mapped or far)
  void measureWalk(const Point2& wearer, double t, PlanOutput& out);  // walking_speed, walk_heading
  bool chooseTarget(const Grid& grid, const Point2& wearer, double heading, bool motion_changed, PlanOutput& out,
                    int& gx, int& gy);
  bool searchPath(const Grid& grid, int wx, int wy, int& gx, int& gy, PlanOutput& out);  // D* Lite
  void shapePath(const Grid& grid, double heading, PlanOutput& out) const;  // path, its heading, length
  void extendPastGoal(const Grid& grid, int gx, int gy, PlanOutput& out) const;  // steer_path to next_
  void placeSteeringPoint(const Grid& grid, bool walking, PlanOutput& out) const;
  void markPassage(const Grid& grid, PlanOutput& out) const;  // passage_* (findPassage)
  // a standing wearer's IN_UNKNOWN: the unmapped floor on its path and judged ray -> unseen_
  void holdUnseenFloorAhead(const Grid& grid, double t, double judged_yaw, PlanOutput& out);
  void freeCrossedSteps(const Point2& wearer);  // work_ (crossed_ dropped once far)
  // a standing wearer held by a step just ahead along `judged_yaw` -> crossed_ (after step_stand_s)
  void crossStepAhead(const Grid& grid, double t, double judged_yaw, PlanOutput& out);

  PlannerParams p_;
  DStarLite dstar_;
  MotionVector motion_;
  WaypointSelector waypoints_;
  CrossingWatch crossing_;
  RangerReading ranger_;
  bool have_grid_ = false;
  Grid last_grid_;  // geometry only (data not kept)
  bool ever_planned_ = false;
  bool has_goal_ = false;
  Point2 goal_;
  bool has_next_ = false;
  Point2 next_;
  std::vector<Point2> walked_;  // the wearer's positions, >= 0.05 m apart
  // floor planned around as blocked: unmapped, just ahead of a standing wearer who could not see it
  std::vector<Point2> unseen_;
  /// How long one standstill has lasted: its cycles at most 0.5 s apart (a longer gap, such as a
  /// cycle with another status between, or time going back starts a new one).
  struct StandstillClock
  {
    double since = -1.0, last = -1.0;  // since < 0: none under way
    double lasted(double t);           // counts cycle t in
    void reset() { since = -1.0; }
  };
  StandstillClock unseen_clock_;  // a standing wearer's IN_UNKNOWN on unmapped floor ahead
  std::vector<Point2> crossed_;   // step cells (centres) a standing wearer was sent over
  StandstillClock step_clock_;    // a standing wearer held by a step ahead
  std::vector<std::pair<double, Point2>> recent_;  // (t, position) over the last walk_window_s
  Grid work_;                   // the input grid with the walked floor marked
  cv::Mat obstacle_dist_;       // work_'s obstacle distance field (cells), this cycle's
};
}  // namespace assistive_planner
