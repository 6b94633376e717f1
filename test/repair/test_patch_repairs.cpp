// The three repair entry points (patch_repairs.h): their defaults, their results at one and two
// threads, and the ownership rule — a class that keeps an input shares it, so an input passed as a
// temporary cannot dangle.
#include <pcl_patchdict/core/error.h>
#include <pcl_patchdict_eval/shapes.h>
#include <pcl_patchdict/geometry/coarse_mesh_estimation.h>
#include <pcl_patchdict/geometry/hole_filling.h>
#include <pcl_patchdict/patches/patch_mesh_reconstruction.h>
#include <pcl_patchdict/quads/quad_remesher.h>
#include <pcl_patchdict/repair/patch_correction.h>
#include <pcl_patchdict/repair/patch_repairs.h>

#include <gtest/gtest.h>

#include <memory>
#include <random>
#include <type_traits>
#include <utility>

using namespace pcl::patchdict;

namespace {

// ---- the ownership rule, at compile time: no setter takes a plain reference it could keep.
template <class C, class T, class = void>
struct SetInputMeshTakes : std::false_type {};
template <class C, class T>
struct SetInputMeshTakes<C, T, std::void_t<decltype(std::declval<C&>().setInputMesh(std::declval<T>()))>>
    : std::true_type {};

template <class C>
constexpr bool sharesItsInputMesh()
{
  return !SetInputMeshTakes<C, TriangleMesh>::value && !SetInputMeshTakes<C, const TriangleMesh&>::value &&
         SetInputMeshTakes<C, std::shared_ptr<const TriangleMesh>>::value &&
         SetInputMeshTakes<C, std::shared_ptr<TriangleMesh>>::value;
}

static_assert(sharesItsInputMesh<HoleFilling>(), "HoleFilling must share its input");
static_assert(sharesItsInputMesh<QuadRemesher>(), "QuadRemesher must share its input");
static_assert(sharesItsInputMesh<CoarseMeshEstimation>(), "CoarseMeshEstimation must share its input");
static_assert(!std::is_invocable_v<decltype(&PatchCorrection::setEstimate), PatchCorrection&, TriangleMesh>,
              "PatchCorrection must share its estimate");
static_assert(!std::is_invocable_v<decltype(&PatchMeshReconstruction::setTargetMesh), PatchMeshReconstruction&,
                                   TriangleMesh>,
              "PatchMeshReconstruction must share its target");

/** An icosphere with the faces around one pole removed. */
TriangleMesh holedSphere()
{
  TriangleMesh mesh = makeIcosphere(3);
  std::vector<Face> kept;
  for (const Face& f : mesh.faces)
    if ((mesh.vertices[f[0]] + mesh.vertices[f[1]] + mesh.vertices[f[2]]).z() / 3.0 < 0.85)
      kept.push_back(f);
  mesh.faces = kept;
  return mesh;
}

TriangleMesh noisySphere(double sigma, std::uint64_t seed)
{
  TriangleMesh mesh = makeIcosphere(3);
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> noise(0.0, sigma);
  for (auto& v : mesh.vertices)
    v += noise(rng) * v.normalized();
  return mesh;
}

void expectSameMesh(const TriangleMesh& a, const TriangleMesh& b)
{
  ASSERT_EQ(a.numVertices(), b.numVertices());
  ASSERT_EQ(a.numFaces(), b.numFaces());
  for (std::size_t v = 0; v < a.numVertices(); ++v)
    ASSERT_EQ(a.vertices[v], b.vertices[v]) << "vertex " << v;  // bit for bit
  for (std::size_t f = 0; f < a.numFaces(); ++f)
    ASSERT_EQ(a.faces[f], b.faces[f]);
}

}  // namespace

