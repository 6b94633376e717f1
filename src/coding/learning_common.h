// Helpers shared by the dictionary learners (private to the library).
#pragma once

#include <pcl_patchdict/coding/dictionary_learning.h>

#include <random>
#include <string>

namespace pcl {
namespace patchdict {
namespace detail {

/** Throws Error unless signals are finite and non-empty and the mask is empty or the same size. */
void checkTrainingData(const Eigen::MatrixXd& signals, const ObservationMask& mask, int num_atoms, int sparsity);

/** Codes with Batch-OMP (no mask) or masked OMP. */
SparseCodes codeSignals(const Eigen::MatrixXd& dictionary, const Eigen::MatrixXd& signals,
                        const ObservationMask& mask, int sparsity);

/** Column p with its unobserved entries zeroed. */
Eigen::VectorXd observedColumn(const Eigen::MatrixXd& signals, const ObservationMask& mask, Eigen::Index p);

/** K unit atoms: distinct signals of non-zero observed energy in seeded random order; Gaussian
  * random atoms if there are not enough such signals. */
Eigen::MatrixXd initialAtoms(const Eigen::MatrixXd& signals, const ObservationMask& mask, int num_atoms,
                             std::mt19937_64& rng);

/** The generator's state in the standard's text form (portable between builds), and back; the
  * latter throws Error "<what>: the saved generator state does not parse". */
std::string generatorText(const std::mt19937_64& rng);
std::mt19937_64 generatorFromText(const std::string& text, const std::string& what);

}  // namespace detail
}  // namespace patchdict
}  // namespace pcl
