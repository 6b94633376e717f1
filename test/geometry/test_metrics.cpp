// Tests of the metrics: closest point on a triangle (all Voronoi regions, degenerate triangles,
// against an independent brute-force minimisation), the AABB-tree distance against a loop over
// all faces, closed-form distances to planes and spheres, surface distances and PSNR, vertex RMSE.
#include <pcl_patchdict/core/error.h>
#include <pcl_patchdict/geometry/metrics.h>
#include <pcl_patchdict_eval/shapes.h>

#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <string>

#include <omp.h>

using namespace pcl::patchdict;
using Eigen::Vector3d;

namespace {

/** Reference answer: min over all faces, no tree. */
double bruteForceSquaredDistance(const TriangleMesh& m, const Vector3d& p)
{
  double best = std::numeric_limits<double>::infinity();
  for (const Face& f : m.faces)
    best = std::min(best, (p - closestPointOnTriangle(p, m.vertices[f[0]], m.vertices[f[1]],
                                                       m.vertices[f[2]])).squaredNorm());
  return best;
}

/** Independent minimiser of |p − x| over the triangle: grid over the barycentric simplex, then
  * repeated zooms (×10) around the best grid point. |p − x(u,v)|² is convex in (u, v), so
  * zooming around the grid minimum converges to the global one. */
double gridSearchDistance(const Vector3d& p, const Vector3d& a, const Vector3d& b, const Vector3d& c)
{
  auto dist = [&](double u, double v) { return (a + u * (b - a) + v * (c - a) - p).norm(); };
  double best = std::numeric_limits<double>::infinity(), bu = 0, bv = 0;
  double cu = 0.5, cv = 0.5, half = 0.5;  // window centre and half-width
  for (int level = 0; level < 8; ++level) {
    const int steps = level == 0 ? 100 : 60;
    const double h = 2 * half / steps;
    for (int i = 0; i <= steps; ++i)
      for (int j = 0; j <= steps; ++j) {
        const double u = std::clamp(cu - half + i * h, 0.0, 1.0);
        double v = std::clamp(cv - half + j * h, 0.0, 1.0);
        if (u + v > 1.0)
          v = 1.0 - u;
        const double d = dist(u, v);
        if (d < best) {
          best = d;
          bu = u;
          bv = v;
        }
      }
    cu = bu;
    cv = bv;
    half = 3 * h;
  }
  return best;
}

void expectNear(const Vector3d& got, const Vector3d& want, double tol, const char* what)
{
  EXPECT_LT((got - want).norm(), tol) << what << ": got " << got.transpose() << ", want " << want.transpose();
}

}  // namespace

// ------------------------------------------------------------------ closestPointOnTriangle

TEST(MetricsClosestPoint, SevenVoronoiRegions)
{
  // Triangle a=(0,0,0), b=(4,0,0), c=(0,3,0); answers worked out by hand. The same cases are
  // then replayed after a rigid motion, so no axis alignment helps the implementation.
  const Vector3d a(0, 0, 0), b(4, 0, 0), c(0, 3, 0);
  struct Case {
    const char* region;
    Vector3d p, want;
  };
  const Case cases[] = {
      {"face", {1, 1, 5}, {1, 1, 0}},
      {"vertex a", {-1, -2, 3}, a},
      {"vertex b", {6, -1, 2}, b},
      {"vertex c", {-1, 5, 1}, c},
      {"edge ab", {2, -3, 1}, {2, 0, 0}},
      {"edge ac", {-2, 1, -1}, {0, 1, 0}},
      // Edge bc: midpoint (2, 1.5) plus 5 × its outward unit normal (3, 4)/5.
      {"edge bc", {5, 5.5, 2}, {2, 1.5, 0}},
      {"on the face", {1, 0.5, 0}, {1, 0.5, 0}},
  };
  const Eigen::Matrix3d rotation = Eigen::AngleAxisd(0.7, Vector3d(1, 2, -0.5).normalized()).toRotationMatrix();
  const Vector3d shift(0.3, -1.7, 2.9);
  for (const Case& k : cases) {
    expectNear(closestPointOnTriangle(k.p, a, b, c), k.want, 1e-12, k.region);
    // The vertex order must not matter.
    expectNear(closestPointOnTriangle(k.p, c, a, b), k.want, 1e-12, k.region);
    expectNear(closestPointOnTriangle(k.p, b, a, c), k.want, 1e-12, k.region);
    auto move = [&](const Vector3d& x) -> Vector3d { return rotation * x + shift; };
    expectNear(closestPointOnTriangle(move(k.p), move(a), move(b), move(c)), move(k.want), 1e-12, k.region);
  }
}

