// The two geometric steps of Liepa's hole filling that work on a hole alone ("Filling holes in
// meshes", Liepa 2003, SGP): minimum-weight triangulation of a boundary loop, and refinement of it.
#pragma once

#include <pcl_patchdict/core/triangle_mesh.h>

#include <cstdint>
#include <utility>
#include <vector>

namespace pcl {
namespace patchdict {

/** What the triangulation minimises. Liepa's weight compares (largest dihedral angle, total area)
  * lexicographically; Area is the classic minimum-area triangulation (exactly optimal by the DP,
  * used as a known answer in the tests). */
enum class HoleTriangulationWeight { DihedralThenArea, Area };

struct HoleTriangulationOptions {
  HoleTriangulationWeight weight = HoleTriangulationWeight::DihedralThenArea;
  /** Loops with more vertices are split by a short chord into pieces of at most this many before
    * the O(n³) dynamic programme runs on each piece (see triangulateHoleLoop). */
  std::size_t max_dp_vertices = 200;
};

/** A triangulation of a loop: faces index the loop's vertices (0..n−1). A face (a, b, c) is
  * oriented so that it walks loop edge i → i+1 in loop order, i.e. it agrees with mesh faces that
  * walk the loop in the opposite direction. */
struct HoleTriangulation {
  std::vector<Face> faces;
  bool valid = false;               ///< false: every triangulation uses a forbidden edge
  double max_dihedral_angle = 0.0;  ///< radians, over interior and loop edges (loop edges with an apex)
  double area = 0.0;
  std::size_t pieces = 1;           ///< sub-loops the DP ran on (1: no split)
};

/** \brief Minimum-weight triangulation of a closed polygon in 3D with no new vertices, by Liepa's
  * dynamic programme (after Barequet & Sharir; O(n³) time, O(n²) memory per piece).
  *
  * \param loop         the n ≥ 3 loop positions in walking order
  * \param outside_apex per loop edge (i, i+1 mod n), the third vertex of the mesh face across it
  *                     (its dihedral angle with the fill counts); empty or a non-finite entry: none
  * \param forbidden    pairs of loop indices that must not become edges (e.g. already mesh edges)
  *
  * The dihedral angle across a fill edge is measured against the triangle the sub-problem chose
  * on the other side, as in Liepa's paper; the DP is therefore exact for the Area weight and a
  * (very good) heuristic for the lexicographic one. Loops longer than options.max_dp_vertices are
  * split first, recursively, by the chord (i, k) with the smallest ratio of its length to the
  * shorter loop arc between i and k, among chords leaving at least a quarter of the loop on each
  * side; the chord is an ordinary fill edge afterwards (refinement may flip it). The whole DP is
  * cubic in the loop's length; the split keeps long loops fast at the price of a larger worst
  * dihedral angle before refinement (the chords are not weighed; figures in docs/). */
HoleTriangulation triangulateHoleLoop(const std::vector<Eigen::Vector3d>& loop,
                                      const std::vector<Eigen::Vector3d>& outside_apex,
                                      const std::vector<std::pair<int, int>>& forbidden,
                                      const HoleTriangulationOptions& options = {});

/** A hole's fill in local indices: the loop's vertices first (boundary_count of them, fixed), then
  * new ones. scale is Liepa's σ per vertex: for loop vertices the mean length of their mesh edges. */
struct HolePatch {
  std::vector<Eigen::Vector3d> positions;
  std::vector<double> scale;
  std::vector<Face> faces;
  std::size_t boundary_count = 0;
};

struct HoleRefinementOptions {
  double density_factor = 1.4142135623730951;  ///< Liepa's α = √2
  int max_rounds = 40;                         ///< split/relax rounds; stops earlier when nothing splits
};

struct HoleRefinementReport {
  int rounds = 0;
  std::size_t splits = 0, flips = 0;
};

/** \brief Liepa's refinement: a triangle is split at its centroid c when, for each corner m,
  * α·|c − v_m| exceeds both σ(c) (mean σ of the corners) and σ(v_m); new vertices get σ(c).
  * After each split the triangle's old edges are relaxed, and after each round all interior edges,
  * by flips. An edge (a, b) between triangles with opposite vertices c, d is flipped when the
  * angles at c and d sum to more than π (the Delaunay criterion; for a planar pair the same as
  * "d lies in the circumcircle of abc"), never onto an existing edge (patch edges and the
  * forbidden pairs of loop indices) and never into a zero-area triangle. Loop edges stay. */
void refineHolePatch(HolePatch& patch, const std::vector<std::pair<int, int>>& forbidden,
                     const HoleRefinementOptions& options = {}, HoleRefinementReport* report = nullptr);

}  // namespace patchdict
}  // namespace pcl
