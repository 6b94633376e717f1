// detail::denoiseCloud's stages (private): the state they hand each other and the stages defined
// outside denoise_cloud.cpp (noise and bandwidth: denoise_cloud_bandwidth.cpp; normal orientation:
// denoise_cloud_normals.cpp).
#pragma once

#include <pcl_patchdict/cloud/local_quadric_projection.h>
#include <pcl_patchdict/cloud/geometric_cloud_repair.h>

#include <Eigen/Core>

#include <cstddef>
#include <vector>

namespace pcl {
namespace patchdict {
namespace denoise_detail {

/// The median of `values` (0 for none).
double median(std::vector<double> values);

// Every query at its own bandwidth h[j] (the depth-law path): the queries are grouped by h into bins
// of 1/32 octave and each bin is fitted at its geometric centre (within 1.1 % of every member's h).
// Deterministic: the bins and their members come in a fixed order.
void fitAtBandwidths(const std::vector<Eigen::Vector3d>& points, const std::vector<char>& usable,
                     const RadiusNeighbourSearch& radius, const std::vector<std::size_t>& queries,
                     const std::vector<double>& h, LocalQuadricParameters parameters, bool leave_one_out,
                     std::vector<LocalQuadricFit>& fits);

// Depth law: at h = factor × s_i the max_neighbours nearest lie within √(max/π) s_i on a surface
// facing the camera; the search stops at 1.5 times that (2h when less: the usual support), which
// keeps every one of them up to 64° of incidence and spares the search the ring it would discard.
LocalQuadricParameters capped(LocalQuadricParameters p, double factor, int max_neighbours);

/// What the stages of one denoising hand each other: the inputs, then what each stage found.
struct DenoisingRun {
  DenoisingRun(const std::vector<Eigen::Vector3d>& points_, const std::vector<std::size_t>& queries_,
               const detail::KnnSearch& knn_, const RadiusNeighbourSearch& radius_,
               const CloudRepairParameters& parameters_, const detail::PointScales* scales_,
               CloudRepairReport& report_)
      : points(points_), queries(queries_), knn(knn_), radius(radius_), parameters(parameters_), scales(scales_),
        report(report_)
  {
  }

  const std::vector<Eigen::Vector3d>& points;
  const std::vector<std::size_t>& queries;
  const detail::KnnSearch& knn;
  const RadiusNeighbourSearch& radius;
  const CloudRepairParameters& parameters;
  const detail::PointScales* scales;
  CloudRepairReport& report;
  int threads = 1;
  std::size_t nq = 0;
  // 1. pre-filter
  std::vector<char> usable;  // per point: finite, not an outlier
  std::vector<char> finite, passed;  // per query
  double s = 0.0;  // the mean spacing
  // 2. noise and bandwidth
  std::vector<std::size_t> kept_queries;  // query numbers of the points that passed
  std::vector<std::size_t> sample, sample_q;  // point indices, and their query numbers
  LocalQuadricParameters fit_parameters;
  double sigma = 0.0;
  double factor_used = 0.0;  // depth law: h_i = factor_used × s_i (0: parameters.bandwidth for all)
  std::vector<double> point_h, point_limit;  // per kept query (depth law)

  // With a depth law, σ_i and s_i are the point's own (σ_i: the given σ instead, when there is one).
  double sigmaOf(std::size_t q) const { return parameters.noise_sigma > 0.0 ? parameters.noise_sigma : scales->sigma[q]; }
  LocalQuadricParameters cappedAt(double factor) const { return capped(fit_parameters, factor, parameters.max_neighbours); }
};

/// 2. Noise level and bandwidth, over an evenly spaced sample of the kept points: the sample, σ,
/// the bandwidth (given, or by the risk estimate) and, with a depth law, every kept point's own.
void estimateNoiseAndBandwidth(DenoisingRun& run);

/// What the normals are oriented from, and into.
struct Orientation {
  const std::vector<Eigen::Vector3d>& points;
  const std::vector<Eigen::Vector3d>& normals;  // the input's
  const std::vector<std::size_t>& queries;
  const detail::KnnSearch& knn;
  const std::vector<char>& kept;
  const std::vector<Eigen::Vector3d>& positions;
  std::vector<Eigen::Vector3d>& out_normals;
  CloudRepairReport& report;
};

/// 4. Each kept point's normal oriented: towards its input normal or the viewpoint, and from its
/// neighbours where it has neither; else consistently by propagation over the kept points.
void orientNormals(Orientation& o, const Eigen::Vector3d* viewpoint, int threads);

}  // namespace denoise_detail
}  // namespace patchdict
}  // namespace pcl
