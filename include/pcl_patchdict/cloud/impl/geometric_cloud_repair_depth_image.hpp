// GeometricCloudRepair<PointInT, PointOutT>::processDepthImage (see
// geometric_cloud_repair.h): an organised cloud whose grid is a pinhole image, denoised along
// its pixels' rays, filled in place, with the free-space test.
#pragma once

#include <pcl_patchdict/core/error.h>
#include <pcl_patchdict/cloud/geometric_cloud_repair.h>

#include <pcl/common/copy_point.h>
#include <pcl/point_traits.h>
#include <pcl/search/kdtree.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>

#include <omp.h>

namespace pcl {
namespace patchdict {
namespace detail {

/// What processDepthImage's stages hand each other: the image, its measured pixels and the grid's
/// positions and normals as they are denoised and filled.
struct DepthRun {
  /// with_normals: the output type keeps normals (else `normal` stays empty: 7 MB a VGA frame saved).
  DepthRun(const std::vector<Eigen::Vector3d>& points, const DepthImage& image_, bool with_normals)
      : image(image_), W(image_.width), H(image_.height), n(W * H), points_(points), position(n),
        normal(with_normals ? n : 0), present(image_.valid)
  {
    // Off-ray points are no measurements: from here on, a pixel is its depth image's. Per pixel in
    // parallel (each its own), the list of measured pixels after, in order.
    const Eigen::Vector3d none = Eigen::Vector3d::Constant(std::numeric_limits<double>::quiet_NaN());
    const long long pixels = static_cast<long long>(n);
#pragma omp parallel for schedule(static)
    for (long long k = 0; k < pixels; ++k) {
      const std::size_t i = static_cast<std::size_t>(k);
      position[i] = image.valid[i] ? points[i] : none;
      if (with_normals)
        normal[i].setZero();
    }
    queries.reserve(n);
    for (std::size_t i = 0; i < n; ++i)
      if (image.valid[i])
        queries.push_back(i);
  }

  /// A measured pixel's point (image.valid[i]), as read: the caller's points, not a copy.
  const Eigen::Vector3d& measured(std::size_t i) const { return points_[i]; }
  /// The measured points with NaN at every other pixel (for the cloud denoiser, which reads them all).
  std::vector<Eigen::Vector3d> measuredCloud() const
  {
    std::vector<Eigen::Vector3d> out(n, Eigen::Vector3d::Constant(std::numeric_limits<double>::quiet_NaN()));
    for (const std::size_t i : queries)
      out[i] = points_[i];
    return out;
  }
  Eigen::Vector3d ray(std::size_t i) const { return image.camera.pointAt(double(i % W), double(i / W), 1.0); }
  // Normals from the grid: central differences of the present neighbours, facing the camera.
  Eigen::Vector3d gridNormal(std::size_t i) const
  {
    const std::size_t c = i % W, r = i / W;
    const auto at = [&](std::size_t cc, std::size_t rr) { return present[rr * W + cc] ? position[rr * W + cc] : position[i]; };
    const Eigen::Vector3d du = at(std::min(W - 1, c + 1), r) - at(c ? c - 1 : 0, r);
    const Eigen::Vector3d dv = at(c, std::min(H - 1, r + 1)) - at(c, r ? r - 1 : 0);
    Eigen::Vector3d nrm = du.cross(dv);
    nrm = nrm.norm() > 0.0 ? nrm.normalized() : Eigen::Vector3d(-ray(i).normalized());
    return nrm.dot(position[i]) > 0.0 ? Eigen::Vector3d(-nrm) : nrm;
  }

