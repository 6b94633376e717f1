// fitLocalQuadrics (see local_quadric_projection.h).
#include <pcl_patchdict/core/error.h>
#include <pcl_patchdict/cloud/local_quadric_projection.h>

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>

#include <cmath>
#include <cstdint>

#ifdef _OPENMP
#include <omp.h>
#endif

namespace pcl {
namespace patchdict {

namespace {

// One query: the fit of its neighbourhood (indices / squared distances from the search).
LocalQuadricFit fitOne(const std::vector<Eigen::Vector3d>& points, const std::vector<char>& usable, std::size_t query,
                       const pcl::Indices& indices, const std::vector<float>& squared,
                       const LocalQuadricParameters& parameters, bool leave_one_out)
{
  LocalQuadricFit fit;
  const Eigen::Vector3d& q = points[query];
  const double inv_h2 = 1.0 / (parameters.bandwidth * parameters.bandwidth);
  // Weighted mean and covariance, relative to the query for precision.
  double weight_sum = 0.0;
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  thread_local std::vector<double> weights;
  thread_local std::vector<Eigen::Vector3d> offsets;
  weights.clear();
  offsets.clear();
  std::ptrdiff_t self = -1;  // the query's own sample among the neighbours
  for (std::size_t k = 0; k < indices.size(); ++k) {
    const auto j = static_cast<std::size_t>(indices[k]);
    if (!usable.empty() && !usable[j])
      continue;
    if (leave_one_out && j == query)
      continue;
    const double w = std::exp(-static_cast<double>(squared[k]) * inv_h2);
    const Eigen::Vector3d d = points[j] - q;
    if (j == query)
      self = static_cast<std::ptrdiff_t>(weights.size());
    weights.push_back(w);
    offsets.push_back(d);
    weight_sum += w;
    mean += w * d;
  }
  fit.neighbours = static_cast<int>(weights.size());
  if (fit.neighbours < parameters.min_neighbours || !(weight_sum > 0.0))
    return fit;
  mean /= weight_sum;
  Eigen::Matrix3d covariance = Eigen::Matrix3d::Zero();
  for (std::size_t k = 0; k < weights.size(); ++k) {
    const Eigen::Vector3d d = offsets[k] - mean;
    covariance.noalias() += weights[k] * d * d.transpose();
  }
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eigen(covariance);
  if (eigen.info() != Eigen::Success)
    return fit;
  const Eigen::Vector3d n = eigen.eigenvectors().col(0);
  const Eigen::Vector3d e1 = eigen.eigenvectors().col(2);
  const Eigen::Vector3d e2 = n.cross(e1);
  // Weighted least squares of the height over [1, u, v, u², uv, v²], in units of h (conditioning).
  const double inv_h = 1.0 / parameters.bandwidth;
  Eigen::Matrix<double, 6, 6> normal_matrix = Eigen::Matrix<double, 6, 6>::Zero();
  Eigen::Matrix<double, 6, 1> rhs = Eigen::Matrix<double, 6, 1>::Zero();
  Eigen::Matrix<double, 6, 1> row;
  for (std::size_t k = 0; k < weights.size(); ++k) {
    const Eigen::Vector3d d = offsets[k] - mean;
    const double u = d.dot(e1) * inv_h, v = d.dot(e2) * inv_h, z = d.dot(n);
    row << 1.0, u, v, u * u, u * v, v * v;
    normal_matrix.noalias() += weights[k] * row * row.transpose();
    rhs.noalias() += weights[k] * z * row;
  }
  // A tiny ridge keeps degenerate neighbourhoods (collinear samples) solvable.
  normal_matrix.diagonal().array() += 1e-9 * normal_matrix.trace();
  const Eigen::LDLT<Eigen::Matrix<double, 6, 6>> solver(normal_matrix);
  if (solver.info() != Eigen::Success)
    return fit;
  const Eigen::Matrix<double, 6, 1> c = solver.solve(rhs);
  if (!c.allFinite())
    return fit;
  const Eigen::Vector3d dq = -mean;  // the query relative to the frame's origin
  const double u = dq.dot(e1) * inv_h, v = dq.dot(e2) * inv_h, z = dq.dot(n);
  const double height = c(0) + c(1) * u + c(2) * v + c(3) * u * u + c(4) * u * v + c(5) * v * v;
  const double dh_du = (c(1) + 2.0 * c(3) * u + c(4) * v) * inv_h;
  const double dh_dv = (c(2) + c(4) * u + 2.0 * c(5) * v) * inv_h;
  fit.residual = z - height;
  if (!leave_one_out && self >= 0 && parameters.want_leverage) {  // ∂height/∂(own sample's height): weight × rowᵀ N⁻¹ row
    row << 1.0, u, v, u * u, u * v, v * v;
    fit.leverage = weights[static_cast<std::size_t>(self)] * row.dot(solver.solve(row));
  }
  // The same fit without the query's own sample (frame kept): its height there is an honest
  // prediction, so a point the fit bent towards still shows how far it is from its neighbours.
  fit.loo_residual = fit.residual;
  if (!leave_one_out && self >= 0 && parameters.want_loo_residual) {
    const Eigen::Vector3d d = offsets[static_cast<std::size_t>(self)] - mean;
    const double su = d.dot(e1) * inv_h, sv = d.dot(e2) * inv_h, sz = d.dot(n);
    row << 1.0, su, sv, su * su, su * sv, sv * sv;
    const double w = weights[static_cast<std::size_t>(self)];
    Eigen::Matrix<double, 6, 6> reduced = normal_matrix;
    reduced.noalias() -= w * row * row.transpose();
    const Eigen::LDLT<Eigen::Matrix<double, 6, 6>> loo(reduced);
    const Eigen::Matrix<double, 6, 1> cl = loo.solve(rhs - w * sz * row);
    if (loo.info() == Eigen::Success && cl.allFinite())
      fit.loo_residual = z - (cl(0) + cl(1) * u + cl(2) * v + cl(3) * u * u + cl(4) * u * v + cl(5) * v * v);
  }
  fit.position = q + (height - z) * n;
  fit.normal = (n - dh_du * e1 - dh_dv * e2).normalized();
  fit.valid = fit.position.allFinite() && fit.normal.allFinite();
  return fit;
}

}  // namespace

void fitLocalQuadrics(const std::vector<Eigen::Vector3d>& points, const std::vector<char>& usable,
                      const RadiusNeighbourSearch& search, const std::vector<std::size_t>& queries,
                      const LocalQuadricParameters& parameters, bool leave_one_out,
                      std::vector<LocalQuadricFit>& fits)
{
  if (!(parameters.bandwidth > 0.0) || !std::isfinite(parameters.bandwidth))
    throw Error("local quadric fit: the bandwidth must be positive and finite");
  if (!(parameters.support_factor >= 1.0) || parameters.max_neighbours < 6 || parameters.min_neighbours < 6 ||
      parameters.min_neighbours > parameters.max_neighbours)
    throw Error("local quadric fit: support factor must be ≥ 1 and 6 ≤ min neighbours ≤ max neighbours");
  if (!usable.empty() && usable.size() != points.size())
    throw Error("local quadric fit: one usable flag per point is needed");
  fits.assign(queries.size(), LocalQuadricFit{});
  const double radius = parameters.support_factor * parameters.bandwidth;
  const auto n = static_cast<std::ptrdiff_t>(queries.size());
#ifdef _OPENMP
  const int threads = parameters.num_threads > 0 ? parameters.num_threads : omp_get_max_threads();
#endif
#pragma omp parallel num_threads(threads)
  {
    pcl::Indices indices;
    std::vector<float> squared;
#pragma omp for schedule(dynamic, 512)
    for (std::ptrdiff_t i = 0; i < n; ++i) {
      const std::size_t query = queries[static_cast<std::size_t>(i)];
      if (query >= points.size() || !points[query].allFinite())
        continue;
      search(query, radius, parameters.max_neighbours, indices, squared);
      fits[static_cast<std::size_t>(i)] =
          fitOne(points, usable, query, indices, squared, parameters, leave_one_out);
    }
  }
}

}  // namespace patchdict
}  // namespace pcl
