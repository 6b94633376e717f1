// Extrinsic 4-PoSy position field: per vertex, a lattice origin on its tangent plane whose square
// lattice (axes from the 4-RoSy field, spacing s) agrees with its neighbours' (Jakob et al. 2015 §4).
#pragma once

#include <pcl_patchdict/quads/orientation_field.h>

#include <Eigen/Core>

#include <cstdint>
#include <utility>
#include <vector>

namespace pcl {
namespace patchdict {

/** Lattice point o + q·⌊q·(p−o)/s⌋·s + t·⌊t·(p−o)/s⌋·s with t = n×q: the corner of the lattice
  * cell containing p (position_floor_4). */
Eigen::Vector3d positionFloor4(const Eigen::Vector3d& o, const Eigen::Vector3d& q, const Eigen::Vector3d& n,
                               const Eigen::Vector3d& p, double scale);
/** The integer coordinates of that corner relative to o. */
Eigen::Vector2i positionFloorIndex4(const Eigen::Vector3d& o, const Eigen::Vector3d& q, const Eigen::Vector3d& n,
                                    const Eigen::Vector3d& p, double scale);
/** The lattice point nearest to p (position_round_4). */
Eigen::Vector3d positionRound4(const Eigen::Vector3d& o, const Eigen::Vector3d& q, const Eigen::Vector3d& n,
                               const Eigen::Vector3d& p, double scale);

/** The point nearest to both p0 and p1 (least squares) that lies on both tangent planes
  * (p0, n0) and (p1, n1), with the 1e-4 regularisation of Jakob et al. for parallel planes. */
Eigen::Vector3d middlePoint(const Eigen::Vector3d& p0, const Eigen::Vector3d& n0, const Eigen::Vector3d& p1,
                            const Eigen::Vector3d& n1);

/** compat_position_extrinsic_4: the pair of lattice points, one of lattice (o0, q0, n0) and one of
  * lattice (o1, q1, n1), among the corners of the cells containing the middle point of the two
  * vertices, that are closest to each other. */
std::pair<Eigen::Vector3d, Eigen::Vector3d> compatPositionExtrinsic4(
    const Eigen::Vector3d& v0, const Eigen::Vector3d& n0, const Eigen::Vector3d& q0, const Eigen::Vector3d& o0,
    const Eigen::Vector3d& v1, const Eigen::Vector3d& n1, const Eigen::Vector3d& q1, const Eigen::Vector3d& o1,
    double scale);

/** The same match as integer lattice coordinates (each relative to its own origin, along its own
  * q and n×q); `error` receives the squared distance between the two matched points. */
std::pair<Eigen::Vector2i, Eigen::Vector2i> compatPositionExtrinsicIndex4(
    const Eigen::Vector3d& v0, const Eigen::Vector3d& n0, const Eigen::Vector3d& q0, const Eigen::Vector3d& o0,
    const Eigen::Vector3d& v1, const Eigen::Vector3d& n1, const Eigen::Vector3d& q1, const Eigen::Vector3d& o1,
    double scale, double* error = nullptr);

struct PositionFieldParameters {
  double scale = 0.03;           ///< lattice spacing s (the target edge length)
  std::uint64_t seed = 0;        ///< seeds the random origins on the coarsest level
  int iterations_per_level = 6;  ///< Gauss–Seidel sweeps per level
  int num_threads = 0;           ///< 0: OpenMP's default; the result does not depend on it
};

/** \brief Orientation field of every level: level 0 as given, each coarser vertex the
  * area-weighted 4-RoSy average of its children, in its own tangent plane. */
std::vector<std::vector<Eigen::Vector3d>> restrictOrientationField(const FieldHierarchy& hierarchy,
                                                                   const std::vector<Eigen::Vector3d>& field);

/** \brief Smooth extrinsic 4-PoSy field by hierarchical Gauss–Seidel (Jakob et al. 2015 §3–5):
  * random origins within one spacing of each vertex on the coarsest level, sweeps per level in
  * colour phases, prolongation by projection onto the children's tangent planes. Each returned
  * origin is the lattice point nearest its level-0 vertex, on its tangent plane.
  * `orientation` holds one field per level (restrictOrientationField). Throws Error for a scale
  * that is not positive and finite or fields that do not match the hierarchy. */
std::vector<Eigen::Vector3d> computePositionField(const FieldHierarchy& hierarchy,
                                                  const std::vector<std::vector<Eigen::Vector3d>>& orientation,
                                                  const PositionFieldParameters& parameters = {});

/** \brief Σ over level-0 edges of the squared distance between the matched lattice points
  * (compatPositionExtrinsic4), divided by s²: 0 for a field that is one lattice everywhere. */
double positionFieldEnergy(const FieldLevel& level, const std::vector<Eigen::Vector3d>& orientation,
                           const std::vector<Eigen::Vector3d>& origins, double scale);

}  // namespace patchdict
}  // namespace pcl
