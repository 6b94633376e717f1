// PatchCodec (.pdc) and quad subdivision: round trips with error bounds, determinism, and rejection
// of truncated, corrupted and mismatched data.
#include <pcl_patchdict/core/error.h>
#include <pcl_patchdict/patches/height_map_patch_extractor.h>
#include <pcl_patchdict/io/mesh_io.h>
#include <pcl_patchdict/geometry/metrics.h>
#include <pcl_patchdict/core/normalization.h>
#include <pcl_patchdict/codec/patch_codec.h>
#include <pcl_patchdict/quads/patch_layout.h>
#include <pcl_patchdict/quads/quad_subdivision.h>
#include <pcl_patchdict/eval/shapes.h>

#include "test_support.h"

#include <gtest/gtest.h>

#include <omp.h>

#include <zlib.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <iterator>

using namespace pcl::patchdict;
using test_support::q;
using test_support::runTool;

namespace {

TriangleMesh loadBunny()
{
  TriangleMesh bunny;
  readMesh(test_support::dataDir() + "/bunny.obj", bunny);
  return bunny;
}

/** The bunny's patches the codec tests' dictionary is learned from: 16×16 of side 0.08 on its
  * quad layout (unit cube). */
PatchSet bunnyPatches(const TriangleMesh& bunny)
{
  TriangleMesh unit = bunny;
  UnitCubeNormalization::fromMesh(unit).apply(unit);
  PatchLayoutParameters layout_parameters;
  layout_parameters.quad_length = 0.08;
  PatchLayout layout;
  computePatchLayout(unit, layout_parameters, layout);
  HeightMapPatchExtractor extractor;
  extractor.setInputMesh(std::make_shared<const TriangleMesh>(unit));
  extractor.setSeeds(layout.seeds, layout.frames);
  extractor.setRadius(0.08 / std::sqrt(2.0));
  extractor.setGridSize(16);
  PatchSet patches;
  extractor.compute(patches);
  return patches;
}

/** A local dictionary of the bunny: 48 atoms, K-SVD (sparsity 8, 5 iterations) on bunnyPatches. */
PatchDictionary::Ptr learnBunnyDictionary(const TriangleMesh& bunny, std::uint64_t seed = 1)
{
  const PatchSet patches = bunnyPatches(bunny);
  auto dictionary = std::make_shared<PatchDictionary>();
  dictionary->setNumAtoms(48);
  dictionary->setSparsity(8);
  dictionary->setIterations(5);
  dictionary->setSeed(seed);
  dictionary->learn(patches.heights, patches.observed);
  return dictionary;
}

std::string bunnyDictionaryPath() { return test_support::testDataDir() + "/bunny_local48.pdd"; }

/** learnBunnyDictionary(bunny, 1) as stored in test/data, so that the codec tests do not each learn
  * it again; FixtureDictionaryIsTheBunnysOwn learns it once (1.8 s, 23.8 s under the sanitizers,
  * learning and checking), checks the fixture and rewrites it with PCL_PATCHDICT_WRITE_FIXTURES=1. */
PatchDictionary::Ptr bunnyDictionary() { return PatchDictionary::load(bunnyDictionaryPath(), 16); }

/** Another dictionary of the same size: the fixture with atom `which` negated (another fingerprint). */
PatchDictionary::Ptr otherDictionary(int which)
{
  auto other = std::make_shared<PatchDictionary>(*bunnyDictionary());
  Eigen::MatrixXd atoms = other->atoms();
  atoms.col(which) *= -1.0;
  other->setAtoms(atoms);
  return other;
}

PatchCodecParameters bunnyParameters()
{
  PatchCodecParameters parameters;
  parameters.quad_length = 0.064;  // patch side 0.08
  parameters.coefficients = 12;
  return parameters;
}

}  // namespace

