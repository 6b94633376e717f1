// The .pds patch-set file (formatPatchSet, parsePatchSet, savePatchSet, loadPatchSet) and the
// patches as a PNG contact sheet.
#include "core/binary_format.h"
#include "core/byte_stream.h"

#include <pcl_patchdict/core/atomic_file.h>
#include <pcl_patchdict/core/checksum.h>
#include <pcl_patchdict/core/error.h>
#include <pcl_patchdict/io/patch_set_io.h>
#include <pcl_patchdict/io/png_writer.h>

#include <algorithm>
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

// The header: magic (8 bytes), version (u32), grid size (u32), patch count (u64), radius (f64),
// reserved (u64, 0).
constexpr std::size_t kHeaderBytes = 40;

std::size_t bytesPerPatch(std::size_t bins)
{
  return 3 * sizeof(double) + 9 * sizeof(double) + bins * sizeof(double) + bins + sizeof(std::int32_t);
}

}  // namespace

std::string formatPatchSet(const PatchSet& set)
{
  set.check();
  if (!detail::isLittleEndian())
    throw Error("writing .pds files needs a little-endian machine");
  const std::size_t patches = set.seeds.size();
  const std::size_t bins = static_cast<std::size_t>(set.grid_size) * set.grid_size;
  detail::ByteWriter out;
  out.bytes().reserve(kHeaderBytes + patches * bytesPerPatch(bins) + sizeof(std::uint64_t));
  out.putRaw(kMagic, sizeof kMagic);
  out.putU32(kVersion);
  out.putU32(static_cast<std::uint32_t>(set.grid_size));
  out.putU64(static_cast<std::uint64_t>(patches));
  out.putF64(set.radius);
  out.putU64(0);  // reserved
  for (const auto& seed : set.seeds)
    out.putRaw(seed.data(), 3 * sizeof(double));
  for (const auto& rotation : set.rotations)
    out.putRaw(rotation.data(), 9 * sizeof(double));
  out.putRaw(set.heights.data(), sizeof(double) * static_cast<std::size_t>(set.heights.size()));
  for (Eigen::Index k = 0; k < set.observed.size(); ++k)
    out.putU8(set.observed.data()[k] ? 1 : 0);
  out.putRaw(set.source.data(), sizeof(std::int32_t) * set.source.size());
  out.putU64(fnv1a64(out.bytes().data(), out.bytes().size()));
  return out.bytes();
}

void savePatchSet(const std::string& path, const PatchSet& set)
{
  writeFileAtomically(path, formatPatchSet(set));
}

PatchSet loadPatchSet(const std::string& path)
{
  return parsePatchSet(readWholeFile(path), path);
}

PatchSet parsePatchSet(const std::string& bytes, const std::string& name)
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
  if (grid_size < 1 || grid_size > static_cast<std::uint32_t>(PatchSet::kMaxGridSize) || !(radius > 0.0) || !std::isfinite(radius) ||
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

void savePatchSetPNG(const std::string& path, const PatchSet& set, int columns, int pixels_per_bin, std::size_t max_patches)
{
  set.check();
  const std::size_t count = max_patches > 0 ? std::min(max_patches, set.numPatches()) : set.numPatches();
  if (count == 0)
    throw Error("patch set: no patches to draw");
  std::vector<std::vector<double>> tiles(count);
  std::vector<std::vector<bool>> masks(count);
  for (std::size_t p = 0; p < count; ++p) {
    const auto column = static_cast<Eigen::Index>(p);
    tiles[p].assign(set.heights.col(column).data(), set.heights.col(column).data() + set.heights.rows());
    masks[p].resize(static_cast<std::size_t>(set.heights.rows()));
    for (Eigen::Index b = 0; b < set.heights.rows(); ++b)
      masks[p][static_cast<std::size_t>(b)] = set.observed(b, column);
  }
  int width = 0, height = 0;
  const auto pixels = contactSheet(tiles, set.grid_size, columns, pixels_per_bin, width, height, &masks);
  writeFileAtomically(path, encodeGrayPNG(width, height, pixels));
}

}  // namespace patchdict
}  // namespace pcl
