// PatchCorrection — what the patches say about chosen vertices of a current surface estimate:
// point-to-plane constraints from sparse-coded height-map patches, each with a confidence weight.
#pragma once

#include <pcl_patchdict/repair/patch_constrained_solve.h>
#include <pcl_patchdict/coding/patch_dictionary.h>
#include <pcl_patchdict/quads/patch_layout.h>
#include <pcl_patchdict/patches/patch_set.h>
#include <pcl_patchdict/core/triangle_mesh.h>

#include <cstdint>
#include <memory>
#include <vector>

namespace pcl {
namespace patchdict {

/** Parameters of the patch stage shared by every repair mode (lengths in unit-cube units). */
struct PatchCorrectionParameters {
  /// Quad length L; 0 = automatic, L = quad_length_factor × mean edge length of the estimate.
  double quad_length = 0.0;
  double quad_length_factor = 3.0;
  double patch_scale = 1.0;  ///< patch side = patch_scale × L (radius = side / √2)
  int overlap = 1;           ///< k of the layout: 4k offset seeds per quad
  /// Smoothing iterations of the layout's coarse shape (the paper's 30): fewer let the quad field,
  /// and so the frames, follow a relief instead of the smooth base under it.
  int smoothing_iterations = 30;
  int sparsity = 8;          ///< at most this many atoms per code
  /// ε: coding stops once the rms residual over the observed bins is ≤ ε (0: always `sparsity`
  /// atoms). Denoising sets it from the noise level.
  double error_per_bin = 0.0;
  /// Confidence terms (each 0 disables it):
  double centre_sigma = 0.5;     ///< Gaussian σ of the distance to the centre, × half the side
  double observed_power = 1.0;   ///< w ∝ (observed fraction)^power
  double fit_scale = 0.1;        ///< w ∝ 1/(1 + (fit rms / (fit_scale × mean edge))²)
  double agreement_scale = 0.1;  ///< w ∝ exp(−½ (d − d̄)² / (agreement_scale × mean edge)²)
  double min_observed_fraction = 0.2;  ///< patches less observed than this give no constraint
  /// Constraint normal: the patch surface's own normal at p (its tangent plane); false: frame Z.
  bool surface_normals = true;
  /// N, bins per side: 0 = the dictionary's (16 for a self-similar one); another N is an error.
  int grid_size = 0;
  /// Point-cloud observed surfaces: a bin's height from the points within this many bins of its
  /// centre (HeightMapParameters::bin_reach; 0: the points in the bin, the paper's rule).
  double bin_reach = 0.0;
  int self_similar_atoms = 100;  ///< self-similar dictionary (none given): atoms,
  int self_similar_iterations = 15;     ///< K-SVD iterations,
  int self_similar_max_patches = 4000;  ///< and an evenly spaced subset of the usable patches
  int num_threads = 0;                  ///< 0 = OpenMP's default
  std::uint64_t seed = 0;
};

/** What the patch stage did. */
struct PatchCorrectionReport {
  double mean_edge_length = 0.0;  ///< of the estimate
  double quad_length = 0.0;       ///< L used
  double patch_side = 0.0;
  int grid_size = 0;
  int atoms = 0;
  bool self_similar = false;         ///< the dictionary was learned from the observed patches
  std::size_t patches = 0;           ///< seeds of the layout
  std::size_t patches_used = 0;      ///< observed enough to give constraints
  double observed_fraction = 0.0;    ///< over all patches
  double mean_atoms = 0.0;           ///< non-zeros per code
  std::size_t constraints = 0;
  std::size_t constrained_vertices = 0;
  double seconds_layout = 0.0, seconds_patches = 0.0, seconds_dictionary = 0.0, seconds_coding = 0.0,
         seconds_constraints = 0.0;
};

/** \brief From an estimate of the surface (normalised), the part of it that was observed, and a
  * dictionary: for each target vertex, one point-to-plane constraint per patch whose square holds
  * the vertex (Sarkar et al. 2017, sections 4–5, with the combination of docs/design.md, "Findings that shaped it").
  *
  *  1. patch layout (coarse shape → quads → frames) on the estimate;
  *  2. height maps of the observed faces only; masked OMP (or OMP to the error target ε) fills
  *     every bin from the dictionary — a self-similar one is learned from the observed patches
  *     (masked K-SVD) when none is given;
  *  3. a target vertex x0 inside a patch's square gets n·(x − p) = 0, p the coded patch surface at
  *     x0's tangent coordinates (bilinear in the bins), n its normal there, weighted by closeness
  *     to the centre, observed fraction, fit residual, and agreement with the other patches.
  * Deterministic for a given input and parameters, whatever the thread count. */
class PatchCorrection {
public:
  using Ptr = std::shared_ptr<PatchCorrection>;
  using ConstPtr = std::shared_ptr<const PatchCorrection>;

