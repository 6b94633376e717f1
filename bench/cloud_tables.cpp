// Issue 11's point-cloud tables, self-contained (the protocol of the harness, made here):
//  denoise — 100k area-uniform samples of the unit-cube mesh, moved along the face normal by
//            N(0, (k s)²), s their mean nearest-neighbour spacing, plus 1 % outliers uniform in the
//            bounding box; scored by the RMS distance of every output point to the mesh, against
//            PCL's StatisticalOutlierRemoval (50, 1.0) + MovingLeastSquares (order 2, Gaussian r²)
//            at each radius of a sweep (the best one is the oracle);
//  holes   — the clean samples minus 12 discs of radius 0.035 (centres: random samples); coverage =
//            share of the removed samples with an output point within 1.5 s, inside = mean distance
//            to the mesh of the new points, against pcl::Poisson (depth 8) resampled at the input's
//            density inside the discs; for the holes rows, "parameter" counts the added points elsewhere
//            (openings of the mesh itself that are narrower than the hole limit).
// usage: cloud_tables MESH... [--noise 0.5,1] [--radii 3,4,6,8,10,12] [--threads T] [--csv FILE]
#include <pcl_patchdict/geometry/metrics.h>
#include <pcl_patchdict/io/mesh_io.h>
#include <pcl_patchdict/core/normalization.h>
#include <pcl_patchdict/cloud/geometric_cloud_repair.h>
#include <pcl_patchdict/core/surface_sampling.h>
#include <pcl_patchdict/pcl/conversions.h>

#include <pcl/filters/statistical_outlier_removal.h>
#include <pcl/search/kdtree.h>
#include <pcl/surface/mls.h>
#include <pcl/surface/poisson.h>
#include <pcl/conversions.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#ifdef _OPENMP
#include <omp.h>
#endif

using namespace pcl::patchdict;
using Cloud = pcl::PointCloud<pcl::PointXYZ>;

