#include "surface_patches.h"

#include "cli.h"

#include <pcl_patchdict/core/normalization.h>

#include <cmath>
#include <cstdio>

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
  stage("seeds");
  PatchLayoutParameters parameters;
  parameters.quad_length = options.quad_length;
  parameters.overlap = options.overlap;
  parameters.seed = options.seed;
  PatchPlacementReport placement;
  const PatchLayout layout = layPatches(surface, parameters, options.placement, &placement);
  if (out.is_cloud) {
    out.poisson_depth = placement.poisson_depth;
    out.coarse_faces = placement.surface_faces;
    char line[160];
    std::snprintf(line, sizeof line, "  coarse surface: Poisson depth %d, %zu faces (%.2f s of the seeds' time)",
                  placement.poisson_depth, placement.surface_faces, placement.seconds_surface);
    note(quiet, line);
  }
  stage("extract");
  out.patches = extractSurfacePatches(surface, layout, options.grid_size);
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
