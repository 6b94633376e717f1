// PatchCodec — a surface stored as its quad mesh plus a few sparse coefficients per patch over a
// dictionary both sides hold (section 5.2 and Table 1 of Sarkar et al. 2017): the .pdc format.
#pragma once

#include <pcl_patchdict/coding/patch_dictionary.h>
#include <pcl_patchdict/core/triangle_mesh.h>

#include <cstdint>
#include <memory>
#include <string>

namespace pcl {
namespace patchdict {

struct PatchCodecParameters {
  double quad_length = 0.05;  ///< L in unit-cube units: the quad mesh's edge length
  /** Patch side / L: patches larger than their quads cover the quads' corners however the lattice
    * bends, and overlap their neighbours, so every point of the surface gets several estimates. */
  double patch_scale = 1.25;
  int overlap = 0;            ///< k: 4k extra seeds per quad (each one more patch to store)
  int coefficients = 20;      ///< non-zeros per patch at most (the paper's 20)
  /** Fewer non-zeros where they are not needed: a patch stops taking atoms once the RMS error of
    * its observed bins is below target_error × L (0: every patch takes `coefficients`). The
    * paper's Table 1 stores ~19 entities per patch, quad mesh included, so its patches too used
    * fewer than 20 on average. */
  double target_error = 0.0;
  /** Rate–distortion allocation of atoms across patches: each keeps the code of k ≤ its cap atoms
    * (OMP with at most k) that minimises E_k + atom_cost × L² × k, where E_k is the summed squared
    * error of its observed bins (0: off). The cap is `coefficients` for quad patches and a quarter
    * of the kept bins for coverage patches. One price for every patch puts the atoms where they
    * remove the most error (at equal entities it beats `target_error`; figures in docs/). Both
    * may be set: the error target then also ends each code early. */
  double atom_cost = 0.0;
  int coefficient_bits = 6;   ///< uniform quantiser: the 99th percentile of |coefficient| maps to 2^(bits−1) − 1
  int position_bits = 10;     ///< quad-mesh vertex grid over the unit cube (seed offsets absorb its error)
  int subdivision = 0;        ///< splits per quad side of the decoded mesh; 0 = grid size / 2
  /** Laplacian iterations of the coarse shape the quads are laid on. Fewer than the layout's 30:
    * a heavily smoothed shape loses thin parts (the bunny's ears), whose quads then go missing from
    * the file (figures in docs/). */
  int smoothing_iterations = 5;
  /** Move the quad vertices from the smoothed coarse shape onto the input before storing them, so
    * patches code small residual heights rather than the smoothing's shrinkage. */
  bool project_quads = true;
  /** Store the input's own faces and each vertex's place on the quad mesh; the decoder then rebuilds
    * the input's connectivity instead of the subdivided quad mesh (costs bytes, see Report). */
  bool keep_connectivity = false;
  int location_bits = 10;  ///< barycentric precision of a vertex's place (keep_connectivity only)
  /** Coverage patches: where the decoded quad-mesh surface misses the input by more than this
    * many L (thin parts narrower than the quads — ears, fingers — have no quads at a large L),
    * patches with stored frames cover it; 0 turns them off. Not with keep_connectivity. */
  double coverage_tolerance = 0.1;
  /** At most this many coverage patches per quad-mesh patch. */
  double coverage_budget = 1.0;
  std::uint64_t seed = 1;
  int num_threads = 0;
};

/** \brief Encoder and decoder of .pdc data.
  *
  * Encoding: unit-cube normalisation; coarse shape (Laplacian smoothing) and field-aligned quad
  * mesh at L (QuadRemesher); quad vertices projected onto the input and quantised; frames and seeds
  * from the *quantised* quad mesh (computeQuadFrames, vertex normals from the faces), exactly as
  * the decoder will derive them, so frames are never stored; exact height maps of the input at
  * those seeds; masked OMP with `coefficients` atoms; coefficients uniformly quantised. Then the
  * encoder decodes what it wrote: parts of the input the result misses (no quads reach them)
  * get coverage patches, whose frames are stored (seed on the position grid, octahedral normal,
  * tangent angle) and whose codes cover only the bins
  * the surface lacks.
  *
  * File: magic "PDCv", version, the dictionary's fingerprint, grid size and atom count, the
  * parameters, the normalisation, then zlib-packed sections — quad vertices (deltas), quad faces
  * (valence + back-references), per-patch seed offsets along Z, per-patch atom sets, coefficients,
  * patch means (when the dictionary removes them), observation masks (patches whose grid left the
  * surface, and coverage patches) — atom sets, coefficients and masks range-coded since version 3
  * (sparse_code_coding.h, mask_coding.h) — optionally the input's faces and vertex places, the coverage frames — and an FNV-1a
  * 64 checksum.
  *
  * Decoding: the quad mesh is rebuilt, frames re-derived, patches decoded (D·codes), and the
  * surface reconstructed (PatchMeshReconstruction, bilinear rule) on the quad mesh subdivided
  * `subdivision` times per side — or on the input's connectivity when it was kept; each coverage
  * patch adds its kept bins as a small grid of triangles (a separate piece of the output). */
class PatchCodec {
public:
  using Ptr = std::shared_ptr<PatchCodec>;
  using ConstPtr = std::shared_ptr<const PatchCodec>;

