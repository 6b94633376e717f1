// Known answers for extractMeshHeightMaps and extractCloudHeightMaps: planes (level, tilted, at an edge, folded), the
// sinusoidal relief and a sphere in mesh mode; bin-centred grids in cloud mode; determinism; errors.
#include <pcl_patchdict/core/error.h>
#include <pcl_patchdict/patches/height_maps.h>
#include <pcl_patchdict/patches/patch_seeds.h>
#include <pcl_patchdict_eval/shapes.h>

#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include <cmath>
#include <random>

using namespace pcl::patchdict;

namespace {

std::vector<Eigen::Matrix3d> identityFrames(std::size_t count)
{
  return std::vector<Eigen::Matrix3d>(count, Eigen::Matrix3d::Identity());
}

// A right-handed frame whose Z is `normal`.
Eigen::Matrix3d frameWithNormal(const Eigen::Vector3d& normal)
{
  const Eigen::Vector3d z = normal.normalized();
  const Eigen::Vector3d helper = std::abs(z.x()) < 0.9 ? Eigen::Vector3d::UnitX() : Eigen::Vector3d::UnitY();
  const Eigen::Vector3d x = (helper - helper.dot(z) * z).normalized();
  const Eigen::Vector3d y = z.cross(x);
  Eigen::Matrix3d rotation;
  rotation.row(0) = x.transpose();
  rotation.row(1) = y.transpose();
  rotation.row(2) = z.transpose();
  return rotation;
}

double binCentre(int index, int grid, double radius)
{
  const double side = std::sqrt(2.0) * radius;
  return (index + 0.5) / grid * side - side / 2.0;
}

PatchSet extractMesh(const TriangleMesh& mesh, const std::vector<Eigen::Vector3d>& seeds,
                     const std::vector<Eigen::Matrix3d>& frames, double radius, int grid = 16, int threads = 0)
{
  PatchSet out;
  extractMeshHeightMaps(mesh, seeds, frames, {radius, grid, threads}, out);
  return out;
}

PatchSet extractCloud(const TriangleMesh& cloud, const std::vector<Eigen::Vector3d>& seeds,
                      const std::vector<Eigen::Matrix3d>& frames, double radius, int grid = 16, int threads = 0)
{
  PatchSet out;
  extractCloudHeightMaps(cloud.vertices, seeds, frames, {radius, grid, threads}, out);
  return out;
}

bool identical(const PatchSet& a, const PatchSet& b)
{
  return a.heights.rows() == b.heights.rows() && a.heights.cols() == b.heights.cols() &&
         (a.heights.array() == b.heights.array()).all() && a.observed == b.observed;
}

}  // namespace

TEST(HeightMapsMesh, LevelPlaneIdentityFrameIsZeroAndFullyObserved)
{
  const auto plane = makePlaneGrid(20, 20);
  const PatchSet set = extractMesh(plane, {Eigen::Vector3d(0.5, 0.5, 0.0), Eigen::Vector3d(0.33, 0.61, 0.0)},
                                   identityFrames(2), 0.1);
  ASSERT_EQ(set.heights.rows(), 256);
  ASSERT_EQ(set.heights.cols(), 2);
  EXPECT_EQ(set.grid_size, 16);
  EXPECT_DOUBLE_EQ(set.radius, 0.1);
  EXPECT_EQ(set.heights.cwiseAbs().maxCoeff(), 0.0);
  EXPECT_TRUE(set.observed.all());
  EXPECT_DOUBLE_EQ(set.observedFraction(), 1.0);
  EXPECT_EQ(set.source, std::vector<std::int32_t>({0, 0}));
}

TEST(HeightMapsMesh, RampFixesBinOrderColumnAlongXRowAlongY)
{
  // z = 0.5·x + 0.25·y: the height of bin (i, j) at row j·N + i is 0.5·x_i + 0.25·y_j.
  auto ramp = makePlaneGrid(10, 10);
  for (auto& v : ramp.vertices)
    v.z() = 0.5 * v.x() + 0.25 * v.y();
  const Eigen::Vector3d seed(0.5, 0.5, 0.375);
  const int grid = 8;
  const double radius = 0.1;
  const PatchSet set = extractMesh(ramp, {seed}, identityFrames(1), radius, grid);
  EXPECT_TRUE(set.observed.all());
  for (int j = 0; j < grid; ++j)
    for (int i = 0; i < grid; ++i)
      EXPECT_NEAR(set.heights(j * grid + i, 0), 0.5 * binCentre(i, grid, radius) + 0.25 * binCentre(j, grid, radius),
                  1e-14);
}

