// Tests of the field hierarchy and the extrinsic 4-RoSy orientation field (Jakob et al. 2015):
// known answers of the matching, constant fields on a plane, Poincaré–Hopf on closed surfaces.
#include <pcl_patchdict/core/error.h>
#include <pcl_patchdict/core/mesh_topology.h>
#include <pcl_patchdict/quads/orientation_field.h>
#include <pcl_patchdict_eval/shapes.h>
#include <pcl_patchdict/core/vertex_normals.h>

#include <gtest/gtest.h>
#include <omp.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <iostream>

using namespace pcl::patchdict;

namespace {

constexpr double kPi = 3.14159265358979323846;

/** Signed index sum in quarter units: +1 per face of index sum 1, −1 per face of index sum 3. */
int signedQuarterSum(const std::vector<int>& indices, int* doubles = nullptr)
{
  int sum = 0, twos = 0;
  for (const int k : indices) {
    if (k == 1)
      ++sum;
    else if (k == 3)
      --sum;
    else if (k == 2)
      ++twos;
  }
  if (doubles)
    *doubles = twos;
  return sum;
}

void expectUnitTangents(const std::vector<Eigen::Vector3d>& field, const std::vector<Eigen::Vector3d>& normals)
{
  ASSERT_EQ(field.size(), normals.size());
  for (std::size_t i = 0; i < field.size(); ++i) {
    EXPECT_NEAR(field[i].norm(), 1.0, 1e-9) << "vertex " << i;
    EXPECT_NEAR(field[i].dot(normals[i]), 0.0, 1e-9) << "vertex " << i;
  }
}

// A mesh's field hierarchy and its orientation field with the default parameters, the field
// checked to be unit tangents to the finest level's normals.
struct DefaultField {
  explicit DefaultField(const TriangleMesh& mesh)
    : hierarchy(buildFieldHierarchy(mesh)), field(computeOrientationField(hierarchy))
  {
    expectUnitTangents(field, normals());
  }
  const std::vector<Eigen::Vector3d>& normals() const { return hierarchy.levels.front().normals; }

  FieldHierarchy hierarchy;
  std::vector<Eigen::Vector3d> field;
};

}  // namespace

TEST(OrientationFieldCompat, QuarterTurnAboutSharedNormalIsPerfectMatch)
{
  const Eigen::Vector3d n(0, 0, 1);
  const Eigen::Vector3d q0 = Eigen::Vector3d(1, 2, 0).normalized();
  const Eigen::Vector3d q1 = n.cross(q0);  // q0 rotated by +90° about n
  const auto ab = compatOrientationExtrinsic4(q0, n, q1, n);
  EXPECT_NEAR(std::abs(ab.first.dot(ab.second)), 1.0, 1e-15);
  EXPECT_GT(ab.first.dot(ab.second), 0.0);  // b is sign-corrected to agree with a
  // rot^3(q1) = −n×q1 = q0.
  EXPECT_EQ(compatOrientationExtrinsicIndex4(q0, n, q1, n), 3);
  EXPECT_EQ(compatOrientationExtrinsicIndex4(q0, n, q0, n), 0);
  EXPECT_EQ(compatOrientationExtrinsicIndex4(q0, n, -q0, n), 2);
  EXPECT_EQ(compatOrientationExtrinsicIndex4(q0, n, -q1, n), 1);  // n×(−q1) = q0
}

TEST(OrientationFieldCompat, FortyFiveDegreesIsTheWorstMatch)
{
  const Eigen::Vector3d n(0, 0, 1);
  const Eigen::Vector3d q0(1, 0, 0);
  const Eigen::Vector3d q1 = Eigen::Vector3d(1, 1, 0).normalized();
  const auto ab = compatOrientationExtrinsic4(q0, n, q1, n);
  EXPECT_NEAR(ab.first.dot(ab.second), std::sqrt(0.5), 1e-15);
  // 30°: the best representative pair is (q0, q1) itself with cos 30°.
  const Eigen::Vector3d q30(std::cos(kPi / 6), std::sin(kPi / 6), 0);
  const auto ab30 = compatOrientationExtrinsic4(q0, n, q30, n);
  EXPECT_NEAR(ab30.first.dot(ab30.second), std::cos(kPi / 6), 1e-15);
  EXPECT_TRUE(ab30.first.isApprox(q0));
  // 120° = 90° + 30°: matched through n×q0 (or −q1), the match is again cos 30°.
  const Eigen::Vector3d q120(std::cos(2 * kPi / 3), std::sin(2 * kPi / 3), 0);
  const auto ab120 = compatOrientationExtrinsic4(q0, n, q120, n);
  EXPECT_NEAR(ab120.first.dot(ab120.second), std::cos(kPi / 6), 1e-15);
}

