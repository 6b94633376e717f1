// GeometricCloudRepair<PointInT, PointOutT> (see geometric_cloud_repair.h): the typed
// shell around detail::denoiseCloud — point fields in and out, the search, organisation; the
// organised paths in geometric_cloud_repair_depth_image.hpp (pinhole) and _range_image.hpp (spinning).
#pragma once

#include <pcl_patchdict/core/error.h>
#include <pcl_patchdict/cloud/gross_outliers.h>
#include <pcl_patchdict/cloud/geometric_cloud_repair.h>

#include <pcl/common/copy_point.h>
#include <pcl/point_traits.h>
#include <pcl/search/kdtree.h>

#include <chrono>
#include <cmath>
#include <limits>
#include <numeric>

#include <omp.h>

namespace pcl {
namespace patchdict {
namespace detail {

/// What performProcessing's stages hand each other.
struct CloudRun {
  std::vector<Eigen::Vector3d> points, normals;  // per input point (normals: when the type has them)
  std::vector<std::size_t> queries;               // the indices, in order
  bool identity = false;                          // the indices are the whole cloud, in order
  // Exact copies of a position: the first of each is processed (run_queries), the others follow it.
  std::vector<std::size_t> first, run_queries, slot;
  bool organised = false, completing = false, height_field = false;
  Eigen::Vector3d up = Eigen::Vector3d::UnitZ();
  std::vector<char> kept;  // per run query, then per query
  std::vector<Eigen::Vector3d> moved, moved_normals;
  std::vector<Eigen::Vector3d> added, added_normals;  // the Complete modes' new points
  std::vector<std::size_t> added_source;
};

/// A cloud's points and normals in one of its sensor's frames (sensorFrames): in the cloud's own
/// frame they are the run's, not a copy.
struct FramedPoints {
  FramedPoints(const CloudRun& run_, const SensorPose& frame_) : run(run_), frame(frame_), own(frame_.isIdentity())
  {
    if (own)
      return;
    moved_points = toSensorFrame(run.points, frame);
    moved_normals.resize(run.normals.size());
    for (std::size_t i = 0; i < run.normals.size(); ++i)
      moved_normals[i] = frame.R.transpose() * run.normals[i];
  }
  const std::vector<Eigen::Vector3d>& points() const { return own ? run.points : moved_points; }
  const std::vector<Eigen::Vector3d>& normals() const { return own ? run.normals : moved_normals; }
  const CloudRun& run;
  const SensorPose frame;
  const bool own;
  std::vector<Eigen::Vector3d> moved_points, moved_normals;
};

}  // namespace detail

template <typename PointInT, typename PointOutT>
void GeometricCloudRepair<PointInT, PointOutT>::performProcessing(PointCloudOut& output)
{
  report_ = CloudRepairReport{};
  kept_indices_.clear();
  added_sources_.clear();
  const PointCloudIn& input = *input_;
  const auto start = std::chrono::steady_clock::now();
  detail::CloudRun run;
  readInput(run);
  used_sensor_model_ = SensorModel{};
  if (run.identity && input.height > 1 && keep_organized_ &&
      (sensorModelGiven() ? processOnSensorModel(run, output)
                         : processAsDepthImage(run, output) || processAsRangeImage(run, output)))
    return;

  KdTreePtr tree = tree_;
  if (!tree)
    tree.reset(new pcl::search::KdTree<PointInT>(true));
  mergeCopies(run);
  const typename PointCloudIn::ConstPtr searched = searchedCloud(run);
  tree->setInputCloud(searched);
  const pcl::search::Search<PointInT>& search = *tree;
  const detail::KnnSearch knn = [&](std::size_t query, int k, pcl::Indices& found, std::vector<float>& squared) {
    search.nearestKSearch(input[query], k, found, squared);
  };
  const RadiusNeighbourSearch radius = [&](std::size_t query, double r, int max_nn, pcl::Indices& found,
                                           std::vector<float>& squared) {
    search.radiusSearch(input[query], r, found, squared, static_cast<unsigned int>(max_nn));
  };
  report_.seconds_search = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();

  denoiseRun(run, knn, radius);
  report_.input_points = run.queries.size();
  if (run.completing)
    completeRun(run);
  followCopies(run);
  writeOutput(run, output);
}

template <typename PointInT, typename PointOutT>
void GeometricCloudRepair<PointInT, PointOutT>::readInput(detail::CloudRun& run)
{
  const PointCloudIn& input = *input_;
  std::vector<Eigen::Vector3d>& points = run.points;
  points.resize(input.size());
  const long long count = static_cast<long long>(input.size());
#pragma omp parallel for schedule(static) num_threads(parameters_.num_threads > 0 ? parameters_.num_threads : omp_get_max_threads())
  for (long long k = 0; k < count; ++k) {
    const std::size_t i = static_cast<std::size_t>(k);
    const PointInT& p = input[i];
    points[i] = Eigen::Vector3d(p.x, p.y, p.z);
    if (!points[i].allFinite())
      points[i].setConstant(std::numeric_limits<double>::quiet_NaN());
  }
  // A whole organised frame on a given sensor model needs no such guard: a coordinate no sensor
  // measured (a depth of 1e30) is off its pixel's ray, or 1000 × off the frame's typical depth or
  // range, and no measurement there either (depthImageOnCamera, makeRangeImage).
  const bool on_model = sensorModelGiven() && keep_organized_ && input.height > 1 && indices_->size() == input.size();
  if (!on_model)
    report_.gross_outliers = removeGrossOutliers(points);
  if constexpr (pcl::traits::has_normal_v<PointInT>) {
    run.normals.resize(input.size(), Eigen::Vector3d::Zero());
    for (std::size_t i = 0; i < input.size(); ++i) {
      const Eigen::Vector3d n(input[i].normal_x, input[i].normal_y, input[i].normal_z);
      if (n.allFinite() && n.norm() > 0.0)
        run.normals[i] = n.normalized();
    }
  }
  run.queries.reserve(indices_->size());
  run.identity = indices_->size() == input.size();
  for (std::size_t q = 0; q < indices_->size(); ++q) {
    const auto index = (*indices_)[q];
    if (index < 0 || static_cast<std::size_t>(index) >= input.size())
      throw Error("index " + std::to_string(index) + " is outside the cloud of " + std::to_string(input.size()) +
                  " points");
    run.identity = run.identity && static_cast<std::size_t>(index) == q;
    run.queries.push_back(static_cast<std::size_t>(index));
  }
}

template <typename PointInT, typename PointOutT>
bool GeometricCloudRepair<PointInT, PointOutT>::processAsDepthImage(const detail::CloudRun& run,
                                                                        PointCloudOut& output)
{
  const PointCloudIn& input = *input_;
  // The grid is a pinhole image in the cloud's own frame (as grabbers write it), or else in the
  // frame of its sensor pose (sensor_origin_, sensor_orientation_).
  for (const SensorPose& frame : sensorFrames(sensorPoseOf(input), SensorModel::Kind::Pinhole)) {
    const detail::FramedPoints local(run, frame);
    const DepthImage image = makeDepthImage(local.points(), input.width, input.height);
    if (image.camera.valid) {
      processDepthImage(local.points(), local.normals(), image, frame.R, frame.o, output);
      return true;
    }
  }
  return false;
}

template <typename PointInT, typename PointOutT>
void GeometricCloudRepair<PointInT, PointOutT>::mergeCopies(detail::CloudRun& run)
{
  // Exact copies of a position carry nothing new and make the spacing 0: the first of each is
  // processed, the others follow it.
  run.first = firstCopies(run.points);
  run.slot.resize(run.queries.size());
  std::vector<std::size_t> slot_of(run.points.size(), std::numeric_limits<std::size_t>::max());
  for (std::size_t q = 0; q < run.queries.size(); ++q) {
    const std::size_t rep = run.first[run.queries[q]];
    if (slot_of[rep] == std::numeric_limits<std::size_t>::max()) {
      slot_of[rep] = run.run_queries.size();
      run.run_queries.push_back(rep);
    }
    run.slot[q] = slot_of[rep];
  }
  for (std::size_t i = 0; i < run.points.size(); ++i)
    if (run.first[i] != i) {
      run.points[i].setConstant(std::numeric_limits<double>::quiet_NaN());
      ++report_.duplicate_points;
    }
}

template <typename PointInT, typename PointOutT>
typename pcl::PointCloud<PointInT>::ConstPtr
GeometricCloudRepair<PointInT, PointOutT>::searchedCloud(const detail::CloudRun& run) const
{
  const PointCloudIn& input = *input_;
  const std::vector<Eigen::Vector3d>& points = run.points;
  // A cloud with NaN points must say so, or FLANN indexes them; gross outliers and copies are NaN.
  bool dense = true, changed = false;
  for (std::size_t i = 0; i < points.size(); ++i) {
    dense = dense && points[i].allFinite();
    changed = changed || (!points[i].allFinite() && std::isfinite(input[i].x) && std::isfinite(input[i].y) &&
                          std::isfinite(input[i].z));
  }
  typename PointCloudIn::ConstPtr searched = input_;
  if ((!dense && input.is_dense) || changed) {
    auto copy = std::make_shared<PointCloudIn>(input);
    copy->is_dense = false;
    for (std::size_t i = 0; i < points.size(); ++i)
      if (!points[i].allFinite())
        (*copy)[i].x = (*copy)[i].y = (*copy)[i].z = std::numeric_limits<float>::quiet_NaN();
    searched = copy;
  }
  std::size_t finite = 0;
  for (const std::size_t q : run.run_queries)
    finite += points[q].allFinite() ? 1 : 0;
  if (finite < 100)
    throw Error("the cloud has " + std::to_string(finite) + " distinct finite points; denoising needs at least 100");
  return searched;
}

template <typename PointInT, typename PointOutT>
void GeometricCloudRepair<PointInT, PointOutT>::denoiseRun(detail::CloudRun& run, const detail::KnnSearch& knn,
                                                               const RadiusNeighbourSearch& radius)
{
  const PointCloudIn& input = *input_;
  Eigen::Vector3d viewpoint = viewpoint_;
  run.organised = input.height > 1;
  bool use_viewpoint = has_viewpoint_;
  if (!use_viewpoint && run.organised) {  // depth sensors: the sensor origin, even at (0, 0, 0)
    viewpoint = input.sensor_origin_.template head<3>().template cast<double>();
    use_viewpoint = true;
  }
  run.completing = mode_ != Mode::Denoise;
  // 2.5-D clouds (aerial LiDAR, terrain, facades) are completed as height fields over their plane.
  if (run.completing && height_field_ != HeightField::Never) {
    std::vector<Eigen::Vector3d> sample;
    for (const std::size_t q : run.run_queries)
      if (run.points[q].allFinite())
        sample.push_back(run.points[q]);
    run.height_field = isHeightFieldCloud(sample, &run.up) || height_field_ == HeightField::Always;
  }
  report_.height_field_used = run.height_field;
  if (run.height_field && mode_ == Mode::Complete) {  // the fill fits its own rims: no patches needed
    run.kept.assign(run.run_queries.size(), 0);
    run.moved.assign(run.run_queries.size(), Eigen::Vector3d::Zero());
    run.moved_normals.assign(run.run_queries.size(), run.up);
    for (std::size_t q = 0; q < run.run_queries.size(); ++q) {
      run.kept[q] = run.points[run.run_queries[q]].allFinite();
      run.moved[q] = run.points[run.run_queries[q]];
    }
    report_.output_points = static_cast<std::size_t>(std::count(run.kept.begin(), run.kept.end(), 1));
  } else {
    detail::denoiseCloud(run.points, run.normals, run.run_queries, knn, radius, parameters_,
                         pcl::traits::has_normal_v<PointOutT> || run.completing, use_viewpoint ? &viewpoint : nullptr,
                         run.kept, run.moved, run.moved_normals, report_);
  }
}

template <typename PointInT, typename PointOutT>
void GeometricCloudRepair<PointInT, PointOutT>::completeRun(detail::CloudRun& run)
{
  std::vector<Eigen::Vector3d> surface, surface_normals;
  std::vector<std::size_t> owner;
  for (std::size_t q = 0; q < run.run_queries.size(); ++q)
    if (run.kept[q]) {
      surface.push_back(run.moved[q]);
      surface_normals.push_back(run.moved_normals[q]);
      owner.push_back(run.run_queries[q]);
    }
  if (run.height_field) {
    HeightFieldFillParameters fill = height_field_fill_;
    if (height_field_ == HeightField::Auto)
      fill.up = run.up;
    if (completion_.max_hole_diameter > 0.0)
      fill.max_hole_diameter = completion_.max_hole_diameter;
    fillHeightFieldHoles(surface, fill, run.added, run.added_source, report_.height_field);
    run.added_normals.assign(run.added.size(), report_.height_field.up);
    report_.completion.points_added = run.added.size();
    report_.completion.holes_filled = report_.height_field.holes_filled;
    report_.completion.seconds_fill = report_.height_field.seconds;
  } else {
    CloudCompletionParameters completion = completion_;
    completion.num_threads = parameters_.num_threads;
    completeCloudHoles(surface, surface_normals, report_.mean_spacing, completion, run.added, run.added_normals,
                       run.added_source, report_.completion);
  }
  if (has_viewpoint_ && !run.added.empty()) {  // a given viewpoint: no new point where it saw through
    const double spacing = report_.mean_spacing > 0.0 ? report_.mean_spacing : report_.height_field.spacing;
    const ViewpointFreeSpaceTest free_space(surface, viewpoint_, spacing);
    std::size_t k = 0;
    for (std::size_t j = 0; j < run.added.size(); ++j) {
      if (free_space.violates(run.added[j])) {
        ++report_.free_space_dropped;
        continue;
      }
      run.added[k] = run.added[j];
      run.added_normals[k] = run.added_normals[j];
      run.added_source[k++] = run.added_source[j];
    }
    run.added.resize(k);
    run.added_normals.resize(k);
    run.added_source.resize(k);
  }
  report_.points_added = run.added.size();
  for (std::size_t& source : run.added_source)
    source = owner[source];
}

template <typename PointInT, typename PointOutT>
void GeometricCloudRepair<PointInT, PointOutT>::followCopies(detail::CloudRun& run)
{
  if (run.run_queries.size() == run.queries.size())
    return;
  const std::size_t nq = run.queries.size();
  std::vector<char> all_kept(nq);
  std::vector<Eigen::Vector3d> all_moved(nq), all_normals(nq);
  for (std::size_t q = 0; q < nq; ++q) {
    all_kept[q] = run.kept[run.slot[q]];
    all_moved[q] = run.moved[run.slot[q]];
    all_normals[q] = run.moved_normals[run.slot[q]];
  }
  report_.output_points = static_cast<std::size_t>(std::count(all_kept.begin(), all_kept.end(), 1));
  run.kept.swap(all_kept);
  run.moved.swap(all_moved);
  run.moved_normals.swap(all_normals);
}

template <typename PointInT, typename PointOutT>
void GeometricCloudRepair<PointInT, PointOutT>::writeOutput(const detail::CloudRun& run, PointCloudOut& output)
{
  const PointCloudIn& input = *input_;
  const std::vector<std::size_t>& queries = run.queries;
  // Complete: the output is the input, unchanged and whole (outliers and NaN points too), followed
  // by the new points; outliers were only kept out of the surface the holes were filled from, and
  // the fill came from the patches' surface so that noise in the rim does not go into it.
  const bool keep_input = mode_ == Mode::Complete;
  if (keep_input) {
    report_.mean_displacement = 0.0;
    report_.output_points = queries.size();
  }
  report_.normals_computed = pcl::traits::has_normal_v<PointOutT>;

  kept_indices_.clear();
  for (std::size_t q = 0; q < queries.size(); ++q)
    if (run.kept[q] || keep_input)
      kept_indices_.push_back(static_cast<pcl::index_t>(queries[q]));
  const bool keep_grid = run.organised && keep_organized_ && run.identity && !run.completing;
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const auto fill = [&](std::size_t q, PointOutT& out) {
    pcl::copyPoint(input[queries[q]], out);
    if (keep_input && run.points[run.first[queries[q]]].allFinite())
      return;
    if (!run.kept[q] || keep_input) {  // removed, or no measurement (NaN, a gross outlier)
      out.x = out.y = out.z = nan;
      if constexpr (pcl::traits::has_normal_v<PointOutT>)
        out.normal_x = out.normal_y = out.normal_z = nan;
      return;
    }
    place(out, run.moved[q], run.moved_normals[q]);
  };
  const auto header = output.header;
  output.clear();
  output.header = header;
  output.sensor_origin_ = input.sensor_origin_;
  output.sensor_orientation_ = input.sensor_orientation_;
  if (keep_grid) {
    output.resize(input.width, input.height);
    for (std::size_t q = 0; q < queries.size(); ++q)
      fill(q, output[q]);
    output.is_dense = report_.output_points == input.size();
    return;
  }
  output.reserve(report_.output_points + run.added.size());
  bool finite_only = true;
  for (std::size_t q = 0; q < queries.size(); ++q)
    if (run.kept[q] || keep_input) {
      PointOutT p;
      fill(q, p);
      finite_only = finite_only && std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z);
      output.push_back(p);
    }
  for (std::size_t k = 0; k < run.added.size(); ++k) {
    PointOutT p;
    pcl::copyPoint(input[run.added_source[k]], p);
    place(p, run.added[k], run.added_normals[k]);
    output.push_back(p);
    added_sources_.push_back(static_cast<pcl::index_t>(run.added_source[k]));
  }
  output.width = static_cast<std::uint32_t>(output.size());
  output.height = 1;
  output.is_dense = finite_only;
}

template <typename PointInT, typename PointOutT>
void GeometricCloudRepair<PointInT, PointOutT>::place(PointOutT& out, const Eigen::Vector3d& position,
                                                          const Eigen::Vector3d& normal)
{
  out.x = static_cast<float>(position.x());
  out.y = static_cast<float>(position.y());
  out.z = static_cast<float>(position.z());
  if constexpr (pcl::traits::has_normal_v<PointOutT>) {
    out.normal_x = static_cast<float>(normal.x());
    out.normal_y = static_cast<float>(normal.y());
    out.normal_z = static_cast<float>(normal.z());
  } else {
    (void)normal;
  }
}

}  // namespace patchdict
}  // namespace pcl

#include <pcl_patchdict/cloud/impl/geometric_cloud_repair_depth_image.hpp>
#include <pcl_patchdict/cloud/impl/geometric_cloud_repair_range_image.hpp>
