// Completion of a point cloud's holes: the gaps Poisson's surface bridges, filled with new points at
// the cloud's own density on the smoothest surface through the hole's rim (implicit or height field).
#pragma once

#include <Eigen/Core>

#include <cstddef>
#include <vector>

namespace pcl {
namespace patchdict {

struct CloudCompletionParameters {
  /// Holes wider than this (absolute units) stay open — a scan's own open borders, which Poisson
  /// closes with a cap; 0 = 0.15 × the largest side of the cloud's bounding box.
  double max_hole_diameter = 0.0;
  double gap_factor = 3.0;   ///< Poisson faces farther than this × s from every point are gaps
  /// Fewer connected gap faces: a gap between random samples, not a hole. With gap_factor this sets
  /// the smallest hole found: wider than ~2 × 3 s plus a few Poisson cells (cell ≤ 4 s) — an 80 × 60
  /// grid's hole of radius 6 cells was not found, one of 12 cells was.
  int min_gap_faces = 20;
  int poisson_depth = 0;     ///< 0 = the smallest depth whose cell is at most 4 s (it only finds the gaps)
  double rim_width = 0.3;    ///< the rim: points within (1 + rim_width) × the hole's radius of its centre
  int max_rim_points = 800;  ///< the spline goes through an evenly spaced subset of at most this many
  double smoothing = 1e-4;   ///< λ of the spline (0 interpolates the rim exactly)
  /// A gap whose area-weighted mean normal has length below this × its area is not flat enough for
  /// a height field over one plane: Poisson's surface is sampled there instead.
  double flatness = 0.5;
  /// Lattice points up to gap_factor × s + rim_reach × the lattice spacing from the gap (in the plane)
  /// are over the hole: the gap's Poisson faces stop gap_factor × s short of the data.
  double rim_reach = 1.0;
  /// New points closer than this × the lattice spacing to an input point are dropped (the data
  /// is there already).
  double clearance = 0.75;
  /// How a hole is filled. Implicit: the zero set of a biharmonic implicit through the rim points
  /// and their normals (biharmonic_implicit.h), sampled where Poisson's bridge lies, so that a hole
  /// through folds is filled as one surface. HeightField: a thin-plate spline over the gap's plane,
  /// sampled on a hexagonal lattice (a gap that is not flat gets Poisson's surface). Auto: the
  /// height field for a flat gap whose rim faces one way (single_sheet), the implicit otherwise
  /// (what Auto gains over the height field alone: docs/results.md, "Point clouds").
  enum class Surface { Auto, Implicit, HeightField };
  Surface surface = Surface::Auto;
  /// Auto: the height field when at least this share of the rim's points face the gap's mean normal
  /// (cosine > 0.3).
  double single_sheet = 0.98;
  int implicit_points = 500;     ///< rim points of the implicit, evenly spaced (its system is 3n + 4)
  double implicit_offset = 2.0;  ///< ε of the off-surface constraints, × s
  /// Implicit: Poisson's surface over the gap and up to the lattice's reach around it is sampled at
  /// this × the input density, each sample moved onto f = 0, then thinned to at most one point per
  /// disc of radius thinning × the lattice spacing (random sequential packing jams near the input's
  /// density at 0.75).
  int oversampling = 16;
  double thinning = 0.75;
  int num_threads = 0;
};

struct CloudCompletionReport {
  std::size_t gaps = 0;             ///< connected far-face regions of the Poisson surface
  std::size_t holes_filled = 0;       ///< through their rim (the implicit or the spline)
  std::size_t holes_implicit = 0;     ///< of those, by the implicit
  std::size_t holes_from_poisson = 0; ///< not flat enough, or too thin a rim: Poisson's surface sampled
  std::size_t holes_too_large = 0;    ///< wider than max_hole_diameter: left open
  std::size_t points_added = 0;
  double density = 0.0;           ///< input points per unit area
  double lattice_spacing = 0.0;   ///< of the new points (hexagonal, the input's density)
  int poisson_depth = 0;
  std::size_t poisson_faces = 0;
  double seconds_poisson = 0.0, seconds_gaps = 0.0, seconds_fill = 0.0;
};

/** \brief New points where a cloud has holes:
  *  1. the screened Poisson surface of the oriented cloud (CoarseMeshEstimation, untrimmed);
  *  2. its faces farther than gap_factor × s from every point, in edge-connected regions of at least
  *     min_gap_faces faces: the gaps; a gap wider than max_hole_diameter is a border, not a hole;
  *  3. per hole (parameters.surface): a biharmonic implicit through the rim (the points around the
  *     gap) and their normals, whose zero set takes dense samples of Poisson's bridge over the gap,
  *     thinned to the input's density; or, for a flat gap whose rim faces one way, a thin-plate
  *     spline height field over the gap's plane, evaluated on a hexagonal lattice at the input's
  *     density. New points clear of the data, with the surface's normal (oriented like the input
  *     normals) and the nearest input point as their source (for colour and other fields); a hole
  *     without a usable rim gets area-uniform samples of the Poisson surface over it instead.
  * `points` finite, `normals` unit and consistently oriented (outwards), `spacing` the mean
  * nearest-neighbour distance. Deterministic. Throws Error from Poisson on a degenerate cloud. */
void completeCloudHoles(const std::vector<Eigen::Vector3d>& points, const std::vector<Eigen::Vector3d>& normals,
                        double spacing, const CloudCompletionParameters& parameters,
                        std::vector<Eigen::Vector3d>& added, std::vector<Eigen::Vector3d>& added_normals,
                        std::vector<std::size_t>& added_source, CloudCompletionReport& report);

}  // namespace patchdict
}  // namespace pcl
