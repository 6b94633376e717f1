// A small software renderer for pictures of results (README, --report): orthographic view,
// z-buffer, Lambert shading, optional face colours and polygon edges; no display or GPU needed.
#pragma once

#include <Eigen/Core>

#include <array>
#include <cstdint>
#include <string>
#include <vector>

namespace pcl {
namespace patchdict {

struct RenderOptions {
  int width = 800, height = 800;
  /** Direction the camera looks along (towards the object) and the image's up direction. */
  Eigen::Vector3d view_direction = Eigen::Vector3d(0.0, 0.0, -1.0);
  Eigen::Vector3d up = Eigen::Vector3d(0.0, 1.0, 0.0);
  bool draw_edges = true;
  std::array<std::uint8_t, 3> background{255, 255, 255};
  std::array<std::uint8_t, 3> edge_colour{40, 40, 40};
};

/** \brief Renders polygons (fan-triangulated) into RGB pixels (row-major, 3 bytes each), the
  * object scaled to fit with a 5 % margin. `face_colours` (one per face, or empty for light grey)
  * are shaded by |n·view| (two-sided) with 25 % ambient. Throws Error for bad sizes or indices. */
std::vector<std::uint8_t> renderPolygons(const std::vector<Eigen::Vector3d>& vertices,
                                         const std::vector<std::vector<std::int32_t>>& faces,
                                         const std::vector<std::array<std::uint8_t, 3>>& face_colours,
                                         const RenderOptions& options = {});

/** Renders and writes a PNG, atomically. */
void writePolygonsPNG(const std::string& path, const std::vector<Eigen::Vector3d>& vertices,
                      const std::vector<std::vector<std::int32_t>>& faces,
                      const std::vector<std::array<std::uint8_t, 3>>& face_colours, const RenderOptions& options = {});

}  // namespace patchdict
}  // namespace pcl
