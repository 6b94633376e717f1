// computeQuadFrames: orthonormal frames, Z along the surface normal, X consistent across quads,
// seeds and overlap offsets where the paper puts them.
#include <pcl_patchdict/core/error.h>
#include <pcl_patchdict/geometry/mesh_hygiene.h>
#include <pcl_patchdict/io/mesh_io.h>
#include <pcl_patchdict/pcl/reference_frame.h>
#include <pcl_patchdict/geometry/metrics.h>
#include <pcl_patchdict/core/normalization.h>
#include <pcl_patchdict/core/vertex_normals.h>
#include <pcl_patchdict/quads/patch_layout.h>
#include <pcl_patchdict/quads/quad_frames.h>
#include <pcl_patchdict/quads/quad_remesher.h>
#include <pcl_patchdict_eval/shapes.h>

#include "test_support.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <map>

using namespace pcl::patchdict;

namespace {

constexpr double kDegree = 3.14159265358979323846 / 180.0;

/** Fraction of face pairs sharing an edge whose X axes agree within `limit` after transport. */
double consistentPairs(const QuadMesh& mesh, const std::vector<Eigen::Matrix3d>& frames, double limit)
{
  std::map<std::pair<int, int>, std::vector<int>> edge_faces;
  for (std::size_t f = 0; f < mesh.faces.size(); ++f)
    for (std::size_t k = 0; k < mesh.faces[f].size(); ++k) {
      const int a = mesh.faces[f][k], b = mesh.faces[f][(k + 1) % mesh.faces[f].size()];
      edge_faces[{std::min(a, b), std::max(a, b)}].push_back(static_cast<int>(f));
    }
  int pairs = 0, good = 0;
  for (const auto& [edge, faces] : edge_faces)
    if (faces.size() == 2) {
      ++pairs;
      good += transportedXAngle(frames[faces[0]], frames[faces[1]]) < limit;
    }
  return pairs ? static_cast<double>(good) / pairs : 0.0;
}

}  // namespace

TEST(QuadFrames, APlaneGridGetsOneFrameEverywhere)
{
  QuadMesh grid;
  const int n = 6;
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i) {
      grid.vertices.emplace_back(0.1 * i, 0.1 * j, 0.0);
      grid.normals.emplace_back(0.0, 0.0, 1.0);
    }
  // Faces start at different corners, so their first sides point in all four directions.
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      std::vector<std::int32_t> face{j * (n + 1) + i, j * (n + 1) + i + 1, (j + 1) * (n + 1) + i + 1,
                                     (j + 1) * (n + 1) + i};
      std::rotate(face.begin(), face.begin() + (i + 2 * j) % 4, face.end());
      grid.faces.push_back(face);
    }
  std::vector<Eigen::Vector3d> seeds;
  std::vector<Eigen::Matrix3d> frames;
  std::vector<std::int32_t> seed_faces;
  computeQuadFrames(grid, 1, seeds, frames, &seed_faces);
  ASSERT_EQ(seeds.size(), 5u * n * n);
  ASSERT_EQ(frames.size(), seeds.size());
  const Eigen::Matrix3d first = frames[0];
  for (std::size_t s = 0; s < seeds.size(); ++s) {
    const Eigen::Matrix3d r = frames[s];
    EXPECT_LT((r - first).cwiseAbs().maxCoeff(), 1e-7);  // every X the same despite the rotated faces
    EXPECT_NEAR(r(2, 2), 1.0, 1e-7);
    EXPECT_NEAR(seeds[s].z(), 0.0, 1e-12);
  }
  // Face 0 spans [0, 0.1]²: centre, then the four offsets half way to its corners.
  EXPECT_TRUE(seeds[0].isApprox(Eigen::Vector3d(0.05, 0.05, 0.0), 1e-12));
  for (int k = 1; k <= 4; ++k) {
    EXPECT_EQ(seed_faces[k], 0);
    EXPECT_NEAR(std::abs(seeds[k].x() - 0.05), 0.025, 1e-12);
    EXPECT_NEAR(std::abs(seeds[k].y() - 0.05), 0.025, 1e-12);
  }
  computeQuadFrames(grid, 0, seeds, frames);
  EXPECT_EQ(seeds.size(), static_cast<std::size_t>(n * n));
  computeQuadFrames(grid, 2, seeds, frames);
  EXPECT_EQ(seeds.size(), 9u * n * n);
}