TEST(QuadSubdivision, SharesEdgePointsAndKeepsTheArea)
{
  // Two unit quads side by side in the plane z = 0, and a triangle and a pentagon beside them.
  QuadMesh quads;
  quads.vertices = {{0, 0, 0}, {1, 0, 0}, {2, 0, 0}, {0, 1, 0}, {1, 1, 0}, {2, 1, 0}};
  quads.faces = {{0, 1, 4, 3}, {1, 2, 5, 4}};
  const TriangleMesh fine = subdivideQuadMesh(quads, 3);
  // 6 corners, 7 edges × 2 inner points, 2 × 4 interior points; 2 × 9 cells × 2 triangles.
  EXPECT_EQ(fine.vertices.size(), 6u + 14u + 8u);
  EXPECT_EQ(fine.faces.size(), 36u);
  EXPECT_NEAR(fine.surfaceArea(), 2.0, 1e-12);
  for (std::size_t f = 0; f < fine.faces.size(); ++f)
    EXPECT_GT(fine.faceNormal(f).z(), 0.99);  // orientation kept

  QuadMesh mixed;
  mixed.vertices = {{0, 0, 0}, {1, 0, 0}, {0.5, 1, 0}, {2, 0.5, 0}, {1.5, 1.5, 0}, {0.8, 1.6, 0}};
  mixed.faces = {{0, 1, 2}, {1, 3, 4, 5, 2}};
  const TriangleMesh split = subdivideQuadMesh(mixed, 2);
  // Triangle: 4 triangles; pentagon: 5 fan triangles × 4. Shared edge 1–2 has one point.
  EXPECT_EQ(split.faces.size(), 4u + 20u);
  const double area_triangle = 0.5, area_pentagon = [&] {
    double a = 0.0;
    const std::vector<int> ring{1, 3, 4, 5, 2};
    for (std::size_t k = 0; k < ring.size(); ++k) {
      const auto& p = mixed.vertices[static_cast<std::size_t>(ring[k])];
      const auto& r = mixed.vertices[static_cast<std::size_t>(ring[(k + 1) % ring.size()])];
      a += 0.5 * (p.x() * r.y() - r.x() * p.y());
    }
    return a;
  }();
  EXPECT_NEAR(split.surfaceArea(), area_triangle + area_pentagon, 1e-12);
  // Besides the 6 corners and the pentagon's centre, one point per edge: the triangle's 3 (one
  // shared with the pentagon), the pentagon's 4 others and its 5 spokes.
  EXPECT_EQ(split.vertices.size() - 6 - 1, 3u + 4u + 5u);
  EXPECT_THROW(subdivideQuadMesh(mixed, 0), Error);
}

TEST(PatchCodec, FixtureDictionaryIsTheBunnysOwn)
{
  // The stored dictionary codes the bunny's patches as well as one learned now by the same recipe
  // (K-SVD may differ in the last bits between builds, so the check is on what it does).
  const TriangleMesh bunny = loadBunny();
  const auto learned = learnBunnyDictionary(bunny);
  if (std::getenv("PCL_PATCHDICT_WRITE_FIXTURES"))
    learned->save(bunnyDictionaryPath());
  const auto stored = bunnyDictionary();
  ASSERT_EQ(stored->atoms().cols(), 48);
  const PatchSet patches = bunnyPatches(bunny);
  const auto rmse = [&](const PatchDictionary& d) {
    return observedRMSE(d.decode(d.encodeMasked(patches.heights, patches.observed, {8, 0.0})), patches.heights,
                        patches.observed);
  };
  const double stored_rmse = rmse(*stored), learned_rmse = rmse(*learned);
  RecordProperty("stored_rmse", std::to_string(stored_rmse));
  EXPECT_LT(std::abs(stored_rmse - learned_rmse), 0.05 * learned_rmse) << stored_rmse << " vs " << learned_rmse;
  // And far better than a dictionary of the same size that knows nothing of the bunny.
  PatchDictionary identity;
  identity.setAtoms(Eigen::MatrixXd::Identity(256, 48));
  EXPECT_LT(stored_rmse, 0.5 * rmse(identity));
}

