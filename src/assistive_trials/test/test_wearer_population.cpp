// The wearer population (issue 33): a wearer is a pure function of its seed, every trait of 10,000
// wearers lies inside its published range, the population's means match the stated ones (the
// sources' where the sources give a mean), and the slowest decile is the slowest.
#include <assistive_trials/wearer_population.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <map>

#include <gtest/gtest.h>

using namespace assistive_trials;

namespace
{
constexpr int kPopulationDraws = 10000;

std::vector<WearerTraits> populationSample(uint32_t first_seed = 1)
{
  const WearerPopulation pop;
  std::vector<WearerTraits> w;
  w.reserve(kPopulationDraws);
  for (int i = 0; i < kPopulationDraws; ++i) w.push_back(pop.draw(first_seed + uint32_t(i)));
  return w;
}

double traitValue(const WearerTraits& w, const std::string& name)
{
  if (name == "preferred_speed_mps") return w.preferred_speed_mps;
  if (name == "reaction_s") return w.reaction_s;
  if (name == "turn_gain") return w.turn_gain;
  if (name == "veer_sigma_deg_per_sqrt_m") return w.veer_sigma_deg_per_sqrt_m;
  if (name == "veer_bias_deg_per_m") return w.veer_bias_deg_per_m;
  if (name == "intensity_levels") return w.intensity_levels;
  if (name == "min_pulse_s") return w.min_pulse_s;
  if (name == "body_radius_m") return w.body_radius_m;
  if (name == "gait_accel_mps2") return w.gait_accel_mps2;
  ADD_FAILURE() << "a spec names an unknown trait: " << name;
  return std::nan("");
}

bool sameTraits(const WearerTraits& a, const WearerTraits& b)
{
  return a.preferred_speed_mps == b.preferred_speed_mps && a.reaction_s == b.reaction_s &&
         a.turn_gain == b.turn_gain && a.veer_sigma_deg_per_sqrt_m == b.veer_sigma_deg_per_sqrt_m &&
         a.veer_bias_deg_per_m == b.veer_bias_deg_per_m && a.intensity_levels == b.intensity_levels &&
         a.min_pulse_s == b.min_pulse_s && a.body_radius_m == b.body_radius_m && a.gait_accel_mps2 == b.gait_accel_mps2;
}
}  // namespace

TEST(WearerPopulation, SameSeedSameWearerOtherSeedOtherWearer)
{
  const WearerPopulation a, b;
  for (uint32_t seed : {0u, 1u, 7u, 123456u, 0xFFFFFFFFu})
  {
    EXPECT_TRUE(sameTraits(a.draw(seed), b.draw(seed))) << "seed " << seed;
    EXPECT_TRUE(sameTraits(a.draw(seed), a.draw(seed))) << "seed " << seed;
    EXPECT_TRUE(sameTraits(a.drawSlowest(seed), b.drawSlowest(seed))) << "seed " << seed;
  }
  const WearerTraits w1 = a.draw(1), w2 = a.draw(2);
  EXPECT_NE(w1.preferred_speed_mps, w2.preferred_speed_mps);
  EXPECT_NE(w1.reaction_s, w2.reaction_s);
  EXPECT_NE(w1.body_radius_m, w2.body_radius_m);
}

TEST(WearerPopulation, KnownSeedGivesKnownWearer)
{
  // Pins the generator: a change to any draw (it must come with a new source) shows up here. The
  // draws are integer arithmetic and exp/log/cos/sqrt/pow, so 1e-9 holds on any libm.
  const WearerTraits w = WearerPopulation().draw(42);
  EXPECT_NEAR(w.preferred_speed_mps, 1.2026827911078968, 1e-9);
  EXPECT_NEAR(w.reaction_s, 0.78660773888961599, 1e-9);
  EXPECT_NEAR(w.turn_gain, 0.78580888174556629, 1e-9);
  EXPECT_NEAR(w.veer_sigma_deg_per_sqrt_m, 1.1801214394385513, 1e-9);
  EXPECT_NEAR(w.veer_bias_deg_per_m, 1.5157927737619652, 1e-9);
  EXPECT_EQ(w.intensity_levels, 3);
  EXPECT_NEAR(w.min_pulse_s, 0.028541157807835605, 1e-9);
  EXPECT_NEAR(w.body_radius_m, 0.24569633781604344, 1e-9);
  EXPECT_NEAR(w.gait_accel_mps2, 0.7919053927959058, 1e-9);
}

