// The wearer population (issue 33). Each trait: its distribution, its range, and the source it
// rests on; full citations, the quoted figures and what is not sourced are in
// docs/wearer_population.md. Where a source gives a range but not the population's shape over it,
// the draw is uniform over the range (the least-informed choice, and one that gives the slow and
// clumsy ends of a range as much weight as the middle).
#include <assistive_trials/wearer_population.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace assistive_trials
{
namespace
{
// ---- the population's constants (change only with a new source) ----

// Preferred walking speed (m/s): uniform over issue 33's range. The upper end matches sighted
// adults' comfortable gait speed (Bohannon 1997: group means 1.272 to 1.462 m/s, ages 20-79);
// blind pedestrians walking with a sighted guide choose a pace close to sighted pedestrians'
// (Clark-Carter, Heyes & Howarth 1986) and walk more slowly on their own (Nakamura 1997). The
// lower end 0.9 m/s is the issue's; no paper in reach gave blind adults' guided pace in m/s.
constexpr double kSpeedLo = 0.9, kSpeedHi = 1.4;

// Reaction to a torso vibration while walking (s): uniform over issue 33's range. Lower end: the
// issue's 0.3 s, a simple vibrotactile reaction at rest, to which stimulus location and a
// secondary task add 20-120 and > 130 ms (Bao et al. 2019). Upper end: belt guidance while
// walking measured "slightly more than 1 seconds" for every pattern (Cosgun, Sisbot &
// Christensen 2014) and 1-2 s on average (Cosgun et al., Haptics Symposium 2014).
constexpr double kReactionLo = 0.3, kReactionHi = 1.2;

// Turning gain (turn made / turn asked): log-normal around 1, sigma_log 0.15, truncated at
// +-2 sigma (0.741..1.350). Persistent individual turn biases: Kallie et al. 2007 (consistent step
// bias), the seed (5.5.3.3: wearers over-turned). The spread is DERIVED, not measured: Cosgun et
// al. 2014's mean angular error of 8.4 deg (best belt pattern), read as a fraction of a 70 deg
// turn (our assumption), is 12 % = E|log gain| = 0.8 sigma_log -> sigma_log 0.15.
constexpr double kGainSigmaLog = 0.15, kGainTruncSigmas = 2.0;

// Veering, in Kallie, Schrater & Legge 2007's form (undetected variable error in each step, the
// largest source, plus a consistent step bias; initial orientation error is per trial, not a
// trait). Bias magnitude uniform 0..5.7 deg/m, sign even: 5.7 deg/m is a 20 m diameter circle,
// Souman et al. 2009's blindfolded walkers' "often surprisingly small circles (diameter < 20 m)";
// 0 (straight) is within Bestaven et al. 2012's outcomes (11 % of blindfolded trajectories
// straight, 50 % left, 39 % right). Random-walk sigma uniform 1..3 deg/sqrt(m): NOT SOURCED
// (Kallie et al.'s fitted values were not in reach); at 20 m it gives a lateral spread of
// 0.9-2.7 m (1 sigma), the scale of Guth 2008's veering-training criterion (stay within 1 m either
// side of a 20 m crossing): a plausibility check, not a source.
constexpr double kVeerBiasMax = 5.7;
constexpr double kVeerSigmaLo = 1.0, kVeerSigmaHi = 3.0;

// Intensity levels told apart: round(2^IT), the information transferred IT uniform over 1..2 bits,
// the range Rabinowitz et al. 1987 measured for one-dimensional vibrotactile sets (intensity,
// frequency or area alone); van Erp 2002: "not more than 4 different levels" between detection
// threshold and comfort. P(2, 3, 4) = 0.322, 0.485, 0.193.
constexpr double kLevelsBitsLo = 1.0, kLevelsBitsHi = 2.0;

// Shortest burst felt as a vibration (s): uniform 20..40 ms around Remache-Vinueza, Trujillo-Leon
// & Vidal-Verdu 2025's minimum duration of about 30 ms (35 participants, 40-590 Hz); the spread
// is NOT SOURCED.
constexpr double kPulseLo = 0.020, kPulseHi = 0.040;

// Body radius (m): half the bideltoid shoulder breadth plus 10 mm indoor clothing, men and women
// in equal numbers, normal per sex truncated at its 5th and 95th percentiles (British adults
// 19-65, the "online anthropometry" tables of A.H.S. Chan, City University of Hong Kong):
// men 420/465/510 mm (SD 28), women 355/395/435 mm (SD 24).
struct Breadth
{
  double p5, p50, p95, sd;
};
constexpr Breadth kMen{420.0, 465.0, 510.0, 28.0}, kWomen{355.0, 395.0, 435.0, 24.0};
constexpr double kClothingMm = 10.0;

// Gait initiation, the mean acceleration from standing to the preferred speed (m/s^2): uniform
// 0.5..1.2. DERIVED from Seethapathi & Srinivasan 2015's published per-subject data (healthy
// adults walking 0.5-89 m at their preferred pace, start to stop; dryad.95115): each subject's
// average speed over 6-14 m read with this wearer model's own start (a) and stop (2a) against its
// 89 m speed gives a = 0.43-0.62 m/s^2 (subject 1) and 1.00-1.25 m/s^2 (subject 2) (the two
// subjects whose 89 m walks were in reach). A lower bound where a subject chose a lower peak speed
// for a short walk (their paper's finding). Cross-checks: steady speed within three steps
// (a sloped-gait study in Gait & Posture, authors not in reach: >= 95 % with the 3rd step on the
// level; 0.5 m/s^2 reaches 1.15 m/s in 1.3 m, about two steps) and at the end of the first step in adults (Breniere & Do);
// frail adults aged 83 reach only 0.66 m/s after 1.43 m (Lindemann et al. 2008: about
// 0.15 m/s^2, a slower population than this one's 0.9-1.4 m/s walkers, left out).
constexpr double kAccelLo = 0.5, kAccelHi = 1.2;

// ---- the generator: splitmix64, one stream per trait (fully specified, platform-independent) ----
enum Trait : uint64_t
{
  SPEED = 1,
  REACTION,
  GAIN,
  VEER_SIGMA,
  VEER_BIAS,
  LEVELS,
  PULSE,
  BODY,
  ACCEL
};

class Stream
{
public:
  Stream(uint32_t seed, Trait trait)
    : state_((uint64_t(seed) << 8 | uint64_t(trait)) * 0x9E3779B97F4A7C15ull ^ 0xD1B54A32D192ED03ull)
  {
  }
  /// Uniform in [0, 1).
  double uniform()
  {
    uint64_t z = (state_ += 0x9E3779B97F4A7C15ull);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    z ^= z >> 31;
    return double(z >> 11) * (1.0 / 9007199254740992.0);
  }
  double uniform(double lo, double hi) { return lo + (hi - lo) * uniform(); }
  /// Standard normal (Box-Muller).
  double normal()
  {
    const double u1 = 1.0 - uniform();  // (0, 1]
    const double u2 = uniform();
    return std::sqrt(-2.0 * std::log(u1)) * std::cos(2.0 * M_PI * u2);
  }
  /// Standard normal truncated to [-k, k] (rejection).
  double normalWithin(double k)
  {
    for (;;)
    {
      const double z = normal();
      if (std::abs(z) <= k) return z;
    }
  }

private:
  uint64_t state_;
};

double truncatedBreadth(Stream& s, const Breadth& b)
{
  for (;;)
  {
    const double v = b.p50 + b.sd * s.normal();
    if (v >= b.p5 && v <= b.p95) return v;
  }
}

double stdNormalCdf(double x) { return 0.5 * std::erfc(-x / std::sqrt(2.0)); }
}  // namespace

WearerTraits WearerPopulation::draw(uint32_t seed) const
{
  WearerTraits w;
  {
    Stream s(seed, SPEED);
    w.preferred_speed_mps = s.uniform(kSpeedLo, kSpeedHi);
  }
  {
    Stream s(seed, REACTION);
    w.reaction_s = s.uniform(kReactionLo, kReactionHi);
  }
  {
    Stream s(seed, GAIN);
    w.turn_gain = std::exp(kGainSigmaLog * s.normalWithin(kGainTruncSigmas));
  }
  {
    Stream s(seed, VEER_SIGMA);
    w.veer_sigma_deg_per_sqrt_m = s.uniform(kVeerSigmaLo, kVeerSigmaHi);
  }
  {
    Stream s(seed, VEER_BIAS);
    const double sign = s.uniform() < 0.5 ? -1.0 : 1.0;
    w.veer_bias_deg_per_m = sign * s.uniform(0.0, kVeerBiasMax);
  }
  {
    Stream s(seed, LEVELS);
    w.intensity_levels = int(std::lround(std::pow(2.0, s.uniform(kLevelsBitsLo, kLevelsBitsHi))));
  }
  {
    Stream s(seed, PULSE);
    w.min_pulse_s = s.uniform(kPulseLo, kPulseHi);
  }
  {
    Stream s(seed, BODY);
    const Breadth& b = s.uniform() < 0.5 ? kMen : kWomen;
    w.body_radius_m = (truncatedBreadth(s, b) + kClothingMm) / 2000.0;
  }
  {
    Stream s(seed, ACCEL);
    w.gait_accel_mps2 = s.uniform(kAccelLo, kAccelHi);
  }
  return w;
}

WearerTraits WearerPopulation::drawSlowest(uint32_t seed, double fraction) const
{
  if (!(fraction > 0.0 && fraction <= 1.0)) throw std::invalid_argument("drawSlowest: fraction must be in (0, 1]");
  WearerTraits w = draw(seed);
  Stream s(seed, REACTION);
  w.reaction_s = s.uniform(reactionQuantile(1.0 - fraction), kReactionHi);
  return w;
}

double WearerPopulation::reactionQuantile(double q) const
{
  if (!(q >= 0.0 && q <= 1.0)) throw std::invalid_argument("reactionQuantile: q must be in [0, 1]");
  return kReactionLo + q * (kReactionHi - kReactionLo);
}

std::vector<size_t> WearerPopulation::slowestReaction(const std::vector<WearerTraits>& wearers, double fraction)
{
  if (!(fraction > 0.0 && fraction <= 1.0)) throw std::invalid_argument("slowestReaction: fraction must be in (0, 1]");
  std::vector<size_t> idx(wearers.size());
  for (size_t i = 0; i < idx.size(); ++i) idx[i] = i;
  std::stable_sort(idx.begin(), idx.end(),
                   [&](size_t a, size_t b) { return wearers[a].reaction_s > wearers[b].reaction_s; });
  const size_t n = size_t(std::ceil(fraction * double(wearers.size()) - 1e-9));
  idx.resize(std::min(n, idx.size()));
  return idx;
}

const std::vector<TraitSpec>& WearerPopulation::specs()
{
  static const std::vector<TraitSpec> rows = [] {
    // Analytic means of the distributions above.
    const double k = kGainTruncSigmas, sg = kGainSigmaLog;
    const double gain_mean = std::exp(sg * sg / 2) * (stdNormalCdf(k - sg) - stdNormalCdf(-k - sg)) /
                             (stdNormalCdf(k) - stdNormalCdf(-k));
    double levels_mean = 0.0;  // P(round(2^IT) = n) for IT uniform in [1, 2] bits
    for (int n = 2; n <= 4; ++n)
    {
      const double a = std::max(kLevelsBitsLo, std::log2(n - 0.5)), b = std::min(kLevelsBitsHi, std::log2(n + 0.5));
      levels_mean += n * std::max(0.0, b - a) / (kLevelsBitsHi - kLevelsBitsLo);
    }
    const double body_mean = ((kMen.p50 + kWomen.p50) / 2 + kClothingMm) / 2000.0;  // truncation symmetric
    return std::vector<TraitSpec>{
        {"preferred_speed_mps", kSpeedLo, kSpeedHi, (kSpeedLo + kSpeedHi) / 2, "uniform",
         "issue 33; Bohannon 1997; Clark-Carter, Heyes & Howarth 1986"},
        {"reaction_s", kReactionLo, kReactionHi, (kReactionLo + kReactionHi) / 2, "uniform",
         "issue 33; Cosgun, Sisbot & Christensen 2014; Bao et al. 2019"},
        {"turn_gain", std::exp(-k * sg), std::exp(k * sg), gain_mean, "log-normal, sigma_log 0.15, truncated +-2 sigma",
         "Kallie et al. 2007 (persistent bias); spread derived from Cosgun et al. 2014 (8.4 deg)"},
        {"veer_sigma_deg_per_sqrt_m", kVeerSigmaLo, kVeerSigmaHi, (kVeerSigmaLo + kVeerSigmaHi) / 2, "uniform",
         "form: Kallie, Schrater & Legge 2007; magnitude NOT SOURCED"},
        {"veer_bias_deg_per_m", -kVeerBiasMax, kVeerBiasMax, 0.0, "sign even, magnitude uniform 0..5.7",
         "Souman et al. 2009 (circles < 20 m); Bestaven et al. 2012"},
        {"intensity_levels", 2, 4, levels_mean, "round(2^IT), IT uniform 1..2 bits",
         "Rabinowitz et al. 1987; van Erp 2002"},
        {"min_pulse_s", kPulseLo, kPulseHi, (kPulseLo + kPulseHi) / 2, "uniform (spread NOT SOURCED)",
         "Remache-Vinueza et al. 2025 (about 30 ms)"},
        {"body_radius_m", (kWomen.p5 + kClothingMm) / 2000.0, (kMen.p95 + kClothingMm) / 2000.0, body_mean,
         "half of (bideltoid + 10 mm); 50/50 men/women, normal truncated 5th-95th",
         "Chan, online anthropometry (British adults 19-65)"},
        {"gait_accel_mps2", kAccelLo, kAccelHi, (kAccelLo + kAccelHi) / 2, "uniform",
         "derived from Seethapathi & Srinivasan 2015 (per-subject speeds over 6-14 m and 89 m)"},
    };
  }();
  return rows;
}

}  // namespace assistive_trials
