// ThinPlateSpline (see thin_plate_spline.h).
#include <pcl_patchdict/core/error.h>
#include <pcl_patchdict/geometry/thin_plate_spline.h>

#include <Eigen/Dense>

#include <cmath>

namespace pcl {
namespace patchdict {

namespace {
double kernel(double r2) { return r2 > 0.0 ? 0.5 * r2 * std::log(r2) : 0.0; }  // r² log r
}  // namespace

void ThinPlateSpline::fit(const std::vector<Eigen::Vector2d>& sites, const std::vector<double>& heights,
                          double smoothing)
{
  const std::size_t n = sites.size();
  if (n < 3 || heights.size() != n)
    throw Error("thin-plate spline: at least 3 sites, one height each, are needed");
  if (!(smoothing >= 0.0) || !std::isfinite(smoothing))
    throw Error("thin-plate spline: the smoothing must be finite and ≥ 0");
  centre_.setZero();
  for (std::size_t i = 0; i < n; ++i) {
    if (!sites[i].allFinite() || !std::isfinite(heights[i]))
      throw Error("thin-plate spline: non-finite site or height");
    centre_ += sites[i];
  }
  centre_ /= static_cast<double>(n);
  scale_ = 0.0;
  for (const auto& s : sites)
    scale_ = std::max(scale_, (s - centre_).norm());
  if (!(scale_ > 0.0))
    throw Error("thin-plate spline: the sites coincide");
  sites_.resize(n);
  for (std::size_t i = 0; i < n; ++i)
    sites_[i] = (sites[i] - centre_) / scale_;
  Eigen::Matrix2d spread = Eigen::Matrix2d::Zero();
  for (const auto& s : sites_)
    spread += s * s.transpose();
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> extent(spread);
  if (!(extent.eigenvalues()(0) > 1e-12 * extent.eigenvalues()(1)))
    throw Error("thin-plate spline: the sites are collinear");
  const auto m = static_cast<Eigen::Index>(n);
  Eigen::MatrixXd system = Eigen::MatrixXd::Zero(m + 3, m + 3);
  Eigen::VectorXd rhs = Eigen::VectorXd::Zero(m + 3);
  for (Eigen::Index i = 0; i < m; ++i) {
    for (Eigen::Index j = i + 1; j < m; ++j)
      system(i, j) = system(j, i) = kernel((sites_[static_cast<std::size_t>(i)] - sites_[static_cast<std::size_t>(j)]).squaredNorm());
    system(i, i) = smoothing;
    system(i, m) = system(m, i) = 1.0;
    system(i, m + 1) = system(m + 1, i) = sites_[static_cast<std::size_t>(i)].x();
    system(i, m + 2) = system(m + 2, i) = sites_[static_cast<std::size_t>(i)].y();
    rhs(i) = heights[static_cast<std::size_t>(i)];
  }
  const Eigen::PartialPivLU<Eigen::MatrixXd> lu(system);
  const Eigen::VectorXd solution = lu.solve(rhs);
  if (!solution.allFinite() || (system * solution - rhs).norm() > 1e-6 * (1.0 + rhs.norm()))
    throw Error("thin-plate spline: the system is singular (collinear sites?)");
  weights_ = solution.head(m);
  affine_ = solution.tail<3>();
}

double ThinPlateSpline::operator()(const Eigen::Vector2d& x) const
{
  const Eigen::Vector2d y = (x - centre_) / scale_;
  double f = affine_(0) + affine_(1) * y.x() + affine_(2) * y.y();
  for (std::size_t i = 0; i < sites_.size(); ++i)
    f += weights_(static_cast<Eigen::Index>(i)) * kernel((y - sites_[i]).squaredNorm());
  return f;
}

Eigen::Vector2d ThinPlateSpline::gradient(const Eigen::Vector2d& x) const
{
  const Eigen::Vector2d y = (x - centre_) / scale_;
  Eigen::Vector2d g(affine_(1), affine_(2));
  for (std::size_t i = 0; i < sites_.size(); ++i) {
    const Eigen::Vector2d d = y - sites_[i];
    const double r2 = d.squaredNorm();
    if (r2 > 0.0)  // ∇(½ r² log r²) = d (log r² + 1)
      g += weights_(static_cast<Eigen::Index>(i)) * d * (std::log(r2) + 1.0);
  }
  return g / scale_;
}

}  // namespace patchdict
}  // namespace pcl