  /** Bytes of each part of an encoded file, and what the encoder / decoder saw. */
  struct Report {
    std::size_t header_bytes = 0, quad_vertex_bytes = 0, quad_face_bytes = 0, offset_bytes = 0, atom_bytes = 0,
                coefficient_bytes = 0, mean_bytes = 0, mask_bytes = 0, connectivity_bytes = 0,
                total_bytes = 0;
    std::size_t quad_vertices = 0, quad_faces = 0, patches = 0, nonzeros = 0;
    std::size_t masked_patches = 0;  ///< patches whose masks are stored (bins off the surface; every coverage patch)
    std::size_t coverage_patches = 0;  ///< of `patches`: those with stored frames (see coverage_tolerance)
    std::size_t coverage_bytes = 0;    ///< their frames' section
    std::size_t output_vertices = 0, output_faces = 0;
    std::size_t coverage_faces = 0;  ///< decoder: the last faces of the output, the coverage patches' pieces
    double coefficient_step = 0.0;
    double patch_rmse = 0.0;  ///< encoder: RMS height error of the quad patches' quantised codes, observed bins (unit cube)
    double seconds_layout = 0.0, seconds_patches = 0.0, seconds_coding = 0.0, seconds_reconstruct = 0.0,
           seconds_coverage = 0.0;  ///< encoder: decoding its own output and choosing coverage patches
    /** The paper's count (Table 1): non-zero coefficients plus the quad mesh's entities
      * (one per vertex, one per face corner), plus two per coverage patch (its seed, counted
      * like a vertex, and its orientation). */
    std::size_t patchEntities() const;
  };

  void setDictionary(const PatchDictionary::ConstPtr& dictionary) { dictionary_ = dictionary; }
  void setParameters(const PatchCodecParameters& parameters) { parameters_ = parameters; }
  const PatchCodecParameters& getParameters() const { return parameters_; }

  /** The .pdc bytes of a triangle mesh. Throws Error without a dictionary, for parameters out of
    * range, a mesh without faces, or a quad mesh too coarse for the shape. Deterministic: the same
    * mesh, parameters and dictionary give the same bytes for any thread count. */
  std::string encode(const TriangleMesh& mesh, Report* report = nullptr) const;

  /** The surface of .pdc bytes, in the input's coordinates. Throws Error (one line, prefixed with
    * `what`, e.g. "'x.pdc': ") for truncated or corrupted data, another format version, or a
    * dictionary other than the one the data was encoded with. */
  void decode(const std::string& bytes, TriangleMesh& out, Report* report = nullptr,
              const std::string& what = "") const;

private:
  void requireDictionary() const;
  PatchDictionary::ConstPtr dictionary_;
  PatchCodecParameters parameters_;
};

/** Mesh entities as the paper counts them (Table 1): 3 per face plus 1 per vertex. */
std::size_t meshEntities(const TriangleMesh& mesh);

}  // namespace patchdict
}  // namespace pcl
