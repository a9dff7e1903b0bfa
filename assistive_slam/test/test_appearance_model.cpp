// The appearance model (seed 3.2.4) on hand-made word statistics: exact counters, eq. 3.49 weights,
// eq. 3.52 distinctiveness and the posterior of eqs. 3.39/3.48 worked out by hand.
#include <gtest/gtest.h>

#include <cmath>

#include "assistive_slam/appearance_model.h"

using assistive_slam::AppearanceModel;
using assistive_slam::AppearanceParams;
using assistive_slam::HashedGrid;

namespace
{
// one keyframe of 1-D "descriptors" (hashed raw: projection_dims = 0)
cv::Mat desc(std::initializer_list<float> v)
{
  cv::Mat d(static_cast<int>(v.size()), 1, CV_32F);
  int i = 0;
  for (float x : v)
    d.at<float>(i++, 0) = x;
  return d;
}

AppearanceParams rawParams()
{
  AppearanceParams p;
  p.resolutions = {16, 256};
  p.projection_dims = 0;
  p.recent_submaps_excluded = 0;
  p.prior_memory = 0.0;
  p.new_place_prior = 0.2;
  p.word_probability_min = 0.01;
  p.likelihood_exponent = 1.0;
  p.distinctive_min_hits = 2;
  p.max_candidates = 5;
  p.evidence_grids = 2;
  return p;
}

double post(const assistive_slam::AppearanceResult& r, int submap)
{
  for (const auto& p : r.posterior)
    if (p.first == submap)
      return p.second;
  return -1.0;
}
}  // namespace

TEST(HashedGrid, QuantisesByResolution)
{
  HashedGrid g16(16), g32(32);
  EXPECT_EQ(g16.key(desc({0.f})), g16.key(desc({15.9f})));
  EXPECT_NE(g16.key(desc({15.f})), g16.key(desc({17.f})));
  EXPECT_EQ(g32.key(desc({15.f})), g32.key(desc({17.f})));
  EXPECT_NE(g16.key(desc({5.f})), g32.key(desc({5.f})));  // grids never share keys
}

TEST(AppearanceModel, HitAndMissCounters)
{
  AppearanceParams p = rawParams();
  p.resolutions = {16, 32};
  AppearanceModel m(p);
  m.add(0, 7, desc({5.f, 40.f}));
  m.add(1, 7, desc({5.f}));
  m.add(2, 8, desc({40.f, 41.f}));  // one word twice in one keyframe: one hit
  const auto& g16 = m.grids()[0];
  const auto& g32 = m.grids()[1];
  const auto w5 = g16.key(desc({5.f})), w40 = g16.key(desc({40.f}));
  EXPECT_EQ(g16.counts(w5, 7).hits, 2);
  EXPECT_EQ(g16.counts(w5, 7).misses, 0);
  EXPECT_EQ(g16.counts(w40, 7).hits, 1);
  EXPECT_EQ(g16.counts(w40, 7).misses, 1);
  EXPECT_EQ(g16.counts(w40, 8).hits, 1);
  EXPECT_EQ(g16.counts(w40, 8).misses, 0);
  EXPECT_EQ(g16.counts(w5, 8).hits, 0);
  EXPECT_EQ(g32.counts(g32.key(desc({40.f})), 7).hits, 1);  // 40 -> bin 1 of R = 32
  EXPECT_EQ(g16.size(), 2u);
  EXPECT_DOUBLE_EQ(m.wordProbability(0, w40, 7), 0.5);
  EXPECT_DOUBLE_EQ(m.wordProbability(0, w5, 8), 0.01);  // the floor
  EXPECT_EQ(m.submapCount(), 2);
  EXPECT_EQ(m.keyframeCount(), 3);
  // Upsilon proportional to 1/R: (1/16) / (1/16 + 1/32) = 2/3
  EXPECT_NEAR(m.detectorProbability(0), 2.0 / 3.0, 1e-12);
}

TEST(AppearanceModel, PosteriorOnHandMadeWords)
{
  AppearanceModel m(rawParams());
  m.add(0, 1, desc({8.f}));   // submap A: finest word 0
  m.add(1, 2, desc({40.f}));  // submap B: finest word 2, coarsest word 0
  const auto r = m.query(desc({8.f}), 3);
  // The finest grid holding the word is R = 16 (Upsilon 16/17 for every hypothesis): A has hit it
  // (p = 1), B not (floor 0.01). The new place: mean + 1 standard deviation of the two
  // log-likelihoods, which for two values is the larger one (A's).
  // Priors 0.4, 0.4, 0.2: A 0.4*1, B 0.4*0.01, new 0.2*1 -> 0.4 : 0.004 : 0.2.
  EXPECT_NEAR(post(r, 1), 0.4 / 0.604, 1e-9);
  EXPECT_NEAR(post(r, 2), 0.004 / 0.604, 1e-9);
  EXPECT_NEAR(r.new_place_probability, 0.2 / 0.604, 1e-9);
  EXPECT_EQ(r.evidence_features, 1);
  // a feature found only in the coarsest grid is no evidence when evidence_grids = 1
  AppearanceParams p1 = rawParams();
  p1.evidence_grids = 1;
  AppearanceModel m1(p1);
  m1.add(0, 1, desc({8.f}));
  m1.add(1, 2, desc({40.f}));
  const auto r1 = m1.query(desc({100.f}), 3);
  EXPECT_EQ(r1.evidence_features, 0);
  EXPECT_NEAR(post(r1, 1), 0.4, 1e-9);
  EXPECT_NEAR(r1.new_place_probability, 0.2, 1e-9);
  ASSERT_FALSE(r.candidates.empty());
  EXPECT_EQ(r.candidates.front().submap_id, 1);
  EXPECT_EQ(r.candidates.front().keyframe_id, 0);
  EXPECT_EQ(r.discriminative_absent, 0);
}

