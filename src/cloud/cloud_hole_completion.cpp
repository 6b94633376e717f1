// completeCloudHoles (see cloud_hole_completion.h).
#include <pcl_patchdict/cloud/biharmonic_implicit.h>
#include <pcl_patchdict/cloud/cloud_hole_completion.h>
#include <pcl_patchdict/geometry/coarse_mesh_estimation.h>
#include <pcl_patchdict/core/error.h>
#include <pcl_patchdict/core/mesh_topology.h>
#include <pcl_patchdict/core/surface_sampling.h>
#include <pcl_patchdict/geometry/thin_plate_spline.h>

#include <pcl/search/kdtree.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <numeric>
#include <unordered_map>

#ifdef _OPENMP
#include <omp.h>
#endif

namespace pcl {
namespace patchdict {

namespace {

using Clock = std::chrono::steady_clock;
double secondsSince(Clock::time_point start) { return std::chrono::duration<double>(Clock::now() - start).count(); }

pcl::PointXYZ toPoint(const Eigen::Vector3d& p)
{
  return pcl::PointXYZ(static_cast<float>(p.x()), static_cast<float>(p.y()), static_cast<float>(p.z()));
}

struct Gap {
  std::vector<std::int32_t> faces;
};

/** Appends face f of `surface` to `part` as a triangle of its own. */
void appendFace(const TriangleMesh& surface, std::size_t f, TriangleMesh& part)
{
  const Face& face = surface.faces[f];
  const auto base = static_cast<std::int32_t>(part.vertices.size());
  for (int k = 0; k < 3; ++k)
    part.vertices.push_back(surface.vertices[static_cast<std::size_t>(face[k])]);
  part.faces.push_back(Face{base, base + 1, base + 2});
}

/** Key of the cubic cell of side `cell` holding p, shifted by (dx, dy, dz) cells (21 bits per axis:
  * keys repeat only 2²¹ cells apart, far beyond one hole). */
std::int64_t cellKey(const Eigen::Vector3d& p, double cell, int dx = 0, int dy = 0, int dz = 0)
{
  const auto c = [cell](double v, int d) { return (static_cast<std::int64_t>(std::floor(v / cell)) + d) & 0x1FFFFF; };
  return (c(p.x(), dx) << 42) | (c(p.y(), dy) << 21) | c(p.z(), dz);
}

struct HoleFill {
  std::vector<Eigen::Vector3d> points, normals;
  std::vector<std::size_t> sources;
  enum class Outcome { Filled, FilledImplicit, FilledFromPoisson, TooLarge } outcome = Outcome::FilledFromPoisson;
};

/// The surface, the searches and the scales that every hole's fill reads.
struct Completion {
  Completion(const std::vector<Eigen::Vector3d>& points_, const std::vector<Eigen::Vector3d>& normals_, double spacing_,
             const CloudCompletionParameters& parameters_)
      : points(points_), normals(normals_), spacing(spacing_), parameters(parameters_)
  {
  }

