// Image-space denoising of a depth image: per pixel, a robust weighted least-squares plane in 1/z over
// the pixel grid (a plane seen through a pinhole is affine in 1/z), evaluated on the pixel's own ray.
#pragma once

#include <pcl_patchdict/cloud/depth_image.h>

#include <cstddef>
#include <vector>

namespace pcl {
namespace patchdict {

struct DepthDenoisingParameters {
  /// Half-width of the window, in the cloud's units, that a pixel at depth `reference_depth` averages
  /// over; at depth z it is window_radius · (z / reference_depth)^window_exponent. The exponent 1
  /// keeps the pixel radius constant; the default 0.5 widens the window in metres with depth (where
  /// σ(z) ∝ z² is larger) but narrows it in pixels (where a pixel covers more surface).
  double window_radius = 0.02;
  double reference_depth = 1.0;
  double window_exponent = 0.5;
  /// Pixel radius bounds of the window (square, (2R+1)² pixels); max_radius / window_stride ≤ 32.
  int min_radius = 2;
  int max_radius = 12;
  double spatial_sigma = 0.6;    ///< Gaussian spatial weight, σ = spatial_sigma × R pixels
  /// Range weight: Tukey's biweight of a neighbour's depth off the reference plane, zero beyond
  /// range_sigmas × σ(z). This keeps the far side of a depth edge and the other surface of a corner
  /// out of the fit.
  double range_sigmas = 4.0;
  /// The first (reference) plane comes from a (2·seed_radius+1)² window around the pixel; while it is
  /// seeded from the pixel's own depth, a neighbour d pixels away may differ by up to
  /// range_sigmas·σ(z) + slope_allowance·d·(pixel spacing) — slope_allowance = tan of the steepest
  /// view angle (default ~72°).
  int seed_radius = 2;  ///< ≤ 32
  double slope_allowance = 3.0;
  /// The full window is sampled every window_stride pixels in both directions (from the centre):
  /// neighbouring Kinect pixels' noise is strongly correlated, so every other one carries most of
  /// the information at a quarter of the cost.
  int window_stride = 2;
  int refinements = 1;           ///< extra robust passes over the full window, each about its last plane
  int min_neighbours = 6;        ///< fewer neighbours with weight in the full window: the pixel keeps its depth
  /// The move along the ray is clamped to max_shift_sigmas × σ(z) (0: no clamp).
  double max_shift_sigmas = 4.0;
  int num_threads = 0;           ///< 0: OpenMP's default; the result does not depend on it
};

struct DepthDenoisingReport {
  int radius_near = 0, radius_far = 0;       ///< window pixel radius at depth_near and depth_far
  double depth_near = 0.0, depth_far = 0.0;  ///< 5th and 95th percentiles of the measured depths (of an even sample of ≤ 65,536)
  int radius_min = 0, radius_max = 0;        ///< smallest and largest radius used over the image
  std::size_t measured = 0;                  ///< valid input pixels
  std::size_t moved = 0;                     ///< pixels whose depth changed
  std::size_t left = 0;                      ///< valid pixels kept as they were (no supported fit)
  std::size_t clamped = 0;                   ///< moves cut to max_shift_sigmas × σ(z)
  double rms_shift_sigmas = 0.0;             ///< RMS move over the moved pixels, in units of σ(z)
  double seconds = 0.0;
};

/** The window's pixel radius at depth z (see DepthDenoisingParameters::window_radius). */
int depthDenoisingRadius(const PinholeCamera& camera, const DepthDenoisingParameters& parameters, double z);

/** \brief Denoises a depth image in image space.
  *
  * For every measured pixel p at depth z: (1) a reference plane y = a + b·du + c·dv, where
  * y = (1/z_p − 1/z_q)·z_p² is the neighbour's depth offset linearised at z_p, is fitted by weighted
  * least squares over the seed window, first with range weights about the pixel's own depth (with a
  * slope allowance), then once about that plane; (2) the plane is refitted over the full
  * (2R+1)² window, R = depthDenoisingRadius(z), with weights Gaussian(distance) × Tukey(offset from
  * the reference plane / (range_sigmas·σ(z))), `refinements` times; (3) its value at the centre is
  * the new depth, clamped to ±max_shift_sigmas·σ(z). This is local linear regression with a robust
  * (bilateral) range kernel — the plane-fitting relative of the bilateral filter of range images
  * (Tomasi & Manduchi, ICCV 1998; the trilateral filter of Choudhury & Tumblin, EGSR 2003, which
  * adapts the range kernel to the local gradient the same way) and of kernel regression for image
  * denoising (Takeda, Farsiu & Milanfar, IEEE TIP 2007). The noise of depth comes from `noise`.
  *
  * depth_out[i]: the new depth of pixel i; NaN where image.valid[i] is 0; the input depth where the
  * window holds fewer than min_neighbours neighbours of weight or their plane is degenerate. Each
  * point stays on its pixel's ray (only z changes; x and y follow from camera.pointAt). Each pixel's
  * output depends only on the input, so the result does not depend on num_threads, nor on the
  * instruction set the CPU offers (the pixels are fitted 8 or 16 at a time, one per vector lane, in
  * float; see depth_image_denoising.cpp). Throws
  * pcl::patchdict::Error when the image has no valid camera or the noise model no coefficient. */
void denoiseDepthImage(const DepthImage& image, const DepthNoiseModel& noise, const DepthDenoisingParameters& parameters,
                       std::vector<double>& depth_out, DepthDenoisingReport& report);

}  // namespace patchdict
}  // namespace pcl
