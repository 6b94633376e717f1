// ThinPlateSpline: reproduces affine functions exactly, interpolates its sites, approximates a
// smooth surface between them, and refuses degenerate input.
#include <pcl_patchdict/core/error.h>
#include <pcl_patchdict/geometry/thin_plate_spline.h>

#include <gtest/gtest.h>

#include <cmath>
#include <random>

namespace pcl {
namespace patchdict {
namespace {

TEST(ThinPlateSpline, ReproducesAffineFunctionsAndInterpolatesItsSites)
{
  std::mt19937 rng(1);
  std::uniform_real_distribution<double> uniform(-1.0, 1.0);
  std::vector<Eigen::Vector2d> sites;
  std::vector<double> affine, bumpy;
  for (int i = 0; i < 60; ++i) {
    sites.emplace_back(uniform(rng), uniform(rng));
    affine.push_back(0.3 + 2.0 * sites.back().x() - sites.back().y());
    bumpy.push_back(std::sin(3.0 * sites.back().x()) * std::cos(2.0 * sites.back().y()));
  }
  ThinPlateSpline spline;
  spline.fit(sites, affine);
  EXPECT_NEAR(spline(Eigen::Vector2d(0.1, -0.4)), 0.3 + 0.2 + 0.4, 1e-8);
  EXPECT_NEAR(spline.gradient(Eigen::Vector2d(0.5, 0.5)).x(), 2.0, 1e-7);
  spline.fit(sites, bumpy);
  for (std::size_t i = 0; i < sites.size(); ++i)
    EXPECT_NEAR(spline(sites[i]), bumpy[i], 1e-8);
  EXPECT_NEAR(spline(Eigen::Vector2d(0.0, 0.0)), 0.0, 0.05);
  // A ring of sites around an empty disc: a paraboloid is continued into the disc.
  sites.clear();
  std::vector<double> bowl;
  for (int i = 0; i < 200; ++i) {
    const double r = 0.5 + 0.5 * (i % 10) / 10.0, t = 0.1 * i;
    sites.emplace_back(r * std::cos(t), r * std::sin(t));
    bowl.push_back(0.2 * sites.back().squaredNorm());
  }
  spline.fit(sites, bowl);
  EXPECT_NEAR(spline(Eigen::Vector2d(0.0, 0.0)), 0.0, 0.01);
  EXPECT_NEAR(spline(Eigen::Vector2d(0.3, 0.0)), 0.2 * 0.09, 0.005);
}

TEST(ThinPlateSpline, RefusesDegenerateInput)
{
  ThinPlateSpline spline;
  EXPECT_THROW(spline.fit({{0, 0}, {1, 1}}, {0, 1}), Error);
  EXPECT_THROW(spline.fit({{0, 0}, {1, 1}, {2, 2}, {3, 3}}, {0, 1, 2, 3}), Error);  // collinear
  EXPECT_THROW(spline.fit({{0, 0}, {1, 0}, {0, 1}}, {0, 1}), Error);
  EXPECT_THROW(spline.fit({{0, 0}, {1, 0}, {0, 1}}, {0, 1, std::nan("")}), Error);
}

}  // namespace
}  // namespace patchdict
}  // namespace pcl
