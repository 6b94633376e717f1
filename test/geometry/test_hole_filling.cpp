// HoleFilling (Liepa 2003) and its pieces: the triangulation DP against brute force, refinement
// density, fairing on closed-form surfaces, which loops are holes, and the fill-holes command.
#include <pcl_patchdict/core/error.h>
#include <pcl_patchdict/geometry/hole_filling.h>
#include <pcl_patchdict/geometry/hole_triangulation.h>
#include <pcl_patchdict/geometry/mesh_fairing.h>
#include <pcl_patchdict/geometry/mesh_hygiene.h>
#include <pcl_patchdict/io/mesh_io.h>
#include <pcl_patchdict/core/mesh_topology.h>
#include <pcl_patchdict_eval/shapes.h>

#include "test_support.h"

#include "hole_test_shapes.h"

#include <gtest/gtest.h>

#include <filesystem>

#include <chrono>
#include <cstdio>

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <map>
#include <random>

using namespace pcl::patchdict;
using namespace hole_test;
using test_support::runTool;

namespace {

// ---------------------------------------------------------------- brute force for the DP
using Triangulation = std::vector<Face>;

// Every triangulation of the polygon i..k (faces (i, m, k) with i < m < k, as the DP builds them).
std::vector<Triangulation> allTriangulations(int i, int k)
{
  if (k - i < 2)
    return {Triangulation{}};
  std::vector<Triangulation> all;
  for (int m = i + 1; m < k; ++m)
    for (const auto& left : allTriangulations(i, m))
      for (const auto& right : allTriangulations(m, k)) {
        Triangulation t = left;
        t.insert(t.end(), right.begin(), right.end());
        t.push_back({i, m, k});
        all.push_back(t);
      }
  return all;
}

Eigen::Vector3d normalOf(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& c)
{
  return (b - a).cross(c - a).normalized();
}

double angleBetween(const Eigen::Vector3d& a, const Eigen::Vector3d& b)
{
  return std::atan2(a.cross(b).norm(), a.dot(b));
}

// Liepa's weight of a whole triangulation, computed directly: the largest dihedral angle over its
// interior edges and over the loop edges (against the outside apex), and the total area.
std::pair<double, double> liepaWeight(const Triangulation& t, const std::vector<Eigen::Vector3d>& loop,
                                      const std::vector<Eigen::Vector3d>& apex)
{
  const int n = static_cast<int>(loop.size());
  double worst = 0.0, area = 0.0;
  for (std::size_t f = 0; f < t.size(); ++f) {
    const Face& a = t[f];
    const Eigen::Vector3d na = normalOf(loop[a[0]], loop[a[1]], loop[a[2]]);
    area += 0.5 * (loop[a[1]] - loop[a[0]]).cross(loop[a[2]] - loop[a[0]]).norm();
    for (int c = 0; c < 3; ++c) {
      const int u = a[c], v = a[(c + 1) % 3];
      if ((u + 1) % n == v) {
        worst = std::max(worst, angleBetween(na, normalOf(loop[v], loop[u], apex[u])));
        continue;
      }
      for (std::size_t g = 0; g < t.size(); ++g) {
        if (g == f)
          continue;
        const Face& b = t[g];
        if (std::count(b.begin(), b.end(), u) && std::count(b.begin(), b.end(), v))
          worst = std::max(worst, angleBetween(na, normalOf(loop[b[0]], loop[b[1]], loop[b[2]])));
      }
    }
  }
  return {worst, area};
}

// A wobbly closed polygon in 3D (radius ~1, heights ±0.4) and an outside apex per edge.
void randomLoop(std::mt19937& rng, int n, std::vector<Eigen::Vector3d>& loop, std::vector<Eigen::Vector3d>& apex)
{
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  loop.clear();
  apex.clear();
  for (int i = 0; i < n; ++i) {
    const double phi = 2.0 * M_PI * (i + 0.3 * unit(rng)) / n;
    const double r = 1.0 + 0.3 * unit(rng);
    loop.emplace_back(r * std::cos(phi), r * std::sin(phi), 0.4 * unit(rng));
  }
  for (int i = 0; i < n; ++i) {
    const Eigen::Vector3d mid = 0.5 * (loop[i] + loop[(i + 1) % n]);
    apex.push_back(mid * 1.5 + Eigen::Vector3d(0.0, 0.0, 0.3 * unit(rng)));
  }
}

// A tilted square grid (side 1, n × n quads) with a round hole of the given radius at its centre.
TriangleMesh tiltedPlaneWithHole(int n, double radius, Eigen::Matrix3d& rotation)
{
  TriangleMesh plane = makePlaneGrid(n, n);
  TriangleMesh holed = cutFaces(plane, [&](const Face& f) {
    for (const std::int32_t v : f)
      if ((plane.vertices[v] - Eigen::Vector3d(0.5, 0.5, 0.0)).norm() < radius)
        return false;
    return true;
  });
  rotation = (Eigen::AngleAxisd(0.7, Eigen::Vector3d(1.0, 2.0, 0.5).normalized())).toRotationMatrix();
  for (auto& p : holed.vertices)
    p = rotation * p + Eigen::Vector3d(0.1, -0.2, 0.3);
  return holed;
}

double meanEdgeOfFaces(const TriangleMesh& mesh, const std::vector<std::int32_t>& faces)
{
  double sum = 0.0;
  for (const std::int32_t f : faces)
    for (int c = 0; c < 3; ++c)
      sum += (mesh.vertices[mesh.faces[f][c]] - mesh.vertices[mesh.faces[f][(c + 1) % 3]]).norm();
  return sum / (3.0 * static_cast<double>(faces.size()));
}

// Runs `filler` on a copy of `mesh` into `out`; the report of the run.
HoleFilling::Report fillHoles(HoleFilling& filler, const TriangleMesh& mesh, TriangleMesh& out)
{
  filler.setInputMesh(std::make_shared<const TriangleMesh>(mesh));
  HoleFilling::Report report;
  filler.process(out, &report);
  return report;
}

// Checks a filled mesh: `rims` boundary loops left open, manifold, consistently oriented.
void expectClosedButForRims(const TriangleMesh& mesh, std::size_t rims)
{
  const MeshHygieneReport hygiene = inspectMesh(mesh);
  EXPECT_EQ(hygiene.boundary_loops, rims);
  EXPECT_EQ(hygiene.nonmanifold_edges, 0u);
  EXPECT_EQ(hygiene.nonmanifold_vertices, 0u);
  TriangleMesh copy = mesh;
  EXPECT_EQ(orientFacesConsistently(copy), 0u);
}

}  // namespace

