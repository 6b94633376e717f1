// BiharmonicImplicit: known answers (a plane is reproduced exactly, a sphere closely, with the
// sign of the normals), projection onto the zero set, and refused input.
#include <pcl_patchdict/cloud/biharmonic_implicit.h>
#include <pcl_patchdict/core/error.h>

#include <gtest/gtest.h>

#include <cmath>
#include <random>

namespace pcl {
namespace patchdict {
namespace {

TEST(BiharmonicImplicit, ReproducesAPlaneExactly)
{
  // f = n·(x − p) meets every constraint and lies in the affine part: the fit is that plane.
  const Eigen::Vector3d n = Eigen::Vector3d(1.0, 2.0, 2.0) / 3.0, origin(0.3, -0.2, 0.5);
  const Eigen::Vector3d e1 = n.unitOrthogonal(), e2 = n.cross(e1);
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> uniform(-1.0, 1.0);
  std::vector<Eigen::Vector3d> points, normals;
  for (int i = 0; i < 60; ++i) {
    points.push_back(origin + uniform(rng) * e1 + uniform(rng) * e2);
    normals.push_back(n);
  }
  BiharmonicImplicit f;
  f.fit(points, normals, 0.05);
  for (int i = 0; i < 20; ++i) {
    const Eigen::Vector3d x(uniform(rng), uniform(rng), uniform(rng));
    EXPECT_NEAR(f(x), n.dot(x - origin), 1e-8);
    EXPECT_NEAR((f.gradient(x) - n).norm(), 0.0, 1e-8);
  }
  Eigen::Vector3d x(0.9, 0.9, 0.9);
  ASSERT_TRUE(f.project(x, 1e-12));
  EXPECT_NEAR(n.dot(x - origin), 0.0, 1e-12);
}

TEST(BiharmonicImplicit, FitsASphereWithItsSignAndProjectsOntoIt)
{
  // 300 points of the unit sphere with outward normals: f < 0 inside, > 0 outside, and the zero
  // set within a few thousandths of the sphere between the points.
  std::mt19937 rng(5);
  std::normal_distribution<double> gauss(0.0, 1.0);
  std::vector<Eigen::Vector3d> points, normals;
  for (int i = 0; i < 300; ++i) {
    const Eigen::Vector3d d = Eigen::Vector3d(gauss(rng), gauss(rng), gauss(rng)).normalized();
    points.push_back(d);
    normals.push_back(d);
  }
  BiharmonicImplicit f;
  f.fit(points, normals, 0.05);
  EXPECT_LT(f(Eigen::Vector3d::Zero()), 0.0);
  EXPECT_GT(f(Eigen::Vector3d(1.5, 0.0, 0.0)), 0.0);
  double worst = 0.0;
  for (int i = 0; i < 200; ++i) {
    const Eigen::Vector3d d = Eigen::Vector3d(gauss(rng), gauss(rng), gauss(rng)).normalized();
    Eigen::Vector3d x = 1.2 * d;
    ASSERT_TRUE(f.project(x, 1e-9));
    worst = std::max(worst, std::abs(x.norm() - 1.0));
    EXPECT_GT(f.gradient(x).normalized().dot(x.normalized()), 0.99);
  }
  EXPECT_LT(worst, 0.01);  // points are ~0.2 apart
}

TEST(BiharmonicImplicit, BadInputIsAnError)
{
  BiharmonicImplicit f;
  const std::vector<Eigen::Vector3d> three(3, Eigen::Vector3d::UnitZ());
  EXPECT_THROW(f.fit(three, three, 0.1), Error);
  std::vector<Eigen::Vector3d> points{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {1, 1, 0}}, normals(4, Eigen::Vector3d::UnitZ());
  EXPECT_THROW(f.fit(points, normals, 0.0), Error);
  EXPECT_THROW(f.fit(points, std::vector<Eigen::Vector3d>(3, Eigen::Vector3d::UnitZ()), 0.1), Error);
  normals[2] = Eigen::Vector3d::Zero();
  EXPECT_THROW(f.fit(points, normals, 0.1), Error);
  normals[2] = Eigen::Vector3d::UnitZ();
  points[1].x() = std::nan("");
  EXPECT_THROW(f.fit(points, normals, 0.1), Error);
  // A failed refit keeps the fit it had: the plane z = 0 still.
  points[1].x() = 1.0;
  f.fit(points, normals, 0.1);
  points.push_back(points[0]);  // a duplicate: two identical rows
  normals.push_back(normals[0]);
  EXPECT_THROW(f.fit(points, normals, 0.1), Error);
  EXPECT_FALSE(f.empty());
  EXPECT_NEAR(f(Eigen::Vector3d(0.3, 0.7, 0.25)), 0.25, 1e-9);
}

TEST(BiharmonicImplicit, ShortensOffsetsThatWouldCrossAThinSheet)
{
  // Two parallel sheets 0.1 apart, normals pointing away from each other: offsets of ε = 0.17 along
  // the normals stay clear outside, but the inward ones (−ε n) would land beyond the other sheet.
  // Halved twice where they cross (to 0.0425), the zero set keeps both sheets.
  std::vector<Eigen::Vector3d> points, normals;
  for (int i = 0; i < 8; ++i)
    for (int j = 0; j < 8; ++j)
      for (int side = -1; side <= 1; side += 2) {
        points.emplace_back(0.1 * i, 0.1 * j, 0.05 * side);
        normals.emplace_back(0.0, 0.0, side);
      }
  BiharmonicImplicit f;
  f.fit(points, normals, 0.17);
  EXPECT_LT(f(Eigen::Vector3d(0.35, 0.35, 0.0)), 0.0);   // between the sheets: inside
  EXPECT_GT(f(Eigen::Vector3d(0.35, 0.35, 0.1)), 0.0);   // beyond the upper sheet: outside
  Eigen::Vector3d x(0.35, 0.35, 0.08);
  ASSERT_TRUE(f.project(x, 1e-9));
  EXPECT_NEAR(x.z(), 0.05, 0.01);
}

}  // namespace
}  // namespace patchdict
}  // namespace pcl
