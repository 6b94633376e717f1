// Quad frames — seed points and local reference frames from the faces of a quad mesh (section 3.3
// of Sarkar et al. 2017): Z the face normal, X and Y along the face's sides, made consistent across
// the mesh by a breadth-first traversal. Free functions over the core's QuadMesh; the PCL-shaped
// class that runs the whole layout on a cloud or a pcl::PolygonMesh is
// pcl/quad_frame_estimation.h.
#pragma once

#include <pcl_patchdict/core/local_frame.h>
#include <pcl_patchdict/quads/quad_mesh.h>

#include <cstdint>
#include <vector>

namespace pcl {
namespace patchdict {

/** \brief Seeds and one frame per seed on the faces of a quad mesh; frames are the core's (rows X,
  * Y, Z in double, core/local_frame.h), toReferenceFrames gives PCL's.
  *
  * Every face gives its centre as a seed (the paper uses quads; the few triangles and larger
  * faces of a quad-dominant mesh get seeds too, so no part of the surface is left without one);
  * overlap level k adds 4k seeds per face: for j = 1..k, the four points at parameters
  * (½ ± ½·j/(k+1), ½ ± ½·j/(k+1)) of the face's bilinear patch, i.e. on the way from its centre
  * to its corners (the paper's Fig. 2, right). All seeds of a face share its frame.
  *
  * The frame of a face: Z = the face normal (Newell), oriented like the vertex normals; the two
  * side directions are the means of opposite sides (quads) or the first side (other faces),
  * projected onto the face plane. Of the four candidates ±d0, ±(Z×d0) for X, a breadth-first
  * traversal over faces sharing an edge picks the one closest to the parent face's X transported
  * into this face's plane (transportTangent), so X agrees across the surface except around
  * singularities of the field; Y = Z × X. Each connected component starts at its lowest-index face
  * with X = d0.
  *
  * Seeds come face by face (the centre, then the offsets), each with its face's frame rounded to
  * single precision (roundToSinglePrecision: the frames every output was measured in);
  * `seed_faces`, if given, receives the face of each seed. Throws Error for an overlap outside
  * [0, 16], an out-of-range index, a face with fewer than three vertices, or a mesh without faces.
  * Degenerate faces (zero normal) give no seeds. */
void computeQuadFrames(const QuadMesh& mesh, int overlap, std::vector<Eigen::Vector3d>& seeds,
                       std::vector<Eigen::Matrix3d>& frames, std::vector<std::int32_t>* seed_faces = nullptr);

/** The frame of every face (rows X, Y, Z, not rounded), without seeds, as computeQuadFrames makes
  * them; a degenerate face gets a zero matrix. Throws Error for the mesh errors computeQuadFrames
  * names. */
std::vector<Eigen::Matrix3d> computeQuadFaceFrames(const QuadMesh& mesh);

/** A unit tangent of the plane with normal from_normal carried to the plane with normal to_normal
  * by the smallest rotation between the two normals (discrete parallel transport across an edge). */
Eigen::Vector3d transportTangent(const Eigen::Vector3d& v, const Eigen::Vector3d& from_normal,
                                 const Eigen::Vector3d& to_normal);

/** Angle in radians between the X axes of two frames once the second is transported to the first's
  * tangent plane (transportTangent); the measure of frame consistency across neighbours. */
double transportedXAngle(const Eigen::Matrix3d& frame_a, const Eigen::Matrix3d& frame_b);

}  // namespace patchdict
}  // namespace pcl
