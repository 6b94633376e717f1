// PatchCodec (.pdc) on bad data and bad use: crafted, truncated, corrupted and foreign files, decompression
// bombs, other format versions, bad parameters, and the compress/decompress commands' one-line errors.
#include <pcl_patchdict/core/checksum.h>
#include <pcl_patchdict/core/error.h>
#include <pcl_patchdict/patches/height_maps.h>
#include <pcl_patchdict/io/mesh_io.h>
#include <pcl_patchdict/geometry/metrics.h>
#include <pcl_patchdict/core/normalization.h>
#include <pcl_patchdict/codec/patch_codec.h>
#include <pcl_patchdict/quads/patch_layout.h>
#include <pcl_patchdict/quads/quad_subdivision.h>
#include <pcl_patchdict/io/patch_dictionary_io.h>
#include <pcl_patchdict_eval/shapes.h>

#include "test_support.h"

#include "codec_test_fixtures.h"

#include <gtest/gtest.h>

#include <omp.h>

#include <zlib.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <functional>
#include <iterator>

using namespace pcl::patchdict;
using namespace codec_test;
using test_support::q;
using test_support::runTool;

namespace {

/** Another dictionary of the same size: the fixture with atom `which` negated (another fingerprint). */
PatchDictionary::Ptr otherDictionary(int which)
{
  auto other = std::make_shared<PatchDictionary>(*bunnyDictionary());
  Eigen::MatrixXd atoms = other->atoms();
  atoms.col(which) *= -1.0;
  other->setAtoms(atoms);
  return other;
}

}  // namespace

namespace {

void putVarint(std::string& out, std::uint64_t v)
{
  for (; v >= 0x80; v >>= 7)
    out.push_back(static_cast<char>(v | 0x80));
  out.push_back(static_cast<char>(v));
}

void putSigned(std::string& out, std::int64_t v)
{
  putVarint(out, (static_cast<std::uint64_t>(v) << 1) ^ static_cast<std::uint64_t>(v >> 63));
}

/** .pdc bytes whose last section (the coverage frames) is `raw`, deflated, with a valid checksum:
  * what only a crafted file can hold. The fixed header is 136 bytes, then nine sections of
  * (raw size, packed size, packed bytes), then the 8-byte checksum. */
std::string withCoverageSection(const std::string& bytes, const std::string& raw)
{
  std::size_t at = 136;
  const auto u64 = [&](std::size_t offset) {
    std::uint64_t v = 0;
    std::memcpy(&v, bytes.data() + offset, 8);
    return v;
  };
  for (int section = 0; section < 8; ++section)
    at += 16 + static_cast<std::size_t>(u64(at + 8));
  std::string packed(compressBound(raw.size()), '\0');
  uLongf packed_size = packed.size();
  EXPECT_EQ(compress2(reinterpret_cast<Bytef*>(&packed[0]), &packed_size, reinterpret_cast<const Bytef*>(raw.data()),
                      raw.size(), 9),
            Z_OK);
  packed.resize(packed_size);
  std::string out = bytes.substr(0, at);
  for (const std::uint64_t v : {static_cast<std::uint64_t>(raw.size()), static_cast<std::uint64_t>(packed.size())})
    out.append(reinterpret_cast<const char*>(&v), 8);
  out += packed;
  const std::uint64_t sum = fnv1a64(out.data(), out.size());
  out.append(reinterpret_cast<const char*>(&sum), 8);
  return out;
}

}  // namespace

