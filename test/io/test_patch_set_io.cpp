// The .pds format (io/patch_set_io.h): round trip bit for bit, rejection of damaged files with one line,
// PNG output; and PatchSet::append, which shares the sample set.
#include <pcl_patchdict/core/checksum.h>
#include <pcl_patchdict/core/error.h>
#include <pcl_patchdict/patches/height_maps.h>
#include <pcl_patchdict/coding/patch_dictionary.h>
#include <pcl_patchdict/patches/patch_set.h>
#include <pcl_patchdict/io/patch_dictionary_io.h>
#include <pcl_patchdict/io/patch_set_io.h>
#include <pcl_patchdict_eval/shapes.h>

#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include <cstring>
#include <random>

#include "test_support.h"

using namespace pcl::patchdict;

namespace {

// A set with partly observed patches (seeds near the relief's border), random frames and sources.
PatchSet samplePatchSet()
{
  const auto relief = makeSinusoidalRelief(40, 40, 0.03, 0.4);
  std::mt19937_64 random(3);
  std::uniform_int_distribution<std::size_t> pick(0, relief.numVertices() - 1);
  std::uniform_real_distribution<double> angle(-0.4, 0.4);
  std::vector<Eigen::Vector3d> seeds;
  std::vector<Eigen::Matrix3d> frames;
  for (int k = 0; k < 37; ++k) {
    seeds.push_back(relief.vertices[pick(random)]);
    const Eigen::Matrix3d rows = (Eigen::AngleAxisd(angle(random) * 7.0, Eigen::Vector3d::UnitZ()) *
                                  Eigen::AngleAxisd(angle(random), Eigen::Vector3d::UnitY()))
                                     .toRotationMatrix()
                                     .transpose();
    frames.push_back(roundToSinglePrecision(rows));
  }
  HeightMapParameters parameters;
  parameters.radius = 0.12;
  parameters.grid_size = 12;
  PatchSet set;
  extractMeshHeightMaps(relief, seeds, frames, parameters, set);
  for (std::size_t p = 0; p < set.source.size(); ++p)
    set.source[p] = static_cast<std::int32_t>(p % 5) - 1;
  return set;
}

void expectOneLineError(const std::string& path, const std::string& needle = "")
{
  try {
    loadPatchSet(path);
    ADD_FAILURE() << "loaded a damaged file";
  } catch (const Error& error) {
    const std::string message = error.what();
    EXPECT_EQ(message.find('\n'), std::string::npos) << message;
    if (!needle.empty()) {
      EXPECT_NE(message.find(needle), std::string::npos) << message;
    }
  }
}

// Rewrites the trailing checksum so that only the intended damage is seen.
void fixChecksum(std::string& bytes)
{
  const std::uint64_t checksum = fnv1a64(bytes.data(), bytes.size() - 8);
  std::memcpy(&bytes[bytes.size() - 8], &checksum, 8);
}

}  // namespace

TEST(PatchSetIO, RoundTripIsBitExact)
{
  test_support::TempDir dir;
  const PatchSet set = samplePatchSet();
  ASSERT_GT(set.observedFraction(), 0.2);
  ASSERT_LT(set.observedFraction(), 1.0);  // the mask matters in this round trip
  savePatchSet(dir.file("a.pds"), set);
  const PatchSet loaded = loadPatchSet(dir.file("a.pds"));
  EXPECT_EQ(loaded.grid_size, set.grid_size);
  EXPECT_EQ(std::memcmp(&loaded.radius, &set.radius, sizeof(double)), 0);
  ASSERT_EQ(loaded.numPatches(), set.numPatches());
  EXPECT_EQ(std::memcmp(loaded.heights.data(), set.heights.data(), sizeof(double) * set.heights.size()), 0);
  EXPECT_EQ(loaded.observed, set.observed);
  EXPECT_EQ(loaded.source, set.source);
  for (std::size_t p = 0; p < set.numPatches(); ++p) {
    EXPECT_EQ(std::memcmp(loaded.seeds[p].data(), set.seeds[p].data(), 3 * sizeof(double)), 0);
    EXPECT_EQ(std::memcmp(loaded.rotations[p].data(), set.rotations[p].data(), 9 * sizeof(double)), 0);
  }
  savePatchSet(dir.file("b.pds"), loaded);
  EXPECT_EQ(test_support::readFile(dir.file("a.pds")), test_support::readFile(dir.file("b.pds")));
  EXPECT_DOUBLE_EQ(loaded.observedFraction(), set.observedFraction());
}

TEST(PatchSetIO, EmptySetRoundTrips)
{
  test_support::TempDir dir;
  PatchSet set;
  set.grid_size = 16;
  set.radius = 0.02;
  set.heights.resize(256, 0);
  set.observed.resize(256, 0);
  savePatchSet(dir.file("e.pds"), set);
  const PatchSet loaded = loadPatchSet(dir.file("e.pds"));
  EXPECT_EQ(loaded.numPatches(), 0u);
  EXPECT_EQ(loaded.grid_size, 16);
  EXPECT_EQ(loaded.observedFraction(), 0.0);
}

TEST(PatchSetIO, TruncatedFilesAreRejected)
{
  test_support::TempDir dir;
  savePatchSet(dir.file("a.pds"), samplePatchSet());
  const std::string bytes = test_support::readFile(dir.file("a.pds"));
  for (const std::size_t length : {std::size_t{0}, std::size_t{5}, std::size_t{39}, std::size_t{47}, std::size_t{48},
                                   std::size_t{1000}, bytes.size() / 2, bytes.size() - 9, bytes.size() - 1}) {
    test_support::writeFile(dir.file("t.pds"), bytes.substr(0, length));
    SCOPED_TRACE(length);
    expectOneLineError(dir.file("t.pds"));
  }
  test_support::writeFile(dir.file("long.pds"), bytes + "x");
  expectOneLineError(dir.file("long.pds"), "unexpected bytes");
}

