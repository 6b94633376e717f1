// Pictures of a repair beside its truth: a close-up window around a repaired region, seen by one
// camera for every panel; the top row shaded (truth, then each output), the bottom row coloured by
// the distance to the truth (the input, then each output) with a colour bar.
#pragma once

#include <pcl_patchdict/core/triangle_mesh.h>
#include <pcl_patchdict_eval/picture_layout.h>

#include <string>
#include <vector>

namespace pcl {
namespace patchdict {

/** The value at the 99th percentile (0 for none): the error scale when none is given. */
double percentile99(std::vector<double> values);
/** errorColour of each distance / scale (the low end for scale 0). */
std::vector<RGBColour> errorColours(const std::vector<double>& distances, double scale);

/** The mesh's triangles as renderPolygons takes them. */
std::vector<std::vector<std::int32_t>> polygonsOf(const TriangleMesh& mesh);

/** A close-up: a window of `radius` around `centre`, looked at along `view_direction`. */
struct CloseUpWindow {
  Eigen::Vector3d centre = Eigen::Vector3d::Zero();
  Eigen::Vector3d view_direction = Eigen::Vector3d(0.0, 0.0, -1.0);
  double radius = 0.0;
};

/** A window of `radius` around `centre`, looking against the mean normal of `mesh`'s faces
  * within `radius` of it (along −z when there are none). Throws Error for radius ≤ 0. */
CloseUpWindow windowAround(const TriangleMesh& mesh, const Eigen::Vector3d& centre, double radius);

/** The largest set of faces from `first_new_face` on (connected through shared vertices), framed:
  * centred on its vertices' centroid, radius 1.6 × their largest distance from it, seen against
  * its mean normal. Returns false, leaving `window` alone, when there is no such face. */
bool windowAroundNewFaces(const TriangleMesh& mesh, std::size_t first_new_face, CloseUpWindow& window);

/** The render options that show `window` in a panel of `pixels`². */
RenderOptions closeUpOptions(const CloseUpWindow& window, int pixels);

/** The faces of `mesh` near `window` (a face whose vertices are all within 2.5 × radius of the
  * centre), so that nothing farther away hides the region. Vertices are kept as they are. */
std::vector<std::vector<std::int32_t>> facesNearWindow(const TriangleMesh& mesh, const CloseUpWindow& window);

/** One mesh in a figure, with its label. */
struct FigureMesh {
  std::string label;
  const TriangleMesh* mesh = nullptr;
};

/** \brief The comparison figure of `window`: top row truth | outputs… shaded grey, bottom row
  * input | outputs… coloured by each vertex's distance to the truth (errorColour, 1 at
  * `error_scale`; ≤ 0: the largest 99th percentile of the outputs' distances in the window) times
  * the shade, and a colour bar. `panel_pixels`² per panel. Throws Error for a truth without faces,
  * no outputs or a null mesh. */
RGBImage comparisonFigure(const TriangleMesh& truth, const FigureMesh& input, const std::vector<FigureMesh>& outputs,
                          const CloseUpWindow& window, double error_scale, int panel_pixels);

/** The colour bar's upper label of an error scale: ">=" and two significant digits. */
std::string errorScaleLabel(double scale);

/** One mesh rendered whole, shaded, each vertex coloured by `distances[v] / scale` (errorColour),
  * with a colour bar up to `scale`; `pixels`² before the bar. */
RGBImage errorPicture(const TriangleMesh& mesh, const std::vector<double>& distances, double scale, int pixels);

}  // namespace patchdict
}  // namespace pcl