using test_support::endsWithOneErrorLine;
using test_support::isOneLine;
using test_support::q;

// ---------------------------------------------------------------- triangulation
TEST(HoleFillingTriangulation, MinimumAreaEqualsBruteForce)
{
  std::mt19937 rng(7);
  HoleTriangulationOptions options;
  options.weight = HoleTriangulationWeight::Area;
  for (int trial = 0; trial < 60; ++trial) {
    const int n = 4 + trial % 6;  // 4..9 vertices: up to 429 triangulations
    std::vector<Eigen::Vector3d> loop, apex;
    randomLoop(rng, n, loop, apex);
    const HoleTriangulation dp = triangulateHoleLoop(loop, apex, {}, options);
    ASSERT_TRUE(dp.valid);
    ASSERT_EQ(dp.faces.size(), static_cast<std::size_t>(n - 2));
    double best = 1e300;
    for (const auto& t : allTriangulations(0, n - 1))
      best = std::min(best, liepaWeight(t, loop, apex).second);
    EXPECT_NEAR(dp.area, best, 1e-12 * best) << "n = " << n;
  }
}

TEST(HoleFillingTriangulation, LiepaWeightIsNearTheBruteForceOptimum)
{
  // Liepa's recursion measures the angle across a sub-polygon's closing edge against the triangle
  // the sub-problem chose, and a lexicographic (max, sum) weight does not decompose either, so the
  // DP is not guaranteed optimal for this weight (it is for area alone, test above). Measured here
  // against all triangulations (angles measured directly): optimal on 44 of these 60 polygons,
  // on average 1.9 % of the triangulations are better (at worst 1 of 5).
  std::mt19937 rng(11);
  int exact = 0, trials = 0;
  double worst_better_fraction = 0.0, sum_better_fraction = 0.0;
  for (int trial = 0; trial < 60; ++trial) {
    const int n = 4 + trial % 5;  // 4..8
    std::vector<Eigen::Vector3d> loop, apex;
    randomLoop(rng, n, loop, apex);
    const HoleTriangulation dp = triangulateHoleLoop(loop, apex, {});
    ASSERT_TRUE(dp.valid);
    const auto dp_weight = liepaWeight(dp.faces, loop, apex);
    // The reported weight is the weight of what was built.
    EXPECT_NEAR(dp.max_dihedral_angle, dp_weight.first, 1e-9);
    EXPECT_NEAR(dp.area, dp_weight.second, 1e-9);
    const auto all = allTriangulations(0, n - 1);
    std::pair<double, double> best{1e300, 1e300};
    std::size_t better = 0;
    for (const auto& t : all) {
      const auto w = liepaWeight(t, loop, apex);
      if (w.first < best.first - 1e-9 || (std::abs(w.first - best.first) <= 1e-9 && w.second < best.second))
        best = w;
      if (w.first < dp_weight.first - 1e-9 || (std::abs(w.first - dp_weight.first) <= 1e-9 && w.second < dp_weight.second - 1e-9))
        ++better;
    }
    ++trials;
    exact += better == 0;
    const double fraction = static_cast<double>(better) / static_cast<double>(all.size());
    worst_better_fraction = std::max(worst_better_fraction, fraction);
    sum_better_fraction += fraction;
    EXPECT_LE(dp_weight.first, best.first + 0.35) << "n = " << n;
  }
  EXPECT_GE(exact, 40);
  EXPECT_LT(sum_better_fraction / trials, 0.03);
  EXPECT_LT(worst_better_fraction, 0.25);
}