namespace {

std::vector<double> parseList(const std::string& text)
{
  std::vector<double> values;
  std::stringstream stream(text);
  std::string item;
  while (std::getline(stream, item, ','))
    values.push_back(std::stod(item));
  return values;
}

double seconds(std::chrono::steady_clock::time_point start)
{
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

std::vector<Eigen::Vector3d> positions(const Cloud& cloud)
{
  std::vector<Eigen::Vector3d> out;
  for (const auto& p : cloud)
    if (std::isfinite(p.x))
      out.emplace_back(p.x, p.y, p.z);
  return out;
}

double rmsDistance(const PointToMeshDistance& distance, const Cloud& cloud)
{
  const std::vector<double> d = distance.distances(positions(cloud));
  double sum = 0.0;
  for (const double x : d)
    sum += x * x;
  return d.empty() ? 0.0 : std::sqrt(sum / static_cast<double>(d.size()));
}

double meanSpacing(const Cloud::Ptr& cloud)
{
  pcl::search::KdTree<pcl::PointXYZ> tree;
  tree.setInputCloud(cloud);
  double sum = 0.0;
  pcl::Indices index;
  std::vector<float> squared;
  for (const auto& p : *cloud) {
    tree.nearestKSearch(p, 2, index, squared);
    sum += std::sqrt(double(squared[1]));
  }
  return sum / static_cast<double>(cloud->size());
}

/** The table's rows, printed and optionally written to a CSV file. */
struct Table {
  std::ofstream csv;
  void row(const std::string& mesh, const std::string& what, const std::string& method, double parameter, double rms,
           std::size_t points, double coverage, double inside, double secs)
  {
    std::printf("%-12s %-16s %-10s %6.2f  rms %.3f  points %7zu  cov %5.1f  inside %.3f  %.2f s\n", mesh.c_str(),
                what.c_str(), method.c_str(), parameter, rms * 1e3, points, coverage, inside * 1e3, secs);
    if (csv)
      csv << mesh << ',' << what << ',' << method << ',' << parameter << ',' << rms * 1e3 << ',' << points << ','
          << coverage << ',' << inside * 1e3 << ',' << secs << '\n';
  }
};

/** One mesh in the unit cube, its clean samples with their face normals and their mean spacing. */
struct MeshCase {
  std::string name;
  TriangleMesh mesh;
  SurfaceSamples samples;
  std::vector<Eigen::Vector3d> normals;
  double s = 0.0;  ///< mean nearest-neighbour spacing of the samples
  Eigen::Vector3d low, high;
};

MeshCase loadCase(const std::string& path)
{
  MeshCase c;
  readMesh(path, c.mesh);
  UnitCubeNormalization::fromMesh(c.mesh).apply(c.mesh);
  c.name = path.substr(path.find_last_of('/') + 1);
  c.samples = sampleSurfaceUniform(c.mesh, 100000, 1);
  for (const auto f : c.samples.face_ids) {
    const Face& face = c.mesh.faces[static_cast<std::size_t>(f)];
    const Eigen::Vector3d& a = c.mesh.vertices[static_cast<std::size_t>(face[0])];
    c.normals.push_back((c.mesh.vertices[static_cast<std::size_t>(face[1])] - a)
                            .cross(c.mesh.vertices[static_cast<std::size_t>(face[2])] - a)
                            .normalized());
  }
  Cloud::Ptr clean(new Cloud);
  for (const auto& p : c.samples.points)
    clean->push_back(pcl::PointXYZ(float(p.x()), float(p.y()), float(p.z())));
  c.s = meanSpacing(clean);
  c.low = c.mesh.vertices.front();
  c.high = c.low;
  for (const auto& v : c.mesh.vertices) {
    c.low = c.low.cwiseMin(v);
    c.high = c.high.cwiseMax(v);
  }
  return c;
}

/** Denoise rows at noise level k: ours, then SOR + MLS at every radius of the sweep. */
void denoiseRows(const MeshCase& c, const PointToMeshDistance& distance, double k, const std::vector<double>& radii,
                 Table& table)
{
  const double s = c.s;
  std::mt19937_64 rng(static_cast<std::uint64_t>(1000 * k) + 7);
  std::normal_distribution<double> gauss(0.0, k * s);
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  Cloud::Ptr noisy(new Cloud);
  for (std::size_t i = 0; i < c.samples.points.size(); ++i) {
    const Eigen::Vector3d p = c.samples.points[i] + gauss(rng) * c.normals[i];
    noisy->push_back(pcl::PointXYZ(float(p.x()), float(p.y()), float(p.z())));
  }
  for (int i = 0; i < 1000; ++i) {
    const Eigen::Vector3d p = c.low + Eigen::Vector3d(uniform(rng), uniform(rng), uniform(rng)).cwiseProduct(c.high - c.low);
    noisy->push_back(pcl::PointXYZ(float(p.x()), float(p.y()), float(p.z())));
  }
  const std::string what = "noise " + std::to_string(k).substr(0, 4);
  auto start = std::chrono::steady_clock::now();
  GeometricCloudRepair<pcl::PointXYZ> ours;
  ours.setInputCloud(noisy);
  Cloud denoised;
  ours.process(denoised);
  table.row(c.name, what, "patches", ours.getReport().bandwidth / s, rmsDistance(distance, denoised), denoised.size(),
            0, 0, seconds(start));
  start = std::chrono::steady_clock::now();
  Cloud::Ptr filtered(new Cloud);
  pcl::StatisticalOutlierRemoval<pcl::PointXYZ> sor;
  sor.setInputCloud(noisy);
  sor.setMeanK(50);
  sor.setStddevMulThresh(1.0);
  sor.filter(*filtered);
  const double sor_seconds = seconds(start);
  for (const double r : radii) {
    start = std::chrono::steady_clock::now();
    pcl::MovingLeastSquares<pcl::PointXYZ, pcl::PointXYZ> mls;
    mls.setInputCloud(filtered);
    mls.setSearchMethod(pcl::search::KdTree<pcl::PointXYZ>::Ptr(new pcl::search::KdTree<pcl::PointXYZ>));
    mls.setPolynomialOrder(2);
    mls.setSearchRadius(r * s);
    mls.setSqrGaussParam(r * s * r * s);
    Cloud smoothed;
    mls.process(smoothed);
    table.row(c.name, what, "sor+mls", r, rmsDistance(distance, smoothed), smoothed.size(), 0, 0,
              sor_seconds + seconds(start));
  }
}

/** The holes case: 12 discs of radius 0.035 around random samples, their samples removed. */
struct HolesCase {
  std::vector<Eigen::Vector3d> centres, removed;
  pcl::PointCloud<pcl::PointNormal>::Ptr holed{new pcl::PointCloud<pcl::PointNormal>};

  bool inDisc(const Eigen::Vector3d& p, double margin) const
  {
    bool inside = false;
    for (const auto& c : centres)
      inside = inside || (p - c).norm() < 0.035 + margin;
    return inside;
  }
};

HolesCase punchHoles(const MeshCase& c)
{
  HolesCase h;
  std::mt19937_64 rng(99);
  std::uniform_int_distribution<std::size_t> pick(0, c.samples.points.size() - 1);
  for (int k = 0; k < 12; ++k)
    h.centres.push_back(c.samples.points[pick(rng)]);
  for (std::size_t i = 0; i < c.samples.points.size(); ++i) {
    if (h.inDisc(c.samples.points[i], 0.0)) {
      h.removed.push_back(c.samples.points[i]);
      continue;
    }
    pcl::PointNormal p;
    p.getVector3fMap() = c.samples.points[i].cast<float>();
    p.getNormalVector3fMap() = c.normals[i].cast<float>();
    h.holed->push_back(p);
  }
  return h;
}

/** One holes row: coverage of the removed samples by `out`; inside = mean distance to the mesh of
  * the added points over the discs (within 3 s of one); the others fill openings the mesh has
  * itself (a scan's own small holes), reported apart as the parameter. */
void holesRow(const MeshCase& c, const PointToMeshDistance& distance, const HolesCase& h,
              const std::vector<Eigen::Vector3d>& out, const std::vector<Eigen::Vector3d>& added,
              const std::string& method, double secs, Table& table)
{
  const double s = c.s;
  Cloud::Ptr all(new Cloud);
  for (const auto& p : out)
    all->push_back(pcl::PointXYZ(float(p.x()), float(p.y()), float(p.z())));
  pcl::search::KdTree<pcl::PointXYZ> tree;
  tree.setInputCloud(all);
  std::size_t covered = 0;
  pcl::Indices index;
  std::vector<float> squared;
  for (const auto& r : h.removed) {
    tree.nearestKSearch(pcl::PointXYZ(float(r.x()), float(r.y()), float(r.z())), 1, index, squared);
    covered += std::sqrt(double(squared[0])) < 1.5 * s ? 1 : 0;
  }
  std::vector<Eigen::Vector3d> over_discs;
  for (const auto& p : added)
    if (h.inDisc(p, 3.0 * s))
      over_discs.push_back(p);
  double inside = 0.0;
  const std::vector<double> d = over_discs.empty() ? std::vector<double>{} : distance.distances(over_discs);
  for (const double x : d)
    inside += x;
  table.row(c.name, "holes 0.035", method, static_cast<double>(added.size() - over_discs.size()), 0,
            over_discs.size(), 100.0 * covered / std::max<std::size_t>(1, h.removed.size()),
            d.empty() ? 0.0 : inside / static_cast<double>(d.size()), secs);
}

/** Holes rows: ours (completion), then Poisson (depth 8) resampled at the input's density inside
  * the discs (as if the holes were known). */
void holesRows(const MeshCase& c, const PointToMeshDistance& distance, Table& table)
{
  const HolesCase h = punchHoles(c);
  auto start = std::chrono::steady_clock::now();
  GeometricCloudRepair<pcl::PointNormal> completer;
  completer.setInputCloud(h.holed);
  completer.setMode(GeometricCloudRepair<pcl::PointNormal>::Mode::Complete);
  pcl::PointCloud<pcl::PointNormal> completed;
  completer.process(completed);
  std::vector<Eigen::Vector3d> out, added;
  for (std::size_t i = 0; i < completed.size(); ++i) {
    out.emplace_back(completed[i].x, completed[i].y, completed[i].z);
    if (i >= completer.getReport().output_points)
      added.push_back(out.back());
  }
  holesRow(c, distance, h, out, added, "patches", seconds(start), table);
  start = std::chrono::steady_clock::now();
  pcl::Poisson<pcl::PointNormal> poisson;
  poisson.setDepth(8);
  poisson.setInputCloud(h.holed);
  pcl::PolygonMesh polygons;
  poisson.reconstruct(polygons);
  TriangleMesh surface;
  fromPolygonMesh(polygons, surface);
  const double density = static_cast<double>(c.samples.points.size()) / c.mesh.surfaceArea();
  const SurfaceSamples resampled =
      sampleSurfaceUniform(surface, static_cast<std::size_t>(density * surface.surfaceArea()), 3);
  std::vector<Eigen::Vector3d> poisson_out, poisson_added;
  for (const auto& p : *h.holed)
    poisson_out.emplace_back(p.x, p.y, p.z);
  for (const auto& p : resampled.points)
    if (h.inDisc(p, 0.0)) {
      poisson_out.push_back(p);
      poisson_added.push_back(p);
    }
  holesRow(c, distance, h, poisson_out, poisson_added, "poisson8", seconds(start), table);
}

}  // namespace

int main(int argc, char** argv)
{
  std::vector<std::string> meshes;
  std::vector<double> levels{0.5, 1.0}, radii{3, 4, 6, 8, 10, 12};
  std::string csv_path;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--noise" && i + 1 < argc) levels = parseList(argv[++i]);
    else if (a == "--radii" && i + 1 < argc) radii = parseList(argv[++i]);
    else if (a == "--csv" && i + 1 < argc) csv_path = argv[++i];
#ifdef _OPENMP
    else if (a == "--threads" && i + 1 < argc) omp_set_num_threads(std::stoi(argv[++i]));
#endif
    else if (!a.empty() && a[0] == '-') {
      std::cerr << "usage: cloud_tables MESH... [--noise 0.5,1] [--radii 3,4,6,8,10,12] [--threads T] [--csv FILE]\n";
      return 2;
    }
    else meshes.push_back(a);
  }
  if (meshes.empty()) {
    std::cerr << "cloud_tables: no mesh given\n";
    return 2;
  }
  Table table;
  if (!csv_path.empty()) {
    table.csv.open(csv_path);
    table.csv << "mesh,case,method,parameter,rms_x1000,points,coverage_pct,inside_x1000,seconds\n";
  }
  for (const std::string& path : meshes) {
    const MeshCase c = loadCase(path);
    const PointToMeshDistance distance(c.mesh);
    for (const double k : levels)
      denoiseRows(c, distance, k, radii, table);
    holesRows(c, distance, table);
  }
  return 0;
}
