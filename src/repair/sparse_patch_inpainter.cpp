// SparsePatchInpainter (see sparse_patch_inpainter.h): the three repair modes, each a geometric
// base plus the patch correction of PatchCorrection. Bases: least-squares meshes (Sorkine &
// Cohen-Or, SMI 2004) for missing vertices, Liepa (SGP 2003) for holes, TaubinSmoother (Taubin,
// SIGGRAPH 1995) for denoising. Patches and dictionaries: Sarkar, Varanasi & Stricker, 3DV 2017, sections 4.3 and 5.3.
#include <pcl_patchdict/repair/sparse_patch_inpainter.h>

#include <pcl_patchdict/core/error.h>
#include <pcl_patchdict/core/mesh_topology.h>
#include <pcl_patchdict/core/normalization.h>
#include <pcl_patchdict/repair/patch_prediction_check.h>
#include <pcl_patchdict/geometry/taubin_smoothing.h>
#include <pcl_patchdict/core/vertex_normals.h>

#include <Eigen/Dense>

#include <omp.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <numeric>
#include <string>

namespace pcl {
namespace patchdict {

namespace {

using Clock = std::chrono::steady_clock;
double secondsSince(Clock::time_point t) { return std::chrono::duration<double>(Clock::now() - t).count(); }

/** One run of the relief check (see SparsePatchInpainter::Parameters::relief_probe_factors). */
struct ReliefProbe {
  double quad_length = 0.0;     ///< of the layout probed
  double best_scale = 1.0;      ///< patch side of the best significant probe, × quad_length
  double best_any_scale = 1.0;  ///< patch side of the best probe, significant or not
  double best_significant = 0.0, best_any = 0.0;  ///< gains
  double seconds_layout = 0.0, seconds_patches = 0.0, seconds_prediction = 0.0;
};

/** Lays quads of side `quad_length` (overlap k) on `work` into `layout`, widens the patches on its
  * seeds to each probe side (relief_probe_factors × d, or fixed_scale × quad_length when given),
  * and asks checkPatchPrediction whether the dictionary predicts a hidden disc better than a
  * biharmonic fill. */
ReliefProbe probeRelief(const TriangleMesh& work, const std::vector<bool>& observed,
                        const PatchDictionary::ConstPtr& dictionary, const SparsePatchInpainter::Parameters& p,
                        double median_diameter, double mean_edge_length, double quad_length, int overlap,
                        PatchLayout& layout, int max_seeds = 0, double fixed_scale = 0.0)
{
  ReliefProbe result;
  result.quad_length = quad_length;
  auto t = Clock::now();
  PatchCorrectionParameters probe = p;
  probe.quad_length = quad_length;
  probe.overlap = overlap;
  std::vector<double> scales;  // patch sides × quad_length: the one given, or the candidates × d
  if (fixed_scale > 0.0)
    scales.push_back(fixed_scale);
  else
    for (double factor : p.relief_probe_factors)
      scales.push_back(factor * median_diameter / quad_length);
  computePatchLayout(work, PatchCorrection::layoutParameters(probe, quad_length), layout);
  result.seconds_layout = secondsSince(t);
  t = Clock::now();
  PatchLayout subset;  // evenly spaced seeds of the layout, when it has more than max_seeds
  const bool subsample = max_seeds > 0 && layout.seeds.size() > static_cast<std::size_t>(max_seeds);
  if (subsample) {
    subset.quad_length = layout.quad_length;
    const std::size_t count = static_cast<std::size_t>(max_seeds);
    for (std::size_t i = 0; i < count; ++i) {
      const std::size_t s = i * layout.seeds.size() / count;
      subset.seeds.push_back(layout.seeds[s]);
      subset.frames.push_back(layout.frames[s]);
      subset.seed_faces.push_back(layout.seed_faces[s]);
    }
  }
  PatchCorrection correction;
  correction.setEstimate(work);
  correction.setObservedFaces(observed);
  correction.setDictionary(dictionary);
  correction.setParameters(probe);
  correction.setLayout(subsample ? subset : layout);
  const std::vector<PatchSet> sets = correction.observedPatchesAtScales(scales);
  result.seconds_patches = secondsSince(t);
  t = Clock::now();
  for (std::size_t i = 0; i < sets.size(); ++i) {
    // The probe hides a disc of the holes' radius (the loop's diameter d overstates it by the
    // ring of removed faces: measured 0.35 d ≈ the punched radius on the harness holes).
    // Capped at 0.3 × the patch side: a disc hiding nearly the whole patch says nothing about
    // the surface (large holes: the question is whether it is a relief, not how big the hole is).
    const double side = scales[i] * quad_length;
    const PatchPredictionCheck check = checkPatchPrediction(
        sets[i], std::min(p.relief_probe_radius * median_diameter, 0.3 * side), dictionary, probe, 10);
    // A relief is where the dictionary predicts better by a margin that matters: the gain
    // alone would call a perfect sphere a relief (both errors near zero, their ratio large).
    const bool significant = check.biharmonic_rms - check.dictionary_rms >= p.relief_min_improvement * mean_edge_length;
    if (check.gain > result.best_any) {
      result.best_any = check.gain;
      result.best_any_scale = scales[i];
    }
    if (significant && check.gain > result.best_significant) {
      result.best_significant = check.gain;
      result.best_scale = scales[i];
    }
  }
  result.seconds_prediction = secondsSince(t);
  return result;
}

void checkParameters(const SparsePatchInpainter::Parameters& p)
{
  PatchCorrection::checkParameters(p);
  if (!(p.constraint_weight >= 0.0) || !std::isfinite(p.constraint_weight))
    throw Error("the constraint weight μ must be ≥ 0");
  if (!(p.hole_quad_factor >= 0.0) || !std::isfinite(p.hole_quad_factor))
    throw Error("the hole quad factor must be ≥ 0");
  if (!(p.noise_sigma >= 0.0) || !std::isfinite(p.noise_sigma))
    throw Error("the noise level must be ≥ 0 (0: estimated)");
  if (!(p.error_factor >= 0.0) || !std::isfinite(p.error_factor))
    throw Error("the error factor must be ≥ 0");
  if (!(p.fidelity > 0.0) || !std::isfinite(p.fidelity))
    throw Error("the fidelity weight must be > 0");
  if (p.base_iterations < -1 || p.max_base_iterations < 0)
    throw Error("base iterations must be ≥ 0 (−1: by the discrepancy principle), their maximum ≥ 0");
  if (!(p.discrepancy > 0.0) || !std::isfinite(p.discrepancy))
    throw Error("the discrepancy factor must be > 0");
  if (!(p.relief_gain > 0.0) || !std::isfinite(p.relief_gain) || !(p.relief_constraint_weight >= 0.0) ||
      !std::isfinite(p.relief_constraint_weight) || p.relief_overlap < 0 || p.relief_probe_factors.empty() ||
      !(p.relief_probe_radius > 0.0) || !std::isfinite(p.relief_probe_radius) ||
      !(p.relief_min_improvement >= 0.0) || !std::isfinite(p.relief_min_improvement) || p.relief_probe_max_seeds < 0)
    throw Error("bad relief settings");
  for (double factor : p.relief_probe_factors)
    if (!(factor > 0.0) || !std::isfinite(factor))
      throw Error("relief probe factors must be > 0");
}

void checkMesh(const TriangleMesh& mesh)
{
  const std::size_t n = mesh.numVertices();
  for (const Face& f : mesh.faces)
    for (std::int32_t v : f)
      if (v < 0 || static_cast<std::size_t>(v) >= n)
        throw Error("a face refers to vertex " + std::to_string(v) + ", the mesh has " + std::to_string(n));
}

/** Runs the patch stage on `estimate` for `targets`; one constraint list per target. The data are
  * the estimate's `observed_faces` (empty: all), or `observed_surface` when given. */
std::vector<std::vector<PointToPlaneConstraint>> patchConstraints(const TriangleMesh& estimate,
                                                                  const std::vector<bool>& observed_faces,
                                                                  const std::vector<std::int32_t>& targets,
                                                                  const PatchDictionary::ConstPtr& dictionary,
                                                                  const PatchCorrectionParameters& parameters,
                                                                  PatchCorrectionReport& report,
                                                                  const TriangleMesh* observed_surface = nullptr,
                                                                  const PatchLayout* layout = nullptr)
{
  PatchCorrection correction;
  correction.setEstimate(estimate);
  if (layout)
    correction.setLayout(*layout);
  correction.setObservedFaces(observed_faces);
  if (observed_surface)
    correction.setObservedSurface(*observed_surface);
  correction.setTargets(targets);
  correction.setDictionary(dictionary);
  correction.setParameters(parameters);
  std::vector<std::vector<PointToPlaneConstraint>> constraints;
  correction.compute(constraints, &report);
  return constraints;
}

std::vector<PointToPlaneConstraint> flatten(const std::vector<std::vector<PointToPlaneConstraint>>& lists)
{
  std::vector<PointToPlaneConstraint> out;
  for (const auto& list : lists)
    out.insert(out.end(), list.begin(), list.end());
  return out;
}

double meanCorrection(const std::vector<Eigen::Vector3d>& now, const std::vector<Eigen::Vector3d>& base,
                      const std::vector<std::int32_t>& moved)
{
  double sum = 0.0;
  for (std::int32_t v : moved)
    sum += (now[static_cast<std::size_t>(v)] - base[static_cast<std::size_t>(v)]).norm();
  return moved.empty() ? 0.0 : sum / static_cast<double>(moved.size());
}

}  // namespace

SparsePatchInpainter::Parameters SparsePatchInpainter::defaultParameters(Mode mode)
{
  Parameters parameters;
  if (mode == Mode::Holes) {
    parameters.constraint_weight = 0.1;
    parameters.fit_scale = 0.02;
  } else if (mode == Mode::Denoise) {
    parameters.quad_length_factor = 6.0;
    parameters.sparsity = 20;
  }
  return parameters;
}

double SparsePatchInpainter::estimateNoiseSigma(const TriangleMesh& mesh)
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

void SparsePatchInpainter::process(TriangleMesh& out, Report* report) const
{
  Report local_report;
  Report& r = report ? *report : local_report;
  r = Report();
  r.mode = mode_;
  const Parameters& p = parameters_;
  checkParameters(p);
  if (!input_ || input_->empty())
    throw Error("no input mesh");
  const TriangleMesh& input = *input_;
  const std::size_t n = input.numVertices();
  if (input.faces.empty())
    throw Error("the input has no faces: repairing a mesh needs its connectivity");
  checkMesh(input);
  PatchCorrectionParameters patch_parameters = p;
  const PatchDictionary::ConstPtr dictionary = use_patches_ ? dictionary_ : nullptr;

  if (mode_ == Mode::MissingVertices) {
    if (missing_.empty())
      throw Error("no missing vertex given");
    std::vector<bool> is_missing(n, false);
    for (int v : missing_) {
      if (v < 0 || static_cast<std::size_t>(v) >= n)
        throw Error("missing vertex " + std::to_string(v) + " is out of range: the mesh has " + std::to_string(n) +
                    " vertices");
      if (is_missing[static_cast<std::size_t>(v)])
        throw Error("missing vertex " + std::to_string(v) + " is listed twice");
      is_missing[static_cast<std::size_t>(v)] = true;
    }
    if (missing_.size() == n)
      throw Error("every vertex is missing: nothing to interpolate from");
    r.missing_vertices = missing_.size();

    // Normalise by the known vertices only (the missing ones' input positions mean nothing).
    TriangleMesh known_cloud;
    for (std::size_t v = 0; v < n; ++v)
      if (!is_missing[v]) {
        if (!input.vertices[v].allFinite())
          throw Error("known vertex " + std::to_string(v) + " has a non-finite position");
        known_cloud.vertices.push_back(input.vertices[v]);
      }
    const UnitCubeNormalization normalization = UnitCubeNormalization::fromMesh(known_cloud);
    TriangleMesh work;
    work.faces = input.faces;
    work.vertices.resize(n);
    std::vector<bool> in_face(n, false);
    for (const Face& f : input.faces)
      for (std::int32_t v : f)
        in_face[static_cast<std::size_t>(v)] = true;
    std::vector<bool> is_free(n, false);
    for (std::size_t v = 0; v < n; ++v) {
      is_free[v] = is_missing[v] && in_face[v];
      if (is_missing[v] && !in_face[v])
        ++r.isolated_missing;
      work.vertices[v] = is_missing[v] ? Eigen::Vector3d::Zero() : normalization.apply(input.vertices[v]);
    }

    auto t = Clock::now();
    const PatchConstrainedSolver solver(work, is_free);
    solver.solve(work.vertices);
    const std::vector<Eigen::Vector3d> base = work.vertices;
    r.seconds_base = secondsSince(t);
    r.mean_edge_length = work.meanEdgeLength();
    r.moved_vertices = solver.numFree();

    if (use_patches_ && solver.numFree() > 0) {
      r.used_patches = true;
      t = Clock::now();
      std::vector<bool> observed(work.numFaces());
      for (std::size_t f = 0; f < work.numFaces(); ++f)
        observed[f] = !is_missing[static_cast<std::size_t>(work.faces[f][0])] &&
                      !is_missing[static_cast<std::size_t>(work.faces[f][1])] &&
                      !is_missing[static_cast<std::size_t>(work.faces[f][2])];
      if (std::find(observed.begin(), observed.end(), true) == observed.end())
        throw Error("no face has its three vertices known: there is no observed surface to fit patches to");
      const auto constraints =
          patchConstraints(work, observed, solver.freeVertices(), dictionary, patch_parameters, r.patches);
      r.seconds_patch_stage = secondsSince(t);
      t = Clock::now();
      solver.solve(work.vertices, flatten(constraints), p.constraint_weight);
      r.mean_correction = meanCorrection(work.vertices, base, solver.freeVertices());
      r.seconds_solve = secondsSince(t);
    }
    out = input;
    for (std::size_t v = 0; v < n; ++v)
      if (is_free[v])
        out.vertices[v] = normalization.invert(work.vertices[v]);
    out.normals.clear();  // the repaired vertices' normals would be stale
    return;
  }

  for (std::size_t v = 0; v < n; ++v)
    if (!input.vertices[v].allFinite())
      throw Error("vertex " + std::to_string(v) + " has a non-finite position");
  const UnitCubeNormalization normalization = UnitCubeNormalization::fromMesh(input);

  if (mode_ == Mode::Holes) {
    auto t = Clock::now();
    HoleFilling filling = hole_filling_;
    TriangleMesh input_without_normals = input;
    input_without_normals.normals.clear();
    filling.setInputMesh(input_without_normals);
    TriangleMesh filled;
    filling.process(filled, &r.holes);
    out = filled;
    r.seconds_base = secondsSince(t);
    std::vector<std::int32_t> new_vertices;
    for (std::size_t v = n; v < filled.numVertices(); ++v)
      new_vertices.push_back(static_cast<std::int32_t>(v));
    r.moved_vertices = new_vertices.size();
    TriangleMesh work = filled;
    normalization.apply(work);
    r.mean_edge_length = work.meanEdgeLength();
    if (!use_patches_ || new_vertices.empty())
      return;
    r.used_patches = true;

    // L sees the rim: at least hole_quad_factor × the median diameter of the filled holes.
    t = Clock::now();
    std::vector<double> diameters;
    for (const auto& hole : r.holes.holes)
      if (hole.filled())
        diameters.push_back(normalization.scale * hole.diameter);
    std::nth_element(diameters.begin(), diameters.begin() + static_cast<std::ptrdiff_t>(diameters.size() / 2),
                     diameters.end());
    const double median_diameter = diameters.empty() ? 0.0 : diameters[diameters.size() / 2];
    const bool automatic_quad_length = patch_parameters.quad_length <= 0.0;
    if (automatic_quad_length && median_diameter > 0.0)
      patch_parameters.quad_length =
          std::max(PatchCorrection::quadLength(work, p), p.hole_quad_factor * median_diameter);
    std::vector<bool> observed(work.numFaces(), false);
    std::fill(observed.begin(), observed.begin() + static_cast<std::ptrdiff_t>(input.numFaces()), true);

    // Relief or smooth surface? Measured, not assumed: can the dictionary predict a hidden disc of
    // the holes' size from the intact patches better than a biharmonic fill can?
    PatchLayout probe_layout;
    bool use_probe_layout = false;
    if (p.hole_settings != Parameters::HoleSettings::Smooth && median_diameter > 0.0) {
      const auto check_start = Clock::now();
      const double relief_length = p.relief_probe_factors.front() * median_diameter;
      // The verdict is probed on the layout the smooth settings would use, when their L is
      // automatic: a smooth verdict (the scans) then costs one layout, not two.
      // A quad length given by the caller is kept in both settings, with its patch side
      // (patch_scale × L): the probe then only decides relief or smooth, on that layout.
      const bool shared_layout = patch_parameters.quad_length > 0.0;
      const bool forced_relief = p.hole_settings == Parameters::HoleSettings::Relief;
      ReliefProbe probe;
      if (!forced_relief)
        probe = probeRelief(work, observed, dictionary, p, median_diameter, r.mean_edge_length,
                            shared_layout ? patch_parameters.quad_length : relief_length,
                            shared_layout ? patch_parameters.overlap : 1, probe_layout,
                            shared_layout ? p.relief_probe_max_seeds : 0,
                            automatic_quad_length ? 0.0 : patch_parameters.patch_scale);
      r.seconds_check_layout = probe.seconds_layout;
      r.seconds_check_patches = probe.seconds_patches;
      r.seconds_check_prediction = probe.seconds_prediction;
      r.relief_gain = probe.best_significant > 0.0 ? probe.best_significant : probe.best_any;
      r.relief = forced_relief || probe.best_significant >= p.relief_gain;
      if (r.relief) {
        if (automatic_quad_length) {
          // Relief: quads at the smallest probe's side (0.8 d), the best probe's patch side chosen
          // on them. (Choosing on the smooth settings' denser quads instead gave 1 % more error on
          // average on the harness's sole, knurl and tiles holes, knurl 0.035 +32 %.) A caller-given
          // L keeps its quads and patch side.
          if (forced_relief || std::abs(relief_length - probe.quad_length) > 1e-12 * relief_length) {
            probe = probeRelief(work, observed, dictionary, p, median_diameter, r.mean_edge_length, relief_length, 1,
                                probe_layout);
            r.seconds_check_layout += probe.seconds_layout;
            r.seconds_check_patches += probe.seconds_patches;
            r.seconds_check_prediction += probe.seconds_prediction;
          }
          if (forced_relief)
            r.relief_gain = probe.best_significant > 0.0 ? probe.best_significant : probe.best_any;
          patch_parameters.quad_length = relief_length;
          // In auto mode the verdict was significant on the first probe; should no side of the
          // second clear the margin, its best gain decides rather than the first side by default.
          patch_parameters.patch_scale =
              forced_relief || probe.best_significant > 0.0 ? probe.best_scale : probe.best_any_scale;
        }
        patch_parameters.overlap = p.relief_overlap;
        patch_parameters.fit_scale = 0.0;
        patch_parameters.agreement_scale = 0.0;
        r.seconds_check = secondsSince(check_start);
        // The probe's coarse shape and quads, reseeded at the relief overlap, not made again (no
        // probe ran when a caller-given L is forced to the relief settings).
        if (automatic_quad_length || !forced_relief) {
          reseedPatchLayout(work, p.relief_overlap, probe_layout);
          use_probe_layout = true;
        }
      } else {
        r.seconds_check = secondsSince(check_start);
        use_probe_layout = shared_layout;  // exactly the layout the smooth settings would make
      }
    }
    const auto constraints = patchConstraints(work, observed, new_vertices, dictionary, patch_parameters, r.patches,
                                              nullptr, use_probe_layout ? &probe_layout : nullptr);
    r.seconds_patch_stage = secondsSince(t);

    // Displacement form: δ = 0 on the input vertices, constraints n·(δ − (p − x0)) = 0.
    t = Clock::now();
    std::vector<bool> is_free(work.numVertices(), false);
    for (std::int32_t v : new_vertices)
      is_free[static_cast<std::size_t>(v)] = true;
    std::vector<PointToPlaneConstraint> shifted = flatten(constraints);
    for (PointToPlaneConstraint& c : shifted)
      c.point -= work.vertices[static_cast<std::size_t>(c.vertex)];
    std::vector<Eigen::Vector3d> displacement(work.numVertices(), Eigen::Vector3d::Zero());
    const PatchConstrainedSolver solver(work, is_free);
    solver.solve(displacement, shifted, r.relief ? p.relief_constraint_weight : p.constraint_weight);
    double sum = 0.0;
    for (std::int32_t v : new_vertices) {
      const std::size_t i = static_cast<std::size_t>(v);
      sum += displacement[i].norm();
      out.vertices[i] = normalization.invert(work.vertices[i] + displacement[i]);
    }
    r.mean_correction = sum / static_cast<double>(new_vertices.size());
    r.seconds_solve = secondsSince(t);
    return;
  }

  // Denoise: base = Taubin smoothing, as many iterations as the discrepancy principle asks.
  auto t = Clock::now();
  TriangleMesh noisy = input;
  noisy.normals.clear();
  normalization.apply(noisy);
  r.mean_edge_length = noisy.meanEdgeLength();
  r.noise_sigma = p.noise_sigma > 0.0 ? p.noise_sigma : estimateNoiseSigma(noisy);
  r.noise_estimated = !(p.noise_sigma > 0.0);
  TriangleMesh work = noisy;
  {
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
  r.seconds_base = secondsSince(t);
  out = input;
  out.normals.clear();
  for (std::size_t v = 0; v < n; ++v)
    out.vertices[v] = normalization.invert(work.vertices[v]);
  std::vector<std::int32_t> all(n);
  std::iota(all.begin(), all.end(), 0);
  r.moved_vertices = n;
  if (!use_patches_)
    return;
  r.used_patches = true;
  t = Clock::now();
  patch_parameters.error_per_bin = p.error_factor * r.noise_sigma;
  const auto constraints = patchConstraints(work, {}, all, dictionary, patch_parameters, r.patches, &noisy);
  r.seconds_patch_stage = secondsSince(t);

  // Per vertex: min α·W·|δ|² + Σ w (n·(x0 + δ) − n·p)², x0 the base, W = Σ w (α relative to the
  // patches' weight).
  t = Clock::now();
  std::vector<Eigen::Vector3d> moved(n);
#pragma omp parallel for schedule(static) num_threads(p.num_threads > 0 ? p.num_threads : omp_get_max_threads())
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
    h += p.fidelity * total * Eigen::Matrix3d::Identity();
    moved[v] = x0 + h.ldlt().solve(g);
  }
  double sum = 0.0;
  for (std::size_t v = 0; v < n; ++v) {
    sum += (moved[v] - work.vertices[v]).norm();
    out.vertices[v] = normalization.invert(moved[v]);
  }
  r.mean_correction = n ? sum / static_cast<double>(n) : 0.0;
  r.seconds_solve = secondsSince(t);
}

}  // namespace patchdict
}  // namespace pcl
