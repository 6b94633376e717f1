// CoarseMeshEstimation — the smooth "low-resolution" shape a quad mesh is laid on (section 3.3 of
// Sarkar et al. 2017: 30 Laplacian smoothing iterations before quadrangulation).
#pragma once

#include <pcl_patchdict/triangle_mesh.h>

#include <memory>

namespace pcl {
namespace patchdict {

/** \brief Smooths a mesh into its coarse shape, keeping its connectivity.
  *
  * Method Laplacian: x ← x + λ·(mean of 1-ring − x), λ = 0.5, the paper's setting; it shrinks.
  * Method Taubin (the default): each iteration is a λ step followed by a μ step (μ = −0.53;
  * Taubin, "A signal processing approach to fair surface design", SIGGRAPH 1995), a low-pass
  * filter that barely shrinks. Measured on the bunny, 30 iterations (test
  * SmoothsNoiseAndTaubinShrinksLessThanLaplacian): mean dihedral angle 0.100 → 0.043 rad at
  * −7.6 % area for Laplacian, → 0.069 rad at −0.55 % area for Taubin. Boundary vertices of open scans are smoothed along the boundary only
  * (with their boundary neighbours), so holes and outer rims keep their place. */
class CoarseMeshEstimation {
public:
  using Ptr = std::shared_ptr<CoarseMeshEstimation>;
  using ConstPtr = std::shared_ptr<const CoarseMeshEstimation>;
  enum class Method { Laplacian, Taubin };

  struct Report {
    double area_change = 0.0;  ///< relative: (area after − area before) / area before
    double mean_dihedral_before = 0.0, mean_dihedral_after = 0.0;  ///< radians, over interior edges
  };

  void setInputMesh(const TriangleMesh& mesh) { input_ = &mesh; }
  void setIterations(int iterations) { iterations_ = iterations; }
  int getIterations() const { return iterations_; }
  void setMethod(Method method) { method_ = method; }
  Method getMethod() const { return method_; }
  void setLambda(double lambda) { lambda_ = lambda; }
  void setMu(double mu) { mu_ = mu; }

  /** The smoothed mesh (same vertices and faces, moved). Throws Error for a missing or face-less
    * input, non-finite coordinates, or parameters out of range. */
  void process(TriangleMesh& out, Report* report = nullptr) const;

private:
  const TriangleMesh* input_ = nullptr;
  int iterations_ = 30;
  Method method_ = Method::Taubin;
  double lambda_ = 0.5;
  double mu_ = -0.53;
};

/** Mean angle between the normals of faces sharing an interior manifold edge (radians): a
  * roughness measure that does not depend on size. */
double meanDihedralAngle(const TriangleMesh& mesh);

}  // namespace patchdict
}  // namespace pcl
