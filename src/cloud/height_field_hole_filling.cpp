// Height-field hole filling (see height_field_hole_filling.h).
//
// Pipeline: robust centring and outlier rejection → up frame → spacing s (median 4-NN distance on a
// subsample, grid hash) → plane raster at ~2.5 s → the outside of the data's footprint (the empty
// cells a square probe reaches from beyond the raster: the complement of a morphological closing of
// the occupied cells, Serra 1982) → 4-connected components of the other empty cells, kept when
// mostly enclosed (a narrow mouth to the outside is tolerated) and of plausible size → per hole, a
// robust quadric fitted to the rim (seeded on the lowest point per cell, then IRLS with Tukey's
// biweight; Holland & Welsch, "Robust regression using iteratively reweighted least-squares", 1977)
// plus a thin-plate spline through the pooled rim residuals (Duchon 1977), so the fill meets the rim
// it leaves — the "trend + residual interpolation" scheme of universal kriging / DTM gap filling —
// sampled on a lattice of step ~s where no input point is within 0.75 s in the plane.
#include <pcl_patchdict/core/error.h>
#include <pcl_patchdict/cloud/height_field_hole_filling.h>
#include <pcl_patchdict/geometry/thin_plate_spline.h>

#include <Eigen/Dense>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <limits>
#include <string>

