#include <pcl_patchdict/geometry/mesh_hygiene.h>
#include <pcl_patchdict/io/mesh_io.h>
#include <pcl_patchdict_eval/shapes.h>

#include "test_support.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

using namespace pcl::patchdict;

TEST(MeshHygiene, CleanSphereReportsNothingWrong)
{
  const MeshHygieneReport report = inspectMesh(makeIcosphere(2));
  EXPECT_EQ(report.vertices, 162u);
  EXPECT_EQ(report.faces, 320u);
  EXPECT_EQ(report.unreferenced_vertices + report.nonfinite_vertices + report.degenerate_faces +
                report.duplicate_faces + report.nonmanifold_edges + report.nonmanifold_vertices +
                report.boundary_edges + report.boundary_loops,
            0u);
  EXPECT_EQ(report.components, 1u);
}

TEST(MeshHygiene, DetectsEveryDefect)
{
  TriangleMesh mesh;
  mesh.vertices = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {2, 2, 2} /* unreferenced */,
                   {0, -1, 0}, {std::numeric_limits<double>::quiet_NaN(), 0, 0}, {3, 0, 0}};
  mesh.faces = {
      {0, 1, 2},
      {0, 1, 3},
      {0, 1, 5},  // edge (0,1) now has three faces: non-manifold
      {2, 1, 0},  // duplicate of face 0 (other orientation)
      {0, 0, 3},  // repeated index: degenerate
      {0, 1, 7},  // collinear: zero area, degenerate (and a 4th face on edge 0-1)
      {6, 2, 3},  // non-finite vertex: degenerate
  };
  const MeshHygieneReport report = inspectMesh(mesh);
  EXPECT_EQ(report.unreferenced_vertices, 1u);
  EXPECT_EQ(report.nonfinite_vertices, 1u);
  EXPECT_EQ(report.degenerate_faces, 3u);
  EXPECT_EQ(report.duplicate_faces, 1u);
  EXPECT_EQ(report.nonmanifold_edges, 1u);
}

TEST(MeshHygiene, NonManifoldVertexOfTwoTouchingFans)
{
  TriangleMesh mesh;
  mesh.vertices = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {-1, 0, 0}, {-1, -1, 0}};
  mesh.faces = {{0, 1, 2}, {0, 3, 4}};
  const auto fans = computeVertexFanCounts(mesh);
  EXPECT_EQ(fans[0], 2);
  EXPECT_EQ(fans[1], 1);
  EXPECT_EQ(inspectMesh(mesh).nonmanifold_vertices, 1u);
  // A closed fan (the centre of a grid) is one fan.
  EXPECT_EQ(computeVertexFanCounts(makePlaneGrid(2, 2))[4], 1);
}

TEST(MeshHygiene, CleanRemovesAndKeepsTheIndexMap)
{
  TriangleMesh mesh;
  mesh.vertices = {{9, 9, 9}, {0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {8, 8, 8}, {1, 1, 0}};
  mesh.faces = {{1, 2, 3}, {3, 2, 1}, {1, 1, 2}, {2, 5, 3}};
  const MeshCleanupResult result = cleanMesh(mesh);
  EXPECT_EQ(result.degenerate_faces_removed, 1u);
  EXPECT_EQ(result.duplicate_faces_removed, 1u);
  EXPECT_EQ(result.unreferenced_vertices_removed, 2u);
  EXPECT_EQ(result.old_to_new, (std::vector<int>{-1, 0, 1, 2, -1, 3}));
  EXPECT_EQ(result.new_to_old, (std::vector<int>{1, 2, 3, 5}));
  ASSERT_EQ(mesh.faces.size(), 2u);
  EXPECT_EQ(mesh.faces[0], (Face{0, 1, 2}));
  EXPECT_EQ(mesh.faces[1], (Face{1, 3, 2}));
  EXPECT_EQ(mesh.vertices[3], Eigen::Vector3d(1, 1, 0));
}

TEST(MeshHygiene, OrientationIsMadeConsistent)
{
  TriangleMesh sphere = makeIcosphere(2);
  const TriangleMesh reference = sphere;
  for (std::size_t f = 1; f < sphere.faces.size(); f += 3)
    std::swap(sphere.faces[f][0], sphere.faces[f][1]);
  const std::size_t flipped = orientFacesConsistently(sphere);
  EXPECT_GT(flipped, 0u);
  // Face 0 was kept, so every face must now match the original orientation.
  for (std::size_t f = 0; f < sphere.faces.size(); ++f)
    EXPECT_GT(sphere.faceNormal(f).dot(reference.faceNormal(f)), 0.99) << "face " << f;
}

TEST(MeshHygiene, BunnyHasItsKnownDefects)
{
  TriangleMesh bunny;
  readMesh(test_support::dataDir() + "/bunny.obj", bunny);
  const MeshHygieneReport report = inspectMesh(bunny);
  EXPECT_EQ(report.vertices, 35947u);
  EXPECT_EQ(report.faces, 69451u);
  EXPECT_EQ(report.unreferenced_vertices, 1113u);
  EXPECT_EQ(report.boundary_loops, 5u);
  EXPECT_EQ(report.boundary_edges, 223u);
  EXPECT_EQ(report.nonmanifold_edges, 0u);
  EXPECT_EQ(report.components, 1u);
  const MeshCleanupResult cleanup = cleanMesh(bunny);
  EXPECT_EQ(cleanup.unreferenced_vertices_removed, 1113u);
  EXPECT_EQ(bunny.vertices.size(), 34834u);
}
