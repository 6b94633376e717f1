// Procedural test surfaces with closed forms: plane grid, icosphere, torus, sinusoidal relief.
// Used by the tests (known answers), the benchmarks (meshes of a chosen size) and the demo.
#pragma once

#include <pcl_patchdict/core/triangle_mesh.h>

namespace pcl {
namespace patchdict {

/** Regular grid on z = 0 over [0, size_x] × [0, size_y], nx × ny quads, each split in two. */
TriangleMesh makePlaneGrid(int nx, int ny, double size_x = 1.0, double size_y = 1.0);

/** Icosphere of the given radius around the origin: the icosahedron subdivided `levels` times
  * (20·4^levels faces), every vertex projected onto the sphere. */
TriangleMesh makeIcosphere(int levels, double radius = 1.0);

/** Torus around the z axis: major radius R, minor radius r, nu × nv quads split in two. */
TriangleMesh makeTorus(int nu, int nv, double major_radius = 1.0, double minor_radius = 0.3);

/** Height field z = amplitude · sin(2π x / period) · sin(2π y / period) over [0,1]², on an
  * nx × ny grid: a relief whose exact surface is known everywhere. */
TriangleMesh makeSinusoidalRelief(int nx, int ny, double amplitude, double period);

/** Closed-form height of makeSinusoidalRelief at (x, y). */
double sinusoidalReliefHeight(double x, double y, double amplitude, double period);

/** Loop-free midpoint subdivision: every triangle → 4 (positions unchanged, no smoothing). */
TriangleMesh subdivideMidpoint(const TriangleMesh& mesh);

}  // namespace patchdict
}  // namespace pcl
