// QuadRemesher: refinement, hierarchy, orientation field, position field, extraction.
#include <pcl_patchdict/quads/quad_remesher.h>

#include <pcl_patchdict/core/error.h>
#include <pcl_patchdict/quads/position_field.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <string>

namespace pcl {
namespace patchdict {

TriangleMesh splitLongEdges(const TriangleMesh& mesh, double max_length, std::size_t max_faces)
{
  if (!(max_length > 0.0) || !std::isfinite(max_length))
    throw Error("edge splitting: the maximum edge length must be positive and finite");
  TriangleMesh result = mesh;
  const double limit2 = max_length * max_length;
  // Splitting a face whose longest edge is l into pieces of at most max_length makes about
  // (l / max_length)² faces: refuse early instead of running out of memory.
  double estimate = 0.0;
  for (const Face& f : mesh.faces) {
    double longest2 = 0.0;
    for (int k = 0; k < 3; ++k)
      longest2 = std::max(longest2, (mesh.vertices[f[k]] - mesh.vertices[f[(k + 1) % 3]]).squaredNorm());
    estimate += std::max(1.0, longest2 / limit2);
  }
  if (estimate > static_cast<double>(max_faces))
    throw Error("edge splitting: refining to edges of " + std::to_string(max_length) + " would make about " +
                std::to_string(static_cast<long long>(std::min(estimate, 1e18))) + " faces, more than " +
                std::to_string(max_faces) + " (the target length is too small for this mesh)");
  using EdgeKey = std::pair<std::int32_t, std::int32_t>;
  for (;;) {
    // Edges longer than the limit, longest first (ties by vertex pair: deterministic).
    struct Long {
      double length2;
      std::int32_t a, b;
    };
    std::vector<Long> candidates;
    for (const Face& f : result.faces)
      for (int k = 0; k < 3; ++k) {
        const std::int32_t a = std::min(f[k], f[(k + 1) % 3]), b = std::max(f[k], f[(k + 1) % 3]);
        const double l2 = (result.vertices[a] - result.vertices[b]).squaredNorm();
        if (l2 > limit2)
          candidates.push_back({l2, a, b});
      }
    if (candidates.empty())
      break;
    std::sort(candidates.begin(), candidates.end(), [](const Long& x, const Long& y) {
      return x.length2 != y.length2 ? x.length2 > y.length2 : std::make_pair(x.a, x.b) < std::make_pair(y.a, y.b);
    });
    candidates.erase(std::unique(candidates.begin(), candidates.end(),
                                 [](const Long& x, const Long& y) { return x.a == y.a && x.b == y.b; }),
                     candidates.end());
    // Faces of each long edge, from a sorted list of (edge, face) pairs.
    std::vector<std::pair<EdgeKey, std::size_t>> edge_face;
    for (std::size_t f = 0; f < result.faces.size(); ++f)
      for (int k = 0; k < 3; ++k) {
        const std::int32_t a = result.faces[f][k], b = result.faces[f][(k + 1) % 3];
        const EdgeKey key{std::min(a, b), std::max(a, b)};
        if ((result.vertices[key.first] - result.vertices[key.second]).squaredNorm() > limit2)
          edge_face.emplace_back(key, f);
      }
    std::sort(edge_face.begin(), edge_face.end());
    const auto facesOf = [&](const EdgeKey& key) {
      std::vector<std::size_t> faces;
      auto it = std::lower_bound(edge_face.begin(), edge_face.end(), std::make_pair(key, std::size_t{0}));
      for (; it != edge_face.end() && it->first == key; ++it)
        faces.push_back(it->second);
      return faces;
    };
    // One split per face per round, so the faces an edge lists are still intact when it is split.
    std::vector<char> touched(result.faces.size(), 0);
    std::size_t splits = 0;
    for (const Long& edge : candidates) {
      const std::vector<std::size_t> faces = facesOf({edge.a, edge.b});
      if (std::any_of(faces.begin(), faces.end(), [&](std::size_t f) { return touched[f]; }))
        continue;
      const std::int32_t mid = static_cast<std::int32_t>(result.vertices.size());
      result.vertices.push_back(0.5 * (result.vertices[edge.a] + result.vertices[edge.b]));
      for (const std::size_t f : faces) {
        touched[f] = 1;
        Face face = result.faces[f];
        // Rotate so that the split edge is side 0 → 1 (either direction).
        int k = 0;
        while (!((face[k] == edge.a && face[(k + 1) % 3] == edge.b) || (face[k] == edge.b && face[(k + 1) % 3] == edge.a)))
          ++k;
        const std::int32_t p = face[k], r = face[(k + 1) % 3], s = face[(k + 2) % 3];
        result.faces[f] = {p, mid, s};
        result.faces.push_back({mid, r, s});
        touched.push_back(1);
      }
      ++splits;
      if (result.faces.size() > max_faces)
        throw Error("edge splitting: refining to edges of " + std::to_string(max_length) + " would exceed " +
                    std::to_string(max_faces) + " faces (the target length is too small for this mesh)");
    }
    if (splits == 0)
      break;
  }
  return result;
}

void QuadRemesher::process(QuadMesh& out, Report* report) const
{
  using Clock = std::chrono::steady_clock;
  const auto seconds = [](Clock::time_point a, Clock::time_point b) {
    return std::chrono::duration<double>(b - a).count();
  };
  if (!input_)
    throw Error("quad remeshing: no input mesh");
  if (input_->faces.empty())
    throw Error("quad remeshing: the input mesh has no faces");
  if (!(quad_length_ > 0.0) || !std::isfinite(quad_length_))
    throw Error("quad remeshing: the quad length must be positive and finite");
  for (const auto& v : input_->vertices)
    if (!v.allFinite())
      throw Error("quad remeshing: the input has non-finite coordinates");
  Report r;
  r.input_faces = input_->faces.size();

  auto t0 = Clock::now();
  const TriangleMesh refined = splitLongEdges(*input_, 0.5 * quad_length_, max_refined_faces);
  r.refined_faces = refined.faces.size();
  auto t1 = Clock::now();
  r.seconds_refine = seconds(t0, t1);

  const FieldHierarchy hierarchy = buildFieldHierarchy(refined);
  r.hierarchy_levels = hierarchy.numLevels();
  auto t2 = Clock::now();
  r.seconds_hierarchy = seconds(t1, t2);

  OrientationFieldParameters orientation_parameters;
  orientation_parameters.seed = seed_;
  orientation_parameters.iterations_per_level = iterations_;
  orientation_parameters.num_threads = threads_;
  const std::vector<Eigen::Vector3d> q = computeOrientationField(hierarchy, orientation_parameters);
  r.orientation_singularities = countOrientationSingularities(refined, hierarchy.levels[0].normals, q);
  auto t3 = Clock::now();
  r.seconds_orientation = seconds(t2, t3);

  PositionFieldParameters position_parameters;
  position_parameters.scale = quad_length_;
  position_parameters.seed = seed_;
  position_parameters.iterations_per_level = iterations_;
  position_parameters.num_threads = threads_;
  const auto q_levels = restrictOrientationField(hierarchy, q);
  const std::vector<Eigen::Vector3d> o = computePositionField(hierarchy, q_levels, position_parameters);
  const std::size_t edges = hierarchy.levels[0].adjacency.size() / 2;
  r.position_energy = edges ? positionFieldEnergy(hierarchy.levels[0], q, o, quad_length_) / static_cast<double>(edges)
                            : 0.0;
  auto t4 = Clock::now();
  r.seconds_position = seconds(t3, t4);

  extractQuadMesh(refined, hierarchy.levels[0], q, o, quad_length_, out);
  r.seconds_extraction = seconds(t4, Clock::now());
  if (report)
    *report = r;
}

}  // namespace patchdict
}  // namespace pcl