TEST(HeightMapsMesh, TiltedFrameGivesClosedFormSlope)
{
  // Frame rotated about X by θ: rows x = (1,0,0), y = (0,c,s), z = (0,−s,c). A world point (X, Y, 0)
  // relative to the seed has local y = c·Y, z = −s·Y, so the height at bin centre y is −y·s/c
  // (tan θ for the float-rounded c, s the extractor is given).
  const double theta = 0.3;
  Eigen::Matrix3d rows;
  rows << 1, 0, 0, 0, std::cos(theta), std::sin(theta), 0, -std::sin(theta), std::cos(theta);
  std::vector<Eigen::Matrix3d> frames;
  frames.push_back(roundToSinglePrecision(rows));
  const double c = frames[0](1, 1), s = frames[0](1, 2);
  const double radius = 0.1;
  const int grid = 16;
  const PatchSet set = extractMesh(makePlaneGrid(20, 20), {Eigen::Vector3d(0.5, 0.5, 0.0)}, frames, radius, grid);
  EXPECT_TRUE(set.observed.all());
  for (int j = 0; j < grid; ++j)
    for (int i = 0; i < grid; ++i) {
      const double y = binCentre(j, grid, radius);
      EXPECT_NEAR(set.heights(j * grid + i, 0), -y * s / c, 1e-12);
      EXPECT_NEAR(set.heights(j * grid + i, 0), -y * std::tan(theta), 1e-7);
    }
}

TEST(HeightMapsMesh, SinusoidalReliefMatchesInterpolantAndClosedForm)
{
  const int resolution = 200;
  const double amplitude = 0.01, period = 0.25, radius = 0.1;
  const int grid = 16;
  const auto relief = makeSinusoidalRelief(resolution, resolution, amplitude, period);
  std::vector<Eigen::Vector3d> seeds;
  for (const auto& cell : std::vector<std::pair<int, int>>{{60, 80}, {100, 100}, {130, 71}, {57, 143}})
    seeds.push_back(relief.vertices[static_cast<std::size_t>(cell.second) * (resolution + 1) + cell.first]);
  const PatchSet set = extractMesh(relief, seeds, identityFrames(seeds.size()), radius, grid);
  EXPECT_TRUE(set.observed.all());

  // Linear interpolation error on a triangle: ≤ ½·max‖Hessian‖·ρ², ρ the radius of the smallest
  // circle holding the triangle (h/√2 for the grid's right triangles of leg h), and the relief's
  // Hessian norm is at most amplitude·k² (its eigenvalues are amplitude·k²·cos(kx ± ky)).
  const double k = 2.0 * M_PI / period, h = 1.0 / resolution;
  const double bound = 0.5 * amplitude * k * k * (h * h / 2.0);
  double worst = 0.0;
  for (std::size_t p = 0; p < seeds.size(); ++p)
    for (int j = 0; j < grid; ++j)
      for (int i = 0; i < grid; ++i) {
        const double x = seeds[p].x() + binCentre(i, grid, radius), y = seeds[p].y() + binCentre(j, grid, radius);
        const double value = set.heights(j * grid + i, static_cast<Eigen::Index>(p));
        // The mesh's own interpolant, computed here from the grid's known split of each quad
        // (faces {a,b,c} below the diagonal, {a,c,d} above).
        const int ci = static_cast<int>(std::floor(x * resolution)), cj = static_cast<int>(std::floor(y * resolution));
        const double fx = x * resolution - ci, fy = y * resolution - cj;
        auto z = [&](int di, int dj) {
          return relief.vertices[static_cast<std::size_t>(cj + dj) * (resolution + 1) + ci + di].z();
        };
        const double interpolated = fx >= fy ? z(0, 0) + fx * (z(1, 0) - z(0, 0)) + fy * (z(1, 1) - z(1, 0))
                                             : z(0, 0) + fy * (z(0, 1) - z(0, 0)) + fx * (z(1, 1) - z(0, 1));
        EXPECT_NEAR(value, interpolated - seeds[p].z(), 1e-12);
        const double exact = sinusoidalReliefHeight(x, y, amplitude, period) - seeds[p].z();
        EXPECT_LE(std::abs(value - exact), bound);
        worst = std::max(worst, std::abs(value - exact));
      }
  // The bound is about 4e-5; the patches see heights up to 2e-2 — the comparison means something.
  EXPECT_GT(set.heights.cwiseAbs().maxCoeff(), 0.005);
  RecordProperty("worst_interpolation_error", std::to_string(worst));
}

