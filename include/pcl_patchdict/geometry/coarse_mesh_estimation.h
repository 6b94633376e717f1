// CoarseMeshEstimation — the smooth "low-resolution" shape a quad mesh is laid on (section 3.3 of
// Sarkar et al. 2017: 30 Laplacian smoothing iterations before quadrangulation; Poisson for clouds).
#pragma once

#include <pcl_patchdict/core/triangle_mesh.h>

#include <pcl/point_cloud.h>
#include <pcl/point_types.h>

#include <memory>
#include <vector>

#include <Eigen/Core>

namespace pcl {
namespace patchdict {

/** \brief Smooths a mesh into its coarse shape, keeping its connectivity; or builds that shape from
  * a point cloud first (normals → Poisson → trimming → cleanup → the same smoothing).
  *
  * Method Laplacian: x ← x + λ·(mean of 1-ring − x), λ = 0.5, the paper's setting; it shrinks.
  * Method Taubin (the default): each iteration is a λ step followed by a μ step (μ = −0.53;
  * Taubin, "A signal processing approach to fair surface design", SIGGRAPH 1995), a low-pass
  * filter that barely shrinks (test SmoothsNoiseAndTaubinShrinksLessThanLaplacian; figures in
  * docs/). Boundary vertices of open scans are smoothed along the boundary only (with their
  * boundary neighbours), so holes and outer rims keep their place.
  *
  * Cloud input (setInputCloud):
  *  1. non-finite points (and, for PointNormal, points whose normal is non-finite or zero) are
  *     dropped; fewer than getMinimumPoints() remaining is an Error;
  *  2. PointXYZ: normals by pcl::NormalEstimationOMP (PCA of the k nearest neighbours, default
  *     k = 16), oriented consistently by Hoppe et al.'s propagation ("Surface reconstruction from
  *     unorganized points", SIGGRAPH 1992, section 3.3): a minimum spanning tree of the symmetric
  *     kNN graph with edge cost 1 − |n_i·n_j|, rooted at the highest point of each connected
  *     component, whose normal is made to point up (+z: outward for any closed surface, towards
  *     a viewer above for a scan seen from above); every child is flipped to agree with its
  *     parent. Chosen over "towards a viewpoint / away from the centroid", which fails on concave
  *     regions of closed shapes (the bunny's neck, ears). PointNormal: the normals are used as given;
  *  3. pcl::Poisson (Kazhdan et al. 2006), depth from the sampling density when setPoissonDepth(0)
  *     (the default): the smallest depth whose octree cell, (1.1 · largest bbox side) / 2^depth, is
  *     at most twice the mean nearest-neighbour spacing s, clamped to [5, 10]: past the rule's
  *     depth, Poisson's time grows faster than its accuracy (figures in docs/);
  *  4. trimming: Poisson closes open scans and holes with smooth "bubbles" far from any sample;
  *     faces whose centroid is farther than getTrimFactor() · s from the nearest input point, in
  *     edge-connected regions of at least getMinimumTrimmedRegion() such faces, are removed (see
  *     setTrimFactor for the measured defaults), then cleanMesh (degenerate and duplicate faces,
  *     unreferenced vertices); faces are oriented to agree with the input normals. Poisson also
  *     grows a skirt a few spacings wide beyond the rim of an open scan, and faces there are close
  *     to the rim's samples: part of it stays (far less than untrimmed; figures in docs/);
  *  5. the same smoothing as for a mesh (rims of the trimmed surface slide along themselves).
  * pcl::Poisson keeps global state: reconstructions are serialised by a process-wide mutex (two
  * cloud estimations in two threads are safe, the Poisson stage of one waits for the other). */
class CoarseMeshEstimation {
public:
  using Ptr = std::shared_ptr<CoarseMeshEstimation>;
  using ConstPtr = std::shared_ptr<const CoarseMeshEstimation>;
  enum class Method { Laplacian, Taubin };

  struct Report {
    double area_change = 0.0;  ///< relative, from smoothing: (area after − area before) / area before
    double mean_dihedral_before = 0.0, mean_dihedral_after = 0.0;  ///< radians, over interior edges

    // Cloud input only (zero for a mesh input).
    bool from_cloud = false;
    std::size_t input_points = 0;       ///< points given
    std::size_t points_dropped = 0;     ///< non-finite positions or normals
    bool normals_estimated = false;     ///< false when a PointNormal cloud brought its own
    std::size_t normals_flipped = 0;    ///< by the orientation propagation
    double mean_spacing = 0.0;          ///< mean distance of a point to its nearest neighbour
    int poisson_depth = 0;
    std::size_t poisson_vertices = 0, poisson_faces = 0;  ///< Poisson's raw output (= faces before trimming)
    std::size_t faces_trimmed = 0;      ///< faces farther than trim factor × spacing from every sample
    std::size_t faces_after_cleanup = 0;  ///< faces after trimming and cleanMesh (= faces of the result)
    double area_before_trimming = 0.0, area_after_trimming = 0.0;
    double seconds_normals = 0.0, seconds_poisson = 0.0, seconds_trim = 0.0, seconds_smooth = 0.0;
  };

