#include <pcl_patchdict/shapes.h>
#include <pcl/PolygonMesh.h>
#include <iostream>

int main()
{
  const auto sphere = pcl::patchdict::makeIcosphere(1);
  pcl::PolygonMesh polygon_mesh;
  pcl::patchdict::toPolygonMesh(sphere, polygon_mesh);
  std::cout << "faces=" << polygon_mesh.polygons.size() << "\n";
  return polygon_mesh.polygons.size() == 80 ? 0 : 1;
}
