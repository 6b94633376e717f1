// PatchCodec (.pdc) and quad subdivision: round trips with error bounds, determinism, and rejection
// of truncated, corrupted and mismatched data.
#include <pcl_patchdict/core/error.h>
#include <pcl_patchdict/patches/height_maps.h>
#include <pcl_patchdict/io/mesh_io.h>
#include <pcl_patchdict/geometry/metrics.h>
#include <pcl_patchdict/core/normalization.h>
#include <pcl_patchdict/codec/patch_codec.h>
#include <pcl_patchdict/quads/patch_layout.h>
#include <pcl_patchdict/quads/quad_subdivision.h>
#include <pcl_patchdict/io/patch_codec_io.h>
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
#include <iterator>

using namespace pcl::patchdict;
using namespace codec_test;
using test_support::q;
using test_support::runTool;

namespace {

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
  HeightMapParameters parameters;
  parameters.radius = 0.08 / std::sqrt(2.0);
  parameters.grid_size = 16;
  PatchSet patches;
  extractMeshHeightMaps(unit, layout.seeds, layout.frames, parameters, patches);
  return patches;
}

/** A local dictionary of the bunny: 48 atoms, K-SVD (sparsity 8, 5 iterations) on bunnyPatches. */
PatchDictionary::Ptr learnBunnyDictionary(const TriangleMesh& bunny, std::uint64_t seed = 1)
{
  const PatchSet patches = bunnyPatches(bunny);
  DictionaryLearningOptions options;
  options.num_atoms = 48;
  options.sparsity = 8;
  options.iterations = 5;
  options.seed = seed;
  auto dictionary = std::make_shared<PatchDictionary>();
  dictionary->learn(patches.heights, patches.observed, options);
  return dictionary;
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
    savePatchDictionary(bunnyDictionaryPath(), *learned);
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
  PatchCodec codec = bunnyCodec();
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
  saveCompressedMesh(dir.file("bunny.pdc"), codec, bunny);
  EXPECT_TRUE(test_support::readFile(dir.file("bunny.pdc")) == bytes);
  TriangleMesh from_file;
  loadCompressedMesh(dir.file("bunny.pdc"), codec, from_file);
  EXPECT_TRUE(from_file.vertices == decoded.vertices);
}

TEST(PatchCodec, CoveragePatchesReachThePartsTheQuadsMiss)
{
  // At L = 0.1 the bunny's quad mesh does not reach all of its ears: without coverage patches the
  // decoded surface misses them (the reference-to-output distance is large there).
  const TriangleMesh bunny = loadBunny();
  PatchCodec codec = bunnyCodec();
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
  PatchCodec codec = bunnyCodec();
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
  PatchCodec codec = bunnyCodec();
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
