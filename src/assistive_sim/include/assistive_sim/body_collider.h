#pragma once
// The body's collider against a world (issue 19): a cylinder that counts collisions by obstacle
// kind. ROS-free. World physics, so it lives with the worlds: the mobility trials' wearer
// (assistive_trials) walks with it and the world generator's tests check that a body fits
// through the generated courses.
#include <array>
#include <limits>
#include <set>
#include <string>
#include <vector>

#include <Eigen/Core>

#include <assistive_sim/world.h>

namespace assistive_sim
{
/// What kind of thing the body touched (for `<kind>_collisions_per_trial`).
enum class ObstacleKind
{
  WALL,       ///< `wall` elements (doorway lintels included)
  OVERHANG,   ///< anything whose underside is above `overhang_min_z` (a sign at head height)
  GLASS,      ///< `glass` panels
  FURNITURE,  ///< boxes, columns, tables, benches
  PERSON,     ///< a walking or standing person (World::people, issue 22)
  NUM_KINDS
};
const char* kindName(ObstacleKind k);  ///< "wall", "overhang", "glass", "furniture", "people"

/// The body's collider against a world's solids (glass included; walkable steps never collide)
/// and, once setTime() was called, its people where they are at that time (issue 22): a person
/// collides when the body's cylinder and the person's touch (centre distance < the sum of the
/// radii); it counts once per encounter (the bodies must part by more than 5 cm before it counts
/// again) and makes the walker bump (stop and feel around) at its start, but never blocks a move:
/// a person may walk on through the wearer (its script, or giving way too late:
/// people_give_way.h), so blocking would trap the body.
class BodyCollider
{
public:
  struct Contact
  {
    std::string object;  ///< the world element (`Solid::source`): one per table, wall, sign...
    ObstacleKind kind;
  };
  BodyCollider(const World& world, double radius, double height, double overhang_min_z = 1.0);
  /// Elements whose solids the cylinder at xy (floor to `height`) overlaps.
  std::vector<Contact> contacts(const Eigen::Vector2d& xy) const;
  bool free(const Eigen::Vector2d& xy) const { return contacts(xy).empty(); }
  /// Distance from the body's surface to the nearest solid at body height (m, < 0 inside).
  double clearance(const Eigen::Vector2d& xy) const;
  /// Solids whose z range overlaps [z0, z1] at ground point xy (the cane's tip, a probe); people
  /// too (floor to their height) after setTime().
  bool occupied(const Eigen::Vector2d& xy, double z0, double z1, bool with_people = true) const;
  /// The people's clock (s, personAt's) for the following contacts, occupied() and move(); NaN
  /// (the default) leaves the people out.
  void setTime(double t) { time_ = t; }
  /// People (indices) the body at xy touches at the current time.
  std::vector<size_t> personContacts(const Eigen::Vector2d& xy) const;
  /// Distance from the body's surface to the nearest person's at the current time (+inf: none).
  double personClearance(const Eigen::Vector2d& xy) const;
  /// Move from `from` towards `to`; returns where the body ends (it stops at first contact, in
  /// 2 cm steps), and registers collision events: an element counts once per contact episode
  /// (it must be left by more than 5 cm before it can count again).
  Eigen::Vector2d move(const Eigen::Vector2d& from, const Eigen::Vector2d& to, bool& bumped);
  /// Collision events so far, per kind, and their places.
  const std::array<int, size_t(ObstacleKind::NUM_KINDS)>& collisions() const { return counts_; }
  int totalCollisions() const;
  const std::vector<Eigen::Vector2d>& collisionPlaces() const { return places_; }
  double radius() const { return radius_; }

private:
  double distance(const Solid& s, const Eigen::Vector2d& xy) const;  // footprint distance, < 0 inside
  ObstacleKind classify(const Solid& s) const;
  void release(const Eigen::Vector2d& xy);

  std::vector<Solid> solids_;  ///< only those at body height
  std::vector<Person> people_;
  double time_ = std::numeric_limits<double>::quiet_NaN();
  double radius_, height_, overhang_min_z_;
  std::set<std::string> touching_;
  std::set<size_t> touching_people_;
  std::array<int, size_t(ObstacleKind::NUM_KINDS)> counts_{};
  std::vector<Eigen::Vector2d> places_;
};
}  // namespace assistive_sim
