// .pdk checkpoints of streamed online learning: magic, version, named settings, progress, learner
// state (D, A, B, counters, generator), shuffle buffer; FNV-1a 64 checksum; sizes checked first.
#include "core/binary_format.h"
#include "core/byte_stream.h"

#include <pcl_patchdict/io/atomic_file.h>
#include <pcl_patchdict/core/error.h>
#include <pcl_patchdict/coding/learning_checkpoint.h>
#include <pcl_patchdict/coding/patch_dictionary.h>

#include <cstring>

namespace pcl {
namespace patchdict {

namespace {

constexpr char kMagic[8] = {'P', 'C', 'L', 'P', 'D', 'K', '\0', '\x1a'};
constexpr std::uint32_t kVersion = 1;
constexpr std::uint64_t kMaxRows = 1 << 16;  // 256 × 256 bins, as .pdd allows
constexpr std::uint64_t kMaxString = 1 << 20;

void putString(detail::ByteWriter& out, const std::string& text)
{
  out.putU64(text.size());
  out.putRaw(text.data(), text.size());
}

void putMatrix(detail::ByteWriter& out, const Eigen::MatrixXd& matrix)
{
  out.putU64(static_cast<std::uint64_t>(matrix.rows()));
  out.putU64(static_cast<std::uint64_t>(matrix.cols()));
  if (matrix.size() != 0)  // an empty matrix has no data pointer to copy from (null)
    out.putRaw(matrix.data(), sizeof(double) * static_cast<std::size_t>(matrix.size()));
}

void putMask(detail::ByteWriter& out, const ObservationMask& mask)
{
  out.putU64(static_cast<std::uint64_t>(mask.rows()));
  out.putU64(static_cast<std::uint64_t>(mask.cols()));
  for (Eigen::Index i = 0; i < mask.size(); ++i)
    out.putU8(mask.data()[i] ? 1 : 0);
}

std::string getString(detail::ByteReader& in)
{
  const std::uint64_t size = in.getU64();
  if (size > kMaxString || size > in.remaining())
    throw Error(in.what() + "implausible text length " + std::to_string(size));
  std::string text(static_cast<std::size_t>(size), '\0');
  in.getRaw(&text[0], text.size());
  return text;
}

// Rows and columns, checked against the bytes left (entry_size each) before anything is allocated.
std::pair<Eigen::Index, Eigen::Index> getShape(detail::ByteReader& in, std::size_t entry_size)
{
  const std::uint64_t rows = in.getU64(), cols = in.getU64();
  // No columns without rows: 0 × 2⁶³ is a negative size, 0 × 2⁴⁰ hours of looping over nothing.
  if (rows > kMaxRows || (rows == 0 && cols != 0) || (rows != 0 && cols > in.remaining() / entry_size / rows))
    throw Error(in.what() + "implausible matrix size " + std::to_string(rows) + " × " + std::to_string(cols) +
                " (the file is truncated or corrupted)");
  return {static_cast<Eigen::Index>(rows), static_cast<Eigen::Index>(cols)};
}

Eigen::MatrixXd getMatrix(detail::ByteReader& in)
{
  const auto shape = getShape(in, sizeof(double));
  Eigen::MatrixXd matrix(shape.first, shape.second);
  if (matrix.size() != 0)  // memcpy into Eigen's null pointer of an empty matrix is undefined
    in.getRaw(matrix.data(), sizeof(double) * static_cast<std::size_t>(matrix.size()));
  if (!matrix.allFinite())
    throw Error(in.what() + "a matrix holds NaN or Inf");
  return matrix;
}

ObservationMask getMask(detail::ByteReader& in)
{
  const auto shape = getShape(in, 1);
  ObservationMask mask(shape.first, shape.second);
  for (Eigen::Index i = 0; i < mask.size(); ++i) {
    const std::uint8_t value = in.getU8();
    if (value > 1)
      throw Error(in.what() + "a mask holds a value other than 0 or 1");
    mask.data()[i] = value == 1;
  }
  return mask;
}

}  // namespace

std::string LearningCheckpoint::toBytes() const
{
  if (!detail::isLittleEndian())
    throw Error("writing .pdk files needs a little-endian machine");
  detail::ByteWriter out;
  // The buffer dominates (41 MB at the default size): one allocation, not a doubling string.
  const auto matrixBytes = [](Eigen::Index size, std::size_t entry) { return 16 + entry * static_cast<std::size_t>(size); };
  out.bytes().reserve(4096 + learner.rng.size() + buffer.rng.size() + matrixBytes(learner.dictionary.size(), 8) +
                      matrixBytes(learner.a.size(), 8) + matrixBytes(learner.b.size(), 8) +
                      matrixBytes(buffer.buffered.size(), 9) + matrixBytes(buffer.pending.size(), 9));
  out.putRaw(kMagic, sizeof kMagic);
  out.putU32(kVersion);
  out.putU64(settings.size());
  for (const auto& setting : settings) {
    putString(out, setting.first);
    putString(out, setting.second);
  }
  out.putU64(inputs_fingerprint);
  out.putU64(num_inputs);
  out.putU32(pass);
  out.putU64(next_input);
  out.putU32(static_cast<std::uint32_t>(grid_size));
  out.putU64(patches);
  out.putU64(patches_streamed);
  out.putF64(observed_sum);
  out.putU64(skipped.size());
  for (const auto& entry : skipped) {
    out.putU64(entry.first);
    putString(out, entry.second);
  }
  const OnlineLearningParameters& parameters = learner.parameters;
  out.putU32(static_cast<std::uint32_t>(parameters.num_atoms));
  out.putU32(static_cast<std::uint32_t>(parameters.sparsity));
  out.putU32(static_cast<std::uint32_t>(parameters.batch_size));
  out.putU64(parameters.seed);
  putMatrix(out, learner.dictionary);
  putMatrix(out, learner.a);
  putMatrix(out, learner.b);
  out.putU64(learner.seen);
  out.putU64(learner.steps);
  putString(out, learner.rng);
  putMatrix(out, buffer.buffered);
  putMask(out, buffer.buffered_mask);
  putMatrix(out, buffer.pending);
  putMask(out, buffer.pending_mask);
  putString(out, buffer.rng);
  out.putU64(buffer.high_water);
  out.putU64(fnv1a64(out.bytes().data(), out.bytes().size()));
  return out.bytes();
}

void LearningCheckpoint::save(const std::string& path) const
{
  writeFileAtomically(path, toBytes());
}

LearningCheckpoint LearningCheckpoint::load(const std::string& path)
{
  return fromBytes(readWholeFile(path), path);
}

LearningCheckpoint LearningCheckpoint::fromBytes(const std::string& bytes, const std::string& name)
{
  if (!detail::isLittleEndian())
    throw Error("reading .pdk files needs a little-endian machine");
  const std::string where = "cannot read checkpoint '" + name + "': ";
  if (bytes.size() < sizeof kMagic || std::memcmp(bytes.data(), kMagic, sizeof kMagic) != 0)
    throw Error(where + "not a .pdk checkpoint file");
  if (bytes.size() < sizeof kMagic + 4 + 8)
    throw Error(where + "file is truncated (" + std::to_string(bytes.size()) + " bytes)");
  std::uint32_t version;
  std::memcpy(&version, bytes.data() + sizeof kMagic, sizeof version);
  if (version != kVersion)
    throw Error(where + "format version " + std::to_string(version) + " (this build reads version " +
                std::to_string(kVersion) + ")");
  std::uint64_t stored;
  std::memcpy(&stored, bytes.data() + bytes.size() - sizeof stored, sizeof stored);
  if (fnv1a64(bytes.data(), bytes.size() - sizeof stored) != stored)
    throw Error(where + "checksum mismatch (the file is truncated or corrupted)");
  detail::ByteReader in(bytes.data() + sizeof kMagic + 4, bytes.size() - sizeof kMagic - 4 - sizeof stored, where);
  LearningCheckpoint checkpoint;
  const std::uint64_t num_settings = in.getU64();
  if (num_settings > in.remaining() / 16)
    throw Error(where + "implausible number of settings");
  for (std::uint64_t i = 0; i < num_settings; ++i) {
    std::string key = getString(in);
    checkpoint.settings.emplace_back(std::move(key), getString(in));
  }
  checkpoint.inputs_fingerprint = in.getU64();
  checkpoint.num_inputs = in.getU64();
  checkpoint.pass = in.getU32();
  checkpoint.next_input = in.getU64();
  checkpoint.grid_size = static_cast<std::int32_t>(in.getU32());
  checkpoint.patches = in.getU64();
  checkpoint.patches_streamed = in.getU64();
  checkpoint.observed_sum = in.getF64();
  const std::uint64_t num_skipped = in.getU64();
  if (num_skipped > in.remaining() / 16 || num_skipped > checkpoint.num_inputs)
    throw Error(where + "implausible number of skipped inputs");
  for (std::uint64_t i = 0; i < num_skipped; ++i) {
    const std::uint64_t index = in.getU64();
    checkpoint.skipped.emplace_back(index, getString(in));
  }
  if (checkpoint.next_input > checkpoint.num_inputs || checkpoint.grid_size < 0 || checkpoint.grid_size > 256)
    throw Error(where + "implausible progress fields");
  OnlineLearningParameters& parameters = checkpoint.learner.parameters;
  parameters.num_atoms = static_cast<int>(in.getU32());
  parameters.sparsity = static_cast<int>(in.getU32());
  parameters.batch_size = static_cast<int>(in.getU32());
  parameters.seed = in.getU64();
  checkpoint.learner.dictionary = getMatrix(in);
  checkpoint.learner.a = getMatrix(in);
  checkpoint.learner.b = getMatrix(in);
  checkpoint.learner.seen = in.getU64();
  checkpoint.learner.steps = in.getU64();
  checkpoint.learner.rng = getString(in);
  checkpoint.buffer.buffered = getMatrix(in);
  checkpoint.buffer.buffered_mask = getMask(in);
  checkpoint.buffer.pending = getMatrix(in);
  checkpoint.buffer.pending_mask = getMask(in);
  checkpoint.buffer.rng = getString(in);
  checkpoint.buffer.high_water = in.getU64();
  const PatchShuffleBuffer::State& buffer = checkpoint.buffer;
  if (buffer.buffered_mask.rows() != buffer.buffered.rows() || buffer.buffered_mask.cols() != buffer.buffered.cols() ||
      buffer.pending_mask.rows() != buffer.pending.rows() || buffer.pending_mask.cols() != buffer.pending.cols())
    throw Error(where + "the buffer's masks do not match its patches");
  if (!in.atEnd())
    throw Error(where + std::to_string(in.remaining()) + " unexpected bytes before the checksum");
  return checkpoint;
}

}  // namespace patchdict
}  // namespace pcl
