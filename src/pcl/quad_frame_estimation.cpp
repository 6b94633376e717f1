// QuadFrameEstimation: its type-free core (layPatches, the tool's placement, in the input's units)
// and the explicit instantiations for PCL's common point types.
#include <pcl_patchdict/pcl/impl/quad_frame_estimation.hpp>
#include <pcl_patchdict/pcl/quad_frame_estimation.h>

#include <pcl_patchdict/core/error.h>
#include <pcl_patchdict/core/normalization.h>
#include <pcl_patchdict/geometry/coarse_mesh_estimation.h>
#include <pcl_patchdict/geometry/mesh_hygiene.h>
#include <pcl_patchdict/patches/patch_seeds.h>

#include <pcl/conversions.h>

#include <chrono>
#include <cmath>
#include <string>

namespace pcl {
namespace patchdict {
namespace detail {

namespace {

constexpr double kDefaultQuadLength = 0.03;  // in the unit cube, the tool's default

void fillReport(const PatchLayout& layout, QuadFrameReport& report)
{
  const QuadMeshStatistics stats = computeQuadMeshStatistics(layout.quads);
  report.coarse_faces = layout.coarse.faces.size();
  report.quad_faces = stats.faces;
  report.quads = stats.quads;
  report.singularities = layout.quad_report.orientation_singularities;
  report.seeds = layout.seeds.size();
  report.coverage_seeds = layout.coverage_seeds;
  report.seconds_coarse = layout.seconds_coarse;
  report.seconds_quads = layout.seconds_quads;
  report.seconds_frames = layout.seconds_frames;
}

}  // namespace

void estimateQuadFrames(const TriangleMesh& input, const PatchLayoutParameters& parameters, PatchLayout& layout,
                        QuadFrameReport& report)
{
  report = QuadFrameReport();
  layout = PatchLayout();
  if (!(parameters.quad_length >= 0.0) || !std::isfinite(parameters.quad_length))
    throw Error("QuadFrameEstimation: the quad length must be finite and ≥ 0 (0: automatic), not " +
                std::to_string(parameters.quad_length));
  report.from_cloud = input.faces.empty();
  report.input_points = input.vertices.size();
  if (report.from_cloud && input.vertices.size() < CoarseMeshEstimation::getMinimumPoints())
    throw Error("QuadFrameEstimation: the cloud has " + std::to_string(input.vertices.size()) +
                " finite points, fewer than " + std::to_string(CoarseMeshEstimation::getMinimumPoints()));
  TriangleMesh surface = input;
  if (!report.from_cloud) {
    cleanMesh(surface);
    if (surface.faces.empty())
      throw Error("QuadFrameEstimation: every face of the mesh is degenerate: there is no surface");
  }
  const UnitCubeNormalization unit = UnitCubeNormalization::fromMesh(surface);
  unit.apply(surface);
  PatchLayoutParameters in_unit_cube = parameters;
  in_unit_cube.quad_length = parameters.quad_length > 0.0 ? unit.applyLength(parameters.quad_length)
                                                          : kDefaultQuadLength;
  // The tool's placement, the library's one entry point: on the mesh, or on a cloud's Poisson surface.
  PatchPlacementReport placement;
  layout = layPatches(surface, in_unit_cube, SeedPlacement::Quads, &placement);
  report.normals_given = placement.normals_given;
  report.poisson_depth = placement.poisson_depth;
  report.seconds_surface = placement.seconds_surface;
  report.surface_faces = placement.surface_faces;
  fillReport(layout, report);

  // Back to the input's coordinates: positions and lengths; frames are rotations, unchanged.
  for (auto& seed : layout.seeds)
    seed = unit.invert(seed);
  unit.invert(layout.coarse);
  for (auto& vertex : layout.quads.vertices)
    vertex = unit.invert(vertex);
  layout.quad_length = unit.invertLength(layout.quad_length);
  layout.mean_seed_shift = unit.invertLength(layout.mean_seed_shift);
  report.quad_length = layout.quad_length;
  report.mean_seed_shift = layout.mean_seed_shift;
}

void quadMeshToPolygonMesh(const QuadMesh& quads, pcl::PolygonMesh& out)
{
  pcl::PointCloud<pcl::PointXYZ> vertices;
  vertices.resize(quads.vertices.size());
  for (std::size_t v = 0; v < quads.vertices.size(); ++v)
    vertices[v].getVector3fMap() = quads.vertices[v].cast<float>();
  vertices.width = static_cast<std::uint32_t>(vertices.size());
  vertices.height = 1;
  pcl::toPCLPointCloud2(vertices, out.cloud);
  out.polygons.clear();
  out.polygons.reserve(quads.faces.size());
  for (const auto& face : quads.faces) {
    pcl::Vertices polygon;
    polygon.vertices.assign(face.begin(), face.end());
    out.polygons.push_back(std::move(polygon));
  }
}

}  // namespace detail

template class QuadFrameEstimation<pcl::PointXYZ>;
template class QuadFrameEstimation<pcl::PointNormal>;
template class QuadFrameEstimation<pcl::PointXYZRGBNormal>;

}  // namespace patchdict
}  // namespace pcl
