#pragma once
// The seed's loop-closure model (3.2.4, eqs. 3.39-3.52), learned online with no offline vocabulary:
// multi-resolution hashed descriptor grids (R = 16 ... 256) with hit/miss counters per submap,
// detector probability proportional to 1/R, distinctive words by normalised entropy, and recursive
// Bayes over the submaps plus a new-place hypothesis. ROS-free (OpenCV core only).
//
// Descriptors: float rows (OpenCV SIFT, CV_32F, 128 columns). The seed quantised the 128 raw values
// by R; two views of one feature then almost never share a word (on the 84-image real set: the
// right image ranked first for 5 of 44 revisits at R = 16), so by default each descriptor is first
// mapped to RootSIFT and projected on `projection_tables` fixed random orthonormal 8-D bases (from a
// fixed seed: data-independent, nothing trained), standardised into the grids' 0..255 range; the
// grids then quantise those values by R as in the seed. projection_dims = 0 hashes raw values.
// Binary descriptors (ORB, CV_8U) are unpacked to one dimension per bit (L2 = Hamming) instead of
// RootSIFT and projected the same way.
#include <cstdint>
#include <unordered_map>
#include <unordered_set>
#include <utility>
#include <vector>

#include <opencv2/core.hpp>

namespace assistive_slam
{
struct AppearanceParams
{
  /// Bin widths of the grids, finest first (seed: 16, 32, 64, 128, 256 on 0..255 values).
  std::vector<int> resolutions{16, 32, 64, 128, 256};
  /// Descriptor mapping before hashing (see above); projection_dims = 0: hash the raw values.
  int projection_dims = 8;
  int projection_tables = 4;
  double projection_scale = 64.0;  ///< grid units per standard deviation of a projection
  unsigned projection_seed = 20090601u;
  /// Only features whose finest word lies in the first evidence_grids grids count as evidence; a
  /// feature found only coarser is new to every stored submap alike (on the 84-image real set the
  /// R >= 64 words mostly measured how busy an image is, not where it was taken).
  int evidence_grids = 2;
  /// Words of the finest grid with distinctiveness (eq. 3.52) above this are "discriminative".
  double distinctiveness_min = 0.95;
  /// A discriminative word must have been hit at least this often to count as stable.
  int distinctive_min_hits = 2;
  /// Prior mass of the new-place hypothesis at every update.
  double new_place_prior = 0.2;
  /// log p(z | new place) = mean + new_place_std * standard deviation of the candidates' log p(z | M_i).
  double new_place_std = 1.0;
  /// Fraction of the prior carried over from the previous posterior (the recursive part of eq.
  /// 3.39); the rest is spread uniformly over the candidate submaps.
  double prior_memory = 0.5;
  /// Floor of p(word | submap): a word never seen in a submap is unlikely there, not impossible.
  double word_probability_min = 0.01;
  /// Log-likelihoods are scaled by this before normalising (1 = the seed's product of
  /// independent features; < 1 tempers their over-confidence, as the features are not independent:
  /// at 1 the posterior is 0 or 1 and cannot rank candidates; 0.1 on the 84-image real set).
  double likelihood_exponent = 0.1;
  /// The submaps most recently added (the current one included) are not loop candidates: a place
  /// still in view is not a revisit.
  int recent_submaps_excluded = 1;
  /// Candidates returned: at most this many, each with posterior at least candidate_min.
  int max_candidates = 3;
  double candidate_min = 0.0;
};

/// A loop-closure candidate: a stored submap, its keyframe that shares most words with the query,
/// and the submap's posterior probability.
struct LoopCandidate
{
  int submap_id = -1;
  int keyframe_id = -1;
  double probability = 0.0;
};

struct AppearanceResult
{
  double new_place_probability = 1.0;
  std::vector<LoopCandidate> candidates;  ///< best first
  int features = 0;                       ///< descriptors of the query
  int discriminative_absent = 0;          ///< discriminative words not observed (the F^0 set)
  int evidence_features = 0;              ///< observations found in the evidence grids
  /// The posterior of every candidate submap (submap id, probability), in submap order.
  std::vector<std::pair<int, double>> posterior;
};

/// One grid of resolution R: hashed quantised descriptors -> per-submap hit/miss counters.
class HashedGrid
{
public:
  struct Counts
  {
    int hits = 0;
    int misses = 0;
  };
  using Key = std::uint64_t;
  explicit HashedGrid(int resolution) : resolution_(resolution) {}
  int resolution() const { return resolution_; }
  /// The word of a descriptor row at this resolution (quantise each value by R, hash the bins).
  Key key(const cv::Mat& descriptor_row) const;
  /// Counters of one word in one submap (zeros when absent).
  Counts counts(Key word, int submap_id) const;
  bool contains(Key word) const { return words_.count(word) != 0; }
  std::size_t size() const { return words_.size(); }
  void hit(Key word, int submap_id) { ++words_[word][submap_id].hits; }
  void miss(Key word, int submap_id) { ++words_[word][submap_id].misses; }
  /// Every submap with counters for the word.
  const std::unordered_map<int, Counts>* submaps(Key word) const;

private:
  int resolution_;
  std::unordered_map<Key, std::unordered_map<int, Counts>> words_;
};

class AppearanceModel
{
public:
  explicit AppearanceModel(const AppearanceParams& params = AppearanceParams());

