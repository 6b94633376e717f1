// Height-field hole detection (see height_field_hole_filling.h): the robust bulk, up frame and
// spacing of a cloud, its plane raster, the outside of its footprint and the enclosed empty
// components (the fill: height_field_hole_filling.cpp); isHeightFieldCloud.
#include "cloud/height_field_raster.h"

#include <pcl_patchdict/core/error.h>
#include <pcl_patchdict/cloud/height_field_hole_filling.h>

#include <Eigen/Dense>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <string>

namespace pcl {
namespace patchdict {
namespace height_field_detail {

double quantile(std::vector<double>& values, double q)
{
  const auto k = static_cast<std::ptrdiff_t>(q * static_cast<double>(values.size() - 1));
  std::nth_element(values.begin(), values.begin() + k, values.end());
  return values[static_cast<std::size_t>(k)];
}

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

Vec3 pcaUp(const std::vector<Vec3>& points, const Bulk& bulk, Vec3* variances)
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

Raster buildRaster(const std::vector<Vec3>& local, double cell, std::size_t max_cells, std::size_t pad)
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

namespace {

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

}  // namespace

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

}  // namespace height_field_detail

using namespace height_field_detail;

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

}  // namespace patchdict
}  // namespace pcl
