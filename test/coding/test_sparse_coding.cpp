#include <pcl_patchdict/coding/sparse_coding.h>

#include <gtest/gtest.h>

#include <Eigen/Dense>

#include <algorithm>
#include <random>
#include <set>

using namespace pcl::patchdict;

namespace {

Eigen::MatrixXd randomDictionary(int rows, int atoms, std::mt19937_64& rng)
{
  std::normal_distribution<double> gaussian;
  Eigen::MatrixXd dictionary(rows, atoms);
  for (int k = 0; k < atoms; ++k) {
    for (int r = 0; r < rows; ++r)
      dictionary(r, k) = gaussian(rng);
    dictionary.col(k).normalize();
  }
  return dictionary;
}

// rows × cols standard normal entries drawn from `rng` (column-major order): dense random signals.
Eigen::MatrixXd gaussianSignals(Eigen::Index rows, Eigen::Index cols, std::mt19937_64& rng)
{
  std::normal_distribution<double> gaussian;
  Eigen::MatrixXd signals(rows, cols);
  for (Eigen::Index i = 0; i < signals.size(); ++i)
    signals.data()[i] = gaussian(rng);
  return signals;
}

// Signals with exactly `sparsity` non-zeros each; the supports are returned.
Eigen::MatrixXd sparseSignals(const Eigen::MatrixXd& dictionary, int count, int sparsity, std::mt19937_64& rng,
                              std::vector<std::set<int>>& supports)
{
  std::uniform_int_distribution<int> atom(0, static_cast<int>(dictionary.cols()) - 1);
  std::normal_distribution<double> gaussian;
  Eigen::MatrixXd signals = Eigen::MatrixXd::Zero(dictionary.rows(), count);
  supports.assign(static_cast<std::size_t>(count), {});
  for (int p = 0; p < count; ++p) {
    auto& support = supports[static_cast<std::size_t>(p)];
    while (static_cast<int>(support.size()) < sparsity)
      support.insert(atom(rng));
    for (const int k : support) {
      double c = gaussian(rng);
      c += c >= 0 ? 0.2 : -0.2;  // keep coefficients away from 0, as the classic experiment does
      signals.col(p) += c * dictionary.col(k);
    }
  }
  return signals;
}

}  // namespace

TEST(SparseCoding, NoiseFreeOMPRecoversTheSupport)
{
  std::mt19937_64 rng(11);
  const Eigen::MatrixXd dictionary = randomDictionary(256, 100, rng);
  std::vector<std::set<int>> supports;
  const Eigen::MatrixXd signals = sparseSignals(dictionary, 2000, 5, rng, supports);
  const Eigen::MatrixXd gram = dictionary.transpose() * dictionary;
  const SparseCodes codes = batchOMP(dictionary, gram, signals, {5, 0.0});
  int exact = 0;
  for (int p = 0; p < signals.cols(); ++p) {
    std::set<int> found;
    for (SparseCodes::InnerIterator it(codes, p); it; ++it)
      found.insert(static_cast<int>(it.row()));
    exact += found == supports[static_cast<std::size_t>(p)];
  }
  EXPECT_GE(exact, static_cast<int>(0.99 * signals.cols()));
  const double error = (signals - dictionary * codes).norm() / signals.norm();
  EXPECT_LT(error, 1e-6);
}

TEST(SparseCoding, MatchesAPlainOMPReference)
{
  // Plain OMP with an explicit residual and a least-squares solve, step by step.
  std::mt19937_64 rng(3);
  const Eigen::MatrixXd dictionary = randomDictionary(64, 40, rng);
  std::normal_distribution<double> gaussian;
  Eigen::VectorXd x(64);
  for (int i = 0; i < 64; ++i)
    x[i] = gaussian(rng);
  std::vector<int> reference_support;
  Eigen::VectorXd residual = x, reference_coefficients;
  for (int n = 0; n < 7; ++n) {
    Eigen::Index best;
    (dictionary.transpose() * residual).cwiseAbs().maxCoeff(&best);
    reference_support.push_back(static_cast<int>(best));
    Eigen::MatrixXd chosen(64, reference_support.size());
    for (std::size_t i = 0; i < reference_support.size(); ++i)
      chosen.col(static_cast<Eigen::Index>(i)) = dictionary.col(reference_support[i]);
    reference_coefficients = chosen.colPivHouseholderQr().solve(x);
    residual = x - chosen * reference_coefficients;
  }
  const Eigen::MatrixXd gram = dictionary.transpose() * dictionary;
  std::vector<int> atoms;
  std::vector<double> coefficients;
  batchOMPSingle(gram, dictionary.transpose() * x, x.squaredNorm(), {7, 0.0}, atoms, coefficients);
  ASSERT_EQ(atoms, reference_support);
  for (std::size_t i = 0; i < atoms.size(); ++i)
    EXPECT_NEAR(coefficients[i], reference_coefficients[static_cast<Eigen::Index>(i)], 1e-10);
}

