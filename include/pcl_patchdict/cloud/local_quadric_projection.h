// Local quadric patches of a point cloud: each query point is moved onto the weighted least-squares
// height field z = c0 + c1·u + c2·v + c3·u² + c4·u·v + c5·v² of its neighbours, in their PCA frame.
#pragma once

#include <pcl/types.h>

#include <Eigen/Core>

#include <cstddef>
#include <functional>
#include <vector>

namespace pcl {
namespace patchdict {

/** Neighbours of point `query` (an index into the points) within `radius`, at most `max_neighbours`
  * of the nearest, in increasing distance; squared distances beside. Must be safe to call from
  * several threads at once (pcl::search::KdTree is). */
using RadiusNeighbourSearch =
    std::function<void(std::size_t query, double radius, int max_neighbours, pcl::Indices& indices,
                       std::vector<float>& squared_distances)>;

struct LocalQuadricParameters {
  double bandwidth = 0.0;        ///< h: Gaussian weight exp(−d²/h²) of a neighbour at distance d
  double support_factor = 2.0;   ///< neighbours within support_factor × h (weight there: e^−4)
  int max_neighbours = 192;      ///< the nearest ones, when more lie within the support
  int min_neighbours = 8;        ///< fewer usable neighbours: no fit (LocalQuadricFit::valid false)
  int num_threads = 0;           ///< 0 = OpenMP's default
  /// The two extra statistics of a fit (one more 6 × 6 solve each), for callers that use them.
  bool want_loo_residual = true;
  bool want_leverage = true;
};

struct LocalQuadricFit {
  Eigen::Vector3d position = Eigen::Vector3d::Zero();  ///< the query moved onto the height field
  Eigen::Vector3d normal = Eigen::Vector3d::Zero();    ///< unit normal of the height field there (sign arbitrary)
  double residual = 0.0;  ///< signed height of the query above the field, along the PCA normal
  /// The same with the query's own sample left out of the height fit, in the same frame (with
  /// leave_one_out the frame too is made without it: a slightly different statistic)
  double loo_residual = 0.0;
  /// ∂(fitted height at the query)/∂(the query's own height): the diagonal of the smoother matrix
  /// (0 with leave_one_out), for Stein's unbiased risk estimate of the bandwidth
  double leverage = 0.0;
  int neighbours = 0;     ///< usable neighbours within the support
  bool valid = false;
};

/** \brief Local quadric patch of every query (a weighted form of the moving least squares of
  * Alexa et al., "Computing and rendering point set surfaces", IEEE TVCG 2003, and of PCL's
  * MovingLeastSquares with a polynomial of order 2): the usable neighbours within
  * support_factor·h get Gaussian weights w = exp(−d²/h²) around the query; their weighted mean and
  * covariance give the frame (normal = eigenvector of the smallest eigenvalue); the height field is
  * the weighted least-squares quadric over the frame's tangent coordinates, and the query moves along
  * the normal onto it. With leave_one_out the query's own sample gets weight 0, so `residual` is
  * an honest prediction error (used to estimate the noise). `points[i]` is point i's position;
  * `usable[i]` (empty: all) says whether it may serve as a neighbour. Deterministic whatever the
  * thread count. */
void fitLocalQuadrics(const std::vector<Eigen::Vector3d>& points, const std::vector<char>& usable,
                      const RadiusNeighbourSearch& search, const std::vector<std::size_t>& queries,
                      const LocalQuadricParameters& parameters, bool leave_one_out,
                      std::vector<LocalQuadricFit>& fits);

}  // namespace patchdict
}  // namespace pcl
