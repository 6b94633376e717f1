// HeightMapPatchExtractor, the pcl::Feature: through PCL's base pointer it gives the core's heights
// (NaN exactly where the core's mask is false), on three point types; a planar cloud with SHOT's
// default frames; the bin and frame convention on a tilted plane; exact heights from a
// pcl::PolygonMesh; seeds without a frame; every misuse an Error.
#include <pcl_patchdict/core/error.h>
#include <pcl_patchdict/core/local_frame.h>
#include <pcl_patchdict_eval/shapes.h>
#include <pcl_patchdict/patches/height_maps.h>
#include <pcl_patchdict/pcl/conversions.h>
#include <pcl_patchdict/pcl/height_map_patch_extractor.h>
#include <pcl_patchdict/pcl/reference_frame.h>

#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include <pcl/common/io.h>

#include <cmath>
#include <cstring>
#include <functional>
#include <limits>
#include <random>

using namespace pcl::patchdict;

namespace {

using Histogram = pcl::Histogram<256>;
using Frames = pcl::PointCloud<pcl::ReferenceFrame>;

template <typename PointT>
PointT pointAt(const Eigen::Vector3d& p)
{
  PointT point;
  point.x = static_cast<float>(p.x());
  point.y = static_cast<float>(p.y());
  point.z = static_cast<float>(p.z());
  return point;
}

/** The vertices of a sinusoidal relief (1 × 1, amplitude 0.02, period 0.3) as a cloud. */
template <typename PointT>
typename pcl::PointCloud<PointT>::Ptr reliefCloud()
{
  typename pcl::PointCloud<PointT>::Ptr cloud(new pcl::PointCloud<PointT>);
  toPointCloud(makeSinusoidalRelief(120, 120, 0.02, 0.3), *cloud);
  return cloud;
}

/** 60 seeds at relief vertices (some near the border), each with a tilted, turned frame. */
template <typename PointT>
void seedsAndFrames(const pcl::PointCloud<PointT>& cloud, typename pcl::PointCloud<PointT>::Ptr& seeds,
                    Frames::Ptr& frames)
{
  std::mt19937_64 random(25);
  std::uniform_int_distribution<std::size_t> pick(0, cloud.size() - 1);
  std::uniform_real_distribution<double> angle(-0.4, 0.4);
  seeds.reset(new pcl::PointCloud<PointT>);
  std::vector<Eigen::Matrix3d> rows;
  for (int k = 0; k < 60; ++k) {
    seeds->push_back(cloud[pick(random)]);
    rows.push_back((Eigen::AngleAxisd(angle(random) * 7.0, Eigen::Vector3d::UnitZ()) *
                    Eigen::AngleAxisd(angle(random), Eigen::Vector3d::UnitX()))
                       .toRotationMatrix()
                       .transpose());
  }
  frames.reset(new Frames(toReferenceFrames(rows)));
}

std::vector<Eigen::Vector3d> positions(const pcl::PointCloud<pcl::PointXYZ>& cloud)
{
  std::vector<Eigen::Vector3d> out;
  for (const auto& p : cloud)
    out.emplace_back(p.x, p.y, p.z);
  return out;
}

template <typename PointT>
std::vector<Eigen::Vector3d> positionsOf(const pcl::PointCloud<PointT>& cloud)
{
  pcl::PointCloud<pcl::PointXYZ> xyz;
  pcl::copyPointCloud(cloud, xyz);
  return positions(xyz);
}

std::string errorOf(const std::function<void()>& run)
{
  try {
    run();
  } catch (const Error& error) {
    return error.what();
  }
  return "(no error)";
}

/** What HeightMapPatchExtractor gives for `seeds` on the surface `cloud` at `radius`, in `frames`
  * (none: SHOT's). */
pcl::PointCloud<Histogram> extractHeights(const pcl::PointCloud<pcl::PointXYZ>::Ptr& seeds,
                                          const pcl::PointCloud<pcl::PointXYZ>::Ptr& cloud, double radius,
                                          const Frames::Ptr& frames = nullptr)
{
  HeightMapPatchExtractor<pcl::PointXYZ> extractor;
  extractor.setInputCloud(seeds);
  extractor.setSearchSurface(cloud);
  if (frames)
    extractor.setInputReferenceFrames(frames);
  extractor.setRadiusSearch(radius);
  pcl::PointCloud<Histogram> histograms;
  extractor.compute(histograms);
  return histograms;
}

double binCentre(int index, int grid, double radius)
{
  const double side = std::sqrt(2.0) * radius;
  return (index + 0.5) / grid * side - side / 2.0;
}

}  // namespace

