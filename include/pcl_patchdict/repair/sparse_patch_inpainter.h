// SparsePatchInpainter — repairs a mesh with a dictionary of height-map patches (sections 4.3 and
// 5.3 of Sarkar et al. 2017), with the geometric solution as the base and the first guess:
// patches only correct it through confidence-weighted point-to-plane constraints (docs/design.md, "Findings that shaped it").
#pragma once

#include <pcl_patchdict/geometry/hole_filling.h>
#include <pcl_patchdict/repair/patch_correction.h>
#include <pcl_patchdict/repair/patch_repairs.h>
#include <pcl_patchdict/coding/patch_dictionary.h>
#include <pcl_patchdict/core/triangle_mesh.h>

#include <cstdint>
#include <memory>
#include <vector>

namespace pcl {
namespace patchdict {

/** \brief Compatibility wrapper: the three repairs of patch_repairs.h behind one class.
  *
  * New code calls fillMissingVertices, fillHolesWithPatches or denoiseWithPatches (each with its
  * own options, whose defaults are that repair's). This class keeps the older shape for the tool
  * and existing callers: the mode is fixed at construction and the parameters start at that
  * mode's defaults (defaultParameters(mode)), so no mode can run with another's settings.
  * process() converts the parameters to the mode's options and calls its function: the same
  * result, bit for bit. The input is shared (setInputMesh takes a ConstPtr, as every class of the
  * library that keeps an input does). See patch_repairs.h for what each mode does. */
class SparsePatchInpainter {
public:
  using Ptr = std::shared_ptr<SparsePatchInpainter>;
  using ConstPtr = std::shared_ptr<const SparsePatchInpainter>;

  enum class Mode { MissingVertices, Holes, Denoise };

  struct Parameters : PatchCorrectionParameters {
    double constraint_weight = 0.03;  ///< μ of the missing-vertex and hole solves
    /// Holes: L ≥ this × median diameter of the filled holes (normalised units).
    double hole_quad_factor = 0.6;  ///< (larger sides lost to Liepa on the relief test)
    /// Holes: which settings — Auto measures with checkPatchPrediction whether the dictionary
    /// predicts a hidden disc (relief_probe_radius × the median hole diameter d, at most 0.3 × the
    /// patch side) better than a biharmonic fill, for patch sides relief_probe_factors × d on one
    /// layout; gain ≥ relief_gain with a margin ≥ relief_min_improvement → the relief settings at
    /// the best side (the gains measured on smooth and relief scans: docs/results.md). Smooth
    /// keeps the parameters as given; Relief forces the relief settings. A quad_length given by
    /// the caller (> 0) is kept by both, with its patch side patch_scale × L (the paper's Fig. 8a
    /// protocol); the check then probes that layout at that patch side, and only decides relief or
    /// smooth.
    using HoleSettings = pcl::patchdict::HoleSettings;
    HoleSettings hole_settings = HoleSettings::Auto;
    std::vector<double> relief_probe_factors{0.8, 1.2, 1.6};  ///< patch sides, × d (one layout: the smooth L, if automatic)
    double relief_probe_radius = 0.35;  ///< hidden disc radius of the probe, × d
    /// The verdict probe on the smooth settings' layout uses at most this many of its seeds, evenly
    /// spaced (0: all): it needs tens of test patches, not thousands.
    /// A relief verdict is followed by a full probe that picks the patch side.
    int relief_probe_max_seeds = 600;
    double relief_gain = 1.3;  ///< (a higher bar missed the sole at radius 0.05)
    /// …and only if the dictionary's error is below the biharmonic one by this × mean edge.
    double relief_min_improvement = 0.1;
    /// Relief settings: μ 10, overlap 2, no fit or agreement weighting (the relief's own patches fit and agree).
    double relief_constraint_weight = 10.0;
    int relief_overlap = 2;
    /// Denoise: the noise σ along the normals (normalised units; 0 = estimated).
    double noise_sigma = 0.0;
    double error_factor = 0.7;  ///< ε = error_factor × σ per bin (0: fixed sparsity)
    double fidelity = 0.05;     ///< α: weight of staying at the base, relative to the patches
    /// Denoise base: TaubinSmoother (λ 0.5, μ −0.53, inverse-distance weights) with this many
    /// iterations; −1 = automatic, the first count whose rms displacement reaches discrepancy × σ
    /// (Morozov's discrepancy principle); 0 = the noisy input itself.
    int base_iterations = -1;
    /// (chosen by measurement at noise 0.5 × edge: docs/results.md)
    double discrepancy = 0.95;
    int max_base_iterations = 100;
  };

