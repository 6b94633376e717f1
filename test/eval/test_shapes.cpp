// The evaluation library's procedural shapes: sizes and closed forms.
#include <pcl_patchdict/core/triangle_mesh.h>
#include <pcl_patchdict_eval/shapes.h>

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>

using namespace pcl::patchdict;

TEST(Shapes, KnownSizesAndClosedForms)
{
  const TriangleMesh sphere = makeIcosphere(3, 1.5);
  EXPECT_EQ(sphere.faces.size(), 20u * 64u);
  for (const auto& v : sphere.vertices)
    EXPECT_NEAR(v.norm(), 1.5, 1e-14);
  EXPECT_NEAR(sphere.surfaceArea(), 4.0 * M_PI * 1.5 * 1.5, 0.05 * 4.0 * M_PI * 2.25);

  const TriangleMesh torus = makeTorus(40, 20, 1.0, 0.25);
  EXPECT_EQ(torus.vertices.size(), 800u);
  EXPECT_EQ(torus.faces.size(), 1600u);
  EXPECT_NEAR(torus.surfaceArea(), 4.0 * M_PI * M_PI * 0.25, 0.02 * 4.0 * M_PI * M_PI * 0.25);

  const TriangleMesh plane = makePlaneGrid(10, 5, 2.0, 1.0);
  EXPECT_EQ(plane.vertices.size(), 66u);
  EXPECT_NEAR(plane.surfaceArea(), 2.0, 1e-12);

  const TriangleMesh relief = makeSinusoidalRelief(32, 32, 0.05, 0.25);
  for (const auto& v : relief.vertices)
    EXPECT_DOUBLE_EQ(v.z(), sinusoidalReliefHeight(v.x(), v.y(), 0.05, 0.25));
}