template <typename PointT>
class HeightMapFeature : public ::testing::Test {};
using PointTypes = ::testing::Types<pcl::PointXYZ, pcl::PointNormal, pcl::PointXYZRGBNormal>;
TYPED_TEST_SUITE(HeightMapFeature, PointTypes);

TYPED_TEST(HeightMapFeature, ThroughTheFeatureBaseItGivesTheCoreHeightsAndNaNWhereUnobserved)
{
  const auto cloud = reliefCloud<TypeParam>();
  typename pcl::PointCloud<TypeParam>::Ptr seeds;
  Frames::Ptr frames;
  seedsAndFrames(*cloud, seeds, frames);
  const double radius = 0.1;  // bins of 0.0088, a little more than the relief's spacing 0.0083

  auto extractor = std::make_shared<HeightMapPatchExtractor<TypeParam>>();
  extractor->setInputReferenceFrames(frames);
  const typename pcl::Feature<TypeParam, Histogram>::Ptr feature = extractor;
  feature->setInputCloud(seeds);
  feature->setSearchSurface(cloud);
  feature->setRadiusSearch(radius);
  pcl::PointCloud<Histogram> histograms;
  feature->compute(histograms);

  PatchSet core;
  extractCloudHeightMaps(positionsOf(*cloud), positionsOf(*seeds), fromReferenceFrames(*frames), {radius, 16}, core);
  ASSERT_EQ(histograms.size(), seeds->size());
  std::size_t observed = 0, unobserved = 0;
  for (std::size_t p = 0; p < histograms.size(); ++p)
    for (int b = 0; b < 256; ++b) {
      const float value = histograms[p].histogram[b];
      if (core.observed(b, static_cast<Eigen::Index>(p))) {
        EXPECT_EQ(value, static_cast<float>(core.heights(b, static_cast<Eigen::Index>(p))));
        ++observed;
      } else {
        EXPECT_TRUE(std::isnan(value));
        ++unobserved;
      }
    }
  // Both kinds of bins occur: the relief's spacing leaves some bins empty, seeds near its border more.
  EXPECT_GT(observed, 60u * 256u / 2u);
  EXPECT_GT(unobserved, 100u);
  EXPECT_FALSE(histograms.is_dense);
  // The same bits on one thread and on two.
  for (const int threads : {1, 2}) {
    extractor->setNumberOfThreads(threads);
    pcl::PointCloud<Histogram> again;
    feature->compute(again);
    ASSERT_EQ(again.size(), histograms.size());
    EXPECT_EQ(std::memcmp(again.data(), histograms.data(), sizeof(Histogram) * histograms.size()), 0);
  }
}

TEST(HeightMapFeature, APlanarCloudWithShotFramesGivesHeightsWithinTheNoise)
{
  // A plane z = 0.3 with Gaussian noise σ = 0.001 along z, 60 000 random points on [0, 1]²; seeds
  // away from the rim; no frames given: SHOT's (Z the normal up to its sign).
  const double sigma = 0.001;
  std::mt19937_64 random(3);
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  std::normal_distribution<double> noise(0.0, sigma);
  pcl::PointCloud<pcl::PointXYZ>::Ptr cloud(new pcl::PointCloud<pcl::PointXYZ>), seeds(new pcl::PointCloud<pcl::PointXYZ>);
  for (int i = 0; i < 60000; ++i)
    cloud->push_back(pointAt<pcl::PointXYZ>({uniform(random), uniform(random), 0.3 + noise(random)}));
  for (int i = 0; i < 25; ++i)
    seeds->push_back(pointAt<pcl::PointXYZ>({0.2 + 0.6 * uniform(random), 0.2 + 0.6 * uniform(random), 0.3}));
  const pcl::PointCloud<Histogram> histograms = extractHeights(seeds, cloud, 0.1);
  ASSERT_EQ(histograms.size(), 25u);
  double sum_squares = 0.0, largest = 0.0;
  std::size_t count = 0;
  for (const auto& h : histograms)
    for (const float value : h.histogram)
      if (!std::isnan(value)) {
        sum_squares += value * value;
        largest = std::max(largest, std::abs(static_cast<double>(value)));
        ++count;
      }
  // ~60 000 · 0.02 / 256 ≈ 4.7 points a bin: every bin seen, its mean height within a few σ/√4.7.
  EXPECT_GT(count, 25u * 256u * 95u / 100u);
  EXPECT_LT(std::sqrt(sum_squares / static_cast<double>(count)), 0.7 * sigma);
  EXPECT_LT(largest, 5.0 * sigma);
}

