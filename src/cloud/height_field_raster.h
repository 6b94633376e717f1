// Height-field hole filling's shared pieces (private): the robust bulk of a cloud, its up frame and
// spacing, the plane raster, and the detection of the raster's enclosed empty components.
#pragma once

#include <Eigen/Core>

#include <cstddef>
#include <cstdint>
#include <vector>

namespace pcl {
namespace patchdict {
namespace height_field_detail {

using Vec3 = Eigen::Vector3d;
using Vec2 = Eigen::Vector2d;

/// The q-quantile of `values` (reordered in place).
double quantile(std::vector<double>& values, double q);

/// The finite points, less those farther from the median than 4 × the extent of the central 99.8 %
/// on some axis (a point at 1e30 must not stretch the raster); their median as the centre.
struct Bulk {
  std::vector<std::size_t> kept;
  Vec3 centre = Vec3::Zero();
};

Bulk robustBulk(const std::vector<Vec3>& points);

/// Rows e1, e2, up: a right-handed frame whose third axis is `up` (unit).
Eigen::Matrix3d frameFor(const Vec3& up);

/// Least-variance axis of the bulk (PCA) oriented towards +z (or its largest component positive);
/// eigenvalues ascending in `variances`.
Vec3 pcaUp(const std::vector<Vec3>& points, const Bulk& bulk, Vec3* variances = nullptr);

/// The bulk's points in the frame `rot`, centred on the bulk's centre.
std::vector<Vec3> toLocal(const std::vector<Vec3>& points, const Bulk& bulk, const Eigen::Matrix3d& rot);

/// Median of the pooled distances to the 4 nearest neighbours of ~20 000 subsampled points (zero
/// distances, duplicates, left out), with a 3-D grid hash of sorted cell keys; 0 if undefined.
double estimateSpacing(const std::vector<Vec3>& local);

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

Raster buildRaster(const std::vector<Vec3>& local, double cell, std::size_t max_cells, std::size_t pad = 1);

/// The outside of the data's footprint: the empty cells a square probe of half-width `probe` cells
/// sweeps when it moves in from the pad (wider than the probe) through empty cells only — the
/// pad-connected part of the opening of the empty cells. Bays whose mouth is narrower than the
/// probe stay inside the footprint.
std::vector<char> outsideMask(const Raster& r, std::size_t probe);

/// 4-connected components of the empty cells inside the footprint; label −1 for the others.
struct Components {
  std::vector<std::int32_t> label;
  std::vector<std::vector<std::uint32_t>> cells;
};

Components emptyComponents(const Raster& r, const std::vector<char>& outside);

/// A component's extent (cells, the wider side of its bounding box), its boundary cells (4-adjacent
/// to a cell not in it) and of those the open ones (4-adjacent to the outside).
struct Shape {
  double width = 0.0;
  std::size_t boundary = 0, open = 0;
};

Shape shapeOf(const Raster& r, const std::vector<std::uint32_t>& cells, const std::vector<std::int32_t>& label,
              const std::vector<char>& outside);

}  // namespace height_field_detail
}  // namespace patchdict
}  // namespace pcl
