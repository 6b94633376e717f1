// detail::denoiseCloud (see geometric_cloud_repair.h): the type-free core of
// GeometricCloudRepair — pre-filter, noise and bandwidth, the patches' fits, normal orientation.
#include "cloud/denoise_cloud_stages.h"

#include <pcl_patchdict/core/error.h>
#include <pcl_patchdict/cloud/geometric_cloud_repair.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>

#ifdef _OPENMP
#include <omp.h>
#endif

namespace pcl {
namespace patchdict {

namespace denoise_detail {

double median(std::vector<double> values)
{
  if (values.empty())
    return 0.0;
  const auto middle = values.begin() + static_cast<std::ptrdiff_t>(values.size() / 2);
  std::nth_element(values.begin(), middle, values.end());
  return *middle;
}

// Every query at its own bandwidth h[j] (the depth-law path): the queries are grouped by h into bins
// of 1/32 octave and each bin is fitted at its geometric centre (within 1.1 % of every member's h).
// Deterministic: the bins and their members come in a fixed order.
void fitAtBandwidths(const std::vector<Eigen::Vector3d>& points, const std::vector<char>& usable,
                     const RadiusNeighbourSearch& radius, const std::vector<std::size_t>& queries,
                     const std::vector<double>& h, LocalQuadricParameters parameters, bool leave_one_out,
                     std::vector<LocalQuadricFit>& fits)
{
  constexpr double kBinsPerOctave = 32.0;
  fits.assign(queries.size(), LocalQuadricFit{});
  std::vector<std::pair<long, std::size_t>> order(queries.size());
  for (std::size_t j = 0; j < queries.size(); ++j)
    order[j] = {static_cast<long>(std::floor(kBinsPerOctave * std::log2(h[j]))), j};
  std::sort(order.begin(), order.end());
  std::vector<std::size_t> members, member_queries;
  std::vector<LocalQuadricFit> bin_fits;
  for (std::size_t first = 0; first < order.size();) {
    std::size_t last = first;
    members.clear();
    member_queries.clear();
    while (last < order.size() && order[last].first == order[first].first) {
      members.push_back(order[last].second);
      member_queries.push_back(queries[order[last].second]);
      ++last;
    }
    parameters.bandwidth = std::exp2((static_cast<double>(order[first].first) + 0.5) / kBinsPerOctave);
    fitLocalQuadrics(points, usable, radius, member_queries, parameters, leave_one_out, bin_fits);
    for (std::size_t k = 0; k < members.size(); ++k)
      fits[members[k]] = bin_fits[k];
    first = last;
  }
}

// Depth law: at h = factor × s_i the max_neighbours nearest lie within √(max/π) s_i on a surface
// facing the camera; the search stops at 1.5 times that (2h when less: the usual support), which
// keeps every one of them up to 64° of incidence and spares the search the ring it would discard.
LocalQuadricParameters capped(LocalQuadricParameters p, double factor, int max_neighbours)
{
  const double cap = 1.5 * std::sqrt(static_cast<double>(max_neighbours) / 3.141592653589793) / factor;
  p.support_factor = std::clamp(cap, 1.0, p.support_factor);
  return p;
}

}  // namespace denoise_detail

namespace {

using namespace denoise_detail;

using Clock = std::chrono::steady_clock;
double secondsSince(Clock::time_point start) { return std::chrono::duration<double>(Clock::now() - start).count(); }

int threadCount(int requested)
{
#ifdef _OPENMP
  return requested > 0 ? requested : omp_get_max_threads();
#else
  (void)requested;
  return 1;
#endif
}

void checkParameters(const CloudRepairParameters& p)
{
  const auto bad = [](double x) { return !std::isfinite(x) || x < 0.0; };
  if (p.outlier_filter && (p.outlier_neighbours < 1 || p.outlier_neighbours > 1000 || bad(p.outlier_std)))
    throw Error("outlier filter: neighbours must be in [1, 1000] and the deviation multiplier finite and ≥ 0");
  if (bad(p.noise_sigma) || bad(p.bandwidth) || bad(p.residual_outlier_factor))
    throw Error("cloud denoising: noise sigma, bandwidth and outlier factor must be finite and ≥ 0");
  if (p.bandwidth == 0.0 && p.bandwidth_candidates.empty())
    throw Error("cloud denoising: an automatic bandwidth needs candidates");
  for (const double c : p.bandwidth_candidates)
    if (!(c > 0.0) || !std::isfinite(c) || c > 1000.0)
      throw Error("cloud denoising: bandwidth candidates must be in (0, 1000] spacings");
  if (p.noise_sample < 100)
    throw Error("cloud denoising: the noise sample must hold at least 100 points");
  if (p.min_neighbours < 6 || p.max_neighbours < p.min_neighbours || p.max_neighbours > 4096)
    throw Error("cloud denoising: neighbours must satisfy 6 ≤ min ≤ max ≤ 4096");
}

void checkScales(const std::vector<Eigen::Vector3d>& points, const std::vector<std::size_t>& queries,
                 const detail::PointScales& scales)
{
  const std::size_t nq = queries.size();
  if (scales.sigma.size() != nq || scales.spacing.size() != nq)
    throw Error("cloud denoising: the point scales need one sigma and one spacing per query");
  for (std::size_t q = 0; q < nq; ++q)
    if (queries[q] < points.size() && points[queries[q]].allFinite() &&
        (!(scales.sigma[q] > 0.0) || !std::isfinite(scales.sigma[q]) || !(scales.spacing[q] > 0.0) ||
         !std::isfinite(scales.spacing[q])))
      throw Error("cloud denoising: the point scales must be positive and finite at every finite query");
}

// 1. Pre-filter and spacing, from the same k nearest neighbours.

/// Mean distance of each finite query to its k nearest (in its own spacings with a depth law), and
/// its nearest distinct neighbour.
void neighbourDistances(const DenoisingRun& run, int k, std::vector<double>& mean_distance, std::vector<double>& nearest)
{
  const std::size_t nq = run.nq;
  // The spacing needs the first distinct neighbour: at least 8 are searched, so that stacked
  // duplicates (scanners repeat points) do not hide it.
  const int searched = std::max(k, 8);
  mean_distance.assign(nq, 0.0);
  nearest.assign(nq, 0.0);
#pragma omp parallel num_threads(run.threads)
  {
    pcl::Indices found;
    std::vector<float> squared;
#pragma omp for schedule(dynamic, 1024)
    for (std::ptrdiff_t s = 0; s < static_cast<std::ptrdiff_t>(nq); ++s) {
      const auto q = static_cast<std::size_t>(s);
      if (!run.finite[q])
        continue;
      run.knn(run.queries[q], searched + 1, found, squared);
      double sum = 0.0;
      int counted = 0;
      for (std::size_t j = 0; j < found.size(); ++j) {
        if (static_cast<std::size_t>(found[j]) == run.queries[q])
          continue;
        const double d = std::sqrt(static_cast<double>(squared[j]));
        if (nearest[q] == 0.0 && d > 0.0)
          nearest[q] = d;
        if (counted < k) {
          sum += d;
          ++counted;
        }
      }
      mean_distance[q] = counted ? sum / counted : 0.0;
      if (run.scales)  // in the point's own spacings: a far point of a depth image is no outlier for it
        mean_distance[q] /= run.scales->spacing[q];
    }
  }
}

void filterOutliers(DenoisingRun& run, const std::vector<double>& mean_distance)
{
  const std::size_t nq = run.nq;
  double mean = 0.0, square = 0.0;
  std::size_t count = 0;
  for (std::size_t q = 0; q < nq; ++q)
    if (run.finite[q]) {
      mean += mean_distance[q];
      square += mean_distance[q] * mean_distance[q];
      ++count;
    }
  mean /= static_cast<double>(std::max<std::size_t>(count, 1));
  const double deviation = std::sqrt(std::max(0.0, square / static_cast<double>(std::max<std::size_t>(count, 1)) - mean * mean));
  // Floor at 2.5 × the mean: on a regular grid (a depth image) the deviation is tiny and the rim's
  // larger distances would otherwise count as outliers (a corner's quarter-disc neighbourhood
  // doubles them; 1.5 × lost the four corner cells of a clean 80 × 60 grid).
  const double threshold = std::max(mean + run.parameters.outlier_std * deviation, 2.5 * mean);
  for (std::size_t q = 0; q < nq; ++q)
    if (run.finite[q] && mean_distance[q] > threshold) {
      run.passed[q] = 0;
      run.usable[run.queries[q]] = 0;
      ++run.report.outlier_filter_removed;
    }
}

void prefilter(DenoisingRun& run)
{
  const std::size_t nq = run.nq;
  CloudRepairReport& report = run.report;
  run.usable.assign(run.points.size(), 0);
  for (std::size_t i = 0; i < run.points.size(); ++i)
    run.usable[i] = run.points[i].allFinite() ? 1 : 0;
  run.finite.assign(nq, 0);
  for (std::size_t q = 0; q < nq; ++q)
    run.finite[q] = (run.queries[q] < run.points.size() && run.usable[run.queries[q]]) ? 1 : 0;
  std::vector<double> mean_distance, nearest;
  neighbourDistances(run, run.parameters.outlier_filter ? run.parameters.outlier_neighbours : 1, mean_distance, nearest);
  run.passed = run.finite;
  if (run.parameters.outlier_filter)
    filterOutliers(run, mean_distance);
  std::size_t finite_count = 0, spacing_count = 0;
  for (std::size_t q = 0; q < nq; ++q) {
    finite_count += run.finite[q] ? 1 : 0;
    const double spacing = run.scales ? run.scales->spacing[q] : nearest[q];
    if (run.passed[q] && spacing > 0.0) {
      report.mean_spacing += spacing;
      ++spacing_count;
    }
  }
  report.nonfinite_points = nq - finite_count;
  if (spacing_count == 0)
    throw Error("cloud denoising: every point coincides with its neighbours; no spacing to work at");
  report.mean_spacing /= static_cast<double>(spacing_count);
  run.s = report.mean_spacing;
}
// 3. Every kept point onto its own patch (the leverage was for the risk only).

/// The fit of every kept point; points with too few neighbours at h (sparse spots, rims) try twice
/// and four times h.
std::vector<LocalQuadricFit> fitKeptPoints(DenoisingRun& run)
{
  CloudRepairReport& report = run.report;
  run.fit_parameters.bandwidth = report.bandwidth;
  run.fit_parameters.want_leverage = false;
  run.fit_parameters.want_loo_residual = true;  // the residual-outlier test
  std::vector<std::size_t> fit_queries(run.kept_queries.size());
  for (std::size_t j = 0; j < run.kept_queries.size(); ++j)
    fit_queries[j] = run.queries[run.kept_queries[j]];
  std::vector<LocalQuadricFit> fits;
  if (run.scales)
    fitAtBandwidths(run.points, run.usable, run.radius, fit_queries, run.point_h,
                    run.factor_used > 0.0 ? run.cappedAt(run.factor_used) : run.fit_parameters, false, fits);
  else
    fitLocalQuadrics(run.points, run.usable, run.radius, fit_queries, run.fit_parameters, false, fits);
  for (const double widen : {2.0, 4.0}) {
    std::vector<std::size_t> retry, retry_queries;
    std::vector<double> retry_h;
    for (std::size_t j = 0; j < fits.size(); ++j)
      if (!fits[j].valid) {
        retry.push_back(j);
        retry_queries.push_back(fit_queries[j]);
        if (run.scales)
          retry_h.push_back(widen * run.point_h[j]);
      }
    if (retry.empty())
      break;
    LocalQuadricParameters wider = run.fit_parameters;
    wider.bandwidth = widen * report.bandwidth;
    std::vector<LocalQuadricFit> refits;
    if (run.scales)
      fitAtBandwidths(run.points, run.usable, run.radius, retry_queries, retry_h, wider, false, refits);
    else
      fitLocalQuadrics(run.points, run.usable, run.radius, retry_queries, wider, false, refits);
    for (std::size_t k = 0; k < retry.size(); ++k)
      fits[retry[k]] = refits[k];
  }
  return fits;
}

void projectKeptPoints(DenoisingRun& run, std::vector<char>& kept, std::vector<Eigen::Vector3d>& out_positions,
                       std::vector<Eigen::Vector3d>& out_normals)
{
  CloudRepairReport& report = run.report;
  const std::vector<LocalQuadricFit> fits = fitKeptPoints(run);
  // Residuals of clean samples of a curved or faceted surface are bias, heavy-tailed, not noise:
  // a point is only an outlier beyond two spacings, whatever σ (a clean boot cloud lost 632 of
  // 95,599 points at one spacing). With a depth law: σ_i and s_i, the point's own.
  const double residual_limit = std::max(run.parameters.residual_outlier_factor * run.sigma, 2.0 * run.s);
  double displacement = 0.0;
  for (std::size_t j = 0; j < run.kept_queries.size(); ++j) {
    const std::size_t q = run.kept_queries[j];
    const LocalQuadricFit& fit = fits[j];
    if (!fit.valid) {
      ++report.unfit_removed;
      continue;
    }
    if (run.parameters.residual_outlier_factor > 0.0 &&
        std::abs(fit.loo_residual) > (run.scales ? run.point_limit[j] : residual_limit)) {
      ++report.residual_removed;
      continue;
    }
    kept[q] = 1;
    out_positions[q] = fit.position;
    out_normals[q] = fit.normal;
    displacement += (fit.position - run.points[run.queries[q]]).norm();
    ++report.output_points;
  }
  report.mean_displacement = report.output_points ? displacement / static_cast<double>(report.output_points) : 0.0;
}

}  // namespace

namespace detail {

void denoiseCloud(const std::vector<Eigen::Vector3d>& points, const std::vector<Eigen::Vector3d>& normals,
                  const std::vector<std::size_t>& queries, const KnnSearch& knn,
                  const RadiusNeighbourSearch& radius, const CloudRepairParameters& parameters,
                  bool want_normals, const Eigen::Vector3d* viewpoint, std::vector<char>& kept,
                  std::vector<Eigen::Vector3d>& out_positions, std::vector<Eigen::Vector3d>& out_normals,
                  CloudRepairReport& report, const PointScales* scales)
{
  checkParameters(parameters);
  if (!normals.empty() && normals.size() != points.size())
    throw Error("cloud denoising: one normal per point is needed");
  DenoisingRun run(points, queries, knn, radius, parameters, scales, report);
  run.threads = threadCount(parameters.num_threads);
  run.nq = queries.size();
  if (scales)
    checkScales(points, queries, *scales);
  report.depth_law = scales != nullptr;
  report.input_points = run.nq;
  kept.assign(run.nq, 0);
  out_positions.assign(run.nq, Eigen::Vector3d::Constant(std::numeric_limits<double>::quiet_NaN()));
  out_normals.assign(run.nq, Eigen::Vector3d::Zero());

  auto start = Clock::now();
  prefilter(run);
  report.seconds_outliers = secondsSince(start);

  start = Clock::now();
  estimateNoiseAndBandwidth(run);
  report.seconds_noise = secondsSince(start);

  start = Clock::now();
  projectKeptPoints(run, kept, out_positions, out_normals);
  report.seconds_fit = secondsSince(start);

  start = Clock::now();
  if (want_normals) {
    Orientation orientation{points, normals, queries, knn, kept, out_positions, out_normals, report};
    orientNormals(orientation, viewpoint, run.threads);
  }
  report.seconds_normals = secondsSince(start);
}

}  // namespace detail

}  // namespace patchdict
}  // namespace pcl