  /** The current estimate (unit-cube normalised): layout, frames and the targets' positions. A
    * point cloud (no faces) works with a layout given (setLayout); its normals, if any, tell the
    * targets' sides (a target facing away from a patch takes no constraint from it). */
  void setEstimate(const std::shared_ptr<const TriangleMesh>& estimate) { estimate_ = estimate; }
  /** One flag per face of the estimate: true = its surface is data (empty: every face). */
  void setObservedFaces(const std::vector<bool>& observed) { observed_faces_ = observed; }
  /** Samples the patches from this surface instead of the estimate's observed faces (denoising:
    * the noisy input, while the estimate is the smoothed base). Any vertex count. */
  void setObservedSurface(const std::shared_ptr<const TriangleMesh>& surface) { observed_surface_ = surface; }
  void setTargets(const std::vector<std::int32_t>& targets) { targets_ = targets; }
  void setDictionary(const PatchDictionary::ConstPtr& dictionary) { dictionary_ = dictionary; }
  void setParameters(const PatchCorrectionParameters& parameters) { parameters_ = parameters; }
  /** A layout of the estimate made before (computePatchLayout with layoutParameters at this
    * correction's L, possibly reseeded at another overlap): used instead of computing one again.
    * Its L must be this correction's (Error otherwise). Shared, like every input: null = compute one. */
  void setLayout(const std::shared_ptr<const PatchLayout>& layout) { layout_ = layout; }
  /** The layout parameters a correction with these parameters uses at quad length L. */
  static PatchLayoutParameters layoutParameters(const PatchCorrectionParameters& parameters, double quad_length);
  const PatchCorrectionParameters& getParameters() const { return parameters_; }

  /** constraints[i]: those of targets[i]. Throws Error for an unset or empty estimate, flags of
    * the wrong size, a target out of range, no observed face, bad parameters, or a dictionary
    * that is empty or of another grid size. */
  void compute(std::vector<std::vector<PointToPlaneConstraint>>& constraints,
               PatchCorrectionReport* report = nullptr) const;

  /** Steps 1–2 alone: the patches compute() samples (observed bins marked), for checks that
    * must see the same patches. Throws Error as compute() does. */
  PatchSet observedPatches(PatchCorrectionReport* report = nullptr) const;
  /** The same on one layout, once per patch side = scale × L (probes of several patch sizes). */
  std::vector<PatchSet> observedPatchesAtScales(const std::vector<double>& patch_scales,
                                                PatchCorrectionReport* report = nullptr) const;

  /** The self-similar dictionary compute() learns when none is given: masked K-SVD of (an evenly
    * spaced subset of at most self_similar_max_patches of) the given patches. */
  static PatchDictionary::ConstPtr learnSelfSimilar(const Eigen::MatrixXd& heights, const ObservationMask& mask,
                                                    const PatchCorrectionParameters& parameters);

  /** L for a normalised mesh: the given quad length, or factor × mean edge length. */
  static double quadLength(const TriangleMesh& normalised_mesh, const PatchCorrectionParameters& parameters);
  /** Throws Error when a parameter is out of range. */
  static void checkParameters(const PatchCorrectionParameters& parameters);

  /** Training patches for a global or local dictionary, laid out and sized by the same rules as
    * compute() (unit-cube normalisation, L rule, layout, patch side), from a clean mesh. */
  static PatchSet trainingPatches(const TriangleMesh& clean_mesh, const PatchCorrectionParameters& parameters,
                                  int grid_size);

private:
  void checkInput() const;

  std::shared_ptr<const TriangleMesh> estimate_;
  std::vector<bool> observed_faces_;
  std::shared_ptr<const TriangleMesh> observed_surface_;
  std::shared_ptr<const PatchLayout> layout_;
  std::vector<std::int32_t> targets_;
  PatchDictionary::ConstPtr dictionary_;
  PatchCorrectionParameters parameters_;
};

}  // namespace patchdict
}  // namespace pcl