TEST(OrientationFieldHierarchy, LevelsShrinkConserveAreaAndPhasesAreIndependent)
{
  const TriangleMesh mesh = makeIcosphere(4);
  const FieldHierarchy hierarchy = buildFieldHierarchy(mesh);
  ASSERT_GE(hierarchy.numLevels(), 2u);
  EXPECT_EQ(hierarchy.levels.front().numVertices(), mesh.numVertices());
  EXPECT_TRUE(hierarchy.levels.back().numVertices() == 1 ||
              static_cast<int>(hierarchy.numLevels()) == FieldHierarchy::kMaxLevels);
  const double total_area = mesh.surfaceArea();
  for (std::size_t l = 0; l < hierarchy.numLevels(); ++l) {
    const FieldLevel& level = hierarchy.levels[l];
    const std::size_t n = level.numVertices();
    if (l > 0) {
      EXPECT_LT(n, hierarchy.levels[l - 1].numVertices()) << "level " << l;
      // Matching at most halves a level.
      EXPECT_GE(2 * n, hierarchy.levels[l - 1].numVertices()) << "level " << l;
      ASSERT_EQ(level.children.size(), n);
      const FieldLevel& finer = hierarchy.levels[l - 1];
      ASSERT_EQ(finer.parents.size(), finer.numVertices());
      for (std::size_t c = 0; c < n; ++c)
        for (const int child : level.children[c]) {
          if (child >= 0) {
            EXPECT_EQ(finer.parents[child], static_cast<int>(c));
          }
        }
    }
    double area = 0.0;
    for (const double a : level.areas)
      area += a;
    EXPECT_NEAR(area, total_area, 1e-9 * total_area) << "level " << l;
    for (const auto& normal : level.normals)
      EXPECT_NEAR(normal.norm(), 1.0, 1e-12);
    // Symmetric adjacency with positive weights; phases partition the vertices, no edge inside a phase.
    std::vector<int> phase_of(n, -1);
    for (std::size_t p = 0; p < level.phases.size(); ++p)
      for (const int v : level.phases[p]) {
        EXPECT_EQ(phase_of[v], -1);
        phase_of[v] = static_cast<int>(p);
      }
    for (std::size_t i = 0; i < n; ++i) {
      ASSERT_GE(phase_of[i], 0);
      for (int e = level.adjacency_offsets[i]; e < level.adjacency_offsets[i + 1]; ++e) {
        const int j = level.adjacency[e];
        EXPECT_NE(j, static_cast<int>(i));
        EXPECT_GT(level.adjacency_weights[e], 0.0);
        EXPECT_NE(phase_of[i], phase_of[j]) << "level " << l << " edge " << i << "-" << j;
      }
    }
  }
  // Uniform weights on level 0: every undirected mesh edge appears twice with weight 1.
  double w0 = 0.0;
  for (const double w : hierarchy.levels.front().adjacency_weights)
    w0 += w;
  EXPECT_EQ(w0, 2.0 * computeEdgeFaceAdjacency(mesh).edges.size());
  std::cout << "[ icosphere(4) hierarchy ] " << hierarchy.numLevels() << " levels, phases on level 0: "
            << hierarchy.levels.front().phases.size() << "\n";
}

TEST(OrientationFieldHierarchy, ThrowsWithoutFaces)
{
  TriangleMesh cloud;
  cloud.vertices = {Eigen::Vector3d::Zero(), Eigen::Vector3d::UnitX()};
  EXPECT_THROW(buildFieldHierarchy(cloud), Error);
  TriangleMesh bad = makePlaneGrid(2, 2);
  bad.faces[0][1] = 1000;
  EXPECT_THROW(buildFieldHierarchy(bad), Error);
}

