// SparsePatchCloudInpainter: the type-free core (detail::denoiseCloud) and the explicit
// instantiations for PCL's common point types (as PCL's own modules do).
#include <pcl_patchdict/geometry/coarse_mesh_estimation.h>
#include <pcl_patchdict/core/error.h>
#include <pcl_patchdict/cloud/impl/sparse_patch_cloud_inpainter.hpp>
#include <pcl_patchdict/cloud/sparse_patch_cloud_inpainter.h>

#include <pcl/search/kdtree.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <deque>
#include <limits>

#ifdef _OPENMP
#include <omp.h>
#endif

namespace pcl {
namespace patchdict {

namespace {

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

void checkParameters(const CloudDenoisingParameters& p)
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

}  // namespace

namespace detail {

void denoiseCloud(const std::vector<Eigen::Vector3d>& points, const std::vector<Eigen::Vector3d>& normals,
                  const std::vector<std::size_t>& queries, const KnnSearch& knn,
                  const RadiusNeighbourSearch& radius, const CloudDenoisingParameters& parameters,
                  bool want_normals, const Eigen::Vector3d* viewpoint, std::vector<char>& kept,
                  std::vector<Eigen::Vector3d>& out_positions, std::vector<Eigen::Vector3d>& out_normals,
                  CloudDenoisingReport& report, const PointScales* scales)
{
  checkParameters(parameters);
  if (!normals.empty() && normals.size() != points.size())
    throw Error("cloud denoising: one normal per point is needed");
  const int threads = threadCount(parameters.num_threads);
  const std::size_t nq = queries.size();
  if (scales) {
    if (scales->sigma.size() != nq || scales->spacing.size() != nq)
      throw Error("cloud denoising: the point scales need one sigma and one spacing per query");
    for (std::size_t q = 0; q < nq; ++q)
      if (queries[q] < points.size() && points[queries[q]].allFinite() &&
          (!(scales->sigma[q] > 0.0) || !std::isfinite(scales->sigma[q]) || !(scales->spacing[q] > 0.0) ||
           !std::isfinite(scales->spacing[q])))
        throw Error("cloud denoising: the point scales must be positive and finite at every finite query");
  }
  report.depth_law = scales != nullptr;
  report.input_points = nq;
  kept.assign(nq, 0);
  out_positions.assign(nq, Eigen::Vector3d::Constant(std::numeric_limits<double>::quiet_NaN()));
  out_normals.assign(nq, Eigen::Vector3d::Zero());

  // 1. Pre-filter and spacing, from the same k nearest neighbours.
  auto start = Clock::now();
  std::vector<char> usable(points.size(), 0);
  for (std::size_t i = 0; i < points.size(); ++i)
    usable[i] = points[i].allFinite() ? 1 : 0;
  std::vector<char> finite(nq, 0);
  for (std::size_t q = 0; q < nq; ++q)
    finite[q] = (queries[q] < points.size() && usable[queries[q]]) ? 1 : 0;
  // The spacing needs the first distinct neighbour: at least 8 are searched, so that stacked
  // duplicates (scanners repeat points) do not hide it.
  const int k = parameters.outlier_filter ? parameters.outlier_neighbours : 1;
  const int searched = std::max(k, 8);
  std::vector<double> mean_distance(nq, 0.0), nearest(nq, 0.0);
#pragma omp parallel num_threads(threads)
  {
    pcl::Indices found;
    std::vector<float> squared;
#pragma omp for schedule(dynamic, 1024)
    for (std::ptrdiff_t s = 0; s < static_cast<std::ptrdiff_t>(nq); ++s) {
      const auto q = static_cast<std::size_t>(s);
      if (!finite[q])
        continue;
      knn(queries[q], searched + 1, found, squared);
      double sum = 0.0;
      int counted = 0;
      for (std::size_t j = 0; j < found.size(); ++j) {
        if (static_cast<std::size_t>(found[j]) == queries[q])
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
      if (scales)  // in the point's own spacings: a far point of a depth image is no outlier for it
        mean_distance[q] /= scales->spacing[q];
    }
  }
  std::vector<char> passed(finite);
  if (parameters.outlier_filter) {
    double mean = 0.0, square = 0.0;
    std::size_t count = 0;
    for (std::size_t q = 0; q < nq; ++q)
      if (finite[q]) {
        mean += mean_distance[q];
        square += mean_distance[q] * mean_distance[q];
        ++count;
      }
    mean /= static_cast<double>(std::max<std::size_t>(count, 1));
    const double deviation = std::sqrt(std::max(0.0, square / static_cast<double>(std::max<std::size_t>(count, 1)) - mean * mean));
    // Floor at 2.5 × the mean: on a regular grid (a depth image) the deviation is tiny and the rim's
    // larger distances would otherwise count as outliers (a corner's quarter-disc neighbourhood
    // doubles them; 1.5 × lost the four corner cells of a clean 80 × 60 grid).
    const double threshold = std::max(mean + parameters.outlier_std * deviation, 2.5 * mean);
    for (std::size_t q = 0; q < nq; ++q)
      if (finite[q] && mean_distance[q] > threshold) {
        passed[q] = 0;
        usable[queries[q]] = 0;
        ++report.outlier_filter_removed;
      }
  }
  std::size_t finite_count = 0, spacing_count = 0;
  for (std::size_t q = 0; q < nq; ++q) {
    finite_count += finite[q] ? 1 : 0;
    const double spacing = scales ? scales->spacing[q] : nearest[q];
    if (passed[q] && spacing > 0.0) {
      report.mean_spacing += spacing;
      ++spacing_count;
    }
  }
  report.nonfinite_points = nq - finite_count;
  if (spacing_count == 0)
    throw Error("cloud denoising: every point coincides with its neighbours; no spacing to work at");
  report.mean_spacing /= static_cast<double>(spacing_count);
  const double s = report.mean_spacing;
  report.seconds_outliers = secondsSince(start);

  // 2. Noise level and bandwidth, over an evenly spaced sample of the kept points.
  start = Clock::now();
  std::vector<std::size_t> kept_queries;
  kept_queries.reserve(nq);
  for (std::size_t q = 0; q < nq; ++q)
    if (passed[q])
      kept_queries.push_back(q);
  LocalQuadricParameters fit_parameters;
  fit_parameters.min_neighbours = parameters.min_neighbours;
  fit_parameters.max_neighbours = parameters.max_neighbours;
  fit_parameters.num_threads = threads;
  fit_parameters.want_loo_residual = false;  // σ and the risk need the leverage, not this
  const std::size_t stride = std::max<std::size_t>(1, kept_queries.size() / static_cast<std::size_t>(parameters.noise_sample));
  std::vector<std::size_t> sample, sample_q;  // point indices, and their query numbers
  for (std::size_t j = 0; j < kept_queries.size(); j += stride) {
    sample.push_back(queries[kept_queries[j]]);
    sample_q.push_back(kept_queries[j]);
  }
  std::vector<LocalQuadricFit> sample_fits;
  // Depth law: at h = factor × s_i the max_neighbours nearest lie within √(max/π) s_i on a surface
  // facing the camera; the search stops at 1.5 times that (2h when less: the usual support), which
  // keeps every one of them up to 64° of incidence and spares the search the ring it would discard.
  const auto capped = [&](LocalQuadricParameters p, double factor) {
    const double cap = 1.5 * std::sqrt(static_cast<double>(parameters.max_neighbours) / 3.141592653589793) / factor;
    p.support_factor = std::clamp(cap, 1.0, p.support_factor);
    return p;
  };
  // With a depth law, σ_i and s_i are the point's own (σ_i: the given σ instead, when there is one).
  const auto sigma_of = [&](std::size_t q) { return parameters.noise_sigma > 0.0 ? parameters.noise_sigma : scales->sigma[q]; };
  if (scales) {
    std::vector<double> sigmas;
    sigmas.reserve(kept_queries.size());
    for (const std::size_t q : kept_queries)
      sigmas.push_back(sigma_of(q));
    report.noise_sigma = median(std::move(sigmas));
  } else if (parameters.noise_sigma > 0.0) {
    report.noise_sigma = parameters.noise_sigma;
  } else {
    // σ̂ = 1.4826 × median |leave-one-out residual| at h = 3 s, less the share of it that is the
    // prediction's own variance (≈ the mean leverage of the same fit with the sample included).
    fit_parameters.bandwidth = 3.0 * s;
    fitLocalQuadrics(points, usable, radius, sample, fit_parameters, true, sample_fits);
    std::vector<double> residuals;
    for (const auto& fit : sample_fits)
      if (fit.valid)
        residuals.push_back(std::abs(fit.residual));
    fitLocalQuadrics(points, usable, radius, sample, fit_parameters, false, sample_fits);
    double leverage = 0.0;
    std::size_t counted = 0;
    for (const auto& fit : sample_fits)
      if (fit.valid) {
        leverage += fit.leverage;
        ++counted;
      }
    leverage = counted ? leverage / static_cast<double>(counted) : 0.0;
    report.noise_sigma = 1.4826 * median(std::move(residuals)) / std::sqrt(1.0 + leverage);
    report.noise_estimated = true;
  }
  const double sigma = report.noise_sigma;
  double factor_used = 0.0;  // depth law: h_i = factor_used × s_i (0: parameters.bandwidth for all)
  if (parameters.bandwidth > 0.0) {
    report.bandwidth = parameters.bandwidth;
  } else {
    // Stein's unbiased risk estimate of the heights' mean squared error over the sample, for each
    // candidate h (Stein 1981; for local regression, e.g. Loader, "Local regression and likelihood",
    // 1999, ch. 10): mean r² − σ² + 2σ²·mean leverage; residuals clipped at 4σ (outliers are not
    // the smoother's business). The smallest wins. With a depth law each point's terms are in its
    // own σ_i² (the risk relative to the noise, so that the far, noisier points do not decide alone),
    // scaled back by the median σ² for the report; h_i = factor × s_i.
    double best = std::numeric_limits<double>::infinity();
    const double clip = 16.0 * sigma * sigma;
    std::vector<double> sample_h;
    // Depth sensors' noise is correlated between neighbouring pixels (disparity matched over a
    // window, quantised in layers): the fit's covariance with a point's own noise is then
    // σ_i² Σ_j S_ij ρ_ij rather than σ_i² S_ii. The smoother is flat near its query (S_ij ≈ S_ii w_j),
    // so that is σ_i² S_ii κ_i(h), κ_i(h) = Σ_j exp(−d_ij²/h²) ρ(d_ij / s_i) over the query's
    // kCorrelationNeighbours nearest (itself included, ρ(0) = 1). ρ is measured on the sample: the
    // heights of those neighbours over the tangent plane of the query's patch at 3 s_i, correlated
    // with the query's own, in bins of half a spacing (the pilot patch follows part of the
    // correlated noise: ρ comes out low rather than high). Heights are clipped at 4 σ_i.
    constexpr int kCorrelationNeighbours = 48, kBins = 12;  // bins cover 6 spacings
    std::vector<std::vector<std::pair<double, int>>> sample_neighbours;  // (d / s_i, bin)
    std::vector<double> rho(kBins, 0.0);
    if (scales) {
      const double widest = *std::max_element(parameters.bandwidth_candidates.begin(), parameters.bandwidth_candidates.end());
      std::vector<double> pilot_h(sample.size());
      for (std::size_t j = 0; j < sample.size(); ++j)
        pilot_h[j] = widest * scales->spacing[sample_q[j]];
      fitAtBandwidths(points, usable, radius, sample, pilot_h, capped(fit_parameters, widest), false, sample_fits);
      sample_neighbours.assign(sample.size(), {});
      std::vector<double> products(sample.size() * kBins, 0.0), own(sample.size(), 0.0);
      std::vector<int> pairs(sample.size() * kBins, 0);
#pragma omp parallel num_threads(threads)
      {
        pcl::Indices found;
        std::vector<float> squared;
#pragma omp for schedule(dynamic, 256)
        for (std::ptrdiff_t t = 0; t < static_cast<std::ptrdiff_t>(sample.size()); ++t) {
          const auto j = static_cast<std::size_t>(t);
          const LocalQuadricFit& fit = sample_fits[j];
          if (!fit.valid)
            continue;
          const double sj = scales->spacing[sample_q[j]], limit = 4.0 * sigma_of(sample_q[j]);
          const auto height = [&](const Eigen::Vector3d& p) {
            return std::clamp(fit.normal.dot(p - fit.position), -limit, limit) / sigma_of(sample_q[j]);
          };
          const double e0 = height(points[sample[j]]);
          own[j] = e0 * e0;
          knn(sample[j], kCorrelationNeighbours, found, squared);
          for (std::size_t k = 0; k < found.size(); ++k) {
            const auto other = static_cast<std::size_t>(found[k]);
            if (other == sample[j] || !usable[other])
              continue;
            const double d = std::sqrt(static_cast<double>(squared[k])) / sj;
            const int bin = static_cast<int>(2.0 * d);
            if (bin >= kBins)
              continue;
            sample_neighbours[j].push_back({d, bin});
            products[j * kBins + static_cast<std::size_t>(bin)] += e0 * height(points[other]);
            ++pairs[j * kBins + static_cast<std::size_t>(bin)];
          }
        }
      }
      double own_sum = 0.0;
      std::vector<double> bin_sum(kBins, 0.0);
      std::vector<double> bin_pairs(kBins, 0.0);
      std::size_t own_count = 0;
      for (std::size_t j = 0; j < sample.size(); ++j) {
        if (!sample_fits[j].valid)
          continue;
        own_sum += own[j];
        ++own_count;
        for (int b = 0; b < kBins; ++b) {
          bin_sum[static_cast<std::size_t>(b)] += products[j * kBins + static_cast<std::size_t>(b)];
          bin_pairs[static_cast<std::size_t>(b)] += pairs[j * kBins + static_cast<std::size_t>(b)];
        }
      }
      const double variance = own_count ? own_sum / static_cast<double>(own_count) : 0.0;
      for (int b = 0; b < kBins; ++b)
        if (bin_pairs[static_cast<std::size_t>(b)] > 0.0 && variance > 0.0)
          rho[static_cast<std::size_t>(b)] =
              std::clamp(bin_sum[static_cast<std::size_t>(b)] / bin_pairs[static_cast<std::size_t>(b)] / variance, 0.0, 1.0);
      report.noise_correlation.assign(rho.begin(), rho.end());
    }
    for (const double factor : parameters.bandwidth_candidates) {
      if (scales) {
        sample_h.resize(sample.size());
        for (std::size_t j = 0; j < sample.size(); ++j)
          sample_h[j] = factor * scales->spacing[sample_q[j]];
        fitAtBandwidths(points, usable, radius, sample, sample_h, capped(fit_parameters, factor), false, sample_fits);
      } else {
        fit_parameters.bandwidth = factor * s;
        fitLocalQuadrics(points, usable, radius, sample, fit_parameters, false, sample_fits);
      }
      double squared = 0.0, leverage = 0.0, risk_sum = 0.0, kappa_sum = 0.0;
      std::size_t counted = 0;
      for (std::size_t j = 0; j < sample_fits.size(); ++j) {
        const LocalQuadricFit& fit = sample_fits[j];
        if (!fit.valid)
          continue;
        if (scales) {
          const double sj2 = sigma_of(sample_q[j]) * sigma_of(sample_q[j]);
          const double r2 = std::min(fit.residual * fit.residual, 16.0 * sj2) / sj2;
          double kappa = 1.0;
          for (const auto& [d, bin] : sample_neighbours[j])
            kappa += std::exp(-d * d / (factor * factor)) * rho[static_cast<std::size_t>(bin)];
          kappa_sum += kappa;
          squared += r2;
          leverage += fit.leverage;
          risk_sum += r2 - 1.0 + 2.0 * parameters.leverage_weight * fit.leverage * kappa;
        } else {
          squared += std::min(fit.residual * fit.residual, clip);
          leverage += fit.leverage;
        }
        ++counted;
      }
      if (counted == 0)
        continue;
      const double n = static_cast<double>(counted);
      const double risk = scales ? sigma * sigma * risk_sum / n
                                 : squared / n - sigma * sigma + 2.0 * parameters.leverage_weight * sigma * sigma * leverage / n;
      report.bandwidth_risks.push_back({factor, risk, scales ? sigma * sigma * squared / n : squared / n, leverage / n});
      if (risk < best) {
        best = risk;
        report.bandwidth = factor * s;
        factor_used = factor;
        report.correlation_sum = kappa_sum / n;
      }
    }
    if (!(report.bandwidth > 0.0))
      throw Error("cloud denoising: no point has enough neighbours for a patch at any bandwidth");
  }
  // The bandwidth of every kept point (depth law) and its limit of the residual-outlier test.
  std::vector<double> point_h, point_limit;
  if (scales) {
    point_h.resize(kept_queries.size());
    point_limit.resize(kept_queries.size());
    std::vector<double> hs;
    for (std::size_t j = 0; j < kept_queries.size(); ++j) {
      const std::size_t q = kept_queries[j];
      point_h[j] = factor_used > 0.0 ? factor_used * scales->spacing[q] : parameters.bandwidth;
      point_limit[j] = std::max(parameters.residual_outlier_factor * sigma_of(q), 2.0 * scales->spacing[q]);
    }
    hs = point_h;
    if (factor_used > 0.0)
      report.bandwidth = median(std::move(hs));
    report.bandwidth_factor = factor_used > 0.0 ? factor_used : report.bandwidth / s;
  } else {
    report.bandwidth_factor = report.bandwidth / s;
  }
  report.seconds_noise = secondsSince(start);

  // 3. Every kept point onto its own patch (the leverage was for the risk only).
  start = Clock::now();
  fit_parameters.bandwidth = report.bandwidth;
  fit_parameters.want_leverage = false;
  fit_parameters.want_loo_residual = true;  // the residual-outlier test
  std::vector<std::size_t> fit_queries(kept_queries.size());
  for (std::size_t j = 0; j < kept_queries.size(); ++j)
    fit_queries[j] = queries[kept_queries[j]];
  std::vector<LocalQuadricFit> fits;
  if (scales)
    fitAtBandwidths(points, usable, radius, fit_queries, point_h,
                    factor_used > 0.0 ? capped(fit_parameters, factor_used) : fit_parameters, false, fits);
  else
    fitLocalQuadrics(points, usable, radius, fit_queries, fit_parameters, false, fits);
  // Points with too few neighbours at h (sparse spots, rims) try twice and four times h.
  for (const double widen : {2.0, 4.0}) {
    std::vector<std::size_t> retry, retry_queries;
    std::vector<double> retry_h;
    for (std::size_t j = 0; j < fits.size(); ++j)
      if (!fits[j].valid) {
        retry.push_back(j);
        retry_queries.push_back(fit_queries[j]);
        if (scales)
          retry_h.push_back(widen * point_h[j]);
      }
    if (retry.empty())
      break;
    LocalQuadricParameters wider = fit_parameters;
    wider.bandwidth = widen * report.bandwidth;
    std::vector<LocalQuadricFit> refits;
    if (scales)
      fitAtBandwidths(points, usable, radius, retry_queries, retry_h, wider, false, refits);
    else
      fitLocalQuadrics(points, usable, radius, retry_queries, wider, false, refits);
    for (std::size_t k = 0; k < retry.size(); ++k)
      fits[retry[k]] = refits[k];
  }
  // Residuals of clean samples of a curved or faceted surface are bias, heavy-tailed, not noise:
  // a point is only an outlier beyond two spacings, whatever σ (a clean boot cloud lost 632 of
  // 95,599 points at one spacing). With a depth law: σ_i and s_i, the point's own.
  const double residual_limit = std::max(parameters.residual_outlier_factor * sigma, 2.0 * s);
  double displacement = 0.0;
  for (std::size_t j = 0; j < kept_queries.size(); ++j) {
    const std::size_t q = kept_queries[j];
    const LocalQuadricFit& fit = fits[j];
    if (!fit.valid) {
      ++report.unfit_removed;
      continue;
    }
    if (parameters.residual_outlier_factor > 0.0 &&
        std::abs(fit.loo_residual) > (scales ? point_limit[j] : residual_limit)) {
      ++report.residual_removed;
      continue;
    }
    kept[q] = 1;
    out_positions[q] = fit.position;
    out_normals[q] = fit.normal;
    displacement += (fit.position - points[queries[q]]).norm();
    ++report.output_points;
  }
  report.mean_displacement = report.output_points ? displacement / static_cast<double>(report.output_points) : 0.0;
  report.seconds_fit = secondsSince(start);

  // 4. Normal orientation.
  start = Clock::now();
  if (want_normals) {
    bool any_input_normal = false;
    for (std::size_t q = 0; q < nq && !any_input_normal; ++q)
      any_input_normal = kept[q] && !normals.empty() && !normals[queries[q]].isZero();
    if (any_input_normal || viewpoint) {
      report.normal_orientation = any_input_normal ? "input normals" : "viewpoint";
      std::vector<char> oriented(nq, 0);
      for (std::size_t q = 0; q < nq; ++q) {
        if (!kept[q])
          continue;
        const bool has_input = any_input_normal && !normals[queries[q]].isZero();
        if (!has_input && !viewpoint)
          continue;  // no normal of its own: from its neighbours, below
        const Eigen::Vector3d reference =
            has_input ? normals[queries[q]] : Eigen::Vector3d(*viewpoint - out_positions[q]);
        if (out_normals[q].dot(reference) < 0.0) {
          out_normals[q] = -out_normals[q];
          ++report.normals_flipped;
        }
        oriented[q] = 1;
      }
      // Points without an input normal (NaN or zero in a cloud that has some), and no viewpoint:
      // oriented outwards from the oriented ones, breadth first over 16 nearest neighbours, each
      // agreeing with the neighbour it was reached from.
      std::vector<std::ptrdiff_t> query_of(points.size(), -1);
      for (std::size_t q = 0; q < nq; ++q)
        query_of[queries[q]] = static_cast<std::ptrdiff_t>(q);
      std::deque<std::size_t> frontier;
      for (std::size_t q = 0; q < nq; ++q)
        if (oriented[q])
          frontier.push_back(q);
      pcl::Indices found;
      std::vector<float> squared;
      while (!frontier.empty()) {
        const std::size_t from = frontier.front();
        frontier.pop_front();
        knn(queries[from], 16, found, squared);
        for (const auto j : found) {
          const std::ptrdiff_t other = query_of[static_cast<std::size_t>(j)];
          if (other < 0 || !kept[static_cast<std::size_t>(other)] || oriented[static_cast<std::size_t>(other)])
            continue;
          const auto to = static_cast<std::size_t>(other);
          if (out_normals[to].dot(out_normals[from]) < 0.0) {
            out_normals[to] = -out_normals[to];
            ++report.normals_flipped;
          }
          oriented[to] = 1;
          frontier.push_back(to);
        }
      }
    } else {
      report.normal_orientation = "propagation";
      auto cloud = std::make_shared<pcl::PointCloud<pcl::PointXYZ>>();
      std::vector<std::size_t> owner;
      for (std::size_t q = 0; q < nq; ++q)
        if (kept[q]) {
          cloud->push_back(pcl::PointXYZ(static_cast<float>(out_positions[q].x()), static_cast<float>(out_positions[q].y()),
                                         static_cast<float>(out_positions[q].z())));
          owner.push_back(q);
        }
      if (!owner.empty()) {
        pcl::search::KdTree<pcl::PointXYZ> tree(true);
        tree.setInputCloud(cloud);
        constexpr int kGraph = 8;
        std::vector<std::vector<int>> graph(owner.size());
#pragma omp parallel num_threads(threads)
        {
          pcl::Indices found;
          std::vector<float> squared;
#pragma omp for schedule(dynamic, 1024)
          for (std::ptrdiff_t i = 0; i < static_cast<std::ptrdiff_t>(owner.size()); ++i) {
            tree.nearestKSearch((*cloud)[static_cast<std::size_t>(i)], kGraph + 1, found, squared);
            for (const auto j : found)
              if (j != static_cast<int>(i) && graph[static_cast<std::size_t>(i)].size() < kGraph)
                graph[static_cast<std::size_t>(i)].push_back(j);
          }
        }
        std::vector<Eigen::Vector3d> oriented(owner.size());
        for (std::size_t i = 0; i < owner.size(); ++i)
          oriented[i] = out_normals[owner[i]];
        report.normals_flipped = propagateNormalOrientation(*cloud, graph, oriented);
        for (std::size_t i = 0; i < owner.size(); ++i)
          out_normals[owner[i]] = oriented[i];
      }
    }
  }
  report.seconds_normals = secondsSince(start);
}

}  // namespace detail

template class SparsePatchCloudInpainter<pcl::PointXYZ, pcl::PointXYZ>;
template class SparsePatchCloudInpainter<pcl::PointXYZ, pcl::PointNormal>;
template class SparsePatchCloudInpainter<pcl::PointNormal, pcl::PointNormal>;
template class SparsePatchCloudInpainter<pcl::PointNormal, pcl::PointXYZ>;
template class SparsePatchCloudInpainter<pcl::PointXYZRGB, pcl::PointXYZRGB>;
template class SparsePatchCloudInpainter<pcl::PointXYZRGB, pcl::PointXYZRGBNormal>;
template class SparsePatchCloudInpainter<pcl::PointXYZRGBNormal, pcl::PointXYZRGBNormal>;
template class SparsePatchCloudInpainter<pcl::PointXYZI, pcl::PointXYZI>;
// Kinect and other RGB-D grabbers' frames.
template class SparsePatchCloudInpainter<pcl::PointXYZRGBA, pcl::PointXYZRGBA>;
template class SparsePatchCloudInpainter<pcl::PointXYZRGBA, pcl::PointXYZRGBNormal>;

}  // namespace patchdict
}  // namespace pcl
