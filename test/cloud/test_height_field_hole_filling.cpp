// Tests of the height-field hole filler on synthetic aerial-like tiles (UTM-sized offsets).
#include <pcl_patchdict/core/error.h>
#include <pcl_patchdict/cloud/height_field_hole_filling.h>

#include <Eigen/Geometry>
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>

namespace pd = pcl::patchdict;

namespace {

const Eigen::Vector3d kOffset(512000.0, 5403000.0, 250.0);
const double kPi = 3.14159265358979323846;

double terrain(double x, double y) { return 0.02 * x + 0.001 * x * y - 0.002 * y * y + 1.5 * std::sin(0.08 * x); }

/// Jittered grid of step 0.5 over [0, extent)², minus the points `cut` rejects, offset to UTM.
template <class Cut>
std::vector<Eigen::Vector3d> tile(double extent, Cut cut, unsigned seed = 7)
{
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> jitter(-0.2, 0.2);
  std::vector<Eigen::Vector3d> points;
  for (double y = 0.25; y < extent; y += 0.5)
    for (double x = 0.25; x < extent; x += 0.5) {
      const double u = x + jitter(rng), v = y + jitter(rng);
      if (!cut(u, v))
        points.push_back(kOffset + Eigen::Vector3d(u, v, terrain(u, v)));
    }
  return points;
}

bool inDisc(double u, double v, double cu, double cv, double r) { return std::hypot(u - cu, v - cv) <= r; }

struct FillRun {
  std::vector<Eigen::Vector3d> added;
  std::vector<std::size_t> source;
  pd::HeightFieldFillReport report;
};

FillRun fill(const std::vector<Eigen::Vector3d>& points, const pd::HeightFieldFillParameters& p = {})
{
  FillRun run;
  pd::fillHeightFieldHoles(points, p, run.added, run.source, run.report);
  return run;
}

}  // namespace

TEST(HeightFieldHoleFilling, FillsAnEnclosedDiscAtTheInputDensityOnTheSurface)
{
  const double r = 6.0;
  const auto points = tile(60.0, [&](double u, double v) { return inDisc(u, v, 30.0, 30.0, r); });
  const FillRun run = fill(points);
  EXPECT_NEAR(run.report.spacing, 0.5, 0.1);
  EXPECT_EQ(run.report.holes_filled, 1u);
  const double expected = kPi * r * r / (run.report.spacing * run.report.spacing);
  EXPECT_GT(static_cast<double>(run.added.size()), 0.75 * expected);
  EXPECT_LT(static_cast<double>(run.added.size()), 1.3 * expected);
  ASSERT_EQ(run.source.size(), run.added.size());
  double worst = 0.0;
  for (std::size_t k = 0; k < run.added.size(); ++k) {
    const Eigen::Vector3d q = run.added[k] - kOffset;
    EXPECT_LE(std::hypot(q.x() - 30.0, q.y() - 30.0), r + 1.0);
    worst = std::max(worst, std::abs(q.z() - terrain(q.x(), q.y())));
    ASSERT_LT(run.source[k], points.size());
    EXPECT_LT((points[run.source[k]] - run.added[k]).head<2>().norm(), r + 1.0);
  }
  EXPECT_LT(worst, 0.1);  // the surface bends by ~2 m over the hole
}

TEST(HeightFieldHoleFilling, LeavesSampledGroundBordersAndBaysAlone)
{
  // Poisson-like sparse ground (no hole), a wide notch into the tile's edge and a bay open to it.
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> coin(0.0, 1.0);
  const auto points = tile(60.0, [&](double u, double v) {
    return coin(rng) < 0.3 || (u > 20.0 && u < 35.0 && v < 12.0) || inDisc(u, v, 50.0, 57.0, 6.0);
  });
  const FillRun run = fill(points);
  EXPECT_EQ(run.report.holes_filled, 0u);
  EXPECT_EQ(run.added.size(), 0u);
}

TEST(HeightFieldHoleFilling, RobustToTreesOnTheRim)
{
  const auto ground = tile(60.0, [&](double u, double v) { return inDisc(u, v, 30.0, 30.0, 5.0); });
  std::vector<Eigen::Vector3d> points = ground;
  for (const Eigen::Vector3d& p : ground) {  // a tree crown over a third of the rim, 12 m up
    const Eigen::Vector3d q = p - kOffset;
    const double d = std::hypot(q.x() - 30.0, q.y() - 30.0);
    if (d < 9.0 && q.x() > 32.0)
      points.push_back(p + Eigen::Vector3d(0.1, 0.1, 12.0));
  }
  const FillRun run = fill(points);
  ASSERT_EQ(run.report.holes_filled, 1u);
  double worst = 0.0;
  for (const Eigen::Vector3d& a : run.added) {
    const Eigen::Vector3d q = a - kOffset;
    worst = std::max(worst, std::abs(q.z() - terrain(q.x(), q.y())));
  }
  EXPECT_LT(worst, 0.3);
}