TEST(SparseCoding, ErrorTargetStopsEarly)
{
  std::mt19937_64 rng(5);
  const Eigen::MatrixXd dictionary = randomDictionary(128, 60, rng);
  const Eigen::MatrixXd gram = dictionary.transpose() * dictionary;
  const Eigen::MatrixXd signals = gaussianSignals(128, 200, rng);
  const double target = 0.75 * 128;  // a quarter of the expected energy removed: ~32 of the 60 atoms
  const SparseCodes codes = batchOMP(dictionary, gram, signals, {60, target});
  const Eigen::MatrixXd residual = signals - dictionary * codes;
  int reached = 0;
  for (Eigen::Index p = 0; p < signals.cols(); ++p) {
    const Eigen::Index used = codes.col(p).nonZeros();
    if (used == 0) {  // already within the target: nothing to add
      EXPECT_LE(signals.col(p).squaredNorm(), target);
      continue;
    }
    if (used == 60)  // every atom used: the target may be out of reach
      continue;
    ++reached;
    EXPECT_LE(residual.col(p).squaredNorm(), target * (1 + 1e-9));
    // ... and stopped as soon as the target was reached: one atom fewer would not reach it.
    std::vector<int> atoms;
    std::vector<double> coefficients;
    batchOMPSingle(gram, dictionary.transpose() * signals.col(p), signals.col(p).squaredNorm(),
                   {static_cast<int>(used) - 1, 0.0}, atoms, coefficients);
    Eigen::VectorXd approximation = Eigen::VectorXd::Zero(128);
    for (std::size_t i = 0; i < atoms.size(); ++i)
      approximation += coefficients[i] * dictionary.col(atoms[i]);
    EXPECT_GT((signals.col(p) - approximation).squaredNorm(), target);
  }
  EXPECT_GT(reached, 150);
}

TEST(SparseCoding, MaskedOMPFillsMaskedEntries)
{
  // 30 % of the entries hidden: the error there stays within twice the full-data error.
  std::mt19937_64 rng(21);
  const Eigen::MatrixXd dictionary = randomDictionary(256, 100, rng);
  std::vector<std::set<int>> supports;
  Eigen::MatrixXd clean = sparseSignals(dictionary, 1000, 5, rng, supports);
  std::normal_distribution<double> gaussian;
  Eigen::MatrixXd noisy = clean;
  const double noise = 0.1 * clean.norm() / std::sqrt(static_cast<double>(clean.size()));  // 20 dB
  for (Eigen::Index i = 0; i < noisy.size(); ++i)
    noisy.data()[i] += noise * gaussian(rng);
  std::bernoulli_distribution hidden(0.3);
  Eigen::Matrix<bool, Eigen::Dynamic, Eigen::Dynamic> mask(256, 1000);
  for (Eigen::Index i = 0; i < mask.size(); ++i)
    mask.data()[i] = !hidden(rng);
  const Eigen::MatrixXd gram = dictionary.transpose() * dictionary;
  const Eigen::MatrixXd full = dictionary * batchOMP(dictionary, gram, noisy, {5, 0.0});
  const Eigen::MatrixXd filled = dictionary * maskedOMP(dictionary, noisy, mask, {5, 0.0});
  double full_error = 0.0, masked_error = 0.0;
  std::size_t masked_count = 0;
  for (Eigen::Index i = 0; i < mask.size(); ++i) {
    if (mask.data()[i])
      continue;
    masked_error += std::pow(filled.data()[i] - clean.data()[i], 2);
    full_error += std::pow(full.data()[i] - clean.data()[i], 2);
    ++masked_count;
  }
  EXPECT_GT(masked_count, 0u);
  EXPECT_LE(masked_error, 2.0 * full_error);
  EXPECT_LT(masked_error, 0.05 * clean.squaredNorm() * 0.3);  // far below predicting zeros
}

