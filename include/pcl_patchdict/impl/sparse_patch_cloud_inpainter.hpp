// SparsePatchCloudInpainter<PointInT, PointOutT> (see sparse_patch_cloud_inpainter.h): the typed
// shell around detail::denoiseCloud — point fields in and out, the search, organisation.
#pragma once

#include <pcl_patchdict/error.h>
#include <pcl_patchdict/sparse_patch_cloud_inpainter.h>

#include <pcl/common/copy_point.h>
#include <pcl/point_traits.h>
#include <pcl/search/kdtree.h>

#include <chrono>
#include <cmath>
#include <limits>
#include <numeric>

namespace pcl {
namespace patchdict {

template <typename PointInT, typename PointOutT>
void SparsePatchCloudInpainter<PointInT, PointOutT>::performProcessing(PointCloudOut& output)
{
  report_ = CloudDenoisingReport{};
  kept_indices_.clear();
  const PointCloudIn& input = *input_;
  const auto start = std::chrono::steady_clock::now();

  std::vector<Eigen::Vector3d> points(input.size());
  for (std::size_t i = 0; i < input.size(); ++i) {
    const PointInT& p = input[i];
    points[i] = Eigen::Vector3d(p.x, p.y, p.z);
    if (!points[i].allFinite())
      points[i].setConstant(std::numeric_limits<double>::quiet_NaN());
  }
  std::vector<Eigen::Vector3d> normals;
  if constexpr (pcl::traits::has_normal_v<PointInT>) {
    normals.resize(input.size(), Eigen::Vector3d::Zero());
    for (std::size_t i = 0; i < input.size(); ++i) {
      const Eigen::Vector3d n(input[i].normal_x, input[i].normal_y, input[i].normal_z);
      if (n.allFinite() && n.norm() > 0.0)
        normals[i] = n.normalized();
    }
  }
  std::vector<std::size_t> queries;
  queries.reserve(indices_->size());
  bool identity = indices_->size() == input.size();
  for (std::size_t q = 0; q < indices_->size(); ++q) {
    const auto index = (*indices_)[q];
    if (index < 0 || static_cast<std::size_t>(index) >= input.size())
      throw Error("index " + std::to_string(index) + " is outside the cloud of " + std::to_string(input.size()) +
                  " points");
    identity = identity && static_cast<std::size_t>(index) == q;
    queries.push_back(static_cast<std::size_t>(index));
  }

  KdTreePtr tree = tree_;
  if (!tree)
    tree.reset(new pcl::search::KdTree<PointInT>(true));
  // A cloud with NaN points must say so, or FLANN indexes them.
  bool dense = true;
  for (const auto& p : points)
    dense = dense && p.allFinite();
  typename PointCloudIn::ConstPtr searched = input_;
  if (!dense && input.is_dense) {
    auto copy = std::make_shared<PointCloudIn>(input);
    copy->is_dense = false;
    searched = copy;
  }
  std::size_t finite = 0;
  for (const std::size_t q : queries)
    finite += (q < points.size() && points[q].allFinite()) ? 1 : 0;
  if (finite < 100)
    throw Error("the cloud has " + std::to_string(finite) + " finite points; denoising needs at least 100");
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

  Eigen::Vector3d viewpoint = viewpoint_;
  const bool organised = input.height > 1;
  bool use_viewpoint = has_viewpoint_;
  if (!use_viewpoint && organised) {  // depth sensors: the sensor origin, even at (0, 0, 0)
    viewpoint = input.sensor_origin_.template head<3>().template cast<double>();
    use_viewpoint = true;
  }
  std::vector<char> kept;
  std::vector<Eigen::Vector3d> moved, moved_normals;
  const bool completing = mode_ != Mode::Denoise;
  detail::denoiseCloud(points, normals, queries, knn, radius, parameters_,
                       pcl::traits::has_normal_v<PointOutT> || completing, use_viewpoint ? &viewpoint : nullptr, kept,
                       moved, moved_normals, report_);
  std::vector<Eigen::Vector3d> added, added_normals;
  std::vector<std::size_t> added_source;
  added_sources_.clear();
  if (completing) {
    std::vector<Eigen::Vector3d> surface, surface_normals;
    std::vector<std::size_t> owner;
    for (std::size_t q = 0; q < queries.size(); ++q)
      if (kept[q]) {
        surface.push_back(moved[q]);
        surface_normals.push_back(moved_normals[q]);
        owner.push_back(queries[q]);
      }
    CloudCompletionParameters completion = completion_;
    completion.num_threads = parameters_.num_threads;
    completeCloudHoles(surface, surface_normals, report_.mean_spacing, completion, added, added_normals, added_source,
                       report_.completion);
    report_.points_added = added.size();
    for (std::size_t& source : added_source)
      source = owner[source];
  }
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
    if (kept[q] || keep_input)
      kept_indices_.push_back(static_cast<pcl::index_t>(queries[q]));
  const bool keep_grid = organised && keep_organized_ && identity && !completing;
  const float nan = std::numeric_limits<float>::quiet_NaN();
  // Position (and normal, if the type has one) of an output point; its other fields are copied.
  const auto place = [](PointOutT& out, const Eigen::Vector3d& position, const Eigen::Vector3d& normal) {
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
  };
  const auto fill = [&](std::size_t q, PointOutT& out) {
    pcl::copyPoint(input[queries[q]], out);
    if (keep_input)
      return;
    if (!kept[q]) {
      out.x = out.y = out.z = nan;
      if constexpr (pcl::traits::has_normal_v<PointOutT>)
        out.normal_x = out.normal_y = out.normal_z = nan;
      return;
    }
    place(out, moved[q], moved_normals[q]);
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
  } else {
    output.reserve(report_.output_points + added.size());
    bool finite_only = true;
    for (std::size_t q = 0; q < queries.size(); ++q)
      if (kept[q] || keep_input) {
        PointOutT p;
        fill(q, p);
        finite_only = finite_only && std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z);
        output.push_back(p);
      }
    for (std::size_t k = 0; k < added.size(); ++k) {
      PointOutT p;
      pcl::copyPoint(input[added_source[k]], p);
      place(p, added[k], added_normals[k]);
      output.push_back(p);
      added_sources_.push_back(static_cast<pcl::index_t>(added_source[k]));
    }
    output.width = static_cast<std::uint32_t>(output.size());
    output.height = 1;
    output.is_dense = finite_only;
  }
}

}  // namespace patchdict
}  // namespace pcl
