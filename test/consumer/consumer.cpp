// A program that finds the installed package: builds an octahedron, runs one algorithm of the
// library on it (vertex normals) and converts it to a pcl::PolygonMesh.
#include <pcl_patchdict/core/triangle_mesh.h>
#include <pcl_patchdict/core/vertex_normals.h>
#include <pcl_patchdict/pcl/conversions.h>
#include <pcl/PolygonMesh.h>
#include <iostream>

int main()
{
  pcl::patchdict::TriangleMesh octahedron;
  octahedron.vertices = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
  octahedron.faces = {{0, 2, 4}, {2, 1, 4}, {1, 3, 4}, {3, 0, 4}, {2, 0, 5}, {1, 2, 5}, {3, 1, 5}, {0, 3, 5}};
  octahedron.normals = pcl::patchdict::computeVertexNormals(octahedron);
  pcl::PolygonMesh polygon_mesh;
  pcl::patchdict::toPolygonMesh(octahedron, polygon_mesh);
  std::cout << "faces=" << polygon_mesh.polygons.size() << "\n";
  return polygon_mesh.polygons.size() == 8 && octahedron.hasNormals() ? 0 : 1;
}
