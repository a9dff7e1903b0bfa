#pragma once
// A population of simulated vest wearers drawn from published ranges (issue 33): each mobility
// trial draws one wearer, so guidance is judged on a population, the slowest-reacting tenth
// included, not on one perfect person. Every trait's distribution and the source it rests on are
// in specs() and in docs/wearer_population.md (the table there is the same as specs()).
//
// The population is fixed before the guidance is tuned and changes only with a new source, never
// to make the guidance look good.
//
// Determinism: a wearer is a pure function of its seed, on every platform (the draws use their own
// generator and transforms, not the standard library's implementation-defined distributions).
// Each trait has its own random stream, so a trait added later does not change the others' values.
//
// ROS-free; no dependency on the wearer's motion model (wearer.h): the wearer's response model
// reads these traits.
#include <cstddef>
#include <cstdint>
#include <vector>

namespace assistive_trials
{
/// One wearer. Units are in the names; angles in degrees, + = to the left (counter-clockwise).
struct WearerTraits
{
  /// Preferred walking speed: the pace with a sighted guide, the PPWS denominator (m/s).
  double preferred_speed_mps = 1.15;
  /// From a change of a torso motor to the start of the body's response while walking (s).
  double reaction_s = 0.75;
  /// Turning gain: turn made / turn asked for (1 = exact, > 1 over-turns). Constant per wearer.
  double turn_gain = 1.0;
  /// Heading noise while trying to walk straight without cues, as a random walk of the heading in
  /// distance walked: after d metres its standard deviation is veer_sigma * sqrt(d) (deg/sqrt(m)).
  /// Per step of length L: sigma_step = veer_sigma * sqrt(L) (Kallie et al. 2007's step error).
  double veer_sigma_deg_per_sqrt_m = 2.0;
  /// The wearer's constant heading drift while walking straight (deg per metre, signed):
  /// Kallie et al. 2007's consistent step bias. A wearer with b walks a circle of radius 57.3/|b| m.
  double veer_bias_deg_per_m = 0.0;
  /// Vibration intensity levels the wearer tells apart by absolute identification (2..4).
  int intensity_levels = 3;
  /// Shortest burst felt as a vibration (not as a tap) (s).
  double min_pulse_s = 0.03;
  /// The body's radius at shoulder level: half the bideltoid breadth with indoor clothing (m).
  double body_radius_m = 0.22;
  /// Gait initiation: the mean forward acceleration from standing to the preferred speed, from the
  /// start of the body's response to a 'go' (m/s^2; the wearer model stops at twice this).
  double gait_accel_mps2 = 0.85;
};

/// One trait's published range, the population's mean of it and where both come from (the
/// docs/wearer_population.md table, row by row).
struct TraitSpec
{
  const char* name;          ///< the WearerTraits field
  double lo, hi;             ///< every draw lies in [lo, hi]
  double mean;               ///< the population's mean (analytic, of the distribution below)
  const char* distribution;  ///< how it is drawn
  const char* source;        ///< short citation (full ones in docs/wearer_population.md)
};

class WearerPopulation
{
public:
  /// The wearer of trial `seed`: every trait drawn independently from its distribution.
  WearerTraits draw(uint32_t seed) const;
  /// The same wearer as draw(seed) except that the reaction time is drawn from the slowest
  /// `fraction` of the population (reaction >= reactionQuantile(1 - fraction)): the issue's
  /// "worst 10 % of wearers (slowest reaction)". fraction in (0, 1].
  WearerTraits drawSlowest(uint32_t seed, double fraction = 0.1) const;
  /// The population's reaction time at quantile q in [0, 1] (exact, from its distribution).
  double reactionQuantile(double q) const;
  /// Indices of the ceil(fraction * n) wearers with the slowest reactions, slowest first (ties by
  /// index). Empty for an empty input.
  static std::vector<size_t> slowestReaction(const std::vector<WearerTraits>& wearers, double fraction = 0.1);
  /// One row per trait, in WearerTraits order.
  static const std::vector<TraitSpec>& specs();
};

}  // namespace assistive_trials