TEST(PatchCodec, RejectsCraftedCoverageSections)
{
  const TriangleMesh sphere = makeIcosphere(3);
  auto dictionary = std::make_shared<PatchDictionary>();
  dictionary->setAtoms(Eigen::MatrixXd::Identity(8 * 8, 8));
  PatchCodec codec;
  codec.setDictionary(dictionary);
  PatchCodecParameters parameters;
  parameters.quad_length = 0.25;
  parameters.coefficients = 2;
  codec.setParameters(parameters);
  PatchCodec::Report report;
  const std::string bytes = codec.encode(sphere, &report);
  ASSERT_EQ(report.coverage_patches, 0u);  // a sphere: the quads reach all of it
  const std::size_t patches = report.patches;
  TriangleMesh out;
  // The rewriting itself keeps a valid file valid: an empty section decodes as before.
  std::string empty;
  putVarint(empty, 0);
  codec.decode(withCoverageSection(bytes, empty), out);
  EXPECT_FALSE(out.faces.empty());
  const auto expectError = [&](const std::string& raw, const std::string& expected) {
    try {
      codec.decode(withCoverageSection(bytes, raw), out);
      ADD_FAILURE() << "accepted; expected an error about '" << expected << "'";
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find(expected), std::string::npos) << e.what();
    }
  };
  const auto frames = [](std::size_t count, std::int64_t delta, std::uint64_t normal) {
    std::string raw;
    putVarint(raw, count);
    for (std::size_t k = 0; k < count; ++k) {
      for (int axis = 0; axis < 3; ++axis)
        putSigned(raw, k == 0 ? 500 : delta);
      putVarint(raw, normal);
      putVarint(raw, normal);
      putVarint(raw, 3);
    }
    return raw;
  };
  expectError(frames(patches, 0, 2047), "implausible coverage patch count");
  expectError(frames(1, 0, 4096), "coverage frame out of range");  // normals have 12 bits
  expectError(frames(2, 600, 2047), "coverage seed outside the quantisation grid");
  expectError(frames(2, std::int64_t(1) << 62, 2047), "implausible coverage seed");  // no overflow
  // One frame more than the patches the file codes: the quad mesh then gives too few.
  expectError(frames(1, 0, 2047), "the file codes");
}

TEST(PatchCodec, KeptConnectivityIsTheInputsAndCostsBytes)
{
  const TriangleMesh bunny = loadBunny();
  PatchCodec codec = bunnyCodec();
  PatchCodecParameters parameters = bunnyParameters();
  parameters.coverage_tolerance = 0.0;  // kept connectivity has none: compare like with like
  codec.setParameters(parameters);
  PatchCodec::Report self_contained;
  const std::size_t plain_size = codec.encode(bunny, &self_contained).size();
  parameters.keep_connectivity = true;
  codec.setParameters(parameters);
  PatchCodec::Report report;
  const std::string bytes = codec.encode(bunny, &report);
  EXPECT_GT(bytes.size(), plain_size);
  EXPECT_EQ(report.total_bytes - report.connectivity_bytes,
            self_contained.total_bytes - self_contained.connectivity_bytes);
  TriangleMesh decoded;
  codec.decode(bytes, decoded);
  ASSERT_EQ(decoded.vertices.size(), bunny.vertices.size());
  EXPECT_TRUE(decoded.faces == bunny.faces);
  const SurfaceDistance distance = surfaceDistance(bunny, decoded, 50000, 1);
  EXPECT_GT(distance.psnr, 62.0);  // measured 65.7 dB
  RecordProperty("psnr_kept", std::to_string(distance.psnr));
  RecordProperty("vertex_rmse_over_diagonal", std::to_string(vertexRMSE(bunny, decoded) / distance.bbox_diagonal));
  // Each vertex comes back near its own place (along the surface too), not just near the surface.
  EXPECT_LT(vertexRMSE(bunny, decoded), 0.01 * distance.bbox_diagonal);
}