TEST(PatchSetIO, CorruptedOrMismatchedFilesAreRejected)
{
  test_support::TempDir dir;
  savePatchSet(dir.file("a.pds"), samplePatchSet());
  const std::string bytes = test_support::readFile(dir.file("a.pds"));

  std::string flipped = bytes;
  flipped[bytes.size() / 2] ^= 0x10;
  test_support::writeFile(dir.file("flip.pds"), flipped);
  expectOneLineError(dir.file("flip.pds"), "checksum");

  std::string magic = bytes;
  magic[3] = 'X';
  test_support::writeFile(dir.file("magic.pds"), magic);
  expectOneLineError(dir.file("magic.pds"), "not a .pds file");

  std::string version = bytes;
  version[8] = 9;
  fixChecksum(version);
  test_support::writeFile(dir.file("version.pds"), version);
  expectOneLineError(dir.file("version.pds"), "version 9");

  // A dictionary is not a patch set.
  PatchDictionary dictionary;
  dictionary.setAtoms(Eigen::MatrixXd::Identity(4, 4));
  savePatchDictionary(dir.file("d.pdd"), dictionary);
  expectOneLineError(dir.file("d.pdd"), "not a .pds file");
}

TEST(PatchSetIO, ImplausibleHeadersAreRejectedBeforeAllocating)
{
  test_support::TempDir dir;
  savePatchSet(dir.file("a.pds"), samplePatchSet());
  const std::string bytes = test_support::readFile(dir.file("a.pds"));
  // Header: magic[8], version u32 @8, grid u32 @12, patches u64 @16, radius f64 @24, reserved @32.
  auto withField = [&](std::size_t offset, const void* value, std::size_t size) {
    std::string damaged = bytes;
    std::memcpy(&damaged[offset], value, size);
    fixChecksum(damaged);
    return damaged;
  };
  const std::uint64_t huge_count = std::uint64_t{1} << 60;
  test_support::writeFile(dir.file("count.pds"), withField(16, &huge_count, 8));
  expectOneLineError(dir.file("count.pds"), "implausible");
  const std::uint64_t max_count = ~std::uint64_t{0};
  test_support::writeFile(dir.file("max.pds"), withField(16, &max_count, 8));
  expectOneLineError(dir.file("max.pds"), "implausible");
  const std::uint32_t huge_grid = 1u << 20;
  test_support::writeFile(dir.file("grid.pds"), withField(12, &huge_grid, 4));
  expectOneLineError(dir.file("grid.pds"), "implausible");
  const std::uint32_t zero_grid = 0;
  test_support::writeFile(dir.file("grid0.pds"), withField(12, &zero_grid, 4));
  expectOneLineError(dir.file("grid0.pds"), "implausible");
  const double negative_radius = -0.5;
  test_support::writeFile(dir.file("radius.pds"), withField(24, &negative_radius, 8));
  expectOneLineError(dir.file("radius.pds"), "implausible");
  // A mask byte other than 0/1, with a valid checksum: the payload is checked too.
  const PatchSet set = samplePatchSet();
  const std::size_t mask_offset = 40 + set.numPatches() * (3 + 9) * 8 + static_cast<std::size_t>(set.heights.size()) * 8;
  const std::uint8_t two = 2;
  test_support::writeFile(dir.file("mask.pds"), withField(mask_offset, &two, 1));
  expectOneLineError(dir.file("mask.pds"), "mask");
}

TEST(PatchSetIO, SaveRejectsInconsistentSets)
{
  test_support::TempDir dir;
  PatchSet set = samplePatchSet();
  set.source.pop_back();
  EXPECT_THROW(savePatchSet(dir.file("x.pds"), set), Error);
  set = samplePatchSet();
  set.heights(0, 0) = std::nan("");
  EXPECT_THROW(savePatchSet(dir.file("x.pds"), set), Error);
  EXPECT_TRUE(test_support::readFile(dir.file("x.pds")).empty());
}

TEST(PatchSetOps, AppendConcatenatesPatches)
{
  const PatchSet a = samplePatchSet();
  PatchSet both;
  both.append(a);
  both.append(a);
  ASSERT_EQ(both.numPatches(), 2 * a.numPatches());
  EXPECT_TRUE((both.heights.rightCols(a.heights.cols()).array() == a.heights.array()).all());
  EXPECT_EQ(both.observed.leftCols(a.observed.cols()), a.observed);
  EXPECT_DOUBLE_EQ(both.observedFraction(), a.observedFraction());
  PatchSet other = a;
  other.radius *= 2.0;
  EXPECT_THROW(both.append(other), Error);
}

TEST(PatchSetPNG, WritesAPNGContactSheet)
{
  test_support::TempDir dir;
  const PatchSet set = samplePatchSet();
  savePatchSetPNG(dir.file("sheet.png"), set, 8);
  const std::string png = test_support::readFile(dir.file("sheet.png"));
  ASSERT_GT(png.size(), 8u);
  EXPECT_EQ(png.substr(0, 8), std::string("\x89PNG\r\n\x1a\n", 8));
  PatchSet empty;
  empty.grid_size = 4;
  empty.radius = 1.0;
  empty.heights.resize(16, 0);
  empty.observed.resize(16, 0);
  EXPECT_THROW(savePatchSetPNG(dir.file("none.png"), empty), Error);
}
