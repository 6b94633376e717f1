// The classic synthetic experiment of Aharon et al. (2006), scaled to our patch size: signals of
// dimension 256 made of 5 atoms of a random 100-atom dictionary, at 20 dB SNR.
#include <pcl_patchdict/coding/dictionary_learning.h>
#include <pcl_patchdict/core/error.h>

#include <gtest/gtest.h>

#include <Eigen/Dense>

#include <random>

using namespace pcl::patchdict;

namespace {

struct Synthetic {
  Eigen::MatrixXd dictionary, clean, noisy;
};

Synthetic makeSynthetic(int count, std::uint64_t seed, double snr_db = 20.0)
{
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> gaussian;
  Synthetic data;
  data.dictionary.resize(256, 100);
  for (Eigen::Index i = 0; i < data.dictionary.size(); ++i)
    data.dictionary.data()[i] = gaussian(rng);
  data.dictionary.colwise().normalize();
  data.clean = Eigen::MatrixXd::Zero(256, count);
  std::uniform_int_distribution<int> atom(0, 99);
  for (int p = 0; p < count; ++p) {
    std::vector<int> chosen;
    while (chosen.size() < 5) {
      const int k = atom(rng);
      if (std::find(chosen.begin(), chosen.end(), k) == chosen.end())
        chosen.push_back(k);
    }
    for (const int k : chosen)
      data.clean.col(p) += gaussian(rng) * data.dictionary.col(k);
  }
  const double noise_sigma =
      std::sqrt(data.clean.squaredNorm() / static_cast<double>(data.clean.size())) * std::pow(10.0, -snr_db / 20.0);
  data.noisy = data.clean;
  for (Eigen::Index i = 0; i < data.noisy.size(); ++i)
    data.noisy.data()[i] += noise_sigma * gaussian(rng);
  return data;
}

// K-SVD settings of an experiment: `atoms` atoms, `sparsity` of them per signal, `iterations`
// sweeps; the seed stays the default unless a test sets it.
KSVDParameters ksvdParameters(int atoms, int sparsity, int iterations)
{
  KSVDParameters parameters;
  parameters.num_atoms = atoms;
  parameters.sparsity = sparsity;
  parameters.iterations = iterations;
  return parameters;
}

// Fraction of true atoms matched by a learned atom with |cos| > 0.99.
double recoveredFraction(const Eigen::MatrixXd& truth, const Eigen::MatrixXd& learned)
{
  const Eigen::MatrixXd cosines = (truth.transpose() * learned).cwiseAbs();
  int found = 0;
  for (Eigen::Index k = 0; k < truth.cols(); ++k)
    found += cosines.row(k).maxCoeff() > 0.99;
  return static_cast<double>(found) / static_cast<double>(truth.cols());
}

}  // namespace

TEST(DictionaryLearning, KSVDRecoversTheGeneratingAtoms)
{
  const Synthetic data = makeSynthetic(4000, 17);
  KSVDParameters parameters = ksvdParameters(100, 5, 50);
  parameters.seed = 2;
  LearningReport report;
  const Eigen::MatrixXd learned = learnKSVD(data.noisy, ObservationMask(), parameters, &report);
  EXPECT_GE(recoveredFraction(data.dictionary, learned), 0.9);
  ASSERT_EQ(report.rmse_per_iteration.size(), 50u);
  EXPECT_LT(report.rmse_per_iteration.back(), 0.5 * report.rmse_per_iteration.front());
  for (Eigen::Index k = 0; k < learned.cols(); ++k)
    EXPECT_NEAR(learned.col(k).norm(), 1.0, 1e-12);
}

TEST(DictionaryLearning, KSVDIsDeterministicForASeed)
{
  const Synthetic data = makeSynthetic(600, 4);
  KSVDParameters parameters = ksvdParameters(40, 4, 5);
  const Eigen::MatrixXd a = learnKSVD(data.noisy, ObservationMask(), parameters);
  const Eigen::MatrixXd b = learnKSVD(data.noisy, ObservationMask(), parameters);
  EXPECT_EQ(a, b);
  parameters.seed = 99;
  EXPECT_NE(a, learnKSVD(data.noisy, ObservationMask(), parameters));
}

TEST(DictionaryLearning, MaskedKSVDLearnsFromDamagedSignals)
{
  // 30 % of every signal unobserved during learning: the atoms are still found.
  const Synthetic data = makeSynthetic(4000, 23);
  std::mt19937_64 rng(5);
  std::bernoulli_distribution hidden(0.3);
  ObservationMask mask(256, 4000);
  for (Eigen::Index i = 0; i < mask.size(); ++i)
    mask.data()[i] = !hidden(rng);
  Eigen::MatrixXd damaged = data.noisy;
  for (Eigen::Index i = 0; i < damaged.size(); ++i)
    if (!mask.data()[i])
      damaged.data()[i] = 1e3;  // garbage where unobserved: it must not leak into the atoms
  const Eigen::MatrixXd learned = learnKSVD(damaged, mask, ksvdParameters(100, 5, 30));
  EXPECT_GE(recoveredFraction(data.dictionary, learned), 0.8);
}

TEST(DictionaryLearning, OnlineLearningRecoversAtomsFromAStream)
{
  const Synthetic data = makeSynthetic(20000, 31);
  OnlineLearningParameters parameters;
  parameters.num_atoms = 100;
  parameters.sparsity = 5;
  parameters.batch_size = 256;
  OnlineDictionaryLearner learner(parameters);
  learner.fit(data.noisy, ObservationMask(), 3);
  EXPECT_EQ(learner.signalsSeen(), 60000u);
  EXPECT_GE(recoveredFraction(data.dictionary, learner.dictionary()), 0.8);
  // An empty batch is refused rather than silently skipped.
  OnlineDictionaryLearner again(parameters);
  EXPECT_THROW(again.update(Eigen::MatrixXd(0, 0)), Error);
}

TEST(DictionaryLearning, RejectsBadInput)
{
  KSVDParameters parameters;
  Eigen::MatrixXd signals = Eigen::MatrixXd::Ones(16, 10);
  parameters.num_atoms = 0;
  EXPECT_THROW(learnKSVD(signals, ObservationMask(), parameters), Error);
  parameters.num_atoms = 4;
  signals(3, 3) = std::nan("");
  EXPECT_THROW(learnKSVD(signals, ObservationMask(), parameters), Error);
  signals(3, 3) = 1.0;
  EXPECT_THROW(learnKSVD(signals, ObservationMask(4, 4), parameters), Error);
  OnlineDictionaryLearner learner({4, 2, 8, 1});
  learner.update(signals);
  EXPECT_THROW(learner.update(Eigen::MatrixXd::Ones(8, 10)), Error);  // another signal size
}