TEST(PatchCodec, RejectsTruncatedCorruptedAndForeignData)
{
  const TriangleMesh bunny = loadBunny();
  const auto dictionary = bunnyDictionary();
  PatchCodec codec;
  codec.setDictionary(dictionary);
  codec.setParameters(bunnyParameters());
  const std::string bytes = codec.encode(bunny);
  TriangleMesh out;
  for (const std::size_t size : {std::size_t(0), std::size_t(3), std::size_t(20), std::size_t(100), bytes.size() / 2,
                                 bytes.size() - 9, bytes.size() - 1})
    EXPECT_THROW(codec.decode(bytes.substr(0, size), out, nullptr, "'x.pdc': "), Error) << "prefix of " << size;
  EXPECT_THROW(codec.decode(bytes + "x", out), Error);
  for (const std::size_t at : {std::size_t(5), std::size_t(40), bytes.size() / 3, bytes.size() - 20}) {
    std::string corrupted = bytes;
    corrupted[at] = static_cast<char>(corrupted[at] ^ 0x21);
    try {
      codec.decode(corrupted, out, nullptr, "'x.pdc': ");
      ADD_FAILURE() << "a flipped byte at " << at << " was accepted";
    } catch (const Error& e) {
      const std::string message = e.what();
      EXPECT_EQ(message.find("'x.pdc': "), 0u) << message;
      EXPECT_EQ(message.find('\n'), std::string::npos);
    }
  }
  try {
    codec.decode("GARBAGE!GARBAGE!", out);
    ADD_FAILURE() << "garbage accepted";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("not a .pdc file"), std::string::npos) << e.what();
  }
  // Another dictionary (same size, other seed) is refused by its fingerprint.
  PatchCodec other;
  other.setDictionary(otherDictionary(2));
  try {
    other.decode(bytes, out);
    ADD_FAILURE() << "decoded with another dictionary";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("another dictionary"), std::string::npos) << e.what();
  }
}

TEST(PatchCodec, RejectsBadParametersAndInputs)
{
  const TriangleMesh bunny = loadBunny();
  PatchCodec codec;
  // Each case must fail for its own reason: the message names it.
  const auto expectError = [&](const TriangleMesh& mesh, const std::string& expected) {
    try {
      codec.encode(mesh);
      ADD_FAILURE() << "accepted; expected an error about '" << expected << "'";
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find(expected), std::string::npos) << e.what();
    }
  };
  expectError(bunny, "needs a patch dictionary");
  auto dictionary = std::make_shared<PatchDictionary>();
  dictionary->setAtoms(Eigen::MatrixXd::Identity(256, 32));  // 32 atoms: the default 20 coefficients fit
  codec.setDictionary(dictionary);
  // Each a bad value of one parameter, the others the bunny's.
  const std::vector<std::pair<std::function<void(PatchCodecParameters&)>, std::string>> bad_values = {
      {[](auto& p) { p.coefficients = 33; }, "coefficients per patch must be in [1, 32]"},
      {[](auto& p) { p.coefficient_bits = 1; }, "coefficient bits"},
      {[](auto& p) { p.patch_scale = 5.0; }, "patch scale"},
      {[](auto& p) { p.target_error = 2.0; }, "target error"},
      {[](auto& p) { p.coverage_tolerance = -0.1; }, "coverage tolerance"},
      {[](auto& p) { p.coverage_budget = std::nan(""); }, "coverage budget"},
      {[](auto& p) { p.quad_length = 0.9; }, "quad"}};  // coarser than the shape
  for (const auto& [set, message] : bad_values) {
    PatchCodecParameters parameters = bunnyParameters();
    set(parameters);
    codec.setParameters(parameters);
    expectError(bunny, message);
  }
  codec.setParameters(bunnyParameters());
  TriangleMesh cloud = bunny;
  cloud.faces.clear();
  expectError(cloud, "no faces");
  // The same codec and parameters accept the mesh itself: the failures above were the cases'.
  EXPECT_GT(codec.encode(bunny).size(), 100u);
}

