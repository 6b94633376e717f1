#include "coding/learning_common.h"

#include <pcl_patchdict/core/error.h>

#include <Eigen/Dense>

#include <algorithm>
#include <numeric>
#include <sstream>

namespace pcl {
namespace patchdict {
namespace detail {

void checkTrainingData(const Eigen::MatrixXd& signals, const ObservationMask& mask, int num_atoms, int sparsity)
{
  if (signals.rows() == 0 || signals.cols() == 0)
    throw Error("dictionary learning: no training signals");
  if (!signals.allFinite())
    throw Error("dictionary learning: the training signals contain NaN or Inf");
  if (mask.size() != 0 && (mask.rows() != signals.rows() || mask.cols() != signals.cols()))
    throw Error("dictionary learning: the mask does not match the signals");
  if (num_atoms < 1)
    throw Error("dictionary learning: the number of atoms must be at least 1");
  if (sparsity < 1)
    throw Error("dictionary learning: the sparsity must be at least 1");
}

SparseCodes codeSignals(const Eigen::MatrixXd& dictionary, const Eigen::MatrixXd& signals,
                        const ObservationMask& mask, int sparsity)
{
  const SparseCodingParameters parameters{sparsity, 0.0};
  if (mask.size() == 0) {
    const Eigen::MatrixXd gram = dictionary.transpose() * dictionary;
    return batchOMP(dictionary, gram, signals, parameters);
  }
  return maskedOMP(dictionary, signals, mask, parameters);
}

Eigen::VectorXd observedColumn(const Eigen::MatrixXd& signals, const ObservationMask& mask, Eigen::Index p)
{
  Eigen::VectorXd column = signals.col(p);
  if (mask.size() != 0)
    for (Eigen::Index r = 0; r < column.size(); ++r)
      if (!mask(r, p))
        column[r] = 0.0;
  return column;
}

Eigen::MatrixXd initialAtoms(const Eigen::MatrixXd& signals, const ObservationMask& mask, int num_atoms,
                             std::mt19937_64& rng)
{
  const Eigen::Index n = signals.rows();
  Eigen::MatrixXd atoms(n, num_atoms);
  std::vector<Eigen::Index> order(static_cast<std::size_t>(signals.cols()));
  std::iota(order.begin(), order.end(), 0);
  // Fisher–Yates with our own draws: std::shuffle's sequence is library-specific.
  for (std::size_t i = order.size(); i > 1; --i)
    std::swap(order[i - 1], order[rng() % i]);
  int filled = 0;
  for (const Eigen::Index p : order) {
    if (filled == num_atoms)
      break;
    Eigen::VectorXd candidate = observedColumn(signals, mask, p);
    const double norm = candidate.norm();
    if (!(norm > 1e-12))
      continue;
    candidate /= norm;
    bool distinct = true;
    for (int k = 0; k < filled && distinct; ++k)
      distinct = std::abs(atoms.col(k).dot(candidate)) < 1.0 - 1e-9;
    if (distinct)
      atoms.col(filled++) = candidate;
  }
  std::normal_distribution<double> gaussian;
  for (; filled < num_atoms; ++filled) {
    for (Eigen::Index r = 0; r < n; ++r)
      atoms(r, filled) = gaussian(rng);
    atoms.col(filled).normalize();
  }
  return atoms;
}

std::string generatorText(const std::mt19937_64& rng)
{
  std::ostringstream text;
  text << rng;
  return text.str();
}

std::mt19937_64 generatorFromText(const std::string& text, const std::string& what)
{
  std::mt19937_64 rng;
  std::istringstream in(text);
  in >> rng;
  if (in.fail())
    throw Error(what + ": the saved generator state does not parse");
  return rng;
}

}  // namespace detail
}  // namespace patchdict
}  // namespace pcl
