// Unit-cube normalisation: the bounding box centred at the origin with its largest side 1.
// All lengths in pcl_patchdict's parameters are in these units; outputs go back through the inverse.
#pragma once

#include <pcl_patchdict/core/triangle_mesh.h>

namespace pcl {
namespace patchdict {

/** x_normalised = (x − center) · scale, scale = 1 / (largest bbox side). */
struct UnitCubeNormalization {
  Eigen::Vector3d center = Eigen::Vector3d::Zero();
  double scale = 1.0;

  /** From the bounding box of the mesh's vertices. Throws Error for an empty mesh, non-finite
    * coordinates, a box of zero or unrepresentable size (all vertices equal), or a box more than
    * 10^6 times the extent of the middle 98 % of the vertices (stray vertices; 100 vertices or more). */
  static UnitCubeNormalization fromMesh(const TriangleMesh& mesh);

  Eigen::Vector3d apply(const Eigen::Vector3d& p) const { return (p - center) * scale; }
  Eigen::Vector3d invert(const Eigen::Vector3d& q) const { return q / scale + center; }
  /** Lengths: normalised units ↔ input units. */
  double applyLength(double length) const { return length * scale; }
  double invertLength(double length) const { return length / scale; }

  /** Transforms all vertex positions (normals are unchanged by a uniform scale). */
  void apply(TriangleMesh& mesh) const;
  void invert(TriangleMesh& mesh) const;
};

}  // namespace patchdict
}  // namespace pcl
