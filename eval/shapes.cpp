#include <pcl_patchdict/core/error.h>
#include <pcl_patchdict_eval/shapes.h>

#include <cmath>
#include <functional>
#include <map>
#include <unordered_map>

namespace pcl {
namespace patchdict {

namespace {

TriangleMesh gridMesh(int nx, int ny, const std::function<Eigen::Vector3d(double, double)>& at,
                      bool wrap_u, bool wrap_v)
{
  if (nx < 1 || ny < 1)
    throw Error("grid resolution must be at least 1×1");
  TriangleMesh mesh;
  const int cols = wrap_u ? nx : nx + 1;
  const int rows = wrap_v ? ny : ny + 1;
  mesh.vertices.reserve(static_cast<std::size_t>(cols) * rows);
  for (int j = 0; j < rows; ++j)
    for (int i = 0; i < cols; ++i)
      mesh.vertices.push_back(at(static_cast<double>(i) / nx, static_cast<double>(j) / ny));
  auto id = [&](int i, int j) { return (j % rows) * cols + (i % cols); };
  for (int j = 0; j < ny; ++j)
    for (int i = 0; i < nx; ++i) {
      const int a = id(i, j), b = id(i + 1, j), c = id(i + 1, j + 1), d = id(i, j + 1);
      mesh.faces.push_back({a, b, c});
      mesh.faces.push_back({a, c, d});
    }
  return mesh;
}

}  // namespace

TriangleMesh makePlaneGrid(int nx, int ny, double size_x, double size_y)
{
  return gridMesh(nx, ny, [&](double u, double v) { return Eigen::Vector3d(u * size_x, v * size_y, 0.0); },
                  false, false);
}

double sinusoidalReliefHeight(double x, double y, double amplitude, double period)
{
  return amplitude * std::sin(2.0 * M_PI * x / period) * std::sin(2.0 * M_PI * y / period);
}

TriangleMesh makeSinusoidalRelief(int nx, int ny, double amplitude, double period)
{
  if (!(period > 0.0))
    throw Error("relief period must be positive");
  return gridMesh(nx, ny, [&](double u, double v) {
    return Eigen::Vector3d(u, v, sinusoidalReliefHeight(u, v, amplitude, period));
  }, false, false);
}

TriangleMesh makeTorus(int nu, int nv, double major_radius, double minor_radius)
{
  if (nu < 3 || nv < 3)
    throw Error("torus resolution must be at least 3×3");
  return gridMesh(nu, nv, [&](double u, double v) {
    const double a = 2.0 * M_PI * u, b = 2.0 * M_PI * v;
    const double ring = major_radius + minor_radius * std::cos(b);
    return Eigen::Vector3d(ring * std::cos(a), ring * std::sin(a), minor_radius * std::sin(b));
  }, true, true);
}

TriangleMesh subdivideMidpoint(const TriangleMesh& mesh)
{
  TriangleMesh out;
  out.vertices = mesh.vertices;
  out.faces.reserve(mesh.faces.size() * 4);
  std::unordered_map<std::uint64_t, std::int32_t> midpoint;
  auto mid = [&](std::int32_t a, std::int32_t b) {
    const std::uint64_t key = (static_cast<std::uint64_t>(std::min(a, b)) << 32) |
                              static_cast<std::uint32_t>(std::max(a, b));
    auto it = midpoint.find(key);
    if (it != midpoint.end())
      return it->second;
    const auto index = static_cast<std::int32_t>(out.vertices.size());
    out.vertices.push_back(0.5 * (mesh.vertices[a] + mesh.vertices[b]));
    midpoint.emplace(key, index);
    return index;
  };
  for (const Face& f : mesh.faces) {
    const std::int32_t ab = mid(f[0], f[1]), bc = mid(f[1], f[2]), ca = mid(f[2], f[0]);
    out.faces.push_back({f[0], ab, ca});
    out.faces.push_back({ab, f[1], bc});
    out.faces.push_back({ca, bc, f[2]});
    out.faces.push_back({ab, bc, ca});
  }
  return out;
}

TriangleMesh makeIcosphere(int levels, double radius)
{
  if (levels < 0 || levels > 9)
    throw Error("icosphere levels must be in [0, 9]");
  const double t = (1.0 + std::sqrt(5.0)) / 2.0;
  TriangleMesh mesh;
  mesh.vertices = {{-1, t, 0}, {1, t, 0}, {-1, -t, 0}, {1, -t, 0}, {0, -1, t}, {0, 1, t},
                   {0, -1, -t}, {0, 1, -t}, {t, 0, -1}, {t, 0, 1}, {-t, 0, -1}, {-t, 0, 1}};
  mesh.faces = {{0, 11, 5}, {0, 5, 1}, {0, 1, 7}, {0, 7, 10}, {0, 10, 11}, {1, 5, 9}, {5, 11, 4},
                {11, 10, 2}, {10, 7, 6}, {7, 1, 8}, {3, 9, 4}, {3, 4, 2}, {3, 2, 6}, {3, 6, 8},
                {3, 8, 9}, {4, 9, 5}, {2, 4, 11}, {6, 2, 10}, {8, 6, 7}, {9, 8, 1}};
  for (int level = 0; level < levels; ++level)
    mesh = subdivideMidpoint(mesh);
  for (auto& v : mesh.vertices)
    v = v.normalized() * radius;
  return mesh;
}

}  // namespace patchdict
}  // namespace pcl
