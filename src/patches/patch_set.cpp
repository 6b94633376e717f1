#include "core/binary_format.h"
#include "core/byte_stream.h"

#include <pcl_patchdict/io/atomic_file.h>
#include <pcl_patchdict/core/error.h>
#include <pcl_patchdict/core/checksum.h>
#include <pcl_patchdict/patches/patch_set.h>
#include <pcl_patchdict/io/png_writer.h>

#include <cmath>
#include <cstring>

namespace pcl {
namespace patchdict {

namespace {

// .pds layout (little-endian): header; seeds (3 float64 per patch); rotations (9 float64 per patch,
// column-major); heights (N²×P float64, column-major); mask (N²×P bytes, 0/1); sources (P int32);
// then FNV-1a 64 of all the bytes before it. Same conventions as the .pdd dictionary file.
constexpr char kMagic[8] = {'P', 'C', 'L', 'P', 'D', 'S', '\0', '\x1a'};
constexpr std::uint32_t kVersion = 1;
constexpr int kMaxGrid = 256;  // as .pdd: a 256×256 patch is already far beyond the paper's 16–24

// The header: magic (8 bytes), version (u32), grid size (u32), patch count (u64), radius (f64),
// reserved (u64, 0).
constexpr std::size_t kHeaderBytes = 40;

std::size_t bytesPerPatch(std::size_t bins)
{
  return 3 * sizeof(double) + 9 * sizeof(double) + bins * sizeof(double) + bins + sizeof(std::int32_t);
}


}  // namespace

double PatchSet::side() const { return std::sqrt(2.0) * radius; }

double PatchSet::observedFraction() const
{
  if (observed.size() == 0)
    return 0.0;
  return static_cast<double>(observed.count()) / static_cast<double>(observed.size());
}

void PatchSet::check() const
{
  if (grid_size < 1 || grid_size > kMaxGrid)
    throw Error("patch set: grid size " + std::to_string(grid_size) + " is outside [1, " + std::to_string(kMaxGrid) +
                "]");
  if (!(radius > 0.0) || !std::isfinite(radius))
    throw Error("patch set: radius must be positive and finite");
  const auto patches = static_cast<Eigen::Index>(seeds.size());
  const Eigen::Index bins = static_cast<Eigen::Index>(grid_size) * grid_size;
  if (static_cast<Eigen::Index>(rotations.size()) != patches || static_cast<Eigen::Index>(source.size()) != patches ||
      heights.rows() != bins || heights.cols() != patches || observed.rows() != bins || observed.cols() != patches)
    throw Error("patch set: sizes disagree (" + std::to_string(seeds.size()) + " seeds, " +
                std::to_string(rotations.size()) + " frames, " + std::to_string(source.size()) + " sources, heights " +
                std::to_string(heights.rows()) + "×" + std::to_string(heights.cols()) + ", mask " +
                std::to_string(observed.rows()) + "×" + std::to_string(observed.cols()) + ", " +
                std::to_string(bins) + " bins expected)");
  if (!heights.allFinite())
    throw Error("patch set: heights contain NaN or Inf");
  for (std::size_t p = 0; p < seeds.size(); ++p)
    if (!seeds[p].allFinite() || !rotations[p].allFinite())
      throw Error("patch set: seed or frame " + std::to_string(p) + " is not finite");
}

void PatchSet::append(const PatchSet& other)
{
  other.check();
  if (seeds.empty() && heights.size() == 0 && grid_size == 0) {
    *this = other;
    return;
  }
  check();
  if (other.grid_size != grid_size || other.radius != radius)
    throw Error("patch set: cannot append patches of grid " + std::to_string(other.grid_size) + " to patches of grid " +
                std::to_string(grid_size) + " (grid size and radius must match)");
  const Eigen::Index old_count = heights.cols(), extra = other.heights.cols();
  heights.conservativeResize(Eigen::NoChange, old_count + extra);
  heights.rightCols(extra) = other.heights;
  observed.conservativeResize(Eigen::NoChange, old_count + extra);
  observed.rightCols(extra) = other.observed;
  seeds.insert(seeds.end(), other.seeds.begin(), other.seeds.end());
  rotations.insert(rotations.end(), other.rotations.begin(), other.rotations.end());
  source.insert(source.end(), other.source.begin(), other.source.end());
}

void PatchSet::save(const std::string& path) const
{
  check();
  if (!detail::isLittleEndian())
    throw Error("writing .pds files needs a little-endian machine");
  const std::size_t patches = seeds.size();
  const std::size_t bins = static_cast<std::size_t>(grid_size) * grid_size;
  detail::ByteWriter out;
  out.bytes().reserve(kHeaderBytes + patches * bytesPerPatch(bins) + sizeof(std::uint64_t));
  out.putRaw(kMagic, sizeof kMagic);
  out.putU32(kVersion);
  out.putU32(static_cast<std::uint32_t>(grid_size));
  out.putU64(static_cast<std::uint64_t>(patches));
  out.putF64(radius);
  out.putU64(0);  // reserved
  for (const auto& seed : seeds)
    out.putRaw(seed.data(), 3 * sizeof(double));
  for (const auto& rotation : rotations)
    out.putRaw(rotation.data(), 9 * sizeof(double));
  out.putRaw(heights.data(), sizeof(double) * static_cast<std::size_t>(heights.size()));
  for (Eigen::Index k = 0; k < observed.size(); ++k)
    out.putU8(observed.data()[k] ? 1 : 0);
  out.putRaw(source.data(), sizeof(std::int32_t) * source.size());
  out.putU64(fnv1a64(out.bytes().data(), out.bytes().size()));
  writeFileAtomically(path, out.bytes());
}

PatchSet PatchSet::load(const std::string& path)
{
  return fromBytes(readWholeFile(path), path);
}

PatchSet PatchSet::fromBytes(const std::string& bytes, const std::string& name)
{
  if (!detail::isLittleEndian())
    throw Error("reading .pds files needs a little-endian machine");
  const std::string where = "cannot read patch set '" + name + "': ";
  if (bytes.size() >= sizeof kMagic && std::memcmp(bytes.data(), kMagic, sizeof kMagic) != 0)
    throw Error(where + "not a .pds file");
  if (bytes.size() < kHeaderBytes + sizeof(std::uint64_t))
    throw Error(where + "file is truncated (" + std::to_string(bytes.size()) + " bytes)");
  detail::ByteReader in(bytes.data(), bytes.size(), where);
  char magic[sizeof kMagic];
  in.getRaw(magic, sizeof magic);
  const std::uint32_t version = in.getU32(), grid_size = in.getU32();
  const std::uint64_t num_patches = in.getU64();
  const double radius = in.getF64();
  const std::uint64_t reserved = in.getU64();
  if (version != kVersion)
    throw Error(where + "format version " + std::to_string(version) + " (this build reads version " +
                std::to_string(kVersion) + ")");
  if (grid_size < 1 || grid_size > static_cast<std::uint32_t>(kMaxGrid) || !(radius > 0.0) || !std::isfinite(radius) ||
      reserved != 0)
    throw Error(where + "implausible header (grid " + std::to_string(grid_size) + ", radius " + std::to_string(radius) +
                ")");
  const std::size_t bins = static_cast<std::size_t>(grid_size) * grid_size;
  const std::size_t per_patch = bytesPerPatch(bins);
  const std::size_t payload = bytes.size() - kHeaderBytes - sizeof(std::uint64_t);
  // Compare by division: a forged count must neither overflow the size computation nor make us
  // allocate more than the file could possibly hold.
  if (num_patches > payload / per_patch)
    throw Error(where + "file is truncated or its patch count is implausible (" + std::to_string(num_patches) +
                " patches declared, " + std::to_string(bytes.size()) + " bytes)");
  const std::size_t patches = static_cast<std::size_t>(num_patches);
  const std::size_t expected = kHeaderBytes + patches * per_patch + sizeof(std::uint64_t);
  if (bytes.size() > expected)
    throw Error(where + std::to_string(bytes.size() - expected) + " unexpected bytes after the patches");
  const std::uint64_t stored = detail::ByteReader(bytes.data() + expected - 8, 8, where).getU64();
  if (fnv1a64(bytes.data(), expected - sizeof stored) != stored)
    throw Error(where + "checksum mismatch (the file is truncated or corrupted)");

  PatchSet set;
  set.grid_size = static_cast<int>(grid_size);
  set.radius = radius;
  set.seeds.resize(patches);
  for (auto& seed : set.seeds)
    in.getRaw(seed.data(), 3 * sizeof(double));
  set.rotations.resize(patches);
  for (auto& rotation : set.rotations)
    in.getRaw(rotation.data(), 9 * sizeof(double));
  const auto rows = static_cast<Eigen::Index>(bins), cols = static_cast<Eigen::Index>(patches);
  set.heights.resize(rows, cols);
  if (patches > 0)  // an empty matrix has no data pointer to copy into
    in.getRaw(set.heights.data(), sizeof(double) * bins * patches);
  set.observed.resize(rows, cols);
  for (std::size_t k = 0; k < bins * patches; ++k) {
    const std::uint8_t flag = in.getU8();
    if (flag > 1)
      throw Error(where + "observation mask holds a byte other than 0 or 1");
    set.observed.data()[k] = flag == 1;
  }
  set.source.resize(patches);
  if (patches > 0)
    in.getRaw(set.source.data(), sizeof(std::int32_t) * patches);
  try {
    set.check();
  } catch (const Error& error) {
    throw Error(where + error.what());
  }
  return set;
}

void PatchSet::savePNG(const std::string& path, int columns, int pixels_per_bin, std::size_t max_patches) const
{
  check();
  const std::size_t count = max_patches > 0 ? std::min(max_patches, numPatches()) : numPatches();
  if (count == 0)
    throw Error("patch set: no patches to draw");
  std::vector<std::vector<double>> tiles(count);
  std::vector<std::vector<bool>> masks(count);
  for (std::size_t p = 0; p < count; ++p) {
    const auto column = static_cast<Eigen::Index>(p);
    tiles[p].assign(heights.col(column).data(), heights.col(column).data() + heights.rows());
    masks[p].resize(static_cast<std::size_t>(heights.rows()));
    for (Eigen::Index b = 0; b < heights.rows(); ++b)
      masks[p][static_cast<std::size_t>(b)] = observed(b, column);
  }
  int width = 0, height = 0;
  const auto pixels = contactSheet(tiles, grid_size, columns, pixels_per_bin, width, height, &masks);
  writeFileAtomically(path, encodeGrayPNG(width, height, pixels));
}

}  // namespace patchdict
}  // namespace pcl
