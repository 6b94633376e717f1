// A small software renderer for pictures of results (README, demo, --report): orthographic view,
// z-buffer, a key light with ambient and a little specular, smooth (per-pixel, from vertex normals)
// or flat shading, optional face or vertex colours, optional polygon edges, and close-ups of a
// window around a point; no display or GPU needed.
#pragma once

#include <Eigen/Core>

#include <array>
#include <cstdint>
#include <string>
#include <vector>

namespace pcl {
namespace patchdict {

using RGBColour = std::array<std::uint8_t, 3>;

struct RenderOptions {
  int width = 800, height = 800;
  /** Direction the camera looks along (towards the object) and the image's up direction. */
  Eigen::Vector3d view_direction = Eigen::Vector3d(0.0, 0.0, -1.0);
  Eigen::Vector3d up = Eigen::Vector3d(0.0, 1.0, 0.0);
  /** Direction towards the key light in camera coordinates (x right, y up, z towards the viewer):
    * upper left by default. Lighting is two-sided. */
  Eigen::Vector3d light = Eigen::Vector3d(-0.45, 0.55, 0.70);
  double ambient = 0.3;    ///< shade = ambient + (1 − ambient)·max(0, n·light) …
  double specular = 0.12;  ///< … plus this much white at the highlight (Blinn, exponent 24)
  /** Normals interpolated per pixel from area-weighted vertex normals; false: one per face. */
  bool smooth_shading = true;
  /** The colours are one per vertex, interpolated across faces (else one per face). */
  bool per_vertex_colours = false;
  bool draw_edges = false;
  /** A close-up: with window_radius > 0 the image's shorter side spans 2 × window_radius (object
    * units) around the projection of window_centre, the same mapping whatever the mesh; else the
    * whole object is fitted with a 5 % margin. */
  Eigen::Vector3d window_centre = Eigen::Vector3d::Zero();
  double window_radius = 0.0;
  RGBColour background{255, 255, 255};
  RGBColour edge_colour{40, 40, 40};
};

/** \brief Renders polygons (fan-triangulated) into RGB pixels (row-major, 3 bytes each).
  * `colours`: one per face (one per vertex with options.per_vertex_colours), or empty for light
  * grey, multiplied by the shade. Throws Error for bad sizes, indices or options. */
std::vector<std::uint8_t> renderPolygons(const std::vector<Eigen::Vector3d>& vertices,
                                         const std::vector<std::vector<std::int32_t>>& faces,
                                         const std::vector<RGBColour>& colours, const RenderOptions& options = {});

/** Renders and writes a PNG, atomically. */
void writePolygonsPNG(const std::string& path, const std::vector<Eigen::Vector3d>& vertices,
                      const std::vector<std::vector<std::int32_t>>& faces, const std::vector<RGBColour>& colours,
                      const RenderOptions& options = {});

/** The error colour map, t clamped to [0, 1]: pale blue-grey (0) → yellow (½) → red (1); light at
  * both low end and middle, so that the shading it is multiplied by stays visible. */
RGBColour errorColour(double t);

}  // namespace patchdict
}  // namespace pcl