TEST(HeightMapsMesh, SphereHeightsWithinTessellationError)
{
  const double sphere_radius = 1.0, radius = 0.3;
  const int grid = 16;
  const auto sphere = makeIcosphere(5, sphere_radius);
  // Every triangle lies inside the sphere; its gap to the sphere, radially, is at most
  // R − √(R² − ρ²) for its circumradius ρ, and along the frame's Z at most that over the cosine of
  // the angle between Z and the normal there (≥ cos(asin(r/R)) within the patch).
  double max_circumradius = 0.0;
  for (std::size_t f = 0; f < sphere.numFaces(); ++f) {
    const Eigen::Vector3d a = sphere.vertices[sphere.faces[f][0]], b = sphere.vertices[sphere.faces[f][1]],
                          c = sphere.vertices[sphere.faces[f][2]];
    const double la = (b - c).norm(), lb = (c - a).norm(), lc = (a - b).norm();
    max_circumradius = std::max(max_circumradius, la * lb * lc / (4.0 * sphere.faceArea(f)));
  }
  const double radial_gap = sphere_radius - std::sqrt(sphere_radius * sphere_radius - max_circumradius * max_circumradius);
  const double bound = radial_gap / std::cos(std::asin(radius / sphere_radius)) + 1e-6;

  std::vector<Eigen::Vector3d> seeds;
  std::vector<Eigen::Matrix3d> frames;
  for (const std::size_t v : {std::size_t{0}, std::size_t{100}, std::size_t{5000}, std::size_t{10241}}) {
    seeds.push_back(sphere.vertices[v]);
    frames.push_back(roundToSinglePrecision(frameWithNormal(sphere.vertices[v])));
  }
  const PatchSet set = extractMesh(sphere, seeds, frames, radius, grid);
  EXPECT_TRUE(set.observed.all());
  for (std::size_t p = 0; p < seeds.size(); ++p) {
    // The sphere in the (float) frame: centre at R·(0 − s); upper sheet.
    const Eigen::Vector3d centre = frames[p] * (-seeds[p]);
    for (int j = 0; j < grid; ++j)
      for (int i = 0; i < grid; ++i) {
        const double x = binCentre(i, grid, radius), y = binCentre(j, grid, radius);
        const double exact = centre.z() + std::sqrt(sphere_radius * sphere_radius - (x - centre.x()) * (x - centre.x()) -
                                                    (y - centre.y()) * (y - centre.y()));
        const double value = set.heights(j * grid + i, static_cast<Eigen::Index>(p));
        EXPECT_LE(value - exact, 1e-6);  // the mesh is inside the sphere
        EXPECT_GE(value - exact, -bound);
        EXPECT_NEAR(exact, -(sphere_radius - std::sqrt(sphere_radius * sphere_radius - x * x - y * y)), 1e-5);
      }
  }
}