TEST(MetricsClosestPoint, CollinearTriangleIsItsSegment)
{
  // c beyond b: the point set is the segment [a, c].
  const Vector3d a(0, 0, 0), b(1, 0, 0), c(3, 0, 0);
  expectNear(closestPointOnTriangle({2, 1, 0}, a, b, c), {2, 0, 0}, 1e-15, "middle");
  expectNear(closestPointOnTriangle({0.5, -2, 7}, a, b, c), {0.5, 0, 0}, 1e-15, "between a and b");
  expectNear(closestPointOnTriangle({4, 1, 1}, a, b, c), c, 1e-15, "past c");
  expectNear(closestPointOnTriangle({-1, 0, 2}, a, b, c), a, 1e-15, "before a");
  // Tilted, middle vertex listed last, exactly representable collinear coordinates.
  const Vector3d d(1, 1, 1), e(3, 3, 3), f(2, 2, 2);
  expectNear(closestPointOnTriangle({2.5, 1.5, 2}, d, e, f), {2, 2, 2}, 1e-15, "tilted middle");
  expectNear(closestPointOnTriangle({6, 4, 5}, d, e, f), e, 1e-15, "tilted end");
  // Two coincident vertices.
  expectNear(closestPointOnTriangle({0.5, 1, 0}, a, a, b), {0.5, 0, 0}, 1e-15, "a = b");
}

TEST(MetricsClosestPoint, PointTriangle)
{
  const Vector3d a(1, 2, 3);
  EXPECT_EQ(closestPointOnTriangle({-4, 0, 9}, a, a, a), a);
  EXPECT_EQ(closestPointOnTriangle(a, a, a, a), a);
}

TEST(MetricsClosestPoint, MatchesBruteForceOnRandomTriangles)
{
  std::mt19937_64 rng(12345);
  std::uniform_real_distribution<double> coord(-1.0, 1.0), far(-3.0, 3.0);
  double worst_gap = 0.0;
  for (int trial = 0; trial < 300; ++trial) {
    const Vector3d a(coord(rng), coord(rng), coord(rng)), b(coord(rng), coord(rng), coord(rng));
    Vector3d c(coord(rng), coord(rng), coord(rng));
    const bool sliver = trial % 10 == 0;
    if (sliver)  // c within 1e-5 of the line ab
      c = a + 0.6 * (b - a) + 1e-5 * Vector3d(coord(rng), coord(rng), coord(rng));
    const Vector3d p(far(rng), far(rng), far(rng));
    const Vector3d q = closestPointOnTriangle(p, a, b, c);
    // q must be on the triangle: its own closest point is itself. A sliver's plane is known only
    // to ~ε/width in double precision (its area is), hence the looser bound there.
    EXPECT_LT((closestPointOnTriangle(q, a, b, c) - q).norm(), sliver ? 1e-10 : 1e-12) << trial;
    const double exact = (p - q).norm();
    const double brute = gridSearchDistance(p, a, b, c);
    EXPECT_LE(exact, brute + 1e-12) << "trial " << trial;
    EXPECT_NEAR(exact, brute, 1e-6) << "trial " << trial;
    worst_gap = std::max(worst_gap, brute - exact);
  }
  RecordProperty("worst_gap_to_grid_search", std::to_string(worst_gap));
}

// ------------------------------------------------------------------ PointToMeshDistance

