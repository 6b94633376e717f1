#include "core/binary_format.h"
#include "core/byte_stream.h"

#include <pcl_patchdict/core/checksum.h>
#include <pcl_patchdict/io/atomic_file.h>
#include <pcl_patchdict/core/error.h>
#include <pcl_patchdict/coding/patch_dictionary.h>
#include <pcl_patchdict/io/png_writer.h>

#include <cmath>
#include <cstring>

namespace pcl {
namespace patchdict {

namespace {

// .pdd layout (little-endian): header, atoms as float64 column-major, then FNV-1a 64 of all before.
constexpr char kMagic[8] = {'P', 'C', 'L', 'P', 'D', 'D', '\0', '\x1a'};
constexpr std::uint32_t kVersion = 1;
constexpr int kMaxGrid = 256;
constexpr int kMaxAtoms = 1 << 16;

// The header: magic (8 bytes); version, grid size, atom count, flags (bit 0: remove mean), method,
// sparsity, iterations, reserved (u32 each); seed, training patches (u64 each).
constexpr std::size_t kHeaderBytes = 56;

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
  const int grid = gridOf(atoms.rows());
  if (atoms.cols() < 1 || atoms.cols() > kMaxAtoms || !atoms.allFinite())
    throw Error("atoms must be finite, at least one and at most " + std::to_string(kMaxAtoms));
  Eigen::MatrixXd normalised = atoms;
  for (Eigen::Index k = 0; k < normalised.cols(); ++k) {
    const double norm = normalised.col(k).norm();
    if (!(norm > 0.0))
      throw Error("atom " + std::to_string(k) + " is zero");
    normalised.col(k) /= norm;
  }
  atoms_ = normalised;
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

void PatchDictionary::save(const std::string& path) const
{
  requireAtoms();
  if (!detail::isLittleEndian())
    throw Error("writing .pdd files needs a little-endian machine");
  detail::ByteWriter out;
  out.putRaw(kMagic, sizeof kMagic);
  for (const std::uint32_t field :
       {kVersion, static_cast<std::uint32_t>(grid_size_), static_cast<std::uint32_t>(atoms_.cols()),
        remove_mean_ ? 1u : 0u, static_cast<std::uint32_t>(learned_with_.method),
        static_cast<std::uint32_t>(learned_with_.sparsity), static_cast<std::uint32_t>(learned_with_.iterations), 0u})
    out.putU32(field);
  out.putU64(learned_with_.seed);
  out.putU64(training_patches_);
  out.putRaw(atoms_.data(), sizeof(double) * static_cast<std::size_t>(atoms_.size()));
  out.putU64(fnv1a64(out.bytes().data(), out.bytes().size()));
  writeFileAtomically(path, out.bytes());
}

PatchDictionary::Ptr PatchDictionary::load(const std::string& path, int expected_grid_size)
{
  return fromBytes(readWholeFile(path), expected_grid_size, path);
}

PatchDictionary::Ptr PatchDictionary::fromBytes(const std::string& bytes, int expected_grid_size,
                                                const std::string& name)
{
  if (!detail::isLittleEndian())
    throw Error("reading .pdd files needs a little-endian machine");
  const std::string where = "cannot read dictionary '" + name + "': ";
  if (bytes.size() < kHeaderBytes + sizeof(std::uint64_t)) {
    if (bytes.size() >= sizeof kMagic && std::memcmp(bytes.data(), kMagic, sizeof kMagic) != 0)
      throw Error(where + "not a .pdd file");
    throw Error(where + "file is truncated (" + std::to_string(bytes.size()) + " bytes)");
  }
  detail::ByteReader in(bytes.data(), bytes.size(), where);
  char magic[sizeof kMagic];
  in.getRaw(magic, sizeof magic);
  if (std::memcmp(magic, kMagic, sizeof kMagic) != 0)
    throw Error(where + "not a .pdd file");
  struct {
    std::uint32_t version, grid_size, num_atoms, flags, method, sparsity, iterations, reserved;
    std::uint64_t seed, training_patches;
  } header;
  for (std::uint32_t* field : {&header.version, &header.grid_size, &header.num_atoms, &header.flags, &header.method,
                               &header.sparsity, &header.iterations, &header.reserved})
    *field = in.getU32();
  header.seed = in.getU64();
  header.training_patches = in.getU64();
  if (header.version != kVersion)
    throw Error(where + "format version " + std::to_string(header.version) + " (this build reads version " +
                std::to_string(kVersion) + ")");
  if (header.grid_size < 1 || header.grid_size > kMaxGrid || header.num_atoms < 1 || header.num_atoms > kMaxAtoms ||
      header.method > 1 || (header.flags & ~1u) != 0)
    throw Error(where + "implausible header (grid " + std::to_string(header.grid_size) + ", atoms " +
                std::to_string(header.num_atoms) + ")");
  const std::size_t rows = static_cast<std::size_t>(header.grid_size) * header.grid_size;
  const std::size_t expected = kHeaderBytes + sizeof(double) * rows * header.num_atoms + sizeof(std::uint64_t);
  if (bytes.size() < expected)
    throw Error(where + "file is truncated (" + std::to_string(bytes.size()) + " of " + std::to_string(expected) +
                " bytes)");
  if (bytes.size() > expected)
    throw Error(where + std::to_string(bytes.size() - expected) + " unexpected bytes after the atoms");
  const std::uint64_t stored = detail::ByteReader(bytes.data() + expected - 8, 8, where).getU64();
  if (fnv1a64(bytes.data(), expected - sizeof stored) != stored)
    throw Error(where + "checksum mismatch (the file is corrupted)");
  if (expected_grid_size > 0 && static_cast<int>(header.grid_size) != expected_grid_size)
    throw Error(where + "its atoms are " + std::to_string(header.grid_size) + "×" + std::to_string(header.grid_size) +
                " patches, but " + std::to_string(expected_grid_size) + "×" + std::to_string(expected_grid_size) +
                " are needed");
  auto dictionary = std::make_shared<PatchDictionary>();
  Eigen::MatrixXd atoms(static_cast<Eigen::Index>(rows), static_cast<Eigen::Index>(header.num_atoms));
  in.getRaw(atoms.data(), sizeof(double) * rows * header.num_atoms);
  if (!atoms.allFinite())
    throw Error(where + "atoms contain NaN or Inf");
  dictionary->atoms_ = atoms;
  dictionary->grid_size_ = static_cast<int>(header.grid_size);
  dictionary->learned_with_.num_atoms = static_cast<int>(header.num_atoms);
  dictionary->remove_mean_ = (header.flags & 1u) != 0;
  dictionary->learned_with_.method = static_cast<LearningMethod>(header.method);
  dictionary->learned_with_.sparsity = static_cast<int>(header.sparsity);
  dictionary->learned_with_.iterations = static_cast<int>(header.iterations);
  dictionary->learned_with_.seed = header.seed;
  dictionary->training_patches_ = header.training_patches;
  dictionary->gram_ = atoms.transpose() * atoms;
  return dictionary;
}

void PatchDictionary::saveAtomsPNG(const std::string& path, int columns, int pixels_per_bin) const
{
  requireAtoms();
  std::vector<std::vector<double>> tiles(static_cast<std::size_t>(atoms_.cols()));
  for (Eigen::Index k = 0; k < atoms_.cols(); ++k)
    tiles[static_cast<std::size_t>(k)].assign(atoms_.col(k).data(), atoms_.col(k).data() + atoms_.rows());
  int width = 0, height = 0;
  const auto pixels = contactSheet(tiles, grid_size_, columns, pixels_per_bin, width, height);
  writeFileAtomically(path, encodeGrayPNG(width, height, pixels));
}

}  // namespace patchdict
}  // namespace pcl
