// The .pdd dictionary file (formatPatchDictionary, parsePatchDictionary, savePatchDictionary,
// loadPatchDictionary) and the atoms as a PNG contact sheet.
#include "core/binary_format.h"
#include "core/byte_stream.h"

#include <pcl_patchdict/core/atomic_file.h>
#include <pcl_patchdict/core/checksum.h>
#include <pcl_patchdict/core/error.h>
#include <pcl_patchdict/io/patch_dictionary_io.h>
#include <pcl_patchdict/io/png_writer.h>

#include <cstring>

namespace pcl {
namespace patchdict {

namespace {

// .pdd layout (little-endian): header, atoms as float64 column-major, then FNV-1a 64 of all before.
constexpr char kMagic[8] = {'P', 'C', 'L', 'P', 'D', 'D', '\0', '\x1a'};
constexpr std::uint32_t kVersion = 1;

// The header: magic (8 bytes); version, grid size, atom count, flags (bit 0: remove mean), method,
// sparsity, iterations, reserved (u32 each); seed, training patches (u64 each).
constexpr std::size_t kHeaderBytes = 56;

}  // namespace

std::string formatPatchDictionary(const PatchDictionary& dictionary)
{
  if (dictionary.empty())
    throw Error("the patch dictionary has no atoms (learn or load it first)");
  const Eigen::MatrixXd& atoms = dictionary.atoms();
  const DictionaryLearningOptions& learned_with = dictionary.learnedWith();
  if (!detail::isLittleEndian())
    throw Error("writing .pdd files needs a little-endian machine");
  detail::ByteWriter out;
  out.putRaw(kMagic, sizeof kMagic);
  for (const std::uint32_t field :
       {kVersion, static_cast<std::uint32_t>(dictionary.gridSize()), static_cast<std::uint32_t>(atoms.cols()),
        dictionary.getRemoveMean() ? 1u : 0u, static_cast<std::uint32_t>(learned_with.method),
        static_cast<std::uint32_t>(learned_with.sparsity), static_cast<std::uint32_t>(learned_with.iterations), 0u})
    out.putU32(field);
  out.putU64(learned_with.seed);
  out.putU64(dictionary.trainingPatches());
  out.putRaw(atoms.data(), sizeof(double) * static_cast<std::size_t>(atoms.size()));
  out.putU64(fnv1a64(out.bytes().data(), out.bytes().size()));
  return out.bytes();
}

void savePatchDictionary(const std::string& path, const PatchDictionary& dictionary)
{
  writeFileAtomically(path, formatPatchDictionary(dictionary));
}

PatchDictionary::Ptr loadPatchDictionary(const std::string& path, int expected_grid_size)
{
  return parsePatchDictionary(readWholeFile(path), expected_grid_size, path);
}

PatchDictionary::Ptr parsePatchDictionary(const std::string& bytes, int expected_grid_size, const std::string& name)
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
  if (header.grid_size < 1 || header.grid_size > PatchDictionary::kMaxGridSize || header.num_atoms < 1 ||
      header.num_atoms > PatchDictionary::kMaxAtoms ||
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
  DictionaryLearningOptions learned_with;
  learned_with.method = static_cast<LearningMethod>(header.method);
  learned_with.sparsity = static_cast<int>(header.sparsity);
  learned_with.iterations = static_cast<int>(header.iterations);
  learned_with.seed = header.seed;
  dictionary->setRemoveMean((header.flags & 1u) != 0);
  dictionary->setStoredAtoms(atoms, header.training_patches, learned_with);
  return dictionary;
}

void saveDictionaryAtomsPNG(const std::string& path, const PatchDictionary& dictionary, int columns, int pixels_per_bin)
{
  if (dictionary.empty())
    throw Error("the patch dictionary has no atoms (learn or load it first)");
  const Eigen::MatrixXd& atoms = dictionary.atoms();
  std::vector<std::vector<double>> tiles(static_cast<std::size_t>(atoms.cols()));
  for (Eigen::Index k = 0; k < atoms.cols(); ++k)
    tiles[static_cast<std::size_t>(k)].assign(atoms.col(k).data(), atoms.col(k).data() + atoms.rows());
  int width = 0, height = 0;
  const auto pixels = contactSheet(tiles, dictionary.gridSize(), columns, pixels_per_bin, width, height);
  writeFileAtomically(path, encodeGrayPNG(width, height, pixels));
}

}  // namespace patchdict
}  // namespace pcl
