// Seeded damage for the demo and the benchmarks (holes where asked, fractions as asked, noise of σ), and the procedural shapes.
#include <pcl_patchdict/core/error.h>
#include <pcl_patchdict_eval/mesh_damage.h>
#include <pcl_patchdict/geometry/mesh_hygiene.h>
#include <pcl_patchdict_eval/shapes.h>
#include <pcl_patchdict/core/triangle_mesh.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

using namespace pcl::patchdict;

TEST(MeshDamage, HolesRemoveExactlyTheFacesNearTheirCentresAndKeepTheRestInOrder)
{
  const TriangleMesh sphere = makeIcosphere(4);
  const HoledMesh holed = punchHoles(sphere, 5, 0.2, 11);
  ASSERT_EQ(holed.centres.size(), 5u);
  for (std::size_t i = 0; i < holed.centres.size(); ++i)
    for (std::size_t j = i + 1; j < holed.centres.size(); ++j)
      EXPECT_GE((holed.centres[i] - holed.centres[j]).norm(), 0.8);
  EXPECT_EQ(inspectMesh(holed.mesh).boundary_loops, 5u);
  EXPECT_EQ(holed.mesh.numVertices() + holed.removed.size(), sphere.numVertices());
  for (std::int32_t v : holed.removed) {
    double nearest = 1e9;
    for (const auto& c : holed.centres)
      nearest = std::min(nearest, (sphere.vertices[static_cast<std::size_t>(v)] - c).norm());
    EXPECT_LE(nearest, 0.2 + 1e-12);
  }
  for (std::size_t v = 0; v < holed.mesh.numVertices(); ++v) {
    ASSERT_EQ(holed.mesh.vertices[v], sphere.vertices[static_cast<std::size_t>(holed.original_index[v])]);
    if (v > 0) {
      ASSERT_LT(holed.original_index[v - 1], holed.original_index[v]);
    }
  }
  // Same seed, same holes; no room for 100 holes of radius 0.2: fewer centres, no error.
  EXPECT_EQ(punchHoles(sphere, 5, 0.2, 11).centres, holed.centres);
  EXPECT_LT(punchHoles(sphere, 100, 0.2, 11).centres.size(), 100u);
  EXPECT_THROW(punchHoles(sphere, 0, 0.2, 1), Error);
  EXPECT_THROW(punchHoles(sphere, 3, -1.0, 1), Error);
}

TEST(MeshDamage, MissingFractionAndNormalNoiseAreAsAsked)
{
  const TriangleMesh sphere = makeIcosphere(4);
  const std::vector<int> missing = pickMissingVertices(sphere, 0.2, 3);
  EXPECT_EQ(missing.size(), static_cast<std::size_t>(std::llround(0.2 * static_cast<double>(sphere.numVertices()))));
  EXPECT_TRUE(std::is_sorted(missing.begin(), missing.end()));
  EXPECT_EQ(std::adjacent_find(missing.begin(), missing.end()), missing.end());
  EXPECT_THROW(pickMissingVertices(sphere, 1.0, 3), Error);
  const TriangleMesh noisy = addNormalNoise(sphere, 0.01, 4);
  double sum = 0.0, tangential = 0.0;
  for (std::size_t v = 0; v < sphere.numVertices(); ++v) {
    const Eigen::Vector3d d = noisy.vertices[v] - sphere.vertices[v];
    const double along = d.dot(sphere.vertices[v].normalized());
    sum += along * along;
    tangential = std::max(tangential, (d - along * sphere.vertices[v].normalized()).norm());
  }
  EXPECT_NEAR(std::sqrt(sum / static_cast<double>(sphere.numVertices())), 0.01, 0.0005);  // 2562 draws
  EXPECT_LT(tangential, 1e-3);  // area-weighted normals of the icosphere are close to radial
}

TEST(MeshDamage, HolesKeepAwayFromTheRimAndCountOnlySurfaceVertices)
{
  // An open 60 × 60 grid plus one vertex no face uses: centres at least 2 radii from the rim, the
  // lone vertex never counted as removed, every removed vertex within the radius of a centre.
  TriangleMesh grid = makePlaneGrid(60, 60);
  grid.vertices.emplace_back(0.5, 0.5, 0.3);
  const double radius = 0.05;
  const HoledMesh holed = punchHoles(grid, 6, radius, 3);
  ASSERT_EQ(holed.centres.size(), 6u);
  for (const auto& c : holed.centres)
    EXPECT_GE(std::min({c.x(), c.y(), 1.0 - c.x(), 1.0 - c.y()}), 2.0 * radius - 1e-12);
  const auto lone = static_cast<std::int32_t>(grid.numVertices() - 1);
  EXPECT_EQ(std::count(holed.removed.begin(), holed.removed.end(), lone), 0);
  EXPECT_FALSE(holed.removed.empty());
  const double spacing = 1.0 / 59.0;
  for (const std::int32_t v : holed.removed) {
    double nearest = 1e9;
    for (const auto& c : holed.centres)
      nearest = std::min(nearest, (grid.vertices[static_cast<std::size_t>(v)] - c).norm());
    EXPECT_LE(nearest, radius + 1.5 * spacing) << v;  // in a removed face: within a face of the disc
  }
  EXPECT_EQ(holed.original_index.size() + holed.removed.size() + 1, grid.numVertices());
}

TEST(MeshDamage, NoiseOfZeroIsTheMeshAndANegativeSigmaIsAnError)
{
  const TriangleMesh sphere = makeIcosphere(2);
  EXPECT_TRUE(addNormalNoise(sphere, 0.0, 1).vertices == sphere.vertices);
  EXPECT_THROW(addNormalNoise(sphere, -0.1, 1), Error);
  EXPECT_THROW(addNormalNoise(sphere, std::nan(""), 1), Error);
}

// The procedural shapes: sizes and closed forms.

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