  const DepthImage& image;
  const std::size_t W, H, n;
  const std::vector<Eigen::Vector3d>& points_;  // the input's points in the sensor frame (not owned)
  std::vector<std::size_t> queries;       // the measured pixels
  std::vector<Eigen::Vector3d> position, normal;
  std::vector<char> present;
  std::vector<std::size_t> filled;
};

}  // namespace detail

template <typename PointInT, typename PointOutT>
void GeometricCloudRepair<PointInT, PointOutT>::processDepthImage(const std::vector<Eigen::Vector3d>& points,
                                                                      const std::vector<Eigen::Vector3d>& normals,
                                                                      const DepthImage& image, const Eigen::Matrix3d& R,
                                                                      const Eigen::Vector3d& o, PointCloudOut& output)
{
  const std::size_t n = image.width * image.height;
  const PinholeCamera& camera = image.camera;
  report_.depth_image = true;
  report_.camera = camera;
  report_.off_ray_points = camera.off_ray;
  report_.input_points = n;
  report_.nonfinite_points = n - image.measured();  // NaN pixels and off-ray points
  const auto start = std::chrono::steady_clock::now();
  const bool given = sensorModelGiven() && sensor_model_.kind == SensorModel::Kind::Pinhole;
  report_.depth_noise = given ? sensor_model_.depth_noise : estimateDepthNoise(image);
  report_.sensor_model_given = given;
  used_sensor_model_.kind = SensorModel::Kind::Pinhole;
  used_sensor_model_.width = image.width;
  used_sensor_model_.height = image.height;
  used_sensor_model_.camera = camera;
  used_sensor_model_.depth_noise = report_.depth_noise;
  report_.seconds_noise = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  detail::DepthRun run(points, image, pcl::traits::has_normal_v<PointOutT>);
  // The sensor's own noise law, unless the caller fixed σ or h for the patches: image-space denoising.
  const bool in_image = depth_image_denoising_ && report_.depth_noise.coefficient > 0.0 &&
                        parameters_.noise_sigma == 0.0 && parameters_.bandwidth == 0.0;
  if (mode_ != Mode::Complete && run.queries.size() < 100)
    throw Error("the cloud has " + std::to_string(run.queries.size()) + " measured pixels; denoising needs at least 100");
  if (mode_ != Mode::Complete && in_image)
    denoiseDepthInImage(run);
  else if (mode_ != Mode::Complete)
    denoiseDepthWithPatches(run, normals);
  if (mode_ != Mode::Denoise)
    fillDepthHoles(run);
  writeDepthOutput(run, R, o, output);
}

template <typename PointInT, typename PointOutT>
void GeometricCloudRepair<PointInT, PointOutT>::denoiseDepthInImage(detail::DepthRun& run)
{
  const DepthImage& image = run.image;
  const PinholeCamera& camera = image.camera;
  const std::size_t W = run.W, n = run.n;
  std::vector<double> depth;
  const auto fit_start = std::chrono::steady_clock::now();
  DepthDenoisingParameters denoising = depth_denoising_;
  if (denoising.num_threads == 0)
    denoising.num_threads = parameters_.num_threads;
  denoiseDepthImage(image, report_.depth_noise, denoising, depth, report_.depth_denoising);
  report_.seconds_fit = std::chrono::duration<double>(std::chrono::steady_clock::now() - fit_start).count();
  report_.depth_denoised_in_image = true;
  const FreeSpaceTest free_space(image);
  const long long queries = static_cast<long long>(run.queries.size());
  const int threads = parameters_.num_threads > 0 ? parameters_.num_threads : omp_get_max_threads();
  std::size_t reverted = 0;
#pragma omp parallel for schedule(static) num_threads(threads) reduction(+ : reverted)
  for (long long q = 0; q < queries; ++q) {
    const std::size_t i = run.queries[std::size_t(q)];
    run.position[i] = camera.pointAt(double(i % W), double(i / W), depth[i]);
    // A point moved away along its own ray is behind its own measurement, which its neighbourhood's
    // nearest depth never exceeds: only moves towards the camera need the test.
    if (!run.position[i].allFinite() || (depth[i] < image.depth[i] && free_space.violatesAt(i, depth[i]))) {
      run.position[i] = run.measured(i);
      ++reverted;
    }
  }
  report_.free_space_reverted += reverted;
  if constexpr (pcl::traits::has_normal_v<PointOutT>) {  // normals only for a type that keeps them
#pragma omp parallel for schedule(static) num_threads(threads)
    for (long long q = 0; q < queries; ++q)
      run.normal[run.queries[std::size_t(q)]] = run.gridNormal(run.queries[std::size_t(q)]);
  }
  // The report's typical depth: the median of up to ~4k evenly spaced measured pixels.
  std::vector<double> depths;
  const std::size_t stride = std::max<std::size_t>(1, run.queries.size() / 4096);
  for (std::size_t k = 0; k < run.queries.size(); k += stride)
    depths.push_back(image.depth[run.queries[k]]);
  std::nth_element(depths.begin(), depths.begin() + static_cast<std::ptrdiff_t>(depths.size() / 2), depths.end());
  const double typical = depths[depths.size() / 2];
  report_.noise_sigma = report_.depth_noise.sigma(typical);  // at the median depth
  report_.mean_spacing = camera.pixelSpacing(typical);
  report_.bandwidth = depthDenoisingRadius(camera, depth_denoising_, typical) * report_.mean_spacing;
  report_.input_points = n;
  report_.nonfinite_points = n - run.queries.size();
}

template <typename PointInT, typename PointOutT>
void GeometricCloudRepair<PointInT, PointOutT>::denoiseDepthWithPatches(detail::DepthRun& run,
                                                                            const std::vector<Eigen::Vector3d>& normals)
{
  const PointCloudIn& input = *input_;
  const DepthImage& image = run.image;
  const PinholeCamera& camera = image.camera;
  const std::size_t n = run.n;
  auto searched = std::make_shared<PointCloudIn>(input);
  for (std::size_t i = 0; i < n; ++i) {
    PointInT& p = (*searched)[i];
    p.x = p.y = p.z = std::numeric_limits<float>::quiet_NaN();
    if (image.valid[i])
      p.getVector3fMap() = run.measured(i).cast<float>();
  }
  searched->is_dense = false;
  KdTreePtr tree = tree_;
  if (!tree)
    tree.reset(new pcl::search::KdTree<PointInT>(true));
  tree->setInputCloud(searched);
  const pcl::search::Search<PointInT>& search = *tree;
  const detail::KnnSearch knn = [&](std::size_t q, int k, pcl::Indices& found, std::vector<float>& squared) {
    search.nearestKSearch((*searched)[q], k, found, squared);
  };
  const RadiusNeighbourSearch radius = [&](std::size_t q, double r, int max_nn, pcl::Indices& found,
                                           std::vector<float>& squared) {
    search.radiusSearch((*searched)[q], r, found, squared, static_cast<unsigned int>(max_nn));
  };
  detail::PointScales scales;
  for (const std::size_t i : run.queries) {
    scales.sigma.push_back(report_.depth_noise.sigma(image.depth[i]));
    scales.spacing.push_back(camera.pixelSpacing(image.depth[i]));
  }
  const bool law = report_.depth_noise.coefficient > 0.0 && parameters_.noise_sigma == 0.0;
  std::vector<char> kept;
  std::vector<Eigen::Vector3d> moved, moved_normals;
  const Eigen::Vector3d origin = Eigen::Vector3d::Zero();  // the fitted camera's centre
  detail::denoiseCloud(run.measuredCloud(), normals, run.queries, knn, radius, parameters_, true, &origin, kept, moved,
                       moved_normals, report_, law ? &scales : nullptr);
  report_.input_points = n;  // the grid's, not only its measured pixels
  report_.nonfinite_points = n - run.queries.size();
  // Each point stays on its pixel's ray, where the ray meets its patch's tangent plane; a point the
  // sensor would have seen through stays as measured.
  const FreeSpaceTest free_space(image);
  for (std::size_t q = 0; q < run.queries.size(); ++q) {
    const std::size_t i = run.queries[q];
    run.present[i] = kept[q];
    if (!kept[q]) {
      run.position[i].setConstant(std::numeric_limits<double>::quiet_NaN());
      continue;
    }
    const Eigen::Vector3d d = run.ray(i), m = moved[q], nq = moved_normals[q];
    const double along = nq.dot(d);
    const double t = std::abs(along) > 0.2 * d.norm() ? nq.dot(m) / along : m.z();
    run.position[i] = t * d;
    if constexpr (pcl::traits::has_normal_v<PointOutT>)
      run.normal[i] = nq;
    if (!(t > 0.0) || free_space.violates(run.position[i])) {
      run.position[i] = run.measured(i);
      ++report_.free_space_reverted;
    }
  }
}

template <typename PointInT, typename PointOutT>
void GeometricCloudRepair<PointInT, PointOutT>::fillDepthHoles(detail::DepthRun& run)
{
  // The denoised depths, when denoised first; in Complete mode the image as it is (no copy).
  DepthImage denoised;
  if (mode_ != Mode::Complete) {
    denoised.width = run.image.width;
    denoised.height = run.image.height;
    denoised.camera = run.image.camera;
    denoised.valid = run.present;
    denoised.depth.resize(run.n);
    const long long pixels = static_cast<long long>(run.n);
#pragma omp parallel for schedule(static)
    for (long long k = 0; k < pixels; ++k) {
      const std::size_t i = static_cast<std::size_t>(k);
      denoised.depth[i] = run.present[i] ? run.position[i].z() : std::numeric_limits<double>::quiet_NaN();
    }
  }
  const DepthImage& source = mode_ != Mode::Complete ? denoised : run.image;
  OrganizedFillParameters fill = organized_fill_;
  if (completion_.max_hole_diameter > 0.0)
    fill.max_hole_diameter = completion_.max_hole_diameter;
  std::vector<Eigen::Vector3d> added;
  const auto fill_start = std::chrono::steady_clock::now();
  fillOrganizedHoles(source, report_.depth_noise, fill, run.filled, added, report_.organized_fill);
  report_.completion.seconds_fill = std::chrono::duration<double>(std::chrono::steady_clock::now() - fill_start).count();
  for (std::size_t k = 0; k < run.filled.size(); ++k) {
    run.position[run.filled[k]] = added[k];
    run.present[run.filled[k]] = 1;
  }
  if constexpr (pcl::traits::has_normal_v<PointOutT>)
    for (const std::size_t i : run.filled)
      run.normal[i] = run.gridNormal(i);
  report_.points_added = run.filled.size();
  report_.completion.points_added = run.filled.size();
  report_.completion.holes_filled = report_.organized_fill.holes_filled;
}

template <typename PointInT, typename PointOutT>
void GeometricCloudRepair<PointInT, PointOutT>::writeDepthOutput(const detail::DepthRun& run,
                                                                     const Eigen::Matrix3d& R, const Eigen::Vector3d& o,
                                                                     PointCloudOut& output)
{
  const PointCloudIn& input = *input_;
  const std::size_t n = run.n;
  // The output: the input's grid; removed and unmeasured pixels NaN, filled ones placed.
  std::vector<char> is_filled(n, 0);
  for (const std::size_t i : run.filled)
    is_filled[i] = 1;
  const auto header = output.header;
  output.clear();
  output.header = header;
  output.sensor_origin_ = input.sensor_origin_;
  output.sensor_orientation_ = input.sensor_orientation_;
  output.resize(run.W, run.H);
  const float fnan = std::numeric_limits<float>::quiet_NaN();
  // Every pixel written in parallel (each its own output point), in fixed blocks of pixels whose
  // moved points' displacements are summed in pixel order and the blocks added in order after: the
  // same sum whatever the thread count. The index lists after, in order.
  constexpr std::size_t block = 4096;
  const long long blocks = static_cast<long long>((n + block - 1) / block);
  std::vector<double> block_sum(static_cast<std::size_t>(blocks), 0.0);
  const int threads = parameters_.num_threads > 0 ? parameters_.num_threads : omp_get_max_threads();
#pragma omp parallel for schedule(static) num_threads(threads)
  for (long long b = 0; b < blocks; ++b) {
    double sum = 0.0;
    for (std::size_t i = std::size_t(b) * block; i < std::min(n, std::size_t(b + 1) * block); ++i) {
      PointOutT& out = output[i];
      pcl::copyPoint(input[i], out);
      if (!run.present[i]) {
        // No point here: NaN, unless the input marked it "no return" as some drivers do, with
        // (0, 0, 0) (isReturn): that stays as written.
        if (input[i].x == 0.0f && input[i].y == 0.0f && input[i].z == 0.0f)
          continue;
        out.x = out.y = out.z = fnan;
        if constexpr (pcl::traits::has_normal_v<PointOutT>)
          out.normal_x = out.normal_y = out.normal_z = fnan;
        continue;
      }
      if (!is_filled[i] && mode_ == Mode::Complete && run.image.valid[i])
        continue;  // Complete: the measured points as they are
      if constexpr (pcl::traits::has_normal_v<PointOutT>)
        place(out, R * run.position[i] + o, R * run.normal[i]);
      else
        place(out, R * run.position[i] + o, Eigen::Vector3d::Zero());
      if (!is_filled[i])
        sum += (run.position[i] - run.measured(i)).norm();
    }
    block_sum[std::size_t(b)] = sum;
  }
  double displacement = 0.0;
  for (const double sum : block_sum)
    displacement += sum;
  std::size_t moved_count = 0;
  kept_indices_.reserve(run.queries.size());
  for (std::size_t i = 0; i < n; ++i) {
    if (!run.present[i])
      continue;
    if (is_filled[i]) {
      added_sources_.push_back(static_cast<pcl::index_t>(i));
      continue;
    }
    kept_indices_.push_back(static_cast<pcl::index_t>(i));
    moved_count += mode_ == Mode::Complete && run.image.valid[i] ? 0 : 1;
  }
  report_.output_points = kept_indices_.size();
  report_.mean_displacement = moved_count ? displacement / static_cast<double>(moved_count) : 0.0;
  report_.normals_computed = pcl::traits::has_normal_v<PointOutT>;
  output.is_dense = kept_indices_.size() + added_sources_.size() == n;
}

}  // namespace patchdict
}  // namespace pcl
