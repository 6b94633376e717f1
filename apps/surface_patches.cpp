#include "surface_patches.h"

#include "cli.h"

#include <pcl_patchdict/geometry/coarse_mesh_estimation.h>
#include <pcl_patchdict/patches/height_maps.h>
#include <pcl_patchdict/geometry/mesh_hygiene.h>
#include <pcl_patchdict/core/normalization.h>
#include <pcl_patchdict/pcl/conversions.h>

#include <cmath>

namespace pcl {
namespace patchdict {
namespace cli {

SurfacePatches surfacePatches(const std::string& path, const SurfacePatchOptions& options, bool quiet,
                              StageTimer* timer)
{
  const auto stage = [timer](const char* name) {
    if (timer)
      timer->start(name);
  };
  stage("load");
  TriangleMesh surface = loadMesh(path, quiet);
  SurfacePatches out;
  out.is_cloud = surface.faces.empty();
  cleanInputMesh(surface, path);
  const UnitCubeNormalization normalization = UnitCubeNormalization::fromMesh(surface);
  normalization.apply(surface);
  out.vertices = surface.vertices.size();
  out.faces = surface.faces.size();
  out.center = normalization.center;
  out.scale = normalization.scale;

  // Seeds live on a surface: the mesh itself, or for a cloud its coarse Poisson surface.
  TriangleMesh placement;
  if (out.is_cloud) {
    stage("coarse_surface");
    pcl::PointCloud<pcl::PointXYZ>::Ptr cloud(new pcl::PointCloud<pcl::PointXYZ>);
    toPointCloud(surface, *cloud);
    CoarseMeshEstimation coarse;
    coarse.setInputCloud(cloud);
    CoarseMeshEstimation::Report coarse_report;
    coarse.process(placement, &coarse_report);
    out.poisson_depth = coarse_report.poisson_depth;
    out.coarse_faces = placement.faces.size();
    note(quiet, "  coarse surface: Poisson depth " + std::to_string(coarse_report.poisson_depth) + ", " +
                    std::to_string(placement.faces.size()) + " faces");
  }
  stage("seeds");
  const SeedsAndFrames seeds = computeSeedsAndFrames(out.is_cloud ? placement : surface, options.quad_length,
                                                     options.overlap, options.seed, options.placement);
  stage("extract");
  if (out.is_cloud) {
    HeightMapParameters parameters;
    parameters.radius = options.quad_length / std::sqrt(2.0);
    parameters.grid_size = options.grid_size;
    extractCloudHeightMaps(surface.vertices, seeds.seeds, seeds.frames, parameters, out.patches);
  } else {
    out.patches = extractMeshPatches(surface, seeds, options.quad_length, options.grid_size);
  }
  return out;
}


SeedPlacement parseSeedPlacement(const std::string& name)
{
  if (name == "quads")
    return SeedPlacement::Quads;
  if (name == "random")
    return SeedPlacement::Random;
  throw UsageError("--placement must be quads or random, not '" + name + "'");
}

}  // namespace cli
}  // namespace patchdict
}  // namespace pcl
