// PNG (ISO/IEC 15948) written directly, with zlib for the deflate stream (Debian's PCL is built
// with DISABLE_PNG, and libpng would be one more dependency for two chunks of bookkeeping).
#include <pcl_patchdict/core/error.h>
#include <pcl_patchdict/io/png_writer.h>

#include <algorithm>
#include <array>
#include <cmath>

#include <zlib.h>

namespace pcl {
namespace patchdict {

namespace {

void putBigEndian(std::string& out, std::uint32_t value)
{
  for (int shift = 24; shift >= 0; shift -= 8)
    out.push_back(static_cast<char>((value >> shift) & 0xFF));
}

void putChunk(std::string& out, const char type[4], const std::string& data)
{
  putBigEndian(out, static_cast<std::uint32_t>(data.size()));
  std::string body(type, 4);
  body += data;
  out += body;
  // The chunk CRC is zlib's CRC-32 (ISO 3309, the one PNG specifies).
  putBigEndian(out, static_cast<std::uint32_t>(
                        ::crc32_z(0L, reinterpret_cast<const Bytef*>(body.data()), static_cast<z_size_t>(body.size()))));
}

/** PNG of 8-bit samples, `channels` per pixel (1: greyscale, 3: RGB). */
std::string encodePNG(int width, int height, int channels, const std::vector<std::uint8_t>& pixels)
{
  if (width <= 0 || height <= 0 ||
      static_cast<std::size_t>(width) * static_cast<std::size_t>(height) * static_cast<std::size_t>(channels) !=
          pixels.size())
    throw Error("PNG: image size does not match its pixels");
  const std::size_t row = static_cast<std::size_t>(width) * static_cast<std::size_t>(channels);
  // Scanlines, each with filter byte 0 (none).
  std::string raw;
  raw.reserve(static_cast<std::size_t>(height) * (row + 1));
  for (int y = 0; y < height; ++y) {
    raw.push_back('\0');
    raw.append(reinterpret_cast<const char*>(pixels.data()) + static_cast<std::size_t>(y) * row, row);
  }
  // zlib stream of the scanlines (RFC 1950), best compression: pictures are mostly flat colour.
  uLongf packed_size = compressBound(static_cast<uLong>(raw.size()));
  std::string zlib(packed_size, '\0');
  if (compress2(reinterpret_cast<Bytef*>(&zlib[0]), &packed_size, reinterpret_cast<const Bytef*>(raw.data()),
                static_cast<uLong>(raw.size()), 9) != Z_OK)
    throw Error("PNG: compression failed");
  zlib.resize(packed_size);

  std::string png("\x89PNG\r\n\x1a\n", 8);
  std::string header;
  putBigEndian(header, static_cast<std::uint32_t>(width));
  putBigEndian(header, static_cast<std::uint32_t>(height));
  // 8-bit samples, colour type 0 (greyscale) or 2 (RGB), no interlace.
  header += std::string{'\x08', channels == 3 ? '\x02' : '\x00', '\x00', '\x00', '\x00'};
  putChunk(png, "IHDR", header);
  putChunk(png, "IDAT", zlib);
  putChunk(png, "IEND", "");
  return png;
}

}  // namespace

std::string encodeGrayPNG(int width, int height, const std::vector<std::uint8_t>& pixels)
{
  return encodePNG(width, height, 1, pixels);
}

std::string encodeRGBPNG(int width, int height, const std::vector<std::uint8_t>& pixels)
{
  return encodePNG(width, height, 3, pixels);
}

std::vector<std::uint8_t> contactSheet(const std::vector<std::vector<double>>& tiles, int grid, int columns,
                                       int scale, int& width, int& height,
                                       const std::vector<std::vector<bool>>* observed)
{
  if (tiles.empty() || grid <= 0 || columns <= 0 || scale <= 0)
    throw Error("contact sheet: nothing to draw");
  const int count = static_cast<int>(tiles.size());
  columns = std::min(columns, count);
  const int rows = (count + columns - 1) / columns;
  const int tile = grid * scale;
  width = columns * (tile + 1) + 1;
  height = rows * (tile + 1) + 1;
  std::vector<std::uint8_t> pixels(static_cast<std::size_t>(width) * height, 255);
  for (int t = 0; t < count; ++t) {
    const auto& values = tiles[t];
    if (values.size() != static_cast<std::size_t>(grid) * grid)
      throw Error("contact sheet: a tile does not have grid² values");
    double lo = INFINITY, hi = -INFINITY;
    for (std::size_t i = 0; i < values.size(); ++i)
      if (!observed || (*observed)[t][i]) {
        lo = std::min(lo, values[i]);
        hi = std::max(hi, values[i]);
      }
    const double range = hi > lo ? hi - lo : 1.0;
    const int x0 = 1 + (t % columns) * (tile + 1), y0 = 1 + (t / columns) * (tile + 1);
    for (int by = 0; by < grid; ++by)
      for (int bx = 0; bx < grid; ++bx) {
        const std::size_t bin = static_cast<std::size_t>(by) * grid + bx;
        const bool seen = !observed || (*observed)[t][bin];
        const double level = seen && std::isfinite(lo) ? (values[bin] - lo) / range : 0.0;
        for (int py = 0; py < scale; ++py)
          for (int px = 0; px < scale; ++px) {
            std::uint8_t value = static_cast<std::uint8_t>(std::lround(level * 255.0));
            if (!seen)
              value = ((px + py) % 2) ? 128 : 0;
            // Image rows go down; the grid's y goes up: flip so the sheet looks like the surface.
            const int y = y0 + (grid - 1 - by) * scale + py, x = x0 + bx * scale + px;
            pixels[static_cast<std::size_t>(y) * width + x] = value;
          }
      }
  }
  return pixels;
}

}  // namespace patchdict
}  // namespace pcl
