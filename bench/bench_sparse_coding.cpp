// Benchmarks of the sparse coders and dictionary learners.
//
// Coding: Batch-OMP (Rubinstein, Zibulevsky & Elad 2008) of 10 000 random Gaussian signals of
// n = 256 values over random Gaussian unit-norm dictionaries, K = 100 and 500 atoms, S = 5 and 20
// atoms per signal, and masked OMP (K = 100, S = 8) with 30 % of every signal hidden — once with a
// different mask per signal (the lazy-Gram path) and once with one mask shared by all signals (the
// shared masked-Gram path). Items/s are patches per second. The Gram matrix DᵀD is computed once
// per dictionary outside the timing (batchOMP takes it precomputed); Dᵀx is inside.
// Coding runs on 1 OpenMP thread (the per-core cost) unless the name says threads:2.
//
// Learning: K-SVD and online learning (Mairal et al. 2009) of 100 atoms from 50 000 synthetic
// signals (8-sparse combinations of a random 100-atom dictionary + Gaussian noise), sparsity 8,
// 20 K-SVD iterations, batch 512 for the online learner; wall seconds of one run, on 1 and on 2
// OpenMP threads. Counters: `recovered` = fraction of the generating atoms matched by a learned
// atom with |cos| > 0.99 (a sanity check that the run learned something), `rmse` = K-SVD's
// representation RMSE at its last coding step (the noise alone gives 0.01).
//
// All data is seeded. Repeat with --benchmark_repetitions=3 on a loaded machine and take the best.
#include <pcl_patchdict/coding/dictionary_learning.h>
#include <pcl_patchdict/coding/sparse_coding.h>

#include <benchmark/benchmark.h>

#include <Eigen/Core>

#include <omp.h>

#include <algorithm>
#include <cstdint>
#include <map>
#include <numeric>
#include <random>
#include <vector>

