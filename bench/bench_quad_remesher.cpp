// Benchmarks of QuadRemesher (refinement + hierarchy + orientation + position field + extraction)
// on scaled copies of one shape, with L = 0.03 in unit-cube units as in the pipeline:
//  - the bundled bunny, normalised and Taubin-smoothed like the pipeline does, at its own 69k
//    faces and subdivided once (278k faces);
//  - a torus of unit-cube size at 25k, 100k and 400k faces (the "scaled copies").
// Arguments: faces (thousands), threads. Time per remeshing in seconds; counters: quads, faces/s.
#include <pcl_patchdict/geometry/coarse_mesh_estimation.h>
#include <pcl_patchdict/geometry/mesh_hygiene.h>
#include <pcl_patchdict/io/mesh_io.h>
#include <pcl_patchdict/core/normalization.h>
#include <pcl_patchdict/quads/quad_remesher.h>
#include <pcl_patchdict_eval/shapes.h>

#include <benchmark/benchmark.h>

#include <map>

namespace {

using namespace pcl::patchdict;

const TriangleMesh& bunny(int thousands)
{
  static std::map<int, TriangleMesh> meshes;
  auto it = meshes.find(thousands);
  if (it != meshes.end())
    return it->second;
  TriangleMesh mesh;
  readMesh(std::string(PCL_PATCHDICT_DATA_DIR) + "/bunny.obj", mesh);
  cleanMesh(mesh);
  UnitCubeNormalization::fromMesh(mesh).apply(mesh);
  if (thousands > 100)
    mesh = subdivideMidpoint(mesh);
  TriangleMesh coarse;
  CoarseMeshEstimation smoothing;
  smoothing.setInputMesh(std::make_shared<const TriangleMesh>(mesh));
  smoothing.process(coarse);
  return meshes.emplace(thousands, std::move(coarse)).first->second;
}

const TriangleMesh& torus(int thousands)
{
  static std::map<int, TriangleMesh> meshes;
  auto it = meshes.find(thousands);
  if (it != meshes.end())
    return it->second;
  // nu × nv × 2 faces with nu = 1.25·nv; major radius 0.35, minor 0.15 (fits the unit cube).
  const int nv = static_cast<int>(std::lround(std::sqrt(thousands * 1000.0 / 2.5)));
  return meshes.emplace(thousands, makeTorus(nv * 5 / 4, nv, 0.35, 0.15)).first->second;
}

void run(benchmark::State& state, const TriangleMesh& mesh)
{
  QuadRemesher remesher;
  remesher.setInputMesh(std::make_shared<const TriangleMesh>(mesh));
  remesher.setQuadLength(0.03);
  remesher.setNumberOfThreads(static_cast<int>(state.range(1)));
  QuadMesh out;
  QuadRemesher::Report report;
  for (auto _ : state) {
    remesher.process(out, &report);
    benchmark::DoNotOptimize(out.faces.data());
  }
  state.counters["input_faces"] = static_cast<double>(mesh.faces.size());
  state.counters["quads"] = static_cast<double>(computeQuadMeshStatistics(out).quads);
  state.counters["s_fields"] = report.seconds_orientation + report.seconds_position;
  state.counters["s_position"] = report.seconds_position;
  state.counters["s_extract"] = report.seconds_extraction;
  state.counters["faces_per_s"] =
      benchmark::Counter(static_cast<double>(mesh.faces.size()), benchmark::Counter::kIsIterationInvariantRate);
}

void BM_QuadRemeshTorus(benchmark::State& state) { run(state, torus(static_cast<int>(state.range(0)))); }
void BM_QuadRemeshBunny(benchmark::State& state) { run(state, bunny(static_cast<int>(state.range(0)))); }

BENCHMARK(BM_QuadRemeshTorus)
    ->ArgsProduct({{25, 100, 400}, {1, 2}})
    ->ArgNames({"kfaces", "threads"})
    ->Unit(benchmark::kSecond)
    ->Iterations(2)
    ->UseRealTime();
BENCHMARK(BM_QuadRemeshBunny)
    ->ArgsProduct({{69, 278}, {1, 2}})
    ->ArgNames({"kfaces", "threads"})
    ->Unit(benchmark::kSecond)
    ->Iterations(2)
    ->UseRealTime();

}  // namespace
