// Optional comparison, not part of the library: fills the holes of a mesh with CGAL's
// triangulate_refine_and_fair_hole (Liepa 2003 as CGAL implements it), so that
// bench/compare_cgal_holes.sh can put pcl_patchdict's HoleFilling beside it. Built only by that
// script, only when Debian's libcgal-dev is installed.
//
// usage: cgal_fill_holes IN OUT [MAX_DIAMETER_FRACTION]
//   Loops whose diameter is at least MAX_DIAMETER_FRACTION (default 0.5) of the mesh's bounding-box
//   diagonal are kept open — the same outer-boundary rule as pcl_patchdict fill-holes.
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Polygon_mesh_processing/IO/polygon_mesh_io.h>
#include <CGAL/Polygon_mesh_processing/triangulate_hole.h>
#include <CGAL/Surface_mesh.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <iterator>
#include <set>
#include <vector>

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using Point = Kernel::Point_3;
using Mesh = CGAL::Surface_mesh<Point>;
using Halfedge = boost::graph_traits<Mesh>::halfedge_descriptor;
namespace PMP = CGAL::Polygon_mesh_processing;

int main(int argc, char** argv)
{
  if (argc < 3) {
    std::fprintf(stderr, "usage: cgal_fill_holes IN OUT [MAX_DIAMETER_FRACTION]\n");
    return 2;
  }
  const double fraction = argc > 3 ? std::atof(argv[3]) : 0.5;
  Mesh mesh;
  if (!PMP::IO::read_polygon_mesh(argv[1], mesh) || mesh.is_empty()) {
    std::fprintf(stderr, "cgal_fill_holes: error: cannot read a mesh from %s\n", argv[1]);
    return 1;
  }
  const auto box = CGAL::bounding_box(mesh.points().begin(), mesh.points().end());
  const double diagonal = std::sqrt(CGAL::squared_distance(box.min(), box.max()));

  // Collect the boundary loops first: filling changes the halfedge set.
  std::vector<Halfedge> loops;
  std::set<Halfedge> seen;
  for (const Halfedge h : halfedges(mesh)) {
    if (!is_border(h, mesh) || seen.count(h))
      continue;
    double widest = 0.0;
    std::vector<Point> points;
    for (const Halfedge g : CGAL::halfedges_around_face(h, mesh)) {
      seen.insert(g);
      points.push_back(mesh.point(target(g, mesh)));
    }
    for (std::size_t i = 0; i < points.size(); ++i)
      for (std::size_t j = i + 1; j < points.size(); ++j)
        widest = std::max(widest, std::sqrt(CGAL::squared_distance(points[i], points[j])));
    if (widest < fraction * diagonal)
      loops.push_back(h);
  }
  const auto start = std::chrono::steady_clock::now();
  std::size_t filled = 0, new_vertices = 0;
  for (const Halfedge h : loops) {
    std::vector<boost::graph_traits<Mesh>::face_descriptor> faces;
    std::vector<boost::graph_traits<Mesh>::vertex_descriptor> vertices;
    const auto result = PMP::triangulate_refine_and_fair_hole(mesh, h, std::back_inserter(faces),
                                                              std::back_inserter(vertices));
    filled += std::get<0>(result) ? 1 : 0;
    new_vertices += vertices.size();
  }
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  if (!CGAL::IO::write_polygon_mesh(argv[2], mesh, CGAL::parameters::stream_precision(17))) {
    std::fprintf(stderr, "cgal_fill_holes: error: cannot write %s\n", argv[2]);
    return 1;
  }
  std::printf("{\"holes\": %zu, \"filled\": %zu, \"new_vertices\": %zu, \"seconds\": %.6f}\n", loops.size(), filled,
              new_vertices, seconds);
  return 0;
}