TEST(PatchCodec, CommandsCompressDecompressAndFailInOneLine)
{
  test_support::TempDir dir;
  const TriangleMesh bunny = loadBunny();
  savePatchDictionary(dir.file("dict.pdd"), *bunnyDictionary());
  const std::string input = test_support::dataDir() + "/bunny.obj";
  const std::string before = test_support::readFile(input);
  auto result = runTool("compress " + q(input) + " --dict " + q(dir.file("dict.pdd")) + " -o " +
                        q(dir.file("b.pdc")) + " --quad-length 0.064 --coefficients 12 --json");
  ASSERT_EQ(result.exit_code, 0) << result.err;
  EXPECT_GT(test_support::jsonNumber(result.out, "psnr"), 62.0);
  EXPECT_GT(test_support::jsonNumber(result.out, "byte_factor"), 50.0);
  EXPECT_GT(test_support::jsonNumber(result.out, "entity_factor"), 5.0);
  EXPECT_EQ(test_support::jsonNumber(result.out, "bytes"),
            static_cast<double>(test_support::readFile(dir.file("b.pdc")).size()));
  EXPECT_TRUE(test_support::readFile(input) == before);

  result = runTool("decompress " + q(dir.file("b.pdc")) + " --dict " + q(dir.file("dict.pdd")) + " -o " +
                   q(dir.file("b.ply")) + " --ref " + q(input) + " --png " + q(dir.file("b.png")) + " --json");
  ASSERT_EQ(result.exit_code, 0) << result.err;
  EXPECT_GT(test_support::jsonNumber(result.out, "psnr"), 62.0);
  EXPECT_LT(test_support::jsonNumber(result.out, "coverage_faces"), test_support::jsonNumber(result.out, "faces"));
  EXPECT_EQ(test_support::readFile(dir.file("b.png")).substr(0, 8), std::string("\x89PNG\r\n\x1a\n", 8));

  // A truncated file and another dictionary: one line, exit 1, no output.
  const std::string bytes = test_support::readFile(dir.file("b.pdc"));
  test_support::writeFile(dir.file("cut.pdc"), bytes.substr(0, bytes.size() / 2));
  result = runTool("decompress " + q(dir.file("cut.pdc")) + " --dict " + q(dir.file("dict.pdd")) + " -o " +
                   q(dir.file("cut.ply")));
  EXPECT_EQ(result.exit_code, 1);
  EXPECT_TRUE(test_support::endsWithOneErrorLine(result.err)) << result.err;
  EXPECT_EQ(test_support::readFile(dir.file("cut.ply")), "");
  savePatchDictionary(dir.file("other.pdd"), *otherDictionary(3));
  result = runTool("decompress " + q(dir.file("b.pdc")) + " --dict " + q(dir.file("other.pdd")) + " -o " +
                   q(dir.file("o.ply")));
  EXPECT_EQ(result.exit_code, 1);
  EXPECT_NE(result.err.find("another dictionary"), std::string::npos) << result.err;
  EXPECT_EQ(test_support::readFile(dir.file("o.ply")), "");
  // Missing --dict is a usage error.
  result = runTool("compress " + q(input) + " -o " + q(dir.file("x.pdc")));
  EXPECT_EQ(result.exit_code, 2);
}

