// SparsePatchInpainter — repairs a mesh with a dictionary of height-map patches (sections 4.3 and
// 5.3 of Sarkar et al. 2017), with the geometric solution as the base and the first guess:
// patches only correct it through confidence-weighted point-to-plane constraints (FINDINGS.md).
#pragma once

#include <pcl_patchdict/patch_constrained_solve.h>
#include <pcl_patchdict/patch_dictionary.h>
#include <pcl_patchdict/patch_layout.h>
#include <pcl_patchdict/patch_set.h>
#include <pcl_patchdict/triangle_mesh.h>

#include <cstdint>
#include <memory>
#include <vector>

namespace pcl {
namespace patchdict {

/** \brief Missing-vertex recovery (connectivity known, some positions unknown) with patches.
  *
  * Pipeline (all lengths in the unit-cube normalisation of the input; the output goes back):
  *  1. first guess: the uniform least-squares bi-Laplacian (Sorkine & Cohen-Or 2004), known
  *     vertices fixed — also the whole result with setUsePatches(false);
  *  2. patch layout (coarse shape → quads → frames) on the first guess, quad length L given or
  *     L = c × mean edge length (patches must span several 1-rings to infer a hidden one);
  *  3. patches extracted from the observed surface only (faces whose three vertices are known);
  *     masked OMP over the dictionary fills their unobserved bins;
  *  4. every missing vertex gets, from each patch whose square holds its tangent-plane position,
  *     a constraint n·(x − p) = 0 (p: the patch surface at the vertex's own tangent coordinates,
  *     bilinear in the bins; n: the frame's Z), weighted by a confidence (distance to the patch
  *     centre, observed fraction, masked-fit residual, agreement with the other patches);
  *  5. one joint sparse solve of bi-Laplacian energy + μ·Σ w (n·(x − p))² over the missing
  *     vertices' three coordinates. Known vertices are copied bit for bit.
  * Without a dictionary (and with patches on), a self-similar one is learned from the observed
  * patches (masked K-SVD). Deterministic for a given input and parameters, whatever the threads.
  *
  * Measured (harness cases, global/local/self-similar dictionaries): with the defaults the result
  * is within ±0.1 % of the bi-Laplacian on every scan tried. The bi-Laplacian's error there is
  * mostly tangential, which normal-only constraints cannot reduce, and the masked-OMP heights at a
  * hidden vertex are less accurate than the bi-Laplacian's along the normal, so a larger μ makes
  * things worse (armadillo 20 %: 0.4959 → 0.4962 at μ = 0.01, 0.5048 at μ = 0.3, ×1e-3).
  *
  * Only Mode::MissingVertices is implemented; Holes and Denoise are the next modes. */
class SparsePatchInpainter {
public:
  using Ptr = std::shared_ptr<SparsePatchInpainter>;
  using ConstPtr = std::shared_ptr<const SparsePatchInpainter>;

  enum class Mode { MissingVertices };

  struct Parameters {
    /// Quad length L (unit-cube units); 0 = automatic, L = quad_length_factor × mean edge length.
    double quad_length = 0.0;
    double quad_length_factor = 3.0;  ///< c of the automatic rule (measured: 3 best of 3, 4, 6)
    double patch_scale = 1.0;         ///< patch side = patch_scale × L (radius = side / √2)
    int overlap = 1;                  ///< k of the layout: 4k offset seeds per quad
    int sparsity = 8;                 ///< atoms per masked code
    double constraint_weight = 0.03;  ///< μ (measured: larger μ is worse on armadillo)
    /// Confidence terms (each 0 disables it):
    double centre_sigma = 0.5;        ///< Gaussian σ of the distance to the centre, × half the side
    double observed_power = 1.0;      ///< w ∝ (observed fraction)^power
    double fit_scale = 0.1;           ///< w ∝ 1/(1 + (fit rms / (fit_scale × mean edge))²)
    double agreement_scale = 0.1;     ///< w ∝ exp(−½ (d − d̄)² / (agreement_scale × mean edge)²)
    double min_observed_fraction = 0.2;  ///< patches less observed than this give no constraint
    /// λ: weight of the unobserved bins, filled from the first guess, in the sparse fit (0: masked
    /// OMP on the observed bins alone; 1: the first-guess patch coded as if observed).
    double first_guess_weight = 0.0;
    /// Constraint normal: the patch surface's own normal at p (from the height map's gradient),
    /// so that the plane is the surface's tangent plane; false: the frame's Z axis.
    bool surface_normals = true;
    /// N, bins per side: 0 = the dictionary's (16 for a self-similar one); a dictionary of
    /// another N is an error.
    int grid_size = 0;
    /// Self-similar dictionary (no dictionary set): atoms and K-SVD iterations.
    int self_similar_atoms = 100;
    int self_similar_iterations = 15;
    int self_similar_max_patches = 4000;  ///< evenly spaced subset of the usable patches to learn from
    int num_threads = 0;  ///< 0 = OpenMP's default
    std::uint64_t seed = 0;
  };

