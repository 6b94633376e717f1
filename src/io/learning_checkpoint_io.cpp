// The .pdk checkpoint file of streamed online learning: magic, version, named settings, progress,
// learner state (D, A, B, counters, generator), shuffle buffer; FNV-1a 64 checksum; sizes checked first.
#include "core/binary_format.h"
#include "core/byte_stream.h"

#include <pcl_patchdict/core/atomic_file.h>
#include <pcl_patchdict/core/checksum.h>
#include <pcl_patchdict/core/error.h>
#include <pcl_patchdict/io/learning_checkpoint_io.h>

#include <cstring>

namespace pcl {
namespace patchdict {

namespace {

constexpr char kMagic[8] = {'P', 'C', 'L', 'P', 'D', 'K', '\0', '\x1a'};
constexpr std::uint32_t kVersion = 2;  // 2: shards (version 1 is read too)
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

void putSkipped(detail::ByteWriter& out, const std::vector<std::pair<std::uint64_t, std::string>>& skipped)
{
  out.putU64(skipped.size());
  for (const auto& entry : skipped) {
    out.putU64(entry.first);
    putString(out, entry.second);
  }
}

std::vector<std::pair<std::uint64_t, std::string>> getSkipped(detail::ByteReader& in, std::uint64_t num_inputs)
{
  const std::uint64_t count = in.getU64();
  if (count > in.remaining() / 16 || count > num_inputs)
    throw Error(in.what() + "implausible number of skipped inputs");
  std::vector<std::pair<std::uint64_t, std::string>> skipped;
  for (std::uint64_t i = 0; i < count; ++i) {
    const std::uint64_t index = in.getU64();
    if (index >= num_inputs)
      throw Error(in.what() + "a skipped input's index is beyond the inputs");
    skipped.emplace_back(index, getString(in));
  }
  return skipped;
}

void putBuffer(detail::ByteWriter& out, const PatchShuffleBuffer::State& buffer)
{
  putMatrix(out, buffer.buffered);
  putMask(out, buffer.buffered_mask);
  putMatrix(out, buffer.pending);
  putMask(out, buffer.pending_mask);
  putString(out, buffer.rng);
  out.putU64(buffer.high_water);
}

PatchShuffleBuffer::State getBuffer(detail::ByteReader& in)
{
  PatchShuffleBuffer::State buffer;
  buffer.buffered = getMatrix(in);
  buffer.buffered_mask = getMask(in);
  buffer.pending = getMatrix(in);
  buffer.pending_mask = getMask(in);
  buffer.rng = getString(in);
  buffer.high_water = in.getU64();
  if (buffer.buffered_mask.rows() != buffer.buffered.rows() || buffer.buffered_mask.cols() != buffer.buffered.cols() ||
      buffer.pending_mask.rows() != buffer.pending.rows() || buffer.pending_mask.cols() != buffer.pending.cols())
    throw Error(in.what() + "the buffer's masks do not match its patches");
  return buffer;
}

void putShard(detail::ByteWriter& out, const ShardProgress& shard)
{
  out.putU64(shard.begun);
  out.putU64(shard.next_column);
  out.putU8(shard.streaming ? 1 : 0);
  out.putU8(shard.flushed ? 1 : 0);
  out.putU32(static_cast<std::uint32_t>(shard.grid_size));
  out.putU64(shard.patches);
  out.putU64(shard.patches_streamed);
  out.putU64(shard.patches_coded);
  out.putU64(shard.max_input_patches);
  out.putF64(shard.observed_sum);
  putSkipped(out, shard.skipped);
  putBuffer(out, shard.buffer);
  out.putU64(shard.ready.size());
  for (std::size_t i = 0; i < shard.ready.size(); ++i) {
    putMatrix(out, shard.ready[i]);
    putMask(out, shard.ready_masks[i]);
  }
}

ShardProgress getShard(detail::ByteReader& in, std::uint64_t num_inputs)
{
  ShardProgress shard;
  shard.begun = in.getU64();
  shard.next_column = in.getU64();
  const std::uint8_t streaming = in.getU8(), flushed = in.getU8();
  shard.grid_size = static_cast<std::int32_t>(in.getU32());
  if (streaming > 1 || flushed > 1 || shard.begun > num_inputs || shard.grid_size < 0 || shard.grid_size > 256)
    throw Error(in.what() + "implausible shard progress");
  shard.streaming = streaming == 1;
  shard.flushed = flushed == 1;
  shard.patches = in.getU64();
  shard.patches_streamed = in.getU64();
  shard.patches_coded = in.getU64();
  shard.max_input_patches = in.getU64();
  shard.observed_sum = in.getF64();
  shard.skipped = getSkipped(in, num_inputs);
  shard.buffer = getBuffer(in);
  const std::uint64_t ready = in.getU64();
  if (ready > in.remaining() / 32)
    throw Error(in.what() + "implausible number of sub-batches");
  for (std::uint64_t i = 0; i < ready; ++i) {
    shard.ready.push_back(getMatrix(in));
    shard.ready_masks.push_back(getMask(in));
    const ObservationMask& mask = shard.ready_masks.back();
    if (mask.size() != 0 && (mask.rows() != shard.ready.back().rows() || mask.cols() != shard.ready.back().cols()))
      throw Error(in.what() + "a sub-batch's mask does not match it");
  }
  return shard;
}

}  // namespace

std::string formatLearningCheckpoint(const LearningCheckpoint& checkpoint)
{
  if (!detail::isLittleEndian())
    throw Error("writing .pdk files needs a little-endian machine");
  detail::ByteWriter out;
  // The buffer dominates (41 MB at the default size): one allocation, not a doubling string.
  const auto matrixBytes = [](Eigen::Index size, std::size_t entry) { return 16 + entry * static_cast<std::size_t>(size); };
  std::size_t shard_bytes = 0;
  for (const ShardProgress& shard : checkpoint.shards) {
    shard_bytes += 4096 + matrixBytes(shard.buffer.buffered.size(), 9) + matrixBytes(shard.buffer.pending.size(), 9);
    for (const Eigen::MatrixXd& batch : shard.ready)
      shard_bytes += matrixBytes(batch.size(), 9);
  }
  const OnlineDictionaryLearner::State& learner = checkpoint.learner;
  const PatchShuffleBuffer::State& buffer = checkpoint.buffer;
  out.bytes().reserve(4096 + shard_bytes + learner.rng.size() + buffer.rng.size() + matrixBytes(learner.dictionary.size(), 8) +
                      matrixBytes(learner.a.size(), 8) + matrixBytes(learner.b.size(), 8) +
                      matrixBytes(buffer.buffered.size(), 9) + matrixBytes(buffer.pending.size(), 9));
  out.putRaw(kMagic, sizeof kMagic);
  out.putU32(kVersion);
  out.putU64(checkpoint.settings.size());
  for (const auto& setting : checkpoint.settings) {
    putString(out, setting.first);
    putString(out, setting.second);
  }
  out.putU64(checkpoint.inputs_fingerprint);
  out.putU64(checkpoint.num_inputs);
  out.putU32(checkpoint.pass);
  out.putU64(checkpoint.next_input);
  out.putU32(static_cast<std::uint32_t>(checkpoint.grid_size));
  out.putU64(checkpoint.patches);
  out.putU64(checkpoint.patches_streamed);
  out.putF64(checkpoint.observed_sum);
  putSkipped(out, checkpoint.skipped);
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
  putBuffer(out, buffer);
  out.putU64(checkpoint.shards.size());
  for (const ShardProgress& shard : checkpoint.shards)
    putShard(out, shard);
  out.putU64(fnv1a64(out.bytes().data(), out.bytes().size()));
  return out.bytes();
}

void saveLearningCheckpoint(const std::string& path, const LearningCheckpoint& checkpoint)
{
  writeFileAtomically(path, formatLearningCheckpoint(checkpoint));
}

LearningCheckpoint loadLearningCheckpoint(const std::string& path)
{
  return parseLearningCheckpoint(readWholeFile(path), path);
}

LearningCheckpoint parseLearningCheckpoint(const std::string& bytes, const std::string& name)
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
  if (version != kVersion && version != 1)
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
  checkpoint.skipped = getSkipped(in, checkpoint.num_inputs);
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
  checkpoint.buffer = getBuffer(in);
  if (version >= 2) {
    const std::uint64_t num_shards = in.getU64();
    if (num_shards > 4096 || num_shards > in.remaining() / 64)
      throw Error(where + "implausible number of shards");
    for (std::uint64_t s = 0; s < num_shards; ++s)
      checkpoint.shards.push_back(getShard(in, checkpoint.num_inputs));
  }
  if (!in.atEnd())
    throw Error(where + std::to_string(in.remaining()) + " unexpected bytes before the checksum");
  return checkpoint;
}

}  // namespace patchdict
}  // namespace pcl