TEST(WearerPopulation, EveryDrawInsideItsPublishedRange)
{
  const auto wearers = populationSample();
  const auto& specs = WearerPopulation::specs();
  ASSERT_EQ(specs.size(), 9u);
  for (const TraitSpec& s : specs)
  {
    ASSERT_NE(s.source, nullptr);
    EXPECT_GT(std::strlen(s.source), 0u) << s.name << " has no source";
    double lo = 1e300, hi = -1e300;
    for (const auto& w : wearers)
    {
      const double v = traitValue(w, s.name);
      lo = std::min(lo, v);
      hi = std::max(hi, v);
    }
    EXPECT_GE(lo, s.lo) << s.name;
    EXPECT_LE(hi, s.hi) << s.name;
    // the draws span the range (within 3 % of its width at each end: the draws reach both ends)
    const double width = s.hi - s.lo;
    EXPECT_LT(lo - s.lo, 0.03 * width) << s.name << " never reaches its low end";
    EXPECT_LT(s.hi - hi, 0.03 * width) << s.name << " never reaches its high end";
  }
}

TEST(WearerPopulation, MeansMatchTheStatedMeans)
{
  const auto wearers = populationSample(1000);
  for (const TraitSpec& s : WearerPopulation::specs())
  {
    double sum = 0.0, sum2 = 0.0;
    for (const auto& w : wearers)
    {
      const double v = traitValue(w, s.name);
      sum += v;
      sum2 += v * v;
    }
    const double n = double(wearers.size());
    const double mean = sum / n, sd = std::sqrt(std::max(0.0, sum2 / n - mean * mean));
    // 4 standard errors of the mean (the seeds are fixed, so the outcome is too)
    EXPECT_NEAR(mean, s.mean, 4.0 * sd / std::sqrt(n) + 1e-12) << s.name;
  }
}

TEST(WearerPopulation, SourcesMeansAndShares)
{
  const auto wearers = populationSample(5000);
  const double n = double(wearers.size());
  // The trait means that are the sources' own figures:
  // Remache-Vinueza et al. 2025: minimum duration for a vibration about 30 ms.
  double pulse = 0.0, radius = 0.0, abs_bias = 0.0, speed = 0.0;
  std::map<int, int> levels;
  int men_like = 0;
  for (const auto& w : wearers)
  {
    pulse += w.min_pulse_s;
    radius += w.body_radius_m;
    abs_bias += std::abs(w.veer_bias_deg_per_m);
    speed += w.preferred_speed_mps;
    ++levels[w.intensity_levels];
    if (w.body_radius_m > (435.0 + 10.0) / 2000.0) ++men_like;  // wider than the widest woman drawn
  }
  EXPECT_NEAR(pulse / n, 0.030, 0.001);
  // Bideltoid 50th percentiles (men 465, women 395 mm) + 10 mm clothing, halved: 0.220 m.
  EXPECT_NEAR(radius / n, 0.220, 0.002);
  // |bias| uniform 0..5.7 deg/m: mean 2.85.
  EXPECT_NEAR(abs_bias / n, 2.85, 0.08);
  // Issue 33's 0.9-1.4 m/s, its middle.
  EXPECT_NEAR(speed / n, 1.15, 0.01);
  // round(2^IT), IT uniform 1..2 bits: P(2, 3, 4) = 0.322, 0.485, 0.193; nothing else.
  EXPECT_EQ(levels.size(), 3u);
  EXPECT_NEAR(levels[2] / n, 0.322, 0.02);
  EXPECT_NEAR(levels[3] / n, 0.485, 0.02);
  EXPECT_NEAR(levels[4] / n, 0.193, 0.02);
  // Wider than the women's 95th percentile (435 mm): only men, those above 435 mm of the men's
  // 420..510 mm (P = 0.90 for N(465, 28) truncated there): 0.45 of the population.
  EXPECT_NEAR(men_like / n, 0.45, 0.02);
  // The veering bias has no preferred side across the population.
  int left = 0;
  for (const auto& w : wearers) left += w.veer_bias_deg_per_m > 0;
  EXPECT_NEAR(left / n, 0.5, 0.02);
}

