// Throughput of extractMeshHeightMaps on a ~100k-face mesh (torus 224 × 224 = 100352 faces,
// normalised to the unit cube), with the CLI's seeds and frames (apps/patch_seeds: random
// area-uniform seeds, 12 per patch area at L = 0.03, N = 16), on 1 and 2 OpenMP threads; and on
// the bundled bunny. Items/s in the output are patches per second.
#include <pcl_patchdict/patches/patch_seeds.h>

#include <pcl_patchdict/patches/height_maps.h>
#include <pcl_patchdict/geometry/mesh_hygiene.h>
#include <pcl_patchdict/io/mesh_io.h>
#include <pcl_patchdict/core/normalization.h>
#include <pcl_patchdict_eval/shapes.h>

#include <benchmark/benchmark.h>

#include <omp.h>

#include <cmath>

namespace {

using namespace pcl::patchdict;

constexpr double kQuadLength = 0.03;

TriangleMesh unitCube(TriangleMesh mesh)
{
  cleanMesh(mesh);
  UnitCubeNormalization::fromMesh(mesh).apply(mesh);
  return mesh;
}

const TriangleMesh& torus()
{
  static const TriangleMesh mesh = unitCube(makeTorus(224, 224, 1.0, 0.3));
  return mesh;
}

const TriangleMesh& bunny()
{
  static const TriangleMesh mesh = [] {
    TriangleMesh m;
    readMesh(std::string(PCL_PATCHDICT_DATA_DIR) + "/bunny.obj", m);
    return unitCube(std::move(m));
  }();
  return mesh;
}

void extract(benchmark::State& state, const TriangleMesh& mesh)
{
  const int threads = static_cast<int>(state.range(0));
  PatchLayoutParameters placement;
  placement.quad_length = kQuadLength;
  placement.seed = 1;
  const PatchLayout seeds = layPatches(mesh, placement);
  HeightMapParameters parameters;
  parameters.radius = kQuadLength / std::sqrt(2.0);
  parameters.grid_size = 16;
  parameters.num_threads = threads;
  PatchSet patches;
  for (auto _ : state) {
    extractMeshHeightMaps(mesh, seeds.seeds, seeds.frames, parameters, patches);
    benchmark::DoNotOptimize(patches.heights.data());
  }
  state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations()) *
                          static_cast<std::int64_t>(seeds.seeds.size()));
  state.counters["patches"] = static_cast<double>(seeds.seeds.size());
  state.counters["faces"] = static_cast<double>(mesh.faces.size());
  state.counters["observed"] = patches.observedFraction();
}

void BM_ExtractTorus100k(benchmark::State& state) { extract(state, torus()); }
void BM_ExtractBunny(benchmark::State& state) { extract(state, bunny()); }

}  // namespace

BENCHMARK(BM_ExtractTorus100k)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_ExtractBunny)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime();
