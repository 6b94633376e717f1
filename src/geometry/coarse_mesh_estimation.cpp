#include <pcl_patchdict/geometry/coarse_mesh_estimation.h>

#include <pcl_patchdict/geometry/taubin_smoothing.h>
#include <pcl_patchdict/core/error.h>
#include <pcl_patchdict/geometry/mesh_hygiene.h>
#include <pcl_patchdict/core/mesh_topology.h>
#include <pcl_patchdict/pcl/conversions.h>

#include <pcl/features/normal_3d_omp.h>
#include <boost/graph/adjacency_list.hpp>
#include <boost/graph/kruskal_min_spanning_tree.hpp>
#include <pcl/search/kdtree.h>
#include <pcl/surface/poisson.h>

#include <fcntl.h>
#include <unistd.h>

#include <omp.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <mutex>
#include <numeric>
#include <queue>
#include <tuple>

#if defined(__SANITIZE_ADDRESS__)
// Sanitizer builds (PCL_PATCHDICT_SANITIZE=ON) only: pcl::Poisson (Debian's PCL 1.13) never frees the
// B-spline tables it allocates in BSplineData::setDotTables; LeakSanitizer would fail every binary that
// reconstructs a cloud for a leak that is not ours. Defined here, beside the Poisson call, so that it
// is linked into exactly the binaries that can make that call.
extern "C" const char* __lsan_default_suppressions() { return "leak:pcl::poisson::BSplineData\n"; }
#endif