TEST(HeightMapsMesh, SeedAtPlaneEdgeObservesOnlyTheBinsOverTheMesh)
{
  const auto plane = makePlaneGrid(20, 20);
  const int grid = 16;
  // Left edge: columns i < N/2 have x < 0, off the mesh. Corner: only i, j ≥ N/2 are on it.
  const PatchSet set = extractMesh(plane, {Eigen::Vector3d(0.0, 0.5, 0.0), Eigen::Vector3d(0.0, 0.0, 0.0)},
                                   identityFrames(2), 0.1, grid);
  EXPECT_EQ(set.observed.col(0).count(), grid * grid / 2);
  EXPECT_EQ(set.observed.col(1).count(), grid * grid / 4);
  for (int j = 0; j < grid; ++j)
    for (int i = 0; i < grid; ++i) {
      EXPECT_EQ(set.observed(j * grid + i, 0), i >= grid / 2);
      EXPECT_EQ(set.observed(j * grid + i, 1), i >= grid / 2 && j >= grid / 2);
      EXPECT_EQ(set.heights(j * grid + i, 0), 0.0);
    }
  EXPECT_DOUBLE_EQ(set.observedFraction(), (128.0 + 64.0) / 512.0);
}

TEST(HeightMapsMesh, FoldKeepsTheSheetClosestToThePatchPlane)
{
  // Two parallel sheets, z = 0 and z = 0.05; a seed at z = 0.04 sees −0.04 and +0.01: keeps +0.01.
  auto lower = makePlaneGrid(10, 10);
  auto both = lower;
  const auto offset = static_cast<std::int32_t>(lower.vertices.size());
  for (auto v : lower.vertices)
    both.vertices.push_back(v + Eigen::Vector3d(0, 0, 0.05));
  for (auto f : lower.faces)
    both.faces.push_back({f[0] + offset, f[1] + offset, f[2] + offset});
  const PatchSet set = extractMesh(both, {Eigen::Vector3d(0.5, 0.5, 0.04)}, identityFrames(1), 0.1, 8);
  EXPECT_TRUE(set.observed.all());
  for (Eigen::Index k = 0; k < set.heights.rows(); ++k)
    EXPECT_NEAR(set.heights(k, 0), 0.01, 1e-15);
}

TEST(HeightMapsMesh, SurfaceOutsideTheRadiusIsUnobserved)
{
  // A steep ramp z = 2·x: bin centre (x, y) lies at distance √(5x² + y²); beyond r it is not in the
  // r-neighbourhood of section 3.1 and stays unobserved.
  auto ramp = makePlaneGrid(20, 20);
  for (auto& v : ramp.vertices)
    v.z() = 2.0 * v.x();
  const int grid = 16;
  const double radius = 0.1;
  const PatchSet set = extractMesh(ramp, {Eigen::Vector3d(0.5, 0.5, 1.0)}, identityFrames(1), radius, grid);
  int expected = 0;
  for (int j = 0; j < grid; ++j)
    for (int i = 0; i < grid; ++i) {
      const double x = binCentre(i, grid, radius), y = binCentre(j, grid, radius);
      const bool inside = 5.0 * x * x + y * y <= radius * radius;
      expected += inside;
      EXPECT_EQ(set.observed(j * grid + i, 0), inside) << i << "," << j;
    }
  EXPECT_GT(expected, 0);
  EXPECT_LT(expected, grid * grid);
}

TEST(HeightMapsCloud, PointsAtBinCentresFillEveryBin)
{
  const int grid = 16;
  const double radius = 0.1;
  const Eigen::Vector3d seed(0.3, 0.7, 0.1);
  TriangleMesh all, every_other;
  for (int j = 0; j < grid; ++j)
    for (int i = 0; i < grid; ++i) {
      const Eigen::Vector3d point = seed + Eigen::Vector3d(binCentre(i, grid, radius), binCentre(j, grid, radius), 0.0);
      all.vertices.push_back(point);
      if (i % 2 == 0 && j % 2 == 0)
        every_other.vertices.push_back(point);
    }
  const PatchSet full = extractCloud(all, {seed}, identityFrames(1), radius, grid);
  EXPECT_DOUBLE_EQ(full.observedFraction(), 1.0);
  EXPECT_EQ(full.heights.cwiseAbs().maxCoeff(), 0.0);
  // One point per 2×2 bins: a quarter of the bins, exactly those with even i and j.
  const PatchSet quarter = extractCloud(every_other, {seed}, identityFrames(1), radius, grid);
  EXPECT_DOUBLE_EQ(quarter.observedFraction(), 0.25);
  for (int j = 0; j < grid; ++j)
    for (int i = 0; i < grid; ++i)
      EXPECT_EQ(quarter.observed(j * grid + i, 0), i % 2 == 0 && j % 2 == 0);
}

