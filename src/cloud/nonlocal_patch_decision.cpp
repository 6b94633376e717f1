// denoiseCloudNonlocally (nonlocal_patch_denoising.h): the non-local patch average decided per cloud by
// a coupled bootstrap — the base and the average both run on the cloud with more noise, scored on its twin.
#include <pcl_patchdict/cloud/local_quadric_projection.h>
#include <pcl_patchdict/cloud/nonlocal_patch_denoising.h>

#include <pcl_patchdict/core/error.h>

#include "geometry/point_search.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <string>

namespace pcl {
namespace patchdict {

namespace {

using Clock = std::chrono::steady_clock;
double secondsSince(Clock::time_point t) { return std::chrono::duration<double>(Clock::now() - t).count(); }

/** The base's local quadrics at bandwidth h, one per point (GeometricCloudRepair's fits on the kept
  * points, at the bandwidth it chose). */
void baseFits(const std::vector<Eigen::Vector3d>& noisy, double h, int threads, std::vector<LocalQuadricFit>& fits)
{
  const detail::PointSearch tree(noisy);
  const RadiusNeighbourSearch search = [&](std::size_t query, double radius, int max_neighbours, pcl::Indices& indices,
                                           std::vector<float>& squared) {
    std::vector<int> found;
    tree.within(noisy[query], detail::floatSearchRadius(radius), found, squared);
    const std::size_t keep = std::min(found.size(), static_cast<std::size_t>(std::max(max_neighbours, 0)));
    indices.assign(found.begin(), found.begin() + static_cast<std::ptrdiff_t>(keep));
    squared.resize(keep);
  };
  LocalQuadricParameters p;
  p.bandwidth = h;
  p.num_threads = threads;
  std::vector<std::size_t> queries(noisy.size());
  for (std::size_t i = 0; i < queries.size(); ++i)
    queries[i] = i;
  fitLocalQuadrics(noisy, {}, search, queries, p, false, fits);
}

/** A standard normal variate per (seed, index): splitmix64 twice, then Box–Muller — the same whatever
  * the thread count or the order of the calls. */
double normalVariate(std::uint64_t seed, std::size_t index)
{
  const auto mix = [](std::uint64_t x) {
    x += 0x9e3779b97f4a7c15ULL;
    x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ULL;
    x = (x ^ (x >> 27)) * 0x94d049bb133111ebULL;
    return x ^ (x >> 31);
  };
  const std::uint64_t a = mix(seed * 0x632be59bd9b4e019ULL + 2 * static_cast<std::uint64_t>(index));
  const std::uint64_t b = mix(a ^ (2 * static_cast<std::uint64_t>(index) + 1));
  const double u1 = (static_cast<double>(a >> 11) + 0.5) / 9007199254740992.0;  // (0, 1)
  const double u2 = static_cast<double>(b >> 11) / 9007199254740992.0;
  return std::sqrt(-2.0 * std::log(u1)) * std::cos(6.283185307179586 * u2);
}

/** The coupled bootstrap check (Oliveira, Lei & Tibshirani 2021, "Unbiased risk estimation in the
  * normal means problem via coupled bootstrap techniques"; Pang et al. 2021, "Recorrupted-to-
  * recorrupted"): with ω ~ N(0, σ²) along each point's normal, y⁺ = y + αω and y⁻ = y − ω/α have
  * independent noise, so the mean of (f(y⁺) − y⁻)² is f's risk at noise σ√(1 + α²) plus σ²(1 + 1/α²),
  * the same constant for the base and for the average: their difference needs no σ. Both are run on
  * y⁺ — the base's quadrics at its bandwidth, the average over them — and scored against y⁻ along the
  * base's normals. */
bool recorruptedCheck(const std::vector<Eigen::Vector3d>& noisy, double spacing, double noise_sigma,
                      double bandwidth, const NonlocalPatchOptions& o, NonlocalPatchReport& r)
{
  std::vector<LocalQuadricFit> fits;
  baseFits(noisy, bandwidth, o.num_threads, fits);
  const double alpha = o.check_alpha;
  std::vector<Eigen::Vector3d> up(noisy), down(noisy), normal(noisy.size(), Eigen::Vector3d::Zero());
  for (std::size_t i = 0; i < noisy.size(); ++i) {
    if (!fits[i].valid)
      continue;
    normal[i] = fits[i].normal;
    const double w = noise_sigma * normalVariate(o.seed, i);
    up[i] += alpha * w * normal[i];
    down[i] -= w / alpha * normal[i];
  }
  std::vector<LocalQuadricFit> up_fits;
  baseFits(up, bandwidth, o.num_threads, up_fits);
  std::vector<Eigen::Vector3d> up_base(up);
  for (std::size_t i = 0; i < up.size(); ++i)
    if (up_fits[i].valid)
      up_base[i] = up_fits[i].position;
  std::vector<Eigen::Vector3d> up_average;
  NonlocalPatchReport scratch;
  const std::size_t stride =
      o.check_queries > 0 ? std::max<std::size_t>(1, (noisy.size() + o.check_queries - 1) / o.check_queries) : 1;
  const detail::NonlocalHeights h = detail::averageAndMove(up, up_base, spacing, noise_sigma * std::sqrt(1.0 + alpha * alpha),
                                                           o, up_average, scratch, stride);
  double base_sum = 0.0, patch_sum = 0.0, gain_sum = 0.0, gain_squares = 0.0;
  std::size_t n = 0;
  for (std::size_t t = 0; t < h.valid.size(); ++t) {
    const std::size_t i = t * stride;
    if (!fits[i].valid || !up_fits[i].valid || !h.valid[t])
      continue;
    const double eb = (up_base[i] - down[i]).dot(normal[i]), ep = (up_average[i] - down[i]).dot(normal[i]);
    const double gain = eb * eb - ep * ep;
    base_sum += eb * eb;
    patch_sum += ep * ep;
    gain_sum += gain;
    gain_squares += gain * gain;
    ++n;
  }
  r.scored_points = n;
  if (n < 100)
    return false;
  const double count = static_cast<double>(n), c = noise_sigma * noise_sigma * (1.0 + 1.0 / (alpha * alpha));
  const double mean_gain = gain_sum / count;
  const double variance = std::max(gain_squares / count - mean_gain * mean_gain, 0.0) * count / (count - 1.0);
  const double base_risk = base_sum / count - c, patch_risk = patch_sum / count - c;
  r.base_error = std::sqrt(std::max(base_risk, 0.0));
  r.patch_error = std::sqrt(std::max(patch_risk, 0.0));
  r.z = variance > 0.0 ? mean_gain / std::sqrt(variance / count) : 0.0;
  return patchesLowerTheRisk(patch_risk, base_risk, o.decision);
}

}  // namespace

void denoiseCloudNonlocally(const std::vector<Eigen::Vector3d>& noisy, const std::vector<Eigen::Vector3d>& base,
                            double spacing, double noise_sigma, double bandwidth, const NonlocalPatchOptions& o,
                            std::vector<Eigen::Vector3d>& denoised, NonlocalPatchReport* report)
{
  NonlocalPatchReport local;
  NonlocalPatchReport& r = report ? *report : local;
  r = NonlocalPatchReport();
  o.check();
  if (noisy.size() != base.size())
    throw Error("non-local patches: one noisy point per base point is needed");
  if (!std::isfinite(noise_sigma) || noise_sigma < 0.0 || !std::isfinite(bandwidth) || bandwidth < 0.0)
    throw Error("non-local patches: the noise sigma and the bandwidth must be finite and ≥ 0");
  denoised = base;
  if (o.decision.mode == PatchDecision::Never) {
    r.outcome = PatchOutcome::Declined;
    r.reason = "patches off";
    return;
  }
  if (base.size() < 200 || !(noise_sigma > 0.0)) {
    r.reason = base.size() < 200 ? "fewer than 200 points" : "no noise to average";
    return;
  }
  if (o.decision.mode == PatchDecision::Auto) {
    if (!(bandwidth > 0.0)) {
      r.outcome = PatchOutcome::Declined;
      r.reason = "no bandwidth of the base to check against";
      return;
    }
    if (o.max_checked_points > 0 && noisy.size() > o.max_checked_points) {
      r.outcome = PatchOutcome::Declined;
      r.reason = "not run: " + std::to_string(noisy.size()) + " points, over the " + std::to_string(o.max_checked_points) +
                 " the check is run on by default (its time: two runs of the stage)";
      return;
    }
    const auto start = Clock::now();
    const bool helps = recorruptedCheck(noisy, spacing, noise_sigma, bandwidth, o, r);
    r.seconds_check = secondsSince(start);
    if (!helps) {
      r.outcome = PatchOutcome::Declined;
      r.reason = r.scored_points < 100 ? "fewer than 100 points could be scored" : "measured not to help";
      return;
    }
  }
  std::vector<Eigen::Vector3d> moved;
  detail::averageAndMove(noisy, base, spacing, noise_sigma, o, moved, r);
  denoised.swap(moved);
  r.outcome = PatchOutcome::Applied;
  r.reason = o.decision.mode == PatchDecision::Auto ? "measured to help" : "forced";
}

}  // namespace patchdict
}  // namespace pcl