TEST(PatchCodec, BunnyRoundTripIsSmallAccurateAndDeterministic)
{
  const TriangleMesh bunny = loadBunny();
  PatchCodec codec;
  codec.setDictionary(bunnyDictionary());
  codec.setParameters(bunnyParameters());
  PatchCodec::Report report;
  const std::string bytes = codec.encode(bunny, &report);
  EXPECT_EQ(bytes.size(), report.total_bytes);
  EXPECT_GT(report.patches, 300u);
  EXPECT_LE(report.nonzeros, 12u * report.patches);
  EXPECT_EQ(report.header_bytes + report.quad_vertex_bytes + report.quad_face_bytes + report.offset_bytes +
                report.atom_bytes + report.coefficient_bytes + report.mean_bytes + report.mask_bytes +
                report.connectivity_bytes + report.coverage_bytes,
            report.total_bytes);
  // Float32 positions and int32 indices would take 12 V + 12 F bytes: at least 80 times more (102×).
  const double raw_bytes = 12.0 * static_cast<double>(bunny.vertices.size() + bunny.faces.size());
  EXPECT_GT(raw_bytes / static_cast<double>(bytes.size()), 80.0);

  TriangleMesh decoded;
  codec.decode(bytes, decoded);
  const SurfaceDistance distance = surfaceDistance(bunny, decoded, 50000, 1);
  EXPECT_GT(distance.psnr, 62.0) << "rms " << distance.rms;  // measured 64.8 dB (12.4 kB)
  RecordProperty("psnr", std::to_string(distance.psnr));
  RecordProperty("bytes", std::to_string(bytes.size()));
  EXPECT_LT(distance.hausdorff, 0.05 * distance.bbox_diagonal);

  // Same input, parameters and dictionary: same bytes, with one thread or two; same decoded mesh.
  const int threads = omp_get_max_threads();
  omp_set_num_threads(1);
  const std::string again = codec.encode(bunny);
  TriangleMesh decoded_again;
  codec.decode(again, decoded_again);
  omp_set_num_threads(threads);
  EXPECT_TRUE(again == bytes);
  ASSERT_EQ(decoded_again.vertices.size(), decoded.vertices.size());
  EXPECT_TRUE(decoded_again.vertices == decoded.vertices);
  EXPECT_TRUE(decoded_again.faces == decoded.faces);

  // Through a file.
  test_support::TempDir dir;
  codec.compress(bunny, dir.file("bunny.pdc"));
  EXPECT_TRUE(test_support::readFile(dir.file("bunny.pdc")) == bytes);
  TriangleMesh from_file;
  codec.decompress(dir.file("bunny.pdc"), from_file);
  EXPECT_TRUE(from_file.vertices == decoded.vertices);
}

TEST(PatchCodec, CoveragePatchesReachThePartsTheQuadsMiss)
{
  // At L = 0.1 the bunny's quad mesh does not reach all of its ears: without coverage patches the
  // decoded surface misses them (the reference-to-output distance is large there).
  const TriangleMesh bunny = loadBunny();
  PatchCodec codec;
  codec.setDictionary(bunnyDictionary());
  PatchCodecParameters parameters = bunnyParameters();
  parameters.quad_length = 0.1;
  parameters.coverage_tolerance = 0.0;
  codec.setParameters(parameters);
  PatchCodec::Report without_report, with_report;
  const std::string without = codec.encode(bunny, &without_report);
  EXPECT_EQ(without_report.coverage_patches, 0u);
  parameters.coverage_tolerance = PatchCodecParameters().coverage_tolerance;
  codec.setParameters(parameters);
  const std::string with = codec.encode(bunny, &with_report);
  EXPECT_GT(with_report.coverage_patches, 0u);
  EXPECT_GT(with_report.coverage_bytes, 0u);
  EXPECT_EQ(with_report.patches, without_report.patches + with_report.coverage_patches);
  EXPECT_LT(with.size(), without.size() * 13 / 10);
  // Same bytes with one thread (the greedy choice, the sampling and the codes do not depend on it).
  const int threads = omp_get_max_threads();
  omp_set_num_threads(1);
  const std::string again = codec.encode(bunny);
  omp_set_num_threads(threads);
  EXPECT_TRUE(again == with);

  TriangleMesh decoded_without, decoded_with;
  codec.decode(without, decoded_without);
  PatchCodec::Report decoded_report;
  codec.decode(with, decoded_with, &decoded_report);
  EXPECT_EQ(decoded_report.coverage_patches, with_report.coverage_patches);
  // The quad mesh's surface is the same; the coverage pieces come after it, every vertex of them
  // in a face.
  ASSERT_GT(decoded_with.faces.size(), decoded_without.faces.size());
  for (std::size_t v = 0; v < decoded_without.vertices.size(); ++v)
    ASSERT_TRUE(decoded_with.vertices[v] == decoded_without.vertices[v]) << v;
  for (std::size_t f = 0; f < decoded_without.faces.size(); ++f)
    ASSERT_TRUE(decoded_with.faces[f] == decoded_without.faces[f]) << f;
  std::vector<char> used(decoded_with.vertices.size(), 0);
  for (const Face& f : decoded_with.faces)
    for (const std::int32_t v : f)
      used[static_cast<std::size_t>(v)] = 1;
  EXPECT_EQ(std::count(used.begin(), used.end(), 0), 0);
  const SurfaceDistance d0 = surfaceDistance(bunny, decoded_without, 50000, 1);
  const SurfaceDistance d1 = surfaceDistance(bunny, decoded_with, 50000, 1);
  RecordProperty("psnr_without", std::to_string(d0.psnr));
  RecordProperty("psnr_with", std::to_string(d1.psnr));
  std::printf("coverage: %zu patches, %zu -> %zu bytes, PSNR %.2f -> %.2f dB, max ref->out %.4f -> %.4f\n",
              with_report.coverage_patches, without.size(), with.size(), d0.psnr, d1.psnr, d0.max_ref_to_out,
              d1.max_ref_to_out);
  EXPECT_GT(d1.psnr, d0.psnr + 2.0);
  EXPECT_LT(d1.max_ref_to_out, 0.5 * d0.max_ref_to_out);
  EXPECT_LT(d1.rms_out_to_ref, 1.2 * d0.rms_out_to_ref);  // the pieces lie on the surface

  // No coverage with kept connectivity (the input's vertices have places on the quad mesh only).
  parameters.keep_connectivity = true;
  codec.setParameters(parameters);
  PatchCodec::Report kept_report;
  codec.encode(bunny, &kept_report);
  EXPECT_EQ(kept_report.coverage_patches, 0u);
}