TEST(WearerPopulation, SlowestDecileHasTheSlowestReactions)
{
  const auto wearers = populationSample();
  const auto worst = WearerPopulation::slowestReaction(wearers, 0.1);
  ASSERT_EQ(worst.size(), size_t(kPopulationDraws / 10));
  // slowest first
  for (size_t i = 1; i < worst.size(); ++i) EXPECT_GE(wearers[worst[i - 1]].reaction_s, wearers[worst[i]].reaction_s);
  // every wearer outside the decile reacts at least as fast as every one inside it
  double fastest_in = 1e300;
  for (size_t i : worst) fastest_in = std::min(fastest_in, wearers[i].reaction_s);
  std::vector<bool> in(wearers.size(), false);
  for (size_t i : worst) in[i] = true;
  for (size_t i = 0; i < wearers.size(); ++i)
  {
    if (!in[i]) { EXPECT_LE(wearers[i].reaction_s, fastest_in) << "wearer " << i; }
  }
  // the decile's edge is the population's 90th percentile (uniform 0.3..1.2 s: 1.11 s)
  const WearerPopulation pop;
  EXPECT_NEAR(pop.reactionQuantile(0.9), 1.11, 1e-12);
  EXPECT_NEAR(fastest_in, pop.reactionQuantile(0.9), 0.01);
  // the decile reacts more slowly on average than the population (mean 0.75 s) and than its edge
  double mean_in = 0.0;
  for (size_t i : worst) mean_in += wearers[i].reaction_s;
  mean_in /= double(worst.size());
  EXPECT_GT(mean_in, pop.reactionQuantile(0.9));
  EXPECT_NEAR(mean_in, 1.155, 0.005);
}

TEST(WearerPopulation, DrawSlowestIsTheSameWearerWithASlowReaction)
{
  const WearerPopulation pop;
  for (uint32_t seed = 1; seed <= 2000; ++seed)
  {
    const WearerTraits w = pop.draw(seed), slow = pop.drawSlowest(seed);
    EXPECT_GE(slow.reaction_s, pop.reactionQuantile(0.9)) << seed;
    EXPECT_LE(slow.reaction_s, 1.2) << seed;
    WearerTraits same = slow;
    same.reaction_s = w.reaction_s;
    EXPECT_TRUE(sameTraits(w, same)) << "drawSlowest changed more than the reaction, seed " << seed;
  }
  // fraction 1: the whole population's range
  EXPECT_GE(pop.drawSlowest(3, 1.0).reaction_s, 0.3);
  EXPECT_THROW(pop.drawSlowest(3, 0.0), std::invalid_argument);
  EXPECT_THROW(pop.reactionQuantile(1.5), std::invalid_argument);
}

TEST(WearerPopulation, SlowestReactionEdgeCases)
{
  EXPECT_TRUE(WearerPopulation::slowestReaction({}, 0.1).empty());
  std::vector<WearerTraits> three(3);
  three[0].reaction_s = 0.5;
  three[1].reaction_s = 0.9;
  three[2].reaction_s = 0.9;
  // ceil(0.1 * 3) = 1: the slowest, ties by index
  const auto one = WearerPopulation::slowestReaction(three, 0.1);
  ASSERT_EQ(one.size(), 1u);
  EXPECT_EQ(one[0], 1u);
  const auto all = WearerPopulation::slowestReaction(three, 1.0);
  ASSERT_EQ(all.size(), 3u);
  EXPECT_EQ(all[2], 0u);
  // exactly a tenth of 20 is 2 (no rounding up past it)
  EXPECT_EQ(WearerPopulation::slowestReaction(std::vector<WearerTraits>(20), 0.1).size(), 2u);
}
