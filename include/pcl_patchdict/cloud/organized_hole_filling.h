// Hole filling in an organised cloud's depth image: NaN regions enclosed by one surface, filled in
// place on their pixels' rays; regions at depth discontinuities (shadows) are never bridged.
#pragma once

#include <pcl_patchdict/cloud/depth_image.h>

#include <Eigen/Core>

#include <cstddef>
#include <vector>

namespace pcl {
namespace patchdict {

struct OrganizedFillParameters {
  /// Regions of more pixels stay open (a harmonic depth-image fill's usual bound: 2000 ≈ a disc of
  /// radius 25 px, 5 cm at 1 m on a 640 × 480 Kinect).
  std::size_t max_hole_pixels = 2000;
  /// Regions whose rim is wider than this (absolute units, 2 × the largest rim distance from its
  /// centroid) stay open; 0: no bound.
  double max_hole_diameter = 0.0;
  /// The rim lies on one surface when the smooth fit through it (a quadric of 1/z over the pixel
  /// grid) leaves at most rim_outlier_share of the rim pixels farther than
  /// τ(z) = max(rim_noise_factor × σ(z), rim_relative_depth × z) and none farther than 4 τ(z).
  double rim_noise_factor = 4.0;
  double rim_relative_depth = 0.005;
  double rim_outlier_share = 0.1;
  /// The fit is a plane in 1/z unless a quadric lowers the weighted misfit by more than this × the
  /// Bayesian information criterion's 3 ln n. Quantised depths err alike over a whole layer of
  /// pixels, so the misfits are far from independent and BIC's own price (1) overstates the evidence
  /// for curvature (docs/real_sensor_scans.md, "Figures behind the defaults").
  double curvature_evidence = 10.0;
  /// Pixels of the ring the surface is fitted to, outward from the region (0: the region's radius
  /// in pixels, clamped to 2…6).
  int fit_ring = 0;
  /// The fit's misfit at the rim, interpolated harmonically into the region, so that the fill meets
  /// the rim it leaves (false: the smooth fit alone).
  bool rim_correction = true;
  /// Filled points in front of the measured 3 × 3 neighbourhood of their pixel by more than
  /// max(free_space_spacing × pixel spacing, free_space_relative × depth) are dropped.
  double free_space_spacing = 2.0;
  double free_space_relative = 0.008;
};

struct OrganizedFillReport {
  std::size_t regions = 0;          ///< 4-connected regions of pixels without a measurement
  std::size_t holes_filled = 0;     ///< regions enclosed by one surface, filled
  std::size_t touching_border = 0;  ///< regions open to the image border (not enclosed)
  std::size_t too_large = 0;        ///< more than max_hole_pixels, or wider than max_hole_diameter
  std::size_t not_one_surface = 0;  ///< rims across a depth discontinuity (shadows, object edges)
  std::size_t pixels_filled = 0;
  std::size_t free_space_dropped = 0;  ///< filled pixels whose point the sensor saw through
};

/** Fills the enclosed NaN regions of a depth image (image.camera must be valid). σ(z) of the noise
  * model weights the rim fit (it is constant in 1/z for σ ∝ z²) and sets the rim's tolerance; a
  * model with coefficient 0 weights evenly and uses rim_relative_depth alone. Appends, for each
  * filled pixel in row-major order, its index and its point on the pixel's ray. Deterministic. */
void fillOrganizedHoles(const DepthImage& image, const DepthNoiseModel& noise, const OrganizedFillParameters& parameters,
                        std::vector<std::size_t>& pixels, std::vector<Eigen::Vector3d>& positions,
                        OrganizedFillReport& report);

}  // namespace patchdict
}  // namespace pcl