namespace {

std::vector<Vector3d> testPoints(const TriangleMesh& mesh, std::size_t n, std::uint64_t seed)
{
  Vector3d lo, hi;
  mesh.boundingBox(lo, hi);
  const Vector3d margin = 0.3 * (hi - lo);
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::normal_distribution<double> noise(0.0, 0.01);
  std::vector<Vector3d> points;
  for (std::size_t i = 0; i < n; ++i) {
    if (i % 2 == 0) {  // anywhere in the expanded box
      const Vector3d t(unit(rng), unit(rng), unit(rng));
      points.push_back(lo - margin + t.cwiseProduct(hi - lo + 2 * margin));
    } else {  // close to a vertex of the surface
      const Vector3d& v = mesh.vertices[rng() % mesh.vertices.size()];
      points.push_back(v + Vector3d(noise(rng), noise(rng), noise(rng)));
    }
  }
  return points;
}

void checkAgainstBruteForce(const TriangleMesh& mesh, std::size_t n, std::uint64_t seed)
{
  const PointToMeshDistance tree(mesh);
  const std::vector<Vector3d> points = testPoints(mesh, n, seed);
  const std::vector<double> d = tree.distances(points);
  ASSERT_EQ(d.size(), points.size());
  for (std::size_t i = 0; i < points.size(); ++i) {
    const Vector3d& p = points[i];
    const double want = bruteForceSquaredDistance(mesh, p);
    const PointToMeshDistance::Result r = tree.query(p);
    ASSERT_NEAR(r.squared_distance, want, 1e-12 * std::max(want, 1e-300)) << "point " << i;
    ASSERT_GE(r.face, 0);
    ASSERT_LT(static_cast<std::size_t>(r.face), mesh.faces.size());
    // The reported point is on the reported face and realises the reported distance.
    const Face& f = mesh.faces[r.face];
    const Vector3d on_face = closestPointOnTriangle(p, mesh.vertices[f[0]], mesh.vertices[f[1]], mesh.vertices[f[2]]);
    ASSERT_LT((on_face - r.closest_point).norm(), 1e-14);
    ASSERT_NEAR((p - r.closest_point).squaredNorm(), r.squared_distance, 1e-15);
    ASSERT_EQ(d[i], std::sqrt(r.squared_distance));
  }
}

}  // namespace

TEST(MetricsPointToMesh, TorusMatchesBruteForce) { checkAgainstBruteForce(makeTorus(48, 24, 1.0, 0.35), 2000, 1); }

TEST(MetricsPointToMesh, IcosphereMatchesBruteForce) { checkAgainstBruteForce(makeIcosphere(3), 2000, 2); }

TEST(MetricsPointToMesh, AwkwardMeshesMatchBruteForce)
{
  // Degenerate faces, duplicated faces, many faces with one centroid (the tree must halve them).
  TriangleMesh m = makePlaneGrid(3, 2);
  const auto base = static_cast<std::int32_t>(m.vertices.size());
  m.vertices.push_back({0.5, 0.5, 1.0});
  m.vertices.push_back({1.5, 0.5, 1.0});
  m.vertices.push_back({2.5, 0.5, 1.0});
  m.faces.push_back({base, base + 1, base + 2});  // collinear
  m.faces.push_back({base, base, base});          // a point
  for (int k = 0; k < 13; ++k)
    m.faces.push_back(m.faces[k % 2]);            // duplicates
  for (int k = 0; k < 9; ++k) {                   // nested triangles sharing the centroid (1, 1, 2)
    const double s = 0.1 * (k + 1);
    const auto i = static_cast<std::int32_t>(m.vertices.size());
    m.vertices.push_back(Vector3d(1, 1, 2) + s * Vector3d(1, 0, 0));
    m.vertices.push_back(Vector3d(1, 1, 2) + s * Vector3d(-0.5, 0.8, 0.1 * k));
    m.vertices.push_back(Vector3d(1, 1, 2) + s * Vector3d(-0.5, -0.8, -0.1 * k));
    m.faces.push_back({i, i + 1, i + 2});
  }
  checkAgainstBruteForce(m, 2000, 3);
  TriangleMesh single;
  single.vertices = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  single.faces = {{0, 1, 2}};
  checkAgainstBruteForce(single, 200, 4);
}

