// Software rendering of polygon meshes: orthographic projection, z-buffered triangle fill with
// barycentric depth, normals and colours, a key light with ambient and specular, depth-tested
// edge lines.
#include <pcl_patchdict_eval/mesh_render.h>

#include <pcl_patchdict/core/error.h>
#include <pcl_patchdict/core/atomic_file.h>
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

/** A triangle corner: screen position (x, y, depth), camera-space normal, colour (0–255). */
struct Corner {
  Eigen::Vector3d screen, normal, colour;
};

/** The light model, in camera coordinates (the viewer along +z). */
struct Shader {
  Eigen::Vector3d light, half;
  double ambient, specular;

  explicit Shader(const RenderOptions& options)
      : light(options.light.normalized()), half((light + Eigen::Vector3d::UnitZ()).normalized()),
        ambient(options.ambient), specular(options.specular)
  {
  }

  /** The pixel's colour: the base colour times the shade, plus the highlight. */
  void shade(Eigen::Vector3d normal, const Eigen::Vector3d& colour, std::uint8_t* pixel) const
  {
    const double length = normal.norm();
    double diffuse = 0.0, highlight = 0.0;
    if (length > 0.0) {
      normal /= length;
      if (normal.z() < 0.0)  // two-sided: a face seen from behind is lit as its front
        normal = -normal;
      diffuse = std::max(0.0, normal.dot(light));
      highlight = specular > 0.0 ? specular * std::pow(std::max(0.0, normal.dot(half)), 24.0) : 0.0;
    }
    const double factor = ambient + (1.0 - ambient) * diffuse;
    for (int c = 0; c < 3; ++c)
      pixel[c] = static_cast<std::uint8_t>(std::lround(std::clamp(colour[c] * factor + 255.0 * highlight, 0.0, 255.0)));
  }
};

/** Z-buffered fill of a screen-space triangle; depth, normal and colour interpolated barycentrically. */
void fillTriangle(Canvas& canvas, const Shader& shader, const Corner& a, const Corner& b, const Corner& c)
{
  const Eigen::Vector3d &pa = a.screen, &pb = b.screen, &pc = c.screen;
  const double area = (pb.x() - pa.x()) * (pc.y() - pa.y()) - (pb.y() - pa.y()) * (pc.x() - pa.x());
  if (std::abs(area) < 1e-12)
    return;
  const int x0 = std::max(0, static_cast<int>(std::floor(std::min({pa.x(), pb.x(), pc.x()}))));
  const int x1 = std::min(canvas.w - 1, static_cast<int>(std::ceil(std::max({pa.x(), pb.x(), pc.x()}))));
  const int y0 = std::max(0, static_cast<int>(std::floor(std::min({pa.y(), pb.y(), pc.y()}))));
  const int y1 = std::min(canvas.h - 1, static_cast<int>(std::ceil(std::max({pa.y(), pb.y(), pc.y()}))));
  for (int y = y0; y <= y1; ++y)
    for (int x = x0; x <= x1; ++x) {
      const double px = x + 0.5, py = y + 0.5;
      const double wa = ((pb.x() - px) * (pc.y() - py) - (pb.y() - py) * (pc.x() - px)) / area;
      const double wb = ((pc.x() - px) * (pa.y() - py) - (pc.y() - py) * (pa.x() - px)) / area;
      const double wc = 1.0 - wa - wb;
      if (wa < -1e-9 || wb < -1e-9 || wc < -1e-9)  // a pixel centre on a shared edge: both triangles take it
        continue;
      const double z = wa * pa.z() + wb * pb.z() + wc * pc.z();
      const std::size_t k = static_cast<std::size_t>(y) * canvas.w + x;
      if (z <= canvas.depth[k])
        continue;
      canvas.depth[k] = z;
      shader.shade(wa * a.normal + wb * b.normal + wc * c.normal, wa * a.colour + wb * b.colour + wc * c.colour,
                   canvas.pixels.data() + 3 * k);
    }
}

/** The Newell normal of a polygon (its length twice the area of a planar one). */
Eigen::Vector3d newellNormal(const std::vector<Eigen::Vector3d>& vertices, const std::vector<std::int32_t>& face)
{
  Eigen::Vector3d normal = Eigen::Vector3d::Zero();
  for (std::size_t k = 0; k < face.size(); ++k)
    normal += vertices[face[k]].cross(vertices[face[(k + 1) % face.size()]]);
  return normal;
}

/** The geometry seen by the camera: screen positions, camera-space face and vertex normals. */
struct Projected {
  std::vector<Eigen::Vector3d> screen, face_normals, vertex_normals;
};

