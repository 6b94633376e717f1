// PatchDictionary — a learned dictionary of N×N height-map atoms (section 4 of Sarkar et al. 2017):
// learn it (K-SVD or online), code patches with Batch-OMP or masked OMP, decode (its .pdd file:
// io/patch_dictionary_io.h).
#pragma once

#include <pcl_patchdict/core/checksum.h>  // fnv1a64, declared here before
#include <pcl_patchdict/coding/dictionary_learning.h>
#include <pcl_patchdict/coding/sparse_coding.h>

#include <Eigen/Core>

#include <cstdint>
#include <memory>
#include <string>

namespace pcl {
namespace patchdict {

/** Sparse codes of a set of patches, with the per-patch mean height when the dictionary removes it. */
struct PatchCodes {
  SparseCodes coefficients;  ///< K × P
  Eigen::VectorXd means;     ///< P (zeros when the dictionary keeps the mean in the atoms)
};

enum class LearningMethod : std::uint32_t { KSVD = 0, Online = 1 };

/** \brief How a dictionary is learned: options of the learning, not part of the dictionary it makes
  * (PatchDictionary::learn). Defaults: 100 atoms, sparsity 8, 20 K-SVD iterations, batch 512,
  * seed 1. */
struct DictionaryLearningOptions {
  int num_atoms = 100;
  int sparsity = 8;     ///< atoms per patch while learning
  int iterations = 20;  ///< K-SVD iterations; with LearningMethod::Online, passes over the data
  int batch_size = 512; ///< LearningMethod::Online: patches per mini-batch
  LearningMethod method = LearningMethod::KSVD;
  std::uint64_t seed = 1;
};

/** \brief A dictionary of patch atoms — a value: the atoms (N² × K, unit columns), whether codes are
  * of patches less their mean, and the fingerprint of both — with coding and decoding (its .pdd
  * file: io/patch_dictionary_io.h). How it was learned is not part of it beyond what the .pdd file records
  * (learnedWith()). */
class PatchDictionary {
public:
  using Ptr = std::shared_ptr<PatchDictionary>;
  using ConstPtr = std::shared_ptr<const PatchDictionary>;

  static constexpr int kMaxAtoms = 1 << 16;  ///< most atoms a dictionary holds
  static constexpr int kMaxGridSize = 256;   ///< largest N of its N×N atoms

  PatchDictionary() = default;

  /** Subtract each patch's mean observed height before coding (and learning) and add it back on
    * decoding (default: the mean is kept). Part of the dictionary: it changes its codes and its
    * fingerprint. */
  void setRemoveMean(bool remove_mean) { remove_mean_ = remove_mean; }
  bool getRemoveMean() const { return remove_mean_; }

  /** \brief Learns the atoms from patches (N² × P, one column per patch, N² a square), replacing
    * any it had. Unobserved bins (mask false; an empty mask: all observed) are ignored. Throws
    * Error for bad sizes or options. */
  LearningReport learn(const Eigen::MatrixXd& patches, const ObservationMask& mask,
                       const DictionaryLearningOptions& options = DictionaryLearningOptions());
  /** The same with every bin observed. */
  LearningReport learn(const Eigen::MatrixXd& patches,
                       const DictionaryLearningOptions& options = DictionaryLearningOptions())
  {
    return learn(patches, ObservationMask(), options);
  }

  /** Uses the given atoms (N² × K, normalised here) instead of learning them; `training_patches`
    * and `learned_with` are what the .pdd file records as their origin (e.g. an
    * OnlineDictionaryLearner's patch count and options). */
  void setAtoms(const Eigen::MatrixXd& atoms, std::uint64_t training_patches = 0,
                const DictionaryLearningOptions& learned_with = DictionaryLearningOptions());

  /** The same with the atoms taken bit for bit, not normalised again: a dictionary as its .pdd file
    * stores it (io/patch_dictionary_io.h). Throws Error for atoms that are not finite, not N² × K with
    * N ≤ kMaxGridSize, or more than kMaxAtoms. */
  void setStoredAtoms(const Eigen::MatrixXd& atoms, std::uint64_t training_patches,
                      const DictionaryLearningOptions& learned_with);

  /** Sparse codes of fully observed patches (Batch-OMP). */
  PatchCodes encode(const Eigen::MatrixXd& patches, const SparseCodingParameters& parameters) const;
  /** Sparse codes from the observed bins only (masked OMP); decode() then fills every bin. */
  PatchCodes encodeMasked(const Eigen::MatrixXd& patches, const ObservationMask& mask,
                          const SparseCodingParameters& parameters) const;
  /** D·codes (+ means): the patches the codes describe. */
  Eigen::MatrixXd decode(const PatchCodes& codes) const;

  bool empty() const { return atoms_.size() == 0; }
  int gridSize() const { return grid_size_; }
  int numAtoms() const { return static_cast<int>(atoms_.cols()); }
  const Eigen::MatrixXd& atoms() const { return atoms_; }
  const Eigen::MatrixXd& gram() const { return gram_; }
  /** Number of patches the atoms were learned from (0 if set directly). */
  std::uint64_t trainingPatches() const { return training_patches_; }
  /** The options the atoms were learned with (learn, setAtoms); num_atoms is the atoms' count. A
    * .pdd file records the method, sparsity, iterations and seed: after load, batch_size is its
    * default. */
  const DictionaryLearningOptions& learnedWith() const { return learned_with_; }
  /** 64-bit fingerprint of the atoms and the mean option: what a compressed file records to
    * refuse decoding with another dictionary. */
  std::uint64_t fingerprint() const;

private:
  void requireAtoms() const;
  void checkPatches(const Eigen::MatrixXd& patches) const;
  Eigen::VectorXd patchMeans(const Eigen::MatrixXd& patches, const ObservationMask* mask) const;
  /** The patches less their means (built in `storage`) when the mean is removed, else the
    * patches themselves, uncopied. */
  const Eigen::MatrixXd& centred(const Eigen::MatrixXd& patches, const Eigen::VectorXd& means,
                                 Eigen::MatrixXd& storage) const;

  DictionaryLearningOptions learned_with_;
  bool remove_mean_ = false;

  int grid_size_ = 0;
  std::uint64_t training_patches_ = 0;
  Eigen::MatrixXd atoms_;  // N² × K, unit columns
  Eigen::MatrixXd gram_;   // atomsᵀ · atoms
};

/** RMS of estimate − heights over the entries `mask` marks observed (all entries for an empty
  * mask); 0 when nothing is observed. How well codes describe the surface they were fitted to. */
double observedRMSE(const Eigen::MatrixXd& estimate, const Eigen::MatrixXd& heights,
                    const ObservationMask& mask = ObservationMask());

}  // namespace patchdict
}  // namespace pcl
