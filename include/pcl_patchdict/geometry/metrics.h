// Error metrics every result is judged by: exact point-to-triangle-mesh distance (through a BVH),
// vertex RMSE, symmetric surface distances (mean / RMS / Hausdorff) and PSNR with the bbox diagonal as peak.
#pragma once

#include <pcl_patchdict/core/triangle_mesh.h>

#include <cstdint>
#include <memory>
#include <vector>

namespace pcl {
namespace patchdict {

/** Closest point to p on the triangle (a, b, c) (Ericson, "Real-Time Collision Detection", 5.1.5).
  * Degenerate triangles included: a zero-area one gives the exact closest point of its edges (a
  * point triangle gives its point); a needle narrower than 1e-8 × its longest edge is treated as
  * its edges (error below that width). */
Eigen::Vector3d closestPointOnTriangle(const Eigen::Vector3d& p, const Eigen::Vector3d& a,
                                       const Eigen::Vector3d& b, const Eigen::Vector3d& c);

/** \brief Exact distance from points to a triangle mesh, accelerated by an AABB tree over its faces.
  * Build once, query from many threads (queries are const and thread-safe). */
class PointToMeshDistance {
public:
  struct Result {
    double squared_distance = 0.0;
    Eigen::Vector3d closest_point = Eigen::Vector3d::Zero();
    std::int32_t face = -1;
  };

  /** Builds the tree; the mesh must have at least one face (throws Error otherwise). The mesh
    * is copied, so it need not outlive this object. */
  explicit PointToMeshDistance(const TriangleMesh& mesh);
  ~PointToMeshDistance();
  PointToMeshDistance(PointToMeshDistance&&) noexcept;
  PointToMeshDistance& operator=(PointToMeshDistance&&) noexcept;

  /** Closest point on the mesh to p (throws Error for a non-finite p). */
  Result query(const Eigen::Vector3d& p) const;
  /** Unsigned distances of all points (OpenMP-parallel; same result for any thread count).
    * Throws Error if a point is not finite. */
  std::vector<double> distances(const std::vector<Eigen::Vector3d>& points) const;

private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

/** RMS of |out.v_i − ref.v_i| over the given vertex indices (all vertices when indices is empty).
  * Throws Error if the vertex counts differ or an index is out of range. */
double vertexRMSE(const TriangleMesh& ref, const TriangleMesh& out, const std::vector<int>& indices = {});

/** Distances of a set of points to a surface (mean, RMS, max). */
struct PointSetDistance {
  double mean = 0.0, rms = 0.0, max = 0.0;
  std::size_t count = 0;
};

/** One-way distance of `points` to the surface of `mesh` (e.g. a cloud output against its
  * reference); distances at rounding level count as 0, as in surfaceDistance. Throws Error if the
  * mesh has no faces; an empty point set gives zeros. */
PointSetDistance pointsToSurfaceDistance(const std::vector<Eigen::Vector3d>& points, const TriangleMesh& mesh);

/** One-way distance of `points` to their nearest point of `reference` (cloud against cloud, e.g.
  * a reconstructed cloud against its input); rounding-level distances count as 0. Throws Error
  * for an empty reference or non-finite points; an empty point set gives zeros. */
PointSetDistance pointsToPointsDistance(const std::vector<Eigen::Vector3d>& points,
                                        const std::vector<Eigen::Vector3d>& reference);

/** Distances one way (samples of A to the surface of B) and their symmetric combination. */
struct SurfaceDistance {
  double mean_ref_to_out = 0.0, rms_ref_to_out = 0.0, max_ref_to_out = 0.0;
  double mean_out_to_ref = 0.0, rms_out_to_ref = 0.0, max_out_to_ref = 0.0;
  double mean = 0.0;       ///< mean over both sample sets
  double rms = 0.0;        ///< sqrt of the mean squared distance over both sample sets
  double hausdorff = 0.0;  ///< max of the two one-way maxima
  double bbox_diagonal = 0.0;  ///< of the reference
  double psnr = 0.0;       ///< 20·log10(bbox_diagonal / rms); +inf when rms = 0
  std::size_t samples_per_side = 0;
};

/** Symmetric surface distance from num_samples area-uniform samples on each mesh (ref sampled
  * with `seed`, out with `seed + 1`), each sample measured exactly against the other surface.
  * Distances within 64 ulps of the largest coordinate magnitude are rounding noise and count as 0,
  * so identical surfaces give exactly 0 and a PSNR of +inf. Throws Error if either mesh has no
  * face of positive area or num_samples is 0. Deterministic for a given seed. */
SurfaceDistance surfaceDistance(const TriangleMesh& ref, const TriangleMesh& out,
                                std::size_t num_samples = 200000, std::uint64_t seed = 1);

/** PSNR = 20·log10(peak / rms), +inf for rms = 0; throws Error for a negative or NaN argument. */
double psnr(double peak, double rms);

}  // namespace patchdict
}  // namespace pcl