namespace pcl {
namespace patchdict {

namespace {

/** meanDihedralAngle on a given adjacency (a smoothed mesh shares its input's). */
double meanDihedralAngle(const TriangleMesh& mesh, const EdgeFaceAdjacency& adjacency)
{
  double sum = 0.0;
  std::size_t count = 0;
  for (const MeshEdge& e : adjacency.edges) {
    if (e.faces.size() != 2)
      continue;
    const Eigen::Vector3d a = mesh.faceNormal(static_cast<std::size_t>(e.faces[0]));
    const Eigen::Vector3d b = mesh.faceNormal(static_cast<std::size_t>(e.faces[1]));
    if (a.isZero() || b.isZero())
      continue;
    sum += std::atan2(a.cross(b).norm(), a.dot(b));
    ++count;
  }
  return count ? sum / static_cast<double>(count) : 0.0;
}

}  // namespace

double meanDihedralAngle(const TriangleMesh& mesh)
{
  return meanDihedralAngle(mesh, computeEdgeFaceAdjacency(mesh));
}

void CoarseMeshEstimation::setInputMesh(const std::shared_ptr<const TriangleMesh>& mesh)
{
  input_ = mesh;
  cloud_.reset();
  cloud_with_normals_.reset();
}

void CoarseMeshEstimation::setInputCloud(const pcl::PointCloud<pcl::PointXYZ>::ConstPtr& cloud)
{
  input_.reset();
  cloud_ = cloud;
  cloud_with_normals_.reset();
}

void CoarseMeshEstimation::setInputCloud(const pcl::PointCloud<pcl::PointNormal>::ConstPtr& cloud)
{
  input_.reset();
  cloud_.reset();
  cloud_with_normals_ = cloud;
}

void CoarseMeshEstimation::checkParameters() const
{
  if (iterations_ < 0 || !(lambda_ > 0.0 && lambda_ <= 1.0) || !(mu_ < 0.0 && mu_ >= -1.0))
    throw Error("coarse mesh estimation: iterations ≥ 0, λ in (0, 1] and μ in [−1, 0) are required");
  if (normal_neighbours_ < 3 || normal_neighbours_ > 1000)
    throw Error("coarse mesh estimation: normal neighbours must be in [3, 1000]");
  if (poisson_depth_ != 0 && (poisson_depth_ < 2 || poisson_depth_ > 14))
    throw Error("coarse mesh estimation: Poisson depth must be 0 (automatic) or in [2, 14]");
  if (!(trim_factor_ >= 0.0) || !std::isfinite(trim_factor_))
    throw Error("coarse mesh estimation: the trim factor must be a finite number ≥ 0");
  if (min_trimmed_region_ < 1)
    throw Error("coarse mesh estimation: the minimum trimmed region must be at least 1 face");
}

void CoarseMeshEstimation::process(TriangleMesh& out, Report* report) const
{
  checkParameters();
  if (report)
    *report = Report();
  if (cloud_ || cloud_with_normals_) {
    processCloud(out, report);
    return;
  }
  if (!input_ || input_->faces.empty())
    throw Error("coarse mesh estimation needs a mesh with faces (or a point cloud)");
  smooth(*input_, out, report);
}

void CoarseMeshEstimation::smooth(const TriangleMesh& input, TriangleMesh& out, Report* report) const
{
  for (std::size_t v = 0; v < input.vertices.size(); ++v)
    if (!input.vertices[v].allFinite())
      throw Error("coarse mesh estimation: vertex " + std::to_string(v) + " is not finite");

  TriangleMesh mesh = input;
  const TaubinSmoother smoother(input, lambda_, mu_, TaubinSmoother::Weights::Uniform);
  for (int iteration = 0; iteration < iterations_; ++iteration) {
    smoother.step(mesh.vertices, lambda_);
    if (method_ == Method::Taubin)
      smoother.step(mesh.vertices, mu_);
  }
  if (report) {
    const double before = input.surfaceArea();
    report->area_change = before > 0.0 ? (mesh.surfaceArea() - before) / before : 0.0;
    const EdgeFaceAdjacency adjacency = computeEdgeFaceAdjacency(input);  // smoothing keeps the faces
    report->mean_dihedral_before = meanDihedralAngle(input, adjacency);
    report->mean_dihedral_after = meanDihedralAngle(mesh, adjacency);
  }
  mesh.normals.clear();
  out = std::move(mesh);
}

namespace {

/** Points file descriptors 1 and 2 at /dev/null while alive (C and C++ streams flushed at both
  * ends): PoissonRecon inside PCL prints diagnostics ("Vertex pair not in list", "[WARNING] Initial
  * residual too low", ...) that mean nothing to a user, on stdout (the tool's --json channel) and on
  * stderr (where an error must be the one last line). Failures surface as our own checks below. */
class ThirdPartyOutputMuted {
public:
  ThirdPartyOutputMuted()
  {
    flushAll();
    const int null_fd = ::open("/dev/null", O_WRONLY | O_CLOEXEC);
    if (null_fd < 0)
      return;
    for (int i = 0; i < 2; ++i) {
      saved_[i] = ::dup(i + 1);
      if (saved_[i] >= 0)
        ::dup2(null_fd, i + 1);
    }
    ::close(null_fd);
  }
  ~ThirdPartyOutputMuted()
  {
    flushAll();
    for (int i = 0; i < 2; ++i)
      if (saved_[i] >= 0) {
        ::dup2(saved_[i], i + 1);
        ::close(saved_[i]);
      }
  }
  ThirdPartyOutputMuted(const ThirdPartyOutputMuted&) = delete;
  ThirdPartyOutputMuted& operator=(const ThirdPartyOutputMuted&) = delete;

private:
  static void flushAll()
  {
    std::cout.flush();
    std::cerr.flush();
    std::fflush(stdout);
    std::fflush(stderr);
  }
  int saved_[2] = {-1, -1};
};

using Clock = std::chrono::steady_clock;
double secondsSince(Clock::time_point start) { return std::chrono::duration<double>(Clock::now() - start).count(); }

// k nearest other points of every point (the point itself and exact duplicates of it excluded
// from the spacing, not from the graph), through a FLANN kd-tree; parallel and deterministic.
struct NeighbourGraph {
  std::vector<std::vector<int>> neighbours;  // k per point
  double mean_spacing = 0.0;                 // mean distance to the nearest distinct point
};

template <typename PointT>
NeighbourGraph nearestNeighbours(const typename pcl::PointCloud<PointT>::ConstPtr& cloud, int k)
{
  pcl::search::KdTree<PointT> tree(false);
  tree.setInputCloud(cloud);
  const auto n = static_cast<std::ptrdiff_t>(cloud->size());
  NeighbourGraph graph;
  graph.neighbours.resize(static_cast<std::size_t>(n));
  std::vector<double> spacing(static_cast<std::size_t>(n), 0.0);
#pragma omp parallel
  {
    pcl::Indices indices;
    std::vector<float> squared;
#pragma omp for schedule(dynamic, 256)
    for (std::ptrdiff_t i = 0; i < n; ++i) {
      // A few extra neighbours so that the point itself and its duplicates can be skipped.
      tree.nearestKSearch((*cloud)[static_cast<std::size_t>(i)], k + 4, indices, squared);
      auto& mine = graph.neighbours[static_cast<std::size_t>(i)];
      double nearest = 0.0;
      for (std::size_t j = 0; j < indices.size(); ++j) {
        if (indices[j] == static_cast<int>(i))
          continue;
        if (static_cast<int>(mine.size()) < k)
          mine.push_back(indices[j]);
        if (nearest == 0.0 && squared[j] > 0.0f)
          nearest = std::sqrt(static_cast<double>(squared[j]));
      }
      spacing[static_cast<std::size_t>(i)] = nearest;
    }
  }
  std::size_t counted = 0;
  for (const double d : spacing)
    if (d > 0.0) {
      graph.mean_spacing += d;
      ++counted;
    }
  graph.mean_spacing = counted ? graph.mean_spacing / static_cast<double>(counted) : 0.0;
  return graph;
}

// Poisson depth from the sampling density: the octree cell (Poisson's cube is 1.1 × the samples'
// bounding cube) no larger than kCellPerSpacing × the mean spacing; clamped to [5, 10].
constexpr double kCellPerSpacing = 2.0;

int automaticPoissonDepth(const pcl::PointCloud<pcl::PointNormal>& cloud, double mean_spacing)
{
  Eigen::Vector3f lo = cloud[0].getVector3fMap(), hi = lo;
  for (const auto& p : cloud) {
    lo = lo.cwiseMin(p.getVector3fMap());
    hi = hi.cwiseMax(p.getVector3fMap());
  }
  const double extent = static_cast<double>((hi - lo).maxCoeff());
  if (!(mean_spacing > 0.0) || !(extent > 0.0))
    return 5;
  const double depth = std::ceil(std::log2(1.1 * extent / (kCellPerSpacing * mean_spacing)));
  return static_cast<int>(std::clamp(depth, 5.0, 10.0));
}

}  // namespace

// Hoppe et al. 1992, section 3.3: orientation propagated along a minimum spanning tree of the
// (symmetrised) kNN graph with cost 1 − |n_i·n_j|, so that it crosses between nearly parallel
// tangent planes first; each component's root is its highest point, its normal turned to +z.
// Points without a normal (zero vector) are passed through at the highest cost and take the mean
// oriented normal of their neighbours afterwards. The spanning forest is Boost.Graph's Kruskal.
std::size_t propagateNormalOrientation(const pcl::PointCloud<pcl::PointXYZ>& cloud, const std::vector<std::vector<int>>& knn,
                                 std::vector<Eigen::Vector3d>& normals)
{
  const std::size_t n = normals.size();
  std::vector<std::vector<int>> adjacency(knn);
  for (std::size_t i = 0; i < n; ++i)
    for (const int j : knn[i])
      adjacency[static_cast<std::size_t>(j)].push_back(static_cast<int>(i));
  for (auto& list : adjacency) {
    std::sort(list.begin(), list.end());
    list.erase(std::unique(list.begin(), list.end()), list.end());
  }
  const auto cost = [&](std::size_t a, std::size_t b) {
    return 1.0 - std::abs(normals[a].dot(normals[b]));  // 1 when either normal is missing (zero)
  };
  using Graph = boost::adjacency_list<boost::vecS, boost::vecS, boost::undirectedS, boost::no_property,
                                      boost::property<boost::edge_weight_t, double>>;
  Graph graph(n);
  for (std::size_t i = 0; i < n; ++i)
    for (const int j : adjacency[i])
      if (static_cast<std::size_t>(j) > i)
        boost::add_edge(i, static_cast<std::size_t>(j), cost(i, static_cast<std::size_t>(j)), graph);
  std::vector<boost::graph_traits<Graph>::edge_descriptor> forest_edges;
  boost::kruskal_minimum_spanning_tree(graph, std::back_inserter(forest_edges));
  std::vector<std::vector<std::size_t>> tree(n);
  for (const auto& e : forest_edges) {
    const std::size_t a = boost::source(e, graph), b = boost::target(e, graph);
    tree[a].push_back(b);
    tree[b].push_back(a);
  }
  std::vector<std::size_t> by_height(n);
  std::iota(by_height.begin(), by_height.end(), std::size_t{0});
  std::stable_sort(by_height.begin(), by_height.end(),
                   [&](std::size_t a, std::size_t b) { return cloud[a].z > cloud[b].z; });
  std::vector<char> visited(n, 0);
  std::size_t flipped = 0;
  for (const std::size_t root : by_height) {
    if (visited[root])
      continue;
    visited[root] = 1;
    if (normals[root].z() < 0.0) {
      normals[root] = -normals[root];
      ++flipped;
    }
    std::vector<std::size_t> stack{root};
    while (!stack.empty()) {
      const std::size_t from = stack.back();
      stack.pop_back();
      for (const std::size_t to : tree[from]) {
        if (visited[to])
          continue;
        visited[to] = 1;
        if (normals[to].dot(normals[from]) < 0.0) {
          normals[to] = -normals[to];
          ++flipped;
        }
        stack.push_back(to);
      }
    }
  }
  for (std::size_t i = 0; i < n; ++i) {
    if (!normals[i].isZero())
      continue;
    Eigen::Vector3d sum = Eigen::Vector3d::Zero();
    for (const int j : adjacency[i])
      sum += normals[static_cast<std::size_t>(j)];
    if (sum.norm() > 0.0)
      normals[i] = sum.normalized();
  }
  return flipped;
}

std::size_t estimateOrientedNormals(const pcl::PointCloud<pcl::PointXYZ>& cloud, int k,
                                    pcl::PointCloud<pcl::PointNormal>& out, double* mean_spacing)
{
  if (k < 3)
    throw Error("normal estimation needs at least 3 neighbours");
  if (cloud.size() <= static_cast<std::size_t>(k))
    throw Error("normal estimation: " + std::to_string(cloud.size()) + " points are too few for " +
                std::to_string(k) + " neighbours");
  for (std::size_t i = 0; i < cloud.size(); ++i)
    if (!std::isfinite(cloud[i].x) || !std::isfinite(cloud[i].y) || !std::isfinite(cloud[i].z))
      throw Error("normal estimation: point " + std::to_string(i) + " is not finite");
  const pcl::PointCloud<pcl::PointXYZ>::ConstPtr points(new pcl::PointCloud<pcl::PointXYZ>(cloud));
  const NeighbourGraph graph = nearestNeighbours<pcl::PointXYZ>(points, k);

  pcl::NormalEstimationOMP<pcl::PointXYZ, pcl::Normal> estimation(omp_get_max_threads());
  estimation.setInputCloud(points);
  estimation.setSearchMethod(pcl::search::KdTree<pcl::PointXYZ>::Ptr(new pcl::search::KdTree<pcl::PointXYZ>(false)));
  estimation.setKSearch(k + 1);  // the point itself is one of the k + 1
  pcl::PointCloud<pcl::Normal> pca;
  estimation.compute(pca);

  std::vector<Eigen::Vector3d> normals(cloud.size(), Eigen::Vector3d::Zero());
  for (std::size_t i = 0; i < cloud.size(); ++i) {
    const Eigen::Vector3d normal(pca[i].normal_x, pca[i].normal_y, pca[i].normal_z);
    if (normal.allFinite() && normal.norm() > 0.5)
      normals[i] = normal.normalized();
  }
  const std::size_t flipped = propagateNormalOrientation(cloud, graph.neighbours, normals);

  out.clear();
  out.resize(cloud.size());
  for (std::size_t i = 0; i < cloud.size(); ++i) {
    pcl::PointNormal& p = out[i];
    p.x = cloud[i].x;
    p.y = cloud[i].y;
    p.z = cloud[i].z;
    p.normal_x = static_cast<float>(normals[i].x());
    p.normal_y = static_cast<float>(normals[i].y());
    p.normal_z = static_cast<float>(normals[i].z());
    p.curvature = pca[i].curvature;
  }
  out.width = static_cast<std::uint32_t>(out.size());
  out.height = 1;
  out.is_dense = true;
  if (mean_spacing)
    *mean_spacing = graph.mean_spacing;
  return flipped;
}

namespace {

using CoarseReport = CoarseMeshEstimation::Report;

/** Finite samples with oriented unit normals: normals estimated and oriented for a plain cloud,
  * normalised for a cloud with normals; fewer than `minimum` usable points is an Error. */
pcl::PointCloud<pcl::PointNormal>::Ptr orientedSamples(const pcl::PointCloud<pcl::PointXYZ>::ConstPtr& cloud,
                                                       const pcl::PointCloud<pcl::PointNormal>::ConstPtr& with_normals,
                                                       int normal_neighbours, std::size_t minimum, CoarseReport& r)
{
  pcl::PointCloud<pcl::PointNormal>::Ptr samples(new pcl::PointCloud<pcl::PointNormal>);
  if (cloud) {
    r.input_points = cloud->size();
    pcl::PointCloud<pcl::PointXYZ> finite;
    for (const auto& p : *cloud)
      if (std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z))
        finite.push_back(p);
    r.points_dropped = r.input_points - finite.size();
    if (finite.size() < minimum)
      throw Error("coarse mesh estimation: the cloud has " + std::to_string(finite.size()) +
                  " finite points, at least " + std::to_string(minimum) + " are needed");
    r.normals_estimated = true;
    r.normals_flipped = estimateOrientedNormals(finite, normal_neighbours, *samples, &r.mean_spacing);
  } else {
    r.input_points = with_normals->size();
    for (const auto& p : *with_normals) {
      const Eigen::Vector3f position = p.getVector3fMap(), normal = p.getNormalVector3fMap();
      if (!position.allFinite() || !normal.allFinite() || !(normal.norm() > 0.0f))
        continue;
      pcl::PointNormal q = p;
      q.getNormalVector3fMap() = normal.normalized();
      samples->push_back(q);
    }
    r.points_dropped = r.input_points - samples->size();
    if (samples->size() < minimum)
      throw Error("coarse mesh estimation: the cloud has " + std::to_string(samples->size()) +
                  " points with finite positions and normals, at least " + std::to_string(minimum) +
                  " are needed");
    r.mean_spacing = nearestNeighbours<pcl::PointNormal>(samples, 1).mean_spacing;
  }
  if (!(r.mean_spacing > 0.0))
    throw Error("coarse mesh estimation: the cloud's points are all at one place");
  return samples;
}

/** Poisson surface of the samples (PCL), its diagnostics muted. */
TriangleMesh poissonSurface(const pcl::PointCloud<pcl::PointNormal>::Ptr& samples, int depth, CoarseReport& r)
{
  r.poisson_depth = depth > 0 ? depth : automaticPoissonDepth(*samples, r.mean_spacing);
  pcl::Poisson<pcl::PointNormal> poisson;
  poisson.setInputCloud(samples);
  poisson.setDepth(r.poisson_depth);
  poisson.setMinDepth(std::min(5, r.poisson_depth));
  poisson.setThreads(1);
  pcl::PolygonMesh polygons;
  {
    // PCL 1.13's Poisson keeps its octree allocator in a static that every reconstruction resets:
    // two at once (two threads, two inpainters) would free each other's octree. One at a time.
    static std::mutex poisson_mutex;
    const std::lock_guard<std::mutex> lock(poisson_mutex);
    const ThirdPartyOutputMuted muted;
    poisson.reconstruct(polygons);
  }
  TriangleMesh mesh;
  fromPolygonMesh(polygons, mesh);
  r.poisson_vertices = mesh.vertices.size();
  r.poisson_faces = mesh.faces.size();
  if (mesh.faces.empty())
    throw Error("coarse mesh estimation: Poisson reconstruction produced no surface from the cloud");
  r.area_before_trimming = mesh.surfaceArea();
  return mesh;
}

/** Flags the faces whose centroid is farther than `limit` from every sample (none when
  * trim_factor ≤ 0) and records each face's nearest sample. */
void flagFarFaces(const TriangleMesh& mesh, const pcl::PointCloud<pcl::PointNormal>& samples, double trim_factor,
                  double limit, std::vector<char>& keep, std::vector<int>& nearest_sample)
{
  pcl::PointCloud<pcl::PointXYZ>::Ptr positions(new pcl::PointCloud<pcl::PointXYZ>);
  positions->resize(samples.size());
  for (std::size_t i = 0; i < samples.size(); ++i)
    (*positions)[i].getVector3fMap() = samples[i].getVector3fMap();
  pcl::search::KdTree<pcl::PointXYZ> tree(false);
  tree.setInputCloud(positions);
  const auto num_faces = static_cast<std::ptrdiff_t>(mesh.faces.size());
  keep.assign(mesh.faces.size(), 1);
  nearest_sample.assign(mesh.faces.size(), 0);
#pragma omp parallel
  {
    pcl::Indices index(1);
    std::vector<float> squared(1);
#pragma omp for schedule(dynamic, 1024)
    for (std::ptrdiff_t f = 0; f < num_faces; ++f) {
      const Face& face = mesh.faces[static_cast<std::size_t>(f)];
      const Eigen::Vector3d centroid = (mesh.vertices[static_cast<std::size_t>(face[0])] +
                                        mesh.vertices[static_cast<std::size_t>(face[1])] +
                                        mesh.vertices[static_cast<std::size_t>(face[2])]) / 3.0;
      pcl::PointXYZ query;
      query.getVector3fMap() = centroid.cast<float>();
      if (tree.nearestKSearch(query, 1, index, squared) < 1)
        continue;
      nearest_sample[static_cast<std::size_t>(f)] = index[0];
      if (trim_factor > 0.0 && std::sqrt(static_cast<double>(squared[0])) > limit)
        keep[static_cast<std::size_t>(f)] = 0;
    }
  }
}

/** Turns each connected component to agree (area-weighted) with the normals of its faces' nearest
  * samples: marching cubes orients its triangles consistently, but which way depends on the sign
  * convention. */
void orientComponentsBySamples(TriangleMesh& trimmed, const pcl::PointCloud<pcl::PointNormal>& samples,
                               const std::vector<int>& kept_nearest)
{
  orientFacesConsistently(trimmed);
  std::vector<int> face_component, vertex_component;
  const int components = computeConnectedComponents(trimmed, face_component, vertex_component);
  std::vector<double> agreement(static_cast<std::size_t>(std::max(components, 0)), 0.0);
  for (std::size_t f = 0; f < trimmed.faces.size(); ++f) {
    const Face& face = trimmed.faces[f];
    const Eigen::Vector3d a = trimmed.vertices[static_cast<std::size_t>(face[0])],
                          b = trimmed.vertices[static_cast<std::size_t>(face[1])],
                          c = trimmed.vertices[static_cast<std::size_t>(face[2])];
    const Eigen::Vector3d area_normal = (b - a).cross(c - a);
    const Eigen::Vector3d sample_normal =
        samples[static_cast<std::size_t>(kept_nearest[f])].getNormalVector3fMap().cast<double>();
    if (face_component[f] >= 0)
      agreement[static_cast<std::size_t>(face_component[f])] += area_normal.dot(sample_normal);
  }
  for (std::size_t f = 0; f < trimmed.faces.size(); ++f)
    if (face_component[f] >= 0 && agreement[static_cast<std::size_t>(face_component[f])] < 0.0)
      std::swap(trimmed.faces[f][1], trimmed.faces[f][2]);
}

}  // namespace

void CoarseMeshEstimation::processCloud(TriangleMesh& out, Report* report) const
{
  Report local;
  Report& r = report ? *report : local;
  r.from_cloud = true;

  // 1–2. Finite samples with oriented unit normals.
  auto start = Clock::now();
  const pcl::PointCloud<pcl::PointNormal>::Ptr samples =
      orientedSamples(cloud_, cloud_with_normals_, normal_neighbours_, getMinimumPoints(), r);
  r.seconds_normals = secondsSince(start);

  // 3. Poisson surface.
  start = Clock::now();
  TriangleMesh mesh = poissonSurface(samples, poisson_depth_, r);
  r.seconds_poisson = secondsSince(start);

  // 4. Trimming, orientation, cleanup.
  start = Clock::now();
  std::vector<char> keep;
  std::vector<int> nearest_sample;
  flagFarFaces(mesh, *samples, trim_factor_, trim_factor_ * r.mean_spacing, keep, nearest_sample);
  // Far faces are gaps in the sampling when they come alone or in small groups (random samples
  // leave holes up to ~4 mean spacings wide, measured), a bubble or a skirt when they form a large
  // connected region: only regions of at least min_trimmed_region_ faces are removed.
  if (min_trimmed_region_ > 1) {
    std::vector<char> far(keep.size());
    for (std::size_t f = 0; f < keep.size(); ++f)
      far[f] = keep[f] ? 0 : 1;
    for (const auto& region : flaggedFaceRegions(mesh, far))
      if (static_cast<int>(region.size()) < min_trimmed_region_)
        for (const std::int32_t f : region)
          keep[static_cast<std::size_t>(f)] = 1;
  }
  TriangleMesh trimmed;
  trimmed.vertices = std::move(mesh.vertices);
  std::vector<int> kept_nearest;
  for (std::size_t f = 0; f < keep.size(); ++f)
    if (keep[f]) {
      trimmed.faces.push_back(mesh.faces[f]);
      kept_nearest.push_back(nearest_sample[f]);
    }
  r.faces_trimmed = mesh.faces.size() - trimmed.faces.size();
  if (trimmed.faces.empty())
    throw Error("coarse mesh estimation: trimming removed the whole Poisson surface (trim factor too small?)");
  orientComponentsBySamples(trimmed, *samples, kept_nearest);
  cleanMesh(trimmed);
  r.faces_after_cleanup = trimmed.faces.size();
  if (trimmed.faces.empty())
    throw Error("coarse mesh estimation: no usable face is left of the Poisson surface");
  r.area_after_trimming = trimmed.surfaceArea();
  r.seconds_trim = secondsSince(start);

  // 5. The mesh path's smoothing.
  start = Clock::now();
  smooth(trimmed, out, report);
  r.seconds_smooth = secondsSince(start);
}

}  // namespace patchdict
}  // namespace pcl
