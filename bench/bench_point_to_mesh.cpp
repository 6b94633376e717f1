// Benchmarks of PointToMeshDistance on a ~100k-face mesh (torus 224 × 224 = 100352 faces):
// tree build time, single-point query throughput, and distances() over 1M points with 1 and 2
// OpenMP threads. Query points: half uniform in the bounding box grown by 20 % on every side,
// half within ~1 % of the box diagonal of the surface (the case the metrics mostly see).
// Items/s in the output are queries per second.
#include <pcl_patchdict/geometry/metrics.h>
#include <pcl_patchdict_eval/shapes.h>

#include <benchmark/benchmark.h>

#include <omp.h>

#include <random>

namespace {

using pcl::patchdict::PointToMeshDistance;
using pcl::patchdict::TriangleMesh;

const TriangleMesh& benchMesh()
{
  static const TriangleMesh mesh = pcl::patchdict::makeTorus(224, 224, 1.0, 0.3);
  return mesh;
}

std::vector<Eigen::Vector3d> queryPoints(std::size_t n)
{
  const TriangleMesh& mesh = benchMesh();
  Eigen::Vector3d lo, hi;
  mesh.boundingBox(lo, hi);
  const Eigen::Vector3d margin = 0.2 * (hi - lo);
  const double near = 0.01 * (hi - lo).norm();
  std::mt19937_64 rng(2024);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::normal_distribution<double> gauss(0.0, near);
  std::vector<Eigen::Vector3d> points;
  points.reserve(n);
  for (std::size_t i = 0; i < n; ++i) {
    if (i % 2 == 0) {
      const Eigen::Vector3d t(unit(rng), unit(rng), unit(rng));
      points.push_back(lo - margin + t.cwiseProduct(hi - lo + 2 * margin));
    } else {
      const Eigen::Vector3d& v = mesh.vertices[rng() % mesh.vertices.size()];
      points.push_back(v + Eigen::Vector3d(gauss(rng), gauss(rng), gauss(rng)));
    }
  }
  return points;
}

const std::vector<Eigen::Vector3d>& millionPoints()
{
  static const std::vector<Eigen::Vector3d> points = queryPoints(1000000);
  return points;
}

void BM_BuildTree(benchmark::State& state)
{
  const TriangleMesh& mesh = benchMesh();
  for (auto _ : state) {
    PointToMeshDistance tree(mesh);
    benchmark::DoNotOptimize(tree);
  }
  state.counters["faces"] = static_cast<double>(mesh.faces.size());
  state.SetItemsProcessed(state.iterations() * static_cast<std::int64_t>(mesh.faces.size()));
}
BENCHMARK(BM_BuildTree)->Unit(benchmark::kMillisecond);

void BM_QuerySingle(benchmark::State& state)
{
  const PointToMeshDistance tree(benchMesh());
  const std::vector<Eigen::Vector3d> points = queryPoints(1 << 16);
  std::size_t i = 0;
  for (auto _ : state) {
    benchmark::DoNotOptimize(tree.query(points[i]));
    i = (i + 1) & (points.size() - 1);
  }
  state.SetItemsProcessed(state.iterations());
}
BENCHMARK(BM_QuerySingle);

void BM_Distances1M(benchmark::State& state)
{
  const PointToMeshDistance tree(benchMesh());
  const std::vector<Eigen::Vector3d>& points = millionPoints();
  const int saved = omp_get_max_threads();
  omp_set_num_threads(static_cast<int>(state.range(0)));
  for (auto _ : state) {
    std::vector<double> d = tree.distances(points);
    benchmark::DoNotOptimize(d.data());
  }
  omp_set_num_threads(saved);
  state.counters["threads"] = static_cast<double>(state.range(0));
  state.SetItemsProcessed(state.iterations() * static_cast<std::int64_t>(points.size()));
}
BENCHMARK(BM_Distances1M)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime()->Iterations(3);

}  // namespace
