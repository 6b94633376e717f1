#include "core/binary_format.h"

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

#pragma pack(push, 1)
struct PdsHeader {
  char magic[8];
  std::uint32_t version;
  std::uint32_t grid_size;
  std::uint64_t num_patches;
  double radius;
  std::uint64_t reserved;
};
#pragma pack(pop)
static_assert(sizeof(PdsHeader) == 40, "unexpected .pds header size");

std::size_t bytesPerPatch(std::size_t bins)
{
  return 3 * sizeof(double) + 9 * sizeof(double) + bins * sizeof(double) + bins + sizeof(std::int32_t);
}

template <typename T>
void appendRaw(std::string& bytes, const T* data, std::size_t count)
{
  bytes.append(reinterpret_cast<const char*>(data), sizeof(T) * count);
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
  PdsHeader header{};
  std::memcpy(header.magic, kMagic, sizeof kMagic);
  header.version = kVersion;
  header.grid_size = static_cast<std::uint32_t>(grid_size);
  header.num_patches = static_cast<std::uint64_t>(seeds.size());
  header.radius = radius;
  const std::size_t patches = seeds.size();
  const std::size_t bins = static_cast<std::size_t>(grid_size) * grid_size;
  std::string bytes;
  bytes.reserve(sizeof header + patches * bytesPerPatch(bins) + sizeof(std::uint64_t));
  appendRaw(bytes, &header, 1);
  for (const auto& seed : seeds)
    appendRaw(bytes, seed.data(), 3);
  for (const auto& rotation : rotations)
    appendRaw(bytes, rotation.data(), 9);
  appendRaw(bytes, heights.data(), static_cast<std::size_t>(heights.size()));
  std::string mask(static_cast<std::size_t>(observed.size()), '\0');
  for (Eigen::Index k = 0; k < observed.size(); ++k)
    mask[static_cast<std::size_t>(k)] = observed.data()[k] ? '\1' : '\0';
  bytes += mask;
  appendRaw(bytes, source.data(), source.size());
  const std::uint64_t checksum = fnv1a64(bytes.data(), bytes.size());
  appendRaw(bytes, &checksum, 1);
  writeFileAtomically(path, bytes);
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
  if (bytes.size() < sizeof(PdsHeader) + sizeof(std::uint64_t))
    throw Error(where + "file is truncated (" + std::to_string(bytes.size()) + " bytes)");
  PdsHeader header;
  std::memcpy(&header, bytes.data(), sizeof header);
  if (header.version != kVersion)
    throw Error(where + "format version " + std::to_string(header.version) + " (this build reads version " +
                std::to_string(kVersion) + ")");
  if (header.grid_size < 1 || header.grid_size > static_cast<std::uint32_t>(kMaxGrid) || !(header.radius > 0.0) ||
      !std::isfinite(header.radius) || header.reserved != 0)
    throw Error(where + "implausible header (grid " + std::to_string(header.grid_size) + ", radius " +
                std::to_string(header.radius) + ")");
  const std::size_t bins = static_cast<std::size_t>(header.grid_size) * header.grid_size;
  const std::size_t per_patch = bytesPerPatch(bins);
  const std::size_t payload = bytes.size() - sizeof header - sizeof(std::uint64_t);
  // Compare by division: a forged count must neither overflow the size computation nor make us
  // allocate more than the file could possibly hold.
  if (header.num_patches > payload / per_patch)
    throw Error(where + "file is truncated or its patch count is implausible (" + std::to_string(header.num_patches) +
                " patches declared, " + std::to_string(bytes.size()) + " bytes)");
  const std::size_t patches = static_cast<std::size_t>(header.num_patches);
  const std::size_t expected = sizeof header + patches * per_patch + sizeof(std::uint64_t);
  if (bytes.size() > expected)
    throw Error(where + std::to_string(bytes.size() - expected) + " unexpected bytes after the patches");
  std::uint64_t stored;
  std::memcpy(&stored, bytes.data() + expected - sizeof stored, sizeof stored);
  if (fnv1a64(bytes.data(), expected - sizeof stored) != stored)
    throw Error(where + "checksum mismatch (the file is truncated or corrupted)");

  PatchSet set;
  set.grid_size = static_cast<int>(header.grid_size);
  set.radius = header.radius;
  const char* cursor = bytes.data() + sizeof header;
  set.seeds.resize(patches);
  for (auto& seed : set.seeds) {
    std::memcpy(seed.data(), cursor, 3 * sizeof(double));
    cursor += 3 * sizeof(double);
  }
  set.rotations.resize(patches);
  for (auto& rotation : set.rotations) {
    std::memcpy(rotation.data(), cursor, 9 * sizeof(double));
    cursor += 9 * sizeof(double);
  }
  const auto rows = static_cast<Eigen::Index>(bins), cols = static_cast<Eigen::Index>(patches);
  set.heights.resize(rows, cols);
  if (patches > 0)  // an empty matrix has no data pointer to copy into
    std::memcpy(set.heights.data(), cursor, sizeof(double) * bins * patches);
  cursor += sizeof(double) * bins * patches;
  set.observed.resize(rows, cols);
  for (std::size_t k = 0; k < bins * patches; ++k) {
    const auto flag = static_cast<unsigned char>(cursor[k]);
    if (flag > 1)
      throw Error(where + "observation mask holds a byte other than 0 or 1");
    set.observed.data()[k] = flag == 1;
  }
  cursor += bins * patches;
  set.source.resize(patches);
  if (patches > 0)
    std::memcpy(set.source.data(), cursor, sizeof(std::int32_t) * patches);
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