TEST(MetricsPointToMesh, PlaneDistanceIsAbsZ)
{
  const PointToMeshDistance tree(makePlaneGrid(20, 20));
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> unit(0.0, 1.0), height(-2.0, 2.0);
  for (int i = 0; i < 2000; ++i) {
    const Vector3d p(unit(rng), unit(rng), height(rng));
    const auto r = tree.query(p);
    ASSERT_NEAR(std::sqrt(r.squared_distance), std::abs(p.z()), 1e-12) << p.transpose();
    ASSERT_NEAR((r.closest_point - Vector3d(p.x(), p.y(), 0)).norm(), 0.0, 1e-12);
  }
}

TEST(MetricsPointToMesh, BeyondThePlaneEdgeIsDistanceToTheBoundary)
{
  const PointToMeshDistance tree(makePlaneGrid(7, 5));
  struct Case {
    Vector3d p, closest;
  };
  const Case cases[] = {
      {{1.5, 0.3, 0.2}, {1.0, 0.3, 0.0}},      // past x = 1
      {{0.5, 1.25, -0.6}, {0.5, 1.0, 0.0}},    // past y = 1
      {{-0.3, -0.4, 0.0}, {0.0, 0.0, 0.0}},    // past a corner, in the plane
      {{-2.0, 0.71, 3.0}, {0.0, 0.71, 0.0}},   // past x = 0
      {{1.2, 1.3, 0.4}, {1.0, 1.0, 0.0}},      // past the opposite corner
  };
  for (const Case& k : cases) {
    const auto r = tree.query(k.p);
    EXPECT_NEAR(std::sqrt(r.squared_distance), (k.p - k.closest).norm(), 1e-12) << k.p.transpose();
    expectNear(r.closest_point, k.closest, 1e-12, "boundary point");
  }
}

namespace {

/** Largest angle subtended at the centre by an edge of a mesh on the unit sphere. */
double maxEdgeAngle(const TriangleMesh& m)
{
  double worst = 0.0;
  for (const Face& f : m.faces)
    for (int k = 0; k < 3; ++k) {
      const Vector3d& u = m.vertices[f[k]];
      const Vector3d& v = m.vertices[f[(k + 1) % 3]];
      worst = std::max(worst, std::atan2(u.cross(v).norm(), u.dot(v)));
    }
  return worst;
}

/** Smallest distance from the centre to a face plane (all vertices on the unit sphere). */
double minFacePlaneDistance(const TriangleMesh& m)
{
  double h = std::numeric_limits<double>::infinity();
  for (std::size_t f = 0; f < m.faces.size(); ++f)
    h = std::min(h, std::abs(m.faceNormal(f).dot(m.vertices[m.faces[f][0]])));
  return h;
}

/** Tessellation error bound for an icosphere of radius 1 with acute faces.
  * The sagitta of one edge of angle θ is 1 − cos(θ/2), but a face's centre sinks deeper: its
  * plane lies at √(1 − R²) from the centre, R = chord circumradius. For an acute triangle
  * R = c/(2 sin C) ≤ c/√3 (C ≥ 60° is the largest angle, opposite the longest chord c =
  * 2 sin(θ/2)), hence the depth is at most 1 − √(1 − (4/3) sin²(θ_max/2)). */
double icosphereSagittaBound(const TriangleMesh& m)
{
  const double s = std::sin(maxEdgeAngle(m) / 2);
  return 1.0 - std::sqrt(1.0 - 4.0 / 3.0 * s * s);
}

bool allFacesAcute(const TriangleMesh& m)
{
  for (const Face& f : m.faces)
    for (int k = 0; k < 3; ++k) {
      const Vector3d& o = m.vertices[f[k]];
      if ((m.vertices[f[(k + 1) % 3]] - o).dot(m.vertices[f[(k + 2) % 3]] - o) <= 0.0)
        return false;
    }
  return true;
}

}  // namespace