TEST(OrientationFieldHierarchy, TwoComponentsAndAnIsolatedVertexStopWithoutCollapsing)
{
  // Two separate grids plus one vertex no face uses: coarsening ends with one vertex per
  // component (plus the isolated one) instead of looping to the depth limit.
  TriangleMesh mesh = makePlaneGrid(4, 4);
  const TriangleMesh second = makeIcosphere(1);
  const int offset = static_cast<int>(mesh.vertices.size());
  for (const auto& v : second.vertices)
    mesh.vertices.push_back(v + Eigen::Vector3d(5, 0, 0));
  for (const Face& f : second.faces)
    mesh.faces.push_back({f[0] + offset, f[1] + offset, f[2] + offset});
  mesh.vertices.push_back(Eigen::Vector3d(-3, 0, 0));
  const FieldHierarchy hierarchy = buildFieldHierarchy(mesh);
  EXPECT_EQ(hierarchy.levels.back().numVertices(), 3u);
  EXPECT_TRUE(hierarchy.levels.back().parents.empty());
  EXPECT_LT(static_cast<int>(hierarchy.numLevels()), FieldHierarchy::kMaxLevels);
  const auto field = computeOrientationField(hierarchy);
  ASSERT_EQ(field.size(), mesh.numVertices());
  const auto& normals = hierarchy.levels.front().normals;
  EXPECT_TRUE(normals.back().isZero());
  for (std::size_t i = 0; i < field.size(); ++i) {
    EXPECT_NEAR(field[i].norm(), 1.0, 1e-9);
    EXPECT_NEAR(field[i].dot(normals[i]), 0.0, 1e-9);
  }
  // The flat grid carries a constant field; the sphere component alone must account for χ = 2.
  int doubles = 0;
  EXPECT_EQ(signedQuarterSum(computeOrientationSingularityIndices(mesh, normals, field), &doubles), 8);
  EXPECT_EQ(doubles, 0);
}

TEST(OrientationField, PlaneGridFieldIsConstantUpToQuarterTurns)
{
  const TriangleMesh mesh = makePlaneGrid(30, 30);
  const DefaultField computed(mesh);
  const auto& normals = computed.normals();
  const auto& field = computed.field;
  // Angle of each tangent mod 90°, compared with vertex 0's on the circle of 4θ.
  const double reference = 4.0 * std::atan2(field[0].y(), field[0].x());
  double worst = 0.0;
  for (const auto& q : field) {
    const double d = 4.0 * std::atan2(q.y(), q.x()) - reference;
    worst = std::max(worst, std::abs(std::atan2(std::sin(d), std::cos(d))) / 4.0);
  }
  EXPECT_LT(worst, 1e-3);
  EXPECT_EQ(countOrientationSingularities(mesh, normals, field), 0);
  EXPECT_LT(orientationFieldEnergy(mesh, normals, field), 1e-9);
}

TEST(OrientationField, IcosphereSingularitiesSumToEulerCharacteristic)
{
  const TriangleMesh mesh = makeIcosphere(4);
  const FieldHierarchy hierarchy = buildFieldHierarchy(mesh);
  const auto& normals = hierarchy.levels.front().normals;
  for (const std::uint64_t seed : {0ull, 1ull, 7ull}) {
    OrientationFieldParameters parameters;
    parameters.seed = seed;
    const std::vector<Eigen::Vector3d> field = computeOrientationField(hierarchy, parameters);
    expectUnitTangents(field, normals);
    std::vector<int> singular_faces;
    const int count = countOrientationSingularities(mesh, normals, field, &singular_faces);
    const std::vector<int> indices = computeOrientationSingularityIndices(mesh, normals, field);
    int doubles = 0;
    const int quarter_sum = signedQuarterSum(indices, &doubles);
    std::cout << "[ icosphere(4) seed " << seed << " ] singularities " << count << ", signed sum "
              << quarter_sum << "/4\n";
    EXPECT_EQ(doubles, 0);
    EXPECT_EQ(quarter_sum, 8);  // Σ index = χ = 2 with index ±1/4 per singular face
    EXPECT_GE(count, 8);
    EXPECT_EQ(count % 2, 0);
    EXPECT_EQ(static_cast<int>(singular_faces.size()), count);
    // Smoothed vs random: the hierarchy removes almost all of the random energy.
    const double energy = orientationFieldEnergy(mesh, normals, field);
    const double random_energy = orientationFieldEnergy(mesh, normals, randomTangentField(normals, seed));
    EXPECT_LT(energy * 50.0, random_energy) << energy << " vs " << random_energy;
  }
}

TEST(OrientationField, TorusSingularitiesCancelAndEnergyDrops)
{
  const TriangleMesh mesh = makeTorus(60, 20);
  const DefaultField computed(mesh);
  const auto& normals = computed.normals();
  const auto& field = computed.field;
  const int count = countOrientationSingularities(mesh, normals, field);
  int doubles = 0;
  const int quarter_sum =
      signedQuarterSum(computeOrientationSingularityIndices(mesh, normals, field), &doubles);
  const double energy = orientationFieldEnergy(mesh, normals, field);
  const double random_energy = orientationFieldEnergy(mesh, normals, randomTangentField(normals, 3));
  std::cout << "[ torus(60,20) ] singularities " << count << ", signed sum " << quarter_sum
            << "/4, energy " << energy << " vs random " << random_energy << "\n";
  EXPECT_EQ(doubles, 0);
  EXPECT_EQ(quarter_sum, 0);  // χ = 0
  EXPECT_EQ(count % 2, 0);
  EXPECT_LT(energy * 10.0, random_energy);
}

