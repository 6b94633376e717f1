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

}  // namespace

void completeCloudHoles(const std::vector<Eigen::Vector3d>& points, const std::vector<Eigen::Vector3d>& normals,
                        double spacing, const CloudCompletionParameters& parameters,
                        std::vector<Eigen::Vector3d>& added, std::vector<Eigen::Vector3d>& added_normals,
                        std::vector<std::size_t>& added_source, CloudCompletionReport& report)
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
#ifdef _OPENMP
  const int threads = parameters.num_threads > 0 ? parameters.num_threads : omp_get_max_threads();
#endif
  added.clear();
  added_normals.clear();
  added_source.clear();
  report = CloudCompletionReport{};

  // 1. The untrimmed Poisson surface.
  auto start = Clock::now();
  auto cloud = std::make_shared<pcl::PointCloud<pcl::PointNormal>>();
  auto positions = std::make_shared<pcl::PointCloud<pcl::PointXYZ>>();
  Eigen::Vector3d low = points.front(), high = points.front();
  for (std::size_t i = 0; i < points.size(); ++i) {
    pcl::PointNormal p;
    p.getVector3fMap() = points[i].cast<float>();
    p.getNormalVector3fMap() = normals[i].cast<float>();
    cloud->push_back(p);
    positions->push_back(toPoint(points[i]));
    low = low.cwiseMin(points[i]);
    high = high.cwiseMax(points[i]);
  }
  const double max_diameter =
      parameters.max_hole_diameter > 0.0 ? parameters.max_hole_diameter : 0.15 * (high - low).maxCoeff();
  CoarseMeshEstimation poisson;
  poisson.setInputCloud(cloud);
  poisson.setTrimFactor(0.0);
  poisson.setIterations(0);
  // Poisson only finds the gaps here (the fill is the spline's): cells of up to 4 s suffice, and each
  // level deeper costs several times more (boot, 95k points, 2 cores shared with a build: depth 9
  // 28 s, depth 8 12 s).
  int depth = parameters.poisson_depth;
  if (depth == 0) {
    const double side = 1.1 * (high - low).maxCoeff();
    depth = 5;
    while (depth < 10 && side / std::ldexp(1.0, depth) > 4.0 * spacing)
      ++depth;
  }
  poisson.setPoissonDepth(depth);
  TriangleMesh surface;
  CoarseMeshEstimation::Report poisson_report;
  poisson.process(surface, &poisson_report);
  report.poisson_depth = poisson_report.poisson_depth;
  report.poisson_faces = surface.faces.size();
  report.seconds_poisson = secondsSince(start);

  // 2. Gaps: far faces, in edge-connected regions.
  start = Clock::now();
  pcl::search::KdTree<pcl::PointXYZ> tree(true);
  tree.setInputCloud(positions);
  const auto nf = static_cast<std::ptrdiff_t>(surface.faces.size());
  std::vector<char> far(surface.faces.size(), 0);
  std::vector<Eigen::Vector3d> centroids(surface.faces.size());
  const double far_limit = parameters.gap_factor * spacing;
#pragma omp parallel num_threads(threads)
  {
    pcl::Indices index;
    std::vector<float> squared;
#pragma omp for schedule(dynamic, 1024)
    for (std::ptrdiff_t f = 0; f < nf; ++f) {
      const Face& face = surface.faces[static_cast<std::size_t>(f)];
      const Eigen::Vector3d c = (surface.vertices[static_cast<std::size_t>(face[0])] +
                                 surface.vertices[static_cast<std::size_t>(face[1])] +
                                 surface.vertices[static_cast<std::size_t>(face[2])]) / 3.0;
      centroids[static_cast<std::size_t>(f)] = c;
      if (tree.nearestKSearch(toPoint(c), 1, index, squared) == 1 && std::sqrt(double(squared[0])) > far_limit)
        far[static_cast<std::size_t>(f)] = 1;
    }
  }
  std::vector<Gap> gaps;
  for (auto& region : flaggedFaceRegions(surface, far))
    if (static_cast<int>(region.size()) >= parameters.min_gap_faces)
      gaps.push_back(Gap{std::move(region)});
  report.gaps = gaps.size();

  // Density of the input: neighbours within 4 s of an evenly spaced sample of points.
  {
    const std::size_t stride = std::max<std::size_t>(1, points.size() / 2000);
    const double radius = 4.0 * spacing;
    double count = 0.0;
    std::size_t sampled = 0;
    pcl::Indices index;
    std::vector<float> squared;
    for (std::size_t i = 0; i < points.size(); i += stride, ++sampled)
      count += static_cast<double>(tree.radiusSearch((*positions)[i], radius, index, squared)) - 1.0;
    report.density = count / static_cast<double>(sampled) / (M_PI * radius * radius);
  }
  if (!(report.density > 0.0))
    throw Error("cloud completion: the points have no neighbours within 4 spacings");
  // A hexagonal lattice of the same density: 2 / (√3 a²) points per unit area.
  const double a = std::sqrt(2.0 / (std::sqrt(3.0) * report.density));
  report.lattice_spacing = a;
  report.seconds_gaps = secondsSince(start);

  // 3. Each hole: the implicit or the spline through its rim, sampled at the input's density.
  start = Clock::now();
  // All face centroids, to find the faces around a gap without a pass over the whole surface each.
  auto centroid_cloud = std::make_shared<pcl::PointCloud<pcl::PointXYZ>>();
  for (const Eigen::Vector3d& c : centroids)
    centroid_cloud->push_back(toPoint(c));
  pcl::search::KdTree<pcl::PointXYZ> centroid_tree(false);
  if (!gaps.empty())
    centroid_tree.setInputCloud(centroid_cloud);
  std::vector<HoleFill> fills(gaps.size());
  const auto ng = static_cast<std::ptrdiff_t>(gaps.size());