TEST(MetricsPointToMesh, SphereDistanceWithinTessellationBound)
{
  const TriangleMesh sphere = makeIcosphere(5);
  ASSERT_TRUE(allFacesAcute(sphere));
  const double bound = icosphereSagittaBound(sphere);
  const double edge_sagitta = 1.0 - std::cos(maxEdgeAngle(sphere) / 2);
  // The measured depth of the deepest face plane lies between the edge sagitta and the bound.
  const double depth = 1.0 - minFacePlaneDistance(sphere);
  ASSERT_GT(depth, edge_sagitta);
  ASSERT_LE(depth, bound + 1e-12);  // equality for an equilateral face
  ASSERT_LT(bound, 1e-3);  // level 5 is fine: θ_max ≈ 0.04 rad

  const PointToMeshDistance tree(sphere);
  std::mt19937_64 rng(77);
  std::normal_distribution<double> gauss;
  double largest_deviation = 0.0;
  for (const double rho : {0.3, 0.8, 0.97, 0.999, 1.0, 1.001, 1.03, 1.5, 3.0}) {
    for (int i = 0; i < 300; ++i) {
      const Vector3d dir = Vector3d(gauss(rng), gauss(rng), gauss(rng)).normalized();
      const double d = std::sqrt(tree.query(rho * dir).squared_distance);
      const double deviation = rho >= 1.0 ? d - (rho - 1.0) : (1.0 - rho) - d;
      // Outside: the polyhedron is inside the unit ball (d ≥ ρ − 1) and its radial point is at
      // depth ≤ bound. Inside: it contains the ball of radius 1 − bound, so the same holds mirrored.
      ASSERT_GE(deviation, -1e-12) << "rho " << rho;
      ASSERT_LE(deviation, bound + 1e-12) << "rho " << rho;
      largest_deviation = std::max(largest_deviation, deviation);
    }
  }
  EXPECT_GT(largest_deviation, 0.2 * bound);  // the bound is not vacuous
}

TEST(MetricsPointToMesh, EdgeCases)
{
  TriangleMesh cloud;
  cloud.vertices = {{0, 0, 0}};
  EXPECT_THROW(PointToMeshDistance{cloud}, Error);
  TriangleMesh bad;
  bad.vertices = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  bad.faces = {{0, 1, 5}};
  EXPECT_THROW(PointToMeshDistance{bad}, Error);

  PointToMeshDistance tree(makePlaneGrid(2, 2));
  EXPECT_TRUE(tree.distances({}).empty());
  EXPECT_THROW(tree.distances({Vector3d(0, 0, std::nan(""))}), Error);
  PointToMeshDistance moved(std::move(tree));
  EXPECT_DOUBLE_EQ(moved.query({0.5, 0.5, 2.0}).squared_distance, 4.0);
}

TEST(MetricsPointToMesh, DistancesIndependentOfThreads)
{
  const TriangleMesh mesh = makeTorus(60, 30);
  const PointToMeshDistance tree(mesh);
  const std::vector<Vector3d> points = testPoints(mesh, 20000, 9);
  const int saved = omp_get_max_threads();
  omp_set_num_threads(1);
  const std::vector<double> one = tree.distances(points);
  omp_set_num_threads(3);
  const std::vector<double> three = tree.distances(points);
  omp_set_num_threads(saved);
  EXPECT_EQ(one, three);
}

// ------------------------------------------------------------------ surface distance, PSNR

TEST(MetricsSurfaceDistance, IdenticalMeshesAreAtZeroAndInfinitePsnr)
{
  const TriangleMesh torus = makeTorus(40, 20);
  for (const TriangleMesh& mesh : {torus, makePlaneGrid(5, 5), makeIcosphere(2)}) {
    const SurfaceDistance s = surfaceDistance(mesh, mesh, 20000, 3);
    EXPECT_EQ(s.mean, 0.0);
    EXPECT_EQ(s.rms, 0.0);
    EXPECT_EQ(s.hausdorff, 0.0);
    EXPECT_EQ(s.max_ref_to_out, 0.0);
    EXPECT_EQ(s.max_out_to_ref, 0.0);
    EXPECT_TRUE(std::isinf(s.psnr) && s.psnr > 0);
    EXPECT_EQ(s.samples_per_side, 20000u);
  }
  // Same surface, faces listed in another order and rotated corner order.
  TriangleMesh shuffled = torus;
  std::reverse(shuffled.faces.begin(), shuffled.faces.end());
  for (Face& f : shuffled.faces)
    f = {f[1], f[2], f[0]};
  EXPECT_EQ(surfaceDistance(torus, shuffled, 20000, 4).hausdorff, 0.0);
}