TEST(PatchRepairs, TemporaryInputsAreKeptAliveNotDangling)
{
  // The old API kept `&mesh`: a temporary passed to setInputMesh dangled by the next statement.
  // Now the class shares the mesh: the temporary's owner is the class.
  HoleFilling from_temporary;
  from_temporary.setInputMesh(std::make_shared<const TriangleMesh>(holedSphere()));
  TriangleMesh a;
  HoleFilling::Report report_a;
  from_temporary.process(a, &report_a);

  auto named = std::make_shared<TriangleMesh>(holedSphere());
  HoleFilling from_named;
  from_named.setInputMesh(named);
  named.reset();  // the caller lets go of its handle: the filling still holds the mesh
  TriangleMesh b;
  from_named.process(b);
  EXPECT_EQ(report_a.holes_filled, 1u);
  expectSameMesh(a, b);

  QuadRemesher remesher;
  remesher.setInputMesh(std::make_shared<const TriangleMesh>(makeIcosphere(3)));
  remesher.setQuadLength(0.3);
  QuadMesh quads;
  remesher.process(quads);
  EXPECT_GT(quads.faces.size(), 6u);

  HoleRepairOptions liepa_only;  // the repair's base is the same filling
  liepa_only.decision.mode = PatchDecision::Never;
  TriangleMesh c;
  fillHolesWithPatches(holedSphere(), c, liepa_only);
  expectSameMesh(a, c);
}

TEST(PatchRepairs, EachRepairsOptionsStartAtItsOwnDefaults)
{
  const MissingVerticesOptions missing;
  const HoleRepairOptions holes;
  const DenoiseOptions denoise;
  const PatchCorrectionParameters shared;
  EXPECT_EQ(missing.constraint_weight, 0.03);
  EXPECT_EQ(missing.fit_scale, shared.fit_scale);
  EXPECT_EQ(holes.constraint_weight, 0.1);
  EXPECT_EQ(holes.fit_scale, 0.02);
  EXPECT_EQ(denoise.quad_length_factor, 6.0);
  EXPECT_EQ(denoise.sparsity, 20);
  EXPECT_EQ(holes.quad_length_factor, shared.quad_length_factor);
  EXPECT_EQ(denoise.fit_scale, shared.fit_scale);
}

TEST(PatchRepairs, EachRepairGivesTheSameMeshAtOneAndTwoThreads)
{
  TriangleMesh one, two;
  const TriangleMesh truth = makeIcosphere(3);
  std::vector<int> missing;
  for (int v = 0; v < static_cast<int>(truth.numVertices()); v += 7)
    missing.push_back(v);
  MissingVerticesOptions missing_options;
  MissingVerticesReport missing_report;
  missing_options.num_threads = 1;
  fillMissingVertices(truth, missing, one, missing_options, &missing_report);
  EXPECT_TRUE(missing_report.used_patches);
  missing_options.num_threads = 2;
  fillMissingVertices(truth, missing, two, missing_options);
  expectSameMesh(one, two);

  const TriangleMesh holed = holedSphere();
  HoleRepairOptions hole_options;
  HoleRepairReport hole_report;
  hole_options.num_threads = 1;
  fillHolesWithPatches(holed, one, hole_options, &hole_report);
  EXPECT_TRUE(hole_report.used_patches);
  EXPECT_EQ(hole_report.holes.holes_filled, 1u);
  hole_options.num_threads = 2;
  fillHolesWithPatches(holed, two, hole_options);
  expectSameMesh(one, two);

  const TriangleMesh noisy = noisySphere(0.01, 3);
  DenoiseOptions denoise_options;
  DenoiseReport denoise_report;
  denoise_options.num_threads = 1;
  denoiseWithPatches(noisy, one, denoise_options, &denoise_report);
  EXPECT_TRUE(denoise_report.noise_estimated);
  EXPECT_GT(denoise_report.base_iterations, 0);
  denoise_options.num_threads = 2;
  denoiseWithPatches(noisy, two, denoise_options);
  expectSameMesh(one, two);
}

TEST(PatchRepairs, EachRepairChecksItsOwnOptions)
{
  const TriangleMesh mesh = makeIcosphere(2);
  TriangleMesh out;
  MissingVerticesOptions missing;
  missing.constraint_weight = -1.0;
  EXPECT_THROW(fillMissingVertices(mesh, {0}, out, missing), Error);
  EXPECT_THROW(fillMissingVertices(mesh, {}, out), Error);
  HoleRepairOptions holes;
  holes.decision.probe_factors.clear();
  EXPECT_THROW(fillHolesWithPatches(mesh, out, holes), Error);
  DenoiseOptions denoise;
  denoise.fidelity = 0.0;
  EXPECT_THROW(denoiseWithPatches(mesh, out, denoise), Error);
  EXPECT_THROW(denoiseWithPatches(TriangleMesh(), out), Error);
}
