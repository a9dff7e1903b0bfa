#pragma once
// Scoring of the people keys of obstacles_benchmark (issue 22) against the simulator's truth
// (/ground_truth/people). ROS-free so that the rules are gtested on hand-made truths.
//
// - People per frame (scorePeopleFrame): truth people and confirmed tracks, both in the world frame,
//   matched one to one greedily by distance (nearest pairs first) within `gate` (0.5 m). Recall =
//   matched truth people within `radius` (5 m) of the wearer / truth people within it; precision
//   = matched tracks within `radius` / tracks within it (both sets are matched with partners up to
//   radius + gate, so a pair straddling the circle counts for the one inside). Velocity error:
//   |v_track - v_truth| over matched tracks within the radius whose age is at least `min_age` (0.5 s).
// - Ghosts (countGhostCells): of the cells within `radius` whose static truth is free and whose
//   estimate is known (in view, once observed), those the map marks obstacle (100). Cells under a
//   truth person's footprint this frame are left out (a person standing there is rightly an
//   obstacle).
// - Standing people (heldByMap): found when the map marks an obstacle cell under them.
// - Crossings (CrossingScore): per truth person, the closest approach to the wearer over the run
//   (truth positions at the frame times). People whose closest approach is below `cross_distance`
//   (0.5 m) while walking (truth speed at that moment >= `min_speed`, 0.3 m/s: a person standing
//   still has no path to cross and no scene flow; the map holds them as an obstacle) are crossings: warned in time when a warning for a track matched to them came between
//   `lookback` (5 s) and `lead` (1.5 s) before that moment. False warnings: warning onsets (a track
//   warned this frame and not in the previous one) for tracks matched to people whose closest
//   approach stays at or above `far_distance` (1 m), or matched to nobody, per minute of run.
//   The camera's floor (issue 37): a crossing is visible in time when the person was where the
//   camera can see and match them (addVisible(): the caller's test, e.g. the centre inside the
//   image's matchable part) in at least `min_visible_frames` frames between `lookback` and `lead`
//   before the closest approach; one coming from outside the 65 deg view on a constant bearing
//   (a collision course) is not, whatever the pipeline does.
#include <map>
#include <set>
#include <vector>

#include <Eigen/Core>

#include <assistive_obstacles/obstacle_map.h>

namespace assistive_obstacles
{
struct PersonState
{
  int id = 0;
  Eigen::Vector2d position = Eigen::Vector2d::Zero();  ///< m, world
  Eigen::Vector2d velocity = Eigen::Vector2d::Zero();  ///< m/s
  double radius = 0.0;                                 ///< m
  double age = 0.0;                                    ///< s since the track was born (tracks only)
};

struct PeopleScoreParams
{
  double radius = 5.0;    ///< m, people and tracks this close to the wearer are scored
  double gate = 0.5;      ///< m, a track within this of a truth person may be it
  double min_age = 0.5;   ///< s, tracks younger than this are left out of the velocity error
};

struct PeopleFrameScore
{
  int truth_in_range = 0, truth_matched = 0;
  int tracks_in_range = 0, tracks_matched = 0;
  double velocity_err_sum = 0.0;  ///< m/s, summed over the matched tracks old enough
  int velocity_n = 0;
  std::map<int, int> track_to_truth;  ///< track id -> truth id (every match, in range or not)
};

PeopleFrameScore scorePeopleFrame(const std::vector<PersonState>& truth, const std::vector<PersonState>& tracks,
                                  const Eigen::Vector2d& wearer, const PeopleScoreParams& p = PeopleScoreParams());

struct GhostCount
{
  long free_known = 0;  ///< truth-free cells within the radius with a known estimate
  long ghost = 0;       ///< of them, marked obstacle
};

/// `truth` and `est` are grids of the cell codes (cell_values.h); `people` the truth people of
/// the frame (their footprints are left out).
GhostCount countGhostCells(const GridData& truth, const GridData& est, const Eigen::Vector2d& wearer, double radius,
                           const std::vector<PersonState>& people);

/// Whether the map holds a standing person (issue 37: a person standing still has no flow and is
/// mapped as an ordinary obstacle, which is finding them): a cell of `est` marked obstacle whose
/// centre lies within the person's radius plus half a cell's diagonal.
bool heldByMap(const GridData& est, const PersonState& person);

struct CrossingScoreParams
{
  double cross_distance = 0.5;  ///< m, closest approach that makes a crossing
  double far_distance = 1.0;    ///< m, people never this close must not be warned about
  double lead = 1.5;            ///< s, a warning must come at least this long before the closest approach
  double lookback = 5.0;        ///< s, ... and at most this long
  double min_speed = 0.3;       ///< m/s, a person slower than this at the closest approach is standing, not crossing
  int min_visible_frames = 3;   ///< frames in view before `lead` that make a crossing visible in time (the tracker's birth hits)
};

class CrossingScore
{
public:
  explicit CrossingScore(const CrossingScoreParams& p = CrossingScoreParams()) : params_(p) {}
  /// One frame: the wearer's and the people's truth positions, the warned track ids and the
  /// frame's match of tracks to truth people (scorePeopleFrame().track_to_truth).
  void addFrame(double t, const Eigen::Vector2d& wearer, const std::vector<PersonState>& truth,
                const std::set<int>& warned_tracks, const std::map<int, int>& track_to_truth);

  /// The truth people the camera could see this frame (see above).
  void addVisible(double t, const std::set<int>& truth_ids);

  int crossings() const;          ///< truth people whose closest approach < cross_distance
  int crossingsVisible() const;   ///< of them, visible in time
  int crossingsWarnedVisible() const;  ///< of those, warned in time
  int crossingsWarned() const;    ///< of them, warned in time
  double warnedPct() const;       ///< NaN when there is no crossing
  int falseWarnings() const;      ///< warning onsets for people never within far_distance, or for no one
  double falseWarningsPerMin() const;  ///< NaN for a run shorter than one frame
  double minutes() const { return t_last_ > t_first_ ? (t_last_ - t_first_) / 60.0 : 0.0; }
  /// Per crossing (diagnostics): truth id, closest approach time and distance, the first time a
  /// track was matched to the person within the lookback and the first warning then (NaN: none).
  struct CrossingDetail
  {
    int id;
    double t_closest, d_closest, first_tracked, first_warned;
    double first_visible;  ///< the first frame in view within the lookback (NaN: none)
    bool visible;          ///< visible in time
  };
  std::vector<CrossingDetail> details() const;

private:
  struct Onset
  {
    double t;
    int truth_id;  ///< 0: matched to no one
  };
  CrossingScoreParams params_;
  struct Closest
  {
    double d, t, speed;
  };
  std::map<int, Closest> closest_;  ///< truth id -> distance, time and truth speed at the closest approach
  std::map<int, std::vector<double>> warned_at_;      ///< truth id -> times a matched track was warned
  std::map<int, std::vector<double>> matched_at_;     ///< truth id -> times a track was matched to them
  std::map<int, std::vector<double>> visible_at_;     ///< truth id -> times the camera could see them
  bool isCrossing(const Closest& c) const { return c.d < params_.cross_distance && c.speed >= params_.min_speed; }
  bool visibleInTime(int id, double tc) const;
  bool warnedInTime(int id, double tc) const;
  std::vector<Onset> onsets_;
  std::set<int> warned_prev_;
  double t_first_ = 0.0, t_last_ = 0.0;
  bool started_ = false;
};

}  // namespace assistive_obstacles