  struct Report {
    std::size_t missing_vertices = 0;
    std::size_t isolated_missing = 0;  ///< missing vertices in no face: left where the input had them
    bool used_patches = false;
    bool self_similar = false;       ///< the dictionary was learned from the input itself
    double mean_edge_length = 0.0;   ///< of the first guess, normalised units
    double quad_length = 0.0;        ///< L used
    double patch_side = 0.0;
    int grid_size = 0;
    int atoms = 0;
    std::size_t patches = 0;           ///< seeds of the layout
    std::size_t patches_used = 0;      ///< with enough observed bins to give constraints
    double observed_fraction = 0.0;    ///< over all patches
    std::size_t constraints = 0;
    std::size_t constrained_vertices = 0;  ///< missing vertices with at least one constraint
    double mean_correction = 0.0;          ///< mean |x − first guess| over missing vertices (normalised)
    double seconds_first_guess = 0.0, seconds_layout = 0.0, seconds_patches = 0.0,
           seconds_dictionary = 0.0, seconds_coding = 0.0, seconds_solve = 0.0;
  };

  SparsePatchInpainter() = default;

  void setInputMesh(const TriangleMesh& mesh) { input_ = std::make_shared<const TriangleMesh>(mesh); }
  void setInputMesh(const std::shared_ptr<const TriangleMesh>& mesh) { input_ = mesh; }
  /** Dictionary to code the patches with (null: self-similar, learned from the input). */
  void setDictionary(const PatchDictionary::ConstPtr& dictionary) { dictionary_ = dictionary; }
  /** Indices of the vertices whose positions are unknown (their input positions are ignored). */
  void setMissingVertices(const std::vector<int>& indices) { missing_ = indices; }
  void setMode(Mode mode) { mode_ = mode; }
  Mode getMode() const { return mode_; }
  /** false: the geometric base alone (the bi-Laplacian). */
  void setUsePatches(bool use_patches) { use_patches_ = use_patches; }
  bool getUsePatches() const { return use_patches_; }

  void setParameters(const Parameters& parameters) { parameters_ = parameters; }
  const Parameters& getParameters() const { return parameters_; }
  void setQuadLength(double quad_length) { parameters_.quad_length = quad_length; }
  void setQuadLengthFactor(double factor) { parameters_.quad_length_factor = factor; }
  void setSparsity(int sparsity) { parameters_.sparsity = sparsity; }
  void setConstraintWeight(double mu) { parameters_.constraint_weight = mu; }
  void setNumberOfThreads(int threads) { parameters_.num_threads = threads; }

  /** Repairs the input into `out` (vertex count, order and faces kept; known vertices bit-
    * identical; normals dropped). Throws Error for bad input: no mesh or faces, an index out of
    * range or repeated, no vertex missing, every vertex of a connected part missing, non-finite
    * known positions, an empty dictionary or one whose N is not the grid size asked for. */
  void process(TriangleMesh& out, Report* report = nullptr) const;

  /** The quad length the automatic rule picks for a (normalised) mesh. */
  static double automaticQuadLength(const TriangleMesh& normalised_mesh, const Parameters& parameters);

  /** Training patches for a global or local dictionary, laid out and sized by the same rules as
    * process() uses (unit-cube normalisation, L rule, layout, patch side), from a clean mesh.
    * With grid_size N. Throws Error as computePatchLayout and HeightMapPatchExtractor do. */
  static PatchSet trainingPatches(const TriangleMesh& clean_mesh, const Parameters& parameters, int grid_size);

private:
  std::shared_ptr<const TriangleMesh> input_;
  PatchDictionary::ConstPtr dictionary_;
  std::vector<int> missing_;
  Mode mode_ = Mode::MissingVertices;
  bool use_patches_ = true;
  Parameters parameters_;
};

}  // namespace patchdict
}  // namespace pcl