  /// Posterior over the stored submaps and the new place for one keyframe's descriptors, without
  /// learning from them. `current_submap` is the submap the keyframe belongs to (excluded with the
  /// other recent ones).
  /// `recent_excluded` >= 0 overrides params().recent_submaps_excluded (relocalisation: 0).
  AppearanceResult query(const cv::Mat& descriptors, int current_submap, int recent_excluded = -1) const;
  /// Learn a keyframe: hits for its words in `submap_id`, misses for the submap's words it lacks.
  void add(int keyframe_id, int submap_id, const cv::Mat& descriptors);
  /// query() then add(); the posterior becomes the next update's prior (eq. 3.39).
  AppearanceResult process(int keyframe_id, int submap_id, const cv::Mat& descriptors);

  const AppearanceParams& params() const { return params_; }
  const std::vector<HashedGrid>& grids() const { return grids_; }
  int submapCount() const { return static_cast<int>(submap_order_.size()); }
  int keyframeCount() const { return keyframes_; }

  /// p(W = 1 | M_i) from the counters: hits / (hits + misses), floored (word_probability_min).
  double wordProbability(std::size_t grid, HashedGrid::Key word, int submap_id) const;
  /// Distinctiveness D (eq. 3.52) of a finest-grid word over the stored submaps; 0 with < 2 submaps.
  double distinctiveness(HashedGrid::Key word) const;
  /// Upsilon of grid g: (1/R_g) / sum_k (1/R_k) (eq. 3.49).
  double detectorProbability(std::size_t grid) const;
  /// words[g][f]: the word of observation f in grid g (projection_tables observations per row).
  std::vector<std::vector<HashedGrid::Key>> words(const cv::Mat& descriptors) const;

private:
  cv::Mat mapDescriptors(const cv::Mat& descriptors) const;
  std::vector<int> candidateSubmaps(int current_submap, int recent_excluded) const;
  std::vector<double> prior(const std::vector<int>& candidates) const;
  // The steps of query(): the log-likelihoods of the candidates (index: submap id -> candidate),
  // each returning how many features / words it counted, then the posterior (best first).
  int addObservedWords(const std::vector<std::vector<HashedGrid::Key>>& w,
                       const std::unordered_map<int, std::size_t>& index, std::vector<double>& loglik) const;
  int addAbsentWords(const std::unordered_set<HashedGrid::Key>& seen, const std::unordered_map<int, std::size_t>& index,
                     std::vector<double>& loglik) const;
  std::vector<std::pair<double, int>> posterior(const std::vector<int>& cand, const std::vector<double>& loglik,
                                                AppearanceResult& res) const;

  AppearanceParams params_;
  std::vector<HashedGrid> grids_;
  std::vector<int> submap_order_;                         ///< submap ids, oldest first
  std::unordered_map<int, std::vector<int>> submap_keyframes_;
  /// finest-grid words of each keyframe (for the best keyframe of a candidate submap)
  std::unordered_map<int, std::vector<HashedGrid::Key>> keyframe_words_;
  std::unordered_map<int, double> prior_;                 ///< last posterior per submap
  /// every word each submap has hit, per grid (for its miss counters)
  std::unordered_map<int, std::vector<std::unordered_set<HashedGrid::Key>>> submap_words_;
  /// finest-grid words hit at least distinctive_min_hits times (the discriminative candidates)
  std::unordered_set<HashedGrid::Key> stable_words_;
  mutable cv::Mat projection_;
  int keyframes_ = 0;
};
}  // namespace assistive_slam