TEST(QuadFrames, FramesOnASphereAreOrthonormalRadialAndConsistent)
{
  const TriangleMesh sphere = makeIcosphere(5, 0.5);
  QuadRemesher remesher;
  remesher.setInputMesh(std::make_shared<const TriangleMesh>(sphere));
  remesher.setQuadLength(0.05);
  QuadMesh quads;
  remesher.process(quads);
  std::vector<Eigen::Vector3d> seeds;
  std::vector<Eigen::Matrix3d> frames;
  std::vector<std::int32_t> seed_faces;
  computeQuadFrames(quads, 1, seeds, frames, &seed_faces);
  ASSERT_GT(seeds.size(), 1000u);
  const std::vector<Eigen::Matrix3d> face_frames = computeQuadFaceFrames(quads);
  std::size_t radial = 0;
  for (std::size_t s = 0; s < seeds.size(); ++s) {
    const Eigen::Matrix3d r = frames[s];
    // The seed's frame is its face's as it comes back through PCL's float pcl::ReferenceFrame, bit
    // for bit (what the frames were before they stayed in double: the outputs depend on it).
    const Eigen::Matrix3d rounded =
        fromReferenceFrame(toReferenceFrame(face_frames[static_cast<std::size_t>(seed_faces[s])]));
    EXPECT_EQ(std::memcmp(r.data(), rounded.data(), sizeof(double) * 9), 0);
    EXPECT_LT((r * r.transpose() - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff(), 1e-5);
    EXPECT_GT(r.determinant(), 0.0);
    radial += r.row(2).dot(seeds[s].normalized()) > 0.9;
  }
  EXPECT_GE(static_cast<double>(radial) / seeds.size(), 0.95);
  // A sphere needs singularities, but most neighbouring quads must agree.
  EXPECT_GE(consistentPairs(quads, face_frames, 20.0 * kDegree), 0.9);
}

TEST(QuadFrames, BadInput)
{
  std::vector<Eigen::Vector3d> seeds;
  std::vector<Eigen::Matrix3d> frames;
  QuadMesh mesh;
  EXPECT_THROW(computeQuadFrames(mesh, 1, seeds, frames), Error);  // no faces
  EXPECT_THROW(computeQuadFaceFrames(mesh), Error);
  mesh.vertices = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};
  mesh.faces = {{0, 1, 2, 7}};
  EXPECT_THROW(computeQuadFrames(mesh, 1, seeds, frames), Error);  // index out of range
  mesh.faces = {{0, 1, 2, 3}, {0, 0, 0}};  // the degenerate face gives no seed
  computeQuadFrames(mesh, 0, seeds, frames);
  EXPECT_EQ(seeds.size(), 1u);
  EXPECT_THROW(computeQuadFrames(mesh, -1, seeds, frames), Error);
  EXPECT_THROW(computeQuadFrames(mesh, 17, seeds, frames), Error);
}

TEST(PatchLayout, TooLargeAQuadLengthIsAClearError)
{
  const TriangleMesh sphere = makeIcosphere(3, 0.5);
  PatchLayoutParameters parameters;
  parameters.quad_length = 5.0;
  PatchLayout layout;
  try {
    computePatchLayout(sphere, parameters, layout);
    FAIL() << "expected an Error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("too large"), std::string::npos);
  }
  parameters.quad_length = 0.05;
  computePatchLayout(sphere, parameters, layout);
  EXPECT_EQ(layout.seeds.size(), layout.frames.size());
  EXPECT_EQ(layout.seeds.size(), layout.seed_faces.size());
  EXPECT_GT(layout.quads.faces.size(), 500u);
}

TEST(PatchLayout, BunnyFramesMeetTheIssueBounds)
{
  // The bundled scan, as the pipeline sees it: cleaned, in the unit cube, L = 0.03.
  TriangleMesh bunny;
  readMesh(test_support::dataDir() + "/bunny.obj", bunny);
  cleanMesh(bunny);
  UnitCubeNormalization::fromMesh(bunny).apply(bunny);
  PatchLayout layout;
  computePatchLayout(bunny, PatchLayoutParameters{}, layout);
  const QuadMeshStatistics stats = computeQuadMeshStatistics(layout.quads);
  EXPECT_GE(stats.quad_fraction, 0.9);
  EXPECT_GE(stats.interior_valence4_fraction, 0.85);
  EXPECT_NEAR(stats.mean_edge_length, 0.03, 0.15 * 0.03);
  EXPECT_EQ(stats.degenerate_faces, 0u);
  EXPECT_EQ(stats.duplicate_faces, 0u);
  // Z against the coarse surface's normal at the seed (interpolated vertex normals).
  const PointToMeshDistance coarse(layout.coarse);
  const auto normals = computeVertexNormals(layout.coarse);
  std::size_t agreeing = 0;
  for (std::size_t s = 0; s < layout.seeds.size(); ++s) {
    const auto hit = coarse.query(layout.seeds[s]);
    const Face& f = layout.coarse.faces[hit.face];
    const Eigen::Vector3d &a = layout.coarse.vertices[f[0]], &b = layout.coarse.vertices[f[1]],
                          &c = layout.coarse.vertices[f[2]], &p = hit.closest_point;
    const double area = (b - a).cross(c - a).norm();
    const double wa = (b - p).cross(c - p).norm() / area, wb = (c - p).cross(a - p).norm() / area;
    const Eigen::Vector3d n = (wa * normals[f[0]] + wb * normals[f[1]] + (1 - wa - wb) * normals[f[2]]).normalized();
    agreeing += layout.frames[s].row(2).dot(n.transpose()) > 0.9;
  }
  EXPECT_GE(static_cast<double>(agreeing) / layout.seeds.size(), 0.95);
  // X consistency of the frames the layout emits (each face's centre seed), not recomputed ones.
  std::vector<Eigen::Matrix3d> face_frames(layout.quads.faces.size(), Eigen::Matrix3d::Zero());
  for (std::size_t s = 0; s < layout.seeds.size(); ++s)
    if (layout.seed_faces[s] >= 0 && face_frames[layout.seed_faces[s]].isZero())
      face_frames[layout.seed_faces[s]] = layout.frames[s];
  EXPECT_GE(consistentPairs(layout.quads, face_frames, 20.0 * kDegree), 0.9);
}