/** Shaded fill of every face (a fan of triangles). */
void fillFaces(Canvas& canvas, const Projected& projected, const std::vector<std::vector<std::int32_t>>& faces,
               const std::vector<RGBColour>& colours, const RenderOptions& options)
{
  const Shader shader(options);
  const auto toVector = [](const RGBColour& c) { return Eigen::Vector3d(c[0], c[1], c[2]); };
  const Eigen::Vector3d grey(215.0, 215.0, 215.0);
  for (std::size_t f = 0; f < faces.size(); ++f) {
    const auto& face = faces[f];
    if (face.size() < 3)
      continue;
    const auto corner = [&](std::int32_t v) {
      const std::size_t i = static_cast<std::size_t>(v);
      Corner c{projected.screen[i], options.smooth_shading ? projected.vertex_normals[i] : projected.face_normals[f],
               grey};
      if (!colours.empty())
        c.colour = toVector(colours[options.per_vertex_colours ? i : f]);
      return c;
    };
    const Corner first = corner(face[0]);
    for (std::size_t k = 1; k + 1 < face.size(); ++k)
      fillTriangle(canvas, shader, first, corner(face[k]), corner(face[k + 1]));
  }
}

/** Edge lines, drawn where they are not behind the surface by more than `bias`. */
void drawEdges(Canvas& canvas, const std::vector<Eigen::Vector3d>& screen,
               const std::vector<std::vector<std::int32_t>>& faces, const RGBColour& edge_colour, double bias)
{
  const int w = canvas.w, h = canvas.h;
  for (const auto& face : faces)
    for (std::size_t k = 0; k < face.size(); ++k) {
      const Eigen::Vector3d& a = screen[face[k]];
      const Eigen::Vector3d& b = screen[face[(k + 1) % face.size()]];
      const double span = std::max(std::abs(b.x() - a.x()), std::abs(b.y() - a.y()));
      if (!(span < 4.0 * (w + h)))  // far outside a close-up's window
        continue;
      const int steps = static_cast<int>(std::ceil(span)) + 1;
      for (int s = 0; s <= steps; ++s) {
        const Eigen::Vector3d p = a + (b - a) * (static_cast<double>(s) / steps);
        const int x = static_cast<int>(std::floor(p.x())), y = static_cast<int>(std::floor(p.y()));
        if (x < 0 || y < 0 || x >= w || y >= h)
          continue;
        const std::size_t index = static_cast<std::size_t>(y) * w + x;
        if (p.z() + bias < canvas.depth[index])
          continue;
        std::copy(edge_colour.begin(), edge_colour.end(), canvas.pixels.begin() + static_cast<std::ptrdiff_t>(3 * index));
      }
    }
}

void checkInput(const std::vector<Eigen::Vector3d>& vertices, const std::vector<std::vector<std::int32_t>>& faces,
                const std::vector<RGBColour>& colours, const RenderOptions& options)
{
  const int w = options.width, h = options.height;
  if (w <= 0 || h <= 0 || w > 16384 || h > 16384)
    throw Error("render: image size must be in [1, 16384]");
  if (!colours.empty() && colours.size() != (options.per_vertex_colours ? vertices.size() : faces.size()))
    throw Error(options.per_vertex_colours ? "render: one colour per vertex expected"
                                           : "render: one colour per face expected");
  if (!(options.window_radius >= 0.0) || !std::isfinite(options.window_radius) || !options.window_centre.allFinite())
    throw Error("render: the close-up window must be finite, its radius ≥ 0");
  if (!(options.ambient >= 0.0 && options.ambient <= 1.0) || !(options.specular >= 0.0 && options.specular <= 1.0) ||
      !(options.light.norm() > 0.0) || !options.light.allFinite())
    throw Error("render: ambient and specular must be in [0, 1], the light a nonzero direction");
  const std::int64_t n = static_cast<std::int64_t>(vertices.size());
  for (const auto& face : faces)
    for (const std::int32_t v : face)
      if (v < 0 || v >= n)
        throw Error("render: face index out of range");
}

/** Camera-space normals: one per face (Newell) and per vertex (sum of its faces' Newell normals). */
void projectNormals(Projected& projected, const std::vector<Eigen::Vector3d>& vertices,
                    const std::vector<std::vector<std::int32_t>>& faces, const Eigen::Matrix3d& camera)
{
  projected.face_normals.resize(faces.size());
  projected.vertex_normals.assign(vertices.size(), Eigen::Vector3d::Zero());
  for (std::size_t f = 0; f < faces.size(); ++f) {
    projected.face_normals[f] = camera * newellNormal(vertices, faces[f]);
    for (const std::int32_t v : faces[f])
      projected.vertex_normals[static_cast<std::size_t>(v)] += projected.face_normals[f];
  }
}

}  // namespace

