#include <pcl_patchdict/core/error.h>
#include <pcl_patchdict/core/mesh_topology.h>
#include <pcl_patchdict/patches/patch_mesh_reconstruction.h>
#include <pcl_patchdict/core/vertex_normals.h>

#include "geometry/point_search.h"

#include <pcl/kdtree/kdtree_flann.h>
#include <pcl/point_types.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

namespace pcl {
namespace patchdict {

void PatchMeshReconstruction::checkInput() const
{
  if (!patches_ || !target_)
    throw Error("patch reconstruction needs a patch set and a target mesh");
  patches_->check();
  if (patches_->grid_size < 2 || !(patches_->radius > 0.0))
    throw Error("patch reconstruction: the patch set has no usable grid (N " + std::to_string(patches_->grid_size) +
                ", r " + std::to_string(patches_->radius) + ")");
  for (std::size_t v = 0; v < target_->vertices.size(); ++v)
    if (!target_->vertices[v].allFinite())
      throw Error("patch reconstruction: target vertex " + std::to_string(v) + " is not finite");
}

std::vector<VertexPatchSample> PatchMeshReconstruction::computeMapping() const
{
  checkInput();
  const PatchSet& set = *patches_;
  std::vector<VertexPatchSample> mapping;
  if (set.numPatches() == 0 || target_->vertices.empty())
    return mapping;
  const detail::PointSearch tree(set.seeds);
  const double radius = set.radius;
  // FLANN searches in float: widen a little, then decide exactly in double.
  const float search_radius = detail::floatSearchRadius(radius);
  const auto count = static_cast<std::ptrdiff_t>(target_->vertices.size());
  // A vertex facing away from the patch's Z is on another sheet (the inside of a thin wall, the
  // far side of an ear): the patch sampled the sheet facing it, not this one.
  const std::vector<Eigen::Vector3d> normals =
      target_->faces.empty() ? std::vector<Eigen::Vector3d>(target_->vertices.size(), Eigen::Vector3d::Zero())
                             : computeVertexNormals(*target_);
  std::vector<std::vector<VertexPatchSample>> per_vertex(static_cast<std::size_t>(count));
#pragma omp parallel
  {
    std::vector<int> indices;
    std::vector<float> distances;
#pragma omp for schedule(dynamic, 256)
    for (std::ptrdiff_t v = 0; v < count; ++v) {
      const Eigen::Vector3d& p = target_->vertices[static_cast<std::size_t>(v)];
      tree.within(p, search_radius, indices, distances);
      std::sort(indices.begin(), indices.end());  // FLANN's order is not specified
      auto& samples = per_vertex[static_cast<std::size_t>(v)];
      for (const int patch : indices) {
        Eigen::Vector3d local;
        if (!patchContains(set.seeds[static_cast<std::size_t>(patch)], set.rotations[static_cast<std::size_t>(patch)],
                           radius, p, normals[static_cast<std::size_t>(v)], &local))
          continue;
        samples.push_back({static_cast<std::int32_t>(v), patch, local.x(), local.y(), local.z()});
      }
    }
  }
  for (auto& samples : per_vertex)
    mapping.insert(mapping.end(), samples.begin(), samples.end());
  return mapping;
}

namespace {

/** The point a patch gives for one mapped vertex, in the patch's frame: the height at the nearest
  * bin centre (BinCentres) or interpolated over the 2×2 bin centres around it (Bilinear). False
  * when the patch did not observe the place; `unobserved` then says so. */
bool patchPoint(const PatchSet& set, PatchMeshReconstruction::Rule rule, const VertexPatchSample& sample,
                Eigen::Vector3d& local, bool& unobserved)
{
  const int grid = set.grid_size;
  const double side = set.side(), bin = side / grid;
  const int patch = sample.patch;
  // Continuous bin coordinate of a tangent coordinate: bin centres sit at integers.
  auto binCoordinate = [&](double t) { return (t + 0.5 * side) / bin - 0.5; };
  auto observed = [&](int i, int j) { return set.observed(j * grid + i, patch); };
  auto height = [&](int i, int j) { return set.heights(j * grid + i, patch); };
  const double u = binCoordinate(sample.x), w = binCoordinate(sample.y);
  if (rule == PatchMeshReconstruction::Rule::BinCentres) {
    const int i = std::clamp(static_cast<int>(std::floor(u + 0.5)), 0, grid - 1);
    const int j = std::clamp(static_cast<int>(std::floor(w + 0.5)), 0, grid - 1);
    if (!observed(i, j)) {
      unobserved = true;
      return false;
    }
    local = Eigen::Vector3d((i + 0.5) * bin - 0.5 * side, (j + 0.5) * bin - 0.5 * side, height(i, j));
    return true;
  }
  // The 2×2 bin centres around (u, w); at the border the nearest pair, extrapolated linearly.
  const int i0 = std::clamp(static_cast<int>(std::floor(u)), 0, grid - 2);
  const int j0 = std::clamp(static_cast<int>(std::floor(w)), 0, grid - 2);
  const int corner_i[4] = {i0, i0 + 1, i0, i0 + 1}, corner_j[4] = {j0, j0, j0 + 1, j0 + 1};
  bool seen[4];
  bool all_seen = true;
  for (int c = 0; c < 4; ++c)
    all_seen &= seen[c] = observed(corner_i[c], corner_j[c]);
  double a = u - i0, b = w - j0;
  if (!all_seen) {
    // Near the edge of the observed area: interpolate inside the cell only, over the corners
    // that exist, and only when they carry most of the weight.
    a = std::clamp(a, 0.0, 1.0);
    b = std::clamp(b, 0.0, 1.0);
  }
  const double weight[4] = {(1 - a) * (1 - b), a * (1 - b), (1 - a) * b, a * b};
  double h = 0.0, total = 0.0;
  for (int c = 0; c < 4; ++c)
    if (seen[c]) {
      h += weight[c] * height(corner_i[c], corner_j[c]);
      total += weight[c];
    }
  if (!all_seen) {
    // A vertex on the rim of an open surface has unobserved bins on its outer side: the
    // observed corners, renormalised, are still a far better height than its 1-ring's mean
    // (measured on an open relief: 45 rim vertices carried 99.6 % of the squared error).
    if (total < 1e-3) {
      unobserved = true;
      return false;
    }
    h /= total;
  }
  local = Eigen::Vector3d(sample.x, sample.y, h);
  return true;
}

/** Sums each vertex's estimates. With three or more estimates, those farther than 3 × their median
  * distance from the coordinate-wise median (and more than a bin from it) come from another sheet of
  * a folded surface or a badly tilted frame: they are dropped before averaging. Returns how many
  * were dropped. */
std::size_t robustSums(const std::vector<std::vector<Eigen::Vector3d>>& points, double bin,
                       std::vector<Eigen::Vector3d>& sum, std::vector<int>& estimates)
{
  const std::size_t n = points.size();
  sum.assign(n, Eigen::Vector3d::Zero());
  estimates.assign(n, 0);
  std::size_t rejected = 0;
#pragma omp parallel for schedule(dynamic, 256) reduction(+ : rejected)
  for (std::ptrdiff_t v = 0; v < static_cast<std::ptrdiff_t>(n); ++v) {
    const auto& list = points[static_cast<std::size_t>(v)];
    if (list.empty())
      continue;
    double limit = std::numeric_limits<double>::infinity();
    Eigen::Vector3d median = Eigen::Vector3d::Zero();
    if (list.size() >= 3) {
      std::vector<double> values(list.size());
      for (int c = 0; c < 3; ++c) {
        for (std::size_t k = 0; k < list.size(); ++k)
          values[k] = list[k][c];
        std::nth_element(values.begin(), values.begin() + static_cast<std::ptrdiff_t>(values.size() / 2), values.end());
        median[c] = values[values.size() / 2];
      }
      for (std::size_t k = 0; k < list.size(); ++k)
        values[k] = (list[k] - median).norm();
      std::nth_element(values.begin(), values.begin() + static_cast<std::ptrdiff_t>(values.size() / 2), values.end());
      limit = std::max(3.0 * values[values.size() / 2], bin);
    }
    Eigen::Vector3d total = Eigen::Vector3d::Zero();
    int count = 0;
    for (const auto& p : list) {
      if ((p - median).norm() > limit) {
        ++rejected;
        continue;
      }
      total += p;
      ++count;
    }
    sum[static_cast<std::size_t>(v)] = total;
    estimates[static_cast<std::size_t>(v)] = count;
  }
  return rejected;
}

/** Uncovered vertices: mean of their reconstructed 1-ring, spreading inwards round by round.
  * Returns how many were placed. */
std::size_t fillFromOneRings(const TriangleMesh& target, std::vector<char>& known, TriangleMesh& result)
{
  const std::size_t n = target.vertices.size();
  std::size_t placed = 0;
  const auto rings = computeVertexOneRings(target);
  for (bool changed = true; changed;) {
    changed = false;
    std::vector<std::pair<std::size_t, Eigen::Vector3d>> updates;
    for (std::size_t v = 0; v < n; ++v) {
      if (known[v])
        continue;
      Eigen::Vector3d mean = Eigen::Vector3d::Zero();
      int count = 0;
      for (const auto w : rings[v])
        if (known[static_cast<std::size_t>(w)]) {
          mean += result.vertices[static_cast<std::size_t>(w)];
          ++count;
        }
      if (count)
        updates.emplace_back(v, mean / count);
    }
    for (const auto& [v, position] : updates) {
      result.vertices[v] = position;
      known[v] = 1;
      ++placed;
      changed = true;
    }
  }
  return placed;
}

}  // namespace

void PatchMeshReconstruction::compute(TriangleMesh& out, Report* report) const
{
  const std::vector<VertexPatchSample> mapping = computeMapping();
  const PatchSet& set = *patches_;
  const double side = set.side(), bin = side / set.grid_size, max_jump = 0.5 * side;
  const std::size_t n = target_->vertices.size();
  // Estimates per vertex (the mapping is in vertex order), combined robustly below.
  std::vector<std::vector<Eigen::Vector3d>> points(n);
  std::vector<char> over_unobserved(n, 0);
  for (const VertexPatchSample& sample : mapping) {
    Eigen::Vector3d local;
    bool unobserved = false;
    if (!patchPoint(set, rule_, sample, local, unobserved)) {
      if (unobserved)
        over_unobserved[static_cast<std::size_t>(sample.vertex)] = 1;
      continue;
    }
    if (std::abs(local.z() - sample.z) > max_jump)
      continue;  // another sheet of the surface crosses this patch: its height is not this vertex's
    const auto patch = static_cast<std::size_t>(sample.patch);
    points[static_cast<std::size_t>(sample.vertex)].push_back(set.seeds[patch] + set.rotations[patch].transpose() * local);
  }
  std::vector<Eigen::Vector3d> sum;
  std::vector<int> estimates;
  const std::size_t rejected = robustSums(points, bin, sum, estimates);

  TriangleMesh result;
  result.faces = target_->faces;
  result.vertices = target_->vertices;
  Report local_report;
  std::vector<char> known(n, 0);
  std::size_t total_estimates = 0;
  for (std::size_t v = 0; v < n; ++v)
    if (estimates[v] > 0) {
      result.vertices[v] = sum[v] / estimates[v];
      known[v] = 1;
      ++local_report.vertices_covered;
      total_estimates += static_cast<std::size_t>(estimates[v]);
    }
  local_report.vertices_from_ring = fillFromOneRings(*target_, known, result);
  local_report.estimates_rejected = rejected;
  local_report.vertices_unchanged = n - local_report.vertices_covered - local_report.vertices_from_ring;
  local_report.mean_estimates = local_report.vertices_covered
                                    ? static_cast<double>(total_estimates) / static_cast<double>(local_report.vertices_covered)
                                    : 0.0;
  out = std::move(result);
  if (report) {
    local_report.estimates.assign(estimates.begin(), estimates.end());
    local_report.off_surface.assign(n, 0);
    for (std::size_t v = 0; v < n; ++v)
      local_report.off_surface[v] = estimates[v] == 0 && over_unobserved[v];
    *report = std::move(local_report);
  }
}

std::vector<Eigen::Vector3d> patchSetToPoints(const PatchSet& patches)
{
  patches.check();
  const int grid = patches.grid_size;
  const double side = patches.side(), bin = side / grid;
  std::vector<Eigen::Vector3d> points;
  points.reserve(static_cast<std::size_t>(patches.observed.count()));
  for (std::size_t p = 0; p < patches.numPatches(); ++p)
    for (int j = 0; j < grid; ++j)
      for (int i = 0; i < grid; ++i) {
        const Eigen::Index row = j * grid + i;
        if (!patches.observed(row, static_cast<Eigen::Index>(p)))
          continue;
        const Eigen::Vector3d local((i + 0.5) * bin - 0.5 * side, (j + 0.5) * bin - 0.5 * side,
                                    patches.heights(row, static_cast<Eigen::Index>(p)));
        points.push_back(patches.seeds[p] + patches.rotations[p].transpose() * local);
      }
  return points;
}

}  // namespace patchdict
}  // namespace pcl
