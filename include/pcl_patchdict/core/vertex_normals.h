// Vertex normals as the angle-weighted mean of incident face normals (Thürmer & Wüthrich 1998):
// independent of how the 1-ring is triangulated, which area or uniform weights are not.
#pragma once

#include <pcl_patchdict/core/triangle_mesh.h>

namespace pcl {
namespace patchdict {

/** Unit normal per vertex; zero for vertices no non-degenerate face uses. Assumes consistently
  * oriented faces (see orientFacesConsistently). */
std::vector<Eigen::Vector3d> computeVertexNormals(const TriangleMesh& mesh);

}  // namespace patchdict
}  // namespace pcl
