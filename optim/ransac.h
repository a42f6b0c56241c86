// One seeded RANSAC loop over an estimator concept, with an MSAC score, adaptive stopping and a
// final local optimisation on the consensus (Fischler & Bolles 1981; MSAC: Torr & Zisserman
// 2000; LO-RANSAC: Chum, Matas & Kittler 2003). Every robust solve in the project runs this
// loop; what differs between problems is the estimator (docs/extending.md has a worked example).
//
// Data are indexed 0 .. NumData()-1. Per iteration the loop
//   1. draws a minimal sample: distinct data, uniformly, until the estimator says the sample is
//      complete (a fixed size, or "until the sample measures 6 rows"), at most MaxSampleSize();
//   2. asks the minimal solver for 0 .. k hypotheses from it;
//   3. scores each hypothesis with the truncated (MSAC) cost
//        score(model) = sum_d min(cost_d(model), threshold_d),
//      a datum whose cost cannot be evaluated counting its threshold; the inliers of a model are
//      the data with cost_d < threshold_d; the lowest score wins (ties keep the earlier);
//   4. stops once enough samples were drawn to have drawn an all-inlier one with `confidence`:
//        N = log(1 - confidence) / log(1 - w^m),
//      w the best model's inlier ratio and m the largest sample drawn so far.
// Hypotheses given by the caller (e.g. a filter's predicted pose) are scored before sampling.
// At the end the estimator may refine the best model on its inliers (LocalOptimize); the refined
// model replaces it when it has at least as many inliers. The result succeeds when the best model
// has at least MinSampleSize() inliers.
//
// The estimator concept (a class passed by const reference; all indices are datum indices):
//
//   using Model = ...;                       // copyable
//   int NumData() const;
//   int MinSampleSize() const;               // >= 1; also the fewest inliers of a success
//   int MaxSampleSize() const;               // >= MinSampleSize()
//   // Asked once the sample holds MinSampleSize() data or more; a fixed-size estimator returns
//   // true (or derives from FixedSampleSize<N>, which also gives the two sizes above).
//   bool SampleComplete(const int* sample, int count) const;
//   // Appends 0 .. k hypotheses to *models (cleared by the loop).
//   void MinimalSolve(const int* sample, int count, std::vector<Model>* models) const;
//   // The datum's squared cost under `model`; false when it cannot be evaluated there.
//   bool Cost(int datum, const Model& model, double* cost) const;
//   double Threshold(int datum) const;       // inlier threshold on that cost
//   // Optional: refines `model` on `inliers` (sorted datum indices); false leaves it unused.
//   bool LocalOptimize(const std::vector<int>& inliers, Model* model) const;
//   // Optional: draws the sample itself instead of step 1's uniform draw, for problems whose
//   // plausible samples are known (e.g. the candidate line triplets of a primitive
//   // configuration, methods/elqursh_three_line): writes MinSampleSize() .. MaxSampleSize()
//   // datum indices to sample[] and returns their count, or 0 when it has no more samples
//   // (the loop then stops). It draws from the loop's generator, so a seed still fixes the run.
//   int DrawSample(std::mt19937_64& rng, int* sample) const;
//
// Random draws come from the Ransac object's std::mt19937_64, seeded by the caller: one stream
// per solver, reproducible for a seed and the sequence of calls.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <random>
#include <type_traits>
#include <utility>
#include <vector>

#include "common/options.h"

namespace slt {

// The options of a robust solve, one struct for every tracker that runs one (their configs keep
// the flat keys of RansacOptionsSchema: OptionSchema::Flat).
struct RansacOptions {
  int max_iterations = 200;  // samples drawn at most
  double confidence = 0.999;  // of having drawn an all-inlier sample, for adaptive stopping
  std::uint64_t seed = 1;     // the caller's Ransac::Reset(seed) when it starts over
};

inline const OptionSchema<RansacOptions>& RansacOptionsSchema() {
  static const OptionSchema<RansacOptions> schema =
      OptionSchema<RansacOptions>()
          .Field("ransac_max_iterations", &RansacOptions::max_iterations, AtLeast(1), "RANSAC samples at most")
          .Field("ransac_confidence", &RansacOptions::confidence, InRange(0.0, 1.0, "()"),
                 "RANSAC adaptive stopping: probability of an all-inlier sample")
          .Field("seed", &RansacOptions::seed, AnyNumber(), "seed of the RANSAC sampler (reset with the tracker)");
  return schema;
}

template <typename Model>
struct RansacResult {
  bool success = false;
  Model model{};
  std::vector<int> inliers;  // sorted datum indices, inside the threshold at `model`
  double score = std::numeric_limits<double>::infinity();
  int hypotheses = 0;  // models scored (the caller's included)
  int samples = 0;     // minimal samples drawn
};

// Gives a fixed-size estimator its sample sizes and SampleComplete.
template <int N>
struct FixedSampleSize {
  static_assert(N >= 1, "a sample holds at least one datum");
  int MinSampleSize() const { return N; }
  int MaxSampleSize() const { return N; }
  bool SampleComplete(const int*, int) const { return true; }
};

namespace ransac_internal {
template <typename E, typename = void>
struct HasDrawSample : std::false_type {};
template <typename E>
struct HasDrawSample<E, std::void_t<decltype(std::declval<const E&>().DrawSample(std::declval<std::mt19937_64&>(),
                                                                                 std::declval<int*>()))>>
    : std::true_type {};
template <typename E, typename = void>
struct HasLocalOptimize : std::false_type {};
template <typename E>
struct HasLocalOptimize<E, std::void_t<decltype(std::declval<const E&>().LocalOptimize(
                               std::declval<const std::vector<int>&>(), std::declval<typename E::Model*>()))>>
    : std::true_type {};
}  // namespace ransac_internal

template <typename Model>
class Ransac {
 public:
  explicit Ransac(std::uint64_t seed = 1) : rng_(seed) {}
  void Reset(std::uint64_t seed) { rng_.seed(seed); }