TEST(SparseCoding, SharedAndPerSignalMasksGiveTheSameCodes)
{
  // The shared-Gram path (many signals, one mask) and the lazy path (one signal) agree, also when
  // some atoms have no energy on the observed rows (they must never be chosen).
  std::mt19937_64 rng(8);
  Eigen::MatrixXd dictionary = randomDictionary(64, 30, rng);
  std::normal_distribution<double> gaussian;
  Eigen::MatrixXd signals(64, 40);
  for (Eigen::Index i = 0; i < signals.size(); ++i)
    signals.data()[i] = gaussian(rng);
  Eigen::Matrix<bool, Eigen::Dynamic, Eigen::Dynamic> mask(64, 40);
  std::bernoulli_distribution hidden(0.4);
  for (Eigen::Index r = 0; r < 64; ++r) {
    const bool value = !hidden(rng);
    mask.row(r).setConstant(value);
  }
  for (const bool blind_atoms : {false, true}) {
    if (blind_atoms)  // atoms 0 … 4 live on the hidden rows only
      for (Eigen::Index k = 0; k < 5; ++k) {
        for (Eigen::Index r = 0; r < 64; ++r)
          dictionary(r, k) = mask(r, 0) ? 0.0 : gaussian(rng);
        dictionary.col(k).normalize();
      }
    const SparseCodes together = maskedOMP(dictionary, signals, mask, {6, 0.0});
    for (Eigen::Index p = 0; p < 40; p += 7) {
      const SparseCodes alone = maskedOMP(dictionary, signals.col(p), mask.col(p), {6, 0.0});
      EXPECT_NEAR((Eigen::MatrixXd(together.col(p)) - Eigen::MatrixXd(alone)).norm(), 0.0, 1e-9) << blind_atoms;
      EXPECT_EQ(together.col(p).nonZeros(), 6) << blind_atoms;
    }
    if (blind_atoms) {
      EXPECT_EQ(Eigen::MatrixXd(together).topRows(5).cwiseAbs().maxCoeff(), 0.0);
    }
  }
}

TEST(SparseCoding, FullMaskEqualsPlainOMP)
{
  std::mt19937_64 rng(9);
  const Eigen::MatrixXd dictionary = randomDictionary(32, 20, rng);
  const Eigen::MatrixXd gram = dictionary.transpose() * dictionary;
  const Eigen::MatrixXd signals = gaussianSignals(32, 10, rng);
  const Eigen::Matrix<bool, Eigen::Dynamic, Eigen::Dynamic> mask =
      Eigen::Matrix<bool, Eigen::Dynamic, Eigen::Dynamic>::Constant(32, 10, true);
  const Eigen::MatrixXd a = batchOMP(dictionary, gram, signals, {4, 0.0});
  const Eigen::MatrixXd b = maskedOMP(dictionary, signals, mask, {4, 0.0});
  EXPECT_NEAR((a - b).norm(), 0.0, 1e-9);
}

TEST(SparseCoding, PerEntryErrorTargetScalesWithTheObservedEntries)
{
  // A per-entry target ε² is the budget ε² × (observed entries) of each signal: the same codes as
  // the absolute target computed signal by signal, for full signals and for masked ones.
  std::mt19937_64 rng(21);
  const Eigen::MatrixXd dictionary = randomDictionary(64, 40, rng);
  const Eigen::MatrixXd gram = dictionary.transpose() * dictionary;
  std::vector<std::set<int>> supports;
  Eigen::MatrixXd signals = sparseSignals(dictionary, 30, 10, rng, supports);
  std::normal_distribution<double> noise(0.0, 0.02);
  for (Eigen::Index i = 0; i < signals.size(); ++i)
    signals.data()[i] += noise(rng);
  Eigen::Matrix<bool, Eigen::Dynamic, Eigen::Dynamic> mask(64, 30);
  std::bernoulli_distribution keep(0.6);
  for (Eigen::Index i = 0; i < mask.size(); ++i)
    mask.data()[i] = keep(rng);
  const double per_entry = 0.02 * 0.02;
  SparseCodingParameters relative;
  relative.max_atoms = 30;
  relative.max_squared_error_per_entry = per_entry;
  const SparseCodes full = batchOMP(dictionary, gram, signals, relative);
  const SparseCodes masked = maskedOMP(dictionary, signals, mask, relative);
  std::size_t differing_budgets = 0;
  for (Eigen::Index p = 0; p < signals.cols(); ++p) {
    SparseCodingParameters absolute;
    absolute.max_atoms = 30;
    absolute.max_squared_error = per_entry * 64;
    const SparseCodes one = batchOMP(dictionary, gram, signals.col(p), absolute);
    EXPECT_LT((Eigen::VectorXd(full.col(p)) - Eigen::VectorXd(one.col(0))).norm(), 1e-9) << p;
    const Eigen::Index observed = mask.col(p).count();
    absolute.max_squared_error = per_entry * static_cast<double>(observed);
    const SparseCodes one_masked = maskedOMP(dictionary, signals.col(p), mask.col(p), absolute);
    EXPECT_LT((Eigen::VectorXd(masked.col(p)) - Eigen::VectorXd(one_masked.col(0))).norm(), 1e-9) << p;
    differing_budgets += observed != 64;
  }
  EXPECT_GT(differing_budgets, 20u);
  // And the budget binds: the masked codes stop earlier than with the full-length budget's
  // per-entry share ignored (absolute ε² × 64 on every signal).
  SparseCodingParameters loose;
  loose.max_atoms = 30;
  loose.max_squared_error = per_entry * 64;
  EXPECT_LT(maskedOMP(dictionary, signals, mask, loose).nonZeros(), masked.nonZeros());
}
