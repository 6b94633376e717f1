// Tests of sampleSurfaceUniform: reproducibility, samples on their faces, area-proportional face
// choice and uniformity inside faces (binomial / CLT bounds at 4 standard deviations), errors.
#include <pcl_patchdict/core/error.h>
#include <pcl_patchdict/geometry/metrics.h>
#include <pcl_patchdict_eval/shapes.h>
#include <pcl_patchdict/core/surface_sampling.h>

#include <gtest/gtest.h>

#include <cmath>

#include <omp.h>

using namespace pcl::patchdict;

namespace {

/** Two coplanar triangles of areas 1 and 3, built by hand. */
TriangleMesh twoTriangles()
{
  TriangleMesh m;
  m.vertices = {{0, 0, 0}, {2, 0, 0}, {0, 1, 0}, {8, 0, 0}, {2, 1, 0}};
  m.faces = {{0, 1, 2}, {1, 3, 4}};  // ½·2·1 = 1 and ½·6·1 = 3
  return m;
}

}  // namespace

TEST(SurfaceSamplingTest, HandBuiltMeshHasTheIntendedAreas)
{
  const TriangleMesh m = twoTriangles();
  EXPECT_DOUBLE_EQ(m.faceArea(0), 1.0);
  EXPECT_DOUBLE_EQ(m.faceArea(1), 3.0);
}

TEST(SurfaceSamplingTest, SameSeedSameSamplesDifferentSeedDifferent)
{
  const TriangleMesh mesh = makeTorus(40, 20);
  const SurfaceSamples a = sampleSurfaceUniform(mesh, 50000, 42);
  const SurfaceSamples b = sampleSurfaceUniform(mesh, 50000, 42);
  const SurfaceSamples c = sampleSurfaceUniform(mesh, 50000, 43);
  ASSERT_EQ(a.points.size(), 50000u);
  ASSERT_EQ(a.face_ids.size(), 50000u);
  EXPECT_EQ(a.face_ids, b.face_ids);
  std::size_t same_points = 0, same_c = 0;
  for (std::size_t i = 0; i < a.points.size(); ++i) {
    same_points += (a.points[i] == b.points[i]);
    same_c += (a.points[i] == c.points[i]);
  }
  EXPECT_EQ(same_points, a.points.size());
  EXPECT_EQ(same_c, 0u);
  EXPECT_NE(a.face_ids, c.face_ids);
}

TEST(SurfaceSamplingTest, IndependentOfThreadCount)
{
  const TriangleMesh mesh = makeIcosphere(3);
  const int saved = omp_get_max_threads();
  omp_set_num_threads(1);
  const SurfaceSamples one = sampleSurfaceUniform(mesh, 40000, 7);
  omp_set_num_threads(4);
  const SurfaceSamples four = sampleSurfaceUniform(mesh, 40000, 7);
  omp_set_num_threads(saved);
  EXPECT_EQ(one.face_ids, four.face_ids);
  for (std::size_t i = 0; i < one.points.size(); ++i)
    ASSERT_EQ(one.points[i], four.points[i]) << i;
}

TEST(SurfaceSamplingTest, PrefixOfALongerRunIsTheShorterRun)
{
  // Blocks are seeded independently of the total count, so asking for more samples only appends.
  const TriangleMesh mesh = makePlaneGrid(3, 3);
  const SurfaceSamples short_run = sampleSurfaceUniform(mesh, 10000, 5);
  const SurfaceSamples long_run = sampleSurfaceUniform(mesh, 30000, 5);
  for (std::size_t i = 0; i < short_run.points.size(); ++i)
    ASSERT_EQ(short_run.points[i], long_run.points[i]) << i;
}

TEST(SurfaceSamplingTest, SamplesLieOnTheirFace)
{
  const TriangleMesh mesh = makeTorus(30, 17, 1.0, 0.4);
  const SurfaceSamples s = sampleSurfaceUniform(mesh, 20000, 3);
  double worst = 0.0;
  for (std::size_t i = 0; i < s.points.size(); ++i) {
    ASSERT_GE(s.face_ids[i], 0);
    ASSERT_LT(static_cast<std::size_t>(s.face_ids[i]), mesh.faces.size());
    const Face& f = mesh.faces[s.face_ids[i]];
    const Eigen::Vector3d q = closestPointOnTriangle(s.points[i], mesh.vertices[f[0]], mesh.vertices[f[1]],
                                                     mesh.vertices[f[2]]);
    worst = std::max(worst, (q - s.points[i]).norm());
  }
  EXPECT_LT(worst, 1e-12);
}

