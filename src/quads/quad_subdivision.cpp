// Quad subdivision: bilinear grids on quads, barycentric grids on triangles, fans elsewhere.
#include <pcl_patchdict/quads/quad_subdivision.h>

#include <pcl_patchdict/core/error.h>

#include <map>
#include <string>
#include <utility>

namespace pcl {
namespace patchdict {

namespace {

class Subdivider {
public:
  Subdivider(TriangleMesh& out, int n) : out_(out), n_(n) {}

  /** Output index of the k-th of n points on the edge from a to b (k = 0: a, k = n: b). */
  std::int32_t edgePoint(std::int32_t a, std::int32_t b, int k)
  {
    if (k == 0)
      return a;
    if (k == n_)
      return b;
    const bool forward = a < b;
    const auto key = forward ? std::make_pair(a, b) : std::make_pair(b, a);
    auto it = edges_.find(key);
    if (it == edges_.end()) {
      const auto first = static_cast<std::int32_t>(out_.vertices.size());
      const Eigen::Vector3d p = out_.vertices[static_cast<std::size_t>(key.first)];
      const Eigen::Vector3d q = out_.vertices[static_cast<std::size_t>(key.second)];
      for (int i = 1; i < n_; ++i)
        out_.vertices.push_back(p + (q - p) * (static_cast<double>(i) / n_));
      it = edges_.emplace(key, first).first;
    }
    return it->second + (forward ? k - 1 : n_ - 1 - k);
  }

  std::int32_t addPoint(const Eigen::Vector3d& p)
  {
    out_.vertices.push_back(p);
    return static_cast<std::int32_t>(out_.vertices.size() - 1);
  }

  void quad(const std::int32_t q[4])
  {
    const int n = n_;
    std::vector<std::int32_t> grid(static_cast<std::size_t>((n + 1) * (n + 1)));
    auto at = [&](int i, int j) -> std::int32_t& { return grid[static_cast<std::size_t>(j * (n + 1) + i)]; };
    Eigen::Vector3d c[4];
    for (int k = 0; k < 4; ++k)
      c[k] = out_.vertices[static_cast<std::size_t>(q[k])];
    for (int j = 0; j <= n; ++j)
      for (int i = 0; i <= n; ++i) {
        if (j == 0)
          at(i, j) = edgePoint(q[0], q[1], i);
        else if (j == n)
          at(i, j) = edgePoint(q[3], q[2], i);
        else if (i == 0)
          at(i, j) = edgePoint(q[0], q[3], j);
        else if (i == n)
          at(i, j) = edgePoint(q[1], q[2], j);
        else {
          const double s = static_cast<double>(i) / n, t = static_cast<double>(j) / n;
          at(i, j) = addPoint((1 - s) * (1 - t) * c[0] + s * (1 - t) * c[1] + s * t * c[2] + (1 - s) * t * c[3]);
        }
      }
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i) {
        out_.faces.push_back({at(i, j), at(i + 1, j), at(i + 1, j + 1)});
        out_.faces.push_back({at(i, j), at(i + 1, j + 1), at(i, j + 1)});
      }
  }

  void triangle(std::int32_t t0, std::int32_t t1, std::int32_t t2)
  {
    const int n = n_;
    std::vector<std::int32_t> grid(static_cast<std::size_t>((n + 1) * (n + 1)), -1);
    auto at = [&](int i, int j) -> std::int32_t& { return grid[static_cast<std::size_t>(j * (n + 1) + i)]; };
    const Eigen::Vector3d a = out_.vertices[static_cast<std::size_t>(t0)];
    const Eigen::Vector3d b = out_.vertices[static_cast<std::size_t>(t1)];
    const Eigen::Vector3d c = out_.vertices[static_cast<std::size_t>(t2)];
    for (int j = 0; j <= n; ++j)
      for (int i = 0; i + j <= n; ++i) {
        if (j == 0)
          at(i, j) = edgePoint(t0, t1, i);
        else if (i == 0)
          at(i, j) = edgePoint(t0, t2, j);
        else if (i + j == n)
          at(i, j) = edgePoint(t1, t2, j);
        else
          at(i, j) = addPoint(a + (b - a) * (static_cast<double>(i) / n) + (c - a) * (static_cast<double>(j) / n));
      }
    for (int j = 0; j < n; ++j)
      for (int i = 0; i + j < n; ++i) {
        out_.faces.push_back({at(i, j), at(i + 1, j), at(i, j + 1)});
        if (i + j < n - 1)
          out_.faces.push_back({at(i + 1, j), at(i + 1, j + 1), at(i, j + 1)});
      }
  }

private:
  TriangleMesh& out_;
  int n_;
  std::map<std::pair<std::int32_t, std::int32_t>, std::int32_t> edges_;
};

}  // namespace

TriangleMesh subdivideQuadMesh(const QuadMesh& quads, int n)
{
  if (n < 1 || n > 256)
    throw Error("quad subdivision: " + std::to_string(n) + " splits per side is outside [1, 256]");
  TriangleMesh out;
  out.vertices = quads.vertices;
  const auto num_vertices = static_cast<std::int32_t>(quads.vertices.size());
  for (const auto& face : quads.faces) {
    if (face.size() < 3)
      throw Error("quad subdivision: a face with fewer than 3 vertices");
    for (const std::int32_t v : face)
      if (v < 0 || v >= num_vertices)
        throw Error("quad subdivision: face index " + std::to_string(v) + " is out of range");
  }
  Subdivider subdivider(out, n);
  for (const auto& face : quads.faces) {
    if (face.size() == 4) {
      subdivider.quad(face.data());
    } else if (face.size() == 3) {
      subdivider.triangle(face[0], face[1], face[2]);
    } else {
      Eigen::Vector3d centre = Eigen::Vector3d::Zero();
      for (const std::int32_t v : face)
        centre += quads.vertices[static_cast<std::size_t>(v)];
      const std::int32_t c = subdivider.addPoint(centre / static_cast<double>(face.size()));
      for (std::size_t k = 0; k < face.size(); ++k)
        subdivider.triangle(face[k], face[(k + 1) % face.size()], c);
    }
  }
  return out;
}

}  // namespace patchdict
}  // namespace pcl
