// Software rendering of polygon meshes: orthographic projection, z-buffered triangle fill with
// barycentric depth, Lambert shading, depth-tested edge lines.
#include <pcl_patchdict/eval/mesh_render.h>

#include <pcl_patchdict/io/atomic_file.h>
#include <pcl_patchdict/core/error.h>
#include <pcl_patchdict/io/png_writer.h>

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <limits>

namespace pcl {
namespace patchdict {

namespace {

/** An RGB image and its depth buffer (larger z is nearer). */
struct Canvas {
  int w, h;
  std::vector<std::uint8_t> pixels;
  std::vector<double> depth;
};

/** Z-buffered fill of a screen-space triangle, depth interpolated barycentrically. */
void fillTriangle(Canvas& canvas, const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& c,
                  const std::array<std::uint8_t, 3>& colour)
{
  const int w = canvas.w, h = canvas.h;
  const double area = (b.x() - a.x()) * (c.y() - a.y()) - (b.y() - a.y()) * (c.x() - a.x());
  if (std::abs(area) < 1e-12)
    return;
  const int x0 = std::max(0, static_cast<int>(std::floor(std::min({a.x(), b.x(), c.x()}))));
  const int x1 = std::min(w - 1, static_cast<int>(std::ceil(std::max({a.x(), b.x(), c.x()}))));
  const int y0 = std::max(0, static_cast<int>(std::floor(std::min({a.y(), b.y(), c.y()}))));
  const int y1 = std::min(h - 1, static_cast<int>(std::ceil(std::max({a.y(), b.y(), c.y()}))));
  for (int y = y0; y <= y1; ++y)
    for (int x = x0; x <= x1; ++x) {
      const double px = x + 0.5, py = y + 0.5;
      const double wa = ((b.x() - px) * (c.y() - py) - (b.y() - py) * (c.x() - px)) / area;
      const double wb = ((c.x() - px) * (a.y() - py) - (c.y() - py) * (a.x() - px)) / area;
      const double wc = 1.0 - wa - wb;
      if (wa < 0.0 || wb < 0.0 || wc < 0.0)
        continue;
      const double z = wa * a.z() + wb * b.z() + wc * c.z();
      const std::size_t k = static_cast<std::size_t>(y) * w + x;
      if (z <= canvas.depth[k])
        continue;
      canvas.depth[k] = z;
      std::copy(colour.begin(), colour.end(), canvas.pixels.begin() + static_cast<std::ptrdiff_t>(3 * k));
    }
}

/** Lambert-shaded fill of every face (a fan of triangles), its Newell normal against `back`. */
void fillFaces(Canvas& canvas, const std::vector<Eigen::Vector3d>& vertices, const std::vector<Eigen::Vector3d>& screen,
               const std::vector<std::vector<std::int32_t>>& faces,
               const std::vector<std::array<std::uint8_t, 3>>& face_colours, const Eigen::Vector3d& back)
{
  for (std::size_t f = 0; f < faces.size(); ++f) {
    const auto& face = faces[f];
    if (face.size() < 3)
      continue;
    // Newell normal for the shading.
    Eigen::Vector3d normal = Eigen::Vector3d::Zero();
    for (std::size_t k = 0; k < face.size(); ++k)
      normal += vertices[face[k]].cross(vertices[face[(k + 1) % face.size()]]);
    const double length = normal.norm();
    const double lambert = length > 0.0 ? std::abs(normal.dot(back)) / length : 0.0;
    const double shade = 0.25 + 0.75 * lambert;
    const std::array<std::uint8_t, 3> base = face_colours.empty() ? std::array<std::uint8_t, 3>{215, 215, 215}
                                                                  : face_colours[f];
    std::array<std::uint8_t, 3> colour;
    for (int c = 0; c < 3; ++c)
      colour[c] = static_cast<std::uint8_t>(std::lround(base[c] * shade));
    for (std::size_t k = 1; k + 1 < face.size(); ++k)
      fillTriangle(canvas, screen[face[0]], screen[face[k]], screen[face[k + 1]], colour);
  }
}

/** Edge lines, drawn where they are not behind the surface by more than `bias`. */
void drawEdges(Canvas& canvas, const std::vector<Eigen::Vector3d>& screen,
               const std::vector<std::vector<std::int32_t>>& faces, const std::array<std::uint8_t, 3>& edge_colour,
               double scale, double bias)
{
  const int w = canvas.w, h = canvas.h;
  for (const auto& face : faces)
    for (std::size_t k = 0; k < face.size(); ++k) {
      const Eigen::Vector3d& a = screen[face[k]];
      const Eigen::Vector3d& b = screen[face[(k + 1) % face.size()]];
      const int steps = static_cast<int>(std::ceil(std::max(std::abs(b.x() - a.x()), std::abs(b.y() - a.y())))) + 1;
      for (int s = 0; s <= steps; ++s) {
        const Eigen::Vector3d p = a + (b - a) * (static_cast<double>(s) / steps);
        const int x = static_cast<int>(p.x()), y = static_cast<int>(p.y());
        if (x < 0 || y < 0 || x >= w || y >= h)
          continue;
        const std::size_t index = static_cast<std::size_t>(y) * w + x;
        if (p.z() * scale + bias < canvas.depth[index] * scale)
          continue;
        std::copy(edge_colour.begin(), edge_colour.end(), canvas.pixels.begin() + static_cast<std::ptrdiff_t>(3 * index));
      }
    }
}

}  // namespace

std::vector<std::uint8_t> renderPolygons(const std::vector<Eigen::Vector3d>& vertices,
                                         const std::vector<std::vector<std::int32_t>>& faces,
                                         const std::vector<std::array<std::uint8_t, 3>>& face_colours,
                                         const RenderOptions& options)
{
  const int w = options.width, h = options.height;
  if (w <= 0 || h <= 0 || w > 16384 || h > 16384)
    throw Error("render: image size must be in [1, 16384]");
  if (!face_colours.empty() && face_colours.size() != faces.size())
    throw Error("render: one colour per face expected");
  const std::int64_t n = static_cast<std::int64_t>(vertices.size());
  for (const auto& face : faces)
    for (const std::int32_t v : face)
      if (v < 0 || v >= n)
        throw Error("render: face index out of range");

  // Camera basis: right, up, towards the viewer.
  const Eigen::Vector3d back = -options.view_direction.normalized();
  Eigen::Vector3d up = options.up - back * back.dot(options.up);
  if (up.norm() < 1e-9)
    up = back.unitOrthogonal();
  up.normalize();
  const Eigen::Vector3d right = up.cross(back);

  std::vector<Eigen::Vector3d> screen(vertices.size());
  Eigen::Vector2d lo(std::numeric_limits<double>::infinity(), std::numeric_limits<double>::infinity());
  Eigen::Vector2d hi = -lo;
  for (std::size_t i = 0; i < vertices.size(); ++i) {
    screen[i] = Eigen::Vector3d(right.dot(vertices[i]), up.dot(vertices[i]), back.dot(vertices[i]));
    lo = lo.cwiseMin(screen[i].head<2>());
    hi = hi.cwiseMax(screen[i].head<2>());
  }
  Canvas canvas{w, h, std::vector<std::uint8_t>(static_cast<std::size_t>(w) * h * 3), {}};
  for (std::size_t p = 0; p < canvas.pixels.size(); p += 3)
    std::copy(options.background.begin(), options.background.end(),
              canvas.pixels.begin() + static_cast<std::ptrdiff_t>(p));
  if (vertices.empty() || faces.empty())
    return canvas.pixels;
  const Eigen::Vector2d size = (hi - lo).cwiseMax(1e-12);
  const double scale = 0.9 * std::min(w / size.x(), h / size.y());
  const Eigen::Vector2d centre = 0.5 * (lo + hi);
  for (auto& s : screen) {
    s.x() = 0.5 * w + (s.x() - centre.x()) * scale;
    s.y() = 0.5 * h - (s.y() - centre.y()) * scale;  // image rows grow downwards
  }
  canvas.depth.assign(static_cast<std::size_t>(w) * h, -std::numeric_limits<double>::infinity());
  fillFaces(canvas, vertices, screen, faces, face_colours, back);
  // Lines drawn where they are not behind the surface (depth bias of 0.3 % of the object's size).
  if (options.draw_edges)
    drawEdges(canvas, screen, faces, options.edge_colour, scale, 0.003 * std::max(size.x(), size.y()) * scale);
  return canvas.pixels;
}

void writePolygonsPNG(const std::string& path, const std::vector<Eigen::Vector3d>& vertices,
                      const std::vector<std::vector<std::int32_t>>& faces,
                      const std::vector<std::array<std::uint8_t, 3>>& face_colours, const RenderOptions& options)
{
  const auto pixels = renderPolygons(vertices, faces, face_colours, options);
  writeFileAtomically(path, encodeRGBPNG(options.width, options.height, pixels));
}

}  // namespace patchdict
}  // namespace pcl
