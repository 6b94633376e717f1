// correctCloudFillWithPatches and denoiseCloudWithPatches (cloud_patch_correction.h): the mesh
// repair's relief stage (layout, masked OMP, relief check) on points, each moved by least squares.
#include <pcl_patchdict/cloud/cloud_patch_correction.h>

#include <pcl_patchdict/core/error.h>
#include <pcl_patchdict/core/normalization.h>
#include <pcl_patchdict/quads/patch_layout.h>
#include <pcl_patchdict/repair/patch_correction.h>
#include <pcl_patchdict/repair/patch_prediction_check.h>

#include "geometry/point_search.h"

#include <pcl/kdtree/kdtree_flann.h>

#include <Eigen/Dense>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <memory>
#include <numeric>

namespace pcl {
namespace patchdict {

namespace {

using Clock = std::chrono::steady_clock;
double secondsSince(Clock::time_point t) { return std::chrono::duration<double>(Clock::now() - t).count(); }

void requireFinite(const std::vector<Eigen::Vector3d>& points, const char* what)
{
  for (const auto& p : points)
    if (!p.allFinite())
      throw Error(std::string("patch fill: the ") + what + " points must be finite");
}

/** Connected groups of `points` linked within `link`; returns the group of each point. */
std::vector<int> groupPoints(const std::vector<Eigen::Vector3d>& points, double link, int& groups)
{
  std::vector<int> group(points.size(), -1);
  groups = 0;
  if (points.empty())
    return group;
  const detail::PointSearch tree(points);
  std::vector<int> near;
  std::vector<float> squared;
  for (std::size_t start = 0; start < points.size(); ++start) {
    if (group[start] >= 0)
      continue;
    std::vector<std::size_t> stack{start};
    group[start] = groups;
    while (!stack.empty()) {
      const std::size_t i = stack.back();
      stack.pop_back();
      tree.within(points[i], static_cast<float>(link), near, squared);
      for (int j : near)
        if (group[static_cast<std::size_t>(j)] < 0) {
          group[static_cast<std::size_t>(j)] = groups;
          stack.push_back(static_cast<std::size_t>(j));
        }
    }
    ++groups;
  }
  return group;
}

/** The holes' diameter d: the median diameter (2 × the largest distance from the centroid) of the
  * holes — the groups of ≥ 10 points and of at least a tenth of the largest group's points (their
  * number in `large_groups`). The second bound drops the sampling gaps of a random cloud that the
  * fill closes too (10–20 points, a sixth of a hole across): on grooved reliefs a dozen of them
  * outvoted a dozen real holes of 600 points, and the patches shrank to nothing (declined). */
double medianGroupDiameter(const std::vector<Eigen::Vector3d>& points, const std::vector<int>& group, int groups,
                           std::size_t& large_groups)
{
  std::vector<Eigen::Vector3d> centre(static_cast<std::size_t>(groups), Eigen::Vector3d::Zero());
  std::vector<std::size_t> count(static_cast<std::size_t>(groups), 0);
  for (std::size_t i = 0; i < points.size(); ++i) {
    centre[static_cast<std::size_t>(group[i])] += points[i];
    ++count[static_cast<std::size_t>(group[i])];
  }
  for (std::size_t g = 0; g < centre.size(); ++g)
    centre[g] /= static_cast<double>(std::max<std::size_t>(count[g], 1));
  std::vector<double> reach(centre.size(), 0.0);
  for (std::size_t i = 0; i < points.size(); ++i) {
    const std::size_t g = static_cast<std::size_t>(group[i]);
    reach[g] = std::max(reach[g], (points[i] - centre[g]).norm());
  }
  const std::size_t largest = count.empty() ? 0 : *std::max_element(count.begin(), count.end());
  std::vector<double> diameters;
  for (std::size_t g = 0; g < reach.size(); ++g)
    if (count[g] >= 10 && 10 * count[g] >= largest)
      diameters.push_back(2.0 * reach[g]);
  large_groups = diameters.size();
  if (diameters.empty())
    return 0.0;
  std::nth_element(diameters.begin(), diameters.begin() + static_cast<std::ptrdiff_t>(diameters.size() / 2),
                   diameters.end());
  return diameters[diameters.size() / 2];
}

/** Each seed moved along its frame's Z onto the points: by the mean height of its 16 nearest. */
void moveSeedsOntoPoints(const std::vector<Eigen::Vector3d>& points, PatchLayout& layout)
{
  const detail::PointSearch tree(points);
  const int k = static_cast<int>(std::min<std::size_t>(16, points.size()));
  std::vector<int> near(static_cast<std::size_t>(k));
  std::vector<float> squared(static_cast<std::size_t>(k));
  for (std::size_t i = 0; i < layout.seeds.size(); ++i) {
    const Eigen::Vector3d z = layout.frames[i].row(2).transpose();
    const int found = tree.nearest(layout.seeds[i], k, near, squared);
    if (found <= 0)
      continue;
    double height = 0.0;
    for (int j = 0; j < found; ++j)
      height += z.dot(points[static_cast<std::size_t>(near[static_cast<std::size_t>(j)])] - layout.seeds[i]);
    layout.seeds[i] += z * (height / found);
  }
}

/** The relief check over the probe sides (checkRelief): fills the report's gain and returns the
  * chosen patch scale (× L), or 0 when no side's gain is significant. */
double probeRelief(const PatchCorrection& correction, const CloudPatchOptions& o, double d, double quad_length,
                   double spacing, const PatchCorrectionParameters& p, CloudPatchReport& r)
{
  std::vector<double> scales, sides;
  for (double f : o.decision.probe_factors) {
    scales.push_back(f * d / quad_length);
    sides.push_back(scales.back() * quad_length);
  }
  const std::vector<PatchSet> sets = correction.observedPatchesAtScales(scales);
  const ReliefVerdict verdict = checkRelief(sets, sides, d, spacing, o.decision, o.dictionary, p);
  if (const PatchPredictionCheck* shown = verdict.shown()) {
    r.dictionary_rms = shown->dictionary_rms;
    r.biharmonic_rms = shown->biharmonic_rms;
    r.test_patches = shown->test_patches;
  }
  r.gain = verdict.gain();
  return verdict.relief(o.decision) ? scales[static_cast<std::size_t>(verdict.significant_side)] : 0.0;
}

/** Every k-th seed of the layout, k = ⌈seeds / max_seeds⌉ (0: all): the relief check needs tens of
  * test patches, not all. */
std::shared_ptr<PatchLayout> probeLayout(const PatchLayout& layout, int max_seeds)
{
  auto probe = std::make_shared<PatchLayout>();
  probe->quad_length = layout.quad_length;
  const std::size_t n = layout.seeds.size(), most = max_seeds > 0 ? std::size_t(max_seeds) : std::max<std::size_t>(1, n);
  const std::size_t stride = std::max<std::size_t>(1, (n + most - 1) / most);
  for (std::size_t i = 0; i < n; i += stride) {
    probe->seeds.push_back(layout.seeds[i]);
    probe->frames.push_back(layout.frames[i]);
  }
  return probe;
}

/** x0 + δ, δ minimising Σ w (n·(x0 + δ − p))² + fidelity·Σw·|δ|². */
Eigen::Vector3d solveMove(const Eigen::Vector3d& x0, const std::vector<PointToPlaneConstraint>& list, double fidelity)
{
  Eigen::Matrix3d a = Eigen::Matrix3d::Zero();
  Eigen::Vector3d b = Eigen::Vector3d::Zero();
  double sum_w = 0.0;
  for (const auto& c : list) {
    a += c.weight * c.normal * c.normal.transpose();
    b += c.weight * c.normal * c.normal.dot(c.point - x0);
    sum_w += c.weight;
  }
  if (!(sum_w > 0.0))
    return x0;
  a += fidelity * sum_w * Eigen::Matrix3d::Identity();
  return x0 + a.ldlt().solve(b);
}

}  // namespace

void checkCloudPatchOptions(const CloudPatchOptions& o)
{
  const auto positive = [](double v) { return std::isfinite(v) && v > 0.0; };
  if (o.grid_size != 0 && (o.grid_size < 2 || o.grid_size > 256))
    throw Error("patch fill: the grid size must be 0 (automatic) or in [2, 256]");
  if (o.sparsity < 0 || o.overlap < 0 || o.overlap > 16)
    throw Error("patch fill: sparsity must be ≥ 0 and overlap in [0, 16]");
  if (!positive(o.bin_spacings) || !std::isfinite(o.bin_reach) || o.bin_reach < 0.0 || o.bin_reach > 8.0)
    throw Error("patch fill: bin spacings must be > 0 and the bin reach in [0, 8]");
  o.decision.check();
  if (!positive(o.decision.quad_factor) || !std::isfinite(o.fidelity) || o.fidelity < 0.0)
    throw Error("patch fill: the quad factor must be > 0 and the fidelity ≥ 0");
  if (!positive(o.denoise_scale) || !std::isfinite(o.error_factor) || o.error_factor < 0.0)
    throw Error("patch denoising: the scale must be > 0 and the error factor ≥ 0");
  if (o.layout_points < 100)
    throw Error("patch fill: the layout needs at least 100 points");
  if (o.dictionary && (o.dictionary->empty() || (o.grid_size != 0 && o.dictionary->gridSize() != o.grid_size)))
    throw Error("patch fill: the dictionary must have " + std::to_string(o.grid_size) + "×" +
                std::to_string(o.grid_size) + " atoms");
}

namespace {

/** What the fill and the denoiser hand the shared stage: the points patches are binned from, the
  * estimate (layout and targets: its points from first_target on), and the patch scale d. */
struct StageInput {
  const std::vector<Eigen::Vector3d>& observed;
  const std::vector<Eigen::Vector3d>& estimate;
  std::size_t first_target = 0;
  double d = 0.0;              ///< input units
  double error_per_bin = 0.0;  ///< input units (0: always `sparsity` atoms)
};

/** The shared stage: layout over the estimate, patches binned from the observed points, the
  * relief check, and the moves of the targets onto the coded patches (`corrected`, one per target,
  * left as they are when the patches are declined). */
void runPatchStage(const StageInput& in, const CloudPatchOptions& o, std::vector<Eigen::Vector3d>& corrected,
                   CloudPatchReport& r)
{
  TriangleMesh all;
  all.vertices = in.estimate;
  const UnitCubeNormalization norm = UnitCubeNormalization::fromMesh(all);
  norm.apply(all);
  auto observed_cloud = std::make_shared<TriangleMesh>();
  observed_cloud->vertices.reserve(in.observed.size());
  for (const auto& q : in.observed)
    observed_cloud->vertices.push_back(norm.apply(q));
  const double d = norm.applyLength(in.d), s = norm.applyLength(r.spacing);

  auto t = Clock::now();
  PatchCorrectionParameters p;
  p.quad_length = o.decision.quad_factor * d;
  p.overlap = o.overlap;
  const double middle_side = o.decision.probe_factors[o.decision.probe_factors.size() / 2] * d;
  p.grid_size = o.dictionary ? o.dictionary->gridSize()
                : o.grid_size > 0 ? o.grid_size
                                  : std::clamp(2 * static_cast<int>(std::lround(middle_side / (2.0 * o.bin_spacings * s))), 16, 48);
  p.sparsity = o.sparsity > 0 ? o.sparsity : std::max(1, p.grid_size / 2);
  p.bin_reach = o.bin_reach;
  p.error_per_bin = norm.applyLength(in.error_per_bin);
  p.fit_scale = 0.0;
  p.agreement_scale = 0.0;
  p.num_threads = o.num_threads;
  p.seed = o.seed;
  r.grid_size = p.grid_size;
  TriangleMesh coarse_input;
  const std::size_t stride = (all.vertices.size() + o.layout_points - 1) / o.layout_points;
  for (std::size_t i = 0; i < all.vertices.size(); i += stride)
    coarse_input.vertices.push_back(all.vertices[i]);
  auto layout = std::make_shared<PatchLayout>();
  try {
    computePatchLayout(coarse_input, PatchCorrection::layoutParameters(p, p.quad_length), *layout);
  } catch (const Error& e) {
    // A cloud too small or too sparse for patches of this size: the geometric result stands.
    r.outcome = PatchOutcome::Declined;
    r.reason = std::string("no patch layout: ") + e.what();
    return;
  }
  moveSeedsOntoPoints(all.vertices, *layout);
  r.seconds_layout = secondsSince(t);
  r.quad_length = norm.invertLength(p.quad_length);

  auto estimate = std::make_shared<TriangleMesh>(std::move(all));
  std::vector<std::int32_t> targets(estimate->vertices.size() - in.first_target);
  std::iota(targets.begin(), targets.end(), static_cast<std::int32_t>(in.first_target));
  PatchCorrection correction;
  correction.setEstimate(estimate);
  correction.setObservedSurface(observed_cloud);
  correction.setLayout(layout);
  correction.setTargets(targets);
  correction.setDictionary(o.dictionary);
  correction.setParameters(p);

  // The check runs on an evenly spaced subset of the seeds (it needs tens of test patches, not all).
  t = Clock::now();
  correction.setLayout(probeLayout(*layout, o.decision.probe_max_seeds));
  double scale = probeRelief(correction, o, d, p.quad_length, s, p, r);
  correction.setLayout(layout);
  r.seconds_check = secondsSince(t);
  r.dictionary_rms = norm.invertLength(r.dictionary_rms);
  r.biharmonic_rms = norm.invertLength(r.biharmonic_rms);
  if (scale == 0.0 && o.decision.mode == PatchDecision::Auto) {
    r.outcome = PatchOutcome::Declined;
    r.reason = r.test_patches == 0 ? "too few fully observed patches to measure"
                                   : "the dictionary predicts hidden surface no better than a smooth fill";
    return;
  }
  if (scale == 0.0)
    scale = o.decision.probe_factors.front() * d / p.quad_length;
  p.patch_scale = scale;
  correction.setParameters(p);
  r.patch_side = norm.invertLength(scale * p.quad_length);

  t = Clock::now();
  std::vector<std::vector<PointToPlaneConstraint>> constraints;
  PatchCorrectionReport pr;
  correction.compute(constraints, &pr);
  r.patches = pr.patches;
  r.patches_used = pr.patches_used;
  r.self_similar = pr.self_similar;
  double moved = 0.0;
  for (std::size_t i = 0; i < targets.size(); ++i) {
    if (constraints[i].empty())
      continue;
    const Eigen::Vector3d& x0 = estimate->vertices[in.first_target + i];
    corrected[i] = norm.invert(solveMove(x0, constraints[i], o.fidelity));
    moved += (corrected[i] - in.estimate[in.first_target + i]).norm();
    ++r.moved_points;
  }
  r.mean_correction = r.moved_points ? moved / static_cast<double>(r.moved_points) : 0.0;
  r.seconds_patches = secondsSince(t);
  r.outcome = PatchOutcome::Applied;
}

/** The checks and report fields both entry points start with; false when the stage must not run. */
bool startPatchStage(const std::vector<Eigen::Vector3d>& observed, const std::vector<Eigen::Vector3d>& targets,
                     double spacing, const CloudPatchOptions& o, CloudPatchReport& r)
{
  r = CloudPatchReport();
  checkCloudPatchOptions(o);
  if (observed.size() < 100)
    throw Error("patches: fewer than 100 observed points");
  requireFinite(observed, "observed");
  requireFinite(targets, "target");
  const bool off = o.decision.mode == PatchDecision::Never;
  r.outcome = off ? PatchOutcome::Declined : PatchOutcome::NotRun;
  r.reason = off ? "patches off" : "";
  r.spacing = spacing > 0.0 && std::isfinite(spacing) ? spacing : detail::meanNearestSpacing(observed);
  return !off && !targets.empty();
}

}  // namespace

void correctCloudFillWithPatches(const std::vector<Eigen::Vector3d>& observed, const std::vector<Eigen::Vector3d>& added,
                                 double spacing, const CloudPatchOptions& o,
                                 std::vector<Eigen::Vector3d>& corrected, CloudPatchReport* report)
{
  CloudPatchReport local;
  CloudPatchReport& r = report ? *report : local;
  const bool run = startPatchStage(observed, added, spacing, o, r);
  corrected = added;
  int groups = 0;
  const std::vector<int> group = groupPoints(added, 3.0 * r.spacing, groups);
  r.hole_diameter = medianGroupDiameter(added, group, groups, r.holes);
  if (!run || !(r.hole_diameter > 0.0)) {
    if (r.reason.empty())
      r.reason = added.empty() ? "no point was added" : "no hole";
    return;
  }
  std::vector<Eigen::Vector3d> all = observed;
  all.insert(all.end(), added.begin(), added.end());
  runPatchStage({observed, all, observed.size(), r.hole_diameter, 0.0}, o, corrected, r);
}

void denoiseCloudWithPatches(const std::vector<Eigen::Vector3d>& noisy, const std::vector<Eigen::Vector3d>& base,
                             double spacing, double noise_sigma, double base_risk, const CloudPatchOptions& o,
                             std::vector<Eigen::Vector3d>& corrected, CloudPatchReport* report)
{
  CloudPatchReport local;
  CloudPatchReport& r = report ? *report : local;
  if (!std::isfinite(noise_sigma) || noise_sigma < 0.0 || !std::isfinite(base_risk))
    throw Error("patch denoising: the noise sigma and the base's risk must be finite, the sigma ≥ 0");
  if (noisy.size() != base.size())
    throw Error("patch denoising: one base point per noisy point is needed");
  const bool run = startPatchStage(noisy, base, spacing, o, r);
  corrected = base;
  if (!run) {
    if (r.reason.empty())
      r.reason = "no point to denoise";
    return;
  }
  if (o.decision.mode == PatchDecision::Auto && !(base_risk > 0.0)) {
    r.outcome = PatchOutcome::Declined;
    r.reason = "the base's error has no estimate to compare with";
    return;
  }
  // A bin averages the points within bin_reach bins: about π·reach²·(bin/s)²/2 of them.
  const double bin = o.bin_spacings * r.spacing;
  const double per_bin = std::max(1.0, M_PI * o.bin_reach * o.bin_reach * (bin / r.spacing) * (bin / r.spacing) / 2.0);
  // Patches of at most a fifth of the cloud's largest side (a small cloud has no room for more).
  Eigen::Vector3d low = base.front(), high = base.front();
  for (const auto& q : base) {
    low = low.cwiseMin(q);
    high = high.cwiseMax(q);
  }
  const double d = std::min(o.denoise_scale * r.spacing, 0.2 * (high - low).maxCoeff()), epsilon = o.error_factor * noise_sigma / std::sqrt(per_bin);
  r.base_error = std::sqrt(base_risk > 0.0 ? base_risk : 0.0);
  if (o.decision.mode == PatchDecision::Auto) {
    // Two-fold cross-validation: patches from the even points predict the odd ones, whose noise they
    // never saw: mean squared miss = σ² + the patches' error (on half the data: a pessimistic
    // figure, so a tie goes to the base).
    std::vector<Eigen::Vector3d> even, estimate, odd;
    for (std::size_t i = 0; i < noisy.size(); i += 2) {
      even.push_back(noisy[i]);
      estimate.push_back(base[i]);
    }
    for (std::size_t i = 1; i < noisy.size(); i += 2)
      odd.push_back(noisy[i]);
    estimate.insert(estimate.end(), odd.begin(), odd.end());
    CloudPatchOptions always = o;
    always.decision.mode = PatchDecision::Always;
    CloudPatchReport cv = r;
    std::vector<Eigen::Vector3d> predicted = odd;
    runPatchStage({even, estimate, even.size(), d, epsilon}, always, predicted, cv);
    if (cv.outcome == PatchOutcome::Declined) {
      r.outcome = cv.outcome;
      r.reason = cv.reason;
      return;
    }
    double squared = 0.0;
    std::size_t count = 0;
    for (std::size_t i = 0; i < odd.size(); ++i)
      if (predicted[i] != odd[i]) {
        squared += (predicted[i] - odd[i]).squaredNorm();
        ++count;
      }
    const double patch_risk = count ? squared / static_cast<double>(count) - noise_sigma * noise_sigma : 0.0;
    r.patch_error = std::sqrt(std::max(patch_risk, 0.0));
    r.seconds_check += cv.seconds_layout + cv.seconds_check + cv.seconds_patches;
    if (count == 0 || !patchesLowerTheRisk(patch_risk, base_risk, o.decision)) {
      r.outcome = PatchOutcome::Declined;
      r.reason = "cross-validated, the patches' error is not below the geometric base's";
      return;
    }
  }
  CloudPatchOptions always = o;
  always.decision.mode = PatchDecision::Always;  // measured above: the relief check does not decide here
  runPatchStage({noisy, base, 0, d, epsilon}, always, corrected, r);
}

}  // namespace patchdict
}  // namespace pcl
