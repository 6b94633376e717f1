// Error metrics built on the point-to-mesh distance: vertex RMSE, symmetric surface distances and
// PSNR, with compensated sums so that every reported figure is bit-reproducible.
#include <pcl_patchdict/core/error.h>
#include <pcl_patchdict/geometry/metrics.h>
#include <pcl_patchdict/core/surface_sampling.h>

#include "geometry/point_search.h"

#include <pcl/kdtree/kdtree_flann.h>
#include <pcl/point_types.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <initializer_list>
#include <limits>
#include <string>

namespace pcl {
namespace patchdict {

using Eigen::Vector3d;

namespace {

/** Neumaier-compensated sum: sums of 10^5..10^6 distances keep full double accuracy, in a fixed
  * (sequential) order so results are bit-reproducible. */
struct CompensatedSum {
  double sum = 0.0, compensation = 0.0;
  void add(double x)
  {
    const double t = sum + x;
    compensation += std::abs(sum) >= std::abs(x) ? (sum - t) + x : (x - t) + sum;
    sum = t;
  }
  double value() const { return sum + compensation; }
};

struct OneWay {
  CompensatedSum sum, sum_squares;
  double max = 0.0;
};

/** Distances at or below `noise_floor` are rounding noise of the closest-point computation (a sample
  * lying on the other surface comes out at ~1e-17, not 0) and are counted as 0, so that identical
  * surfaces give exactly 0 and a PSNR of +inf. */
OneWay accumulate(const std::vector<double>& distances, double noise_floor)
{
  OneWay w;
  for (double d : distances) {
    if (d <= noise_floor)
      d = 0.0;
    w.sum.add(d);
    w.sum_squares.add(d * d);
    w.max = std::max(w.max, d);
  }
  return w;
}

// Resolution floor: 64 ulps of the largest coordinate magnitude of the point sets involved.
double noiseFloor(std::initializer_list<const std::vector<Vector3d>*> point_sets)
{
  double magnitude = 0.0;
  for (const auto* points : point_sets)
    for (const Vector3d& p : *points)
      magnitude = std::max(magnitude, p.cwiseAbs().maxCoeff());
  return 64.0 * std::numeric_limits<double>::epsilon() * magnitude;
}

}  // namespace

PointSetDistance pointsToSurfaceDistance(const std::vector<Vector3d>& points, const TriangleMesh& mesh)
{
  if (mesh.faces.empty())
    throw Error("point distance: the surface has no faces");
  PointSetDistance result;
  result.count = points.size();
  if (points.empty())
    return result;
  const PointToMeshDistance to_mesh(mesh);
  const OneWay w = accumulate(to_mesh.distances(points), noiseFloor({&points, &mesh.vertices}));
  const auto n = static_cast<double>(points.size());
  result.mean = w.sum.value() / n;
  result.rms = std::sqrt(w.sum_squares.value() / n);
  result.max = w.max;
  return result;
}

PointSetDistance pointsToPointsDistance(const std::vector<Vector3d>& points, const std::vector<Vector3d>& reference)
{
  PointSetDistance result;
  result.count = points.size();
  if (points.empty())
    return result;
  if (reference.empty())
    throw Error("point distance: the reference cloud is empty");
  for (const auto& p : reference)
    if (!p.allFinite())
      throw Error("point distance: the reference cloud has non-finite points");
  const detail::PointSearch tree(reference);
  std::vector<double> distances(points.size());
  const auto count = static_cast<std::ptrdiff_t>(points.size());
#pragma omp parallel
  {
    std::vector<int> index(1);
    std::vector<float> squared(1);
#pragma omp for schedule(static)
    for (std::ptrdiff_t i = 0; i < count; ++i) {
      const Vector3d& p = points[static_cast<std::size_t>(i)];
      if (!p.allFinite())
        throw Error("point distance: a point is not finite");
      // FLANN finds the nearest in float; the distance itself is recomputed in double.
      tree.nearest(p, 1, index, squared);
      distances[static_cast<std::size_t>(i)] = (reference[static_cast<std::size_t>(index[0])] - p).norm();
    }
  }
  const OneWay w = accumulate(distances, noiseFloor({&points, &reference}));
  const auto n = static_cast<double>(points.size());
  result.mean = w.sum.value() / n;
  result.rms = std::sqrt(w.sum_squares.value() / n);
  result.max = w.max;
  return result;
}

double vertexRMSE(const TriangleMesh& ref, const TriangleMesh& out, const std::vector<int>& indices)
{
  const std::size_t n = ref.vertices.size();
  if (out.vertices.size() != n)
    throw Error("vertex RMSE needs meshes with the same vertex count (" + std::to_string(n) + " vs " +
                std::to_string(out.vertices.size()) + ")");
  CompensatedSum sum;
  if (indices.empty()) {
    if (n == 0)
      return 0.0;
    for (std::size_t i = 0; i < n; ++i)
      sum.add((out.vertices[i] - ref.vertices[i]).squaredNorm());
    return std::sqrt(sum.value() / static_cast<double>(n));
  }
  for (const int i : indices) {
    if (i < 0 || static_cast<std::size_t>(i) >= n)
      throw Error("vertex RMSE: index " + std::to_string(i) + " out of range [0, " + std::to_string(n) + ")");
    sum.add((out.vertices[i] - ref.vertices[i]).squaredNorm());
  }
  return std::sqrt(sum.value() / static_cast<double>(indices.size()));
}

double psnr(double peak, double rms)
{
  if (!(peak >= 0.0) || !(rms >= 0.0))
    throw Error("PSNR needs a non-negative peak and RMS");
  if (rms == 0.0)
    return std::numeric_limits<double>::infinity();
  return 20.0 * std::log10(peak / rms);
}

SurfaceDistance surfaceDistance(const TriangleMesh& ref, const TriangleMesh& out, std::size_t num_samples,
                                std::uint64_t seed)
{
  if (num_samples == 0)
    throw Error("surface distance needs at least one sample per side");
  if (ref.faces.empty())
    throw Error("surface distance: the reference mesh has no faces");
  if (out.faces.empty())
    throw Error("surface distance: the output mesh has no faces");

  // Independent sample sets on the two surfaces (seed and seed + 1), each measured against the
  // other surface exactly.
  const SurfaceSamples ref_samples = sampleSurfaceUniform(ref, num_samples, seed);
  const SurfaceSamples out_samples = sampleSurfaceUniform(out, num_samples, seed + 1);
  const PointToMeshDistance to_out(out);
  const PointToMeshDistance to_ref(ref);
  const double floor = noiseFloor({&ref.vertices, &out.vertices});
  const OneWay ro = accumulate(to_out.distances(ref_samples.points), floor);
  const OneWay orf = accumulate(to_ref.distances(out_samples.points), floor);

  SurfaceDistance r;
  const auto n = static_cast<double>(num_samples);
  r.samples_per_side = num_samples;
  r.mean_ref_to_out = ro.sum.value() / n;
  r.rms_ref_to_out = std::sqrt(ro.sum_squares.value() / n);
  r.max_ref_to_out = ro.max;
  r.mean_out_to_ref = orf.sum.value() / n;
  r.rms_out_to_ref = std::sqrt(orf.sum_squares.value() / n);
  r.max_out_to_ref = orf.max;
  CompensatedSum both, both_squares;
  both.add(ro.sum.value());
  both.add(orf.sum.value());
  both_squares.add(ro.sum_squares.value());
  both_squares.add(orf.sum_squares.value());
  r.mean = both.value() / (2.0 * n);
  r.rms = std::sqrt(both_squares.value() / (2.0 * n));
  r.hausdorff = std::max(ro.max, orf.max);
  r.bbox_diagonal = ref.boundingBoxDiagonal();
  r.psnr = psnr(r.bbox_diagonal, r.rms);
  return r;
}

}  // namespace patchdict
}  // namespace pcl
