// Hole filling for unorganised 2.5-D clouds (aerial LiDAR, terrain): enclosed gaps of a plane raster
// filled at the input's density from a robust quadric + thin-plate spline fitted to each hole's rim.
#pragma once

#include <Eigen/Core>

#include <cstddef>
#include <vector>

namespace pcl {
namespace patchdict {

/** Lengths named *_factor are multiples of the input spacing s (the median distance of the input
  * points to their 4 nearest neighbours, estimated on a subsample); the others are absolute (the
  * cloud's units), 0 meaning "automatic" where stated. */
struct HeightFieldFillParameters {
  /// The up direction (need not be unit length); the zero vector: the axis of least variance of
  /// the cloud (PCA), oriented towards +z. Aerial data: keep +z.
  Eigen::Vector3d up = Eigen::Vector3d::UnitZ();
  /// The input spacing s; 0: estimated.
  double spacing = 0.0;
  /// Detection raster cell, × s: large enough that the random gaps between single returns of
  /// sampled ground leave no empty cell (2.5 s: ~5 returns per cell on uniform ground).
  double detection_cell_factor = 2.5;
  /// The data's footprint: the empty cells a square probe of this half-width (× s, rounded to whole
  /// cells, at least one) reaches from beyond the data are its outside and are never filled; gaps
  /// connected to it through a narrower mouth stay candidates (the footprint is the morphological
  /// closing of the occupied cells).
  double outside_probe_factor = 7.5;
  /// A candidate is a hole when at most this share of its boundary cells touch the outside (0: only
  /// fully enclosed gaps; a bay at the tile's edge has ~0.4).
  double max_open_share = 0.25;
  /// Holes whose bounding box in the plane is wider than this stay open (absolute; 0: automatic,
  /// max_hole_diameter_factor × s; 150 s ≈ 100 m for 0.7 m airborne spacing: a building or a pond).
  double max_hole_diameter = 0.0;
  double max_hole_diameter_factor = 150.0;
  /// Holes without an empty disc at least this wide (the largest distance of the hole's lattice
  /// to the input, × 2) are random sampling gaps and stay open; × s.
  double min_hole_diameter_factor = 4.0;
  /// Filled points lie on a square lattice of this step, × s.
  double lattice_factor = 1.0;
  /// ...and only where no input point lies within this distance in the plane, × s.
  double clearance_factor = 0.75;
  /// Width of the ring of input points around a hole that the surface is fitted to, × s.
  double rim_width_factor = 4.0;
  /// Smoothing λ of the thin-plate spline through the rim residuals (sites scaled into the unit
  /// disc; 0 interpolates).
  double rim_smoothing = 1e-3;
  /// At most this many thin-plate sites per hole (rim residuals are pooled into cells until they
  /// fit; the dense solve is cubic in it).
  std::size_t max_spline_sites = 400;
  /// Raster cells allowed (memory bound: ~12 bytes per cell); a larger raster throws Error.
  std::size_t max_raster_cells = std::size_t(1) << 25;
};

struct HeightFieldFillReport {
  double spacing = 0.0;                      ///< s used
  Eigen::Vector3d up = Eigen::Vector3d::UnitZ();  ///< unit up direction used
  double cell_size = 0.0;                    ///< detection raster cell (absolute)
  std::size_t raster_width = 0, raster_height = 0;
  std::size_t points_used = 0;               ///< finite input points inside the robust extent
  std::size_t points_ignored = 0;            ///< non-finite, or absurdly far from the bulk
  std::size_t empty_components = 0;          ///< 4-connected components of empty cells inside the footprint
  std::size_t holes_filled = 0;
  std::size_t rejected_border = 0;           ///< open to the outside of the data's footprint
  std::size_t rejected_too_big = 0;
  std::size_t rejected_too_small = 0;        ///< random sampling gaps (below min_hole_diameter_factor)
  std::size_t rejected_no_rim = 0;           ///< too few rim points to fit a surface
  std::size_t points_added = 0;
  double seconds = 0.0;
};

/** Decides whether a cloud is 2.5-D: there is a dominant direction (the least-variance axis has at
  * most a quarter of the middle variance) and, in a raster of cells 2.5 s wide perpendicular to
  * it, at least min_single_layer_share of the occupied cells hold one layer (no height gap above
  * 4 s between consecutive points). Non-finite points are ignored; fewer than 16 finite points:
  * false. Optional outputs: the dominant (up) direction, oriented towards +z, and the share. */
bool isHeightFieldCloud(const std::vector<Eigen::Vector3d>& points, Eigen::Vector3d* up = nullptr,
                        double* single_layer_share = nullptr, double min_single_layer_share = 0.6);

/** Fills the enclosed holes of a 2.5-D cloud (see HeightFieldFillParameters): appends nothing to
  * the input; `added` receives the new points (in the input's coordinates) and `added_source` the
  * index into `points` of the nearest (in the plane) rim point of each, for copying colour etc.
  * Deterministic; single-threaded. Throws Error for invalid parameters or a raster above
  * max_raster_cells; non-finite points are ignored, points absurdly far from the bulk of the cloud
  * too (counted in the report). */
void fillHeightFieldHoles(const std::vector<Eigen::Vector3d>& points, const HeightFieldFillParameters& parameters,
                          std::vector<Eigen::Vector3d>& added, std::vector<std::size_t>& added_source,
                          HeightFieldFillReport& report);

}  // namespace patchdict
}  // namespace pcl