TEST(HeightMapFeature, TiltedPlaneFixesTheBinOrderAndTheFrameConvention)
{
  // Points at the bin centres of a plane z = 0.25·x; one seed at the origin, first with the
  // identity frame (heights vary along i, the column along X), then with X = +y, Y = −x, Z = +z
  // (heights vary along j, the row along Y, with the opposite sign).
  const int grid = 16;
  const double radius = 0.1, slope = 0.25;
  pcl::PointCloud<pcl::PointXYZ>::Ptr cloud(new pcl::PointCloud<pcl::PointXYZ>), seed(new pcl::PointCloud<pcl::PointXYZ>);
  for (int j = 0; j < grid; ++j)
    for (int i = 0; i < grid; ++i) {
      const double x = binCentre(i, grid, radius), y = binCentre(j, grid, radius);
      cloud->push_back(pointAt<pcl::PointXYZ>({x, y, slope * x}));
    }
  seed->push_back(pcl::PointXYZ(0.f, 0.f, 0.f));
  Eigen::Matrix3d turned;
  turned << 0, 1, 0, -1, 0, 0, 0, 0, 1;
  for (const bool turn : {false, true}) {
    Frames::Ptr frames(new Frames(toReferenceFrames({turn ? turned : Eigen::Matrix3d::Identity()})));
    const pcl::PointCloud<Histogram> histograms = extractHeights(seed, cloud, radius, frames);
    ASSERT_EQ(histograms.size(), 1u);
    std::size_t finite = 0;
    for (int j = 0; j < grid; ++j)
      for (int i = 0; i < grid; ++i) {
        const float value = histograms[0].histogram[j * grid + i];
        // Every bin centre lies within r of the seed (the corners' at 0.95·r): each bin has its point.
        const double expected = turn ? -slope * binCentre(j, grid, radius) : slope * binCentre(i, grid, radius);
        EXPECT_NEAR(value, expected, 1e-6) << "bin (" << i << ", " << j << ")";
        finite += std::isfinite(value);
      }
    EXPECT_EQ(finite, 256u);
  }
}

TEST(HeightMapFeature, ExactHeightsFromAPolygonMeshAreTheCoreMeshHeights)
{
  const TriangleMesh relief = makeSinusoidalRelief(60, 60, 0.02, 0.3);
  pcl::PolygonMesh::Ptr mesh(new pcl::PolygonMesh);
  toPolygonMesh(relief, *mesh);
  const auto cloud = reliefCloud<pcl::PointXYZ>();
  pcl::PointCloud<pcl::PointXYZ>::Ptr seeds;
  Frames::Ptr frames;
  seedsAndFrames(*cloud, seeds, frames);
  HeightMapPatchExtractor<pcl::PointXYZ> extractor;
  extractor.setInputCloud(seeds);
  extractor.setInputReferenceFrames(frames);
  extractor.setInputPolygonMesh(mesh);
  extractor.setRadiusSearch(0.05);
  pcl::PointCloud<Histogram> histograms;
  extractor.compute(histograms);

  TriangleMesh as_pcl_holds_it;  // float coordinates, as the pcl::PolygonMesh has them
  fromPolygonMesh(*mesh, as_pcl_holds_it);
  PatchSet core;
  extractMeshHeightMaps(as_pcl_holds_it, positions(*seeds), fromReferenceFrames(*frames), {0.05, 16}, core);
  std::size_t observed = 0;
  for (std::size_t p = 0; p < histograms.size(); ++p)
    for (int b = 0; b < 256; ++b) {
      const auto column = static_cast<Eigen::Index>(p);
      if (core.observed(b, column)) {
        EXPECT_EQ(histograms[p].histogram[b], static_cast<float>(core.heights(b, column)));
        ++observed;
      } else {
        EXPECT_TRUE(std::isnan(histograms[p].histogram[b]));
      }
    }
  // Exact heights fill every bin over the mesh: only seeds near its border lose some.
  EXPECT_GT(observed, 60u * 256u * 8u / 10u);
}