#pragma omp parallel for schedule(dynamic, 1) num_threads(threads)
  for (std::ptrdiff_t g = 0; g < ng; ++g) {
    const Gap& gap = gaps[static_cast<std::size_t>(g)];
    HoleFill& fill = fills[static_cast<std::size_t>(g)];
    double area = 0.0;
    Eigen::Vector3d centre = Eigen::Vector3d::Zero(), normal_sum = Eigen::Vector3d::Zero();
    for (const std::int32_t f : gap.faces) {
      const Face& face = surface.faces[static_cast<std::size_t>(f)];
      const Eigen::Vector3d& p0 = surface.vertices[static_cast<std::size_t>(face[0])];
      const Eigen::Vector3d n = (surface.vertices[static_cast<std::size_t>(face[1])] - p0)
                                    .cross(surface.vertices[static_cast<std::size_t>(face[2])] - p0);
      const double face_area = 0.5 * n.norm();
      area += face_area;
      centre += face_area * centroids[static_cast<std::size_t>(f)];
      normal_sum += 0.5 * n;
    }
    if (!(area > 0.0))
      continue;
    centre /= area;
    double radius = 0.0;
    for (const std::int32_t f : gap.faces)
      for (int k = 0; k < 3; ++k)
        radius = std::max(radius, (surface.vertices[static_cast<std::size_t>(surface.faces[static_cast<std::size_t>(f)][k])] - centre).norm());
    if (2.0 * radius > max_diameter) {
      fill.outcome = HoleFill::Outcome::TooLarge;
      continue;
    }
    TriangleMesh part;  // the gap's Poisson faces
    for (const std::int32_t f : gap.faces)
      appendFace(surface, static_cast<std::size_t>(f), part);
    // The gap's faces in 3D, to find the rim: points near them (not merely near the centre: another
    // sheet of a folded surface can pass close by).
    auto gap_faces_3d = std::make_shared<pcl::PointCloud<pcl::PointXYZ>>();
    for (const std::int32_t f : gap.faces)
      gap_faces_3d->push_back(toPoint(centroids[static_cast<std::size_t>(f)]));
    pcl::search::KdTree<pcl::PointXYZ> gap_tree_3d(false);
    gap_tree_3d.setInputCloud(gap_faces_3d);
    const double rim_reach = far_limit + parameters.rim_width * radius + 2.0 * spacing;
    // Where no surface fits — too thin a rim, a singular system, or (height field) a gap that is
    // not roughly flat — the Poisson surface itself is sampled at the input's density.
    const auto fill_from_poisson = [&]() {
      const auto count = static_cast<std::size_t>(std::llround(report.density * area));
      if (count == 0)
        return;
      const SurfaceSamples samples = sampleSurfaceUniform(part, count, static_cast<std::uint64_t>(g) + 1);
      pcl::Indices nearest(1);
      std::vector<float> nearest_squared(1);
      for (std::size_t k = 0; k < samples.points.size(); ++k) {
        const Face& face = part.faces[static_cast<std::size_t>(samples.face_ids[k])];
        const Eigen::Vector3d normal = (part.vertices[static_cast<std::size_t>(face[1])] - part.vertices[static_cast<std::size_t>(face[0])])
                                           .cross(part.vertices[static_cast<std::size_t>(face[2])] - part.vertices[static_cast<std::size_t>(face[0])]);
        if (tree.nearestKSearch(toPoint(samples.points[k]), 1, nearest, nearest_squared) != 1 || !(normal.norm() > 0.0))
          continue;
        fill.points.push_back(samples.points[k]);
        fill.normals.push_back(normal.normalized());
        fill.sources.push_back(static_cast<std::size_t>(nearest[0]));
      }
    };
    // The rim in 3D: every point near the gap's faces, whichever way it faces (index order).
    std::vector<std::size_t> rim_3d;
    {
      pcl::Indices found, nearest(1);
      std::vector<float> found_squared, nearest_squared(1);
      tree.radiusSearch(toPoint(centre), radius + rim_reach, found, found_squared);
      std::sort(found.begin(), found.end());
      for (const auto i : found)
        if (gap_tree_3d.nearestKSearch((*positions)[static_cast<std::size_t>(i)], 1, nearest, nearest_squared) == 1 &&
            std::sqrt(double(nearest_squared[0])) < rim_reach)
          rim_3d.push_back(static_cast<std::size_t>(i));
    }
    // The implicit: f = 0 through the rim with f = ±ε along the normals; Poisson's bridge over the
    // gap, sampled densely, is moved onto f = 0 and thinned to the input's density.
    const auto fill_from_implicit = [&]() -> bool {
      pcl::Indices nearest_face(1);
      std::vector<float> nearest_squared(1);
      // At most implicit_points of the rim, spread in space (duplicates and near-duplicates make
      // the system singular or ill-conditioned): one point per cell of a grid whose cell grows
      // until few enough are left, starting at half a spacing.
      std::vector<std::size_t> kept;
      for (double cell = 0.5 * spacing;; cell *= 1.25) {
        kept.clear();
        std::unordered_map<std::int64_t, char> taken;
        for (const std::size_t j : rim_3d)
          if (taken.emplace(cellKey(points[j], cell), 1).second)
            kept.push_back(j);
        if (kept.size() <= static_cast<std::size_t>(parameters.implicit_points))
          break;
      }
      if (kept.size() < 10)
        return false;
      std::vector<Eigen::Vector3d> rim_points, rim_normals;
      for (const std::size_t j : kept) {
        rim_points.push_back(points[j]);
        rim_normals.push_back(normals[j]);
      }
      BiharmonicImplicit implicit;
      try {
        implicit.fit(rim_points, rim_normals, parameters.implicit_offset * spacing);
      } catch (const Error&) {
        return false;
      }
      // Seeds: the gap's faces and the Poisson faces around it up to the lattice's reach (the gap
      // stops gap_factor × s short of the data; the clearance test below keeps the data's own).
      TriangleMesh seeds = part;
      double seed_area = area;
      {
        const double reach = far_limit + parameters.rim_reach * a;
        pcl::Indices around;
        std::vector<float> around_squared;
        centroid_tree.radiusSearch(toPoint(centre), 1.01 * (radius + reach), around, around_squared);
        std::sort(around.begin(), around.end());
        for (const auto index_f : around) {
          const auto f = static_cast<std::size_t>(index_f);
          if (far[f] || (centroids[f] - centre).norm() > radius + reach)
            continue;
          if (gap_tree_3d.nearestKSearch(toPoint(centroids[f]), 1, nearest_face, nearest_squared) != 1 ||
              std::sqrt(double(nearest_squared[0])) > reach)
            continue;
          appendFace(surface, f, seeds);
          const Eigen::Vector3d* v = &seeds.vertices[seeds.vertices.size() - 3];
          seed_area += 0.5 * (v[1] - v[0]).cross(v[2] - v[0]).norm();
        }
      }
      const auto samples_wanted =
          static_cast<std::size_t>(std::llround(parameters.oversampling * report.density * seed_area));
      if (samples_wanted == 0)
        return false;
      const SurfaceSamples samples = sampleSurfaceUniform(seeds, samples_wanted, static_cast<std::uint64_t>(g) + 1);
      const double min_distance = parameters.thinning * a;
      const double max_move = std::max(0.5 * radius, 4.0 * spacing);
      pcl::Indices nearest_input(1);
      std::vector<float> input_squared(1);
      std::unordered_map<std::int64_t, std::vector<std::size_t>> cells;  // of the kept points
      for (const Eigen::Vector3d& sample : samples.points) {
        Eigen::Vector3d p = sample;
        if (!implicit.project(p, 1e-3 * spacing) || (p - sample).norm() > max_move)
          continue;
        if (tree.nearestKSearch(toPoint(p), 1, nearest_input, input_squared) != 1 ||
            std::sqrt(double(input_squared[0])) < parameters.clearance * a)
          continue;  // the data is there already
        bool crowded = false;
        for (int dx = -1; dx <= 1 && !crowded; ++dx)
          for (int dy = -1; dy <= 1 && !crowded; ++dy)
            for (int dz = -1; dz <= 1 && !crowded; ++dz) {
              const auto it = cells.find(cellKey(p, min_distance, dx, dy, dz));
              if (it != cells.end())
                for (const std::size_t k : it->second)
                  if ((fill.points[k] - p).norm() < min_distance) {
                    crowded = true;
                    break;
                  }
            }
        if (crowded)
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
    };
    // Auto: a flat gap whose rim points all face its way (one sheet) keeps the height field, which
    // fills such holes as well or better (demosthenes, bunny); any other gets the implicit.
    bool height_field = parameters.surface == CloudCompletionParameters::Surface::HeightField;
    if (parameters.surface == CloudCompletionParameters::Surface::Auto && normal_sum.norm() >= parameters.flatness * area) {
      const Eigen::Vector3d mean_normal = normal_sum.normalized();
      std::size_t facing = 0;
      for (const std::size_t j : rim_3d)
        facing += normals[j].dot(mean_normal) > 0.3 ? 1 : 0;
      height_field = !rim_3d.empty() &&
                     static_cast<double>(facing) >= parameters.single_sheet * static_cast<double>(rim_3d.size());
    }
    if (!height_field) {
      if (fill_from_implicit())
        fill.outcome = HoleFill::Outcome::FilledImplicit;
      else
        fill_from_poisson();
      continue;
    }
    if (normal_sum.norm() < parameters.flatness * area) {
      fill_from_poisson();
      continue;
    }
    const Eigen::Vector3d n = normal_sum.normalized();
    const Eigen::Vector3d e1 = n.unitOrthogonal(), e2 = n.cross(e1);
    const double rim_radius = (1.0 + parameters.rim_width) * radius + 2.0 * spacing;
    // The spline's rim: the 3D rim's points near the centre, facing the gap's way.
    std::vector<std::size_t> rim;
    for (const std::size_t j : rim_3d)
      if ((points[j] - centre).norm() <= rim_radius && normals[j].dot(n) > 0.3 &&
          std::abs((points[j] - centre).dot(n)) < rim_radius)
        rim.push_back(j);
    pcl::Indices index;
    std::vector<float> squared;
    if (rim.size() < 10) {
      fill_from_poisson();
      continue;
    }
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
      fill_from_poisson();
      continue;
    }
    // Gap faces near a lattice point in the plane: the point is over the hole (in the plane, so
    // that where Poisson's bridge and the spline part ways the hole is still filled).
    auto gap_cloud = std::make_shared<pcl::PointCloud<pcl::PointXYZ>>();
    for (const std::int32_t f : gap.faces) {
      const Eigen::Vector3d d = centroids[static_cast<std::size_t>(f)] - centre;
      gap_cloud->push_back(pcl::PointXYZ(static_cast<float>(d.dot(e1)), static_cast<float>(d.dot(e2)), 0.0f));
    }
    pcl::search::KdTree<pcl::PointXYZ> gap_tree(false);
    gap_tree.setInputCloud(gap_cloud);
    const double reach = radius + far_limit + parameters.rim_reach * a;
    const double row = a * std::sqrt(3.0) / 2.0;
    for (int r = static_cast<int>(-std::ceil(reach / row)); r * row <= reach; ++r)
      for (int c = static_cast<int>(-std::ceil(reach / a)) - 1; c * a <= reach; ++c) {
        const Eigen::Vector2d uv(c * a + ((r & 1) ? 0.5 * a : 0.0), r * row);
        if (uv.norm() > reach)
          continue;
        const double h = spline(uv);
        if (!std::isfinite(h) || std::abs(h) > rim_radius)
          continue;
        const Eigen::Vector3d p = centre + uv.x() * e1 + uv.y() * e2 + h * n;
        if (gap_tree.nearestKSearch(pcl::PointXYZ(static_cast<float>(uv.x()), static_cast<float>(uv.y()), 0.0f), 1,
                                    index, squared) != 1 ||
            std::sqrt(double(squared[0])) > far_limit + parameters.rim_reach * a)
          continue;
        if (tree.nearestKSearch(toPoint(p), 1, index, squared) != 1 ||
            std::sqrt(double(squared[0])) < parameters.clearance * a)
          continue;
        const Eigen::Vector2d slope = spline.gradient(uv);
        fill.points.push_back(p);
        fill.normals.push_back((n - slope.x() * e1 - slope.y() * e2).normalized());
        fill.sources.push_back(static_cast<std::size_t>(index[0]));
      }
    fill.outcome = HoleFill::Outcome::Filled;
  }
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
