// `pcl_patchdict info IN`: what a mesh is, and what is wrong with it (clouds: cmd_info_cloud.cpp).
#include "cli.h"
#include "options.h"
#include "cloud_input.h"

#include <pcl_patchdict/geometry/mesh_hygiene.h>

#include <iostream>

namespace pcl {
namespace patchdict {
namespace cli {

int runInfo(const std::vector<std::string>& raw)
{
  const Arguments args = readCommandLine(raw, commandSpec("info"));
  if (isCloudFile(args.positionals()[0]))
    return runCloudInfo(args);
  args.refuse("save-sensor-model", "is for organised clouds (.pcd), not meshes");
  ReadInfo read_info;
  const TriangleMesh mesh = loadMesh(args.positionals()[0], true, &read_info);
  const MeshHygieneReport report = inspectMesh(mesh);
  Eigen::Vector3d lo, hi;
  mesh.boundingBox(lo, hi);
  if (args.has("json")) {
    JsonObject json;
    json.add("command", "info").add("input", args.positionals()[0]).add("format", formatName(read_info.format));
    json.add("vertices", report.vertices).add("faces", report.faces);
    json.add("unreferenced_vertices", report.unreferenced_vertices)
        .add("nonfinite_vertices", report.nonfinite_vertices)
        .add("degenerate_faces", report.degenerate_faces)
        .add("duplicate_faces", report.duplicate_faces)
        .add("nonmanifold_edges", report.nonmanifold_edges)
        .add("nonmanifold_vertices", report.nonmanifold_vertices)
        .add("boundary_edges", report.boundary_edges)
        .add("boundary_loops", report.boundary_loops)
        .add("components", report.components)
        .add("bbox_diagonal", mesh.boundingBoxDiagonal())
        .add("mean_edge_length", mesh.meanEdgeLength())
        .add("surface_area", mesh.surfaceArea())
        .add("polygons_triangulated", read_info.polygons_triangulated);
    std::cout << json.str() << '\n';
  } else {
    std::cout << args.positionals()[0] << " (" << formatName(read_info.format) << ")\n  " << report.summary()
              << "\n  bbox [" << lo.transpose() << "] – [" << hi.transpose() << "], diagonal "
              << mesh.boundingBoxDiagonal() << "\n  mean edge " << mesh.meanEdgeLength() << ", area "
              << mesh.surfaceArea() << '\n';
  }
  return 0;
}

}  // namespace cli
}  // namespace patchdict
}  // namespace pcl
