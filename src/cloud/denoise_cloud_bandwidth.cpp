// detail::denoiseCloud, stage 2 (see denoise_cloud.cpp): the noise level and the bandwidth of the
// patches, over an evenly spaced sample of the kept points.
#include "cloud/denoise_cloud_stages.h"

#include <pcl_patchdict/core/error.h>

#include <algorithm>
#include <cmath>
#include <limits>

namespace pcl {
namespace patchdict {
namespace denoise_detail {

namespace {

void chooseSample(DenoisingRun& run)
{
  run.kept_queries.reserve(run.nq);
  for (std::size_t q = 0; q < run.nq; ++q)
    if (run.passed[q])
      run.kept_queries.push_back(q);
  run.fit_parameters.min_neighbours = run.parameters.min_neighbours;
  run.fit_parameters.max_neighbours = run.parameters.max_neighbours;
  run.fit_parameters.num_threads = run.threads;
  run.fit_parameters.want_loo_residual = false;  // σ and the risk need the leverage, not this
  const std::size_t stride =
      std::max<std::size_t>(1, run.kept_queries.size() / static_cast<std::size_t>(run.parameters.noise_sample));
  for (std::size_t j = 0; j < run.kept_queries.size(); j += stride) {
    run.sample.push_back(run.queries[run.kept_queries[j]]);
    run.sample_q.push_back(run.kept_queries[j]);
  }
}

void estimateNoiseSigma(DenoisingRun& run)
{
  CloudRepairReport& report = run.report;
  if (run.scales) {
    std::vector<double> sigmas;
    sigmas.reserve(run.kept_queries.size());
    for (const std::size_t q : run.kept_queries)
      sigmas.push_back(run.sigmaOf(q));
    report.noise_sigma = median(std::move(sigmas));
  } else if (run.parameters.noise_sigma > 0.0) {
    report.noise_sigma = run.parameters.noise_sigma;
  } else {
    // σ̂ = 1.4826 × median |leave-one-out residual| at h = 3 s, less the share of it that is the
    // prediction's own variance (≈ the mean leverage of the same fit with the sample included).
    std::vector<LocalQuadricFit> sample_fits;
    run.fit_parameters.bandwidth = 3.0 * run.s;
    fitLocalQuadrics(run.points, run.usable, run.radius, run.sample, run.fit_parameters, true, sample_fits);
    std::vector<double> residuals;
    for (const auto& fit : sample_fits)
      if (fit.valid)
        residuals.push_back(std::abs(fit.residual));
    fitLocalQuadrics(run.points, run.usable, run.radius, run.sample, run.fit_parameters, false, sample_fits);
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
  run.sigma = report.noise_sigma;
}

// Depth sensors' noise is correlated between neighbouring pixels (disparity matched over a window,
// quantised in layers): the fit's covariance with a point's own noise is then σ_i² Σ_j S_ij ρ_ij
// rather than σ_i² S_ii. The smoother is flat near its query (S_ij ≈ S_ii w_j), so that is
// σ_i² S_ii κ_i(h), κ_i(h) = Σ_j exp(−d_ij²/h²) ρ(d_ij / s_i) over the query's
// kCorrelationNeighbours nearest (itself included, ρ(0) = 1). ρ is measured on the sample: the
// heights of those neighbours over the tangent plane of the query's patch at 3 s_i, correlated with
// the query's own, in bins of half a spacing (the pilot patch follows part of the correlated noise:
// ρ comes out low rather than high). Heights are clipped at 4 σ_i.
constexpr int kCorrelationNeighbours = 48, kBins = 12;  // bins cover 6 spacings

/// The noise correlation ρ per bin, measured on the sample (depth law); each sample point's
/// neighbours as (d / s_i, bin) for κ_i.
void measureNoiseCorrelation(const DenoisingRun& run, std::vector<std::vector<std::pair<double, int>>>& sample_neighbours,
                             std::vector<double>& rho)
{
  const std::vector<std::size_t>& sample = run.sample;
  const CloudRepairParameters& parameters = run.parameters;
  const double widest = *std::max_element(parameters.bandwidth_candidates.begin(), parameters.bandwidth_candidates.end());
  std::vector<double> pilot_h(sample.size());
  for (std::size_t j = 0; j < sample.size(); ++j)
    pilot_h[j] = widest * run.scales->spacing[run.sample_q[j]];
  std::vector<LocalQuadricFit> sample_fits;
  fitAtBandwidths(run.points, run.usable, run.radius, sample, pilot_h, run.cappedAt(widest), false, sample_fits);
  sample_neighbours.assign(sample.size(), {});
  std::vector<double> products(sample.size() * kBins, 0.0), own(sample.size(), 0.0);
  std::vector<int> pairs(sample.size() * kBins, 0);
#pragma omp parallel num_threads(run.threads)
  {
    pcl::Indices found;
    std::vector<float> squared;
#pragma omp for schedule(dynamic, 256)
    for (std::ptrdiff_t t = 0; t < static_cast<std::ptrdiff_t>(sample.size()); ++t) {
      const auto j = static_cast<std::size_t>(t);
      const LocalQuadricFit& fit = sample_fits[j];
      if (!fit.valid)
        continue;
      const double sj = run.scales->spacing[run.sample_q[j]], limit = 4.0 * run.sigmaOf(run.sample_q[j]);
      const auto height = [&](const Eigen::Vector3d& p) {
        return std::clamp(fit.normal.dot(p - fit.position), -limit, limit) / run.sigmaOf(run.sample_q[j]);
      };
      const double e0 = height(run.points[sample[j]]);
      own[j] = e0 * e0;
      run.knn(sample[j], kCorrelationNeighbours, found, squared);
      for (std::size_t k = 0; k < found.size(); ++k) {
        const auto other = static_cast<std::size_t>(found[k]);
        if (other == sample[j] || !run.usable[other])
          continue;
        const double d = std::sqrt(static_cast<double>(squared[k])) / sj;
        const int bin = static_cast<int>(2.0 * d);
        if (bin >= kBins)
          continue;
        sample_neighbours[j].push_back({d, bin});
        products[j * kBins + static_cast<std::size_t>(bin)] += e0 * height(run.points[other]);
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
}

/// Stein's unbiased risk estimate of the heights' mean squared error over the sample, for each
/// candidate h (Stein 1981; for local regression, e.g. Loader, "Local regression and likelihood",
/// 1999, ch. 10): mean r² − σ² + 2σ²·mean leverage; residuals clipped at 4σ (outliers are not the
/// smoother's business). The smallest wins. With a depth law each point's terms are in its own σ_i²
/// (the risk relative to the noise, so that the far, noisier points do not decide alone), scaled
/// back by the median σ² for the report; h_i = factor × s_i.
void chooseBandwidth(DenoisingRun& run)
{
  const CloudRepairParameters& parameters = run.parameters;
  CloudRepairReport& report = run.report;
  const std::vector<std::size_t>& sample = run.sample;
  const double sigma = run.sigma;
  double best = std::numeric_limits<double>::infinity();
  const double clip = 16.0 * sigma * sigma;
  std::vector<double> sample_h;
  std::vector<LocalQuadricFit> sample_fits;
  std::vector<std::vector<std::pair<double, int>>> sample_neighbours;  // (d / s_i, bin)
  std::vector<double> rho(kBins, 0.0);
  if (run.scales) {
    measureNoiseCorrelation(run, sample_neighbours, rho);
    report.noise_correlation.assign(rho.begin(), rho.end());
  }
  for (const double factor : parameters.bandwidth_candidates) {
    if (run.scales) {
      sample_h.resize(sample.size());
      for (std::size_t j = 0; j < sample.size(); ++j)
        sample_h[j] = factor * run.scales->spacing[run.sample_q[j]];
      fitAtBandwidths(run.points, run.usable, run.radius, sample, sample_h, run.cappedAt(factor), false, sample_fits);
    } else {
      run.fit_parameters.bandwidth = factor * run.s;
      fitLocalQuadrics(run.points, run.usable, run.radius, sample, run.fit_parameters, false, sample_fits);
    }
    double squared = 0.0, leverage = 0.0, risk_sum = 0.0, kappa_sum = 0.0;
    std::size_t counted = 0;
    for (std::size_t j = 0; j < sample_fits.size(); ++j) {
      const LocalQuadricFit& fit = sample_fits[j];
      if (!fit.valid)
        continue;
      if (run.scales) {
        const double sj2 = run.sigmaOf(run.sample_q[j]) * run.sigmaOf(run.sample_q[j]);
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
    const double risk = run.scales ? sigma * sigma * risk_sum / n
                                   : squared / n - sigma * sigma + 2.0 * parameters.leverage_weight * sigma * sigma * leverage / n;
    report.bandwidth_risks.push_back({factor, risk, run.scales ? sigma * sigma * squared / n : squared / n, leverage / n});
    if (risk < best) {
      best = risk;
      report.bandwidth = factor * run.s;
      run.factor_used = factor;
      report.correlation_sum = kappa_sum / n;
    }
  }
  if (!(report.bandwidth > 0.0))
    throw Error("cloud denoising: no point has enough neighbours for a patch at any bandwidth");
}

/// The bandwidth of every kept point (depth law) and its limit of the residual-outlier test.
void pointBandwidths(DenoisingRun& run)
{
  CloudRepairReport& report = run.report;
  if (!run.scales) {
    report.bandwidth_factor = report.bandwidth / run.s;
    return;
  }
  run.point_h.resize(run.kept_queries.size());
  run.point_limit.resize(run.kept_queries.size());
  std::vector<double> hs;
  for (std::size_t j = 0; j < run.kept_queries.size(); ++j) {
    const std::size_t q = run.kept_queries[j];
    run.point_h[j] = run.factor_used > 0.0 ? run.factor_used * run.scales->spacing[q] : run.parameters.bandwidth;
    run.point_limit[j] = std::max(run.parameters.residual_outlier_factor * run.sigmaOf(q), 2.0 * run.scales->spacing[q]);
  }
  hs = run.point_h;
  if (run.factor_used > 0.0)
    report.bandwidth = median(std::move(hs));
  report.bandwidth_factor = run.factor_used > 0.0 ? run.factor_used : report.bandwidth / run.s;
}

}  // namespace

void estimateNoiseAndBandwidth(DenoisingRun& run)
{
  chooseSample(run);
  estimateNoiseSigma(run);
  if (run.parameters.bandwidth > 0.0)
    run.report.bandwidth = run.parameters.bandwidth;
  else
    chooseBandwidth(run);
  pointBandwidths(run);
}

}  // namespace denoise_detail
}  // namespace patchdict
}  // namespace pcl
