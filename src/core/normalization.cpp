#include <pcl_patchdict/core/error.h>
#include <pcl_patchdict/core/normalization.h>

#include <algorithm>
#include <cmath>
#include <sstream>
#include <vector>
#include <string>

namespace pcl {
namespace patchdict {

namespace {
/** Beyond this ratio of the whole bounding box to the box of 98 % of the vertices, the box is
  * taken to be made by stray vertices, not by the surface. */
constexpr double kStrayVertexFactor = 1e6;
}  // namespace

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
  // A handful of stray vertices far from the rest (a scanner's garbage point at 1e30) would shrink the
  // surface to nothing in the unit cube, and every later stage would fail for a reason nobody sees.
  // Compare the box with the one holding the middle 98 % of the vertices along each axis.
  if (mesh.vertices.size() >= 100) {
    const std::size_t n = mesh.vertices.size(), cut = n / 100;
    double robust_side = 0.0;
    Eigen::Vector3d robust_middle;
    std::vector<double> values(n);
    for (int axis = 0; axis < 3; ++axis) {
      for (std::size_t v = 0; v < n; ++v)
        values[v] = mesh.vertices[v][axis];
      std::nth_element(values.begin(), values.begin() + static_cast<std::ptrdiff_t>(cut), values.end());
      const double low = values[cut];
      std::nth_element(values.begin(), values.begin() + static_cast<std::ptrdiff_t>(n - 1 - cut), values.end());
      robust_side = std::max(robust_side, values[n - 1 - cut] - low);
      robust_middle[axis] = 0.5 * (low + values[n - 1 - cut]);
    }
    if (robust_side > 0.0 && side > kStrayVertexFactor * robust_side) {
      std::size_t far = 0;
      double far_distance = -1.0;
      for (std::size_t v = 0; v < n; ++v) {
        const double d = (mesh.vertices[v] - robust_middle).cwiseAbs().maxCoeff();
        if (d > far_distance) {
          far_distance = d;
          far = v;
        }
      }
      std::ostringstream text;
      text << "cannot normalise: the bounding box is set by stray vertices far from the rest (it is "
           << side / robust_side << " times the extent of 98 % of the vertices; vertex " << far << " is at ("
           << mesh.vertices[far].x() << ", " << mesh.vertices[far].y() << ", " << mesh.vertices[far].z()
           << ")): remove them first";
      throw Error(text.str());
    }
  }
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
