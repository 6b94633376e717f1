// SparsePatchCloudInpainter<PointInT, PointOutT> (see sparse_patch_cloud_inpainter.h): the typed
// shell around detail::denoiseCloud — point fields in and out, the search, organisation.
#pragma once

#include <pcl_patchdict/core/error.h>
#include <pcl_patchdict/cloud/gross_outliers.h>
#include <pcl_patchdict/cloud/sparse_patch_cloud_inpainter.h>

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
  added_sources_.clear();
  const PointCloudIn& input = *input_;
  const auto start = std::chrono::steady_clock::now();

  std::vector<Eigen::Vector3d> points(input.size());
  for (std::size_t i = 0; i < input.size(); ++i) {
    const PointInT& p = input[i];
    points[i] = Eigen::Vector3d(p.x, p.y, p.z);
    if (!points[i].allFinite())
      points[i].setConstant(std::numeric_limits<double>::quiet_NaN());
  }
  report_.gross_outliers = removeGrossOutliers(points);
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

  if (identity && input.height > 1 && keep_organized_) {
    // The grid is a pinhole image in the cloud's own frame (as grabbers write it), or else in the
    // frame of its sensor pose (sensor_origin_, sensor_orientation_).
    const Eigen::Matrix3d pose_R = input.sensor_orientation_.template cast<double>().normalized().toRotationMatrix();
    const Eigen::Vector3d pose_o = input.sensor_origin_.template head<3>().template cast<double>();
    for (int frame = 0; frame < 2; ++frame) {
      const Eigen::Matrix3d R = frame == 0 ? Eigen::Matrix3d::Identity() : pose_R;
      const Eigen::Vector3d o = frame == 0 ? Eigen::Vector3d::Zero() : pose_o;
      if (frame == 1 && R.isIdentity(1e-12) && o.isZero(0.0))
        break;
      std::vector<Eigen::Vector3d> local(points.size()), local_normals(normals.size());
      for (std::size_t i = 0; i < points.size(); ++i)
        local[i] = R.transpose() * (points[i] - o);
      for (std::size_t i = 0; i < normals.size(); ++i)
        local_normals[i] = R.transpose() * normals[i];
      const DepthImage image = makeDepthImage(local, input.width, input.height);
      if (image.camera.valid) {
        processDepthImage(local, local_normals, image, R, o, output);
        return;
      }
    }
  }

  KdTreePtr tree = tree_;
  if (!tree)
    tree.reset(new pcl::search::KdTree<PointInT>(true));
  // Exact copies of a position carry nothing new and make the spacing 0: the first of each is
  // processed, the others follow it.
  const std::vector<std::size_t> first = firstCopies(points);
  std::vector<std::size_t> run_queries, slot(queries.size());
  {
    std::vector<std::size_t> slot_of(points.size(), std::numeric_limits<std::size_t>::max());
    for (std::size_t q = 0; q < queries.size(); ++q) {
      const std::size_t rep = first[queries[q]];
      if (slot_of[rep] == std::numeric_limits<std::size_t>::max()) {
        slot_of[rep] = run_queries.size();
        run_queries.push_back(rep);
      }
      slot[q] = slot_of[rep];
    }
    for (std::size_t i = 0; i < points.size(); ++i)
      if (first[i] != i) {
        points[i].setConstant(std::numeric_limits<double>::quiet_NaN());
        ++report_.duplicate_points;
      }
  }
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
  for (const std::size_t q : run_queries)
    finite += points[q].allFinite() ? 1 : 0;
  if (finite < 100)
    throw Error("the cloud has " + std::to_string(finite) + " distinct finite points; denoising needs at least 100");
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
  // 2.5-D clouds (aerial LiDAR, terrain, facades) are completed as height fields over their plane.
  Eigen::Vector3d up = Eigen::Vector3d::UnitZ();
  bool height_field = false;
  if (completing && height_field_ != HeightField::Never) {
    std::vector<Eigen::Vector3d> sample;
    for (const std::size_t q : run_queries)
      if (points[q].allFinite())
        sample.push_back(points[q]);
    height_field = isHeightFieldCloud(sample, &up) || height_field_ == HeightField::Always;
  }
  report_.height_field_used = height_field;
  if (height_field && mode_ == Mode::Complete) {  // the fill fits its own rims: no patches needed
    kept.assign(run_queries.size(), 0);
    moved.assign(run_queries.size(), Eigen::Vector3d::Zero());
    moved_normals.assign(run_queries.size(), up);
    for (std::size_t q = 0; q < run_queries.size(); ++q) {
      kept[q] = points[run_queries[q]].allFinite();
      moved[q] = points[run_queries[q]];
    }
    report_.output_points = static_cast<std::size_t>(std::count(kept.begin(), kept.end(), 1));
  } else {
    detail::denoiseCloud(points, normals, run_queries, knn, radius, parameters_,
                         pcl::traits::has_normal_v<PointOutT> || completing, use_viewpoint ? &viewpoint : nullptr, kept,
                         moved, moved_normals, report_);
  }
  report_.input_points = queries.size();
  std::vector<Eigen::Vector3d> added, added_normals;
  std::vector<std::size_t> added_source;
  added_sources_.clear();
  if (completing) {
    std::vector<Eigen::Vector3d> surface, surface_normals;
    std::vector<std::size_t> owner;
    for (std::size_t q = 0; q < run_queries.size(); ++q)
      if (kept[q]) {
        surface.push_back(moved[q]);
        surface_normals.push_back(moved_normals[q]);
        owner.push_back(run_queries[q]);
      }
    if (height_field) {
      HeightFieldFillParameters fill = height_field_fill_;
      if (height_field_ == HeightField::Auto)
        fill.up = up;
      if (completion_.max_hole_diameter > 0.0)
        fill.max_hole_diameter = completion_.max_hole_diameter;
      fillHeightFieldHoles(surface, fill, added, added_source, report_.height_field);
      added_normals.assign(added.size(), report_.height_field.up);
      report_.completion.points_added = added.size();
      report_.completion.holes_filled = report_.height_field.holes_filled;
      report_.completion.seconds_fill = report_.height_field.seconds;
    } else {
      CloudCompletionParameters completion = completion_;
      completion.num_threads = parameters_.num_threads;
      completeCloudHoles(surface, surface_normals, report_.mean_spacing, completion, added, added_normals, added_source,
                         report_.completion);
    }
    if (has_viewpoint_ && !added.empty()) {  // a given viewpoint: no new point where it saw through
      const double spacing = report_.mean_spacing > 0.0 ? report_.mean_spacing : report_.height_field.spacing;
      const ViewpointFreeSpaceTest free_space(surface, viewpoint_, spacing);
      std::size_t k = 0;
      for (std::size_t j = 0; j < added.size(); ++j) {
        if (free_space.violates(added[j])) {
          ++report_.free_space_dropped;
          continue;
        }
        added[k] = added[j];
        added_normals[k] = added_normals[j];
        added_source[k++] = added_source[j];
      }
      added.resize(k);
      added_normals.resize(k);
      added_source.resize(k);
    }
    report_.points_added = added.size();
    for (std::size_t& source : added_source)
      source = owner[source];
  }
  if (run_queries.size() != queries.size()) {  // copies follow their first
    std::vector<char> all_kept(queries.size());
    std::vector<Eigen::Vector3d> all_moved(queries.size()), all_normals(queries.size());
    for (std::size_t q = 0; q < queries.size(); ++q) {
      all_kept[q] = kept[slot[q]];
      all_moved[q] = moved[slot[q]];
      all_normals[q] = moved_normals[slot[q]];
    }
    report_.output_points = static_cast<std::size_t>(std::count(all_kept.begin(), all_kept.end(), 1));
    kept.swap(all_kept);
    moved.swap(all_moved);
    moved_normals.swap(all_normals);
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
    if (keep_input && points[first[queries[q]]].allFinite())
      return;
    if (!kept[q] || keep_input) {  // removed, or no measurement (NaN, a gross outlier)
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

namespace pcl {
namespace patchdict {

template <typename PointInT, typename PointOutT>
void SparsePatchCloudInpainter<PointInT, PointOutT>::processDepthImage(const std::vector<Eigen::Vector3d>& points,
                                                                      const std::vector<Eigen::Vector3d>& normals,
                                                                      const DepthImage& image, const Eigen::Matrix3d& R,
                                                                      const Eigen::Vector3d& o, PointCloudOut& output)
{
  const PointCloudIn& input = *input_;
  const std::size_t W = image.width, H = image.height, n = W * H;
  const PinholeCamera& camera = image.camera;
  report_.depth_image = true;
  report_.camera = camera;
  report_.off_ray_points = camera.off_ray;
  report_.input_points = n;
  report_.nonfinite_points = n - image.measured();  // NaN pixels and off-ray points
  const auto start = std::chrono::steady_clock::now();
  report_.depth_noise = estimateDepthNoise(image);
  report_.seconds_noise = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  const double nan = std::numeric_limits<double>::quiet_NaN();
  // Off-ray points are no measurements: from here on, a pixel is its depth image's.
  std::vector<Eigen::Vector3d> measured(n, Eigen::Vector3d::Constant(nan));
  std::vector<std::size_t> queries;
  for (std::size_t i = 0; i < n; ++i)
    if (image.valid[i]) {
      measured[i] = points[i];
      queries.push_back(i);
    }
  std::vector<Eigen::Vector3d> position(measured), normal(n, Eigen::Vector3d::Zero());
  std::vector<char> present(image.valid);
  const auto ray = [&](std::size_t i) { return camera.pointAt(double(i % W), double(i / W), 1.0); };
  // Normals from the grid: central differences of the present neighbours, facing the camera.
  const auto gridNormal = [&](std::size_t i) {
    const std::size_t c = i % W, r = i / W;
    const auto at = [&](std::size_t cc, std::size_t rr) { return present[rr * W + cc] ? position[rr * W + cc] : position[i]; };
    const Eigen::Vector3d du = at(std::min(W - 1, c + 1), r) - at(c ? c - 1 : 0, r);
    const Eigen::Vector3d dv = at(c, std::min(H - 1, r + 1)) - at(c, r ? r - 1 : 0);
    Eigen::Vector3d nrm = du.cross(dv);
    nrm = nrm.norm() > 0.0 ? nrm.normalized() : Eigen::Vector3d(-ray(i).normalized());
    return nrm.dot(position[i]) > 0.0 ? Eigen::Vector3d(-nrm) : nrm;
  };
  // The sensor's own noise law, unless the caller fixed σ or h for the patches: image-space denoising.
  const bool in_image = depth_image_denoising_ && report_.depth_noise.coefficient > 0.0 &&
                        parameters_.noise_sigma == 0.0 && parameters_.bandwidth == 0.0;
  if (mode_ != Mode::Complete && in_image) {
    if (queries.size() < 100)
      throw Error("the cloud has " + std::to_string(queries.size()) + " measured pixels; denoising needs at least 100");
    std::vector<double> depth;
    const auto fit_start = std::chrono::steady_clock::now();
    DepthDenoisingParameters denoising = depth_denoising_;
    if (denoising.num_threads == 0)
      denoising.num_threads = parameters_.num_threads;
    denoiseDepthImage(image, report_.depth_noise, denoising, depth, report_.depth_denoising);
    report_.seconds_fit = std::chrono::duration<double>(std::chrono::steady_clock::now() - fit_start).count();
    report_.depth_denoised_in_image = true;
    const FreeSpaceTest free_space(image);
    for (const std::size_t i : queries) {
      position[i] = camera.pointAt(double(i % W), double(i / W), depth[i]);
      if (!position[i].allFinite() || free_space.violates(position[i])) {
        position[i] = measured[i];
        ++report_.free_space_reverted;
      }
    }
    for (const std::size_t i : queries)
      normal[i] = gridNormal(i);
    std::vector<double> depths;
    for (const std::size_t i : queries)
      depths.push_back(image.depth[i]);
    std::nth_element(depths.begin(), depths.begin() + static_cast<std::ptrdiff_t>(depths.size() / 2), depths.end());
    const double typical = depths[depths.size() / 2];
    report_.noise_sigma = report_.depth_noise.sigma(typical);  // at the median depth
    report_.mean_spacing = camera.pixelSpacing(typical);
    report_.bandwidth = depthDenoisingRadius(camera, depth_denoising_, typical) * report_.mean_spacing;
    report_.input_points = n;
    report_.nonfinite_points = n - queries.size();
  } else if (mode_ != Mode::Complete) {
    if (queries.size() < 100)
      throw Error("the cloud has " + std::to_string(queries.size()) + " measured pixels; denoising needs at least 100");
    auto searched = std::make_shared<PointCloudIn>(input);
    for (std::size_t i = 0; i < n; ++i) {
      PointInT& p = (*searched)[i];
      p.x = p.y = p.z = std::numeric_limits<float>::quiet_NaN();
      if (image.valid[i])
        p.getVector3fMap() = measured[i].cast<float>();
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
    for (const std::size_t i : queries) {
      scales.sigma.push_back(report_.depth_noise.sigma(image.depth[i]));
      scales.spacing.push_back(camera.pixelSpacing(image.depth[i]));
    }
    const bool law = report_.depth_noise.coefficient > 0.0 && parameters_.noise_sigma == 0.0;
    std::vector<char> kept;
    std::vector<Eigen::Vector3d> moved, moved_normals;
    const Eigen::Vector3d origin = Eigen::Vector3d::Zero();  // the fitted camera's centre
    detail::denoiseCloud(measured, normals, queries, knn, radius, parameters_, true, &origin, kept, moved, moved_normals,
                         report_, law ? &scales : nullptr);
    report_.input_points = n;  // the grid's, not only its measured pixels
    report_.nonfinite_points = n - queries.size();
    // Each point stays on its pixel's ray, where the ray meets its patch's tangent plane; a point the
    // sensor would have seen through stays as measured.
    const FreeSpaceTest free_space(image);
    for (std::size_t q = 0; q < queries.size(); ++q) {
      const std::size_t i = queries[q];
      present[i] = kept[q];
      if (!kept[q]) {
        position[i].setConstant(nan);
        continue;
      }
      const Eigen::Vector3d d = ray(i), m = moved[q], nq = moved_normals[q];
      const double along = nq.dot(d);
      const double t = std::abs(along) > 0.2 * d.norm() ? nq.dot(m) / along : m.z();
      position[i] = t * d;
      normal[i] = nq;
      if (!(t > 0.0) || free_space.violates(position[i])) {
        position[i] = measured[i];
        ++report_.free_space_reverted;
      }
    }
  }
  std::vector<std::size_t> filled;
  if (mode_ != Mode::Denoise) {
    DepthImage source = image;  // the denoised depths, when denoised first
    for (std::size_t i = 0; i < n; ++i) {
      source.valid[i] = present[i];
      source.depth[i] = present[i] ? position[i].z() : nan;
    }
    OrganizedFillParameters fill = organized_fill_;
    if (completion_.max_hole_diameter > 0.0)
      fill.max_hole_diameter = completion_.max_hole_diameter;
    std::vector<Eigen::Vector3d> added;
    const auto fill_start = std::chrono::steady_clock::now();
    fillOrganizedHoles(source, report_.depth_noise, fill, filled, added, report_.organized_fill);
    report_.completion.seconds_fill = std::chrono::duration<double>(std::chrono::steady_clock::now() - fill_start).count();
    for (std::size_t k = 0; k < filled.size(); ++k) {
      position[filled[k]] = added[k];
      present[filled[k]] = 1;
    }
    for (const std::size_t i : filled)
      normal[i] = gridNormal(i);
    report_.points_added = filled.size();
    report_.completion.points_added = filled.size();
    report_.completion.holes_filled = report_.organized_fill.holes_filled;
  }
  // The output: the input's grid; removed and unmeasured pixels NaN, filled ones placed.
  std::vector<char> is_filled(n, 0);
  for (const std::size_t i : filled)
    is_filled[i] = 1;
  const auto header = output.header;
  output.clear();
  output.header = header;
  output.sensor_origin_ = input.sensor_origin_;
  output.sensor_orientation_ = input.sensor_orientation_;
  output.resize(W, H);
  const float fnan = std::numeric_limits<float>::quiet_NaN();
  double displacement = 0.0;
  std::size_t moved_count = 0;
  for (std::size_t i = 0; i < n; ++i) {
    PointOutT& out = output[i];
    pcl::copyPoint(input[i], out);
    const bool input_kept = mode_ == Mode::Complete && image.valid[i];
    if (!present[i]) {
      out.x = out.y = out.z = fnan;
      if constexpr (pcl::traits::has_normal_v<PointOutT>)
        out.normal_x = out.normal_y = out.normal_z = fnan;
      continue;
    }
    if (!is_filled[i]) {
      kept_indices_.push_back(static_cast<pcl::index_t>(i));
      if (input_kept)
        continue;  // Complete: the measured points as they are
      displacement += (position[i] - measured[i]).norm();
      ++moved_count;
    } else {
      added_sources_.push_back(static_cast<pcl::index_t>(i));
    }
    const Eigen::Vector3d x = R * position[i] + o, nx = R * normal[i];
    out.x = static_cast<float>(x.x());
    out.y = static_cast<float>(x.y());
    out.z = static_cast<float>(x.z());
    if constexpr (pcl::traits::has_normal_v<PointOutT>) {
      out.normal_x = static_cast<float>(nx.x());
      out.normal_y = static_cast<float>(nx.y());
      out.normal_z = static_cast<float>(nx.z());
    }
  }
  report_.output_points = kept_indices_.size();
  report_.mean_displacement = moved_count ? displacement / static_cast<double>(moved_count) : 0.0;
  report_.normals_computed = pcl::traits::has_normal_v<PointOutT>;
  output.is_dense = kept_indices_.size() + added_sources_.size() == n;
}

}  // namespace patchdict
}  // namespace pcl