TEST(HeightMapsCloud, BinValueIsTheMeanHeightOfItsPoints)
{
  // 3×3 points per bin, symmetric about the centre, on z = 0.05·x: the mean is the centre's height.
  const int grid = 8;
  const double radius = 0.1;
  const double bin = std::sqrt(2.0) * radius / grid;
  TriangleMesh cloud;
  for (int j = 0; j < grid; ++j)
    for (int i = 0; i < grid; ++i)
      for (int dj = -1; dj <= 1; ++dj)
        for (int di = -1; di <= 1; ++di) {
          const double x = binCentre(i, grid, radius) + di * bin / 3.0, y = binCentre(j, grid, radius) + dj * bin / 3.0;
          cloud.vertices.emplace_back(x, y, 0.05 * x);
        }
  const PatchSet set = extractCloud(cloud, {Eigen::Vector3d::Zero()}, identityFrames(1), radius, grid);
  EXPECT_TRUE(set.observed.all());
  for (int j = 0; j < grid; ++j)
    for (int i = 0; i < grid; ++i)
      EXPECT_NEAR(set.heights(j * grid + i, 0), 0.05 * binCentre(i, grid, radius), 1e-15);
}

// The binned heights against a brute force over every point (the cells must miss none and take
// none too many): random points in a thick slab plus a far cluster (so the cells are coarsened to
// their budget), random seeds and tilted frames, the paper's bins and biweights of reach 1 and 1.7.
TEST(HeightMapsCloud, BinnedHeightsEqualABruteForceOverEveryPoint)
{
  std::mt19937_64 random(21);
  std::uniform_real_distribution<double> unit(0.0, 1.0), angle(-1.0, 1.0);
  std::vector<Eigen::Vector3d> points;
  for (int i = 0; i < 20000; ++i)
    points.emplace_back(unit(random), unit(random), 0.2 * unit(random));
  std::vector<Eigen::Vector3d> with_far_cluster = points;
  for (int i = 0; i < 50; ++i)
    with_far_cluster.emplace_back(300.0 + unit(random), -200.0 + unit(random), 50.0);
  std::vector<Eigen::Vector3d> seeds;
  std::vector<Eigen::Matrix3d> frames;
  for (int k = 0; k < 60; ++k) {
    seeds.emplace_back(unit(random), unit(random), 0.2 * unit(random));
    frames.push_back(roundToSinglePrecision((Eigen::AngleAxisd(angle(random) * 3.0, Eigen::Vector3d::UnitZ()) *
                                             Eigen::AngleAxisd(angle(random), Eigen::Vector3d::UnitX()))
                                                .toRotationMatrix()
                                                .transpose()));
  }
  const double radius = 0.08;
  const int n = 12;
  const double side = std::sqrt(2.0) * radius, bin = side / n;
  for (const auto* cloud : {&points, &with_far_cluster}) {
    for (double reach : {0.0, 1.0, 1.7}) {
      HeightMapParameters parameters{radius, n, 2};
      parameters.bin_reach = reach;
      PatchSet set;
      extractCloudHeightMaps(*cloud, seeds, frames, parameters, set);
      std::size_t observed = 0;
      for (std::size_t p = 0; p < seeds.size(); ++p) {
        std::vector<double> sums(n * n, 0.0), weights(n * n, 0.0);
        for (const auto& point : *cloud) {
          const Eigen::Vector3d local = frames[p] * (point - seeds[p]);
          if (local.norm() > radius)
            continue;
          for (int v = 0; v < n; ++v)
            for (int u = 0; u < n; ++u) {
              const double cx = (u + 0.5) * bin - side / 2.0, cy = (v + 0.5) * bin - side / 2.0;
              double w = 0.0;
              if (reach == 0.0) {
                w = std::abs(local.x() - cx) < bin / 2.0 && std::abs(local.y() - cy) < bin / 2.0 ? 1.0 : 0.0;
              } else {
                const double d2 = ((local.x() - cx) * (local.x() - cx) + (local.y() - cy) * (local.y() - cy)) /
                                  (reach * bin * reach * bin);
                w = d2 < 1.0 ? (1.0 - d2) * (1.0 - d2) : 0.0;
              }
              sums[v * n + u] += w * local.z();
              weights[v * n + u] += w;
            }
        }
        for (int k = 0; k < n * n; ++k) {
          // A weight within rounding of zero may land on either side: only clear cases are compared.
          if (weights[k] > 1e-9) {
            ASSERT_TRUE(set.observed(k, p)) << "reach " << reach << " patch " << p << " bin " << k;
            EXPECT_NEAR(set.heights(k, p), sums[k] / weights[k], 1e-12) << "reach " << reach;
            ++observed;
          } else if (weights[k] == 0.0) {
            EXPECT_FALSE(set.observed(k, p)) << "reach " << reach << " patch " << p << " bin " << k;
          }
        }
      }
      EXPECT_GT(observed, seeds.size() * n * n / 2) << "reach " << reach;  // the slab fills most bins
    }
  }
}