TEST(HeightMapFeature, ASeedWithoutAFrameGetsAnAllNaNHistogram)
{
  const auto cloud = reliefCloud<pcl::PointXYZ>();
  pcl::PointCloud<pcl::PointXYZ>::Ptr seeds;
  Frames::Ptr frames;
  seedsAndFrames(*cloud, seeds, frames);
  for (float& entry : (*frames)[7].rf)
    entry = std::numeric_limits<float>::quiet_NaN();
  (*seeds)[9].x = std::numeric_limits<float>::quiet_NaN();  // and one seed that is not a point
  const pcl::PointCloud<Histogram> histograms = extractHeights(seeds, cloud, 0.1, frames);
  ASSERT_EQ(histograms.size(), 60u);
  EXPECT_FALSE(histograms.is_dense);
  for (const std::size_t p : {7u, 9u})
    for (const float value : histograms[p].histogram)
      EXPECT_TRUE(std::isnan(value));
  std::size_t finite = 0;
  for (const float value : histograms[8].histogram)
    finite += std::isfinite(value);
  EXPECT_GT(finite, 128u);
}

TEST(HeightMapFeature, MisuseIsAnErrorOfOneLine)
{
  const auto cloud = reliefCloud<pcl::PointXYZ>();
  pcl::PointCloud<pcl::PointXYZ>::Ptr seeds;
  Frames::Ptr frames;
  seedsAndFrames(*cloud, seeds, frames);
  pcl::PointCloud<Histogram> out;
  const auto configured = [&]() {
    auto extractor = std::make_shared<HeightMapPatchExtractor<pcl::PointXYZ>>();
    extractor->setInputCloud(seeds);
    extractor->setSearchSurface(cloud);
    extractor->setInputReferenceFrames(frames);
    extractor->setRadiusSearch(0.05);
    return extractor;
  };
  const std::vector<std::pair<std::function<void(HeightMapPatchExtractor<pcl::PointXYZ>&)>, std::string>> cases = {
      {[](auto& e) { e.setGridSize(8); }, "8×8 grid has 64 bins, but the descriptor holds 256"},
      {[](auto& e) { e.setGridSize(1); }, "grid size must be in [2, 256]"},
      {[](auto& e) { e.setRadiusSearch(0.0); }, "must be positive"},
      {[](auto& e) { e.setKSearch(10); }, "not setKSearch"},
      {[](auto& e) { e.setInputCloud(pcl::PointCloud<pcl::PointXYZ>::Ptr(new pcl::PointCloud<pcl::PointXYZ>)); },
       "no seeds"},
      {[&](auto& e) { e.setInputReferenceFrames(Frames::Ptr(new Frames(toReferenceFrames({Eigen::Matrix3d::Identity()})))); },
       "1 reference frames for 60 seeds"},
      {[&](auto& e) {
         Frames::Ptr mirrored(new Frames(*frames));
         (*mirrored)[4].z_axis[0] *= -1.f, (*mirrored)[4].z_axis[1] *= -1.f, (*mirrored)[4].z_axis[2] *= -1.f;
         e.setInputReferenceFrames(mirrored);
       },
       "frame 4 is left-handed"},
      {[&](auto& e) { e.setSearchSurface(pcl::PointCloud<pcl::PointXYZ>::Ptr(new pcl::PointCloud<pcl::PointXYZ>)); },
       "the input surface has no points"},
  };
  for (const auto& [misuse, words] : cases) {
    auto extractor = configured();
    misuse(*extractor);
    const std::string message = errorOf([&]() { extractor->compute(out); });
    EXPECT_NE(message.find(words), std::string::npos) << message;
    EXPECT_EQ(message.find('\n'), std::string::npos) << message;
  }
  auto extractor = configured();  // and configured well, it computes
  extractor->compute(out);
  EXPECT_EQ(out.size(), 60u);
}
