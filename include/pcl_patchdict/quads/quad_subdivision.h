// Quad subdivision — a triangle mesh on a quad-dominant mesh, each face split n times along its
// sides: the dense target a decoder rebuilds a surface on when only the quad mesh travelled.
#pragma once

#include <pcl_patchdict/quads/quad_mesh.h>
#include <pcl_patchdict/core/triangle_mesh.h>

namespace pcl {
namespace patchdict {

/** \brief Splits every face of `quads` into a fine triangle mesh: a quad into an n×n grid of
  * bilinear points (two triangles per cell), a triangle into n² barycentric triangles, a larger
  * polygon into a fan around its centroid whose triangles are split the same way. Points on a
  * shared edge are shared (the result is as connected as the quad mesh); faces keep the quads'
  * orientation. Throws Error for n outside [1, 256] or an out-of-range index. */
TriangleMesh subdivideQuadMesh(const QuadMesh& quads, int n);

}  // namespace patchdict
}  // namespace pcl
