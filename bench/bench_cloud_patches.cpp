// Speed of the cloud patch stage on a 100k-point relief cloud: SparsePatchInpainter completing 12
// holes (base + check + patches) on 1 and 2 threads, and the binned extraction of its patches alone
// (items/s = patches per second). The cloud: 100,000 uniform samples of grooves 0.004 deep, 0.03
// apart, over [-0.5, 0.5] × [-0.35, 0.35], without 12 discs of radius 0.035 (the harness's hole size).
#include <pcl_patchdict/cloud/sparse_patch_inpainter.h>
#include <pcl_patchdict/core/local_frame.h>
#include <pcl_patchdict/patches/height_maps.h>
#include <pcl_patchdict/patches/patch_set.h>

#include <benchmark/benchmark.h>

#include <pcl/point_types.h>

#include <cmath>
#include <random>

namespace {

using namespace pcl::patchdict;

double grooves(double x, double y)
{
  const double phase = (x * std::cos(0.5236) + y * std::sin(0.5236)) / 0.03;
  return 0.002 * std::tanh(4.0 * std::sin(2.0 * M_PI * phase));
}

pcl::PointCloud<pcl::PointXYZ>::Ptr reliefCloud()
{
  std::mt19937_64 random(11);
  std::uniform_real_distribution<double> ux(-0.5, 0.5), uy(-0.35, 0.35);
  std::vector<Eigen::Vector2d> centres;
  for (int i = 0; i < 12; ++i)
    centres.emplace_back(-0.4 + 0.16 * (i % 6), i < 6 ? -0.15 : 0.15);
  auto cloud = std::make_shared<pcl::PointCloud<pcl::PointXYZ>>();
  while (cloud->size() < 100000) {
    const double x = ux(random), y = uy(random);
    bool in_hole = false;
    for (const auto& c : centres)
      in_hole = in_hole || std::hypot(x - c.x(), y - c.y()) < 0.035;
    if (!in_hole)
      cloud->push_back(pcl::PointXYZ(static_cast<float>(x), static_cast<float>(y), static_cast<float>(grooves(x, y))));
  }
  return cloud;
}

const pcl::PointCloud<pcl::PointXYZ>::Ptr& sharedCloud()
{
  static const auto cloud = reliefCloud();
  return cloud;
}

void BM_ReliefCloudCompletion(benchmark::State& state)
{
  const auto& cloud = sharedCloud();
  for (auto _ : state) {
    SparsePatchInpainter<pcl::PointXYZ> inpainter;
    inpainter.setInputCloud(cloud);
    inpainter.setMode(SparsePatchInpainter<pcl::PointXYZ>::Mode::Complete);
    inpainter.setNumberOfThreads(static_cast<int>(state.range(0)));
    pcl::PointCloud<pcl::PointXYZ> out;
    inpainter.process(out);
    const CloudPatchReport& r = inpainter.getPatchReport();
    state.counters["added"] = static_cast<double>(inpainter.getReport().points_added);
    state.counters["applied"] = r.outcome == pcl::patchdict::PatchOutcome::Applied ? 1.0 : 0.0;
    state.counters["s_layout"] = r.seconds_layout;
    state.counters["s_check"] = r.seconds_check;
    state.counters["s_patches"] = r.seconds_patches;
  }
}
BENCHMARK(BM_ReliefCloudCompletion)->Arg(1)->Arg(2)->Unit(benchmark::kSecond)->Iterations(1)->UseRealTime();

/** Binned extraction at the completion's settings (N = 32, one bin of reach, side 0.09) at 20,000
  * seeds on the cloud with frames from the plane's normal. */
void BM_ReliefCloudExtraction(benchmark::State& state)
{
  std::vector<Eigen::Vector3d> points;
  for (const auto& p : *sharedCloud())
    points.emplace_back(p.x, p.y, p.z);
  std::mt19937_64 random(3);
  std::uniform_int_distribution<std::size_t> pick(0, points.size() - 1);
  std::vector<Eigen::Vector3d> seeds(20000);
  for (auto& s : seeds)
    s = points[pick(random)];
  const std::vector<Eigen::Matrix3d> frames(seeds.size(), frameFromNormal(Eigen::Vector3d::UnitZ()));
  HeightMapParameters parameters;
  parameters.radius = 0.09 / std::sqrt(2.0);
  parameters.grid_size = 32;
  parameters.bin_reach = 1.0;
  parameters.num_threads = static_cast<int>(state.range(0));
  for (auto _ : state) {
    PatchSet patches;
    extractCloudHeightMaps(points, seeds, frames, parameters, patches);
    benchmark::DoNotOptimize(patches.heights.data());
  }
  state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations()) * static_cast<std::int64_t>(seeds.size()));
}
// At least 3 s a thread count: one 1-second iteration swung 18k–22k patches/s on this shared machine.
BENCHMARK(BM_ReliefCloudExtraction)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->MinTime(3.0)->UseRealTime();

}  // namespace