TEST(HoleFillingTriangulation, ForbiddenChordsAreAvoidedAndLongLoopsAreSplit)
{
  std::vector<Eigen::Vector3d> loop, apex;
  std::mt19937 rng(3);
  randomLoop(rng, 8, loop, apex);
  // Forbid every chord from vertex 0: the fill must not use any of them.
  std::vector<std::pair<int, int>> forbidden;
  for (int k = 2; k <= 6; ++k)
    forbidden.emplace_back(0, k);
  const HoleTriangulation t = triangulateHoleLoop(loop, apex, forbidden);
  ASSERT_TRUE(t.valid);
  for (const Face& f : t.faces)
    for (int c = 0; c < 3; ++c) {
      const int a = std::min(f[c], f[(c + 1) % 3]), b = std::max(f[c], f[(c + 1) % 3]);
      EXPECT_FALSE(a == 0 && b >= 2 && b <= 6) << a << "-" << b;
    }
  // A triangle's three vertices with all chords... a square whose both diagonals are forbidden.
  const std::vector<Eigen::Vector3d> square{{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};
  EXPECT_FALSE(triangulateHoleLoop(square, {}, {{0, 2}, {1, 3}}).valid);

  // 600 vertices with pieces of at most 200: split, still a triangulation of the whole loop.
  std::vector<Eigen::Vector3d> circle;
  for (int i = 0; i < 600; ++i)
    circle.emplace_back(std::cos(2 * M_PI * i / 600), std::sin(2 * M_PI * i / 600), 0.1 * std::sin(6 * M_PI * i / 600));
  const HoleTriangulation big = triangulateHoleLoop(circle, {}, {});
  ASSERT_TRUE(big.valid);
  EXPECT_GE(big.pieces, 3u);
  EXPECT_EQ(big.faces.size(), 598u);
  std::map<std::pair<int, int>, int> uses;
  for (const Face& f : big.faces)
    for (int c = 0; c < 3; ++c)
      ++uses[{std::min(f[c], f[(c + 1) % 3]), std::max(f[c], f[(c + 1) % 3])}];
  for (const auto& [edge, count] : uses) {
    const bool loop_edge = edge.second - edge.first == 1 || (edge.first == 0 && edge.second == 599);
    EXPECT_EQ(count, loop_edge ? 1 : 2) << edge.first << "-" << edge.second;
  }
}

// ---------------------------------------------------------------- fairing
TEST(HoleFillingFairing, BiLaplacianRestoresAPlaneExactly)
{
  TriangleMesh grid = makePlaneGrid(20, 20);
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> bump(-0.05, 0.05);
  std::vector<std::int32_t> free;
  for (std::size_t v = 0; v < grid.vertices.size(); ++v) {
    const auto& p = grid.vertices[v];
    if (p.x() > 0.2 && p.x() < 0.8 && p.y() > 0.2 && p.y() < 0.8) {
      free.push_back(static_cast<std::int32_t>(v));
      grid.vertices[v].z() += bump(rng);
    }
  }
  for (const auto weights : {FairingWeights::Cotangent, FairingWeights::Uniform})
    for (int continuity = 0; continuity <= 2; ++continuity) {
      TriangleMesh mesh = grid;
      FairingReport report;
      ASSERT_TRUE(fairVertices(mesh, free, {continuity, weights}, &report));
      EXPECT_EQ(report.free_vertices, free.size());
      double worst = 0.0;
      for (const std::int32_t v : free)
        worst = std::max(worst, std::abs(mesh.vertices[v].z()));
      EXPECT_LT(worst, 1e-12) << "continuity " << continuity;
    }
  TriangleMesh mesh = grid;
  EXPECT_THROW(fairVertices(mesh, {static_cast<std::int32_t>(grid.vertices.size())}), Error);
  EXPECT_THROW(fairVertices(mesh, free, {3, FairingWeights::Cotangent}), Error);
}

// ---------------------------------------------------------------- HoleFilling
TEST(HoleFilling, PlanarHoleIsFilledFlatAtTheMeshDensity)
{
  Eigen::Matrix3d rotation;
  const int n = 40;
  const TriangleMesh holed = tiltedPlaneWithHole(n, 0.2, rotation);
  const Eigen::Vector3d normal = rotation * Eigen::Vector3d::UnitZ();
  const double offset = normal.dot(holed.vertices.front());
  HoleFilling filler;
  TriangleMesh out;
  HoleFilling::Report report = fillHoles(filler, holed, out);
  ASSERT_EQ(report.holes_found, 2u);
  EXPECT_EQ(report.holes_filled, 1u);
  EXPECT_EQ(report.holes_skipped, 1u);
  EXPECT_EQ(report.holes[0].skipped, HoleFilling::SkipReason::OuterBoundary);  // the rim, longest
  const HoleFilling::Hole& hole = report.holes[1];
  ASSERT_TRUE(hole.filled());
  EXPECT_TRUE(report.fairing_solved);
  double worst = 0.0;
  for (const std::int32_t v : hole.new_vertices)
    worst = std::max(worst, std::abs(normal.dot(out.vertices[v]) - offset));
  EXPECT_LT(worst, 1e-12);
  // Density: the hole's area holds about as many vertices as the same area of the grid (a grid
  // vertex per (1/n)² of area), and the fill's edges are as long as the grid's.
  const double fill_area = [&] {
    double a = 0.0;
    for (const std::int32_t f : hole.new_faces)
      a += out.faceArea(static_cast<std::size_t>(f));
    return a;
  }();
  const double grid_vertices_in_fill = fill_area * n * n;
  const double interior_new = static_cast<double>(hole.new_vertices.size());
  EXPECT_GT(interior_new, 0.6 * grid_vertices_in_fill);
  EXPECT_LT(interior_new, 1.5 * grid_vertices_in_fill);
  const double grid_edge = holed.meanEdgeLength();
  EXPECT_NEAR(meanEdgeOfFaces(out, hole.new_faces) / grid_edge, 1.0, 0.25);
  // Closed but for the rim, manifold, consistently oriented.
  expectClosedButForRims(out, 1);
}

TEST(HoleFilling, FairedFillFollowsTheSphereMuchBetterThanAFlatFill)
{
  const std::vector<Eigen::Vector3d> centres{Eigen::Vector3d(0, 0, 1),
                                             Eigen::Vector3d(1, 0, 0), Eigen::Vector3d(0, -1, 0)};
  const TriangleMesh holed = sphereWithHoles(4, 0.45, centres);
  HoleFilling filler;
  TriangleMesh faired, flat;
  const HoleFilling::Report faired_report = fillHoles(filler, holed, faired);
  HoleFilling::Report flat_report;
  filler.setFair(false);
  filler.process(flat, &flat_report);
  ASSERT_EQ(faired_report.holes_found, 3u);
  ASSERT_EQ(faired_report.holes_filled, 3u);
  ASSERT_EQ(faired.vertices.size(), flat.vertices.size());
  double faired_error = 0.0, flat_error = 0.0, flat_max = 0.0;
  std::size_t count = 0;
  for (const auto& hole : faired_report.holes)
    for (const std::int32_t v : hole.new_vertices) {
      faired_error += std::abs(faired.vertices[v].norm() - 1.0);
      flat_error += std::abs(flat.vertices[v].norm() - 1.0);
      flat_max = std::max(flat_max, std::abs(flat.vertices[v].norm() - 1.0));
      ++count;
    }
  ASSERT_GT(count, 30u);
  faired_error /= static_cast<double>(count);
  flat_error /= static_cast<double>(count);
  // The flat fill of a cap of chord radius ≤ 0.45 sags by at most 1 − √(1 − 0.45²) ≈ 0.107.
  EXPECT_LT(flat_max, 0.11);
  EXPECT_GT(flat_error, 0.02);
  EXPECT_LT(faired_error, 0.1 * flat_error) << "faired " << faired_error << " flat " << flat_error;
  expectClosedButForRims(faired, 0);
}

TEST(HoleFilling, InputVerticesAndFacesStayBitIdenticalAndFirst)
{
  const TriangleMesh holed = sphereWithHoles(3, 0.5, {Eigen::Vector3d(0.6, 0.0, 0.8)});
  HoleFilling filler;
  TriangleMesh out, again;
  const HoleFilling::Report report = fillHoles(filler, holed, out);
  filler.process(again);
  ASSERT_GT(out.vertices.size(), holed.vertices.size());
  ASSERT_EQ(report.new_vertices, out.vertices.size() - holed.vertices.size());
  EXPECT_EQ(std::memcmp(out.vertices.data(), holed.vertices.data(), holed.vertices.size() * sizeof(Eigen::Vector3d)), 0);
  ASSERT_GE(out.faces.size(), holed.faces.size());
  EXPECT_TRUE(std::equal(holed.faces.begin(), holed.faces.end(), out.faces.begin()));
  // The report's indices: the loop is the input's boundary, new vertices and faces are appended.
  const auto& hole = report.holes.at(0);
  const auto loops = computeBoundaryLoops(holed);
  ASSERT_EQ(loops.size(), 1u);
  std::vector<std::int32_t> a = hole.boundary, b = loops[0].vertices;
  std::sort(a.begin(), a.end());
  std::sort(b.begin(), b.end());
  EXPECT_EQ(a, b);
  for (std::size_t i = 0; i < hole.new_vertices.size(); ++i)
    EXPECT_EQ(hole.new_vertices[i], static_cast<std::int32_t>(holed.vertices.size() + i));
  EXPECT_EQ(hole.new_faces.size(), out.faces.size() - holed.faces.size());
  // Deterministic.
  EXPECT_EQ(std::memcmp(out.vertices.data(), again.vertices.data(), out.vertices.size() * sizeof(Eigen::Vector3d)), 0);
  EXPECT_TRUE(out.faces == again.faces);
}

TEST(HoleFilling, TheRimOfAnOpenDiscIsNotAHole)
{
  const TriangleMesh disc = makePlaneGrid(10, 10);
  HoleFilling filler;
  TriangleMesh out;
  HoleFilling::Report report = fillHoles(filler, disc, out);
  ASSERT_EQ(report.holes_found, 1u);
  EXPECT_EQ(report.holes_filled, 0u);
  EXPECT_EQ(report.holes[0].skipped, HoleFilling::SkipReason::OuterBoundary);
  EXPECT_EQ(out.vertices, disc.vertices);
  EXPECT_TRUE(out.faces == disc.faces);
  // Asked to, it fills the rim too (a fraction no loop reaches).
  filler.setOuterBoundaryFraction(std::numeric_limits<double>::infinity());
  filler.process(out, &report);
  EXPECT_EQ(report.holes_filled, 1u);
  EXPECT_EQ(inspectMesh(out).boundary_loops, 0u);
}

TEST(HoleFilling, LoopThroughANonManifoldVertexIsSkippedAndReported)
{
  // Two grid squares removed that touch at one corner: their boundary passes that vertex twice.
  const TriangleMesh grid = makePlaneGrid(8, 8);
  const auto inSquare = [&](const Face& f, double x0, double y0) {
    Eigen::Vector3d c = (grid.vertices[f[0]] + grid.vertices[f[1]] + grid.vertices[f[2]]) / 3.0;
    return c.x() > x0 && c.x() < x0 + 0.125 && c.y() > y0 && c.y() < y0 + 0.125;
  };
  TriangleMesh holed = cutFaces(grid, [&](const Face& f) {
    return !inSquare(f, 0.25, 0.25) && !inSquare(f, 0.375, 0.375) && !inSquare(f, 0.625, 0.625);
  });
  HoleFilling filler;
  TriangleMesh out;
  HoleFilling::Report report;
  ASSERT_NO_THROW(report = fillHoles(filler, holed, out));
  std::size_t nonmanifold = 0, filled = 0;
  for (const auto& hole : report.holes) {
    nonmanifold += hole.skipped == HoleFilling::SkipReason::NonManifoldVertex;
    filled += hole.filled();
  }
  EXPECT_GE(nonmanifold, 1u);
  EXPECT_EQ(filled, 1u);  // the separate square at (0.625, 0.625)
  EXPECT_EQ(inspectMesh(out).nonmanifold_edges, 0u);
  EXPECT_EQ(toString(HoleFilling::SkipReason::NonManifoldVertex), "non-manifold vertex on loop");
}

TEST(HoleFilling, LimitsOnEdgesAndDiameterAreRespected)
{
  // Two holes on a sphere: a small one and a large one.
  const TriangleMesh holed = [] {
    const TriangleMesh sphere = makeIcosphere(4, 1.0);
    const Eigen::Vector3d small_centre(0, 0, 1), large_centre(0, 0, -1);
    return cutFaces(sphere, [&](const Face& f) {
      for (const std::int32_t v : f)
        if ((sphere.vertices[v] - small_centre).norm() < 0.2 || (sphere.vertices[v] - large_centre).norm() < 0.6)
          return false;
      return true;
    });
  }();
  HoleFilling filler;
  TriangleMesh out;
  HoleFilling::Report report = fillHoles(filler, holed, out);
  ASSERT_EQ(report.holes_found, 2u);
  ASSERT_EQ(report.holes_filled, 2u);
  const HoleFilling::Hole large = report.holes[0], small = report.holes[1];  // longest first
  ASSERT_GT(large.boundary.size(), small.boundary.size());

  filler.setMaxHoleEdges(small.boundary.size());
  filler.process(out, &report);
  EXPECT_TRUE(report.holes[1].filled());
  EXPECT_EQ(report.holes[0].skipped, HoleFilling::SkipReason::TooManyEdges);
  EXPECT_EQ(inspectMesh(out).boundary_loops, 1u);

  filler.setMaxHoleEdges(0);
  filler.setMaxHoleDiameter(0.5 * (small.diameter + large.diameter));
  filler.process(out, &report);
  EXPECT_TRUE(report.holes[1].filled());
  EXPECT_EQ(report.holes[0].skipped, HoleFilling::SkipReason::TooLarge);
  EXPECT_EQ(report.holes_skipped, 1u);

  filler.setMaxHoleDiameter(0.0);
  EXPECT_THROW(filler.process(out), Error);
  const TriangleMesh cloud = [] { TriangleMesh m; m.vertices.emplace_back(0, 0, 0); return m; }();
  filler.setInputMesh(std::make_shared<const TriangleMesh>(cloud));
  filler.setMaxHoleDiameter(1.0);
  EXPECT_THROW(filler.process(out), Error);
}

TEST(HoleFilling, FiveHundredEdgeHoleIsClosed)
{
  // A wavy annulus from radius 1 to 3, rings spaced like its edges (r_k = (1 + 2π/500)^k): the
  // inner loop is a 500-edge hole, the outer rim spans the component and stays open.
  TriangleMesh annulus;
  const int segments = 500;
  const double step = 1.0 + 2 * M_PI / segments;
  const int rings = static_cast<int>(std::log(3.0) / std::log(step)) + 1;
  for (int ring = 0; ring < rings; ++ring)
    for (int i = 0; i < segments; ++i) {
      const double phi = 2 * M_PI * (i + 0.5 * ring) / segments, r = std::pow(step, ring);
      annulus.vertices.emplace_back(r * std::cos(phi), r * std::sin(phi), 0.05 * std::sin(3 * phi) * r);
    }
  for (int ring = 0; ring + 1 < rings; ++ring)
    for (int i = 0; i < segments; ++i) {
      const int a = ring * segments + i, b = ring * segments + (i + 1) % segments;
      annulus.faces.push_back({a, b, a + segments});
      annulus.faces.push_back({b, b + segments, a + segments});
    }
  ASSERT_EQ(inspectMesh(annulus).nonmanifold_edges, 0u);
  HoleFilling filler;
  filler.setInputMesh(std::make_shared<const TriangleMesh>(annulus));
  TriangleMesh out;
  HoleFilling::Report report;
  const auto start = std::chrono::steady_clock::now();
  filler.process(out, &report);
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  // Timing is printed, not asserted (speed goals are measured, not tested): README "Measured".
  std::printf("500-edge hole: %zu new vertices in %.3f s (triangulation %.3f s, refinement %.3f s, fairing %.3f s)\n",
              report.new_vertices, seconds, report.seconds_triangulation, report.seconds_refinement,
              report.seconds_fairing);
  ASSERT_EQ(report.holes_found, 2u);
  EXPECT_EQ(report.holes[0].skipped, HoleFilling::SkipReason::OuterBoundary);
  ASSERT_TRUE(report.holes[1].filled());
  EXPECT_EQ(report.holes[1].boundary.size(), 500u);
  EXPECT_TRUE(report.fairing_solved);
  // Liepa's density: about one new vertex per (√3/2)σ² of the disc of radius 1, σ ≈ 2π/500.
  const double expected = M_PI / (std::sqrt(3.0) / 2.0 * std::pow(2 * M_PI / segments, 2));
  EXPECT_GT(static_cast<double>(report.new_vertices), 0.6 * expected);
  EXPECT_LT(static_cast<double>(report.new_vertices), 1.5 * expected);
  expectClosedButForRims(out, 1);
}

// ---------------------------------------------------------------- command line