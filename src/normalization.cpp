#include <pcl_patchdict/error.h>
#include <pcl_patchdict/normalization.h>

#include <cmath>
#include <string>

namespace pcl {
namespace patchdict {

UnitCubeNormalization UnitCubeNormalization::fromMesh(const TriangleMesh& mesh)
{
  if (mesh.vertices.empty())
    throw Error("cannot normalise an empty mesh");
  for (std::size_t v = 0; v < mesh.vertices.size(); ++v)
    if (!mesh.vertices[v].allFinite())
      throw Error("cannot normalise: vertex " + std::to_string(v) + " has a non-finite coordinate");
  Eigen::Vector3d lo, hi;
  mesh.boundingBox(lo, hi);
  const double side = (hi - lo).maxCoeff();
  // A side that overflows or vanishes would give an infinite or zero scale.
  if (!(side > 0.0) || !std::isfinite(side) || !std::isfinite(1.0 / side))
    throw Error("cannot normalise: the bounding box has no usable size (largest side " + std::to_string(side) + ")");
  UnitCubeNormalization normalization;
  normalization.center = 0.5 * (lo + hi);
  normalization.scale = 1.0 / side;
  return normalization;
}

void UnitCubeNormalization::apply(TriangleMesh& mesh) const
{
  for (auto& v : mesh.vertices)
    v = apply(v);
}

void UnitCubeNormalization::invert(TriangleMesh& mesh) const
{
  for (auto& v : mesh.vertices)
    v = invert(v);
}

}  // namespace patchdict
}  // namespace pcl
