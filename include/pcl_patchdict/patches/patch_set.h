// PatchSet — the height-map patches of a surface (section 3 of Sarkar et al. 2017): grid size N,
// radius r, per patch its seed s and frame R_s, its N² heights and which bins were observed; saved as .pds
// (io/patch_set_io.h).
#pragma once

#include <pcl_patchdict/core/observation_mask.h>

#include <Eigen/Core>

#include <cstdint>
#include <string>
#include <vector>

namespace pcl {
namespace patchdict {

/** \brief Patches as columns: bin (i, j) — i the column along the frame's X, j the row along its
  * Y — is row j·N + i of `heights`, so a column read row-major is the height map as an image.
  *
  * Frames are kept as rotation matrices whose rows are the frame's X, Y, Z axes (local =
  * R·(p − s), world = s + Rᵀ·local, the T_s of section 3.1), in double, the core's form of a frame
  * (core/local_frame.h): the extractor stores the frames it receives as they are. */
struct PatchSet {
  /** Largest N (as a dictionary's): a 256×256 patch is already far beyond the paper's 16–24. */
  static constexpr int kMaxGridSize = 256;

  int grid_size = 0;        ///< N: a patch has N×N bins
  double radius = 0.0;      ///< r: patch side √2·r, neighbourhood radius r
  std::vector<Eigen::Vector3d> seeds;      ///< P seed points s (patch origins)
  std::vector<Eigen::Matrix3d> rotations;  ///< P rotations, rows = X, Y, Z axes of the frame
  Eigen::MatrixXd heights;                 ///< N² × P; 0 where unobserved
  ObservationMask observed;                ///< N² × P
  std::vector<std::int32_t> source;        ///< P: which input (shape) each patch came from

  std::size_t numPatches() const { return seeds.size(); }
  /** Side of the square grid, √2·r (section 3.2 of the paper). */
  double side() const;
  /** Fraction of observed bins over all patches (0 for an empty set). */
  double observedFraction() const;
  /** Throws Error (one line) if the members disagree in size or hold non-finite values. */
  void check() const;
  /** Appends another set's patches (same grid size and radius, else Error): global sets. */
  void append(const PatchSet& other);
};

}  // namespace patchdict
}  // namespace pcl
