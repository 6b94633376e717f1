// Height maps: exact heights rasterised from a mesh's triangles, or binned heights of a cloud's
// points, at given seeds and frames.
#include <pcl_patchdict/core/error.h>
#include <pcl_patchdict/patches/height_maps.h>

#include "patches/point_cells.h"

#include <omp.h>

#if defined(__linux__)
#include <sys/mman.h>
#endif

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>

namespace pcl {
namespace patchdict {

namespace {

constexpr int kMaxGrid = 256;  // as the .pds / .pdd readers accept

// Grid geometry of section 3.2: side √2·r, N bins per side, bin centres at (i + 0.5)·bin − side/2.
struct Grid {
  int size;
  double radius;
  double side;
  double bin;
  double half;
  double centre(int index) const { return (index + 0.5) * bin - half; }
};

Grid makeGrid(int grid_size, double radius)
{
  Grid grid;
  grid.size = grid_size;
  grid.radius = radius;
  grid.side = std::sqrt(2.0) * radius;
  grid.bin = grid.side / grid_size;
  grid.half = 0.5 * grid.side;
  return grid;
}

int threadCount(int requested) { return requested > 0 ? requested : omp_get_max_threads(); }

/** ⌊v⌋ for |v| well inside the int range. */
inline int floorToInt(double v)
{
  const int i = static_cast<int>(v);
  return i - (static_cast<double>(i) > v ? 1 : 0);
}

/** Sums and weights of an N×N grid with a margin of one bin on every side: a point's 2×2 bins
  * never need a bounds test (the margin is dropped at the end). */
struct BinSums {
  explicit BinSums(int size)
      : n(size), stride(size + 2), sums(static_cast<std::size_t>(stride) * stride),
        weights(static_cast<std::size_t>(stride) * stride)
  {
  }
  void clear()
  {
    std::fill(sums.begin(), sums.end(), 0.0);
    std::fill(weights.begin(), weights.end(), 0.0);
  }
  std::size_t index(int u, int v) const
  {
    return static_cast<std::size_t>(v + 1) * static_cast<std::size_t>(stride) + static_cast<std::size_t>(u + 1);
  }
  int n, stride;
  std::vector<double> sums, weights;
};

/** max(v, 0) without a branch (GCC turns std::max into one, mispredicted at a kernel's edge). */
inline double positivePart(double v) { return 0.5 * (v + std::fabs(v)); }

/** A point's height spread over the bins whose centres lie within R = reach bins of it (x, y: its
  * place in bins from the first bin's centre), weighted by the biweight (1 − d²/R²)² (close to a
  * Gaussian of σ = R/2, without an exponential per bin): bins stay observed where random samples
  * are sparser than the grid. Floors by integer conversion (a library call otherwise, without
  * SSE4.1 in the build); weights clamped at 0 without a branch (adding 0 changes nothing).
  * inv_reach_sq = 1 / reach², computed once by the caller. */
void splat(double x, double y, double z, double reach, double inv_reach_sq, BinSums& bins)
{
  if (reach <= 1.0) {  // at most the 2×2 bins around the point: unrolled, no bounds test
    const int u = floorToInt(x), v = floorToInt(y);
    if (u < -1 || v < -1 || u >= bins.n || v >= bins.n)
      return;  // all four outside the grid
    const double fx = x - u, fy = y - v, gx = 1.0 - fx, gy = 1.0 - fy;
    const double w[4] = {fx * fx, gx * gx, fy * fy, gy * gy};
    const std::size_t k = bins.index(u, v), s = static_cast<std::size_t>(bins.stride);
    const std::size_t at[4] = {k, k + 1, k + s, k + s + 1};
    const double q[4] = {positivePart(1.0 - (w[0] + w[2]) * inv_reach_sq),
                         positivePart(1.0 - (w[1] + w[2]) * inv_reach_sq),
                         positivePart(1.0 - (w[0] + w[3]) * inv_reach_sq),
                         positivePart(1.0 - (w[1] + w[3]) * inv_reach_sq)};
    for (int i = 0; i < 4; ++i) {
      bins.sums[at[i]] += q[i] * q[i] * z;
      bins.weights[at[i]] += q[i] * q[i];
    }
    return;
  }
  const int n = bins.n;
  const int u0 = std::max(0, -floorToInt(reach - x)), u1 = std::min(n - 1, floorToInt(x + reach));
  const int v0 = std::max(0, -floorToInt(reach - y)), v1 = std::min(n - 1, floorToInt(y + reach));
  for (int v = v0; v <= v1; ++v) {
    const double dy = v - y;
    const double row = 1.0 - dy * dy * inv_reach_sq;
    for (int u = u0; u <= u1; ++u) {
      const double dx = u - x;
      const double q = positivePart(row - dx * dx * inv_reach_sq);
      bins.sums[bins.index(u, v)] += q * q * z;
      bins.weights[bins.index(u, v)] += q * q;
    }
  }
}

const std::string kWhat = "height-map patches: ";

void checkParameters(const std::vector<Eigen::Vector3d>& seeds, const std::vector<Eigen::Matrix3d>& frames,
                     const HeightMapParameters& parameters)
{
  if (!(parameters.radius > 0.0) || !std::isfinite(parameters.radius))
    throw Error(kWhat + "the radius must be positive and finite");
  if (parameters.grid_size < 2 || parameters.grid_size > kMaxGrid)
    throw Error(kWhat + "the grid size must be in [2, " + std::to_string(kMaxGrid) + "], not " +
                std::to_string(parameters.grid_size));
  if (frames.size() != seeds.size())
    throw Error(kWhat + std::to_string(seeds.size()) + " seeds but " + std::to_string(frames.size()) + " frames");
  for (std::size_t p = 0; p < seeds.size(); ++p) {
    if (!seeds[p].allFinite())
      throw Error(kWhat + "seed or frame " + std::to_string(p) + " is not finite");
    checkHeightMapFrame(frames[p], p);
  }
}

void checkPoints(const std::vector<Eigen::Vector3d>& points)
{
  if (points.empty())
    throw Error(kWhat + "the input surface has no points");
  for (const auto& v : points)
    if (!v.allFinite())
      throw Error(kWhat + "the input surface has non-finite coordinates");
}

/** Asks Linux for 2 MB pages under a large buffer not yet touched: 20,000 patches of 32×32 are
  * 164 MB, and their first touch in 4 kB pages cost a fifth of the extraction (measured). */
void adviseHugePages(void* data, std::size_t bytes)
{
#if defined(__linux__) && defined(MADV_HUGEPAGE)
  constexpr std::uintptr_t kPage = 4096;
  const auto begin = (reinterpret_cast<std::uintptr_t>(data) + kPage - 1) & ~(kPage - 1);
  const auto end = (reinterpret_cast<std::uintptr_t>(data) + bytes) & ~(kPage - 1);
  if (bytes >= (std::size_t{8} << 20) && end > begin)
    madvise(reinterpret_cast<void*>(begin), end - begin, MADV_HUGEPAGE);  // advice: failure is harmless
#else
  (void)data;
  (void)bytes;
#endif
}

/** One patch per seed, every bin unobserved at height 0 (or, with `filled_later`, left for the
  * caller to write every bin: no pass over memory to zero it first). */
PatchSet unobservedPatches(const std::vector<Eigen::Vector3d>& seeds, const std::vector<Eigen::Matrix3d>& frames,
                           const HeightMapParameters& parameters, bool filled_later = false)
{
  const auto patches = static_cast<Eigen::Index>(seeds.size());
  const Eigen::Index bins = static_cast<Eigen::Index>(parameters.grid_size) * parameters.grid_size;
  PatchSet result;
  result.grid_size = parameters.grid_size;
  result.radius = parameters.radius;
  result.seeds = seeds;
  result.rotations = frames;
  if (filled_later) {
    result.heights.resize(bins, patches);
    result.observed.resize(bins, patches);
    adviseHugePages(result.heights.data(), sizeof(double) * static_cast<std::size_t>(result.heights.size()));
  } else {
    result.heights = Eigen::MatrixXd::Zero(bins, patches);
    result.observed = ObservationMask::Constant(bins, patches, false);
  }
  result.source.assign(seeds.size(), parameters.source_index);
  return result;
}

// The faces' centroids, and `reach`: any point of a triangle is within it of its centroid (convexity:
// the farthest point is a vertex). The circumradius would not do: for an obtuse triangle it can be
// smaller than that.
std::vector<Eigen::Vector3d> faceCentroids(const TriangleMesh& mesh, double& reach)
{
  std::vector<Eigen::Vector3d> centroids(mesh.faces.size());
  reach = 0.0;
  for (std::size_t f = 0; f < mesh.faces.size(); ++f) {
    const Eigen::Vector3d& a = mesh.vertices[mesh.faces[f][0]];
    const Eigen::Vector3d& b = mesh.vertices[mesh.faces[f][1]];
    const Eigen::Vector3d& c = mesh.vertices[mesh.faces[f][2]];
    const Eigen::Vector3d centroid = (a + b + c) / 3.0;
    centroids[f] = centroid;
    reach = std::max({reach, (a - centroid).norm(), (b - centroid).norm(), (c - centroid).norm()});
  }
  return centroids;
}

// Exact heights: rasterise, in the seed's frame, the XY projections of the triangles that can reach
// the patch, sampling the barycentric interpolant at the bin centres (a ray along Z per bin centre,
// done triangle by triangle).
void meshHeights(const TriangleMesh& mesh, const std::vector<Eigen::Vector3d>& seeds,
                 const std::vector<Eigen::Matrix3d>& frames, const HeightMapParameters& parameters, PatchSet& out)
{
  const double radius = parameters.radius;
  const int grid_size = parameters.grid_size;
  const Grid grid = makeGrid(grid_size, radius);
  const auto& vertices = mesh.vertices;
  const auto& faces = mesh.faces;

  double reach = 0.0;
  const std::vector<Eigen::Vector3d> centroids = faceCentroids(mesh, reach);
  // A surface point counted by the patch is within r of the seed (the r-neighbourhood of section
  // 3.1), so the triangle holding it has its centroid within r + reach. Centroids in cells, as the
  // cloud's points are (no kd-tree; the visiting order does not matter, see the rule below).
  const double query_radius = (radius + reach) * (1.0 + 1e-9);
  const detail::PointCells cells(centroids, 0.5 * query_radius);
  const double radius_squared = radius * radius;
  const int n = grid_size;

#pragma omp parallel num_threads(threadCount(parameters.num_threads))
  {
    std::vector<std::uint32_t> neighbours;
    std::vector<double> best_abs(static_cast<std::size_t>(n) * n);
    std::vector<int> best_face(static_cast<std::size_t>(n) * n);
#pragma omp for schedule(dynamic, 8)
    for (std::ptrdiff_t p = 0; p < static_cast<std::ptrdiff_t>(seeds.size()); ++p) {
      // Copies: the heights written below are doubles that could otherwise alias them.
      const Eigen::Vector3d seed = seeds[static_cast<std::size_t>(p)];
      const Eigen::Matrix3d rotation = frames[static_cast<std::size_t>(p)];
      // The search order does not matter: a bin keeps the candidate nearest the plane, and of
      // equal ones the lowest face index (rule below).
      neighbours.clear();
      cells.forEachNear(seed, query_radius, [&](const Eigen::Vector3d& centroid, std::uint32_t f) {
        if ((centroid - seed).squaredNorm() <= query_radius * query_radius)
          neighbours.push_back(f);
      });
      std::fill(best_abs.begin(), best_abs.end(), std::numeric_limits<double>::infinity());
      auto heights = out.heights.col(p);
      auto observed = out.observed.col(p);
      for (const std::uint32_t face_index : neighbours) {
        const int f = static_cast<int>(face_index);
        const Face& face = faces[static_cast<std::size_t>(f)];
        const Eigen::Vector3d a = rotation * (vertices[face[0]] - seed);
        const Eigen::Vector3d b = rotation * (vertices[face[1]] - seed);
        const Eigen::Vector3d c = rotation * (vertices[face[2]] - seed);
        const double area2 = (b.x() - a.x()) * (c.y() - a.y()) - (b.y() - a.y()) * (c.x() - a.x());
        const double scale = std::max({(b - a).head<2>().squaredNorm(), (c - a).head<2>().squaredNorm(),
                                       (c - b).head<2>().squaredNorm()});
        // A triangle seen edge-on projects to a segment: it covers no bin centre with a defined height.
        if (!(std::abs(area2) > 1e-14 * scale))
          continue;
        const double min_x = std::min({a.x(), b.x(), c.x()}), max_x = std::max({a.x(), b.x(), c.x()});
        const double min_y = std::min({a.y(), b.y(), c.y()}), max_y = std::max({a.y(), b.y(), c.y()});
        // Candidate bins, one bin of slack each side for rounding; the barycentric test decides.
        const int i0 = std::max(0, static_cast<int>(std::floor((min_x + grid.half) / grid.bin - 0.5)));
        const int i1 = std::min(n - 1, static_cast<int>(std::ceil((max_x + grid.half) / grid.bin - 0.5)));
        const int j0 = std::max(0, static_cast<int>(std::floor((min_y + grid.half) / grid.bin - 0.5)));
        const int j1 = std::min(n - 1, static_cast<int>(std::ceil((max_y + grid.half) / grid.bin - 0.5)));
        if (i0 > i1 || j0 > j1)
          continue;
        const double inverse_area2 = 1.0 / area2;
        for (int j = j0; j <= j1; ++j) {
          const double y = grid.centre(j);
          for (int i = i0; i <= i1; ++i) {
            const double x = grid.centre(i);
            const double wa = ((b.x() - x) * (c.y() - y) - (b.y() - y) * (c.x() - x)) * inverse_area2;
            const double wb = ((c.x() - x) * (a.y() - y) - (c.y() - y) * (a.x() - x)) * inverse_area2;
            const double wc = 1.0 - wa - wb;
            // Inclusive edges (with a rounding margin): a bin centre on an edge shared by two
            // triangles must not fall through the crack between them.
            constexpr double tolerance = 1e-12;
            if (wa < -tolerance || wb < -tolerance || wc < -tolerance)
              continue;
            const double z = wa * a.z() + wb * b.z() + wc * c.z();
            if (x * x + y * y + z * z > radius_squared)
              continue;
            const std::size_t k = static_cast<std::size_t>(j) * n + i;
            // Folds (several sheets over one bin centre): keep the sheet closest to the patch plane.
            // The height map can only hold the topological disk around the seed (section 3.3 of
            // the paper); the sheet nearest the plane through the seed is the one that disk
            // continues, the others (the far side of a thin part, an overhang) belong to other patches.
            // Equal candidates (a shared edge) keep the lower face index, whatever the search order.
            if (std::abs(z) < best_abs[k] || (std::abs(z) == best_abs[k] && f < best_face[k])) {
              best_abs[k] = std::abs(z);
              best_face[k] = f;
              heights[static_cast<Eigen::Index>(k)] = z;
              observed[static_cast<Eigen::Index>(k)] = true;
            }
          }
        }
      }
    }
  }
}

// Binning, as the paper does for points (section 3.2): the bin's value is the mean Z of the points
// that fall in it. The mean rather than the median: it is the least-squares height of the bin, for
// a locally linear surface sampled evenly it is the height at the samples' centroid, and it varies
// continuously with the data; outliers and noise are the dictionary's job (sparse approximation),
// not the sampler's.
void cloudHeights(const std::vector<Eigen::Vector3d>& points, const std::vector<Eigen::Vector3d>& seeds,
                  const std::vector<Eigen::Matrix3d>& frames, const HeightMapParameters& parameters,
                  PatchSet& out)
{
  const double radius = parameters.radius;
  const int grid_size = parameters.grid_size;
  const Grid grid = makeGrid(grid_size, radius);
  // Cells of half the radius: a query reads about twice the points of its ball, in a fixed order
  // (cell by cell, index order within one), so the sums are bit-identical whatever the threads.
  const detail::PointCells cells(points, 0.5 * radius);
  const double query_radius = radius * (1.0 + 1e-6);  // the frames are rotations to float precision
  const double radius_squared = radius * radius;
  const int n = grid_size;

#pragma omp parallel num_threads(threadCount(parameters.num_threads))
  {
    BinSums bins(n);
    const double inv_bin = 1.0 / grid.bin;
#pragma omp for schedule(dynamic, 8)
    for (std::ptrdiff_t p = 0; p < static_cast<std::ptrdiff_t>(seeds.size()); ++p) {
      // Copies, not references: the sums are doubles too, and a store to them could otherwise alias
      // the frame, the seed or a parameter and force them to be read again after every point.
      const Eigen::Vector3d seed = seeds[static_cast<std::size_t>(p)];
      const Eigen::Matrix3d rotation = frames[static_cast<std::size_t>(p)];
      const double reach = parameters.bin_reach, inv_reach_sq = reach > 0.0 ? 1.0 / (reach * reach) : 0.0;
      const double half = grid.half;
      bins.clear();
      cells.forEachNear(seed, query_radius, [=, &bins](const Eigen::Vector3d& point, std::uint32_t) {
        const Eigen::Vector3d offset = point - seed;
        if (offset.squaredNorm() > query_radius * query_radius)
          return;
        const Eigen::Vector3d local = rotation * offset;
        if (local.squaredNorm() > radius_squared)
          return;
        if (reach > 0.0) {  // bin units, from the first bin's centre
          splat((local.x() + half) * inv_bin - 0.5, (local.y() + half) * inv_bin - 0.5, local.z(), reach, inv_reach_sq,
                bins);
          return;
        }
        const double u = std::floor((local.x() + half) * inv_bin);
        const double v = std::floor((local.y() + half) * inv_bin);
        if (u < 0.0 || v < 0.0 || u >= n || v >= n)
          return;
        const std::size_t k = bins.index(static_cast<int>(u), static_cast<int>(v));
        bins.sums[k] += local.z();
        bins.weights[k] += 1.0;
      });
      for (int v = 0; v < n; ++v)  // every bin: the output was not zeroed
        for (int u = 0; u < n; ++u) {
          const std::size_t k = bins.index(u, v);
          const auto out_k = static_cast<Eigen::Index>(v) * n + u;
          const bool observed = bins.weights[k] > 0.0;
          out.heights(out_k, p) = observed ? bins.sums[k] / bins.weights[k] : 0.0;
          out.observed(out_k, p) = observed;
        }
    }
  }
}

}  // namespace

void checkHeightMapFrame(const Eigen::Matrix3d& frame, std::size_t index)
{
  if (!frame.allFinite())
    throw Error(kWhat + "seed or frame " + std::to_string(index) + " is not finite");
  // Frames are rounded to float where they are made (or come from pcl::ReferenceFrame): orthonormal
  // to float precision is all we can ask; a left-handed frame would mirror its patch and confuse
  // the dictionary, so it is a bug upstream.
  const double deviation = (frame * frame.transpose() - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff();
  if (deviation > 1e-4)
    throw Error(kWhat + "frame " + std::to_string(index) + " is not orthonormal (deviation " +
                std::to_string(deviation) + ")");
  if (frame.determinant() < 0.0)
    throw Error(kWhat + "frame " + std::to_string(index) + " is left-handed");
}

void extractMeshHeightMaps(const TriangleMesh& mesh, const std::vector<Eigen::Vector3d>& seeds,
                           const std::vector<Eigen::Matrix3d>& frames, const HeightMapParameters& parameters,
                           PatchSet& out)
{
  checkParameters(seeds, frames, parameters);
  checkPoints(mesh.vertices);
  if (mesh.faces.empty())
    throw Error(kWhat + "the input mesh has no faces (use extractCloudHeightMaps for a point cloud)");
  const auto count = static_cast<std::int32_t>(mesh.vertices.size());
  for (const auto& face : mesh.faces)
    for (const auto index : face)
      if (index < 0 || index >= count)
        throw Error(kWhat + "a face refers to vertex " + std::to_string(index) + " of " + std::to_string(count));
  PatchSet result = unobservedPatches(seeds, frames, parameters);
  if (!seeds.empty())
    meshHeights(mesh, seeds, frames, parameters, result);
  out = std::move(result);
}

void extractCloudHeightMaps(const std::vector<Eigen::Vector3d>& points, const std::vector<Eigen::Vector3d>& seeds,
                            const std::vector<Eigen::Matrix3d>& frames, const HeightMapParameters& parameters,
                            PatchSet& out)
{
  checkParameters(seeds, frames, parameters);
  checkPoints(points);
  PatchSet result = unobservedPatches(seeds, frames, parameters, true);
  if (!seeds.empty())
    cloudHeights(points, seeds, frames, parameters, result);
  out = std::move(result);
}

Eigen::Matrix3d frameFromNormal(const Eigen::Vector3d& normal)
{
  const Eigen::Vector3d z = normal.normalized();
  const Eigen::Vector3d x = z.unitOrthogonal(), y = z.cross(x);
  Eigen::Matrix3d rows;
  rows.row(0) = x;
  rows.row(1) = y;
  rows.row(2) = z;
  return roundToSinglePrecision(rows);  // as it was through pcl::ReferenceFrame (core/local_frame.h)
}

}  // namespace patchdict
}  // namespace pcl
