// A minimal PNG encoder (8-bit greyscale or RGB, zlib-compressed): enough for contact sheets of
// atoms and patches without a libpng dependency (Debian's PCL is built with DISABLE_PNG).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace pcl {
namespace patchdict {

/** PNG file bytes of a width × height greyscale image (pixels row-major, one byte each).
  * Throws Error on a size mismatch or an empty image. */
std::string encodeGrayPNG(int width, int height, const std::vector<std::uint8_t>& pixels);
/** The same for an RGB image (three bytes per pixel, R, G, B). */
std::string encodeRGBPNG(int width, int height, const std::vector<std::uint8_t>& pixels);

/** Tiles square height maps (each a column of `values`, grid × grid, row-major bins) into a
  * contact sheet: every tile scaled to its own [min, max], `scale` pixels per bin, 1-pixel gaps.
  * Unobserved bins (mask false, when a mask is given) are drawn black with a mid-grey checker. */
std::vector<std::uint8_t> contactSheet(const std::vector<std::vector<double>>& tiles, int grid, int columns,
                                       int scale, int& width, int& height,
                                       const std::vector<std::vector<bool>>* observed = nullptr);

}  // namespace patchdict
}  // namespace pcl