TEST(AppearanceModel, AbsentDiscriminativeWordPenalisesItsSubmap)
{
  AppearanceModel m(rawParams());
  m.add(0, 1, desc({8.f, 200.f}));  // submap A: words 0 and 12, twice
  m.add(1, 1, desc({8.f, 200.f}));
  m.add(2, 2, desc({8.f}));  // submap B: word 0, twice
  m.add(3, 2, desc({8.f}));
  const auto& g = m.grids()[0];
  EXPECT_DOUBLE_EQ(m.distinctiveness(g.key(desc({200.f}))), 1.0);  // only in A: entropy 0
  EXPECT_NEAR(m.distinctiveness(g.key(desc({8.f}))), 0.0, 1e-12);  // equally in both: maximal entropy
  const auto r = m.query(desc({8.f}), 3);
  // Observed word 0 is equally likely everywhere (A, B: p = 1; new: 4 hits / 4 keyframes). The
  // discriminative word 12 was not seen: delta = misses/(hits+misses) = 0, floored to 0.01;
  // A: (1 - 1) + 0.01 * 1 = 0.01; B never had it: 1; new: mean + 1 std of two = B's.
  // 0.4*0.01 : 0.4 : 0.2
  const double z = 0.004 + 0.4 + 0.2;
  EXPECT_EQ(r.discriminative_absent, 1);
  EXPECT_NEAR(post(r, 1), 0.004 / z, 1e-9);
  EXPECT_NEAR(post(r, 2), 0.4 / z, 1e-9);
  EXPECT_NEAR(r.new_place_probability, 0.2 / z, 1e-9);
}

TEST(AppearanceModel, RecentSubmapsAreNotCandidates)
{
  AppearanceParams p = rawParams();
  p.recent_submaps_excluded = 1;
  AppearanceModel m(p);
  m.add(0, 1, desc({8.f}));
  m.add(1, 2, desc({8.f}));
  const auto r = m.query(desc({8.f}), 2);
  ASSERT_EQ(r.posterior.size(), 1u);
  EXPECT_EQ(r.posterior.front().first, 1);
  AppearanceModel empty(p);
  EXPECT_DOUBLE_EQ(empty.query(desc({8.f}), 0).new_place_probability, 1.0);
}

TEST(AppearanceModel, PriorCarriesThePosteriorToTheNextPlace)
{
  // prior_memory = 1: the previous posterior, each submap's mass split between itself and its
  // neighbours in time. Three submaps with the same words: likelihoods equal, so the posterior
  // equals the prior.
  AppearanceParams p = rawParams();
  p.prior_memory = 1.0;
  AppearanceModel m(p);
  m.add(0, 1, desc({8.f}));
  m.add(1, 2, desc({100.f}));
  m.add(2, 3, desc({200.f}));
  const auto r1 = m.process(3, 9, desc({8.f}));  // mass mostly on submap 1
  const double a = post(r1, 1), b = post(r1, 2), c = post(r1, 3);
  ASSERT_GT(a, 0.5);
  // next query: submap 9 is now stored too
  const auto r2 = m.query(desc({50.f}), 10);  // word seen nowhere at R = 16
  // candidates in time order 1, 2, 3, 9: submap 1 splits its mass in 2 (itself, 2), submaps 2 and
  // 3 in 3; 9 had none. s1 = a/2 + b/3, s2 = a/2 + b/3 + c/3, s3 = b/3 + c/3, s9 = c/3.
  const double s1 = a / 2 + b / 3, s2 = a / 2 + b / 3 + c / 3, s9 = c / 3;
  const double S = a + b + c;
  // likelihoods: every submap has the query's word at R = 256 (none at R = 16): all equal, and so
  // the new place's (mean + 0 std).
  EXPECT_NEAR(post(r2, 1), 0.8 * s1 / S, 1e-9);
  EXPECT_NEAR(post(r2, 2), 0.8 * s2 / S, 1e-9);
  EXPECT_NEAR(post(r2, 9), 0.8 * s9 / S, 1e-9);
  EXPECT_NEAR(r2.new_place_probability, 0.2, 1e-9);
}

TEST(AppearanceModel, BinaryDescriptorsFindTheirKeyframe)
{
  // ORB-like 32-byte descriptors through the default mapping (bits, random projections): a
  // keyframe seen again is found, among two others of unrelated descriptors.
  cv::RNG rng(7);
  std::vector<cv::Mat> kf(3);
  for (auto& d : kf)
  {
    d.create(200, 32, CV_8U);
    rng.fill(d, cv::RNG::UNIFORM, 0, 256);
  }
  AppearanceParams p;
  p.recent_submaps_excluded = 0;
  AppearanceModel m(p);
  for (int i = 0; i < 3; ++i)
    m.add(i, 10 + i, kf[i]);
  const auto r = m.query(kf[1], 99);
  ASSERT_FALSE(r.candidates.empty());
  EXPECT_EQ(r.candidates.front().submap_id, 11);
  EXPECT_EQ(r.candidates.front().keyframe_id, 1);
  EXPECT_GT(r.candidates.front().probability, 0.99);
  EXPECT_EQ(r.evidence_features, 200 * p.projection_tables);
}