TEST(HeightMapsDeterminism, SameResultTwiceAndForAnyThreadCount)
{
  const auto relief = makeSinusoidalRelief(120, 120, 0.02, 0.3);
  std::mt19937_64 random(7);
  std::uniform_int_distribution<std::size_t> pick(0, relief.numVertices() - 1);
  std::uniform_real_distribution<double> angle(-0.5, 0.5);
  std::vector<Eigen::Vector3d> seeds;
  std::vector<Eigen::Matrix3d> frames;
  for (int k = 0; k < 400; ++k) {
    seeds.push_back(relief.vertices[pick(random)]);
    const Eigen::Matrix3d rotation =
        (Eigen::AngleAxisd(angle(random) * 6.0, Eigen::Vector3d::UnitZ()) *
         Eigen::AngleAxisd(angle(random), Eigen::Vector3d::UnitX()))
            .toRotationMatrix()
            .transpose();
    frames.push_back(roundToSinglePrecision(rotation));
  }
  const PatchSet one = extractMesh(relief, seeds, frames, 0.05, 16, 1);
  const PatchSet two = extractMesh(relief, seeds, frames, 0.05, 16, 2);
  const PatchSet again = extractMesh(relief, seeds, frames, 0.05, 16, 0);
  EXPECT_TRUE(identical(one, two));
  EXPECT_TRUE(identical(one, again));
  EXPECT_GT(one.observedFraction(), 0.5);  // seeds near the border lose bins, the others are full

  const PatchSet cloud_one = extractCloud(relief, seeds, frames, 0.05, 16, 1);
  const PatchSet cloud_two = extractCloud(relief, seeds, frames, 0.05, 16, 2);
  EXPECT_TRUE(identical(cloud_one, cloud_two));
  EXPECT_GT(cloud_one.observedFraction(), 0.0);
}