TEST(HeightFieldHoleFilling, IgnoresNonFiniteAndAbsurdPointsAndIsDeterministic)
{
  auto points = tile(40.0, [&](double u, double v) { return inDisc(u, v, 20.0, 20.0, 4.0); });
  const FillRun clean = fill(points);
  const double nan = std::numeric_limits<double>::quiet_NaN(), inf = std::numeric_limits<double>::infinity();
  points.insert(points.begin() + 10, Eigen::Vector3d(nan, 1.0, 1.0));
  points.emplace_back(inf, -inf, 0.0);
  points.emplace_back(1e30, 1e30, 1e30);
  points.emplace_back(kOffset + Eigen::Vector3d(20.0, 20.0, 1e30));
  const FillRun dirty = fill(points);
  EXPECT_EQ(dirty.report.points_ignored, 4u);
  ASSERT_EQ(dirty.added.size(), clean.added.size());
  ASSERT_GT(clean.added.size(), 100u);
  for (std::size_t k = 0; k < clean.added.size(); ++k) {
    EXPECT_TRUE(dirty.added[k].allFinite());
    EXPECT_EQ(dirty.added[k], clean.added[k]);
    EXPECT_TRUE(points[dirty.source[k]].allFinite());
  }
  const FillRun again = fill(points);
  EXPECT_EQ(again.added, dirty.added);
  EXPECT_EQ(again.source, dirty.source);
}

TEST(HeightFieldHoleFilling, BadParametersAndHugeRastersThrowOneLine)
{
  const auto points = tile(20.0, [](double, double) { return false; });
  pd::HeightFieldFillParameters p;
  p.lattice_factor = std::numeric_limits<double>::quiet_NaN();
  EXPECT_THROW(fill(points, p), pd::Error);
  p = {};
  p.detection_cell_factor = -1.0;
  EXPECT_THROW(fill(points, p), pd::Error);
  p = {};
  p.up = Eigen::Vector3d(std::numeric_limits<double>::infinity(), 0.0, 1.0);
  EXPECT_THROW(fill(points, p), pd::Error);
  // Two halves 10⁸ m apart: both are the bulk, the raster would be huge.
  auto split = points;
  for (std::size_t k = 0; k < split.size() / 2; ++k)
    split[k].x() += 1e8;
  try {
    fill(split);
    FAIL() << "no error";
  } catch (const pd::Error& e) {
    EXPECT_EQ(std::string(e.what()).find('\n'), std::string::npos);
    EXPECT_NE(std::string(e.what()).find("max_raster_cells"), std::string::npos);
  }
}

TEST(HeightFieldHoleFilling, TiltedCloudWithAutomaticUp)
{
  const auto flat = tile(50.0, [&](double u, double v) { return inDisc(u, v, 25.0, 25.0, 5.0); });
  const Eigen::Matrix3d tilt = Eigen::AngleAxisd(0.6, Eigen::Vector3d(1.0, 1.0, 0.0).normalized()).toRotationMatrix();
  std::vector<Eigen::Vector3d> points;
  for (const Eigen::Vector3d& p : flat)
    points.push_back(kOffset + tilt * (p - kOffset));
  pd::HeightFieldFillParameters p;
  p.up = Eigen::Vector3d::Zero();
  const FillRun run = fill(points, p);
  EXPECT_GT(run.report.up.dot(tilt * Eigen::Vector3d::UnitZ()), 0.98);
  EXPECT_EQ(run.report.holes_filled, 1u);
  double worst = 0.0;
  for (const Eigen::Vector3d& a : run.added) {
    const Eigen::Vector3d q = tilt.transpose() * (a - kOffset);
    worst = std::max(worst, std::abs(q.z() - terrain(q.x(), q.y())));
  }
  EXPECT_LT(worst, 0.2);
}

TEST(HeightFieldHoleFilling, RecognisesHeightFields)
{
  const auto terrain_points = tile(40.0, [](double, double) { return false; });
  Eigen::Vector3d up;
  double share = 0.0;
  EXPECT_TRUE(pd::isHeightFieldCloud(terrain_points, &up, &share));
  EXPECT_GT(up.z(), 0.99);
  EXPECT_GT(share, 0.95);
  std::vector<Eigen::Vector3d> sphere;  // closed surface: two layers everywhere
  std::mt19937 rng(5);
  std::normal_distribution<double> g;
  for (int k = 0; k < 20000; ++k)
    sphere.push_back(kOffset + 10.0 * Eigen::Vector3d(g(rng), g(rng), g(rng)).normalized());
  EXPECT_FALSE(pd::isHeightFieldCloud(sphere, nullptr, &share));
  EXPECT_LT(share, 0.5);
  std::vector<Eigen::Vector3d> junk(10, Eigen::Vector3d::Constant(std::numeric_limits<double>::quiet_NaN()));
  EXPECT_FALSE(pd::isHeightFieldCloud(junk));
}
