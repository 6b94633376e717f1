// Repair reports (see repair_report.h): shaded pictures by the software renderer (mesh_render.h,
// repair_figure.h: no display or GPU needed, so it works on a headless machine), a coloured PLY
// written here.
#include "repair_report.h"

#include <pcl_patchdict/core/atomic_file.h>
#include <pcl_patchdict_eval/mesh_render.h>
#include <pcl_patchdict_eval/repair_figure.h>
#include <pcl_patchdict/geometry/metrics.h>

#include <algorithm>
#include <numeric>
#include <cstdint>
#include <filesystem>

namespace pcl {
namespace patchdict {
namespace cli {

namespace {

using Colour = RGBColour;

const Colour kGrey{205, 205, 205}, kFill{250, 185, 120};

/** Binary little-endian PLY with float32 positions and uchar colours per vertex. */
void writeColouredPly(const std::string& path, const TriangleMesh& mesh, const std::vector<Colour>& colours)
{
  std::string bytes = "ply\nformat binary_little_endian 1.0\ncomment pcl_patchdict repair report: colour = "
                      "distance to the reference\nelement vertex " +
                      std::to_string(mesh.numVertices()) +
                      "\nproperty float x\nproperty float y\nproperty float z\nproperty uchar red\nproperty uchar "
                      "green\nproperty uchar blue\nelement face " +
                      std::to_string(mesh.numFaces()) + "\nproperty list uchar int vertex_indices\nend_header\n";
  const auto append = [&](const void* data, std::size_t size) {
    bytes.append(static_cast<const char*>(data), size);
  };
  for (std::size_t v = 0; v < mesh.numVertices(); ++v) {
    for (int c = 0; c < 3; ++c) {
      const float value = static_cast<float>(mesh.vertices[v][c]);
      append(&value, sizeof value);
    }
    append(colours[v].data(), 3);
  }
  for (const Face& f : mesh.faces) {
    const std::uint8_t count = 3;
    append(&count, 1);
    for (std::int32_t index : f)
      append(&index, sizeof index);
  }
  writeFileAtomically(path, bytes);
}

}  // namespace

void writeFillPicture(const std::string& path, const TriangleMesh& mesh, std::size_t first_new_face, int pixels)
{
  std::vector<Colour> colours(mesh.numFaces(), kGrey);
  for (std::size_t f = std::min(first_new_face, mesh.numFaces()); f < mesh.numFaces(); ++f)
    colours[f] = kFill;
  RenderOptions options;
  options.width = options.height = pixels;
  writePolygonsPNG(path, mesh.vertices, polygonsOf(mesh), colours, options);
}

JsonObject writeRepairReport(const std::string& dir, const TriangleMesh& before, const TriangleMesh& after,
                             std::size_t first_new_face, const TriangleMesh* reference, double scale)
{
  const auto file = [&](const std::string& name) { return (std::filesystem::path(dir) / name).string(); };
  JsonObject json;
  json.add("folder", dir);
  writeFillPicture(file("before.png"), before, before.numFaces());
  writeFillPicture(file("after.png"), after, first_new_face);
  json.add("before_png", file("before.png")).add("after_png", file("after.png"));
  if (!reference)
    return json;
  if (reference->faces.empty())
    throw Error("the reference has no faces: the error colouring needs a surface");
  const std::vector<double> distances = PointToMeshDistance(*reference).distances(after.vertices);
  const double top = scale > 0.0 ? scale : percentile99(distances);
  const double sum = std::accumulate(distances.begin(), distances.end(), 0.0);
  writeColouredPly(file("error.ply"), after, errorColours(distances, top));
  writeImagePNG(file("error.png"), errorPicture(after, distances, top, 800));
  json.add("error_ply", file("error.ply")).add("error_png", file("error.png"));
  // A close-up of the largest filled region beside the reference, when the repair added faces.
  CloseUpWindow window;
  if (windowAroundNewFaces(after, first_new_face, window)) {
    writeImagePNG(file("closeup.png"), comparisonFigure(*reference, {"input", &before}, {{"output", &after}},
                                                        window, top, 400));
    json.add("closeup_png", file("closeup.png"));
  }
  json.add("error_scale", top).add("mean_vertex_distance", distances.empty() ? 0.0 : sum / distances.size());
  return json;
}

}  // namespace cli
}  // namespace patchdict
}  // namespace pcl
