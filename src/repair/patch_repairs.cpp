// The three repairs of patch_repairs.h, each a geometric base plus the patch correction of
// PatchCorrection. Bases: least-squares meshes (Sorkine & Cohen-Or, SMI 2004) for missing
// vertices, Liepa (SGP 2003) for holes, TaubinSmoother (Taubin, SIGGRAPH 1995) for denoising.
// Patches and dictionaries: Sarkar, Varanasi & Stricker, 3DV 2017, sections 4.3 and 5.3.
#include <pcl_patchdict/repair/patch_repairs.h>

#include "repair/repair_common.h"

#include <pcl_patchdict/core/error.h>
#include <pcl_patchdict/core/mesh_topology.h>
#include <pcl_patchdict/core/normalization.h>
#include <pcl_patchdict/core/vertex_normals.h>
#include <pcl_patchdict/geometry/taubin_smoothing.h>
#include <pcl_patchdict/quads/patch_layout.h>
#include <pcl_patchdict/repair/patch_constrained_solve.h>

#include <Eigen/Dense>

#include <omp.h>

#include <algorithm>
#include <cmath>
#include <numeric>
#include <random>
#include <string>

namespace pcl {
namespace patchdict {

namespace detail {

void checkRepairInput(const TriangleMesh& input)
{
  if (input.empty())
    throw Error("no input mesh");
  if (input.faces.empty())
    throw Error("the input has no faces: repairing a mesh needs its connectivity");
  const std::size_t n = input.numVertices();
  for (const Face& f : input.faces)
    for (std::int32_t v : f)
      if (v < 0 || static_cast<std::size_t>(v) >= n)
        throw Error("a face refers to vertex " + std::to_string(v) + ", the mesh has " + std::to_string(n));
}

std::vector<std::vector<PointToPlaneConstraint>> patchConstraints(
    const std::shared_ptr<const TriangleMesh>& estimate, const std::vector<bool>& observed_faces,
    const std::vector<std::int32_t>& targets, const PatchDictionary::ConstPtr& dictionary,
    const PatchCorrectionParameters& parameters, PatchCorrectionReport& report,
    const std::shared_ptr<const TriangleMesh>& observed_surface, const std::shared_ptr<const PatchLayout>& layout)
{
  PatchCorrection correction;
  correction.setEstimate(estimate);
  if (layout)
    correction.setLayout(layout);
  correction.setObservedFaces(observed_faces);
  if (observed_surface)
    correction.setObservedSurface(observed_surface);
  correction.setTargets(targets);
  correction.setDictionary(dictionary);
  correction.setParameters(parameters);
  std::vector<std::vector<PointToPlaneConstraint>> constraints;
  correction.compute(constraints, &report);
  return constraints;
}

UnitCubeNormalization checkedNormalization(const TriangleMesh& input)
{
  checkRepairInput(input);
  for (std::size_t v = 0; v < input.numVertices(); ++v)
    if (!input.vertices[v].allFinite())
      throw Error("vertex " + std::to_string(v) + " has a non-finite position");
  return UnitCubeNormalization::fromMesh(input);
}

double meanCorrection(const std::vector<Eigen::Vector3d>& now, const std::vector<Eigen::Vector3d>& base,
                      const std::vector<std::int32_t>& moved)
{
  double sum = 0.0;
  for (std::int32_t v : moved)
    sum += (now[static_cast<std::size_t>(v)] - base[static_cast<std::size_t>(v)]).norm();
  return moved.empty() ? 0.0 : sum / static_cast<double>(moved.size());
}

std::vector<PointToPlaneConstraint> flatten(const std::vector<std::vector<PointToPlaneConstraint>>& lists)
{
  std::vector<PointToPlaneConstraint> out;
  for (const auto& list : lists)
    out.insert(out.end(), list.begin(), list.end());
  return out;
}

void checkFinite(double value, bool ok, const char* message)
{
  if (!ok || !std::isfinite(value))
    throw Error(message);
}

}  // namespace detail

namespace {

using detail::Clock;
using detail::secondsSince;

/** The missing vertices as flags, after checking the list. */
std::vector<bool> missingFlags(const std::vector<int>& missing, std::size_t n)
{
  if (missing.empty())
    throw Error("no missing vertex given");
  std::vector<bool> is_missing(n, false);
  for (int v : missing) {
    if (v < 0 || static_cast<std::size_t>(v) >= n)
      throw Error("missing vertex " + std::to_string(v) + " is out of range: the mesh has " + std::to_string(n) +
                  " vertices");
    if (is_missing[static_cast<std::size_t>(v)])
      throw Error("missing vertex " + std::to_string(v) + " is listed twice");
    is_missing[static_cast<std::size_t>(v)] = true;
  }
  if (missing.size() == n)
    throw Error("every vertex is missing: nothing to interpolate from");
  return is_missing;
}

/** Normalises by the known vertices only (the missing ones' input positions mean nothing). */
UnitCubeNormalization knownNormalization(const TriangleMesh& input, const std::vector<bool>& is_missing)
{
  TriangleMesh known_cloud;
  for (std::size_t v = 0; v < input.numVertices(); ++v)
    if (!is_missing[v]) {
      if (!input.vertices[v].allFinite())
        throw Error("known vertex " + std::to_string(v) + " has a non-finite position");
      known_cloud.vertices.push_back(input.vertices[v]);
    }
  return UnitCubeNormalization::fromMesh(known_cloud);
}

/** Faces whose three vertices are known (Error when there is none). */
std::vector<bool> knownFaces(const TriangleMesh& work, const std::vector<bool>& is_missing)
{
  std::vector<bool> observed(work.numFaces());
  for (std::size_t f = 0; f < work.numFaces(); ++f)
    observed[f] = !is_missing[static_cast<std::size_t>(work.faces[f][0])] &&
                  !is_missing[static_cast<std::size_t>(work.faces[f][1])] &&
                  !is_missing[static_cast<std::size_t>(work.faces[f][2])];
  if (std::find(observed.begin(), observed.end(), true) == observed.end())
    throw Error("no face has its three vertices known: there is no observed surface to fit patches to");
  return observed;
}

}  // namespace

void checkMissingVerticesOptions(const MissingVerticesOptions& options)
{
  PatchCorrection::checkParameters(options);
  detail::checkFinite(options.constraint_weight, options.constraint_weight >= 0.0, "the constraint weight μ must be ≥ 0");
}

void fillMissingVertices(const TriangleMesh& input, const std::vector<int>& missing, TriangleMesh& out,
                         const MissingVerticesOptions& options, MissingVerticesReport* report)
{
  MissingVerticesReport local_report;
  MissingVerticesReport& r = detail::freshReport(report, local_report);
  checkMissingVerticesOptions(options);
  detail::checkRepairInput(input);
  const MissingVerticesOptions& p = options;
  const std::size_t n = input.numVertices();
  const std::vector<bool> is_missing = missingFlags(missing, n);
  r.missing_vertices = missing.size();
  const UnitCubeNormalization normalization = knownNormalization(input, is_missing);
  const auto work = std::make_shared<TriangleMesh>();  // shared with the patch stage
  work->faces = input.faces;
  work->vertices.resize(n);
  std::vector<bool> in_face(n, false);
  for (const Face& f : input.faces)
    for (std::int32_t v : f)
      in_face[static_cast<std::size_t>(v)] = true;
  std::vector<bool> is_free(n, false);
  for (std::size_t v = 0; v < n; ++v) {
    is_free[v] = is_missing[v] && in_face[v];
    if (is_missing[v] && !in_face[v])
      ++r.isolated_missing;
    work->vertices[v] = is_missing[v] ? Eigen::Vector3d::Zero() : normalization.apply(input.vertices[v]);
  }

  auto t = Clock::now();
  const PatchConstrainedSolver solver(*work, is_free);
  solver.solve(work->vertices);
  const std::vector<Eigen::Vector3d> base = work->vertices;
  r.seconds_base = secondsSince(t);
  r.mean_edge_length = work->meanEdgeLength();
  r.moved_vertices = solver.numFree();

  if (p.decision.mode != PatchDecision::Never && solver.numFree() > 0) {
    r.used_patches = true;
    t = Clock::now();
    const std::vector<bool> observed = knownFaces(*work, is_missing);
    const auto constraints =
        detail::patchConstraints(work, observed, solver.freeVertices(), p.dictionary, p, r.patches);
    r.seconds_patch_stage = secondsSince(t);
    t = Clock::now();
    solver.solve(work->vertices, detail::flatten(constraints), p.constraint_weight);
    r.mean_correction = detail::meanCorrection(work->vertices, base, solver.freeVertices());
    r.seconds_solve = secondsSince(t);
  }
  out = input;
  for (std::size_t v = 0; v < n; ++v)
    if (is_free[v])
      out.vertices[v] = normalization.invert(work->vertices[v]);
  out.normals.clear();  // the repaired vertices' normals would be stale
}

// ---------------------------------------------------------------- denoising

namespace {

/** Taubin smoothing of `noisy` into `work`, as many iterations as fixed or as the discrepancy
  * principle asks (rms displacement ≥ discrepancy × σ). */
void taubinBase(const TriangleMesh& noisy, const DenoiseOptions& p, TriangleMesh& work, DenoiseReport& r)
{
  const std::size_t n = noisy.numVertices();
  const TaubinSmoother smoother(noisy);
  const int fixed = p.base_iterations;
  const int limit = fixed >= 0 ? fixed : p.max_base_iterations;
  for (int iteration = 0; iteration < limit; ++iteration) {
    if (fixed < 0) {
      double sum = 0.0;
      for (std::size_t v = 0; v < n; ++v)
        sum += (work.vertices[v] - noisy.vertices[v]).squaredNorm();
      if (std::sqrt(sum / static_cast<double>(n)) >= p.discrepancy * r.noise_sigma)
        break;
    }
    smoother.iterate(work.vertices);
    ++r.base_iterations;
  }
}

/** Per vertex: min α·W·|δ|² + Σ w (n·(x0 + δ) − n·p)², x0 the base, W = Σ w (α relative to the
  * patches' weight). */
std::vector<Eigen::Vector3d> movePerVertex(const TriangleMesh& work,
                                           const std::vector<std::vector<PointToPlaneConstraint>>& constraints,
                                           double fidelity, int num_threads)
{
  const std::size_t n = work.numVertices();
  std::vector<Eigen::Vector3d> moved(n);
#pragma omp parallel for schedule(static) num_threads(num_threads > 0 ? num_threads : omp_get_max_threads())
  for (std::ptrdiff_t i = 0; i < static_cast<std::ptrdiff_t>(n); ++i) {
    const std::size_t v = static_cast<std::size_t>(i);
    const Eigen::Vector3d x0 = work.vertices[v];
    double total = 0.0;
    Eigen::Matrix3d h = Eigen::Matrix3d::Zero();
    Eigen::Vector3d g = Eigen::Vector3d::Zero();
    for (const PointToPlaneConstraint& c : constraints[v]) {
      total += c.weight;
      h += c.weight * c.normal * c.normal.transpose();
      g += c.weight * c.normal.dot(c.point - x0) * c.normal;
    }
    if (!(total > 0.0)) {
      moved[v] = x0;
      continue;
    }
    h += fidelity * total * Eigen::Matrix3d::Identity();
    moved[v] = x0 + h.ldlt().solve(g);
  }
  return moved;
}

/** Stein's unbiased estimate of mean |f − x|² for y = x + σ z n (z standard normal, n the normal):
  * mean |f − y|² − σ² + 2σ²·div f, div f = (1/n) Σ ∂(n·f_v)/∂(n·y_v). */
double steinRisk(const std::vector<Eigen::Vector3d>& f, const TriangleMesh& y, double sigma, double divergence)
{
  double sum = 0.0;
  for (std::size_t v = 0; v < f.size(); ++v)
    sum += (f[v] - y.vertices[v]).squaredNorm();
  return sum / static_cast<double>(f.size()) - sigma * sigma + 2.0 * sigma * sigma * divergence;
}

/** The decision of denoiseWithPatches: Stein's risk of base and patch result, their divergences by
  * one Monte-Carlo probe (Ramani, Blu & Unser 2008): y + h·b·n, b = ±1 per vertex (seeded), h =
  * probe_step·σ, n the base's normals; the base again at the same iteration count, the patches
  * again on the same layout (and dictionary, or a self-similar one learned again). Fills the
  * report's errors; true: keep the patches. */
bool patchRiskIsLower(const TriangleMesh& noisy, const TriangleMesh& base, const std::vector<Eigen::Vector3d>& moved,
                         const std::shared_ptr<const PatchLayout>& layout, PatchCorrectionParameters parameters,
                         const DenoiseOptions& p, DenoiseReport& r)
{
  const std::size_t n = noisy.numVertices();
  const double sigma = r.noise_sigma, h = p.probe_step * sigma;
  if (!(h > 0.0) || n == 0)
    return false;  // no noise to measure against: nothing to gain
  const std::vector<Eigen::Vector3d> normals = computeVertexNormals(base);
  std::mt19937_64 random(p.seed ^ 0x5d0e15ee5eedULL);
  std::vector<double> sign(n);
  const auto probed = std::make_shared<TriangleMesh>(noisy);
  for (std::size_t v = 0; v < n; ++v) {
    sign[v] = (random() >> 63) ? 1.0 : -1.0;
    if (normals[v].allFinite())
      probed->vertices[v] += h * sign[v] * normals[v];
  }
  DenoiseOptions fixed = p;
  fixed.base_iterations = r.base_iterations;
  DenoiseReport unused;
  const auto probed_base = std::make_shared<TriangleMesh>(*probed);
  taubinBase(*probed, fixed, *probed_base, unused);
  std::vector<std::int32_t> all(n);
  std::iota(all.begin(), all.end(), 0);
  PatchCorrectionReport probe_report;
  parameters.quad_length = layout->quad_length;  // the probed base's edges would give another L
  // A self-similar dictionary is learned again from the probed input: how much it adapts to the
  // noise is part of the divergence (kept fixed, the risk came out 30 % low on a small scan).
  const auto constraints = detail::patchConstraints(probed_base, {}, all, p.dictionary, parameters, probe_report,
                                                    probed, layout);
  const std::vector<Eigen::Vector3d> probed_moved = movePerVertex(*probed_base, constraints, p.fidelity, p.num_threads);
  double base_divergence = 0.0, patch_divergence = 0.0;
  for (std::size_t v = 0; v < n; ++v) {
    if (!normals[v].allFinite())
      continue;
    base_divergence += sign[v] * normals[v].dot(probed_base->vertices[v] - base.vertices[v]);
    patch_divergence += sign[v] * normals[v].dot(probed_moved[v] - moved[v]);
  }
  base_divergence /= h * static_cast<double>(n);
  patch_divergence /= h * static_cast<double>(n);
  const double base_risk = steinRisk(base.vertices, noisy, sigma, base_divergence);
  const double patch_risk = steinRisk(moved, noisy, sigma, patch_divergence);
  r.base_error = std::sqrt(std::max(base_risk, 0.0));
  r.patch_error = std::sqrt(std::max(patch_risk, 0.0));
  return patchesLowerTheRisk(patch_risk, base_risk, p.decision);
}

}  // namespace

void checkDenoiseOptions(const DenoiseOptions& p)
{
  PatchCorrection::checkParameters(p);
  detail::checkFinite(p.noise_sigma, p.noise_sigma >= 0.0, "the noise level must be ≥ 0 (0: estimated)");
  detail::checkFinite(p.error_factor, p.error_factor >= 0.0, "the error factor must be ≥ 0");
  detail::checkFinite(p.fidelity, p.fidelity > 0.0, "the fidelity weight must be > 0");
  if (p.base_iterations < -1 || p.max_base_iterations < 0)
    throw Error("base iterations must be ≥ 0 (−1: by the discrepancy principle), their maximum ≥ 0");
  detail::checkFinite(p.discrepancy, p.discrepancy > 0.0, "the discrepancy factor must be > 0");
  p.decision.check();
  detail::checkFinite(p.probe_step, p.probe_step > 0.0, "the probe step must be > 0");
}

void denoiseWithPatches(const TriangleMesh& input, TriangleMesh& out, const DenoiseOptions& options,
                        DenoiseReport* report)
{
  DenoiseReport local_report;
  DenoiseReport& r = detail::freshReport(report, local_report);
  checkDenoiseOptions(options);
  const UnitCubeNormalization normalization = detail::checkedNormalization(input);
  const DenoiseOptions& p = options;
  const std::size_t n = input.numVertices();

  // Base: Taubin smoothing, as many iterations as the discrepancy principle asks.
  auto t = Clock::now();
  const auto noisy = std::make_shared<TriangleMesh>(input);  // shared with the patch stage
  noisy->normals.clear();
  normalization.apply(*noisy);
  r.mean_edge_length = noisy->meanEdgeLength();
  r.noise_sigma = p.noise_sigma > 0.0 ? p.noise_sigma : estimateNoiseSigma(*noisy);
  r.noise_estimated = !(p.noise_sigma > 0.0);
  const auto work = std::make_shared<TriangleMesh>(*noisy);
  taubinBase(*noisy, p, *work, r);
  r.seconds_base = secondsSince(t);
  out = input;
  out.normals.clear();
  for (std::size_t v = 0; v < n; ++v)
    out.vertices[v] = normalization.invert(work->vertices[v]);
  std::vector<std::int32_t> all(n);
  std::iota(all.begin(), all.end(), 0);
  r.moved_vertices = n;
  if (p.decision.mode == PatchDecision::Never)
    return;
  t = Clock::now();
  PatchCorrectionParameters patch_parameters = p;
  patch_parameters.error_per_bin = p.error_factor * r.noise_sigma;
  // One layout of the base, shared by the decision's second run.
  auto layout = std::make_shared<PatchLayout>();
  const double quad_length = PatchCorrection::quadLength(*work, patch_parameters);
  computePatchLayout(*work, PatchCorrection::layoutParameters(patch_parameters, quad_length), *layout);
  const auto constraints =
      detail::patchConstraints(work, {}, all, p.dictionary, patch_parameters, r.patches, noisy, layout);
  r.seconds_patch_stage = secondsSince(t);
  t = Clock::now();
  const std::vector<Eigen::Vector3d> moved = movePerVertex(*work, constraints, p.fidelity, p.num_threads);
  r.seconds_solve = secondsSince(t);
  if (p.decision.mode == PatchDecision::Auto) {
    t = Clock::now();
    const bool keep = patchRiskIsLower(*noisy, *work, moved, layout, patch_parameters, p, r);
    r.seconds_decision = secondsSince(t);
    r.outcome = keep ? PatchOutcome::Applied : PatchOutcome::Declined;
    if (!keep)
      return;
  } else {
    r.outcome = PatchOutcome::Applied;  // forced: no estimates (base_error stays −1)
  }
  r.used_patches = true;
  double sum = 0.0;
  for (std::size_t v = 0; v < n; ++v) {
    sum += (moved[v] - work->vertices[v]).norm();
    out.vertices[v] = normalization.invert(moved[v]);
  }
  r.mean_correction = n ? sum / static_cast<double>(n) : 0.0;
}

double estimateNoiseSigma(const TriangleMesh& mesh)
{
  const auto rings = computeVertexOneRings(mesh);
  const auto normals = computeVertexNormals(mesh);
  std::vector<double> residuals;
  double degree_sum = 0.0;
  for (std::size_t v = 0; v < mesh.numVertices(); ++v) {
    if (rings[v].size() < 3 || !normals[v].allFinite() || normals[v].squaredNorm() < 0.5)
      continue;
    Eigen::Vector3d mean = Eigen::Vector3d::Zero();
    for (std::int32_t w : rings[v])
      mean += mesh.vertices[static_cast<std::size_t>(w)];
    mean /= static_cast<double>(rings[v].size());
    residuals.push_back(std::abs(normals[v].dot(mesh.vertices[v] - mean)));
    degree_sum += static_cast<double>(rings[v].size());
  }
  if (residuals.empty())
    return 0.0;
  const auto middle = residuals.begin() + static_cast<std::ptrdiff_t>(residuals.size() / 2);
  std::nth_element(residuals.begin(), middle, residuals.end());
  const double mean_degree = degree_sum / static_cast<double>(residuals.size());
  return 1.4826 * *middle / std::sqrt(1.0 + 1.0 / mean_degree);
}

}  // namespace patchdict
}  // namespace pcl