TEST(MetricsSurfaceDistance, ShiftedPlaneGivesTheShiftEverywhere)
{
  const TriangleMesh ref = makePlaneGrid(10, 10);
  for (const double d : {0.01, 0.25}) {
    TriangleMesh out = ref;
    for (auto& v : out.vertices)
      v.z() += d;
    const SurfaceDistance s = surfaceDistance(ref, out, 50000, 8);
    for (const double value : {s.mean_ref_to_out, s.rms_ref_to_out, s.max_ref_to_out, s.mean_out_to_ref,
                               s.rms_out_to_ref, s.max_out_to_ref, s.mean, s.rms, s.hausdorff})
      EXPECT_NEAR(value, d, 1e-12);
    EXPECT_NEAR(s.bbox_diagonal, std::sqrt(2.0), 1e-15);
    EXPECT_NEAR(s.psnr, 20.0 * std::log10(std::sqrt(2.0) / d), 1e-9);
  }
}

TEST(MetricsSurfaceDistance, ScaledSphereGivesTheRadiusChange)
{
  // ref: icosphere of radius 1; out: the same polyhedron scaled by 1 + d. Both are convex and
  // one is the other scaled, so every sample's distance lies in [d·h_min, d], where h_min is the
  // smallest distance from the centre to a face plane (proof: supporting planes from below, the
  // radial segment from above). h_min ≥ 1 − the sagitta bound.
  const TriangleMesh ref = makeIcosphere(4);
  const double d = 0.01;
  TriangleMesh out = ref;
  for (auto& v : out.vertices)
    v *= 1.0 + d;
  const double h_min = minFacePlaneDistance(ref);
  ASSERT_GE(h_min, 1.0 - icosphereSagittaBound(ref) - 1e-12);
  const SurfaceDistance s = surfaceDistance(ref, out, 50000, 21);
  for (const double mean : {s.mean_ref_to_out, s.mean_out_to_ref, s.mean, s.rms}) {
    EXPECT_GE(mean, d * h_min - 1e-12);
    EXPECT_LE(mean, d + 1e-12);
  }
  EXPECT_LE(s.hausdorff, d + 1e-12);
  EXPECT_GE(s.hausdorff, d * h_min);
  EXPECT_NEAR(s.bbox_diagonal, ref.boundingBoxDiagonal(), 0.0);
  EXPECT_NEAR(s.psnr, 20.0 * std::log10(s.bbox_diagonal / s.rms), 1e-12);
}

TEST(MetricsSurfaceDistance, DeterministicAndSeeded)
{
  const TriangleMesh ref = makeTorus(30, 15);
  const TriangleMesh out = makeTorus(23, 11);
  const SurfaceDistance a = surfaceDistance(ref, out, 10000, 5);
  const SurfaceDistance b = surfaceDistance(ref, out, 10000, 5);
  const SurfaceDistance c = surfaceDistance(ref, out, 10000, 6);
  EXPECT_EQ(a.mean, b.mean);
  EXPECT_EQ(a.rms, b.rms);
  EXPECT_EQ(a.hausdorff, b.hausdorff);
  EXPECT_NE(a.mean, c.mean);
  // Different tessellations of the same torus: small but non-zero, and symmetric-ish.
  EXPECT_GT(a.mean, 0.0);
  EXPECT_LT(a.hausdorff, 0.05);
  EXPECT_NEAR(a.mean, 0.5 * (a.mean_ref_to_out + a.mean_out_to_ref), 1e-15);
  EXPECT_NEAR(a.rms * a.rms, 0.5 * (a.rms_ref_to_out * a.rms_ref_to_out + a.rms_out_to_ref * a.rms_out_to_ref),
              1e-15);
}