TEST(HeightMapErrors, BadInputIsRejectedWithOneLine)
{
  const auto plane = makePlaneGrid(4, 4);
  const std::vector<Eigen::Vector3d> seeds{Eigen::Vector3d(0.5, 0.5, 0.0)};
  // Each case: the mesh, seeds, frames and parameters given to extractMeshHeightMaps.
  const auto expectError = [](const TriangleMesh& mesh, const std::vector<Eigen::Vector3d>& seeds_given,
                              const std::vector<Eigen::Matrix3d>& frames, const HeightMapParameters& parameters,
                              const char* what) {
    PatchSet out;
    try {
      extractMeshHeightMaps(mesh, seeds_given, frames, parameters, out);
      ADD_FAILURE() << "no error for " << what;
    } catch (const Error& error) {
      EXPECT_EQ(std::string(error.what()).find('\n'), std::string::npos) << error.what();
    }
  };
  const HeightMapParameters good{0.1};
  expectError(TriangleMesh(), seeds, identityFrames(1), good, "no surface at all");
  expectError(plane, seeds, identityFrames(2), good, "frames count");
  expectError(plane, seeds, identityFrames(1), {0.0}, "zero radius");
  expectError(plane, seeds, identityFrames(1), {-1.0}, "negative radius");
  expectError(plane, seeds, identityFrames(1), {std::nan("")}, "NaN radius");
  expectError(plane, seeds, identityFrames(1), {0.1, 1}, "grid 1");
  std::vector<Eigen::Matrix3d> skewed = identityFrames(1);
  skewed[0](0, 1) = 0.5;
  expectError(plane, seeds, skewed, good, "non-orthonormal frame");
  std::vector<Eigen::Matrix3d> mirrored = identityFrames(1);
  mirrored[0](2, 2) = -1.0;
  expectError(plane, seeds, mirrored, good, "left-handed frame");
  expectError(plane, {Eigen::Vector3d(std::nan(""), 0, 0)}, identityFrames(1), good, "NaN seed");
  TriangleMesh bare = plane;
  bare.faces.clear();
  expectError(bare, seeds, identityFrames(1), good, "mesh without faces");
  TriangleMesh broken = plane;
  broken.faces[0][1] = 1000;
  expectError(broken, seeds, identityFrames(1), good, "face index out of range");
  PatchSet out;
  EXPECT_THROW(extractCloudHeightMaps({}, seeds, identityFrames(1), good, out), Error);  // empty cloud

  // And the valid configuration works.
  EXPECT_NO_THROW(extractMeshHeightMaps(plane, seeds, identityFrames(1), good, out));
  EXPECT_EQ(out.numPatches(), 1u);
}

// layPatches, the one way from a surface to seeds and frames: a cloud's seeds lie on its Poisson
// surface (here a sphere's vertices: near the sphere, frames' Z along its normal), a mesh's on the
// mesh; random placement lays 12·(1 + 4k)/5 seeds per L² of area; the extraction reads the layout's
// side. Bad parameters are one Error.
TEST(LayPatches, CloudsOnTheirPoissonSurfaceMeshesOnThemselvesRandomByArea)
{
  TriangleMesh cloud = makeIcosphere(5, 0.45);
  cloud.faces.clear();
  PatchLayoutParameters parameters;
  parameters.quad_length = 0.08;
  PatchPlacementReport report;
  const PatchLayout on_cloud = layPatches(cloud, parameters, SeedPlacement::Quads, &report);
  EXPECT_TRUE(report.from_cloud);
  EXPECT_GT(report.poisson_depth, 0);
  EXPECT_GT(report.surface_faces, 0u);
  ASSERT_GT(on_cloud.seeds.size(), 50u);
  for (std::size_t s = 0; s < on_cloud.seeds.size(); ++s) {
    EXPECT_NEAR(on_cloud.seeds[s].norm(), 0.45, 0.02) << s;
    EXPECT_GT(on_cloud.frames[s].row(2).dot(on_cloud.seeds[s].normalized()), 0.9) << s;
  }
  const PatchSet heights = extractSurfacePatches(cloud, on_cloud, 8);
  EXPECT_EQ(heights.numPatches(), on_cloud.seeds.size());
  EXPECT_NEAR(heights.side(), 0.08, 1e-12);

  const TriangleMesh plane = makePlaneGrid(20, 20, 1.0, 1.0);
  PatchPlacementReport mesh_report;
  const PatchLayout random = layPatches(plane, parameters, SeedPlacement::Random, &mesh_report);
  EXPECT_FALSE(mesh_report.from_cloud);
  EXPECT_EQ(random.seeds.size(), static_cast<std::size_t>(std::ceil(12.0 * 5.0 / 5.0 / (0.08 * 0.08))));
  for (const auto& seed : random.seeds)
    EXPECT_EQ(seed.z(), 0.0);
  parameters.quad_length = 0.0;
  EXPECT_THROW(layPatches(plane, parameters), Error);
  parameters.quad_length = 0.08;
  parameters.overlap = 17;
  EXPECT_THROW(layPatches(plane, parameters), Error);
  cloud.vertices.resize(10);
  parameters.overlap = 1;
  EXPECT_THROW(layPatches(cloud, parameters), Error);
}
