// Repairs of a spinning LiDAR's range image: holes (dropouts enclosed by one surface) filled on their
// pixels' rays, and denoising along the beams; nothing ever nearer than the neighbouring beams measured.
#pragma once

#include <pcl_patchdict/cloud/range_image.h>

#include <cstddef>
#include <vector>

namespace pcl {
namespace patchdict {

struct RangeFillParameters {
  /// Regions of more pixels stay open (the usual harmonic range-image fill's bound).
  std::size_t max_hole_pixels = 2000;
  /// Regions whose rim is wider than this (absolute units: 2 × its largest distance from the rim's
  /// centroid) stay open; 0: no bound.
  double max_hole_diameter = 0.0;
  /// The rim lies on one surface when its ranges span at most rim_spread of their median (the
  /// harmonic range-image fill's own test: an object before a wall, or the sky, spreads it far more).
  double rim_spread = 0.03;
  /// The plane through the ring is fitted robustly: Tukey's weight of its misfit, zero beyond
  /// 2 τ(ρ), τ(ρ) = max(rim_noise_factor × σ(ρ), rim_relative_range × ρ).
  double rim_noise_factor = 4.0;
  double rim_relative_range = 0.01;
  /// Regions whose rim plane is seen at more than this angle from its normal stay open: at grazing
  /// incidence the range of a ray is no longer determined by the rim (an angle error δ moves it by
  /// ρ·tan(i)·δ).
  double max_incidence_degrees = 80.0;
  /// Pixels of the ring the plane is fitted to, outward from the region (0: the region's radius in
  /// pixels, clamped to 2…6).
  int fit_ring = 0;
  /// A fill is never nearer than the nearest range its 8 neighbours measured by more than
  /// max(free_space_spacing × the pixel spacing there, free_space_relative × that range), as a depth
  /// image's (OrganizedFillParameters): a surface that recedes along the beams (the ground) has its
  /// truth nearer than the beam above measured, but not by more.
  double free_space_spacing = 2.0;
  double free_space_relative = 0.008;
};

struct RangeFillReport {
  std::size_t regions = 0;          ///< 4-connected regions without a measurement (azimuth wraps)
  std::size_t holes_filled = 0;     ///< enclosed by one surface, filled
  std::size_t touching_border = 0;  ///< reaching the first or last beam (or an open azimuth end)
  std::size_t too_large = 0;        ///< more than max_hole_pixels, or wider than max_hole_diameter
  std::size_t not_one_surface = 0;  ///< rims across a range discontinuity
  std::size_t grazing = 0;          ///< rims on one surface seen beyond max_incidence_degrees
  std::size_t pixels_filled = 0;
  /// Fills left open: nearer than their neighbours measured (beyond the tolerance), or, seen from
  /// the origin, in space the beams crossed.
  std::size_t free_space_dropped = 0;
};

/** Fills the enclosed dropouts of a range image: 4-connected regions without a return that touch
  * neither the first nor the last beam (nor an open end of the azimuth), whose rim lies on one
  * surface (rim_spread) seen at no more than max_incidence_degrees. Each is filled with the plane
  * through the ring around it (1/ρ linear in the ray direction, weighted by 1/σ² of 1/ρ, then
  * Tukey-reweighted twice) plus the plane's misfit at the rim interpolated harmonically inward,
  * evaluated on each pixel's own ray. A pixel whose fill would lie nearer than its 8 neighbours
  * measured (beyond the free-space tolerance), or, seen from the sensor's origin, in space the beams
  * crossed (OriginFreeSpace), is left open. Appends, per filled pixel
  * in row-major order, its index and its range. Deterministic. */
void fillRangeImageHoles(const RangeImage& image, const RangeNoiseModel& noise, const RangeFillParameters& parameters,
                         std::vector<std::size_t>& pixels, std::vector<double>& ranges, RangeFillReport& report);

struct RangeDenoisingParameters {
  /// The window: column_radius azimuth steps along the beam, beam_radius beams across it.
  int column_radius = 3;
  int beam_radius = 1;
  double spatial_sigma = 0.6;     ///< Gaussian weight, σ = spatial_sigma × the radius, per axis
  /// Tukey's biweight of a neighbour's range off the reference plane, zero beyond range_sigmas × σ(ρ):
  /// the far side of a range edge and the other face of a corner stay out of the fit.
  double range_sigmas = 4.0;
  /// The first plane's neighbours lie within range_sigmas·σ(ρ) + slope_allowance·d·(ρ·step) of the
  /// pixel's own range, d its distance in pixels (slope_allowance = tan of the steepest incidence).
  double slope_allowance = 3.0;
  int refinements = 1;            ///< robust passes after the first, each about the last plane
  int min_neighbours = 4;         ///< fewer weighted neighbours: the pixel keeps its range
  double max_shift_sigmas = 4.0;  ///< the move along the ray is clamped to this × σ(ρ)
  /// No move brings a point nearer than the nearest range its 8 neighbours measured by more than
  /// max(free_space_spacing × the pixel spacing, free_space_relative × that range).
  double free_space_spacing = 2.0;
  double free_space_relative = 0.008;
  int num_threads = 0;            ///< 0: OpenMP's default; the result does not depend on it
};

struct RangeDenoisingReport {
  std::size_t measured = 0, moved = 0, left = 0;
  std::size_t clamped = 0;             ///< moves cut to max_shift_sigmas × σ(ρ)
  std::size_t free_space_clamped = 0;  ///< moves cut at the nearest range the neighbouring beams measured
  double rms_shift_sigmas = 0.0;       ///< RMS move over the moved pixels, in σ(ρ)
  double seconds = 0.0;
};

/** Denoises a range image along its beams: for every measured pixel, a robust weighted plane in 1/ρ
  * over the ray directions of its window (local linear regression with a bilateral range kernel, as
  * denoiseDepthImage does for pinhole images), evaluated on the pixel's own ray; the move is clamped
  * to ±max_shift_sigmas·σ(ρ), and never brings the point nearer the sensor than the smallest range its
  * 8 neighbours measured (beyond the free-space tolerance), nor, seen from the origin, into space
  * the beams crossed (OriginFreeSpace). range_out: NaN where the input has none. Throws Error when the noise model
  * has no coefficient. */
void denoiseRangeImage(const RangeImage& image, const RangeNoiseModel& noise, const RangeDenoisingParameters& parameters,
                       std::vector<double>& range_out, RangeDenoisingReport& report);

}  // namespace patchdict
}  // namespace pcl
