// SparsePatchMeshInpainter: the mesh repairs through pcl::MeshProcessing, held by PCL's base.
#include <pcl_patchdict/repair/sparse_patch_mesh_inpainter.h>

#include <pcl_patchdict/core/error.h>
#include <pcl_patchdict/pcl/conversions.h>

#include "geometry/hole_test_shapes.h"

#include <gtest/gtest.h>

namespace {

using namespace pcl::patchdict;

TEST(SparsePatchMeshInpainter, FillsHolesThroughMeshProcessingAsTheFunctionDoes)
{
  const TriangleMesh holed = hole_test::sphereWithHoles(4, 0.3, {Eigen::Vector3d(0, 0, 1), Eigen::Vector3d(1, 0, 0)});
  auto polygon_mesh = std::make_shared<pcl::PolygonMesh>();
  toPolygonMesh(holed, *polygon_mesh);
  TriangleMesh as_read;  // the vertices as PCL's float cloud holds them
  fromPolygonMesh(*polygon_mesh, as_read);
  HoleRepairOptions options;
  options.decision.mode = PatchDecision::Never;  // Liepa's fill: the adapter, not the patch stage, is under test
  TriangleMesh direct;
  fillHolesWithPatches(as_read, direct, options);

  auto inpainter = std::make_shared<SparsePatchMeshInpainter>();
  inpainter->setHoleRepairOptions(options);
  pcl::MeshProcessing::Ptr base = inpainter;  // a PCL pipeline holds it by its base
  base->setInputMesh(polygon_mesh);
  pcl::PolygonMesh output;
  base->process(output);
  TriangleMesh repaired;
  fromPolygonMesh(output, repaired);
  ASSERT_EQ(repaired.numVertices(), direct.numVertices());
  ASSERT_EQ(repaired.numFaces(), direct.numFaces());
  EXPECT_GT(direct.numVertices(), holed.numVertices());  // the holes got new vertices
  for (std::size_t v = 0; v < direct.numVertices(); ++v)
    ASSERT_LT((repaired.vertices[v] - direct.vertices[v]).norm(), 1e-6) << v;
  EXPECT_EQ(inpainter->getHoleRepairReport().holes.holes_filled, 2u);
}

TEST(SparsePatchMeshInpainter, RecoversMissingVerticesAndRefusesBadIndices)
{
  const TriangleMesh sphere = makeIcosphere(3, 1.0);
  auto polygon_mesh = std::make_shared<pcl::PolygonMesh>();
  toPolygonMesh(sphere, *polygon_mesh);
  SparsePatchMeshInpainter inpainter;
  inpainter.setMode(SparsePatchMeshInpainter::Mode::FillMissingVertices);
  MissingVerticesOptions options;
  options.decision.mode = PatchDecision::Never;
  inpainter.setMissingVerticesOptions(options);
  inpainter.setMissingVertices({5, 17, 40});
  inpainter.setInputMesh(polygon_mesh);
  pcl::PolygonMesh output;
  inpainter.process(output);
  TriangleMesh repaired;
  fromPolygonMesh(output, repaired);
  ASSERT_EQ(repaired.numVertices(), sphere.numVertices());
  for (int v : {5, 17, 40})  // back near the unit sphere (the bi-Laplacian of a 642-vertex sphere)
    EXPECT_NEAR(repaired.vertices[static_cast<std::size_t>(v)].norm(), 1.0, 0.02) << v;
  inpainter.setMissingVertices({100000});
  EXPECT_THROW(inpainter.process(output), Error);
}

}  // namespace