TEST(OrientationField, DeterministicForSeedAndThreadCount)
{
  // Large enough (12000 vertices) that level 0's phases exceed the parallel threshold of 1024.
  const TriangleMesh mesh = makeTorus(200, 60);
  const FieldHierarchy hierarchy = buildFieldHierarchy(mesh);
  std::size_t largest_phase = 0;
  for (const auto& phase : hierarchy.levels.front().phases)
    largest_phase = std::max(largest_phase, phase.size());
  ASSERT_GT(largest_phase, 1024u);
  const FieldHierarchy again = buildFieldHierarchy(mesh);
  ASSERT_EQ(again.numLevels(), hierarchy.numLevels());
  for (std::size_t l = 0; l < hierarchy.numLevels(); ++l) {
    EXPECT_EQ(again.levels[l].adjacency, hierarchy.levels[l].adjacency);
    EXPECT_EQ(again.levels[l].phases, hierarchy.levels[l].phases);
  }
  OrientationFieldParameters parameters;
  parameters.seed = 42;
  const int saved_threads = omp_get_max_threads();
  omp_set_num_threads(1);
  const auto one = computeOrientationField(hierarchy, parameters);
  omp_set_num_threads(2);
  const auto two = computeOrientationField(hierarchy, parameters);
  omp_set_num_threads(saved_threads);
  parameters.num_threads = 2;
  const auto explicit_two = computeOrientationField(hierarchy, parameters);
  ASSERT_EQ(one.size(), two.size());
  for (std::size_t i = 0; i < one.size(); ++i) {
    ASSERT_EQ(one[i], two[i]) << "vertex " << i;  // bitwise, not approximately
    ASSERT_EQ(one[i], explicit_two[i]) << "vertex " << i;
  }
  parameters.seed = 43;
  const auto other = computeOrientationField(hierarchy, parameters);
  bool differs = false;
  for (std::size_t i = 0; i < one.size() && !differs; ++i)
    differs = !(one[i] == other[i]);
  EXPECT_TRUE(differs);
}

TEST(OrientationField, SmoothingLowersEnergyOnRelief)
{
  const TriangleMesh mesh = makeSinusoidalRelief(40, 40, 0.05, 0.5);
  const FieldHierarchy hierarchy = buildFieldHierarchy(mesh);
  const auto& normals = hierarchy.levels.front().normals;
  OrientationFieldParameters parameters;
  parameters.iterations_per_level = 0;  // random coarse field, prolonged only
  const double e0 = orientationFieldEnergy(mesh, normals, computeOrientationField(hierarchy, parameters));
  parameters.iterations_per_level = 6;
  const auto field = computeOrientationField(hierarchy, parameters);
  const double e6 = orientationFieldEnergy(mesh, normals, field);
  const double random_energy = orientationFieldEnergy(mesh, normals, randomTangentField(normals, 0));
  EXPECT_LT(e6, e0);
  EXPECT_LT(e6 * 10.0, random_energy);
  // An open disc-like patch (χ = 1): Poincaré–Hopf does not constrain interior singularities to
  // sum to χ because the boundary is free, but a smooth field on a gentle relief needs none.
  EXPECT_EQ(countOrientationSingularities(mesh, normals, field), 0);
}

TEST(OrientationField, HundredThousandFaceTorusTiming)
{
  const TriangleMesh mesh = makeTorus(224, 224);
  ASSERT_EQ(mesh.numFaces(), 100352u);
  const auto t0 = std::chrono::steady_clock::now();
  const FieldHierarchy hierarchy = buildFieldHierarchy(mesh);
  const auto t1 = std::chrono::steady_clock::now();
  const std::vector<Eigen::Vector3d> field = computeOrientationField(hierarchy);
  const auto t2 = std::chrono::steady_clock::now();
  const auto& normals = hierarchy.levels.front().normals;
  expectUnitTangents(field, normals);
  int doubles = 0;
  const int count = countOrientationSingularities(mesh, normals, field);
  const int quarter_sum = signedQuarterSum(computeOrientationSingularityIndices(mesh, normals, field), &doubles);
  const double ms_hierarchy = std::chrono::duration<double, std::milli>(t1 - t0).count();
  const double ms_field = std::chrono::duration<double, std::milli>(t2 - t1).count();
  std::cout << "[ torus(224,224), " << mesh.numFaces() << " faces ] hierarchy " << ms_hierarchy << " ms ("
            << hierarchy.numLevels() << " levels), orientation field " << ms_field << " ms, singularities "
            << count << ", signed sum " << quarter_sum << "/4\n";
  EXPECT_EQ(doubles, 0);
  EXPECT_EQ(quarter_sum, 0);
}