TEST(SurfaceSamplingTest, FaceFrequenciesFollowAreas)
{
  const TriangleMesh m = twoTriangles();
  const std::size_t n = 200000;
  const SurfaceSamples s = sampleSurfaceUniform(m, n, 11);
  std::size_t on_small = 0;
  for (const auto f : s.face_ids)
    on_small += (f == 0);
  const double p = 0.25, sigma = std::sqrt(p * (1 - p) / n);
  const double fraction = static_cast<double>(on_small) / n;
  EXPECT_NEAR(fraction, p, 4 * sigma) << "sigma " << sigma;
}

TEST(SurfaceSamplingTest, ZeroAreaFacesAreNeverChosen)
{
  TriangleMesh m;
  m.vertices = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {2, 0, 0}};
  m.faces = {{0, 1, 3}, {0, 1, 2}, {1, 3, 0}};  // faces 0 and 2 are collinear (zero area)
  const SurfaceSamples s = sampleSurfaceUniform(m, 20000, 1);
  for (const auto f : s.face_ids)
    ASSERT_EQ(f, 1);
}

TEST(SurfaceSamplingTest, MeanOfUnitSquareSamplesIsItsCentre)
{
  // One cell (two triangles: tests the in-face warp) and a 5×5 grid (also the face choice).
  for (const int cells : {1, 5}) {
    const TriangleMesh mesh = makePlaneGrid(cells, cells);
    const std::size_t n = 200000;
    const SurfaceSamples s = sampleSurfaceUniform(mesh, n, 99);
    Eigen::Vector3d mean = Eigen::Vector3d::Zero();
    Eigen::Vector2d mean_sq = Eigen::Vector2d::Zero();
    for (const auto& p : s.points) {
      mean += p;
      mean_sq += p.head<2>().cwiseAbs2();
    }
    mean /= static_cast<double>(n);
    mean_sq /= static_cast<double>(n);
    const double sigma = std::sqrt(1.0 / 12.0 / n);  // std of U(0,1) mean
    EXPECT_NEAR(mean.x(), 0.5, 4 * sigma);
    EXPECT_NEAR(mean.y(), 0.5, 4 * sigma);
    EXPECT_EQ(mean.z(), 0.0);
    // E[x²] = 1/3, Var[x²] = 1/5 − 1/9 = 4/45.
    const double sigma_sq = std::sqrt(4.0 / 45.0 / n);
    EXPECT_NEAR(mean_sq.x(), 1.0 / 3.0, 4 * sigma_sq);
    EXPECT_NEAR(mean_sq.y(), 1.0 / 3.0, 4 * sigma_sq);
  }
}

TEST(SurfaceSamplingTest, UniformInsideATriangle)
{
  // On the triangle (0,0),(1,0),(0,1) the fraction of samples with x + y < 1/2 is the area
  // ratio 1/4 — a check of the sqrt warp (without it the fraction would be 1/2).
  TriangleMesh m;
  m.vertices = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  m.faces = {{0, 1, 2}};
  const std::size_t n = 100000;
  const SurfaceSamples s = sampleSurfaceUniform(m, n, 2024);
  std::size_t near_corner = 0;
  for (const auto& p : s.points)
    near_corner += (p.x() + p.y() < 0.5);
  const double sigma = std::sqrt(0.25 * 0.75 / n);
  EXPECT_NEAR(static_cast<double>(near_corner) / n, 0.25, 4 * sigma);
}

TEST(SurfaceSamplingTest, ZeroSamplesGivesEmpty)
{
  const SurfaceSamples s = sampleSurfaceUniform(makePlaneGrid(2, 2), 0, 1);
  EXPECT_TRUE(s.points.empty());
  EXPECT_TRUE(s.face_ids.empty());
}

TEST(SurfaceSamplingTest, ThrowsWithoutFacesOrArea)
{
  TriangleMesh cloud;
  cloud.vertices = {{0, 0, 0}, {1, 0, 0}};
  EXPECT_THROW(sampleSurfaceUniform(cloud, 10, 1), Error);
  TriangleMesh flat;
  flat.vertices = {{0, 0, 0}, {1, 0, 0}, {2, 0, 0}};
  flat.faces = {{0, 1, 2}};
  EXPECT_THROW(sampleSurfaceUniform(flat, 10, 1), Error);
  TriangleMesh bad_index;
  bad_index.vertices = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  bad_index.faces = {{0, 1, 3}};
  EXPECT_THROW(sampleSurfaceUniform(bad_index, 10, 1), Error);
}
