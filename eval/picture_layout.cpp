// Picture layout: a 5×7 bitmap font, panel grids and a colour bar, over RGBImage.
#include <pcl_patchdict_eval/picture_layout.h>

#include <pcl_patchdict/core/error.h>
#include <pcl_patchdict/core/atomic_file.h>
#include <pcl_patchdict/io/png_writer.h>

#include <algorithm>
#include <cctype>
#include <cstring>

namespace pcl {
namespace patchdict {

namespace {

// The glyphs: 7 rows of 5 dots each (bit 4 the leftmost), in the order of kGlyphChars.
const char kGlyphChars[] = "ABCDEFGHIJKLMNOPQRSTUVWXYZ0123456789 .,+-=()/:%><?";
const std::uint8_t kGlyphRows[][7] = {
    {0x0e,0x11,0x11,0x1f,0x11,0x11,0x11}, {0x1e,0x11,0x11,0x1e,0x11,0x11,0x1e}, {0x0e,0x11,0x10,0x10,0x10,0x11,0x0e}, {0x1c,0x12,0x11,0x11,0x11,0x12,0x1c},
    {0x1f,0x10,0x10,0x1e,0x10,0x10,0x1f}, {0x1f,0x10,0x10,0x1e,0x10,0x10,0x10}, {0x0e,0x11,0x10,0x17,0x11,0x11,0x0f}, {0x11,0x11,0x11,0x1f,0x11,0x11,0x11},
    {0x0e,0x04,0x04,0x04,0x04,0x04,0x0e}, {0x07,0x02,0x02,0x02,0x02,0x12,0x0c}, {0x11,0x12,0x14,0x18,0x14,0x12,0x11}, {0x10,0x10,0x10,0x10,0x10,0x10,0x1f},
    {0x11,0x1b,0x15,0x15,0x11,0x11,0x11}, {0x11,0x11,0x19,0x15,0x13,0x11,0x11}, {0x0e,0x11,0x11,0x11,0x11,0x11,0x0e}, {0x1e,0x11,0x11,0x1e,0x10,0x10,0x10},
    {0x0e,0x11,0x11,0x11,0x15,0x12,0x0d}, {0x1e,0x11,0x11,0x1e,0x14,0x12,0x11}, {0x0f,0x10,0x10,0x0e,0x01,0x01,0x1e}, {0x1f,0x04,0x04,0x04,0x04,0x04,0x04},
    {0x11,0x11,0x11,0x11,0x11,0x11,0x0e}, {0x11,0x11,0x11,0x11,0x11,0x0a,0x04}, {0x11,0x11,0x11,0x15,0x15,0x15,0x0a}, {0x11,0x11,0x0a,0x04,0x0a,0x11,0x11},
    {0x11,0x11,0x11,0x0a,0x04,0x04,0x04}, {0x1f,0x01,0x02,0x04,0x08,0x10,0x1f}, {0x0e,0x11,0x13,0x15,0x19,0x11,0x0e}, {0x04,0x0c,0x04,0x04,0x04,0x04,0x0e},
    {0x0e,0x11,0x01,0x02,0x04,0x08,0x1f}, {0x1f,0x02,0x04,0x02,0x01,0x11,0x0e}, {0x02,0x06,0x0a,0x12,0x1f,0x02,0x02}, {0x1f,0x10,0x1e,0x01,0x01,0x11,0x0e},
    {0x06,0x08,0x10,0x1e,0x11,0x11,0x0e}, {0x1f,0x01,0x02,0x04,0x08,0x08,0x08}, {0x0e,0x11,0x11,0x0e,0x11,0x11,0x0e}, {0x0e,0x11,0x11,0x0f,0x01,0x02,0x0c},
    {0x00,0x00,0x00,0x00,0x00,0x00,0x00}, {0x00,0x00,0x00,0x00,0x00,0x0c,0x0c}, {0x00,0x00,0x00,0x00,0x0c,0x04,0x08}, {0x00,0x04,0x04,0x1f,0x04,0x04,0x00},
    {0x00,0x00,0x00,0x1f,0x00,0x00,0x00}, {0x00,0x00,0x1f,0x00,0x1f,0x00,0x00}, {0x02,0x04,0x08,0x08,0x08,0x04,0x02}, {0x08,0x04,0x02,0x02,0x02,0x04,0x08},
    {0x00,0x01,0x02,0x04,0x08,0x10,0x00}, {0x00,0x0c,0x0c,0x00,0x0c,0x0c,0x00}, {0x18,0x19,0x02,0x04,0x08,0x13,0x03}, {0x08,0x04,0x02,0x01,0x02,0x04,0x08},
    {0x02,0x04,0x08,0x10,0x08,0x04,0x02}, {0x0e,0x11,0x01,0x02,0x04,0x00,0x04},
};
static_assert(sizeof kGlyphRows / sizeof kGlyphRows[0] == sizeof kGlyphChars - 1, "one glyph a character");

const int kGlyphWidth = 5, kGlyphHeight = 7, kAdvance = 6;

const std::uint8_t* glyph(char c)
{
  const char upper = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
  const char* at = upper == '\0' ? nullptr : std::strchr(kGlyphChars, upper);
  return kGlyphRows[at ? at - kGlyphChars : std::strlen(kGlyphChars) - 1];
}

void setPixel(RGBImage& image, int x, int y, const RGBColour& colour)
{
  if (x < 0 || y < 0 || x >= image.width || y >= image.height)
    return;
  std::copy(colour.begin(), colour.end(),
            image.pixels.begin() + 3 * (static_cast<std::ptrdiff_t>(y) * image.width + x));
}

}  // namespace

RGBImage blankImage(int width, int height, const RGBColour& colour)
{
  if (width <= 0 || height <= 0 || width > 16384 || height > 16384)
    throw Error("picture: image size must be in [1, 16384]");
  RGBImage image{width, height, std::vector<std::uint8_t>(static_cast<std::size_t>(width) * height * 3)};
  for (std::size_t p = 0; p < image.pixels.size(); p += 3)
    std::copy(colour.begin(), colour.end(), image.pixels.begin() + static_cast<std::ptrdiff_t>(p));
  return image;
}

int textWidth(const std::string& text, int scale)
{
  return text.empty() ? 0 : scale * (kAdvance * static_cast<int>(text.size()) - 1);
}

void drawText(RGBImage& image, int x, int y, const std::string& text, int scale, const RGBColour& colour)
{
  for (std::size_t i = 0; i < text.size(); ++i) {
    const std::uint8_t* rows = glyph(text[i]);
    const int left = x + static_cast<int>(i) * kAdvance * scale;
    for (int row = 0; row < kGlyphHeight; ++row)
      for (int column = 0; column < kGlyphWidth; ++column)
        if (rows[row] & (1u << (kGlyphWidth - 1 - column)))
          for (int dy = 0; dy < scale; ++dy)
            for (int dx = 0; dx < scale; ++dx)
              setPixel(image, left + column * scale + dx, y + row * scale + dy, colour);
  }
}

void paste(RGBImage& target, const RGBImage& source, int x, int y)
{
  for (int row = 0; row < source.height; ++row) {
    const int ty = y + row;
    if (ty < 0 || ty >= target.height)
      continue;
    for (int column = 0; column < source.width; ++column) {
      const std::size_t from = 3 * (static_cast<std::size_t>(row) * source.width + column);
      setPixel(target, x + column, ty, {source.pixels[from], source.pixels[from + 1], source.pixels[from + 2]});
    }
  }
}

RGBImage panelGrid(const std::vector<RGBImage>& panels, const std::vector<std::string>& labels, int columns)
{
  if (panels.empty() || columns < 1)
    throw Error("picture: a grid needs panels and at least one column");
  if (!labels.empty() && labels.size() != panels.size())
    throw Error("picture: one label per panel expected");
  const int w = panels[0].width, h = panels[0].height;
  for (const RGBImage& panel : panels)
    if (panel.width != w || panel.height != h || panel.pixels.size() != static_cast<std::size_t>(w) * h * 3)
      throw Error("picture: the panels of a grid must have one size");
  const int gap = 12, scale = std::max(1, (std::min(w, h) + 100) / 200), label = labels.empty() ? 0 : 7 * scale + 10;
  const int count = static_cast<int>(panels.size());
  const int used_columns = std::min(columns, count), rows = (count + columns - 1) / columns;
  RGBImage grid = blankImage(used_columns * w + (used_columns + 1) * gap, rows * (h + label) + (rows + 1) * gap);
  for (int i = 0; i < count; ++i) {
    const int x = gap + (i % columns) * (w + gap), y = gap + (i / columns) * (h + label + gap);
    if (!labels.empty())
      drawText(grid, x + (w - textWidth(labels[i], scale)) / 2, y + 2, labels[i], scale, {30, 30, 30});
    paste(grid, panels[i], x, y + label);
  }
  return grid;
}

RGBImage withColourBar(const RGBImage& image, const std::string& caption, const std::string& high_label)
{
  const int scale = std::max(1, std::min(2, image.width / 400)), text_height = 7 * scale, bar_height = 3 * scale + 10;
  const int margin = 12, spacing = 4 * scale;
  const int bar_width = std::clamp(image.width / 4, 60, 400);
  const int total = textWidth(caption, scale) + 3 * spacing + textWidth("0", scale) + spacing + bar_width + spacing +
                    textWidth(high_label, scale);
  RGBImage out = blankImage(image.width, image.height + bar_height + 2 * margin);
  paste(out, image, 0, 0);
  int x = std::max(margin, (image.width - total) / 2);
  const int top = image.height + margin, text_top = top + (bar_height - text_height) / 2;
  const RGBColour ink{30, 30, 30};
  drawText(out, x, text_top, caption, scale, ink);
  x += textWidth(caption, scale) + 3 * spacing;
  drawText(out, x, text_top, "0", scale, ink);
  x += textWidth("0", scale) + spacing;
  for (int column = 0; column < bar_width; ++column) {
    const RGBColour colour = errorColour(static_cast<double>(column) / std::max(1, bar_width - 1));
    for (int row = 0; row < bar_height; ++row)
      setPixel(out, x + column, top + row, colour);
  }
  drawText(out, x + bar_width + spacing, text_top, high_label, scale, ink);
  return out;
}

void writeImagePNG(const std::string& path, const RGBImage& image)
{
  writeFileAtomically(path, encodeRGBPNG(image.width, image.height, image.pixels));
}

}  // namespace patchdict
}  // namespace pcl
