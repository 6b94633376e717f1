// Seeded damage (see mesh_damage.h).
#include <pcl_patchdict_eval/mesh_damage.h>

#include <pcl_patchdict/core/error.h>
#include <pcl_patchdict/geometry/metrics.h>
#include <pcl_patchdict/geometry/mesh_hygiene.h>
#include <pcl_patchdict/core/mesh_topology.h>
#include <pcl_patchdict/core/vertex_normals.h>

#include <algorithm>
#include <cmath>
#include <random>

namespace pcl {
namespace patchdict {

HoledMesh punchHoles(const TriangleMesh& mesh, int count, double radius, std::uint64_t seed)
{
  if (mesh.faces.empty())
    throw Error("punching holes needs a mesh with faces");
  if (count < 1 || !(radius > 0.0) || !std::isfinite(radius))
    throw Error("holes: the count must be ≥ 1 and the radius > 0");
  const std::size_t n = mesh.numVertices();
  std::vector<bool> in_face(n, false);
  for (const Face& f : mesh.faces)
    for (std::int32_t v : f)
      in_face[static_cast<std::size_t>(v)] = true;
  std::vector<std::int32_t> used;
  for (std::size_t v = 0; v < n; ++v)
    if (in_face[v])
      used.push_back(static_cast<std::int32_t>(v));
  // A hole that reaches the mesh's rim is a bite out of the rim, not a hole: centres keep 2 radii
  // from every boundary vertex.
  std::vector<bool> on_rim(n, false);
  for (const MeshEdge& e : computeEdgeFaceAdjacency(mesh).edges)
    if (e.isBoundary())
      on_rim[static_cast<std::size_t>(e.v0)] = on_rim[static_cast<std::size_t>(e.v1)] = true;
  std::vector<Eigen::Vector3d> rim;
  for (std::size_t v = 0; v < n; ++v)
    if (on_rim[v])
      rim.push_back(mesh.vertices[v]);
  std::mt19937_64 rng(seed);
  std::shuffle(used.begin(), used.end(), rng);
  HoledMesh out;
  for (std::int32_t v : used) {
    const Eigen::Vector3d& p = mesh.vertices[static_cast<std::size_t>(v)];
    const auto within = [&p](const std::vector<Eigen::Vector3d>& points, double distance) {
      return std::any_of(points.begin(), points.end(),
                         [&](const Eigen::Vector3d& q) { return (p - q).norm() < distance; });
    };
    if (!within(rim, 2.0 * radius) && !within(out.centres, 4.0 * radius))
      out.centres.push_back(p);
    if (static_cast<int>(out.centres.size()) == count)
      break;
  }
  std::vector<bool> near(n, false);
  for (std::size_t v = 0; v < n; ++v)
    for (const auto& c : out.centres)
      if ((mesh.vertices[v] - c).norm() <= radius)
        near[v] = true;
  out.mesh.vertices = mesh.vertices;
  for (const Face& f : mesh.faces)
    if (!near[static_cast<std::size_t>(f[0])] && !near[static_cast<std::size_t>(f[1])] &&
        !near[static_cast<std::size_t>(f[2])])
      out.mesh.faces.push_back(f);
  MeshCleanupOptions unreferenced_only;
  unreferenced_only.remove_degenerate_faces = unreferenced_only.remove_duplicate_faces = false;
  const MeshCleanupResult cleaned = cleanMesh(out.mesh, unreferenced_only);
  out.original_index.assign(cleaned.new_to_old.begin(), cleaned.new_to_old.end());
  // Removed: on the surface before (in a face), not now; vertices the input never used are not.
  for (std::size_t v = 0; v < n; ++v)
    if (in_face[v] && cleaned.old_to_new[v] < 0)
      out.removed.push_back(static_cast<std::int32_t>(v));
  return out;
}

HoleFillScore scoreHoleFill(const TriangleMesh& truth, const HoledMesh& holed, const TriangleMesh& filled)
{
  if (filled.numVertices() < holed.mesh.numVertices())
    throw Error("hole score: the filled mesh has fewer vertices than the holed one");
  std::vector<Eigen::Vector3d> removed;
  for (std::int32_t v : holed.removed)
    removed.push_back(truth.vertices[static_cast<std::size_t>(v)]);
  const std::vector<Eigen::Vector3d> added(
      filled.vertices.begin() + static_cast<std::ptrdiff_t>(holed.mesh.numVertices()), filled.vertices.end());
  return {pointsToSurfaceDistance(removed, filled).mean, pointsToSurfaceDistance(added, truth).mean};
}

std::vector<int> pickMissingVertices(const TriangleMesh& mesh, double fraction, std::uint64_t seed)
{
  if (!(fraction > 0.0 && fraction < 1.0))
    throw Error("the missing fraction must be in (0, 1)");
  std::vector<bool> in_face(mesh.numVertices(), false);
  for (const Face& f : mesh.faces)
    for (std::int32_t v : f)
      in_face[static_cast<std::size_t>(v)] = true;
  std::vector<int> candidates;
  for (std::size_t v = 0; v < in_face.size(); ++v)
    if (in_face[v])
      candidates.push_back(static_cast<int>(v));
  std::mt19937_64 rng(seed);
  std::shuffle(candidates.begin(), candidates.end(), rng);
  const auto count = static_cast<std::size_t>(std::llround(fraction * static_cast<double>(mesh.numVertices())));
  candidates.resize(std::min(candidates.size(), count));
  std::sort(candidates.begin(), candidates.end());
  return candidates;
}

TriangleMesh addNormalNoise(const TriangleMesh& mesh, double sigma, std::uint64_t seed)
{
  if (!(sigma >= 0.0) || !std::isfinite(sigma))
    throw Error("the noise level must be a finite σ ≥ 0");
  TriangleMesh out = mesh;
  if (sigma == 0.0)  // std::normal_distribution needs σ > 0
    return out;
  const std::vector<Eigen::Vector3d> normals = computeVertexNormals(mesh);
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> gaussian(0.0, sigma);
  for (std::size_t v = 0; v < out.vertices.size(); ++v)
    out.vertices[v] += gaussian(rng) * normals[v];
  return out;
}

}  // namespace patchdict
}  // namespace pcl
