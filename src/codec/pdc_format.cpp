// .pdc container: fixed header, nine zlib-packed sections, FNV-1a 64 checksum.
#include "codec/pdc_format.h"

#include "core/binary_format.h"
#include "core/byte_stream.h"
#include "codec/mask_coding.h"
#include "codec/sparse_code_coding.h"

#include <pcl_patchdict/core/checksum.h>
#include <pcl_patchdict/core/error.h>
#include <pcl_patchdict/coding/patch_dictionary.h>

#include <algorithm>
#include <cmath>
#include <limits>

namespace pcl {
namespace patchdict {
namespace detail {

namespace {

constexpr char kMagic[4] = {'P', 'D', 'C', 'v'};
// Version 2 added the coverage section (patches with stored frames); version 3 codes the masks'
// bins, the atom sets and the coefficients with an adaptive range coder (mask_coding.h,
// sparse_code_coding.h) instead of deflated bitmaps and byte planes. This build writes version 3
// and reads 2 and 3.
constexpr std::uint32_t kVersion = 3, kOldestVersion = 2;
constexpr std::uint32_t kFlagRemoveMean = 1, kFlagKeepConnectivity = 2;
// Version 3's range-coded sections cost the reader a few binary decisions per stored bit and can
// stand for far more decisions than bytes: a file may ask for at most this many (atom decisions =
// patches × atoms, mask decisions = masked patches × bins; coefficients: at most `coefficients` per
// patch, 31 decisions each); lucy at L 0.045 asks for 77k and 92k.
constexpr std::uint64_t kMaxCodedDecisions = std::uint64_t(1) << 26;

std::size_t bitmapBytes(std::size_t bits) { return (bits + 7) / 8; }

void putSection(ByteWriter& out, const std::string& raw, std::size_t* size)
{
  const std::string packed = deflateBytes(raw);
  out.putU64(raw.size());
  out.putU64(packed.size());
  out.putRaw(packed.data(), packed.size());
  if (size)
    *size = 16 + packed.size();
}

std::string getSection(ByteReader& in)
{
  const std::uint64_t raw_size = in.getU64(), packed_size = in.getU64();
  if (packed_size > in.remaining())
    throw Error(in.what() + "data is truncated");
  std::string packed(static_cast<std::size_t>(packed_size), '\0');
  in.getRaw(&packed[0], packed.size());
  return inflateBytes(packed, static_cast<std::size_t>(raw_size), in.what());
}

/** previous + the next stored delta; a delta no field of the format can hold (|d| > 2^40) is
  * refused before the sum could overflow. */
std::int64_t addDelta(ByteReader& in, std::int64_t previous, const char* field)
{
  const std::int64_t delta = in.getSigned(), bound = std::int64_t(1) << 40;
  if (delta > bound || delta < -bound)
    throw Error(in.what() + "implausible " + field + " (the file is corrupted)");
  return previous + delta;
}

void expectEnd(const ByteReader& in, const char* section)
{
  if (!in.atEnd())
    throw Error(in.what() + "the " + std::string(section) + " section has unexpected bytes (the file is corrupted)");
}


// --- writing ---------------------------------------------------------------------------------

void writeHeader(const PdcContent& c, ByteWriter& out)
{
  out.putRaw(kMagic, 4);
  out.putU32(kVersion);
  out.putU64(c.fingerprint);
  out.putU32(c.grid_size);
  out.putU32(c.num_atoms);
  out.putU32((c.remove_mean ? kFlagRemoveMean : 0) | (c.keep_connectivity ? kFlagKeepConnectivity : 0));
  out.putF64(c.quad_length);
  out.putF64(c.radius);
  for (int k = 0; k < 3; ++k)
    out.putF64(c.normalization.center[k]);
  out.putF64(c.normalization.scale);
  for (const std::uint32_t v : {c.overlap, c.coefficients, c.coefficient_bits, c.position_bits, c.subdivision,
                                c.location_bits})
    out.putU32(v);
  out.putF64(c.coefficient_step);
  out.putF64(c.mean_step);
  out.putU32(static_cast<std::uint32_t>(c.quad_positions.size()));
  out.putU32(static_cast<std::uint32_t>(c.quad_faces.size()));
  out.putU32(static_cast<std::uint32_t>(c.atoms.size()));
  out.putU32(static_cast<std::uint32_t>(c.faces.size()));
  out.putU32(static_cast<std::uint32_t>(c.places.size()));
}

std::string quadVertexSection(const PdcContent& c)
{
  ByteWriter positions;
  std::array<std::int64_t, 3> previous{0, 0, 0};
  for (const auto& p : c.quad_positions)
    for (int k = 0; k < 3; ++k) {
      positions.putSigned(static_cast<std::int64_t>(p[k]) - previous[k]);
      previous[k] = p[k];
    }
  return positions.bytes();
}

/** Back-references from the next unseen vertex: with vertices numbered in order of first use
  * (the encoder does so), a new vertex costs a 0 and a recent one a small number. */
std::string quadFaceSection(const PdcContent& c)
{
  ByteWriter faces;
  std::int64_t next = 0;
  for (const auto& face : c.quad_faces) {
    faces.putVarint(face.size() - 3);
    for (const std::int32_t v : face) {
      faces.putSigned(next - v);
      next = std::max<std::int64_t>(next, v + 1);
    }
  }
  return faces.bytes();
}

std::string signedSection(const std::vector<std::int64_t>& values)
{
  ByteWriter section;
  for (const std::int64_t v : values)
    section.putSigned(v);
  return section.bytes();
}

/** Faces: the first corner against the previous face's, the others against the first (meshes
  * number their vertices locally, so both differences are small); then the vertex places. */
std::string connectivitySection(const PdcContent& c)
{
  ByteWriter connectivity;
  std::int64_t last = 0;
  for (const Face& f : c.faces) {
    connectivity.putSigned(f[0] - last);
    connectivity.putSigned(f[1] - f[0]);
    connectivity.putSigned(f[2] - f[0]);
    last = f[0];
  }
  last = 0;
  for (const VertexPlace& place : c.places) {
    connectivity.putSigned(place.triangle - last);
    last = place.triangle;
    connectivity.putVarint(place.u);
    connectivity.putVarint(place.v);
  }
  return connectivity.bytes();
}

/** Coverage frames: count, then per frame the position's deltas from the previous frame's and the
  * normal and angle codes. */
std::string coverageSection(const PdcContent& c)
{
  ByteWriter coverage;
  coverage.putVarint(c.coverage.size());
  std::array<std::int64_t, 3> before{0, 0, 0};
  for (const CoverageFrame& f : c.coverage) {
    for (std::size_t k = 0; k < 3; ++k) {
      coverage.putSigned(static_cast<std::int64_t>(f.position[k]) - before[k]);
      before[k] = f.position[k];
    }
    coverage.putVarint(f.normal_u);
    coverage.putVarint(f.normal_v);
    coverage.putVarint(f.angle);
  }
  return coverage.bytes();
}

// --- reading ---------------------------------------------------------------------------------

/** The header's element counts, which the sections are checked against. */
struct PdcCounts {
  std::uint32_t version, num_positions, num_quad_faces, patches, num_faces, num_places;
};

/** The fixed header after the magic and version, checked for plausibility. */
void readHeader(ByteReader& in, const std::string& what, PdcContent& c, PdcCounts& n)
{
  c.fingerprint = in.getU64();
  c.grid_size = in.getU32();
  c.num_atoms = in.getU32();
  const std::uint32_t flags = in.getU32();
  c.remove_mean = (flags & kFlagRemoveMean) != 0;
  c.keep_connectivity = (flags & kFlagKeepConnectivity) != 0;
  c.quad_length = in.getF64();
  c.radius = in.getF64();
  for (int k = 0; k < 3; ++k)
    c.normalization.center[k] = in.getF64();
  c.normalization.scale = in.getF64();
  for (std::uint32_t* v : {&c.overlap, &c.coefficients, &c.coefficient_bits, &c.position_bits, &c.subdivision,
                           &c.location_bits})
    *v = in.getU32();
  c.coefficient_step = in.getF64();
  c.mean_step = in.getF64();
  n.num_positions = in.getU32();
  n.num_quad_faces = in.getU32();
  n.patches = in.getU32();
  n.num_faces = in.getU32();
  n.num_places = in.getU32();
  const bool plausible = c.grid_size >= 2 && c.grid_size <= 256 && c.num_atoms >= 1 && c.num_atoms <= 65536 &&
                         c.position_bits >= 1 && c.position_bits <= 30 && c.coefficient_bits >= 2 &&
                         c.coefficient_bits <= 16 && c.location_bits <= 16 && c.subdivision >= 1 &&
                         c.subdivision <= c.grid_size && c.quad_length > 0 && c.quad_length <= 1 && c.radius > 0 &&
                         c.radius <= 100 && std::isfinite(c.normalization.scale) && c.normalization.scale > 0 &&
                         std::isfinite(1.0 / c.normalization.scale) && c.normalization.center.allFinite() &&
                         c.coefficient_step >= 0 && c.coefficient_step <= 1e6 && c.mean_step >= 0 &&
                         c.mean_step <= 1e6 && n.num_quad_faces >= 1 && n.patches >= 1 && c.overlap <= 16 &&
                         c.coefficients >= 1 && c.coefficients <= c.num_atoms;
  if (!plausible)
    throw Error(what + "implausible header (the file is corrupted)");
}

void readQuadVertices(ByteReader& in, const std::string& what, const PdcCounts& n, PdcContent& c)
{
  const std::string raw = getSection(in);
  if (raw.size() < 3 * static_cast<std::size_t>(n.num_positions))
    throw Error(what + "quad vertex section too short (the file is corrupted)");
  ByteReader section(raw.data(), raw.size(), what);
  std::array<std::int64_t, 3> previous{0, 0, 0};
  const std::int64_t limit = (std::int64_t(1) << c.position_bits) - 1;
  c.quad_positions.resize(n.num_positions);
  for (auto& p : c.quad_positions)
    for (int k = 0; k < 3; ++k) {
      previous[k] = addDelta(section, previous[k], "quad vertex");
      if (previous[k] < 0 || previous[k] > limit)
        throw Error(what + "quad vertex outside the quantisation grid (the file is corrupted)");
      p[k] = static_cast<std::uint32_t>(previous[k]);
    }
  expectEnd(section, "quad vertex");
}

void readQuadFaces(ByteReader& in, const std::string& what, const PdcCounts& n, PdcContent& c)
{
  const std::string raw = getSection(in);
  if (raw.size() < 4 * static_cast<std::size_t>(n.num_quad_faces))
    throw Error(what + "quad face section too short (the file is corrupted)");
  ByteReader section(raw.data(), raw.size(), what);
  std::int64_t next = 0;
  c.quad_faces.resize(n.num_quad_faces);
  for (auto& face : c.quad_faces) {
    const std::uint64_t extra = section.getVarint();
    if (extra > 1024)
      throw Error(what + "implausible face size (the file is corrupted)");
    face.resize(static_cast<std::size_t>(extra + 3));
    for (auto& v : face) {
      const std::int64_t index = next - section.getSigned();
      if (index < 0 || index >= static_cast<std::int64_t>(n.num_positions))
        throw Error(what + "quad face index out of range (the file is corrupted)");
      v = static_cast<std::int32_t>(index);
      next = std::max<std::int64_t>(next, index + 1);
    }
  }
  expectEnd(section, "quad face");
}

void readSeedOffsets(ByteReader& in, const std::string& what, std::uint32_t patches, PdcContent& c)
{
  const std::string raw = getSection(in);
  if (raw.size() < patches)
    throw Error(what + "seed offset section too short (the file is corrupted)");
  ByteReader section(raw.data(), raw.size(), what);
  c.offsets.resize(patches);
  for (auto& o : c.offsets) {
    o = section.getSigned();
    if (std::abs(o) > (std::int64_t(1) << 40))
      throw Error(what + "implausible seed offset (the file is corrupted)");
  }
  expectEnd(section, "seed offset");
}

/** Version 2's atom bitmaps and byte-plane coefficients. */
void readSparseCodesV2(ByteReader& in, const std::string& what, std::uint32_t patches, PdcContent& c)
{
  std::size_t nonzeros = 0;
  {
    const std::string raw = getSection(in);
    const std::size_t row = bitmapBytes(c.num_atoms);
    if (raw.size() != row * patches)
      throw Error(what + "atom section has the wrong size (the file is corrupted)");
    c.atoms.resize(patches);
    for (std::size_t p = 0; p < patches; ++p)
      for (std::uint32_t a = 0; a < c.num_atoms; ++a)
        if (static_cast<unsigned char>(raw[p * row + a / 8]) & (1u << (a % 8)))
          c.atoms[p].push_back(a);
    for (std::size_t p = 0; p < patches; ++p) {
      nonzeros += c.atoms[p].size();
      // Bits beyond the last atom must be clear.
      for (std::uint32_t a = c.num_atoms; a < 8 * row; ++a)
        if (static_cast<unsigned char>(raw[p * row + a / 8]) & (1u << (a % 8)))
          throw Error(what + "atom index out of range (the file is corrupted)");
    }
  }
  const std::string raw = getSection(in);
  if (raw.size() != 2 * nonzeros)
    throw Error(what + "coefficient section has the wrong size (the file is corrupted)");
  c.values.resize(patches);
  std::size_t k = 0;
  for (std::size_t p = 0; p < patches; ++p)
    for (std::size_t i = 0; i < c.atoms[p].size(); ++i, ++k) {
      const std::uint32_t z = static_cast<unsigned char>(raw[k]) |
                              (static_cast<std::uint32_t>(static_cast<unsigned char>(raw[nonzeros + k])) << 8);
      c.values[p].push_back(static_cast<std::int32_t>(z >> 1) ^ -static_cast<std::int32_t>(z & 1));
    }
}

/** The atom sets and coefficients: range-coded (version 3) or as bitmaps and byte planes. */
void readSparseCodes(ByteReader& in, const std::string& what, const PdcCounts& n, PdcContent& c)
{
  if (n.version < 3) {
    readSparseCodesV2(in, what, n.patches, c);
    return;
  }
  if (static_cast<std::uint64_t>(n.patches) * c.num_atoms > kMaxCodedDecisions)
    throw Error(what + "implausible header (the file is corrupted)");
  if (!decodeAtomSets(getSection(in), n.patches, c.num_atoms, c.coefficients, c.atoms))
    throw Error(what + "malformed atom section (the file is corrupted)");
  if (!decodeCoefficients(getSection(in), c.atoms, c.num_atoms, c.values))
    throw Error(what + "malformed coefficient section (the file is corrupted)");
}

void readMeans(ByteReader& in, const std::string& what, std::uint32_t patches, PdcContent& c)
{
  const std::string raw = getSection(in);
  ByteReader section(raw.data(), raw.size(), what);
  if (c.remove_mean) {
    if (raw.size() < patches)
      throw Error(what + "mean section too short (the file is corrupted)");
    c.means.resize(patches);
    for (auto& m : c.means)
      m = section.getSigned();
  }
  expectEnd(section, "mean");
}

/** The masks: one flag per patch, then the flagged patches' masks, range-coded (version 3) or as
  * bitmaps. */
void readMasks(ByteReader& in, const std::string& what, const PdcCounts& n, PdcContent& c)
{
  const std::size_t patches = n.patches, bins = static_cast<std::size_t>(c.grid_size) * c.grid_size;
  const std::string raw = getSection(in);
  if (raw.size() < patches)
    throw Error(what + "mask section too short (the file is corrupted)");
  std::size_t masked = 0;
  for (std::size_t p = 0; p < patches; ++p) {
    if (raw[p] != 0 && raw[p] != 1)
      throw Error(what + "malformed mask flags (the file is corrupted)");
    masked += static_cast<std::size_t>(raw[p]);
  }
  const std::size_t row = bitmapBytes(bins);
  if (n.version >= 3 && masked) {
    if (static_cast<std::uint64_t>(masked) * bins > kMaxCodedDecisions)
      throw Error(what + "implausible mask section (the file is corrupted)");
    std::vector<std::vector<char>> partial;
    if (!decodeMasks(raw.substr(patches), masked, static_cast<int>(c.grid_size), partial))
      throw Error(what + "malformed mask section (the file is corrupted)");
    c.observed = ObservationMask::Constant(static_cast<Eigen::Index>(bins), static_cast<Eigen::Index>(patches), true);
    std::size_t next = 0;
    for (std::size_t p = 0; p < patches; ++p)
      if (raw[p]) {
        for (std::size_t b = 0; b < bins; ++b)
          c.observed(static_cast<Eigen::Index>(b), static_cast<Eigen::Index>(p)) = partial[next][b] != 0;
        ++next;
      }
  } else if (n.version >= 3 ? raw.size() != patches : raw.size() != patches + masked * row) {
    throw Error(what + "mask section has the wrong size (the file is corrupted)");
  } else if (masked) {
    c.observed = ObservationMask::Constant(static_cast<Eigen::Index>(bins), static_cast<Eigen::Index>(patches), true);
    std::size_t offset = patches;
    for (std::size_t p = 0; p < patches; ++p) {
      if (!raw[p])
        continue;
      for (std::size_t b = 0; b < bins; ++b)
        c.observed(static_cast<Eigen::Index>(b), static_cast<Eigen::Index>(p)) =
            (static_cast<unsigned char>(raw[offset + b / 8]) & (1u << (b % 8))) != 0;
      offset += row;
    }
  }
}

void readConnectivity(ByteReader& in, const std::string& what, const PdcCounts& n, PdcContent& c)
{
  const std::string raw = getSection(in);
  if (!c.keep_connectivity && !raw.empty())
    throw Error(what + "connectivity section in a file without kept connectivity (the file is corrupted)");
  if (raw.size() < 3 * static_cast<std::size_t>(n.num_faces) + 3 * static_cast<std::size_t>(n.num_places))
    throw Error(what + "connectivity section too short (the file is corrupted)");
  ByteReader section(raw.data(), raw.size(), what);
  std::int64_t last = 0;
  c.faces.resize(n.num_faces);
  for (Face& f : c.faces) {
    last = addDelta(section, last, "face index");
    const std::int64_t second = addDelta(section, last, "face index"), third = addDelta(section, last, "face index");
    const std::int64_t corners[3] = {last, second, third};
    for (int k = 0; k < 3; ++k) {
      if (corners[k] < 0 || corners[k] >= static_cast<std::int64_t>(n.num_places))
        throw Error(what + "face index out of range (the file is corrupted)");
      f[static_cast<std::size_t>(k)] = static_cast<std::int32_t>(corners[k]);
    }
  }
  last = 0;
  const std::uint64_t scale = (std::uint64_t(1) << c.location_bits) - 1;
  c.places.resize(n.num_places);
  for (VertexPlace& place : c.places) {
    last = addDelta(section, last, "vertex place");
    if (last < 0 || last > std::numeric_limits<std::int32_t>::max())
      throw Error(what + "vertex place out of range (the file is corrupted)");
    place.triangle = static_cast<std::int32_t>(last);
    const std::uint64_t u = section.getVarint(), v = section.getVarint();
    if (u > scale || v > scale || u + v > scale)
      throw Error(what + "vertex place out of range (the file is corrupted)");
    place.u = static_cast<std::uint32_t>(u);
    place.v = static_cast<std::uint32_t>(v);
  }
  expectEnd(section, "connectivity");
}

void readCoverage(ByteReader& in, const std::string& what, std::uint32_t patches, PdcContent& c)
{
  const std::string raw = getSection(in);
  ByteReader section(raw.data(), raw.size(), what);
  const std::uint64_t count = section.getVarint();
  if (count >= patches || count > raw.size())
    throw Error(what + "implausible coverage patch count (the file is corrupted)");
  if (count && c.keep_connectivity)
    throw Error(what + "coverage patches in a file with kept connectivity (the file is corrupted)");
  const std::int64_t limit = (std::int64_t(1) << c.position_bits) - 1;
  const std::uint64_t normal_limit = (std::uint64_t(1) << kCoverageNormalBits) - 1,
                      angle_limit = (std::uint64_t(1) << kCoverageAngleBits) - 1;
  std::array<std::int64_t, 3> before{0, 0, 0};
  c.coverage.resize(static_cast<std::size_t>(count));
  for (CoverageFrame& f : c.coverage) {
    for (std::size_t k = 0; k < 3; ++k) {
      before[k] = addDelta(section, before[k], "coverage seed");
      if (before[k] < 0 || before[k] > limit)
        throw Error(what + "coverage seed outside the quantisation grid (the file is corrupted)");
      f.position[k] = static_cast<std::uint32_t>(before[k]);
    }
    const std::uint64_t u = section.getVarint(), v = section.getVarint(), a = section.getVarint();
    if (u > normal_limit || v > normal_limit || a > angle_limit)
      throw Error(what + "coverage frame out of range (the file is corrupted)");
    f.normal_u = static_cast<std::uint32_t>(u);
    f.normal_v = static_cast<std::uint32_t>(v);
    f.angle = static_cast<std::uint32_t>(a);
  }
  expectEnd(section, "coverage");
}

}  // namespace

std::string writePdc(const PdcContent& c, PdcSizes* sizes)
{
  if (!isLittleEndian())
    throw Error("writing .pdc files needs a little-endian machine");
  const std::size_t patches = c.atoms.size(), bins = static_cast<std::size_t>(c.grid_size) * c.grid_size;
  ByteWriter out;
  writeHeader(c, out);
  PdcSizes local;
  local.header = out.bytes().size();
  putSection(out, quadVertexSection(c), &local.quad_vertices);
  putSection(out, quadFaceSection(c), &local.quad_faces);
  putSection(out, signedSection(c.offsets), &local.offsets);

  // The masks of the patches not fully observed (flag 1), gathered once for the check and the section.
  std::string mask_flags(patches, '\0');
  std::vector<std::vector<char>> partial;
  for (std::size_t p = 0; p < patches && c.observed.size() != 0; ++p) {
    const auto column = c.observed.col(static_cast<Eigen::Index>(p));
    if (column.all())
      continue;
    mask_flags[p] = 1;
    partial.emplace_back(bins);
    for (std::size_t b = 0; b < bins; ++b)
      partial.back()[b] = column(static_cast<Eigen::Index>(b)) ? 1 : 0;
  }
  // What the reader accepts (kMaxCodedDecisions): a file it would refuse is not written.
  if (static_cast<std::uint64_t>(patches) * c.num_atoms > kMaxCodedDecisions ||
      static_cast<std::uint64_t>(partial.size()) * bins > kMaxCodedDecisions)
    throw Error("codec: " + std::to_string(patches) + " patches of " + std::to_string(c.num_atoms) +
                " atoms are more than a .pdc file holds (2^26 atom or mask decisions): use a larger quad length");
  putSection(out, encodeAtomSets(c.atoms, c.num_atoms), &local.atoms);
  putSection(out, encodeCoefficients(c.values, c.atoms, c.num_atoms), &local.coefficients);
  putSection(out, signedSection(c.means), &local.means);
  putSection(out, partial.empty() ? mask_flags : mask_flags + encodeMasks(partial, static_cast<int>(c.grid_size)),
             &local.masks);
  putSection(out, connectivitySection(c), &local.connectivity);
  putSection(out, coverageSection(c), &local.coverage);

  const std::uint64_t checksum = fnv1a64(out.bytes().data(), out.bytes().size());
  out.putU64(checksum);
  local.total = out.bytes().size();
  if (sizes)
    *sizes = local;
  return out.bytes();
}

PdcContent readPdc(const std::string& bytes, const std::string& what)
{
  if (!isLittleEndian())
    throw Error("reading .pdc files needs a little-endian machine");
  if (bytes.size() < 8 || bytes.compare(0, 4, std::string(kMagic, 4)) != 0)
    throw Error(what + "not a .pdc file");
  if (bytes.size() < 8 + 8)
    throw Error(what + "data is truncated");
  ByteReader in(bytes.data(), bytes.size() - 8, what);
  char magic[4];
  in.getRaw(magic, 4);
  PdcCounts n;
  n.version = in.getU32();
  if (n.version < kOldestVersion || n.version > kVersion)
    throw Error(what + "format version " + std::to_string(n.version) + " (this build reads versions " +
                std::to_string(kOldestVersion) + " to " + std::to_string(kVersion) + ")");
  std::uint64_t stored;
  std::memcpy(&stored, bytes.data() + bytes.size() - 8, 8);
  if (fnv1a64(bytes.data(), bytes.size() - 8) != stored)
    throw Error(what + "checksum mismatch (the file is truncated or corrupted)");

  PdcContent c;
  readHeader(in, what, c, n);
  readQuadVertices(in, what, n, c);
  readQuadFaces(in, what, n, c);
  readSeedOffsets(in, what, n.patches, c);
  readSparseCodes(in, what, n, c);
  readMeans(in, what, n.patches, c);
  readMasks(in, what, n, c);
  readConnectivity(in, what, n, c);
  readCoverage(in, what, n.patches, c);
  if (!in.atEnd())
    throw Error(what + "unexpected bytes after the last section (the file is corrupted)");
  return c;
}

}  // namespace detail
}  // namespace patchdict
}  // namespace pcl