// A few kilobytes must not make the decoder build a mesh of hundreds of millions of vertices: a
// valid file asking for 256 splits per quad side on ~1000 quads is refused before allocating.
TEST(PatchCodec, RefusesDecompressionBombs)
{
  // A file may ask for at most as many splits per quad side as its patches have bins: more would
  // only interpolate, and let a few hundred bytes ask for millions of vertices (a fuzzing
  // finding: 890 bytes asking for 255 splits decoded to 2M vertices in 13 s).
  const TriangleMesh sphere = makeIcosphere(4);
  Eigen::MatrixXd atoms = Eigen::MatrixXd::Identity(16 * 16, 16);
  auto dictionary = std::make_shared<PatchDictionary>();
  dictionary->setAtoms(atoms);
  PatchCodec codec;
  codec.setDictionary(dictionary);
  PatchCodecParameters parameters;
  parameters.quad_length = 0.05;
  parameters.coefficients = 2;
  parameters.subdivision = 17;
  codec.setParameters(parameters);
  try {
    codec.encode(sphere);
    ADD_FAILURE() << "the encoder accepted 17 splits with a 16x16 dictionary";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("subdivision must be in [0, 16]"), std::string::npos) << e.what();
  }
  parameters.subdivision = 16;
  codec.setParameters(parameters);
  const std::string bytes = codec.encode(sphere);
  TriangleMesh out;
  codec.decode(bytes, out);
  EXPECT_GT(out.vertices.size(), 1000u);
  // The same file with 255 splits in its header (offset 92) and a valid checksum: refused before
  // anything is decoded.
  std::string crafted = bytes.substr(0, bytes.size() - 8);
  const std::uint32_t splits = 255;
  std::memcpy(&crafted[92], &splits, 4);
  const std::uint64_t sum = fnv1a64(crafted.data(), crafted.size());
  crafted.append(reinterpret_cast<const char*>(&sum), 8);
  TriangleMesh bomb;
  try {
    codec.decode(crafted, bomb);
    ADD_FAILURE() << "decoded 255 splits per quad side";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("implausible header"), std::string::npos) << e.what();
  }
  EXPECT_TRUE(bomb.vertices.empty());
}

TEST(PatchCodec, ReadsFormatVersion2AndRefusesOtherVersions)
{
  // Version 3 changed only how atom sets, coefficients and masks are coded; version-2 files
  // (deflated bitmaps and byte planes) still decode — the fuzz corpus's sphere with a coverage
  // patch, written by the version-2 encoder, gives what that build decoded (510 vertices, 1000
  // faces, one coverage piece of 8 faces, coordinates summing to (8.16671418, -0.06448679,
  // -0.33471924), |coordinates| to 765.2799970).
  const std::string source = PCL_PATCHDICT_TEST_DATA_DIR "/../../fuzz/";
  PatchCodec codec;
  codec.setDictionary(loadPatchDictionary(source + "pdc_dictionary.pdd"));
  std::ifstream file(source + "corpus/pdc/sphere_pin_coverage.pdc", std::ios::binary);
  const std::string version2((std::istreambuf_iterator<char>(file)), std::istreambuf_iterator<char>());
  ASSERT_EQ(version2.substr(0, 5), std::string("PDCv\x02"));
  TriangleMesh decoded;
  PatchCodec::Report report;
  codec.decode(version2, decoded, &report);
  EXPECT_EQ(decoded.vertices.size(), 510u);
  EXPECT_EQ(decoded.faces.size(), 1000u);
  EXPECT_EQ(report.coverage_patches, 1u);
  EXPECT_EQ(report.coverage_faces, 8u);
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  double absolute = 0.0;
  for (const auto& v : decoded.vertices) {
    sum += v;
    absolute += v.cwiseAbs().sum();
  }
  EXPECT_NEAR(sum.x(), 8.16671418, 1e-7);
  EXPECT_NEAR(sum.y(), -0.06448679, 1e-7);
  EXPECT_NEAR(sum.z(), -0.33471924, 1e-7);
  EXPECT_NEAR(absolute, 765.2799970, 1e-6);
  // The same bytes claiming versions 1 and 4 (valid checksums): refused by version.
  for (const std::uint32_t version : {1u, 4u}) {
    std::string crafted = version2.substr(0, version2.size() - 8);
    std::memcpy(&crafted[4], &version, 4);
    const std::uint64_t sum = fnv1a64(crafted.data(), crafted.size());
    crafted.append(reinterpret_cast<const char*>(&sum), 8);
    try {
      codec.decode(crafted, decoded);
      ADD_FAILURE() << "decoded a version-" << version << " file";
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find("format version " + std::to_string(version)), std::string::npos) << e.what();
    }
  }
}
