// BiharmonicImplicit (see biharmonic_implicit.h).
#include <pcl_patchdict/biharmonic_implicit.h>
#include <pcl_patchdict/error.h>

#include <Eigen/Dense>

#include <cmath>

namespace pcl {
namespace patchdict {

void BiharmonicImplicit::fit(const std::vector<Eigen::Vector3d>& points, const std::vector<Eigen::Vector3d>& normals,
                             double epsilon)
{
  const std::size_t n = points.size();
  if (n < 4 || normals.size() != n)
    throw Error("biharmonic implicit: at least 4 points, one normal each, are needed");
  if (!(epsilon > 0.0) || !std::isfinite(epsilon))
    throw Error("biharmonic implicit: the normal offset ε must be finite and > 0");
  centre_.setZero();
  for (std::size_t i = 0; i < n; ++i) {
    if (!points[i].allFinite() || !normals[i].allFinite() || !(normals[i].norm() > 0.0))
      throw Error("biharmonic implicit: non-finite point or normal");
    centre_ += points[i];
  }
  centre_ /= static_cast<double>(n);
  scale_ = 0.0;
  for (const auto& p : points)
    scale_ = std::max(scale_, (p - centre_).norm());
  scale_ += epsilon;
  if (!(scale_ > epsilon))
    throw Error("biharmonic implicit: the points coincide");
  // Centres: each point, and its two offsets along the normal; values 0, +ε, −ε (scaled).
  const double e = epsilon / scale_;
  centres_.clear();
  centres_.reserve(3 * n);
  std::vector<double> values;
  values.reserve(3 * n);
  for (std::size_t i = 0; i < n; ++i) {
    const Eigen::Vector3d p = (points[i] - centre_) / scale_, u = normals[i].normalized();
    centres_.push_back(p);
    values.push_back(0.0);
    centres_.push_back(p + e * u);
    values.push_back(e);
    centres_.push_back(p - e * u);
    values.push_back(-e);
  }
  const auto m = static_cast<Eigen::Index>(centres_.size());
  Eigen::MatrixXd system = Eigen::MatrixXd::Zero(m + 4, m + 4);
  Eigen::VectorXd rhs = Eigen::VectorXd::Zero(m + 4);
  for (Eigen::Index i = 0; i < m; ++i) {
    const Eigen::Vector3d& ci = centres_[static_cast<std::size_t>(i)];
    for (Eigen::Index j = i + 1; j < m; ++j)
      system(i, j) = system(j, i) = (ci - centres_[static_cast<std::size_t>(j)]).norm();
    system(i, m) = system(m, i) = 1.0;
    for (int k = 0; k < 3; ++k)
      system(i, m + 1 + k) = system(m + 1 + k, i) = ci(k);
    rhs(i) = values[static_cast<std::size_t>(i)];
  }
  const Eigen::PartialPivLU<Eigen::MatrixXd> lu(system);
  const Eigen::VectorXd solution = lu.solve(rhs);
  if (!solution.allFinite() || (system * solution - rhs).norm() > 1e-6 * (1.0 + rhs.norm())) {
    centres_.clear();
    throw Error("biharmonic implicit: the system is singular (coplanar points with one normal?)");
  }
  weights_ = solution.head(m);
  affine_ = solution.tail<4>();
}

double BiharmonicImplicit::operator()(const Eigen::Vector3d& x) const
{
  const Eigen::Vector3d y = (x - centre_) / scale_;
  double f = affine_(0) + affine_.tail<3>().dot(y);
  for (std::size_t i = 0; i < centres_.size(); ++i)
    f += weights_(static_cast<Eigen::Index>(i)) * (y - centres_[i]).norm();
  return f * scale_;  // back in the points' units (the values were scaled with them)
}

Eigen::Vector3d BiharmonicImplicit::gradient(const Eigen::Vector3d& x) const
{
  const Eigen::Vector3d y = (x - centre_) / scale_;
  Eigen::Vector3d g = affine_.tail<3>();
  for (std::size_t i = 0; i < centres_.size(); ++i) {
    const Eigen::Vector3d d = y - centres_[i];
    const double r = d.norm();
    if (r > 0.0)
      g += weights_(static_cast<Eigen::Index>(i)) * d / r;
  }
  return g;  // d(f·scale)/dx = df/dy
}

bool BiharmonicImplicit::project(Eigen::Vector3d& x, double tolerance, int iterations) const
{
  for (int k = 0; k <= iterations; ++k) {
    const double f = (*this)(x);
    if (!std::isfinite(f))
      return false;
    if (std::abs(f) <= tolerance)
      return true;
    if (k == iterations)
      break;
    const Eigen::Vector3d g = gradient(x);
    const double g2 = g.squaredNorm();
    if (!(g2 > 1e-12))
      return false;
    x -= (f / g2) * g;
  }
  return false;
}

}  // namespace patchdict
}  // namespace pcl
