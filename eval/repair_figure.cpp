// Comparison figures of repairs: close-up windows, shaded and error-coloured panels, one camera.
#include <pcl_patchdict_eval/repair_figure.h>

#include <pcl_patchdict/core/error.h>
#include <pcl_patchdict/geometry/metrics.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numeric>

namespace pcl {
namespace patchdict {

namespace {

/** Union-find root with path halving. */
std::int32_t root(std::vector<std::int32_t>& parent, std::int32_t v)
{
  while (parent[static_cast<std::size_t>(v)] != v)
    v = parent[static_cast<std::size_t>(v)] = parent[static_cast<std::size_t>(parent[static_cast<std::size_t>(v)])];
  return v;
}

/** Distances to the truth of the vertices the window's faces use (others 0: not drawn). */
std::vector<double> windowDistances(const PointToMeshDistance& truth, const TriangleMesh& mesh,
                                    const std::vector<std::vector<std::int32_t>>& faces, std::vector<double>* used)
{
  std::vector<char> in_window(mesh.numVertices(), 0);
  for (const auto& face : faces)
    for (const std::int32_t v : face)
      in_window[static_cast<std::size_t>(v)] = 1;
  std::vector<Eigen::Vector3d> points;
  std::vector<std::size_t> index;
  for (std::size_t v = 0; v < mesh.numVertices(); ++v)
    if (in_window[v]) {
      points.push_back(mesh.vertices[v]);
      index.push_back(v);
    }
  const std::vector<double> near = points.empty() ? std::vector<double>() : truth.distances(points);
  std::vector<double> distances(mesh.numVertices(), 0.0);
  for (std::size_t i = 0; i < index.size(); ++i)
    distances[index[i]] = near[i];
  if (used)
    used->insert(used->end(), near.begin(), near.end());
  return distances;
}

RGBImage render(const TriangleMesh& mesh, const std::vector<std::vector<std::int32_t>>& faces,
                const std::vector<RGBColour>& vertex_colours, const RenderOptions& base)
{
  RenderOptions options = base;
  options.per_vertex_colours = !vertex_colours.empty();
  return RGBImage{options.width, options.height, renderPolygons(mesh.vertices, faces, vertex_colours, options)};
}

}  // namespace

double percentile99(std::vector<double> values)
{
  if (values.empty())
    return 0.0;
  const std::size_t at = (values.size() - 1) * 99 / 100;
  std::nth_element(values.begin(), values.begin() + static_cast<std::ptrdiff_t>(at), values.end());
  return values[at];
}

std::vector<RGBColour> errorColours(const std::vector<double>& distances, double scale)
{
  std::vector<RGBColour> colours(distances.size());
  for (std::size_t v = 0; v < distances.size(); ++v)
    colours[v] = errorColour(scale > 0.0 ? distances[v] / scale : 0.0);
  return colours;
}


std::vector<std::vector<std::int32_t>> polygonsOf(const TriangleMesh& mesh)
{
  std::vector<std::vector<std::int32_t>> faces;
  faces.reserve(mesh.numFaces());
  for (const Face& f : mesh.faces)
    faces.push_back({f[0], f[1], f[2]});
  return faces;
}

std::string errorScaleLabel(double scale)
{
  char text[32];
  std::snprintf(text, sizeof text, ">=%.2g", scale);
  return text;
}

CloseUpWindow windowAround(const TriangleMesh& mesh, const Eigen::Vector3d& centre, double radius)
{
  if (!(radius > 0.0) || !std::isfinite(radius) || !centre.allFinite())
    throw Error("close-up: the window needs a finite centre and a radius > 0");
  CloseUpWindow window;
  window.centre = centre;
  window.radius = radius;
  Eigen::Vector3d normal = Eigen::Vector3d::Zero();
  for (const Face& f : mesh.faces) {
    const Eigen::Vector3d &a = mesh.vertices[f[0]], &b = mesh.vertices[f[1]], &c = mesh.vertices[f[2]];
    if (((a + b + c) / 3.0 - centre).norm() <= radius)
      normal += (b - a).cross(c - a);
  }
  if (normal.norm() > 0.0)
    window.view_direction = -normal.normalized();
  return window;
}

bool windowAroundNewFaces(const TriangleMesh& mesh, std::size_t first_new_face, CloseUpWindow& window)
{
  if (first_new_face >= mesh.numFaces())
    return false;
  std::vector<std::int32_t> parent(mesh.numVertices());
  std::iota(parent.begin(), parent.end(), 0);
  for (std::size_t f = first_new_face; f < mesh.numFaces(); ++f)
    for (int k = 1; k < 3; ++k)
      parent[static_cast<std::size_t>(root(parent, mesh.faces[f][k]))] = root(parent, mesh.faces[f][0]);
  std::vector<std::size_t> count(mesh.numVertices(), 0);
  for (std::size_t f = first_new_face; f < mesh.numFaces(); ++f)
    ++count[static_cast<std::size_t>(root(parent, mesh.faces[f][0]))];
  const std::int32_t largest = static_cast<std::int32_t>(std::max_element(count.begin(), count.end()) - count.begin());
  std::vector<char> used(mesh.numVertices(), 0);
  for (std::size_t f = first_new_face; f < mesh.numFaces(); ++f)
    if (root(parent, mesh.faces[f][0]) == largest)
      for (const std::int32_t v : mesh.faces[f])
        used[static_cast<std::size_t>(v)] = 1;
  Eigen::Vector3d centre = Eigen::Vector3d::Zero();
  std::size_t n = 0;
  for (std::size_t v = 0; v < used.size(); ++v)
    if (used[v]) {
      centre += mesh.vertices[v];
      ++n;
    }
  centre /= static_cast<double>(n);
  double extent = 0.0;
  for (std::size_t v = 0; v < used.size(); ++v)
    if (used[v])
      extent = std::max(extent, (mesh.vertices[v] - centre).norm());
  if (!(extent > 0.0))
    return false;
  window = windowAround(mesh, centre, 1.6 * extent);
  return true;
}

RenderOptions closeUpOptions(const CloseUpWindow& window, int pixels)
{
  RenderOptions options;
  options.width = options.height = pixels;
  options.view_direction = window.view_direction;
  options.window_centre = window.centre;
  options.window_radius = window.radius;
  return options;
}

std::vector<std::vector<std::int32_t>> facesNearWindow(const TriangleMesh& mesh, const CloseUpWindow& window)
{
  std::vector<std::vector<std::int32_t>> faces;
  const double reach = 2.5 * window.radius;
  for (const Face& f : mesh.faces)
    if ((mesh.vertices[f[0]] - window.centre).norm() <= reach && (mesh.vertices[f[1]] - window.centre).norm() <= reach &&
        (mesh.vertices[f[2]] - window.centre).norm() <= reach)
      faces.push_back({f[0], f[1], f[2]});
  return faces;
}

RGBImage comparisonFigure(const TriangleMesh& truth, const FigureMesh& input, const std::vector<FigureMesh>& outputs,
                          const CloseUpWindow& window, double error_scale, int panel_pixels)
{
  if (truth.faces.empty() || outputs.empty() || !input.mesh)
    throw Error("figure: a truth with faces, an input and at least one output expected");
  for (const FigureMesh& output : outputs)
    if (!output.mesh)
      throw Error("figure: an output without a mesh");
  const RenderOptions options = closeUpOptions(window, panel_pixels);
  const PointToMeshDistance to_truth(truth);
  std::vector<FigureMesh> coloured{input};
  coloured.insert(coloured.end(), outputs.begin(), outputs.end());
  std::vector<std::vector<double>> distances;
  double scale = error_scale;
  for (const FigureMesh& item : coloured) {
    std::vector<double> used;
    distances.push_back(windowDistances(to_truth, *item.mesh, facesNearWindow(*item.mesh, window), &used));
    if (error_scale <= 0.0 && item.mesh != input.mesh)
      scale = std::max(scale, percentile99(used));
  }
  std::vector<RGBImage> panels;
  std::vector<std::string> labels;
  panels.push_back(render(truth, facesNearWindow(truth, window), {}, options));
  labels.push_back("truth");
  for (const FigureMesh& output : outputs) {
    panels.push_back(render(*output.mesh, facesNearWindow(*output.mesh, window), {}, options));
    labels.push_back(output.label);
  }
  for (std::size_t i = 0; i < coloured.size(); ++i) {
    panels.push_back(render(*coloured[i].mesh, facesNearWindow(*coloured[i].mesh, window),
                            errorColours(distances[i], scale), options));
    labels.push_back(coloured[i].label + " error");
  }
  return withColourBar(panelGrid(panels, labels, static_cast<int>(coloured.size())), "distance to the truth",
                       errorScaleLabel(scale));
}

RGBImage errorPicture(const TriangleMesh& mesh, const std::vector<double>& distances, double scale, int pixels)
{
  if (distances.size() != mesh.numVertices())
    throw Error("figure: one distance per vertex expected");
  RenderOptions options;
  options.width = options.height = pixels;
  const RGBImage picture = render(mesh, polygonsOf(mesh), errorColours(distances, scale), options);
  return withColourBar(picture, "distance to the reference", errorScaleLabel(scale));
}

}  // namespace patchdict
}  // namespace pcl
