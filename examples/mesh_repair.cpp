// mesh_repair — fills the holes of a triangle mesh: Liepa's fill, corrected by sparse height-map
// patches learned from the mesh itself (fillHolesWithPatches).
// usage: mesh_repair IN OUT [MAX_HOLE_DIAMETER]   (PLY, OBJ, OFF or STL, from the extensions;
//        the diameter in the mesh's units, default 10 % of its bounding-box diagonal)
#include <pcl_patchdict/geometry/hole_filling.h>
#include <pcl_patchdict/io/mesh_io.h>
#include <pcl_patchdict/repair/patch_repairs.h>
#include <pcl_patchdict/core/triangle_mesh.h>

#include <cstdio>
#include <cstdlib>
#include <exception>
#include <stdexcept>
#include <string>

int main(int argc, char** argv)
{
  if (argc != 3 && argc != 4) {
    std::fprintf(stderr, "usage: %s IN OUT [MAX_HOLE_DIAMETER]\n", argv[0]);
    return 2;
  }
  try {
    pcl::patchdict::TriangleMesh mesh;
    pcl::patchdict::readMesh(argv[1], mesh);  // throws pcl::patchdict::Error with one line

    // Which boundary loops are holes: up to the given diameter (the rim of an open scan never is).
    char* end = nullptr;
    const double max_diameter = argc == 4 ? std::strtod(argv[3], &end) : 0.1 * mesh.boundingBoxDiagonal();
    if (argc == 4 && (end == argv[3] || *end != '\0' || !(max_diameter > 0.0)))
      throw std::runtime_error(std::string("MAX_HOLE_DIAMETER must be a positive number, not '") + argv[3] + "'");
    pcl::patchdict::HoleRepairOptions options;  // the repair's measured defaults
    options.filling.setMaxHoleDiameter(max_diameter);

    pcl::patchdict::TriangleMesh repaired;
    pcl::patchdict::HoleRepairReport report;
    pcl::patchdict::fillHolesWithPatches(mesh, repaired, options, &report);
    pcl::patchdict::writeMesh(argv[2], repaired);

    std::printf("holes %zu found, %zu filled, %zu skipped; %zu new vertices, %zu new faces (%s); "
                "faces %zu -> %zu -> %s\n",
                report.holes.holes_found, report.holes.holes_filled, report.holes.holes_skipped,
                report.holes.new_vertices, report.holes.new_faces,
                !report.used_patches ? "Liepa only" : report.relief ? "patches, relief" : "patches, smooth",
                mesh.numFaces(), repaired.numFaces(), argv[2]);
    return 0;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "mesh_repair: %s\n", e.what());
    return 1;
  }
}