  const std::vector<Eigen::Vector3d>& points;
  const std::vector<Eigen::Vector3d>& normals;
  const double spacing;
  const CloudCompletionParameters& parameters;
  std::shared_ptr<pcl::PointCloud<pcl::PointXYZ>> positions = std::make_shared<pcl::PointCloud<pcl::PointXYZ>>();
  pcl::search::KdTree<pcl::PointXYZ> tree{true};  // over the positions
  double max_diameter = 0.0;
  TriangleMesh surface;  // Poisson's, untrimmed
  std::vector<char> far;  // per face
  std::vector<Eigen::Vector3d> centroids;  // per face
  pcl::search::KdTree<pcl::PointXYZ> centroid_tree{false};
  double far_limit = 0.0, density = 0.0, a = 0.0;  // a: the spacing of a lattice of that density
};

void checkParameters(const std::vector<Eigen::Vector3d>& points, const std::vector<Eigen::Vector3d>& normals,
                     double spacing, const CloudCompletionParameters& parameters)
{
  if (points.size() != normals.size())
    throw Error("cloud completion: one normal per point is needed");
  if (points.size() < CoarseMeshEstimation::getMinimumPoints())
    throw Error("cloud completion: " + std::to_string(points.size()) +
                " points are left after outlier removal; at least 100 are needed");
  if (!(spacing > 0.0) || !std::isfinite(spacing) || !(parameters.gap_factor > 0.0) || parameters.min_gap_faces < 1 ||
      !(parameters.max_hole_diameter >= 0.0) || !(parameters.rim_width > 0.0) || parameters.max_rim_points < 10 ||
      !(parameters.smoothing >= 0.0) || !(parameters.clearance >= 0.0) || !(parameters.single_sheet >= 0.0) ||
      !(parameters.single_sheet <= 1.0) || parameters.implicit_points < 10 || !(parameters.implicit_offset > 0.0) ||
      !std::isfinite(parameters.implicit_offset) || parameters.oversampling < 1 || parameters.oversampling > 1000 ||
      !(parameters.thinning > 0.0) || !std::isfinite(parameters.thinning))
    throw Error("cloud completion: parameters out of range");
}

// 1. The untrimmed Poisson surface.
void poissonSurface(Completion& c, CloudCompletionReport& report)
{
  const std::vector<Eigen::Vector3d>& points = c.points;
  auto cloud = std::make_shared<pcl::PointCloud<pcl::PointNormal>>();
  Eigen::Vector3d low = points.front(), high = points.front();
  for (std::size_t i = 0; i < points.size(); ++i) {
    pcl::PointNormal p;
    p.getVector3fMap() = points[i].cast<float>();
    p.getNormalVector3fMap() = c.normals[i].cast<float>();
    cloud->push_back(p);
    c.positions->push_back(toPoint(points[i]));
    low = low.cwiseMin(points[i]);
    high = high.cwiseMax(points[i]);
  }
  c.max_diameter =
      c.parameters.max_hole_diameter > 0.0 ? c.parameters.max_hole_diameter : 0.15 * (high - low).maxCoeff();
  CoarseMeshEstimation poisson;
  poisson.setInputCloud(cloud);
  poisson.setTrimFactor(0.0);
  poisson.setIterations(0);
  // Poisson only finds the gaps here (the fill is the spline's): cells of up to 4 s suffice, and each
  // level deeper costs several times more (boot, 95k points, 2 cores shared with a build: depth 9
  // 28 s, depth 8 12 s).
  int depth = c.parameters.poisson_depth;
  if (depth == 0) {
    const double side = 1.1 * (high - low).maxCoeff();
    depth = 5;
    while (depth < 10 && side / std::ldexp(1.0, depth) > 4.0 * c.spacing)
      ++depth;
  }
  poisson.setPoissonDepth(depth);
  CoarseMeshEstimation::Report poisson_report;
  poisson.process(c.surface, &poisson_report);
  report.poisson_depth = poisson_report.poisson_depth;
  report.poisson_faces = c.surface.faces.size();
}

// 2. Gaps: far faces, in edge-connected regions.
std::vector<Gap> findGaps(Completion& c, int threads, CloudCompletionReport& report)
{
  const TriangleMesh& surface = c.surface;
  c.tree.setInputCloud(c.positions);
  const auto nf = static_cast<std::ptrdiff_t>(surface.faces.size());
  c.far.assign(surface.faces.size(), 0);
  c.centroids.resize(surface.faces.size());
  c.far_limit = c.parameters.gap_factor * c.spacing;
#pragma omp parallel num_threads(threads)
  {
    pcl::Indices index;
    std::vector<float> squared;
#pragma omp for schedule(dynamic, 1024)
    for (std::ptrdiff_t f = 0; f < nf; ++f) {
      const Face& face = surface.faces[static_cast<std::size_t>(f)];
      const Eigen::Vector3d centroid = (surface.vertices[static_cast<std::size_t>(face[0])] +
                                        surface.vertices[static_cast<std::size_t>(face[1])] +
                                        surface.vertices[static_cast<std::size_t>(face[2])]) / 3.0;
      c.centroids[static_cast<std::size_t>(f)] = centroid;
      if (c.tree.nearestKSearch(toPoint(centroid), 1, index, squared) == 1 && std::sqrt(double(squared[0])) > c.far_limit)
        c.far[static_cast<std::size_t>(f)] = 1;
    }
  }
  (void)threads;  // without OpenMP
  std::vector<Gap> gaps;
  for (auto& region : flaggedFaceRegions(surface, c.far))
    if (static_cast<int>(region.size()) >= c.parameters.min_gap_faces)
      gaps.push_back(Gap{std::move(region)});
  report.gaps = gaps.size();
  return gaps;
}

/// Density of the input: neighbours within 4 s of an evenly spaced sample of points; and the
/// spacing of a hexagonal lattice of the same density.
void measureDensity(Completion& c, CloudCompletionReport& report)
{
  {
    const std::size_t stride = std::max<std::size_t>(1, c.points.size() / 2000);
    const double radius = 4.0 * c.spacing;
    double count = 0.0;
    std::size_t sampled = 0;
    pcl::Indices index;
    std::vector<float> squared;
    for (std::size_t i = 0; i < c.points.size(); i += stride, ++sampled)
      count += static_cast<double>(c.tree.radiusSearch((*c.positions)[i], radius, index, squared)) - 1.0;
    report.density = count / static_cast<double>(sampled) / (M_PI * radius * radius);
  }
  if (!(report.density > 0.0))
    throw Error("cloud completion: the points have no neighbours within 4 spacings");
  c.density = report.density;
  // A hexagonal lattice of the same density: 2 / (√3 a²) points per unit area.
  c.a = std::sqrt(2.0 / (std::sqrt(3.0) * report.density));
  report.lattice_spacing = c.a;
}

// 3. Each hole: the implicit or the spline through its rim, sampled at the input's density.

/// One gap's extent, its Poisson faces and the input points around it.
struct GapGeometry {
  double area = 0.0, radius = 0.0, rim_reach = 0.0;
  Eigen::Vector3d centre = Eigen::Vector3d::Zero(), normal_sum = Eigen::Vector3d::Zero();
  TriangleMesh part;  // the gap's Poisson faces
  pcl::search::KdTree<pcl::PointXYZ> gap_tree_3d{false};  // over the gap faces' centroids
  std::vector<std::size_t> rim_3d;
};

/// Area, centre, summed normal and radius of the gap; false for a gap without area.
bool measureGap(const Completion& c, const Gap& gap, GapGeometry& geo)
{
  const TriangleMesh& surface = c.surface;
  for (const std::int32_t f : gap.faces) {
    const Face& face = surface.faces[static_cast<std::size_t>(f)];
    const Eigen::Vector3d& p0 = surface.vertices[static_cast<std::size_t>(face[0])];
    const Eigen::Vector3d n = (surface.vertices[static_cast<std::size_t>(face[1])] - p0)
                                  .cross(surface.vertices[static_cast<std::size_t>(face[2])] - p0);
    const double face_area = 0.5 * n.norm();
    geo.area += face_area;
    geo.centre += face_area * c.centroids[static_cast<std::size_t>(f)];
    geo.normal_sum += 0.5 * n;
  }
  if (!(geo.area > 0.0))
    return false;
  geo.centre /= geo.area;
  for (const std::int32_t f : gap.faces)
    for (int k = 0; k < 3; ++k)
      geo.radius = std::max(geo.radius, (surface.vertices[static_cast<std::size_t>(surface.faces[static_cast<std::size_t>(f)][k])] - geo.centre).norm());
  return true;
}

/// The gap's faces, in a mesh of their own and in 3D for the rim: points near them (not merely near
/// the centre: another sheet of a folded surface can pass close by), whichever way they face.
void findRim(const Completion& c, const Gap& gap, GapGeometry& geo)
{
  for (const std::int32_t f : gap.faces)
    appendFace(c.surface, static_cast<std::size_t>(f), geo.part);
  auto gap_faces_3d = std::make_shared<pcl::PointCloud<pcl::PointXYZ>>();
  for (const std::int32_t f : gap.faces)
    gap_faces_3d->push_back(toPoint(c.centroids[static_cast<std::size_t>(f)]));
  geo.gap_tree_3d.setInputCloud(gap_faces_3d);
  geo.rim_reach = c.far_limit + c.parameters.rim_width * geo.radius + 2.0 * c.spacing;
  // The rim in 3D: every point near the gap's faces, whichever way it faces (index order).
  pcl::Indices found, nearest(1);
  std::vector<float> found_squared, nearest_squared(1);
  c.tree.radiusSearch(toPoint(geo.centre), geo.radius + geo.rim_reach, found, found_squared);
  std::sort(found.begin(), found.end());
  for (const auto i : found)
    if (geo.gap_tree_3d.nearestKSearch((*c.positions)[static_cast<std::size_t>(i)], 1, nearest, nearest_squared) == 1 &&
        std::sqrt(double(nearest_squared[0])) < geo.rim_reach)
      geo.rim_3d.push_back(static_cast<std::size_t>(i));
}

// Where no surface fits — too thin a rim, a singular system, or (height field) a gap that is not
// roughly flat — the Poisson surface itself is sampled at the input's density.
void fillFromPoisson(const Completion& c, const GapGeometry& geo, std::size_t g, HoleFill& fill)
{
  const TriangleMesh& part = geo.part;
  const auto count = static_cast<std::size_t>(std::llround(c.density * geo.area));
  if (count == 0)
    return;
  const SurfaceSamples samples = sampleSurfaceUniform(part, count, static_cast<std::uint64_t>(g) + 1);
  pcl::Indices nearest(1);
  std::vector<float> nearest_squared(1);
  for (std::size_t k = 0; k < samples.points.size(); ++k) {
    const Face& face = part.faces[static_cast<std::size_t>(samples.face_ids[k])];
    const Eigen::Vector3d normal = (part.vertices[static_cast<std::size_t>(face[1])] - part.vertices[static_cast<std::size_t>(face[0])])
                                       .cross(part.vertices[static_cast<std::size_t>(face[2])] - part.vertices[static_cast<std::size_t>(face[0])]);
    if (c.tree.nearestKSearch(toPoint(samples.points[k]), 1, nearest, nearest_squared) != 1 || !(normal.norm() > 0.0))
      continue;
    fill.points.push_back(samples.points[k]);
    fill.normals.push_back(normal.normalized());
    fill.sources.push_back(static_cast<std::size_t>(nearest[0]));
  }
}

/// At most implicit_points of the rim, spread in space (duplicates and near-duplicates make the
/// system singular or ill-conditioned): one point per cell of a grid whose cell grows until few
/// enough are left, starting at half a spacing.
std::vector<std::size_t> spreadRim(const Completion& c, const GapGeometry& geo)
{
  std::vector<std::size_t> kept;
  for (double cell = 0.5 * c.spacing;; cell *= 1.25) {
    kept.clear();
    std::unordered_map<std::int64_t, char> taken;
    for (const std::size_t j : geo.rim_3d)
      if (taken.emplace(cellKey(c.points[j], cell), 1).second)
        kept.push_back(j);
    if (kept.size() <= static_cast<std::size_t>(c.parameters.implicit_points))
      break;
  }
  return kept;
}

/// Seeds: the gap's faces and the Poisson faces around it up to the lattice's reach (the gap stops
/// gap_factor × s short of the data; the clearance test keeps the data's own). Returns their area.
double implicitSeeds(const Completion& c, const GapGeometry& geo, TriangleMesh& seeds)
{
  pcl::Indices nearest_face(1);
  std::vector<float> nearest_squared(1);
  seeds = geo.part;
  double seed_area = geo.area;
  const double reach = c.far_limit + c.parameters.rim_reach * c.a;
  pcl::Indices around;
  std::vector<float> around_squared;
  c.centroid_tree.radiusSearch(toPoint(geo.centre), 1.01 * (geo.radius + reach), around, around_squared);
  std::sort(around.begin(), around.end());
  for (const auto index_f : around) {
    const auto f = static_cast<std::size_t>(index_f);
    if (c.far[f] || (c.centroids[f] - geo.centre).norm() > geo.radius + reach)
      continue;
    if (geo.gap_tree_3d.nearestKSearch(toPoint(c.centroids[f]), 1, nearest_face, nearest_squared) != 1 ||
        std::sqrt(double(nearest_squared[0])) > reach)
      continue;
    appendFace(c.surface, f, seeds);
    const Eigen::Vector3d* v = &seeds.vertices[seeds.vertices.size() - 3];
    seed_area += 0.5 * (v[1] - v[0]).cross(v[2] - v[0]).norm();
  }
  return seed_area;
}

/// Whether p lies within min_distance of a point already in the fill (cells: of the fill's points).
bool crowded(const HoleFill& fill, const std::unordered_map<std::int64_t, std::vector<std::size_t>>& cells,
             const Eigen::Vector3d& p, double min_distance)
{
  bool near = false;
  for (int dx = -1; dx <= 1 && !near; ++dx)
    for (int dy = -1; dy <= 1 && !near; ++dy)
      for (int dz = -1; dz <= 1 && !near; ++dz) {
        const auto it = cells.find(cellKey(p, min_distance, dx, dy, dz));
        if (it != cells.end())
          for (const std::size_t k : it->second)
            if ((fill.points[k] - p).norm() < min_distance) {
              near = true;
              break;
            }
      }
  return near;
}

// The implicit: f = 0 through the rim with f = ±ε along the normals; Poisson's bridge over the gap,
// sampled densely, is moved onto f = 0 and thinned to the input's density.
bool fillFromImplicit(const Completion& c, const GapGeometry& geo, std::size_t g, HoleFill& fill)
{
  const CloudCompletionParameters& parameters = c.parameters;
  const std::vector<std::size_t> kept = spreadRim(c, geo);
  if (kept.size() < 10)
    return false;
  std::vector<Eigen::Vector3d> rim_points, rim_normals;
  for (const std::size_t j : kept) {
    rim_points.push_back(c.points[j]);
    rim_normals.push_back(c.normals[j]);
  }
  BiharmonicImplicit implicit;
  try {
    implicit.fit(rim_points, rim_normals, parameters.implicit_offset * c.spacing);
  } catch (const Error&) {
    return false;
  }
  TriangleMesh seeds;
  const double seed_area = implicitSeeds(c, geo, seeds);
  const auto samples_wanted = static_cast<std::size_t>(std::llround(parameters.oversampling * c.density * seed_area));
  if (samples_wanted == 0)
    return false;
  const SurfaceSamples samples = sampleSurfaceUniform(seeds, samples_wanted, static_cast<std::uint64_t>(g) + 1);
  const double min_distance = parameters.thinning * c.a;
  const double max_move = std::max(0.5 * geo.radius, 4.0 * c.spacing);
  pcl::Indices nearest_input(1);
  std::vector<float> input_squared(1);
  std::unordered_map<std::int64_t, std::vector<std::size_t>> cells;  // of the kept points
  for (const Eigen::Vector3d& sample : samples.points) {
    Eigen::Vector3d p = sample;
    if (!implicit.project(p, 1e-3 * c.spacing) || (p - sample).norm() > max_move)
      continue;
    if (c.tree.nearestKSearch(toPoint(p), 1, nearest_input, input_squared) != 1 ||
        std::sqrt(double(input_squared[0])) < parameters.clearance * c.a)
      continue;  // the data is there already
    if (crowded(fill, cells, p, min_distance))
      continue;
    Eigen::Vector3d gradient;
    implicit.valueAndGradient(p, gradient);
    if (!(gradient.norm() > 0.0))
      continue;
    cells[cellKey(p, min_distance)].push_back(fill.points.size());
    fill.points.push_back(p);
    fill.normals.push_back(gradient.normalized());  // f grows along the input's normals
    fill.sources.push_back(static_cast<std::size_t>(nearest_input[0]));
  }
  return !fill.points.empty();
}

// Auto: a flat gap whose rim points all face its way (one sheet) keeps the height field, which fills
// such holes as well or better (demosthenes, bunny); any other gets the implicit.
bool fillsAsHeightField(const Completion& c, const GapGeometry& geo)
{
  const CloudCompletionParameters& parameters = c.parameters;
  bool height_field = parameters.surface == CloudCompletionParameters::Surface::HeightField;
  if (parameters.surface == CloudCompletionParameters::Surface::Auto &&
      geo.normal_sum.norm() >= parameters.flatness * geo.area) {
    const Eigen::Vector3d mean_normal = geo.normal_sum.normalized();
    std::size_t facing = 0;
    for (const std::size_t j : geo.rim_3d)
      facing += c.normals[j].dot(mean_normal) > 0.3 ? 1 : 0;
    height_field = !geo.rim_3d.empty() &&
                   static_cast<double>(facing) >= parameters.single_sheet * static_cast<double>(geo.rim_3d.size());
  }
  return height_field;
}

/// The height field: a thin-plate spline over the gap's plane through the rim's heights, sampled on
/// the lattice; false (nothing added) when the rim is too thin or the spline cannot be fitted.
bool fillFromSpline(const Completion& c, const Gap& gap, const GapGeometry& geo, HoleFill& fill)
{
  const CloudCompletionParameters& parameters = c.parameters;
  const std::vector<Eigen::Vector3d>& points = c.points;
  const Eigen::Vector3d& centre = geo.centre;
  const double a = c.a;
  const Eigen::Vector3d n = geo.normal_sum.normalized();
  const Eigen::Vector3d e1 = n.unitOrthogonal(), e2 = n.cross(e1);
  const double rim_radius = (1.0 + parameters.rim_width) * geo.radius + 2.0 * c.spacing;
  // The spline's rim: the 3D rim's points near the centre, facing the gap's way.
  std::vector<std::size_t> rim;
  for (const std::size_t j : geo.rim_3d)
    if ((points[j] - centre).norm() <= rim_radius && c.normals[j].dot(n) > 0.3 &&
        std::abs((points[j] - centre).dot(n)) < rim_radius)
      rim.push_back(j);
  pcl::Indices index;
  std::vector<float> squared;
  if (rim.size() < 10)
    return false;
  const std::size_t stride = (rim.size() + static_cast<std::size_t>(parameters.max_rim_points) - 1) /
                             static_cast<std::size_t>(parameters.max_rim_points);
  std::vector<Eigen::Vector2d> sites;
  std::vector<double> heights;
  for (std::size_t k = 0; k < rim.size(); k += stride) {
    const Eigen::Vector3d d = points[rim[k]] - centre;
    sites.emplace_back(d.dot(e1), d.dot(e2));
    heights.push_back(d.dot(n));
  }
  ThinPlateSpline spline;
  try {
    spline.fit(sites, heights, parameters.smoothing);
  } catch (const Error&) {
    return false;
  }
  // Gap faces near a lattice point in the plane: the point is over the hole (in the plane, so that
  // where Poisson's bridge and the spline part ways the hole is still filled).
  auto gap_cloud = std::make_shared<pcl::PointCloud<pcl::PointXYZ>>();
  for (const std::int32_t f : gap.faces) {
    const Eigen::Vector3d d = c.centroids[static_cast<std::size_t>(f)] - centre;
    gap_cloud->push_back(pcl::PointXYZ(static_cast<float>(d.dot(e1)), static_cast<float>(d.dot(e2)), 0.0f));
  }
  pcl::search::KdTree<pcl::PointXYZ> gap_tree(false);
  gap_tree.setInputCloud(gap_cloud);
  const double reach = geo.radius + c.far_limit + parameters.rim_reach * a;
  const double row = a * std::sqrt(3.0) / 2.0;
  for (int r = static_cast<int>(-std::ceil(reach / row)); r * row <= reach; ++r)
    for (int col = static_cast<int>(-std::ceil(reach / a)) - 1; col * a <= reach; ++col) {
      const Eigen::Vector2d uv(col * a + ((r & 1) ? 0.5 * a : 0.0), r * row);
      if (uv.norm() > reach)
        continue;
      const double h = spline(uv);
      if (!std::isfinite(h) || std::abs(h) > rim_radius)
        continue;
      const Eigen::Vector3d p = centre + uv.x() * e1 + uv.y() * e2 + h * n;
      if (gap_tree.nearestKSearch(pcl::PointXYZ(static_cast<float>(uv.x()), static_cast<float>(uv.y()), 0.0f), 1,
                                  index, squared) != 1 ||
          std::sqrt(double(squared[0])) > c.far_limit + parameters.rim_reach * a)
        continue;
      if (c.tree.nearestKSearch(toPoint(p), 1, index, squared) != 1 ||
          std::sqrt(double(squared[0])) < parameters.clearance * a)
        continue;
      const Eigen::Vector2d slope = spline.gradient(uv);
      fill.points.push_back(p);
      fill.normals.push_back((n - slope.x() * e1 - slope.y() * e2).normalized());
      fill.sources.push_back(static_cast<std::size_t>(index[0]));
    }
  return true;
}

void fillHole(const Completion& c, const Gap& gap, std::size_t g, HoleFill& fill)
{
  GapGeometry geo;
  if (!measureGap(c, gap, geo))
    return;
  if (2.0 * geo.radius > c.max_diameter) {
    fill.outcome = HoleFill::Outcome::TooLarge;
    return;
  }
  findRim(c, gap, geo);
  if (!fillsAsHeightField(c, geo)) {
    if (fillFromImplicit(c, geo, g, fill))
      fill.outcome = HoleFill::Outcome::FilledImplicit;
    else
      fillFromPoisson(c, geo, g, fill);
    return;
  }
  if (geo.normal_sum.norm() < c.parameters.flatness * geo.area) {
    fillFromPoisson(c, geo, g, fill);
    return;
  }
  if (fillFromSpline(c, gap, geo, fill))
    fill.outcome = HoleFill::Outcome::Filled;
  else
    fillFromPoisson(c, geo, g, fill);
}

}  // namespace

void completeCloudHoles(const std::vector<Eigen::Vector3d>& points, const std::vector<Eigen::Vector3d>& normals,
                        double spacing, const CloudCompletionParameters& parameters,
                        std::vector<Eigen::Vector3d>& added, std::vector<Eigen::Vector3d>& added_normals,
                        std::vector<std::size_t>& added_source, CloudCompletionReport& report)
{
  checkParameters(points, normals, spacing, parameters);
  int threads = 1;
#ifdef _OPENMP
  threads = parameters.num_threads > 0 ? parameters.num_threads : omp_get_max_threads();
#endif
  added.clear();
  added_normals.clear();
  added_source.clear();
  report = CloudCompletionReport{};
  Completion c(points, normals, spacing, parameters);

  auto start = Clock::now();
  poissonSurface(c, report);
  report.seconds_poisson = secondsSince(start);

  start = Clock::now();
  const std::vector<Gap> gaps = findGaps(c, threads, report);
  measureDensity(c, report);
  report.seconds_gaps = secondsSince(start);

  start = Clock::now();
  // All face centroids, to find the faces around a gap without a pass over the whole surface each.
  auto centroid_cloud = std::make_shared<pcl::PointCloud<pcl::PointXYZ>>();
  for (const Eigen::Vector3d& centroid : c.centroids)
    centroid_cloud->push_back(toPoint(centroid));
  if (!gaps.empty())
    c.centroid_tree.setInputCloud(centroid_cloud);
  std::vector<HoleFill> fills(gaps.size());
  const auto ng = static_cast<std::ptrdiff_t>(gaps.size());
#pragma omp parallel for schedule(dynamic, 1) num_threads(threads)
  for (std::ptrdiff_t g = 0; g < ng; ++g)
    fillHole(c, gaps[static_cast<std::size_t>(g)], static_cast<std::size_t>(g), fills[static_cast<std::size_t>(g)]);
  for (HoleFill& fill : fills) {
    switch (fill.outcome) {
    case HoleFill::Outcome::Filled: ++report.holes_filled; break;
    case HoleFill::Outcome::FilledImplicit:
      ++report.holes_filled;
      ++report.holes_implicit;
      break;
    case HoleFill::Outcome::TooLarge: ++report.holes_too_large; break;
    case HoleFill::Outcome::FilledFromPoisson: ++report.holes_from_poisson; break;
    }
    added.insert(added.end(), fill.points.begin(), fill.points.end());
    added_normals.insert(added_normals.end(), fill.normals.begin(), fill.normals.end());
    added_source.insert(added_source.end(), fill.sources.begin(), fill.sources.end());
  }
  report.points_added = added.size();
  report.seconds_fill = secondsSince(start);
}

}  // namespace patchdict
}  // namespace pcl
