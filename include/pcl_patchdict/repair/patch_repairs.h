// The three mesh repairs — missing vertices, holes, denoising — each one call with its own options
// (whose defaults are that repair's measured defaults) and its own report. Each is a geometric base
// corrected by PatchCorrection (Sarkar et al. 2017, sections 4.3 and 5.3; docs/design.md): patches
// only correct the base through confidence-weighted point-to-plane constraints.
#pragma once

#include <pcl_patchdict/coding/patch_dictionary.h>
#include <pcl_patchdict/core/triangle_mesh.h>
#include <pcl_patchdict/geometry/hole_filling.h>
#include <pcl_patchdict/repair/patch_correction.h>
#include <pcl_patchdict/repair/patch_decision.h>

#include <cstdint>
#include <string>
#include <vector>

namespace pcl {
namespace patchdict {

/** What every repair's options add to the patch stage's parameters. */
struct PatchRepairCommon : PatchCorrectionParameters {
  /// Dictionary to code the patches with (null: self-similar, learned from the input).
  PatchDictionary::ConstPtr dictionary;
  /// Whether and how the patch stage is decided; decision.mode Never: the geometric base alone
  /// (bi-Laplacian, Liepa, or Taubin), no patch stage.
  PatchDecisionOptions decision;
};

/** What every repair's report holds. */
struct PatchRepairReport {
  std::size_t moved_vertices = 0;  ///< vertices the repair may move (free, new, or all)
  bool used_patches = false;       ///< the result holds the patch stage's correction
  double mean_edge_length = 0.0;   ///< of the base, normalised units
  PatchCorrectionReport patches;   ///< the patch stage
  double mean_correction = 0.0;    ///< mean |x − base| over the moved vertices (normalised)
  double seconds_base = 0.0, seconds_patch_stage = 0.0, seconds_solve = 0.0;
};

// ---------------------------------------------------------------- missing vertices

/** Options of the missing-vertex repair; its defaults were measured (docs/results.md). */
struct MissingVerticesOptions : PatchRepairCommon {
  double constraint_weight = 0.03;  ///< μ of the joint solve
};

struct MissingVerticesReport : PatchRepairReport {
  std::size_t missing_vertices = 0;
  std::size_t isolated_missing = 0;  ///< missing vertices in no face: left where the input had them
};

/** Base = uniform least-squares bi-Laplacian (Sorkine & Cohen-Or 2004), known vertices fixed;
  * patches from the faces whose three vertices are known; one joint solve of bi-Laplacian energy
  * + μ·Σ w (n·(x − p))² over the missing vertices. `missing`: indices whose positions are unknown
  * (their input positions are ignored). `out` keeps vertex count, order and faces, the known
  * vertices bit-identical; normals are dropped. Throws Error for bad input: no mesh or faces, an
  * index out of range or repeated, no vertex missing, every vertex of a connected part missing,
  * non-finite known positions, an empty dictionary or one whose N is not the grid size. */
void fillMissingVertices(const TriangleMesh& input, const std::vector<int>& missing, TriangleMesh& out,
                         const MissingVerticesOptions& options = {}, MissingVerticesReport* report = nullptr);

// ---------------------------------------------------------------- holes

/** Holes: which settings (see HoleRepairOptions::hole_settings). */
enum class HoleSettings { Auto, Smooth, Relief };

/** Options of the hole repair: μ 0.1, fit_scale 0.02, chosen by measurement (docs/results.md,
  * "Figures behind the library's defaults"). */
struct HoleRepairOptions : PatchRepairCommon {
  HoleRepairOptions() { fit_scale = 0.02; }
  double constraint_weight = 0.1;  ///< μ of the displacement solve (smooth settings)
  /// L ≥ decision.quad_factor × the median diameter d of the filled holes. Auto runs the relief
  /// check of `decision` (checkRelief; the length unit is the mean edge) on one layout: a relief
  /// → the relief settings at the best side (the gains measured on smooth and relief scans:
  /// docs/results.md). Smooth keeps the options as given; Relief forces the relief settings. A
  /// quad_length given (> 0) is kept by both, with its patch side patch_scale × L (the paper's
  /// Fig. 8a protocol); the check then only decides relief or smooth, on at most
  /// decision.probe_max_seeds of that layout's seeds (a relief verdict is followed by a full probe
  /// that picks the patch side).
  HoleSettings hole_settings = HoleSettings::Auto;
  /// Relief settings: μ 10, overlap 2, no fit or agreement weighting.
  double relief_constraint_weight = 10.0;
  int relief_overlap = 2;
  /// How holes are chosen and filled (Liepa); its input mesh is ignored: the repair sets it.
  HoleFilling filling;
};

struct HoleRepairReport : PatchRepairReport {
  HoleFilling::Report holes;  ///< what Liepa's filling did
  bool relief = false;        ///< the relief settings were used
  double relief_gain = 0.0;   ///< best significant gain of the check (else best gain; 0: not run)
  double seconds_check = 0.0; ///< the relief check, of which:
  double seconds_check_layout = 0.0, seconds_check_patches = 0.0, seconds_check_prediction = 0.0;
};

/** Base = HoleFilling (Liepa 2003); patches from the input faces, masked OMP fills the hole; the
  * new vertices move by a displacement δ minimising Σ|Lδ|² + μ·Σ w (n·(x0+δ − p))² (δ = 0 on the
  * input vertices). `out`: the input vertices first, bit-identical, new ones appended; normals
  * dropped. Throws Error as fillMissingVertices does (non-finite positions included). */
void fillHolesWithPatches(const TriangleMesh& input, TriangleMesh& out, const HoleRepairOptions& options = {},
                          HoleRepairReport* report = nullptr);

// ---------------------------------------------------------------- denoising

/** Options of the patch denoiser: quad_length_factor 6, sparsity 20 (measured defaults). */
struct DenoiseOptions : PatchRepairCommon {
  DenoiseOptions()
  {
    quad_length_factor = 6.0;
    sparsity = 20;
  }
  /// The noise σ along the normals (normalised units; 0 = estimated, estimateNoiseSigma).
  double noise_sigma = 0.0;
  double error_factor = 0.7;  ///< ε = error_factor × σ per bin (0: fixed sparsity)
  double fidelity = 0.05;     ///< α: weight of staying at the base, relative to the patches
  /// Base: TaubinSmoother (λ 0.5, μ −0.53) with this many iterations; −1 = the first count whose
  /// rms displacement reaches discrepancy × σ (Morozov's discrepancy principle); 0 = the input.
  int base_iterations = -1;
  double discrepancy = 0.95;
  int max_base_iterations = 100;
  /// decision.mode Auto: the patches go into the result only if their estimated error (Stein's
  /// unbiased risk, below) is at least decision.min_risk_reduction below the base's; Always:
  /// applied unmeasured; Never: the Taubin base alone.
  /// The risk's divergence term by one random probe of the input along the normals, this size × σ.
  double probe_step = 0.25;
};

struct DenoiseReport : PatchRepairReport {
  double noise_sigma = 0.0;  ///< σ used (normalised units)
  int base_iterations = 0;   ///< Taubin iterations of the base
  bool noise_estimated = false;
  /// The patch stage's fate: measured when base_error ≥ 0, forced (decision Always) otherwise.
  /// used_patches is outcome Applied.
  PatchOutcome outcome = PatchOutcome::NotRun;
  /// Estimated RMS error against the unknown clean surface (normalised units; −1: not measured).
  double base_error = -1.0, patch_error = -1.0;
  double seconds_decision = 0.0;  ///< the perturbed second run of base and patches
};

/** Every patch coded to ε = error_factor × σ (or with `sparsity` atoms); each vertex moves to the
  * weighted least-squares point of its patches' tangent planes with a fidelity term α·Σw·|δ|²
  * around the Taubin base. `out` keeps vertex count, order and faces; normals dropped.
  * With decision Auto the result keeps the patches only when they are measured to help: for noise
  * of σ along the normals, Stein's unbiased risk estimate of base and patch result, mean|f − y|² −
  * σ² + 2σ²·div f, the divergence by a Monte-Carlo probe (Ramani, Blu & Unser, IEEE TIP 2008): the
  * input moved by ±probe_step·σ along the base's normals, base and patches run again on the same
  * layout (a self-similar dictionary learned again). */
void denoiseWithPatches(const TriangleMesh& input, TriangleMesh& out, const DenoiseOptions& options = {},
                        DenoiseReport* report = nullptr);

/** Estimated σ of noise along the normals: 1.4826 × median |n·(x − mean of the 1-ring)| /
  * √(1 + 1/k̄) (robust; curvature adds a small bias on clean meshes). */
double estimateNoiseSigma(const TriangleMesh& mesh);

/** The options' checks, Error with one line when a value is out of range. */
void checkMissingVerticesOptions(const MissingVerticesOptions& options);
void checkHoleRepairOptions(const HoleRepairOptions& options);
void checkDenoiseOptions(const DenoiseOptions& options);

}  // namespace patchdict
}  // namespace pcl