namespace {

using pcl::patchdict::ObservationMask;
using pcl::patchdict::SparseCodes;
using pcl::patchdict::SparseCodingParameters;

constexpr Eigen::Index kDimension = 256;        // 16 × 16 height-map patches
constexpr Eigen::Index kCodingSignals = 10000;
constexpr Eigen::Index kLearningSignals = 50000;
constexpr int kLearningAtoms = 100;
constexpr int kLearningSparsity = 8;
constexpr double kHiddenFraction = 0.3;

Eigen::MatrixXd gaussianMatrix(Eigen::Index rows, Eigen::Index cols, std::uint64_t seed)
{
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> gaussian;
  Eigen::MatrixXd m(rows, cols);
  for (Eigen::Index j = 0; j < cols; ++j)
    for (Eigen::Index i = 0; i < rows; ++i)
      m(i, j) = gaussian(rng);
  return m;
}

Eigen::MatrixXd unitDictionary(Eigen::Index atoms, std::uint64_t seed)
{
  Eigen::MatrixXd d = gaussianMatrix(kDimension, atoms, seed);
  d.colwise().normalize();
  return d;
}

// Function-local statics: each data set is generated once, outside any timing, and only if a
// benchmark that needs it is selected by --benchmark_filter.
const Eigen::MatrixXd& codingDictionary(int atoms)
{
  static std::map<int, Eigen::MatrixXd> cache;
  auto it = cache.find(atoms);
  if (it == cache.end())
    it = cache.emplace(atoms, unitDictionary(atoms, 1000 + static_cast<std::uint64_t>(atoms))).first;
  return it->second;
}

const Eigen::MatrixXd& codingSignals()
{
  static const Eigen::MatrixXd signals = gaussianMatrix(kDimension, kCodingSignals, 7);
  return signals;
}

// Exactly round(30 % · n) hidden entries per signal, chosen at random (partial Fisher–Yates).
ObservationMask randomMask(std::mt19937_64& rng)
{
  const auto hidden = static_cast<Eigen::Index>(kHiddenFraction * static_cast<double>(kDimension) + 0.5);
  std::vector<Eigen::Index> rows(static_cast<std::size_t>(kDimension));
  std::iota(rows.begin(), rows.end(), 0);
  ObservationMask mask = ObservationMask::Constant(kDimension, 1, true);
  for (Eigen::Index i = 0; i < hidden; ++i) {
    const auto pick = i + static_cast<Eigen::Index>(rng() % static_cast<std::uint64_t>(kDimension - i));
    std::swap(rows[static_cast<std::size_t>(i)], rows[static_cast<std::size_t>(pick)]);
    mask(rows[static_cast<std::size_t>(i)], 0) = false;
  }
  return mask;
}

const ObservationMask& perSignalMasks()
{
  static const ObservationMask masks = [] {
    std::mt19937_64 rng(11);
    ObservationMask m(kDimension, kCodingSignals);
    for (Eigen::Index p = 0; p < kCodingSignals; ++p)
      m.col(p) = randomMask(rng);
    return m;
  }();
  return masks;
}

const ObservationMask& sharedMask()
{
  static const ObservationMask masks = [] {
    std::mt19937_64 rng(13);
    return ObservationMask(randomMask(rng).replicate(1, kCodingSignals));
  }();
  return masks;
}

struct LearningData {
  Eigen::MatrixXd generator;  // the 100 atoms the signals are made of
  Eigen::MatrixXd signals;
};

// Sparse combinations of a random dictionary: learning has a ground truth to find, so the
// `recovered` counter tells a fast-but-broken learner from a working one.
const LearningData& learningData()
{
  static const LearningData data = [] {
    LearningData d;
    d.generator = unitDictionary(kLearningAtoms, 21);
    d.signals = 0.01 * gaussianMatrix(kDimension, kLearningSignals, 22);  // noise, SNR ≈ 25 dB
    std::mt19937_64 rng(23);
    std::normal_distribution<double> gaussian;
    std::vector<int> atoms(kLearningAtoms);
    std::iota(atoms.begin(), atoms.end(), 0);
    for (Eigen::Index p = 0; p < kLearningSignals; ++p) {
      for (int i = 0; i < kLearningSparsity; ++i) {  // 8 distinct atoms per signal
        std::swap(atoms[static_cast<std::size_t>(i)],
                  atoms[static_cast<std::size_t>(i + static_cast<int>(rng() % (kLearningAtoms - i)))]);
        d.signals.col(p) += gaussian(rng) * d.generator.col(atoms[static_cast<std::size_t>(i)]);
      }
    }
    return d;
  }();
  return data;
}

double recoveredFraction(const Eigen::MatrixXd& generator, const Eigen::MatrixXd& learned)
{
  const Eigen::MatrixXd similarity = (generator.transpose() * learned).cwiseAbs();
  Eigen::Index found = 0;
  for (Eigen::Index k = 0; k < similarity.rows(); ++k)
    found += similarity.row(k).maxCoeff() > 0.99 ? 1 : 0;
  return static_cast<double>(found) / static_cast<double>(similarity.rows());
}

// Sets the OpenMP thread count for one benchmark and restores it afterwards, so that the order
// in which benchmarks run does not matter.
class ThreadScope {
public:
  explicit ThreadScope(int threads) : saved_(omp_get_max_threads()) { omp_set_num_threads(threads); }
  ~ThreadScope() { omp_set_num_threads(saved_); }
  ThreadScope(const ThreadScope&) = delete;
  ThreadScope& operator=(const ThreadScope&) = delete;

private:
  int saved_;
};

// ---------------------------------------------------------------- coding

// Args: K (atoms), S (atoms per signal), OpenMP threads.
void BM_BatchOMP(benchmark::State& state)
{
  const int atoms = static_cast<int>(state.range(0));
  const SparseCodingParameters parameters{static_cast<int>(state.range(1)), 0.0};
  const ThreadScope threads(static_cast<int>(state.range(2)));
  const Eigen::MatrixXd& dictionary = codingDictionary(atoms);
  const Eigen::MatrixXd gram = dictionary.transpose() * dictionary;
  const Eigen::MatrixXd& signals = codingSignals();
  for (auto _ : state) {
    const SparseCodes codes = pcl::patchdict::batchOMP(dictionary, gram, signals, parameters);
    benchmark::DoNotOptimize(codes.valuePtr());
  }
  state.SetItemsProcessed(state.iterations() * signals.cols());
}
BENCHMARK(BM_BatchOMP)
    ->ArgNames({"K", "S", "threads"})
    ->Args({100, 5, 1})
    ->Args({100, 20, 1})
    ->Args({500, 5, 1})
    ->Args({500, 20, 1})
    ->Args({500, 20, 2})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

// Args: shared mask (0: a different mask per signal, 1: one mask for all), OpenMP threads.
void BM_MaskedOMP(benchmark::State& state)
{
  const bool shared = state.range(0) != 0;
  const ThreadScope threads(static_cast<int>(state.range(1)));
  const SparseCodingParameters parameters{8, 0.0};
  const Eigen::MatrixXd& dictionary = codingDictionary(100);
  const Eigen::MatrixXd& signals = codingSignals();
  const ObservationMask& mask = shared ? sharedMask() : perSignalMasks();
  for (auto _ : state) {
    const SparseCodes codes = pcl::patchdict::maskedOMP(dictionary, signals, mask, parameters);
    benchmark::DoNotOptimize(codes.valuePtr());
  }
  state.SetItemsProcessed(state.iterations() * signals.cols());
}
// The 2-thread rows show whether each path scales across cores.
BENCHMARK(BM_MaskedOMP)
    ->ArgNames({"shared", "threads"})
    ->Args({0, 1})
    ->Args({1, 1})
    ->Args({0, 2})
    ->Args({1, 2})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

// ---------------------------------------------------------------- learning

// Arg: OpenMP threads.
void BM_LearnKSVD(benchmark::State& state)
{
  const ThreadScope threads(static_cast<int>(state.range(0)));
  const LearningData& data = learningData();
  pcl::patchdict::KSVDParameters parameters;  // 20 iterations by default
  parameters.num_atoms = kLearningAtoms;
  parameters.sparsity = kLearningSparsity;
  Eigen::MatrixXd dictionary;
  pcl::patchdict::LearningReport report;
  for (auto _ : state) {
    dictionary = pcl::patchdict::learnKSVD(data.signals, ObservationMask(), parameters, &report);
    benchmark::DoNotOptimize(dictionary.data());
  }
  state.counters["ksvd_iterations"] = parameters.iterations;
  state.counters["rmse"] = report.rmse_per_iteration.empty() ? 0.0 : report.rmse_per_iteration.back();
  state.counters["recovered"] = recoveredFraction(data.generator, dictionary);
  state.SetItemsProcessed(state.iterations() * data.signals.cols());
}
BENCHMARK(BM_LearnKSVD)
    ->ArgName("threads")
    ->Arg(1)
    ->Arg(2)
    ->Unit(benchmark::kSecond)
    ->Iterations(1)
    ->UseRealTime();

// Args: epochs, OpenMP threads.
void BM_OnlineLearning(benchmark::State& state)
{
  const ThreadScope threads(static_cast<int>(state.range(1)));
  const LearningData& data = learningData();
  const int epochs = static_cast<int>(state.range(0));
  pcl::patchdict::OnlineLearningParameters parameters;
  parameters.num_atoms = kLearningAtoms;
  parameters.sparsity = kLearningSparsity;
  parameters.batch_size = 512;
  Eigen::MatrixXd dictionary;
  for (auto _ : state) {
    pcl::patchdict::OnlineDictionaryLearner learner(parameters);
    learner.fit(data.signals, ObservationMask(), epochs);
    dictionary = learner.dictionary();
    benchmark::DoNotOptimize(dictionary.data());
  }
  state.counters["recovered"] = recoveredFraction(data.generator, dictionary);
  state.SetItemsProcessed(state.iterations() * epochs * data.signals.cols());
}
BENCHMARK(BM_OnlineLearning)
    ->ArgNames({"epochs", "threads"})
    ->Args({1, 1})
    ->Args({3, 1})
    ->Args({1, 2})
    ->Args({3, 2})
    ->Unit(benchmark::kSecond)
    ->Iterations(1)
    ->UseRealTime();

}  // namespace
