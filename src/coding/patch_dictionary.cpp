#include <pcl_patchdict/core/error.h>
#include <pcl_patchdict/coding/patch_dictionary.h>

#include <cmath>

namespace pcl {
namespace patchdict {

namespace {

int gridOf(Eigen::Index rows)
{
  const int grid = static_cast<int>(std::lround(std::sqrt(static_cast<double>(rows))));
  if (rows <= 0 || static_cast<Eigen::Index>(grid) * grid != rows)
    throw Error("patches have " + std::to_string(rows) + " bins, which is not N×N");
  return grid;
}

}  // namespace

double observedRMSE(const Eigen::MatrixXd& estimate, const Eigen::MatrixXd& heights, const ObservationMask& mask)
{
  if (estimate.rows() != heights.rows() || estimate.cols() != heights.cols() ||
      (mask.size() != 0 && (mask.rows() != heights.rows() || mask.cols() != heights.cols())))
    throw Error("observedRMSE: the estimate, the heights and the mask differ in size");
  double squared = 0.0;
  std::size_t count = 0;
  for (Eigen::Index i = 0; i < heights.size(); ++i)
    if (mask.size() == 0 || mask.data()[i]) {
      squared += std::pow(estimate.data()[i] - heights.data()[i], 2);
      ++count;
    }
  return count ? std::sqrt(squared / static_cast<double>(count)) : 0.0;
}

void PatchDictionary::requireAtoms() const
{
  if (empty())
    throw Error("the patch dictionary has no atoms (learn or load it first)");
}

void PatchDictionary::checkPatches(const Eigen::MatrixXd& patches) const
{
  requireAtoms();
  if (patches.rows() != atoms_.rows())
    throw Error("patches have " + std::to_string(patches.rows()) + " bins but the dictionary's atoms have " +
                std::to_string(atoms_.rows()) + " (grid " + std::to_string(grid_size_) + "×" +
                std::to_string(grid_size_) + ")");
  if (!patches.allFinite())
    throw Error("patches contain NaN or Inf heights");
}

Eigen::VectorXd PatchDictionary::patchMeans(const Eigen::MatrixXd& patches, const ObservationMask* mask) const
{
  Eigen::VectorXd means = Eigen::VectorXd::Zero(patches.cols());
  if (!remove_mean_)
    return means;
  for (Eigen::Index p = 0; p < patches.cols(); ++p) {
    double sum = 0.0;
    Eigen::Index count = 0;
    for (Eigen::Index r = 0; r < patches.rows(); ++r)
      if (!mask || (*mask)(r, p)) {
        sum += patches(r, p);
        ++count;
      }
    means[p] = count ? sum / static_cast<double>(count) : 0.0;
  }
  return means;
}

LearningReport PatchDictionary::learn(const Eigen::MatrixXd& patches, const ObservationMask& mask,
                                     const DictionaryLearningOptions& options)
{
  const int grid = gridOf(patches.rows());
  if (options.num_atoms < 1 || options.num_atoms > kMaxAtoms)
    throw Error("the number of atoms must be in [1, " + std::to_string(kMaxAtoms) + "]");
  if (options.sparsity < 1 || options.iterations < 1 || options.batch_size < 1)
    throw Error("sparsity, iterations and batch size must be at least 1");
  const ObservationMask* mask_pointer = mask.size() ? &mask : nullptr;
  Eigen::MatrixXd storage;
  const Eigen::MatrixXd& training = centred(patches, patchMeans(patches, mask_pointer), storage);
  LearningReport report;
  if (options.method == LearningMethod::KSVD) {
    KSVDParameters parameters;
    parameters.num_atoms = options.num_atoms;
    parameters.sparsity = options.sparsity;
    parameters.iterations = options.iterations;
    parameters.seed = options.seed;
    atoms_ = learnKSVD(training, mask, parameters, &report);
  } else {
    OnlineLearningParameters parameters;
    parameters.num_atoms = options.num_atoms;
    parameters.sparsity = options.sparsity;
    parameters.batch_size = options.batch_size;
    parameters.seed = options.seed;
    OnlineDictionaryLearner learner(parameters);
    learner.fit(training, mask, options.iterations);
    atoms_ = learner.dictionary();
  }
  learned_with_ = options;
  learned_with_.num_atoms = static_cast<int>(atoms_.cols());
  grid_size_ = grid;
  gram_ = atoms_.transpose() * atoms_;
  training_patches_ = static_cast<std::uint64_t>(patches.cols());
  return report;
}

void PatchDictionary::setAtoms(const Eigen::MatrixXd& atoms, std::uint64_t training_patches,
                               const DictionaryLearningOptions& learned_with)
{
  gridOf(atoms.rows());
  if (atoms.cols() < 1 || atoms.cols() > kMaxAtoms || !atoms.allFinite())
    throw Error("atoms must be finite, at least one and at most " + std::to_string(kMaxAtoms));
  Eigen::MatrixXd normalised = atoms;
  for (Eigen::Index k = 0; k < normalised.cols(); ++k) {
    const double norm = normalised.col(k).norm();
    if (!(norm > 0.0))
      throw Error("atom " + std::to_string(k) + " is zero");
    normalised.col(k) /= norm;
  }
  setStoredAtoms(normalised, training_patches, learned_with);
}

void PatchDictionary::setStoredAtoms(const Eigen::MatrixXd& atoms, std::uint64_t training_patches,
                                     const DictionaryLearningOptions& learned_with)
{
  const int grid = gridOf(atoms.rows());
  if (grid > kMaxGridSize || atoms.cols() < 1 || atoms.cols() > kMaxAtoms || !atoms.allFinite())
    throw Error("stored atoms must be finite, at most " + std::to_string(kMaxGridSize) + "×" +
                std::to_string(kMaxGridSize) + " bins, at least one and at most " + std::to_string(kMaxAtoms));
  atoms_ = atoms;
  grid_size_ = grid;
  learned_with_ = learned_with;
  learned_with_.num_atoms = static_cast<int>(atoms.cols());
  gram_ = atoms_.transpose() * atoms_;
  training_patches_ = training_patches;
}

PatchCodes PatchDictionary::encode(const Eigen::MatrixXd& patches, const SparseCodingParameters& parameters) const
{
  checkPatches(patches);
  PatchCodes codes;
  codes.means = patchMeans(patches, nullptr);
  Eigen::MatrixXd storage;
  codes.coefficients = batchOMP(atoms_, gram_, centred(patches, codes.means, storage), parameters);
  return codes;
}

PatchCodes PatchDictionary::encodeMasked(const Eigen::MatrixXd& patches, const ObservationMask& mask,
                                         const SparseCodingParameters& parameters) const
{
  checkPatches(patches);
  if (mask.rows() != patches.rows() || mask.cols() != patches.cols())
    throw Error("the mask does not match the patches");
  PatchCodes codes;
  codes.means = patchMeans(patches, &mask);
  Eigen::MatrixXd storage;
  codes.coefficients = maskedOMP(atoms_, centred(patches, codes.means, storage), mask, parameters);
  return codes;
}

const Eigen::MatrixXd& PatchDictionary::centred(const Eigen::MatrixXd& patches, const Eigen::VectorXd& means,
                                                Eigen::MatrixXd& storage) const
{
  if (!remove_mean_)
    return patches;  // no copy: the training set can be as large as memory allows
  storage = patches;
  storage.rowwise() -= means.transpose();
  return storage;
}

Eigen::MatrixXd PatchDictionary::decode(const PatchCodes& codes) const
{
  requireAtoms();
  if (codes.coefficients.rows() != atoms_.cols())
    throw Error("codes refer to " + std::to_string(codes.coefficients.rows()) + " atoms, the dictionary has " +
                std::to_string(atoms_.cols()));
  Eigen::MatrixXd patches = atoms_ * codes.coefficients;
  if (codes.means.size() == patches.cols())
    patches.rowwise() += codes.means.transpose();
  return patches;
}

std::uint64_t PatchDictionary::fingerprint() const
{
  requireAtoms();
  std::uint64_t hash = fnv1a64(atoms_.data(), sizeof(double) * static_cast<std::size_t>(atoms_.size()));
  const std::uint8_t mean_flag = remove_mean_ ? 1 : 0;
  return fnv1a64(&mean_flag, 1, hash);
}

}  // namespace patchdict
}  // namespace pcl