  template <typename Estimator>
  void Run(const Estimator& estimator, const RansacOptions& options, const std::vector<Model>& extra_hypotheses,
           RansacResult<Model>* result);

 private:
  // MSAC score of `model`; fills `inliers`.
  template <typename Estimator>
  double Score(const Estimator& estimator, const Model& model, std::vector<int>* inliers) const;

  std::mt19937_64 rng_;
  std::vector<int> sample_;
  std::vector<int> candidate_inliers_;
  std::vector<Model> models_;
};

template <typename Model>
template <typename Estimator>
double Ransac<Model>::Score(const Estimator& estimator, const Model& model, std::vector<int>* inliers) const {
  inliers->clear();
  double score = 0.0;
  const int n = estimator.NumData();
  for (int d = 0; d < n; ++d) {
    double cost;
    const double threshold = estimator.Threshold(d);
    if (!estimator.Cost(d, model, &cost) || !(cost < threshold)) {
      score += threshold;
      continue;
    }
    score += cost;
    inliers->push_back(d);
  }
  return score;
}

template <typename Model>
template <typename Estimator>
void Ransac<Model>::Run(const Estimator& estimator, const RansacOptions& options,
                        const std::vector<Model>& extra_hypotheses, RansacResult<Model>* result) {
  static_assert(std::is_same_v<typename Estimator::Model, Model>, "the estimator's model type");
  result->success = false;
  result->hypotheses = 0;
  result->samples = 0;
  result->inliers.clear();
  result->score = std::numeric_limits<double>::infinity();
  const int n = estimator.NumData();
  const int min_sample = estimator.MinSampleSize();
  const int max_sample = estimator.MaxSampleSize();
  if (n < min_sample) return;

  auto consider = [&](const Model& model) {
    ++result->hypotheses;
    const double score = Score(estimator, model, &candidate_inliers_);
    if (score < result->score) {
      result->score = score;
      result->model = model;
      result->inliers.swap(candidate_inliers_);
    }
  };
  for (const Model& model : extra_hypotheses) consider(model);

  std::uniform_int_distribution<int> pick(0, n - 1);
  int needed = options.max_iterations;
  int largest_sample = min_sample;
  sample_.resize(max_sample);
  for (int iteration = 0; iteration < needed && iteration < options.max_iterations; ++iteration) {
    int count = 0;
    if constexpr (ransac_internal::HasDrawSample<Estimator>::value) {
      count = estimator.DrawSample(rng_, sample_.data());
      if (count == 0) break;  // no more samples
    } else {
      while (count < max_sample && count < n &&
             (count < min_sample || !estimator.SampleComplete(sample_.data(), count))) {
        const int candidate = pick(rng_);
        if (std::find(sample_.begin(), sample_.begin() + count, candidate) != sample_.begin() + count) continue;
        sample_[count++] = candidate;
      }
    }
    ++result->samples;
    largest_sample = std::max(largest_sample, count);
    models_.clear();
    estimator.MinimalSolve(sample_.data(), count, &models_);
    for (const Model& model : models_) consider(model);
    // Adaptive stopping (clamped in double: with many data and one inlier the count exceeds int).
    const double w = static_cast<double>(result->inliers.size()) / n;
    const double p_good = std::pow(w, largest_sample);
    if (p_good >= 1.0 - 1e-12) break;
    if (p_good > 0.0) {
      needed = static_cast<int>(std::min<double>(
          std::ceil(std::log(1.0 - options.confidence) / std::log(1.0 - p_good)), options.max_iterations));
    }
  }
  if (static_cast<int>(result->inliers.size()) < min_sample) return;

  if constexpr (ransac_internal::HasLocalOptimize<Estimator>::value) {
    // Refine on the consensus and re-collect the inliers there; keep the refinement when it
    // explains at least as many data.
    Model refined = result->model;
    if (estimator.LocalOptimize(result->inliers, &refined)) {
      const double score = Score(estimator, refined, &candidate_inliers_);
      if (candidate_inliers_.size() >= result->inliers.size()) {
        result->inliers.swap(candidate_inliers_);
        result->model = refined;
        result->score = score;
      }
    }
  }
  result->success = true;
}

}  // namespace slt
