// Composing rendered pictures: panels side by side with labels, a colour-bar strip, text from a
// built-in 5×7 bitmap font (capitals, digits and a little punctuation; lower case is drawn in
// capitals), PNG output.
#pragma once

#include <pcl_patchdict_eval/mesh_render.h>

#include <string>
#include <vector>

namespace pcl {
namespace patchdict {

/** An RGB picture: row-major pixels, 3 bytes each. */
struct RGBImage {
  int width = 0, height = 0;
  std::vector<std::uint8_t> pixels;
};

/** A width × height picture of one colour. Throws Error for a size outside [1, 16384]. */
RGBImage blankImage(int width, int height, const RGBColour& colour = {255, 255, 255});

/** Width in pixels of `text` drawn at `scale` pixels per font dot. */
int textWidth(const std::string& text, int scale);

/** Draws `text` with its top-left corner at (x, y), clipped to the image; characters outside the
  * font are drawn as '?'. */
void drawText(RGBImage& image, int x, int y, const std::string& text, int scale, const RGBColour& colour);

/** Copies `source` into `target` with its top-left corner at (x, y), clipped. */
void paste(RGBImage& target, const RGBImage& source, int x, int y);

/** Panels (all of the first panel's size) in rows of `columns`, each with its label centred above
  * it, on white with gaps. Throws Error for no panels, panels of different sizes, or labels not
  * one per panel (or none). */
RGBImage panelGrid(const std::vector<RGBImage>& panels, const std::vector<std::string>& labels, int columns);

/** `image` with a strip below it: `caption`, then the error colour map (errorColour) from 0 to
  * `high_label` drawn as a bar. */
RGBImage withColourBar(const RGBImage& image, const std::string& caption, const std::string& high_label);

/** Writes the picture as a PNG, atomically. */
void writeImagePNG(const std::string& path, const RGBImage& image);

}  // namespace patchdict
}  // namespace pcl