  struct Report {
    Mode mode = Mode::MissingVertices;
    std::size_t missing_vertices = 0;
    std::size_t isolated_missing = 0;  ///< missing vertices in no face: left where the input had them
    std::size_t moved_vertices = 0;    ///< vertices the mode may move (free, new, or all)
    bool used_patches = false;
    double mean_edge_length = 0.0;     ///< of the base, normalised units
    double noise_sigma = 0.0;          ///< denoise: σ used (normalised units)
    int base_iterations = 0;           ///< denoise: Taubin iterations of the base
    bool noise_estimated = false;
    HoleFilling::Report holes;         ///< holes mode: what Liepa's filling did
    bool relief = false;               ///< holes mode: the relief settings were used
    double relief_gain = 0.0;          ///< holes mode: best significant gain of the check (else best gain; 0: not run)
    double seconds_check = 0.0;        ///< the relief check, of which:
    double seconds_check_layout = 0.0, seconds_check_patches = 0.0, seconds_check_prediction = 0.0;
    PatchCorrectionReport patches;     ///< the patch stage
    double mean_correction = 0.0;      ///< mean |x − base| over the moved vertices (normalised)
    double seconds_base = 0.0, seconds_patch_stage = 0.0, seconds_solve = 0.0;
  };

  /** A repair of this mode, its parameters at defaultParameters(mode). */
  explicit SparsePatchInpainter(Mode mode) : mode_(mode), parameters_(defaultParameters(mode)) {}

  /** The measured defaults of a mode: those of its options struct (MissingVerticesOptions,
    * HoleRepairOptions, DenoiseOptions). A Parameters built by hand has the missing-vertex ones:
    * start from this (or getParameters()) before setParameters. */
  static Parameters defaultParameters(Mode mode);

  /** The mesh to repair, shared (kept alive until replaced). */
  void setInputMesh(const std::shared_ptr<const TriangleMesh>& mesh) { input_ = mesh; }
  /** Dictionary to code the patches with (null: self-similar, learned from the input). */
  void setDictionary(const PatchDictionary::ConstPtr& dictionary) { dictionary_ = dictionary; }
  /** Holes mode: how holes are chosen and filled (its input mesh is ignored: process() sets it). */
  void setHoleFilling(const HoleFilling& filling) { hole_filling_ = filling; }
  /** Indices of the vertices whose positions are unknown (their input positions are ignored). */
  void setMissingVertices(const std::vector<int>& indices) { missing_ = indices; }
  Mode getMode() const { return mode_; }
  /** false: the geometric base alone (bi-Laplacian, Liepa, or the input for Denoise). */
  void setUsePatches(bool use_patches) { use_patches_ = use_patches; }
  bool getUsePatches() const { return use_patches_; }

  void setParameters(const Parameters& parameters) { parameters_ = parameters; }
  const Parameters& getParameters() const { return parameters_; }
  void setQuadLength(double quad_length) { parameters_.quad_length = quad_length; }
  void setQuadLengthFactor(double factor) { parameters_.quad_length_factor = factor; }
  void setSparsity(int sparsity) { parameters_.sparsity = sparsity; }
  void setConstraintWeight(double mu) { parameters_.constraint_weight = mu; }
  void setNumberOfThreads(int threads) { parameters_.num_threads = threads; }

  /** Repairs the input into `out`: MissingVertices and Denoise keep vertex count, order and faces
    * (known vertices bit-identical); Holes keeps the input vertices first, bit-identical, and
    * appends new ones. Normals are dropped. Throws Error for bad input: no mesh or faces, a
    * missing index out of range or repeated, no vertex missing, every vertex of a connected part
    * missing, non-finite positions, an empty dictionary or one whose N is not the grid size. */
  void process(TriangleMesh& out, Report* report = nullptr) const;

  /** pcl::patchdict::estimateNoiseSigma. */
  static double estimateNoiseSigma(const TriangleMesh& mesh) { return pcl::patchdict::estimateNoiseSigma(mesh); }

private:
  /// The parameters as each repair's options (the dictionary, patches and hole filling included).
  MissingVerticesOptions missingVerticesOptions() const;
  HoleRepairOptions holeRepairOptions() const;
  DenoiseOptions denoiseOptions() const;

  std::shared_ptr<const TriangleMesh> input_;
  PatchDictionary::ConstPtr dictionary_;
  std::vector<int> missing_;
  HoleFilling hole_filling_;
  Mode mode_;
  bool use_patches_ = true;
  Parameters parameters_;
};

}  // namespace patchdict
}  // namespace pcl