  /** A mesh to smooth, shared (kept alive until it is replaced). Clears a cloud. */
  void setInputMesh(const std::shared_ptr<const TriangleMesh>& mesh);
  /** A bare cloud: normals are estimated and oriented (see the class comment). Clears a mesh. */
  void setInputCloud(const pcl::PointCloud<pcl::PointXYZ>::ConstPtr& cloud);
  /** A cloud with normals (unit or not; oriented consistently, outwards). Clears a mesh. */
  void setInputCloud(const pcl::PointCloud<pcl::PointNormal>::ConstPtr& cloud);

  void setIterations(int iterations) { iterations_ = iterations; }
  int getIterations() const { return iterations_; }
  void setMethod(Method method) { method_ = method; }
  Method getMethod() const { return method_; }
  void setLambda(double lambda) { lambda_ = lambda; }
  void setMu(double mu) { mu_ = mu; }

  /** Neighbours for normal estimation and the orientation graph (cloud input; default 16). */
  void setNormalNeighbours(int k) { normal_neighbours_ = k; }
  int getNormalNeighbours() const { return normal_neighbours_; }
  /** Poisson octree depth; 0 (default) = from the sampling density (see the class comment). */
  void setPoissonDepth(int depth) { poisson_depth_ = depth; }
  int getPoissonDepth() const { return poisson_depth_; }
  /** Faces whose centroid is farther than trim_factor × mean spacing from every input point are
    * removed (in regions, see setMinimumTrimmedRegion); 0 disables trimming. Defaults 3 and 20
    * faces, chosen on random area-uniform samples of a sphere and a torus, where every face is
    * true surface: a smaller factor, or single faces, trims pinholes into them (random samples
    * leave gaps of a few spacings); factor ≥ 2.5 with regions ≥ 20 faces trims none. On open
    * scans the closing bubble or skirt is one large region and goes (test
    * TrimmingRemovesTheBubbleOfAnOpenScan). Factor 3 rather than 2.5 leaves room for noise, at a
    * little more skirt area on an open random scan (figures in docs/). */
  void setTrimFactor(double trim_factor) { trim_factor_ = trim_factor; }
  double getTrimFactor() const { return trim_factor_; }
  /** Far faces are removed only where they form an edge-connected region of at least this many
    * faces (1 = every far face): smaller groups are gaps between random samples, not bubbles. */
  void setMinimumTrimmedRegion(int faces) { min_trimmed_region_ = faces; }
  int getMinimumTrimmedRegion() const { return min_trimmed_region_; }
  /** Fewest points (after dropping non-finite ones) a cloud may have. */
  static constexpr std::size_t getMinimumPoints() { return 100; }

  /** The coarse mesh. Mesh input: the smoothed mesh (same vertices and faces, moved). Cloud input:
    * a new mesh (Poisson, trimmed, cleaned, smoothed). Throws Error for a missing or face-less
    * mesh, too few points, non-finite mesh coordinates, or parameters out of range. */
  void process(TriangleMesh& out, Report* report = nullptr) const;

private:
  void checkParameters() const;
  void smooth(const TriangleMesh& input, TriangleMesh& out, Report* report) const;
  void processCloud(TriangleMesh& out, Report* report) const;

  std::shared_ptr<const TriangleMesh> input_;
  pcl::PointCloud<pcl::PointXYZ>::ConstPtr cloud_;
  pcl::PointCloud<pcl::PointNormal>::ConstPtr cloud_with_normals_;
  int iterations_ = 30;
  Method method_ = Method::Taubin;
  double lambda_ = 0.5;
  double mu_ = -0.53;
  int normal_neighbours_ = 16;
  int poisson_depth_ = 0;
  double trim_factor_ = 3.0;
  int min_trimmed_region_ = 20;
};

/** Mean angle between the normals of faces sharing an interior manifold edge (radians): a
  * roughness measure that does not depend on size. */
double meanDihedralAngle(const TriangleMesh& mesh);

/** \brief Normals of a bare cloud, consistently oriented (the cloud path of CoarseMeshEstimation):
  * pcl::NormalEstimationOMP over the k nearest neighbours, then Hoppe et al. 1992's minimum
  * spanning tree propagation (see CoarseMeshEstimation). The cloud must be finite and hold more
  * than k points (Error otherwise). Returns the number of normals the propagation flipped;
  * `mean_spacing`, if given, receives the mean nearest-neighbour distance. Deterministic. */
std::size_t estimateOrientedNormals(const pcl::PointCloud<pcl::PointXYZ>& cloud, int k,
                                    pcl::PointCloud<pcl::PointNormal>& out, double* mean_spacing = nullptr);

/** \brief Consistent orientation of unoriented normals (Hoppe et al. 1992, section 3.3): a minimum
  * spanning tree of the symmetrised kNN graph `knn` with edge cost 1 − |n_i·n_j|, rooted at the
  * highest point (largest z) of each component, whose normal is turned to +z; each child is flipped
  * to agree with its parent. Zero normals take the mean of their oriented neighbours. Returns the
  * number of flips. Deterministic. */
std::size_t propagateNormalOrientation(const pcl::PointCloud<pcl::PointXYZ>& cloud, const std::vector<std::vector<int>>& knn,
                                       std::vector<Eigen::Vector3d>& normals);

}  // namespace patchdict
}  // namespace pcl