std::vector<std::uint8_t> renderPolygons(const std::vector<Eigen::Vector3d>& vertices,
                                         const std::vector<std::vector<std::int32_t>>& faces,
                                         const std::vector<RGBColour>& colours, const RenderOptions& options)
{
  checkInput(vertices, faces, colours, options);
  const int w = options.width, h = options.height;
  // Camera basis: right, up, towards the viewer (the rows of `camera`).
  const Eigen::Vector3d back = -options.view_direction.normalized();
  Eigen::Vector3d up = options.up - back * back.dot(options.up);
  if (up.norm() < 1e-9)
    up = back.unitOrthogonal();
  up.normalize();
  Eigen::Matrix3d camera;
  camera.row(0) = up.cross(back);
  camera.row(1) = up;
  camera.row(2) = back;

  Projected projected;
  projected.screen.resize(vertices.size());
  Eigen::Vector2d lo(std::numeric_limits<double>::infinity(), std::numeric_limits<double>::infinity());
  Eigen::Vector2d hi = -lo;
  for (std::size_t i = 0; i < vertices.size(); ++i) {
    projected.screen[i] = camera * vertices[i];
    lo = lo.cwiseMin(projected.screen[i].head<2>());
    hi = hi.cwiseMax(projected.screen[i].head<2>());
  }
  Canvas canvas{w, h, std::vector<std::uint8_t>(static_cast<std::size_t>(w) * h * 3), {}};
  for (std::size_t p = 0; p < canvas.pixels.size(); p += 3)
    std::copy(options.background.begin(), options.background.end(),
              canvas.pixels.begin() + static_cast<std::ptrdiff_t>(p));
  if (vertices.empty() || faces.empty())
    return canvas.pixels;
  const Eigen::Vector2d size = (hi - lo).cwiseMax(1e-12);
  const bool close_up = options.window_radius > 0.0;
  const double scale = close_up ? 0.5 * std::min(w, h) / options.window_radius
                                : 0.9 * std::min(w / size.x(), h / size.y());
  const Eigen::Vector2d centre = close_up ? Eigen::Vector2d((camera * options.window_centre).head<2>())
                                          : Eigen::Vector2d(0.5 * (lo + hi));
  for (auto& s : projected.screen) {
    s.x() = 0.5 * w + (s.x() - centre.x()) * scale;
    s.y() = 0.5 * h - (s.y() - centre.y()) * scale;  // image rows grow downwards
    s.z() *= scale;
  }
  projectNormals(projected, vertices, faces, camera);
  canvas.depth.assign(static_cast<std::size_t>(w) * h, -std::numeric_limits<double>::infinity());
  fillFaces(canvas, projected, faces, colours, options);
  // Lines drawn where they are not behind the surface (depth bias of 0.3 % of the view's size).
  if (options.draw_edges)
    drawEdges(canvas, projected.screen, faces, options.edge_colour,
              0.003 * (close_up ? 2.0 * options.window_radius : std::max(size.x(), size.y())) * scale);
  return canvas.pixels;
}

void writePolygonsPNG(const std::string& path, const std::vector<Eigen::Vector3d>& vertices,
                      const std::vector<std::vector<std::int32_t>>& faces, const std::vector<RGBColour>& colours,
                      const RenderOptions& options)
{
  const auto pixels = renderPolygons(vertices, faces, colours, options);
  writeFileAtomically(path, encodeRGBPNG(options.width, options.height, pixels));
}

RGBColour errorColour(double t)
{
  t = std::isnan(t) ? 1.0 : std::clamp(t, 0.0, 1.0);
  // Stops at 0, ½ and 1, linear in RGB between them.
  static const double stops[3][3] = {{196.0, 206.0, 224.0}, {250.0, 204.0, 60.0}, {214.0, 40.0, 36.0}};
  const int segment = t < 0.5 ? 0 : 1;
  const double u = t < 0.5 ? 2.0 * t : 2.0 * t - 1.0;
  RGBColour colour;
  for (int c = 0; c < 3; ++c)
    colour[c] = static_cast<std::uint8_t>(std::lround(stops[segment][c] + u * (stops[segment + 1][c] - stops[segment][c])));
  return colour;
}

}  // namespace patchdict
}  // namespace pcl