namespace pcl {
namespace patchdict {

namespace {

using Vec3 = Eigen::Vector3d;
using Vec2 = Eigen::Vector2d;

double quantile(std::vector<double>& values, double q)
{
  const auto k = static_cast<std::ptrdiff_t>(q * static_cast<double>(values.size() - 1));
  std::nth_element(values.begin(), values.begin() + k, values.end());
  return values[static_cast<std::size_t>(k)];
}

/// The finite points, less those farther from the median than 4 × the extent of the central 99.8 %
/// on some axis (a point at 1e30 must not stretch the raster); their median as the centre.
struct Bulk {
  std::vector<std::size_t> kept;
  Vec3 centre = Vec3::Zero();
};

Bulk robustBulk(const std::vector<Vec3>& points)
{
  Bulk bulk;
  std::vector<std::size_t> finite;
  finite.reserve(points.size());
  for (std::size_t i = 0; i < points.size(); ++i)
    if (points[i].allFinite())
      finite.push_back(i);
  if (finite.empty())
    return bulk;
  Vec3 low, high;
  std::vector<double> axis(finite.size());
  for (int a = 0; a < 3; ++a) {
    for (std::size_t k = 0; k < finite.size(); ++k)
      axis[k] = points[finite[k]](a);
    bulk.centre(a) = quantile(axis, 0.5);
    low(a) = quantile(axis, 0.001);
    high(a) = quantile(axis, 0.999);
  }
  const double extent = std::max((high - low).maxCoeff(), 1e-9 * (1.0 + bulk.centre.cwiseAbs().maxCoeff()));
  for (const std::size_t i : finite)
    if (((points[i] - bulk.centre).cwiseAbs().array() <= 4.0 * extent).all())
      bulk.kept.push_back(i);
  axis.resize(bulk.kept.size());  // the centre of what is kept: the outliers do not move the lattice
  for (int a = 0; a < 3; ++a) {
    for (std::size_t k = 0; k < bulk.kept.size(); ++k)
      axis[k] = points[bulk.kept[k]](a);
    bulk.centre(a) = quantile(axis, 0.5);
  }
  return bulk;
}

/// Rows e1, e2, up: a right-handed frame whose third axis is `up` (unit).
Eigen::Matrix3d frameFor(const Vec3& up)
{
  const Vec3 z = up.normalized();
  const Vec3 seed = std::abs(z.x()) < 0.9 ? Vec3::UnitX() : Vec3::UnitY();
  const Vec3 e1 = (seed - seed.dot(z) * z).normalized();
  Eigen::Matrix3d rot;
  rot.row(0) = e1.transpose();
  rot.row(1) = z.cross(e1).transpose();
  rot.row(2) = z.transpose();
  return rot;
}

/// Least-variance axis of the bulk (PCA) oriented towards +z (or its largest component positive);
/// eigenvalues ascending in `variances`.
Vec3 pcaUp(const std::vector<Vec3>& points, const Bulk& bulk, Vec3* variances = nullptr)
{
  Eigen::Matrix3d cov = Eigen::Matrix3d::Zero();
  for (const std::size_t i : bulk.kept) {
    const Vec3 d = points[i] - bulk.centre;
    cov += d * d.transpose();
  }
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(cov / std::max<double>(1.0, bulk.kept.size()));
  Vec3 up = eig.eigenvectors().col(0);
  Eigen::Index largest = 0;
  up.cwiseAbs().maxCoeff(&largest);
  if (up.z() < -1e-9 || (std::abs(up.z()) <= 1e-9 && up(largest) < 0.0))
    up = -up;
  if (variances)
    *variances = eig.eigenvalues();
  return up;
}

std::vector<Vec3> toLocal(const std::vector<Vec3>& points, const Bulk& bulk, const Eigen::Matrix3d& rot)
{
  std::vector<Vec3> local(bulk.kept.size());
  for (std::size_t k = 0; k < bulk.kept.size(); ++k)
    local[k] = rot * (points[bulk.kept[k]] - bulk.centre);
  return local;
}

/// Median of the pooled distances to the 4 nearest neighbours of ~20 000 subsampled points (zero
/// distances, duplicates, left out), with a 3-D grid hash of sorted cell keys; 0 if undefined.
double estimateSpacing(const std::vector<Vec3>& local)
{
  const std::size_t n = local.size();
  if (n < 2)
    return 0.0;
  Vec3 low = local[0], high = local[0];
  for (const Vec3& p : local) {
    low = low.cwiseMin(p);
    high = high.cwiseMax(p);
  }
  const double area = std::max((high.x() - low.x()) * (high.y() - low.y()), 1e-300);
  double g = std::sqrt(2.0 * area / static_cast<double>(n));
  if (!(g > 0.0) || !std::isfinite(g))
    g = std::max((high - low).maxCoeff(), 1e-300);
  const std::int64_t cap = (std::int64_t(1) << 21) - 1;
  auto cellOf = [&](const Vec3& p) {
    Eigen::Matrix<std::int64_t, 3, 1> c;
    for (int a = 0; a < 3; ++a)
      c(a) = std::min<std::int64_t>(cap, static_cast<std::int64_t>((p(a) - low(a)) / g));
    return c;
  };
  auto key = [](std::int64_t i, std::int64_t j, std::int64_t k) { return (i << 42) | (j << 21) | k; };
  std::vector<std::pair<std::int64_t, std::uint32_t>> sorted(n);
  for (std::size_t i = 0; i < n; ++i) {
    const auto c = cellOf(local[i]);
    sorted[i] = {key(c(0), c(1), c(2)), static_cast<std::uint32_t>(i)};
  }
  std::sort(sorted.begin(), sorted.end());
  const std::size_t stride = std::max<std::size_t>(1, n / 20000);
  std::vector<double> pooled;
  std::vector<double> near;
  for (std::size_t q = 0; q < n; q += stride) {
    const auto c = cellOf(local[q]);
    for (std::int64_t r = 1; r <= 4; ++r) {
      near.clear();
      for (std::int64_t i = std::max<std::int64_t>(0, c(0) - r); i <= std::min(cap, c(0) + r); ++i)
        for (std::int64_t j = std::max<std::int64_t>(0, c(1) - r); j <= std::min(cap, c(1) + r); ++j)
          for (std::int64_t k = std::max<std::int64_t>(0, c(2) - r); k <= std::min(cap, c(2) + r); ++k) {
            auto it = std::lower_bound(sorted.begin(), sorted.end(), std::make_pair(key(i, j, k), std::uint32_t(0)));
            for (; it != sorted.end() && it->first == key(i, j, k); ++it) {
              const double d = (local[it->second] - local[q]).norm();
              if (d > 0.0)
                near.push_back(d);
            }
          }
      if (near.size() < 4)
        continue;
      std::partial_sort(near.begin(), near.begin() + 4, near.end());
      if (near[3] <= static_cast<double>(r) * g || r == 4) {
        pooled.insert(pooled.end(), near.begin(), near.begin() + 4);
        break;
      }
    }
  }
  return pooled.empty() ? 0.0 : quantile(pooled, 0.5);
}

/// Plane raster with an empty pad of `pad` cells all round, points listed per cell (CSR).
struct Raster {
  double u0 = 0.0, v0 = 0.0, cell = 1.0;
  std::size_t nx = 0, ny = 0;
  std::vector<std::uint32_t> start, order;
  std::size_t index(std::size_t i, std::size_t j) const { return j * nx + i; }
  std::size_t count(std::size_t c) const { return start[c + 1] - start[c]; }
  /// f(i, j, cell index) for the cells within Chebyshev distance R of (ci, cj), clipped.
  template <class F>
  void around(std::ptrdiff_t ci, std::ptrdiff_t cj, std::ptrdiff_t R, F f) const
  {
    for (std::ptrdiff_t j = std::max<std::ptrdiff_t>(0, cj - R); j <= std::min<std::ptrdiff_t>(ny - 1, cj + R); ++j)
      for (std::ptrdiff_t i = std::max<std::ptrdiff_t>(0, ci - R); i <= std::min<std::ptrdiff_t>(nx - 1, ci + R); ++i)
        f(i, j, static_cast<std::size_t>(j) * nx + static_cast<std::size_t>(i));
  }
  template <class F>
  void around(const Vec2& x, std::ptrdiff_t R, F f) const
  {
    around(static_cast<std::ptrdiff_t>((x.x() - u0) / cell), static_cast<std::ptrdiff_t>((x.y() - v0) / cell), R, f);
  }
};

Raster buildRaster(const std::vector<Vec3>& local, double cell, std::size_t max_cells, std::size_t pad = 1)
{
  Raster r;
  r.cell = cell;
  double u1 = -std::numeric_limits<double>::infinity(), v1 = u1;
  r.u0 = r.v0 = std::numeric_limits<double>::infinity();
  for (const Vec3& p : local) {
    r.u0 = std::min(r.u0, p.x());
    r.v0 = std::min(r.v0, p.y());
    u1 = std::max(u1, p.x());
    v1 = std::max(v1, p.y());
  }
  const double fx = (u1 - r.u0) / cell + 1.0 + 2.0 * static_cast<double>(pad), fy = (v1 - r.v0) / cell + 1.0 + 2.0 * static_cast<double>(pad);
  if (!(fx * fy <= static_cast<double>(max_cells)))
    throw Error("height-field fill: the raster would need " + std::to_string(static_cast<long long>(fx * fy)) +
                " cells of " + std::to_string(cell) + " (max_raster_cells " + std::to_string(max_cells) +
                "): the cloud is too wide for its spacing");
  r.nx = static_cast<std::size_t>(fx);
  r.ny = static_cast<std::size_t>(fy);
  const double umin = r.u0, vmin = r.v0;  // indices from the data's corner: no point rounds into the pad
  r.u0 -= static_cast<double>(pad) * cell;
  r.v0 -= static_cast<double>(pad) * cell;
  r.start.assign(r.nx * r.ny + 1, 0);
  std::vector<std::uint32_t> cell_of(local.size());
  for (std::size_t k = 0; k < local.size(); ++k) {
    const auto i = pad + std::min(r.nx - 1 - 2 * pad, static_cast<std::size_t>((local[k].x() - umin) / cell));
    const auto j = pad + std::min(r.ny - 1 - 2 * pad, static_cast<std::size_t>((local[k].y() - vmin) / cell));
    cell_of[k] = static_cast<std::uint32_t>(r.index(i, j));
    ++r.start[cell_of[k] + 1];
  }
  for (std::size_t c = 0; c + 1 < r.start.size(); ++c)
    r.start[c + 1] += r.start[c];
  r.order.resize(local.size());
  std::vector<std::uint32_t> fill(r.start.begin(), r.start.end() - 1);
  for (std::size_t k = 0; k < local.size(); ++k)
    r.order[fill[cell_of[k]]++] = static_cast<std::uint32_t>(k);
  return r;
}

/// Box sums of `mask` over squares of half-width `h` (clamped at the raster's edge), separable.
std::vector<std::uint32_t> boxCount(const Raster& r, const std::vector<char>& mask, std::size_t h)
{
  std::vector<std::uint32_t> rows(mask.size()), out(mask.size());
  std::vector<std::uint32_t> prefix(std::max(r.nx, r.ny) + 1);
  for (std::size_t j = 0; j < r.ny; ++j) {
    for (std::size_t i = 0; i < r.nx; ++i)
      prefix[i + 1] = prefix[i] + (mask[r.index(i, j)] ? 1 : 0);
    for (std::size_t i = 0; i < r.nx; ++i)
      rows[r.index(i, j)] = prefix[std::min(r.nx, i + h + 1)] - prefix[i >= h ? i - h : 0];
  }
  for (std::size_t i = 0; i < r.nx; ++i) {
    for (std::size_t j = 0; j < r.ny; ++j)
      prefix[j + 1] = prefix[j] + rows[r.index(i, j)];
    for (std::size_t j = 0; j < r.ny; ++j)
      out[r.index(i, j)] = prefix[std::min(r.ny, j + h + 1)] - prefix[j >= h ? j - h : 0];
  }
  return out;
}

/// The outside of the data's footprint: the empty cells a square probe of half-width `probe` cells
/// sweeps when it moves in from the pad (wider than the probe) through empty cells only — the
/// pad-connected part of the opening of the empty cells. Bays whose mouth is narrower than the
/// probe stay inside the footprint.
std::vector<char> outsideMask(const Raster& r, std::size_t probe)
{
  const std::size_t n = r.nx * r.ny;
  std::vector<char> occupied(n);
  for (std::size_t c = 0; c < n; ++c)
    occupied[c] = r.count(c) > 0;
  const std::vector<std::uint32_t> blocked = boxCount(r, occupied, probe);
  std::vector<char> reached(n, 0);
  std::vector<std::uint32_t> queue{0};
  reached[0] = 1;
  for (std::size_t head = 0; head < queue.size(); ++head) {
    const std::size_t c = queue[head], i = c % r.nx, j = c / r.nx;
    const std::size_t next[4] = {i > 0 ? c - 1 : c, i + 1 < r.nx ? c + 1 : c, j > 0 ? c - r.nx : c,
                                 j + 1 < r.ny ? c + r.nx : c};
    for (const std::size_t d : next)
      if (!reached[d] && blocked[d] == 0) {
        reached[d] = 1;
        queue.push_back(static_cast<std::uint32_t>(d));
      }
  }
  const std::vector<std::uint32_t> swept = boxCount(r, reached, probe);
  std::vector<char> outside(n);
  for (std::size_t c = 0; c < n; ++c)
    outside[c] = swept[c] > 0 && !occupied[c];
  return outside;
}

/// 4-connected components of the empty cells inside the footprint; label −1 for the others.
struct Components {
  std::vector<std::int32_t> label;
  std::vector<std::vector<std::uint32_t>> cells;
};

Components emptyComponents(const Raster& r, const std::vector<char>& outside)
{
  Components comp;
  comp.label.assign(r.nx * r.ny, -1);
  const std::int32_t unvisited = std::numeric_limits<std::int32_t>::max();
  for (std::size_t c = 0; c < comp.label.size(); ++c)
    if (r.count(c) == 0 && !outside[c])
      comp.label[c] = unvisited;
  for (std::size_t seed = 0; seed < comp.label.size(); ++seed) {
    if (comp.label[seed] != unvisited)
      continue;
    const auto id = static_cast<std::int32_t>(comp.cells.size());
    comp.cells.emplace_back();
    std::vector<std::uint32_t>& list = comp.cells.back();
    comp.label[seed] = id;
    list.push_back(static_cast<std::uint32_t>(seed));
    for (std::size_t head = 0; head < list.size(); ++head) {
      const std::size_t c = list[head], i = c % r.nx, j = c / r.nx;
      const std::size_t next[4] = {i > 0 ? c - 1 : c, i + 1 < r.nx ? c + 1 : c, j > 0 ? c - r.nx : c,
                                   j + 1 < r.ny ? c + r.nx : c};
      for (const std::size_t d : next)
        if (comp.label[d] == unvisited) {
          comp.label[d] = id;
          list.push_back(static_cast<std::uint32_t>(d));
        }
    }
  }
  return comp;
}

/// Robust quadric h ≈ q(u, v) in coordinates centred on `origin` and scaled by `scale` (a plane
/// below 12 points). Seeded by least squares through the lowest rim point of each raster cell (the
/// ground under trees and roofs: the lowest-point seed of progressive TIN densification, Axelsson
/// 2000), then IRLS with Tukey's biweight (c = 4.685 σ, σ = 1.4826 MAD floored at `noise_floor`):
/// redescending, it settles on the surface the seed is near and gives outliers weight 0.
struct Quadric {
  Vec2 origin = Vec2::Zero();
  double scale = 1.0;
  Eigen::Matrix<double, 6, 1> c = Eigen::Matrix<double, 6, 1>::Zero();
  Eigen::Matrix<double, 6, 1> basis(const Vec2& x) const
  {
    const Vec2 y = (x - origin) / scale;
    Eigen::Matrix<double, 6, 1> b;
    b << 1.0, y.x(), y.y(), y.x() * y.x(), y.x() * y.y(), y.y() * y.y();
    return b;
  }
  double operator()(const Vec2& x) const { return c.dot(basis(x)); }
};

void solveWeighted(const std::vector<Vec3>& pts, const std::vector<double>& w, int terms, Quadric& q)
{
  Eigen::MatrixXd normal = Eigen::MatrixXd::Zero(terms, terms);
  Eigen::VectorXd rhs = Eigen::VectorXd::Zero(terms);
  for (std::size_t k = 0; k < pts.size(); ++k) {
    const Eigen::VectorXd b = q.basis(pts[k].head<2>()).head(terms);
    normal.noalias() += w[k] * b * b.transpose();
    rhs.noalias() += w[k] * pts[k].z() * b;
  }
  normal.diagonal().array() += 1e-9 * (1.0 + normal.diagonal().maxCoeff());
  q.c.setZero();
  q.c.head(terms) = normal.ldlt().solve(rhs);
}

std::vector<double> fitRobustQuadric(const std::vector<Vec3>& rim, const std::vector<Vec3>& seeds,
                                     double noise_floor, Quadric& q)
{
  const std::size_t n = rim.size();
  solveWeighted(seeds, std::vector<double>(seeds.size(), 1.0), seeds.size() >= 12 ? 6 : 3, q);
  const int terms = n >= 12 ? 6 : 3;
  std::vector<double> w(n, 1.0), residual(n), absolute(n);
  for (int round = 0; round < 8; ++round) {
    if (round > 0)
      solveWeighted(rim, w, terms, q);
    for (std::size_t k = 0; k < n; ++k) {
      residual[k] = rim[k].z() - q(rim[k].head<2>());
      absolute[k] = std::abs(residual[k]);
    }
    const double sigma = std::max(noise_floor, 1.4826 * quantile(absolute, 0.5));
    for (std::size_t k = 0; k < n; ++k) {
      const double t = std::abs(residual[k]) / (4.685 * sigma);
      w[k] = t < 1.0 ? (1.0 - t * t) * (1.0 - t * t) : 0.0;
    }
  }
  return w;
}

/// Thin-plate spline through the inlier rim residuals, pooled (median) into square cells grown
/// until at most max_sites remain. False when there are too few sites or the fit fails.
bool fitResidualSpline(const std::vector<Vec3>& rim, const std::vector<double>& w, const Quadric& q,
                       double cell, std::size_t max_sites, double smoothing, ThinPlateSpline& tps)
{
  std::vector<std::size_t> inliers;
  for (std::size_t k = 0; k < rim.size(); ++k)
    if (w[k] > 0.1)
      inliers.push_back(k);
  std::vector<std::pair<std::int64_t, std::size_t>> keyed(inliers.size());
  std::vector<Vec2> sites;
  std::vector<double> values;
  for (int attempt = 0; attempt < 40; ++attempt, cell *= 1.3) {
    for (std::size_t m = 0; m < inliers.size(); ++m) {
      const Vec2 x = (rim[inliers[m]].head<2>() - q.origin) / cell;
      keyed[m] = {(static_cast<std::int64_t>(std::floor(x.x())) + (1 << 20)) * (std::int64_t(1) << 22) +
                      static_cast<std::int64_t>(std::floor(x.y())) + (1 << 20), inliers[m]};
    }
    std::sort(keyed.begin(), keyed.end());
    sites.clear();
    values.clear();
    std::vector<double> group;
    for (std::size_t a = 0, b = 0; a < keyed.size(); a = b) {
      Vec2 mean = Vec2::Zero();
      group.clear();
      for (b = a; b < keyed.size() && keyed[b].first == keyed[a].first; ++b) {
        mean += rim[keyed[b].second].head<2>();
        group.push_back(rim[keyed[b].second].z() - q(rim[keyed[b].second].head<2>()));
      }
      sites.push_back(mean / static_cast<double>(b - a));
      values.push_back(quantile(group, 0.5));
    }
    if (sites.size() <= max_sites)
      break;
  }
  if (sites.size() < 6 || sites.size() > max_sites)
    return false;
  try {
    tps.fit(sites, values, smoothing);
  } catch (const Error&) {
    return false;
  }
  return true;
}

struct Settings {
  double s, cell, lattice, clearance, rim_width, min_radius, max_diameter, smoothing;
  std::size_t max_sites;
};

/// Distance in the plane from x to the nearest input point, searching `reach` cells around its
/// cell (capped at reach × cell).
double planeDistance(const Raster& r, const std::vector<Vec3>& local, const Vec2& x, std::size_t reach)
{
  double best = static_cast<double>(reach) * r.cell;
  r.around(x, static_cast<std::ptrdiff_t>(reach), [&](std::ptrdiff_t, std::ptrdiff_t, std::size_t c) {
    for (std::uint32_t k = r.start[c]; k < r.start[c + 1]; ++k)
      best = std::min(best, (local[r.order[k]].head<2>() - x).norm());
  });
  return best;
}

/// Cells within Chebyshev distance `reach` of the component (itself excluded), each once, sorted;
/// the component's cells get mark `stamp`, the ring's `stamp + 1`.
std::vector<std::uint32_t> dilation(const Raster& r, const std::vector<std::uint32_t>& cells, std::size_t reach,
                                    std::vector<std::uint32_t>& mark, std::uint32_t stamp)
{
  std::vector<std::uint32_t> ring;
  for (const std::uint32_t c : cells)
    mark[c] = stamp;
  for (const std::uint32_t c : cells)
    r.around(c % r.nx, c / r.nx, static_cast<std::ptrdiff_t>(reach), [&](std::ptrdiff_t, std::ptrdiff_t, std::size_t d) {
      if (mark[d] != stamp && mark[d] != stamp + 1) {
        mark[d] = stamp + 1;
        ring.push_back(static_cast<std::uint32_t>(d));
      }
    });
  std::sort(ring.begin(), ring.end());
  return ring;
}

/// Lattice points (global lattice of step `lattice`, anchored at the frame's origin) in cell c with
/// no input point within the clearance.
template <class Accept = bool (*)(const Vec2&)>
void latticeInCell(const Raster& r, const std::vector<Vec3>& local, std::size_t c, const Settings& st,
                   std::vector<Vec2>& out, Accept accept = [](const Vec2&) { return true; })
{
  const double ua = r.u0 + static_cast<double>(c % r.nx) * r.cell, va = r.v0 + static_cast<double>(c / r.nx) * r.cell;
  for (double b = std::ceil(va / st.lattice); b * st.lattice < va + r.cell; b += 1.0)
    for (double a = std::ceil(ua / st.lattice); a * st.lattice < ua + r.cell; a += 1.0) {
      const Vec2 x(a * st.lattice, b * st.lattice);
      if (accept(x) && planeDistance(r, local, x, 1) >= st.clearance)
        out.push_back(x);
    }
}

/// A component's extent (cells, the wider side of its bounding box), its boundary cells (4-adjacent
/// to a cell not in it) and of those the open ones (4-adjacent to the outside).
struct Shape {
  double width = 0.0;
  std::size_t boundary = 0, open = 0;
};

Shape shapeOf(const Raster& r, const std::vector<std::uint32_t>& cells, const std::vector<std::int32_t>& label,
              const std::vector<char>& outside)
{
  Shape shape;
  std::size_t i0 = r.nx, i1 = 0, j0 = r.ny, j1 = 0;
  for (const std::uint32_t c : cells) {  // never on the raster's edge: the pad is outside
    const std::size_t i = c % r.nx, j = c / r.nx;
    i0 = std::min(i0, i), i1 = std::max(i1, i), j0 = std::min(j0, j), j1 = std::max(j1, j);
    bool edge = false, open = false;
    for (const std::size_t d : {std::size_t(c) - 1, std::size_t(c) + 1, c - r.nx, c + r.nx}) {
      edge |= label[d] != label[c];
      open |= outside[d] != 0;
    }
    shape.boundary += edge;
    shape.open += open;
  }
  shape.width = static_cast<double>(std::max(i1 - i0, j1 - j0) + 1);
  return shape;
}

/// Whether x lies within half a cell of a cell marked `stamp` (the hole's empty cells): the fill
/// reaches into the occupied cells around a hole only as far as the hole's edge can lie.
bool nearCells(const Raster& r, const Vec2& x, const std::vector<std::uint32_t>& mark, std::uint32_t stamp)
{
  bool near = false;
  r.around(x, 1, [&](std::ptrdiff_t i, std::ptrdiff_t j, std::size_t c) {
    const Vec2 lo(r.u0 + static_cast<double>(i) * r.cell, r.v0 + static_cast<double>(j) * r.cell);
    near |= mark[c] == stamp && (lo - x).cwiseMax(x - lo - Vec2::Constant(r.cell)).cwiseMax(0.0).norm() <= 0.5 * r.cell;
  });
  return near;
}

enum class Outcome { filled, too_small, no_rim };

/// Fills one enclosed component: lattice over its cells and the occupied cells touching it
/// (unclaimed), heights from the rim's robust quadric + residual spline.
Outcome fillHole(const Raster& r, const std::vector<Vec3>& local, const std::vector<std::uint32_t>& cells,
                 const Settings& st, std::vector<std::uint32_t>& mark, std::uint32_t stamp,
                 std::vector<char>& claimed, std::vector<Vec3>& out_local, std::vector<std::size_t>& out_source)
{
  const auto reach = static_cast<std::size_t>(std::max(2.0, std::ceil(st.rim_width / r.cell)));
  const std::vector<std::uint32_t> ring = dilation(r, cells, reach, mark, stamp);
  std::vector<Vec2> lattice;
  for (const std::uint32_t c : cells)
    if (!claimed[c])
      latticeInCell(r, local, c, st, lattice);
  const std::size_t deep = lattice.size();
  const auto search = static_cast<std::size_t>(std::max(1.0, std::ceil(st.min_radius / r.cell)));
  double widest = 0.0;
  for (std::size_t m = 0; m < deep && widest < st.min_radius; ++m)
    widest = std::max(widest, planeDistance(r, local, lattice[m], search));
  if (widest < st.min_radius)
    return Outcome::too_small;
  std::vector<Vec3> rim, seeds;
  std::vector<std::uint32_t> rim_index;
  for (const std::uint32_t c : ring)
    for (std::uint32_t k = r.start[c]; k < r.start[c + 1]; ++k) {
      rim.push_back(local[r.order[k]]);
      rim_index.push_back(r.order[k]);
      if (k == r.start[c] || rim.back().z() < seeds.back().z())
        (k == r.start[c] ? seeds.emplace_back() : seeds.back()) = rim.back();
    }
  if (rim.size() < 4)
    return Outcome::no_rim;
  for (const std::uint32_t c : ring) {  // the occupied cells touching the hole: fill their gaps too
    bool touches = false;
    r.around(c % r.nx, c / r.nx, 1, [&](std::ptrdiff_t, std::ptrdiff_t, std::size_t d) { touches |= mark[d] == stamp; });
    if (touches && !claimed[c] && r.count(c) > 0)
      latticeInCell(r, local, c, st, lattice, [&](const Vec2& x) { return nearCells(r, x, mark, stamp); });
    if (touches)
      claimed[c] = 1;
  }
  for (const std::uint32_t c : cells)
    claimed[c] = 1;
  Quadric q;
  Vec2 lo = rim[0].head<2>(), hi = lo;
  for (const Vec3& p : rim) {
    lo = lo.cwiseMin(p.head<2>());
    hi = hi.cwiseMax(p.head<2>());
  }
  q.origin = 0.5 * (lo + hi);
  q.scale = std::max(0.5 * (hi - lo).maxCoeff(), st.s);
  const std::vector<double> w = fitRobustQuadric(rim, seeds, 0.05 * st.s, q);
  ThinPlateSpline tps;
  const bool spline = fitResidualSpline(rim, w, q, st.s, st.max_sites, st.smoothing, tps);
  for (const Vec2& x : lattice) {
    std::size_t best = 0;
    double best_d = std::numeric_limits<double>::infinity();
    for (std::size_t k = 0; k < rim.size(); ++k) {
      const double d = (rim[k].head<2>() - x).squaredNorm();
      if (d < best_d) {
        best_d = d;
        best = k;
      }
    }
    out_local.emplace_back(x.x(), x.y(), q(x) + (spline ? tps(x) : 0.0));
    out_source.push_back(rim_index[best]);
  }
  return Outcome::filled;
}

void checkParameters(const HeightFieldFillParameters& p)
{
  const std::pair<double, const char*> positive[] = {
      {p.detection_cell_factor, "detection_cell_factor"}, {p.max_hole_diameter_factor, "max_hole_diameter_factor"},
      {p.lattice_factor, "lattice_factor"}, {p.clearance_factor, "clearance_factor"}, {p.rim_width_factor, "rim_width_factor"}};
  const std::pair<double, const char*> non_negative[] = {
      {p.spacing, "spacing"}, {p.max_hole_diameter, "max_hole_diameter"}, {p.rim_smoothing, "rim_smoothing"},
      {p.min_hole_diameter_factor, "min_hole_diameter_factor"}, {p.outside_probe_factor, "outside_probe_factor"},
      {p.max_open_share, "max_open_share"}};
  for (const auto& [v, name] : positive)
    if (!std::isfinite(v) || !(v > 0.0))
      throw Error(std::string("height-field fill: ") + name + " must be finite and > 0");
  for (const auto& [v, name] : non_negative)
    if (!std::isfinite(v) || !(v >= 0.0))
      throw Error(std::string("height-field fill: ") + name + " must be finite and >= 0");
  if (!p.up.allFinite())
    throw Error("height-field fill: the up direction must be finite");
  if (p.clearance_factor >= p.detection_cell_factor)
    throw Error("height-field fill: clearance_factor must be smaller than detection_cell_factor");
  if (p.max_spline_sites < 6 || p.max_spline_sites > 5000)
    throw Error("height-field fill: max_spline_sites must lie in 6…5000");
  if (p.max_raster_cells < 16)
    throw Error("height-field fill: max_raster_cells must be at least 16");
}

}  // namespace

bool isHeightFieldCloud(const std::vector<Eigen::Vector3d>& points, Eigen::Vector3d* up,
                        double* single_layer_share, double min_single_layer_share)
{
  if (single_layer_share)
    *single_layer_share = 0.0;
  const Bulk bulk = robustBulk(points);
  Vec3 variances;
  const Vec3 axis = bulk.kept.size() >= 16 ? pcaUp(points, bulk, &variances) : Vec3::UnitZ();
  if (up)
    *up = axis;
  if (bulk.kept.size() < 16)
    return false;
  const std::vector<Vec3> local = toLocal(points, bulk, frameFor(axis));
  const double s = estimateSpacing(local);
  if (!(s > 0.0))
    return false;
  const Raster r = buildRaster(local, 2.5 * s, std::size_t(1) << 25);
  std::size_t several = 0, single = 0;
  std::vector<double> h;
  for (std::size_t c = 0; c + 1 < r.start.size(); ++c) {
    if (r.count(c) < 2)
      continue;
    h.clear();
    for (std::uint32_t k = r.start[c]; k < r.start[c + 1]; ++k)
      h.push_back(local[r.order[k]].z());
    std::sort(h.begin(), h.end());
    bool gap = false;
    for (std::size_t k = 1; k < h.size() && !gap; ++k)
      gap = h[k] - h[k - 1] > 4.0 * s;
    ++(gap ? several : single);
  }
  const double share = single + several > 0 ? static_cast<double>(single) / static_cast<double>(single + several) : 0.0;
  if (single_layer_share)
    *single_layer_share = share;
  return variances(0) <= 0.25 * variances(1) && share >= min_single_layer_share;
}

void fillHeightFieldHoles(const std::vector<Eigen::Vector3d>& points, const HeightFieldFillParameters& parameters,
                          std::vector<Eigen::Vector3d>& added, std::vector<std::size_t>& added_source,
                          HeightFieldFillReport& report)
{
  const auto t0 = std::chrono::steady_clock::now();
  checkParameters(parameters);
  added.clear();
  added_source.clear();
  report = HeightFieldFillReport();
  auto finish = [&] {
    report.points_added = added.size();
    report.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  };
  const Bulk bulk = robustBulk(points);
  report.points_used = bulk.kept.size();
  report.points_ignored = points.size() - bulk.kept.size();
  if (points.size() >= (std::size_t(1) << 32))
    throw Error("height-field fill: at most 2^32 − 1 points");
  const bool automatic_up = !(parameters.up.norm() > 0.0);
  report.up = automatic_up ? (bulk.kept.size() >= 3 ? pcaUp(points, bulk) : Vec3::UnitZ())
                           : Vec3(parameters.up.normalized());
  if (bulk.kept.size() < 16)
    return finish();
  const Eigen::Matrix3d rot = frameFor(report.up);
  const std::vector<Vec3> local = toLocal(points, bulk, rot);
  report.spacing = parameters.spacing > 0.0 ? parameters.spacing : estimateSpacing(local);
  if (!(report.spacing > 0.0))
    return finish();
  const double s = report.spacing;
  Settings st{s, parameters.detection_cell_factor * s, parameters.lattice_factor * s,
              parameters.clearance_factor * s, parameters.rim_width_factor * s,
              0.5 * parameters.min_hole_diameter_factor * s,
              parameters.max_hole_diameter > 0.0 ? parameters.max_hole_diameter : parameters.max_hole_diameter_factor * s,
              parameters.rim_smoothing, parameters.max_spline_sites};
  report.cell_size = st.cell;
  const auto probe = static_cast<std::size_t>(std::max(1.0, std::round(parameters.outside_probe_factor * s / st.cell)));
  const Raster r = buildRaster(local, st.cell, parameters.max_raster_cells, probe + 1);
  report.raster_width = r.nx;
  report.raster_height = r.ny;
  const std::vector<char> outside = outsideMask(r, probe);
  const Components comp = emptyComponents(r, outside);
  report.empty_components = comp.cells.size();
  std::vector<std::uint32_t> mark(r.nx * r.ny, 0);
  std::vector<char> claimed(r.nx * r.ny, 0);
  std::vector<Vec3> out_local;
  for (std::size_t id = 0; id < comp.cells.size(); ++id) {
    const std::vector<std::uint32_t>& cells = comp.cells[id];
    const Shape shape = shapeOf(r, cells, comp.label, outside);
    if (static_cast<double>(shape.open) > parameters.max_open_share * static_cast<double>(shape.boundary)) {
      ++report.rejected_border;
      continue;
    }
    if (shape.width * st.cell > st.max_diameter) {
      ++report.rejected_too_big;
      continue;
    }
    const auto stamp = static_cast<std::uint32_t>(2 * id + 2);
    const Outcome o = fillHole(r, local, cells, st, mark, stamp, claimed, out_local, added_source);
    (o == Outcome::filled ? report.holes_filled : o == Outcome::too_small ? report.rejected_too_small
                                                                          : report.rejected_no_rim)++;
  }
  added.reserve(out_local.size());
  for (std::size_t k = 0; k < out_local.size(); ++k) {
    added.push_back(bulk.centre + rot.transpose() * out_local[k]);
    added_source[k] = bulk.kept[added_source[k]];
  }
  finish();
}

}  // namespace patchdict
}  // namespace pcl
