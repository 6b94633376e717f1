// BiharmonicImplicit (see biharmonic_implicit.h).
#include <pcl_patchdict/cloud/biharmonic_implicit.h>
#include <pcl_patchdict/core/error.h>

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
  Eigen::Vector3d centre = Eigen::Vector3d::Zero();
  for (std::size_t i = 0; i < n; ++i) {
    if (!points[i].allFinite() || !normals[i].allFinite() || !(normals[i].norm() > 0.0))
      throw Error("biharmonic implicit: non-finite point or normal");
    centre += points[i];
  }
  centre /= static_cast<double>(n);
  double scale = 0.0;
  for (const auto& p : points)
    scale = std::max(scale, (p - centre).norm());
  if (!(scale > 0.0))
    throw Error("biharmonic implicit: the points coincide");
  scale += epsilon;
  // Centres: each point and its two offsets along the normal, with values 0, +ε_i, −ε_i. As Carr et
  // al. do, ε_i is halved (up to 3 times) until the offset point's nearest input point is p_i
  // itself: across a thin sheet or a fold an offset of ε would land beside the other side's points
  // and contradict their constraints.
  std::vector<Eigen::Vector3d> centres;
  std::vector<double> values;
  centres.reserve(3 * n);
  values.reserve(3 * n);
  std::vector<Eigen::Vector3d> scaled(n);
  for (std::size_t i = 0; i < n; ++i)
    scaled[i] = (points[i] - centre) / scale;
  const auto nearest_is = [&](const Eigen::Vector3d& q, std::size_t i) {
    const double own = (q - scaled[i]).squaredNorm();
    for (std::size_t j = 0; j < n; ++j)
      if (j != i && (q - scaled[j]).squaredNorm() < own)
        return false;
    return true;
  };
  for (std::size_t i = 0; i < n; ++i) {
    const Eigen::Vector3d u = normals[i].normalized();
    double e = epsilon / scale;
    for (int halving = 0; halving < 3 && !(nearest_is(scaled[i] + e * u, i) && nearest_is(scaled[i] - e * u, i));
         ++halving)
      e *= 0.5;
    centres.push_back(scaled[i]);
    values.push_back(0.0);
    centres.push_back(scaled[i] + e * u);
    values.push_back(e);
    centres.push_back(scaled[i] - e * u);
    values.push_back(-e);
  }
  const auto m = static_cast<Eigen::Index>(centres.size());
  Eigen::MatrixXd system = Eigen::MatrixXd::Zero(m + 4, m + 4);
  Eigen::VectorXd rhs = Eigen::VectorXd::Zero(m + 4);
  for (Eigen::Index i = 0; i < m; ++i) {
    const Eigen::Vector3d& ci = centres[static_cast<std::size_t>(i)];
    for (Eigen::Index j = i + 1; j < m; ++j)
      system(i, j) = system(j, i) = (ci - centres[static_cast<std::size_t>(j)]).norm();
    system(i, m) = system(m, i) = 1.0;
    for (int k = 0; k < 3; ++k)
      system(i, m + 1 + k) = system(m + 1 + k, i) = ci(k);
    rhs(i) = values[static_cast<std::size_t>(i)];
  }
  const Eigen::PartialPivLU<Eigen::MatrixXd> lu(system);
  const Eigen::VectorXd solution = lu.solve(rhs);
  if (!solution.allFinite() || (system * solution - rhs).norm() > 1e-6 * (1.0 + rhs.norm()))
    throw Error("biharmonic implicit: the system is singular (duplicate points, or constraints that contradict)");
  // Only a successful fit replaces the previous one.
  centres_ = std::move(centres);
  weights_ = solution.head(m);
  affine_ = solution.tail<4>();
  centre_ = centre;
  scale_ = scale;
}

double BiharmonicImplicit::valueAndGradient(const Eigen::Vector3d& x, Eigen::Vector3d& gradient) const
{
  const Eigen::Vector3d y = (x - centre_) / scale_;
  double f = affine_(0) + affine_.tail<3>().dot(y);
  gradient = affine_.tail<3>();
  for (std::size_t i = 0; i < centres_.size(); ++i) {
    const Eigen::Vector3d d = y - centres_[i];
    const double r = d.norm();
    const double w = weights_(static_cast<Eigen::Index>(i));
    f += w * r;
    if (r > 0.0)
      gradient += (w / r) * d;
  }
  return f * scale_;  // values back in the points' units; d(f·scale)/dx = df/dy
}

double BiharmonicImplicit::operator()(const Eigen::Vector3d& x) const
{
  Eigen::Vector3d gradient;
  return valueAndGradient(x, gradient);
}

Eigen::Vector3d BiharmonicImplicit::gradient(const Eigen::Vector3d& x) const
{
  Eigen::Vector3d gradient;
  valueAndGradient(x, gradient);
  return gradient;
}

bool BiharmonicImplicit::project(Eigen::Vector3d& x, double tolerance, int iterations) const
{
  Eigen::Vector3d g;
  for (int k = 0; k <= iterations; ++k) {
    const double f = valueAndGradient(x, g);
    if (!std::isfinite(f))
      return false;
    if (std::abs(f) <= tolerance)
      return true;
    if (k == iterations)
      break;
    const double g2 = g.squaredNorm();
    if (!(g2 > 1e-12))
      return false;
    x -= (f / g2) * g;
  }
  return false;
}

}  // namespace patchdict
}  // namespace pcl
