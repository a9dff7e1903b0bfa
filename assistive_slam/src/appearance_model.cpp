// The seed's online appearance model (3.2.4). See appearance_model.h.
#include "assistive_slam/appearance_model.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <stdexcept>
#include <unordered_set>

namespace assistive_slam
{
namespace
{
constexpr std::uint64_t kFnvOffset = 1469598103934665603ULL;
constexpr std::uint64_t kFnvPrime = 1099511628211ULL;

std::uint64_t fnvMix(std::uint64_t h, std::int64_t v)
{
  for (int b = 0; b < 8; ++b)
  {
    h ^= static_cast<std::uint64_t>((v >> (8 * b)) & 0xff);
    h *= kFnvPrime;
  }
  return h;
}
}  // namespace

// ------------------------------------------------------------------------------ HashedGrid
HashedGrid::Key HashedGrid::key(const cv::Mat& row) const
{
  std::uint64_t h = fnvMix(kFnvOffset, resolution_);
  const int n = row.cols * row.channels();
  for (int k = 0; k < n; ++k)
  {
    const double v = row.depth() == CV_32F ? row.ptr<float>(0)[k] : row.depth() == CV_64F ? row.ptr<double>(0)[k]
                                                                                            : row.ptr<std::uint8_t>(0)[k];
    h = fnvMix(h, static_cast<std::int64_t>(std::floor(v / resolution_)));
  }
  return h;
}

HashedGrid::Counts HashedGrid::counts(Key word, int submap_id) const
{
  const auto* s = submaps(word);
  if (!s)
    return {};
  const auto it = s->find(submap_id);
  return it == s->end() ? Counts{} : it->second;
}

const std::unordered_map<int, HashedGrid::Counts>* HashedGrid::submaps(Key word) const
{
  const auto it = words_.find(word);
  return it == words_.end() ? nullptr : &it->second;
}

// ------------------------------------------------------------------------------ AppearanceModel
AppearanceModel::AppearanceModel(const AppearanceParams& params) : params_(params)
{
  if (params_.resolutions.empty())
    throw std::invalid_argument("AppearanceModel: no grid resolutions");
  for (std::size_t g = 1; g < params_.resolutions.size(); ++g)
    if (params_.resolutions[g] <= params_.resolutions[g - 1])
      throw std::invalid_argument("AppearanceModel: resolutions must grow from the finest to the coarsest");
  for (int r : params_.resolutions)
    grids_.emplace_back(r);
}

cv::Mat AppearanceModel::mapDescriptors(const cv::Mat& descriptors) const
{
  if (descriptors.empty() || params_.projection_dims <= 0)
    return descriptors;
  // binary descriptors (ORB): one dimension per bit, so the L2 distance below is the Hamming distance
  const bool binary = descriptors.depth() == CV_8U;
  cv::Mat d;
  if (binary)
  {
    d.create(descriptors.rows, descriptors.cols * 8, CV_32F);
    for (int i = 0; i < descriptors.rows; ++i)
      for (int c = 0; c < descriptors.cols * 8; ++c)
        d.at<float>(i, c) = static_cast<float>((descriptors.at<std::uint8_t>(i, c / 8) >> (c % 8)) & 1);
  }
  else
    descriptors.convertTo(d, CV_32F);
  const int dims = d.cols;
  if (projection_.empty() || projection_.rows != dims)
  {
    // A fixed random orthonormal basis from a fixed seed: data-independent, so nothing is trained.
    std::mt19937 rng(params_.projection_seed);
    std::normal_distribution<float> n01(0.f, 1.f);
    cv::Mat g(dims, dims, CV_32F);
    for (int r = 0; r < dims; ++r)
      for (int c = 0; c < dims; ++c)
        g.at<float>(r, c) = n01(rng);
    cv::Mat w, u, vt;
    cv::SVD::compute(g, w, u, vt);
    const int k = std::min(dims, params_.projection_dims * std::max(1, params_.projection_tables));
    projection_ = u.colRange(0, k).clone();
  }
  // Float: RootSIFT (L1-normalise, square root: unit L2 norm, Hellinger distance). Binary: bits
  // centred on 0.5, unit L2 norm. Both centred so each projection has about zero mean and standard
  // deviation 1/sqrt(dims).
  cv::Mat r(d.rows, dims, CV_32F);
  const float centre = 1.0f / std::sqrt(static_cast<float>(dims));
  for (int i = 0; i < d.rows; ++i)
  {
    const float* src = d.ptr<float>(i);
    float* dst = r.ptr<float>(i);
    if (binary)
    {
      for (int c = 0; c < dims; ++c)
        dst[c] = (src[c] - 0.5f) * 2.0f * centre;
      continue;
    }
    double l1 = 0.0;
    for (int c = 0; c < dims; ++c)
      l1 += std::abs(src[c]);
    for (int c = 0; c < dims; ++c)
      dst[c] = std::sqrt(std::abs(src[c]) / static_cast<float>(l1 + 1e-12)) - centre;
  }
  cv::Mat y = r * projection_;
  // Standardise (x sqrt(dims)) and put the mean at 128 of the grids' 0..255 range.
  y.convertTo(y, CV_32F, params_.projection_scale * std::sqrt(static_cast<double>(dims)), 128.0);
  return y;
}

std::vector<std::vector<HashedGrid::Key>> AppearanceModel::words(const cv::Mat& descriptors) const
{
  // words[g][f]: the word of observation f in grid g. One descriptor gives projection_tables
  // observations (one per independent projection), as several hash tables do in LSH.
  const cv::Mat y = mapDescriptors(descriptors);
  const int tables = params_.projection_dims > 0 ? std::max(1, params_.projection_tables) : 1;
  const int k = params_.projection_dims > 0 ? params_.projection_dims : y.cols;
  std::vector<std::vector<HashedGrid::Key>> out(grids_.size());
  for (std::size_t g = 0; g < grids_.size(); ++g)
  {
    out[g].reserve(static_cast<std::size_t>(y.rows * tables));
    for (int i = 0; i < y.rows; ++i)
      for (int t = 0; t < tables; ++t)
      {
        const cv::Mat part = y.row(i).colRange(t * k, std::min(y.cols, (t + 1) * k));
        const HashedGrid::Key key = grids_[g].key(part);
        out[g].push_back(t == 0 ? key : fnvMix(key, t));
      }
  }
  return out;
}

double AppearanceModel::detectorProbability(std::size_t grid) const
{
  // Upsilon proportional to 1/R (eq. 3.49), normalised over the grids.
  double s = 0.0;
  for (int r : params_.resolutions)
    s += 1.0 / r;
  return (1.0 / params_.resolutions[grid]) / s;
}

double AppearanceModel::wordProbability(std::size_t grid, HashedGrid::Key word, int submap_id) const
{
  const HashedGrid::Counts c = grids_.at(grid).counts(word, submap_id);
  const double p = c.hits + c.misses > 0 ? static_cast<double>(c.hits) / (c.hits + c.misses) : 0.0;
  return std::max(p, params_.word_probability_min);
}

double AppearanceModel::distinctiveness(HashedGrid::Key word) const
{
  const int n = submapCount();
  if (n < 2)
    return 0.0;
  const auto* s = grids_.front().submaps(word);
  if (!s)
    return 0.0;
  // p(X = M_i): the word's occurrence rates in the submaps, normalised over the submaps
  // (submaps without the word contribute 0 log 0 = 0).
  std::vector<double> p;
  double sum = 0.0;
  for (const auto& kv : *s)
  {
    const auto& c = kv.second;
    const double q = c.hits + c.misses > 0 ? static_cast<double>(c.hits) / (c.hits + c.misses) : 0.0;
    if (q > 0.0)
    {
      p.push_back(q);
      sum += q;
    }
  }
  if (sum <= 0.0)
    return 0.0;
  double h = 0.0;
  for (double q : p)
    h -= (q / sum) * std::log(q / sum);
  const double hmax = std::log(static_cast<double>(n));  // eq. 3.50
  return (hmax - h) / hmax;                               // eq. 3.52
}

std::vector<int> AppearanceModel::candidateSubmaps(int current_submap, int recent_excluded) const
{
  std::vector<int> c;
  const int n = submapCount();
  const int keep = n - std::max(0, recent_excluded >= 0 ? recent_excluded : params_.recent_submaps_excluded);
  for (int i = 0; i < keep; ++i)
    if (submap_order_[i] != current_submap)
      c.push_back(submap_order_[i]);
  return c;
}

std::vector<double> AppearanceModel::prior(const std::vector<int>& candidates) const
{
  // The recursive part of eq. 3.39: the previous posterior, each submap's mass spread over itself
  // and its neighbours in time (the wearer moves on), mixed with a uniform prior; the new place
  // keeps a fixed share.
  const std::size_t n = candidates.size();
  std::vector<double> pr(n, 0.0);
  if (n == 0)
    return pr;
  std::vector<double> carried(n, 0.0);
  double carried_sum = 0.0;
  for (std::size_t i = 0; i < n; ++i)
  {
    for (std::size_t j = (i > 0 ? i - 1 : 0); j <= std::min(n - 1, i + 1); ++j)
    {
      const auto it = prior_.find(candidates[j]);
      if (it == prior_.end())
        continue;
      // a submap's mass goes in equal parts to itself and its (up to two) neighbours
      const std::size_t nb = 1 + (j > 0 ? 1 : 0) + (j + 1 < n ? 1 : 0);
      carried[i] += it->second / static_cast<double>(nb);
    }
    carried_sum += carried[i];
  }
  const double mem = carried_sum > 0.0 ? params_.prior_memory : 0.0;
  for (std::size_t i = 0; i < n; ++i)
    pr[i] = (1.0 - params_.new_place_prior) *
            (mem * (carried_sum > 0.0 ? carried[i] / carried_sum : 0.0) + (1.0 - mem) / static_cast<double>(n));
  return pr;
}

AppearanceResult AppearanceModel::query(const cv::Mat& descriptors, int current_submap, int recent_excluded) const
{
  AppearanceResult res;
  const auto w = words(descriptors);
  const std::size_t nf = w.empty() ? 0 : w.front().size();
  res.features = static_cast<int>(nf);
  const std::vector<int> cand = candidateSubmaps(current_submap, recent_excluded);
  if (cand.empty())
    return res;  // nothing to close a loop with: certainly a new place
  std::unordered_map<int, std::size_t> index;
  for (std::size_t i = 0; i < cand.size(); ++i)
    index[cand[i]] = i;
  std::vector<double> loglik(cand.size(), 0.0);
  res.evidence_features = addObservedWords(w, index, loglik);
  const std::unordered_set<HashedGrid::Key> seen(w.front().begin(), w.front().end());
  res.discriminative_absent = addAbsentWords(seen, index, loglik);
  for (const auto& o : posterior(cand, loglik, res))
  {
    if (static_cast<int>(res.candidates.size()) >= params_.max_candidates || o.first < params_.candidate_min)
      break;
    LoopCandidate c;
    c.submap_id = cand[o.second];
    c.probability = o.first;
    // the submap's keyframe sharing most finest-grid words with the query
    int best = -1;
    for (int kf : submap_keyframes_.at(c.submap_id))
    {
      int shared = 0;
      for (const auto word : keyframe_words_.at(kf))
        shared += seen.count(word) ? 1 : 0;
      if (shared > best)
      {
        best = shared;
        c.keyframe_id = kf;
      }
    }
    res.candidates.push_back(c);
  }
  return res;
}

int AppearanceModel::addObservedWords(const std::vector<std::vector<HashedGrid::Key>>& w,
                                      const std::unordered_map<int, std::size_t>& index,
                                      std::vector<double>& loglik) const
{
  // Observed features (first factor of eq. 3.48). As in the seed, a feature's word is looked up
  // from the finest grid to the coarsest and the search stops at the first grid holding it (the
  // grids are shared by all submaps); that grid gives Upsilon (1/R, eq. 3.49) and each submap's
  // counters in that bin give p(W = 1 | M_i) (floored). A feature found only in the coarse grids
  // (beyond evidence_grids) is a new feature: it weighs the same for every hypothesis and is left out.
  int evidence_features = 0;
  const std::size_t nf = w.empty() ? 0 : w.front().size();
  const std::size_t evidence = std::min<std::size_t>(grids_.size(), static_cast<std::size_t>(std::max(0, params_.evidence_grids)));
  std::vector<int> at_floor(grids_.size(), 0);  // features per grid, counted at the floor for every submap
  for (std::size_t f = 0; f < nf; ++f)
  {
    for (std::size_t g = 0; g < grids_.size(); ++g)
    {
      const auto* s = grids_[g].submaps(w[g][f]);
      if (!s)
        continue;
      if (g >= evidence)
        break;
      ++evidence_features;
      ++at_floor[g];
      for (const auto& kv : *s)
      {
        const auto it = index.find(kv.first);
        if (it == index.end() || kv.second.hits <= 0)
          continue;
        loglik[it->second] += std::log(wordProbability(g, w[g][f], kv.first) / params_.word_probability_min);
      }
      break;
    }
  }
  for (std::size_t g = 0; g < grids_.size(); ++g)
    for (auto& l : loglik)
      l += at_floor[g] * std::log(detectorProbability(g) * params_.word_probability_min);
  return evidence_features;
}

int AppearanceModel::addAbsentWords(const std::unordered_set<HashedGrid::Key>& seen,
                                    const std::unordered_map<int, std::size_t>& index,
                                    std::vector<double>& loglik) const
{
  // Discriminative words not observed (second factor of eq. 3.48, the F^0 set, 3.2.4.3).
  int absent = 0;
  for (const auto word : stable_words_)
  {
    if (seen.count(word) || distinctiveness(word) <= params_.distinctiveness_min)
      continue;
    ++absent;
    const auto* s = grids_.front().submaps(word);
    int hits = 0, misses = 0;
    for (const auto& kv : *s)
    {
      hits += kv.second.hits;
      misses += kv.second.misses;
    }
    // delta: the word's miss probability (its stability), from the miss counters
    const double delta = std::max(static_cast<double>(misses) / std::max(1, hits + misses), params_.word_probability_min);
    for (const auto& kv : *s)
    {
      const auto it = index.find(kv.first);
      if (it == index.end())
        continue;
      const auto& c = kv.second;
      const double p1 = c.hits + c.misses > 0 ? static_cast<double>(c.hits) / (c.hits + c.misses) : 0.0;
      loglik[it->second] += std::log((1.0 - p1) + delta * p1);
    }
  }
  return absent;
}

std::vector<std::pair<double, int>> AppearanceModel::posterior(const std::vector<int>& cand,
                                                               const std::vector<double>& loglik,
                                                               AppearanceResult& res) const
{
  // The new place: the seed leaves its likelihood open. A place never seen looks like a typical
  // stored one, so its log-likelihood is the candidates' mean plus new_place_std standard
  // deviations (RTAB-Map's normalisation of its new-location hypothesis is of the same kind): a
  // submap must stand out from the rest to win over it.
  double mean = 0.0, var = 0.0;
  for (double l : loglik)
    mean += l / static_cast<double>(loglik.size());
  for (double l : loglik)
    var += (l - mean) * (l - mean) / static_cast<double>(loglik.size());
  const double loglik_new = mean + params_.new_place_std * std::sqrt(var);

  // Recursive Bayes (eq. 3.39) with the new-place hypothesis.
  const std::vector<double> pr = prior(cand);
  std::vector<double> lp(cand.size());
  double mx = std::log(params_.new_place_prior) + params_.likelihood_exponent * loglik_new;
  const double lp_new = mx;
  for (std::size_t i = 0; i < cand.size(); ++i)
  {
    lp[i] = std::log(std::max(pr[i], 1e-300)) + params_.likelihood_exponent * loglik[i];
    mx = std::max(mx, lp[i]);
  }
  double z = std::exp(lp_new - mx);
  for (double v : lp)
    z += std::exp(v - mx);
  res.new_place_probability = std::exp(lp_new - mx) / z;
  std::vector<std::pair<double, int>> order;
  for (std::size_t i = 0; i < cand.size(); ++i)
    order.emplace_back(std::exp(lp[i] - mx) / z, static_cast<int>(i));
  std::sort(order.begin(), order.end(), [](const auto& a, const auto& b) { return a.first > b.first; });
  res.posterior.reserve(cand.size());
  for (std::size_t i = 0; i < cand.size(); ++i)
    res.posterior.emplace_back(cand[i], std::exp(lp[i] - mx) / z);
  return order;
}

void AppearanceModel::add(int keyframe_id, int submap_id, const cv::Mat& descriptors)
{
  const auto w = words(descriptors);
  if (!submap_keyframes_.count(submap_id))
    submap_order_.push_back(submap_id);
  submap_keyframes_[submap_id].push_back(keyframe_id);
  ++keyframes_;
  for (std::size_t g = 0; g < grids_.size(); ++g)
  {
    // one hit per word per keyframe (a word seen twice in one image is still one occurrence)
    std::unordered_set<HashedGrid::Key> kf(w[g].begin(), w[g].end());
    for (const auto word : kf)
      grids_[g].hit(word, submap_id);
    // a miss for every word this submap has hit before but this keyframe lacks (the landmark is
    // taken to be in view within its own submap)
    auto& known = submap_words_[submap_id];
    if (known.size() < grids_.size())
      known.resize(grids_.size());
    for (const auto word : known[g])
      if (!kf.count(word))
        grids_[g].miss(word, submap_id);
    for (const auto word : kf)
      known[g].insert(word);
    if (g == 0)
    {
      keyframe_words_[keyframe_id].assign(kf.begin(), kf.end());
      for (const auto word : kf)
      {
        const auto* s = grids_[g].submaps(word);
        int hits = 0;
        for (const auto& kv : *s)
          hits += kv.second.hits;
        if (hits >= params_.distinctive_min_hits)
          stable_words_.insert(word);
      }
    }
  }
}

AppearanceResult AppearanceModel::process(int keyframe_id, int submap_id, const cv::Mat& descriptors)
{
  AppearanceResult r = query(descriptors, submap_id);
  prior_.clear();
  for (const auto& p : r.posterior)
    prior_[p.first] = p.second;
  add(keyframe_id, submap_id, descriptors);
  return r;
}
}  // namespace assistive_slam
