// SparsePatchInpainter (see sparse_patch_inpainter.h): the compatibility wrapper of the three
// repairs of patch_repairs.h — the mode's parameters converted to its options, its function
// called, its report copied.
#include <pcl_patchdict/repair/sparse_patch_inpainter.h>

namespace pcl {
namespace patchdict {

namespace {

void setCommon(const SparsePatchInpainter::Parameters& p, const PatchDictionary::ConstPtr& dictionary,
               bool use_patches, PatchRepairCommon& options)
{
  static_cast<PatchCorrectionParameters&>(options) = p;
  options.dictionary = use_patches ? dictionary : nullptr;
  options.use_patches = use_patches;
}

void copyCommon(const PatchRepairReport& from, SparsePatchInpainter::Report& r)
{
  r.moved_vertices = from.moved_vertices;
  r.used_patches = from.used_patches;
  r.mean_edge_length = from.mean_edge_length;
  r.patches = from.patches;
  r.mean_correction = from.mean_correction;
  r.seconds_base = from.seconds_base;
  r.seconds_patch_stage = from.seconds_patch_stage;
  r.seconds_solve = from.seconds_solve;
}

}  // namespace

SparsePatchInpainter::Parameters SparsePatchInpainter::defaultParameters(Mode mode)
{
  Parameters parameters;
  if (mode == Mode::Holes) {
    const HoleRepairOptions holes;
    parameters.constraint_weight = holes.constraint_weight;
    parameters.fit_scale = holes.fit_scale;
  } else if (mode == Mode::Denoise) {
    const DenoiseOptions denoise;
    parameters.quad_length_factor = denoise.quad_length_factor;
    parameters.sparsity = denoise.sparsity;
  }
  return parameters;
}

MissingVerticesOptions SparsePatchInpainter::missingVerticesOptions() const
{
  const Parameters& p = parameters_;
  MissingVerticesOptions options;
  setCommon(p, dictionary_, use_patches_, options);
  options.constraint_weight = p.constraint_weight;
  return options;
}

HoleRepairOptions SparsePatchInpainter::holeRepairOptions() const
{
  const Parameters& p = parameters_;
  HoleRepairOptions options;
  setCommon(p, dictionary_, use_patches_, options);
  options.constraint_weight = p.constraint_weight;
  options.hole_quad_factor = p.hole_quad_factor;
  options.hole_settings = p.hole_settings;
  options.relief_probe_factors = p.relief_probe_factors;
  options.relief_probe_radius = p.relief_probe_radius;
  options.relief_probe_max_seeds = p.relief_probe_max_seeds;
  options.relief_gain = p.relief_gain;
  options.relief_min_improvement = p.relief_min_improvement;
  options.relief_constraint_weight = p.relief_constraint_weight;
  options.relief_overlap = p.relief_overlap;
  options.filling = hole_filling_;
  return options;
}

DenoiseOptions SparsePatchInpainter::denoiseOptions() const
{
  const Parameters& p = parameters_;
  DenoiseOptions options;
  setCommon(p, dictionary_, use_patches_, options);
  options.noise_sigma = p.noise_sigma;
  options.error_factor = p.error_factor;
  options.fidelity = p.fidelity;
  options.base_iterations = p.base_iterations;
  options.discrepancy = p.discrepancy;
  options.max_base_iterations = p.max_base_iterations;
  return options;
}

void SparsePatchInpainter::process(TriangleMesh& out, Report* report) const
{
  Report local_report;
  Report& r = report ? *report : local_report;
  r = Report();
  r.mode = mode_;
  // Every parameter is checked, whatever the mode, as each repair checks its own options; the
  // mode's function then checks the input ("no input mesh" when empty).
  checkMissingVerticesOptions(missingVerticesOptions());
  checkHoleRepairOptions(holeRepairOptions());
  checkDenoiseOptions(denoiseOptions());
  static const TriangleMesh no_input;
  const TriangleMesh& input = input_ ? *input_ : no_input;
  if (mode_ == Mode::MissingVertices) {
    const MissingVerticesOptions options = missingVerticesOptions();
    MissingVerticesReport done;
    fillMissingVertices(input, missing_, out, options, &done);
    copyCommon(done, r);
    r.missing_vertices = done.missing_vertices;
    r.isolated_missing = done.isolated_missing;
  } else if (mode_ == Mode::Holes) {
    const HoleRepairOptions options = holeRepairOptions();
    HoleRepairReport done;
    fillHolesWithPatches(input, out, options, &done);
    copyCommon(done, r);
    r.holes = done.holes;
    r.relief = done.relief;
    r.relief_gain = done.relief_gain;
    r.seconds_check = done.seconds_check;
    r.seconds_check_layout = done.seconds_check_layout;
    r.seconds_check_patches = done.seconds_check_patches;
    r.seconds_check_prediction = done.seconds_check_prediction;
  } else {
    const DenoiseOptions options = denoiseOptions();
    DenoiseReport done;
    denoiseWithPatches(input, out, options, &done);
    copyCommon(done, r);
    r.noise_sigma = done.noise_sigma;
    r.base_iterations = done.base_iterations;
    r.noise_estimated = done.noise_estimated;
  }
}

}  // namespace patchdict
}  // namespace pcl
