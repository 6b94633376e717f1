// fillHolesWithPatches (patch_repairs.h): Liepa's fill (SGP 2003) as the base, the relief check
// that chooses the patch settings, and the displacement solve of the new vertices.
#include <pcl_patchdict/repair/patch_repairs.h>

#include "repair/repair_common.h"

#include <pcl_patchdict/core/error.h>
#include <pcl_patchdict/core/normalization.h>
#include <pcl_patchdict/repair/patch_constrained_solve.h>
#include <pcl_patchdict/repair/patch_prediction_check.h>

#include <algorithm>
#include <cmath>
#include <string>

namespace pcl {
namespace patchdict {

namespace {

using detail::Clock;
using detail::secondsSince;

/** One run of the relief check (see PatchDecisionOptions::probe_factors). */
struct ReliefProbe {
  double quad_length = 0.0;     ///< of the layout probed
  double best_scale = 1.0;      ///< patch side of the best significant probe, × quad_length
  double best_any_scale = 1.0;  ///< patch side of the best probe, significant or not
  double best_significant = 0.0, best_any = 0.0;  ///< gains
  double seconds_layout = 0.0, seconds_patches = 0.0, seconds_prediction = 0.0;
};

/** Evenly spaced seeds of `layout`, at most `max_seeds` (null when the layout has no more). */
std::shared_ptr<const PatchLayout> subsampledLayout(const PatchLayout& layout, int max_seeds)
{
  if (!(max_seeds > 0 && layout.seeds.size() > static_cast<std::size_t>(max_seeds)))
    return nullptr;
  auto subset = std::make_shared<PatchLayout>();
  subset->quad_length = layout.quad_length;
  const std::size_t count = static_cast<std::size_t>(max_seeds);
  for (std::size_t i = 0; i < count; ++i) {
    const std::size_t s = i * layout.seeds.size() / count;
    subset->seeds.push_back(layout.seeds[s]);
    subset->frames.push_back(layout.frames[s]);
    subset->seed_faces.push_back(layout.seed_faces[s]);
  }
  return subset;
}

/** Lays quads of side `quad_length` (overlap k) on `work` into `layout`, widens the patches on its
  * seeds to each probe side (decision.probe_factors × d, or fixed_scale × quad_length when given),
  * and asks checkRelief whether the dictionary predicts a hidden disc better than a biharmonic fill. */
ReliefProbe probeRelief(const std::shared_ptr<const TriangleMesh>& work, const std::vector<bool>& observed,
                        const HoleRepairOptions& p, double median_diameter, double mean_edge_length,
                        double quad_length, int overlap, const std::shared_ptr<PatchLayout>& layout,
                        int max_seeds = 0, double fixed_scale = 0.0)
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
    for (double factor : p.decision.probe_factors)
      scales.push_back(factor * median_diameter / quad_length);
  computePatchLayout(*work, PatchCorrection::layoutParameters(probe, quad_length), *layout);
  result.seconds_layout = secondsSince(t);
  t = Clock::now();
  const std::shared_ptr<const PatchLayout> subset = subsampledLayout(*layout, max_seeds);
  PatchCorrection correction;
  correction.setEstimate(work);
  correction.setObservedFaces(observed);
  correction.setDictionary(p.dictionary);
  correction.setParameters(probe);
  correction.setLayout(subset ? subset : layout);
  const std::vector<PatchSet> sets = correction.observedPatchesAtScales(scales);
  result.seconds_patches = secondsSince(t);
  t = Clock::now();
  std::vector<double> sides;
  for (double scale : scales)
    sides.push_back(scale * quad_length);
  const ReliefVerdict verdict =
      checkRelief(sets, sides, median_diameter, mean_edge_length, p.decision, p.dictionary, probe);
  result.best_significant = verdict.best_significant;
  result.best_any = verdict.best_any;
  if (verdict.significant_side >= 0)
    result.best_scale = scales[static_cast<std::size_t>(verdict.significant_side)];
  if (verdict.any_side >= 0)
    result.best_any_scale = scales[static_cast<std::size_t>(verdict.any_side)];
  result.seconds_prediction = secondsSince(t);
  return result;
}

void addProbeTimes(const ReliefProbe& probe, HoleRepairReport& r)
{
  r.seconds_check_layout += probe.seconds_layout;
  r.seconds_check_patches += probe.seconds_patches;
  r.seconds_check_prediction += probe.seconds_prediction;
}

/** What the relief check decided: the patch stage's parameters, and the layout to reuse (null:
  * the patch stage makes its own). */
struct HoleSettingsChoice {
  PatchCorrectionParameters parameters;
  std::shared_ptr<const PatchLayout> layout;
};

/** Relief or smooth surface? Measured, not assumed: can the dictionary predict a hidden disc of
  * the holes' size from the intact patches better than a biharmonic fill can? `parameters` holds
  * the smooth settings (L already at least decision.quad_factor × d when automatic). */
HoleSettingsChoice chooseHoleSettings(const std::shared_ptr<const TriangleMesh>& work,
                                      const std::vector<bool>& observed, const HoleRepairOptions& p,
                                      double median_diameter, bool automatic_quad_length,
                                      PatchCorrectionParameters parameters, HoleRepairReport& r)
{
  HoleSettingsChoice choice;
  const auto check_start = Clock::now();
  const double relief_length = p.decision.probe_factors.front() * median_diameter;
  // The verdict is probed on the layout the smooth settings would use, when their L is
  // automatic: a smooth verdict (the scans) then costs one layout, not two.
  // A quad length given by the caller is kept in both settings, with its patch side
  // (patch_scale × L): the probe then only decides relief or smooth, on that layout.
  const bool shared_layout = parameters.quad_length > 0.0;
  const bool forced_relief = p.hole_settings == HoleSettings::Relief;
  const auto probe_layout = std::make_shared<PatchLayout>();
  ReliefProbe probe;
  if (!forced_relief)
    probe = probeRelief(work, observed, p, median_diameter, r.mean_edge_length,
                        shared_layout ? parameters.quad_length : relief_length, shared_layout ? parameters.overlap : 1,
                        probe_layout, shared_layout ? p.decision.probe_max_seeds : 0,
                        automatic_quad_length ? 0.0 : parameters.patch_scale);
  addProbeTimes(probe, r);
  r.relief_gain = probe.best_significant > 0.0 ? probe.best_significant : probe.best_any;
  r.relief = forced_relief || probe.best_significant >= p.decision.relief_gain;
  if (!r.relief) {
    r.seconds_check = secondsSince(check_start);
    if (shared_layout)  // exactly the layout the smooth settings would make
      choice.layout = probe_layout;
    choice.parameters = parameters;
    return choice;
  }
  if (automatic_quad_length) {
    // Relief: quads at the smallest probe's side (0.8 d), the best probe's patch side chosen
    // on them. (Choosing on the smooth settings' denser quads instead gave 1 % more error on
    // average on the harness's sole, knurl and tiles holes, knurl 0.035 +32 %.) A caller-given
    // L keeps its quads and patch side.
    if (forced_relief || std::abs(relief_length - probe.quad_length) > 1e-12 * relief_length) {
      probe = probeRelief(work, observed, p, median_diameter, r.mean_edge_length, relief_length, 1, probe_layout);
      addProbeTimes(probe, r);
    }
    if (forced_relief)
      r.relief_gain = probe.best_significant > 0.0 ? probe.best_significant : probe.best_any;
    parameters.quad_length = relief_length;
    // In auto mode the verdict was significant on the first probe; should no side of the
    // second clear the margin, its best gain decides rather than the first side by default.
    parameters.patch_scale = forced_relief || probe.best_significant > 0.0 ? probe.best_scale : probe.best_any_scale;
  }
  parameters.overlap = p.relief_overlap;
  parameters.fit_scale = 0.0;
  parameters.agreement_scale = 0.0;
  r.seconds_check = secondsSince(check_start);
  // The probe's coarse shape and quads, reseeded at the relief overlap, not made again (no
  // probe ran when a caller-given L is forced to the relief settings).
  if (automatic_quad_length || !forced_relief) {
    reseedPatchLayout(*work, p.relief_overlap, *probe_layout);
    choice.layout = probe_layout;
  }
  choice.parameters = parameters;
  return choice;
}

/** Median diameter of the filled holes, normalised (0: none filled). */
double medianFilledDiameter(const HoleFilling::Report& holes, double scale)
{
  std::vector<double> diameters;
  for (const auto& hole : holes.holes)
    if (hole.filled())
      diameters.push_back(scale * hole.diameter);
  std::nth_element(diameters.begin(), diameters.begin() + static_cast<std::ptrdiff_t>(diameters.size() / 2),
                   diameters.end());
  return diameters.empty() ? 0.0 : diameters[diameters.size() / 2];
}

/** Displacement form: δ = 0 on the input vertices, constraints n·(δ − (p − x0)) = 0; the new
  * vertices of `out` moved to x0 + δ (in the input's frame). */
void solveDisplacement(const TriangleMesh& work, const std::vector<std::int32_t>& new_vertices,
                       const std::vector<std::vector<PointToPlaneConstraint>>& constraints, double mu,
                       const UnitCubeNormalization& normalization, TriangleMesh& out, HoleRepairReport& r)
{
  std::vector<bool> is_free(work.numVertices(), false);
  for (std::int32_t v : new_vertices)
    is_free[static_cast<std::size_t>(v)] = true;
  std::vector<PointToPlaneConstraint> shifted = detail::flatten(constraints);
  for (PointToPlaneConstraint& c : shifted)
    c.point -= work.vertices[static_cast<std::size_t>(c.vertex)];
  std::vector<Eigen::Vector3d> displacement(work.numVertices(), Eigen::Vector3d::Zero());
  const PatchConstrainedSolver solver(work, is_free);
  solver.solve(displacement, shifted, mu);
  double sum = 0.0;
  for (std::int32_t v : new_vertices) {
    const std::size_t i = static_cast<std::size_t>(v);
    sum += displacement[i].norm();
    out.vertices[i] = normalization.invert(work.vertices[i] + displacement[i]);
  }
  r.mean_correction = sum / static_cast<double>(new_vertices.size());
}

}  // namespace

void checkHoleRepairOptions(const HoleRepairOptions& p)
{
  PatchCorrection::checkParameters(p);
  using detail::checkFinite;
  checkFinite(p.constraint_weight, p.constraint_weight >= 0.0, "the constraint weight μ must be ≥ 0");
  p.decision.check();
  const char* relief = "bad relief settings";
  checkFinite(p.relief_constraint_weight, p.relief_constraint_weight >= 0.0, relief);
  if (p.relief_overlap < 0)
    throw Error(relief);
}

void fillHolesWithPatches(const TriangleMesh& input, TriangleMesh& out, const HoleRepairOptions& p,
                          HoleRepairReport* report)
{
  HoleRepairReport local_report;
  HoleRepairReport& r = detail::freshReport(report, local_report);
  checkHoleRepairOptions(p);
  const UnitCubeNormalization normalization = detail::checkedNormalization(input);

  // Base: Liepa's fill of the input (normals dropped); the new vertices are the ones after n.
  auto t = Clock::now();
  HoleFilling filling = p.filling;
  const std::size_t n = input.numVertices();
  auto input_without_normals = std::make_shared<TriangleMesh>(input);
  input_without_normals->normals.clear();
  filling.setInputMesh(input_without_normals);
  filling.process(out, &r.holes);
  r.seconds_base = secondsSince(t);
  std::vector<std::int32_t> new_vertices;
  for (std::size_t v = n; v < out.numVertices(); ++v)
    new_vertices.push_back(static_cast<std::int32_t>(v));
  r.moved_vertices = new_vertices.size();
  const auto work = std::make_shared<TriangleMesh>(out);  // shared with the patch stage
  normalization.apply(*work);
  r.mean_edge_length = work->meanEdgeLength();
  if (p.decision.mode == PatchDecision::Never || new_vertices.empty())
    return;
  r.used_patches = true;

  // L sees the rim: at least decision.quad_factor × the median diameter of the filled holes.
  t = Clock::now();
  const double median_diameter = medianFilledDiameter(r.holes, normalization.scale);
  PatchCorrectionParameters patch_parameters = p;
  const bool automatic_quad_length = patch_parameters.quad_length <= 0.0;
  if (automatic_quad_length && median_diameter > 0.0)
    patch_parameters.quad_length = std::max(PatchCorrection::quadLength(*work, p), p.decision.quad_factor * median_diameter);
  std::vector<bool> observed(work->numFaces(), false);
  std::fill(observed.begin(), observed.begin() + static_cast<std::ptrdiff_t>(input.numFaces()), true);
  HoleSettingsChoice choice{patch_parameters, nullptr};
  if (p.hole_settings != HoleSettings::Smooth && median_diameter > 0.0)
    choice = chooseHoleSettings(work, observed, p, median_diameter, automatic_quad_length, patch_parameters, r);
  const auto constraints = detail::patchConstraints(work, observed, new_vertices, p.dictionary, choice.parameters,
                                                    r.patches, nullptr, choice.layout);
  r.seconds_patch_stage = secondsSince(t);

  t = Clock::now();
  solveDisplacement(*work, new_vertices, constraints, r.relief ? p.relief_constraint_weight : p.constraint_weight,
                    normalization, out, r);
  r.seconds_solve = secondsSince(t);
}

}  // namespace patchdict
}  // namespace pcl