TEST(PatchCodec, AnErrorTargetSpendsFewerCoefficientsForLittleError)
{
  // A patch stops taking atoms once its observed bins are coded to target_error × L: fewer
  // non-zeros and bytes, at a PSNR near the full codes'.
  const TriangleMesh bunny = loadBunny();
  PatchCodec codec;
  codec.setDictionary(bunnyDictionary());
  PatchCodecParameters parameters = bunnyParameters();
  codec.setParameters(parameters);
  PatchCodec::Report full_report, targeted_report;
  const std::string full = codec.encode(bunny, &full_report);
  parameters.target_error = 0.01;
  codec.setParameters(parameters);
  const std::string targeted = codec.encode(bunny, &targeted_report);
  TriangleMesh full_mesh, targeted_mesh;
  codec.decode(full, full_mesh);
  codec.decode(targeted, targeted_mesh);
  const SurfaceDistance d_full = surfaceDistance(bunny, full_mesh, 50000, 1);
  const SurfaceDistance d_targeted = surfaceDistance(bunny, targeted_mesh, 50000, 1);
  std::printf("error target 0.01 L: %zu -> %zu non-zeros, %zu -> %zu bytes, PSNR %.2f -> %.2f dB\n",
              full_report.nonzeros, targeted_report.nonzeros, full.size(), targeted.size(), d_full.psnr,
              d_targeted.psnr);
  EXPECT_LT(targeted_report.nonzeros, full_report.nonzeros * 85 / 100);  // measured 80 %
  EXPECT_LT(targeted.size(), full.size());
  EXPECT_GT(d_targeted.psnr, d_full.psnr - 1.0);  // measured −0.25 dB
  // The patches' own error grows, but stays near the target (RMS over the observed bins).
  EXPECT_GT(targeted_report.patch_rmse, full_report.patch_rmse);
  EXPECT_LT(targeted_report.patch_rmse, 2.0 * 0.01 * parameters.quad_length);
}

