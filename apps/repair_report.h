// --report DIR of the repair commands: before/after pictures and, with a reference (--ref), the
// output coloured by its distance to the reference, as PLY and picture.
#pragma once

#include "cli.h"

#include <pcl_patchdict/core/triangle_mesh.h>

#include <string>

namespace pcl {
namespace patchdict {
namespace cli {

/** The mesh as a shaded PNG of `pixels`², grey, faces from `first_new_face` on in orange (a fill). */
void writeFillPicture(const std::string& path, const TriangleMesh& mesh, std::size_t first_new_face, int pixels = 800);

/** Writes DIR/before.png and DIR/after.png (faces from `first_new_face` on in orange: a fill),
  * and with a reference DIR/error.ply (the output with per-vertex colours: distance to the
  * reference surface, errorColour: pale blue-grey 0 → yellow → red at `scale`, 0 = the 99th
  * percentile), DIR/error.png (the same colours, shaded, with a colour bar) and, when the repair
  * added faces, DIR/closeup.png (the largest added region: reference | output shaded, input |
  * output coloured by the distance).
  * Both meshes and the reference in the same coordinates. Returns what it wrote and measured for
  * --json. DIR must exist (prepareReport makes it before any work). Throws Error when a file
  * cannot be written. */
JsonObject writeRepairReport(const std::string& dir, const TriangleMesh& before, const TriangleMesh& after,
                             std::size_t first_new_face, const TriangleMesh* reference, double scale = 0.0);

}  // namespace cli
}  // namespace patchdict
}  // namespace pcl