TEST(MetricsSurfaceDistance, RejectsBadInput)
{
  TriangleMesh cloud;
  cloud.vertices = {{0, 0, 0}, {1, 1, 1}};
  const TriangleMesh plane = makePlaneGrid(2, 2);
  EXPECT_THROW(surfaceDistance(cloud, plane), Error);
  EXPECT_THROW(surfaceDistance(plane, cloud), Error);
  EXPECT_THROW(surfaceDistance(plane, plane, 0), Error);
}

TEST(MetricsPsnr, KnownValues)
{
  EXPECT_DOUBLE_EQ(psnr(10.0, 1.0), 20.0);
  EXPECT_DOUBLE_EQ(psnr(1.0, 0.001), 60.0);
  EXPECT_TRUE(std::isinf(psnr(1.0, 0.0)));
  EXPECT_THROW(psnr(1.0, -1.0), Error);
  EXPECT_THROW(psnr(-1.0, 1.0), Error);
  EXPECT_THROW(psnr(1.0, std::nan("")), Error);
}

// ------------------------------------------------------------------ vertex RMSE

TEST(MetricsVertexRmse, KnownAnswerAndSubsets)
{
  const TriangleMesh ref = makePlaneGrid(4, 4);  // 25 vertices
  ASSERT_EQ(ref.vertices.size(), 25u);
  TriangleMesh out = ref;
  out.vertices[0] += Vector3d(1, 2, 2);     // |·| = 3
  out.vertices[5] += Vector3d(0, 0, -4);    // |·| = 4
  out.vertices[7] += Vector3d(0, -12, 5);   // |·| = 13
  EXPECT_NEAR(vertexRMSE(ref, out), std::sqrt((9.0 + 16.0 + 169.0) / 25.0), 1e-14);
  EXPECT_NEAR(vertexRMSE(ref, out, {0, 5, 7}), std::sqrt((9.0 + 16.0 + 169.0) / 3.0), 1e-14);
  EXPECT_NEAR(vertexRMSE(ref, out, {0, 1}), std::sqrt(9.0 / 2.0), 1e-14);
  EXPECT_EQ(vertexRMSE(ref, out, {1, 2, 24}), 0.0);
  EXPECT_EQ(vertexRMSE(ref, ref), 0.0);
}

TEST(MetricsVertexRmse, ThrowsOnMismatchOrBadIndex)
{
  const TriangleMesh ref = makePlaneGrid(2, 2);  // 9 vertices
  TriangleMesh shorter = ref;
  shorter.vertices.pop_back();
  EXPECT_THROW(vertexRMSE(ref, shorter), Error);
  EXPECT_THROW(vertexRMSE(ref, ref, {0, 9}), Error);
  EXPECT_THROW(vertexRMSE(ref, ref, {-1}), Error);
  EXPECT_NO_THROW(vertexRMSE(ref, ref, {8}));
}

TEST(Metrics, PointsToPointsDistanceKnownAnswers)
{
  // A grid of points and the same grid lifted by 0.25 of its spacing: every nearest neighbour is
  // the point below, at exactly 0.025.
  std::vector<Eigen::Vector3d> grid, lifted;
  for (int i = 0; i < 20; ++i)
    for (int j = 0; j < 20; ++j) {
      grid.emplace_back(0.1 * i, 0.1 * j, 0.0);
      lifted.emplace_back(0.1 * i, 0.1 * j, 0.025);
    }
  const auto d = pcl::patchdict::pointsToPointsDistance(lifted, grid);
  EXPECT_EQ(d.count, grid.size());
  EXPECT_NEAR(d.mean, 0.025, 1e-12);
  EXPECT_NEAR(d.rms, 0.025, 1e-12);
  EXPECT_NEAR(d.max, 0.025, 1e-12);
  EXPECT_EQ(pcl::patchdict::pointsToPointsDistance(grid, grid).max, 0.0);
  EXPECT_THROW(pcl::patchdict::pointsToPointsDistance(grid, {}), pcl::patchdict::Error);
  EXPECT_EQ(pcl::patchdict::pointsToPointsDistance({}, grid).count, 0u);
}