TEST(PatchCodec, OnePricePerAtomBeatsAPerPatchErrorTarget)
{
  // The Lagrangian allocation (atom_cost) spends atoms where they remove the most error; against
  // the per-patch error target at no more non-zeros, the patches' own error is lower. Quad patches
  // first (coverage off), then the coverage pieces.
  const TriangleMesh bunny = loadBunny();
  PatchCodec codec;
  codec.setDictionary(bunnyDictionary());
  PatchCodecParameters parameters = bunnyParameters();
  parameters.coverage_tolerance = 0.0;
  const auto encodeWith = [&](double target_error, double atom_cost, std::string* bytes = nullptr) {
    parameters.target_error = target_error;
    parameters.atom_cost = atom_cost;
    codec.setParameters(parameters);
    PatchCodec::Report report;
    const std::string encoded = codec.encode(bunny, &report);
    if (bytes)
      *bytes = encoded;
    return report;
  };
  std::string targeted, priced;
  const PatchCodec::Report full_report = encodeWith(0.0, 0.0);
  const PatchCodec::Report targeted_report = encodeWith(0.01, 0.0, &targeted);
  const PatchCodec::Report priced_report = encodeWith(0.0, 0.003, &priced);
  const PatchCodec::Report dearer_report = encodeWith(0.0, 0.012);
  const PatchCodec::Report free_report = encodeWith(0.0, 1e-9);
  const PatchCodec::Report prohibitive_report = encodeWith(0.0, 10.0);
  TriangleMesh targeted_mesh, priced_mesh;
  codec.decode(targeted, targeted_mesh);
  codec.decode(priced, priced_mesh);
  const SurfaceDistance d_targeted = surfaceDistance(bunny, targeted_mesh, 50000, 1);
  const SurfaceDistance d_priced = surfaceDistance(bunny, priced_mesh, 50000, 1);
  std::printf("error target 0.01 L vs atom cost 0.003: %zu / %zu non-zeros, patch rmse %.4g / %.4g, "
              "PSNR %.2f / %.2f dB, %zu / %zu bytes; cost 0.012: %zu, 1e-9: %zu (full codes %zu), 10: %zu\n",
              targeted_report.nonzeros, priced_report.nonzeros, targeted_report.patch_rmse,
              priced_report.patch_rmse, d_targeted.psnr, d_priced.psnr, targeted.size(), priced.size(),
              dearer_report.nonzeros, free_report.nonzeros, full_report.nonzeros, prohibitive_report.nonzeros);
  // Measured (no coverage patches): 4897 / 4714 non-zeros, patch rmse 1.006e-3 / 0.999e-3,
  // 64.60 / 64.63 dB; 0.012 L²: 3053; 1e-9 L²: 6118 = the full codes; 10 L²: 6 (a few patches
  // whose heights are that far from their mean). On this local dictionary the gain is small; with
  // the global one on max_planck it is 0.5–1 dB at equal entities.
  EXPECT_LE(priced_report.nonzeros, targeted_report.nonzeros);
  EXPECT_LT(priced_report.patch_rmse, targeted_report.patch_rmse);
  EXPECT_GT(d_priced.psnr, d_targeted.psnr - 0.1);
  // A dearer atom buys fewer; a free one buys the full codes; a prohibitive one leaves the means.
  EXPECT_LT(dearer_report.nonzeros, priced_report.nonzeros * 3 / 4);
  EXPECT_EQ(free_report.nonzeros, full_report.nonzeros);
  EXPECT_DOUBLE_EQ(free_report.patch_rmse, full_report.patch_rmse);
  EXPECT_LT(prohibitive_report.nonzeros, full_report.nonzeros / 100);
  // The price chooses the coverage patches' atoms too, below their own caps (a quarter of their bins).
  parameters.coverage_tolerance = PatchCodecParameters().coverage_tolerance;
  const PatchCodec::Report covered_report = encodeWith(0.0, 0.0);
  const PatchCodec::Report covered_dearer_report = encodeWith(0.0, 0.012);
  ASSERT_GT(covered_report.coverage_patches, 0u);
  ASSERT_GT(covered_dearer_report.coverage_patches, 0u);
  const double per_piece = double(covered_report.nonzeros - full_report.nonzeros) / covered_report.coverage_patches;
  const double per_piece_dearer =
      double(covered_dearer_report.nonzeros - dearer_report.nonzeros) / covered_dearer_report.coverage_patches;
  std::printf("coverage patches: %zu at %.1f non-zeros each, at 0.012 L²: %zu at %.1f\n", covered_report.coverage_patches,
              per_piece, covered_dearer_report.coverage_patches, per_piece_dearer);
  EXPECT_LT(per_piece_dearer, 0.75 * per_piece);  // measured 17 pieces at 7.4, 19 at 1.9
  parameters.atom_cost = -1.0;
  codec.setParameters(parameters);
  EXPECT_THROW(codec.encode(bunny), Error);
}

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
  PatchCodec codec;
  codec.setDictionary(bunnyDictionary());
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
  PatchCodecParameters parameters = bunnyParameters();
  parameters.coefficients = 33;
  codec.setParameters(parameters);
  expectError(bunny, "coefficients per patch must be in [1, 32]");
  parameters = bunnyParameters();
  parameters.coefficient_bits = 1;
  codec.setParameters(parameters);
  expectError(bunny, "coefficient bits");
  parameters = bunnyParameters();
  parameters.patch_scale = 5.0;
  codec.setParameters(parameters);
  expectError(bunny, "patch scale");
  parameters = bunnyParameters();
  parameters.target_error = 2.0;
  codec.setParameters(parameters);
  expectError(bunny, "target error");
  parameters = bunnyParameters();
  parameters.coverage_tolerance = -0.1;
  codec.setParameters(parameters);
  expectError(bunny, "coverage tolerance");
  parameters = bunnyParameters();
  parameters.coverage_budget = std::nan("");
  codec.setParameters(parameters);
  expectError(bunny, "coverage budget");
  parameters = bunnyParameters();
  parameters.quad_length = 0.9;  // coarser than the shape
  codec.setParameters(parameters);
  expectError(bunny, "quad");
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
  bunnyDictionary()->save(dir.file("dict.pdd"));
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
  otherDictionary(3)->save(dir.file("other.pdd"));
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
  codec.setDictionary(PatchDictionary::load(source + "pdc_dictionary.pdd"));
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
