// Shapes with holes the hole-filling tests share (test/geometry/test_hole_filling.cpp, test/cli/test_cli_fill_holes_mesh.cpp).
#pragma once

#include <pcl_patchdict/core/triangle_mesh.h>
#include <pcl_patchdict_eval/shapes.h>
#include <pcl_patchdict/geometry/mesh_hygiene.h>

#include <Eigen/Core>

#include <cstdint>
#include <vector>

namespace hole_test {

using namespace pcl::patchdict;

// Keeps the faces for which keep(centroid) holds and drops vertices no face uses.
template <typename Keep>
inline TriangleMesh cutFaces(const TriangleMesh& mesh, Keep keep)
{
  TriangleMesh out = mesh;
  out.faces.clear();
  for (const Face& f : mesh.faces)
    if (keep(f))
      out.faces.push_back(f);
  cleanMesh(out);
  return out;
}

// A unit icosphere with every face removed that has a vertex within `radius` of each centre.
inline TriangleMesh sphereWithHoles(int levels, double radius, const std::vector<Eigen::Vector3d>& centres)
{
  const TriangleMesh sphere = makeIcosphere(levels, 1.0);
  return cutFaces(sphere, [&](const Face& f) {
    for (const std::int32_t v : f)
      for (const auto& c : centres)
        if ((sphere.vertices[v] - c).norm() < radius)
          return false;
    return true;
  });
}

}  // namespace hole_test
