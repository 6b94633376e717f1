// The software renderer and the PNG encoder: known pixel counts, depth order, a PNG that zlib
// inflates back to the exact pixels.
#include <pcl_patchdict/core/error.h>
#include <pcl_patchdict/eval/mesh_render.h>
#include <pcl_patchdict/io/png_writer.h>

#include <gtest/gtest.h>

#include <zlib.h>

using namespace pcl::patchdict;

namespace {

std::uint32_t bigEndian(const std::string& s, std::size_t at)
{
  return (static_cast<std::uint32_t>(static_cast<unsigned char>(s[at])) << 24) |
         (static_cast<std::uint32_t>(static_cast<unsigned char>(s[at + 1])) << 16) |
         (static_cast<std::uint32_t>(static_cast<unsigned char>(s[at + 2])) << 8) |
         static_cast<std::uint32_t>(static_cast<unsigned char>(s[at + 3]));
}

}  // namespace

TEST(MeshRender, ASquareFacingTheCameraFillsItsShareOfTheImage)
{
  const std::vector<Eigen::Vector3d> vertices{{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};
  const std::vector<std::vector<std::int32_t>> faces{{0, 1, 2, 3}};
  RenderOptions options;
  options.width = options.height = 200;
  options.draw_edges = false;
  const auto pixels = renderPolygons(vertices, faces, {{{200, 100, 50}}}, options);
  ASSERT_EQ(pixels.size(), 200u * 200u * 3u);
  std::size_t coloured = 0;
  for (std::size_t p = 0; p < pixels.size(); p += 3) {
    if (pixels[p] != 255) {
      ++coloured;
      // Facing the camera: full Lambert shade, the colour itself.
      EXPECT_EQ(pixels[p], 200);
      EXPECT_EQ(pixels[p + 1], 100);
      EXPECT_EQ(pixels[p + 2], 50);
    }
  }
  // The square is scaled to 90 % of the image: 180 × 180 pixels.
  EXPECT_NEAR(static_cast<double>(coloured), 180.0 * 180.0, 2.0 * 180.0);
}

TEST(MeshRender, TheNearerFaceHidesTheFartherOne)
{
  // Two overlapping squares; the camera looks along −z, so z = 1 is in front.
  const std::vector<Eigen::Vector3d> vertices{{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0},
                                              {0, 0, 1}, {1, 0, 1}, {1, 1, 1}, {0, 1, 1}};
  RenderOptions options;
  options.width = options.height = 64;
  options.draw_edges = false;
  for (const bool front_first : {true, false}) {
    const std::vector<std::vector<std::int32_t>> faces =
        front_first ? std::vector<std::vector<std::int32_t>>{{4, 5, 6, 7}, {0, 1, 2, 3}}
                    : std::vector<std::vector<std::int32_t>>{{0, 1, 2, 3}, {4, 5, 6, 7}};
    const std::vector<std::array<std::uint8_t, 3>> colours =
        front_first ? std::vector<std::array<std::uint8_t, 3>>{{0, 255, 0}, {255, 0, 0}}
                    : std::vector<std::array<std::uint8_t, 3>>{{255, 0, 0}, {0, 255, 0}};
    const auto pixels = renderPolygons(vertices, faces, colours, options);
    const std::size_t centre = 3 * (32 * 64 + 32);
    EXPECT_EQ(pixels[centre], 0);  // green (the front square) whatever the drawing order
    EXPECT_EQ(pixels[centre + 1], 255);
  }
  EXPECT_THROW(renderPolygons(vertices, {{0, 1, 9}}, {}, options), Error);
  EXPECT_THROW(renderPolygons(vertices, {{0, 1, 2}}, {{{1, 2, 3}}, {{1, 2, 3}}}, options), Error);
}

TEST(PngWriter, RGBImageInflatesBackToItsPixels)
{
  const int w = 37, h = 11;
  std::vector<std::uint8_t> pixels(static_cast<std::size_t>(w) * h * 3);
  for (std::size_t i = 0; i < pixels.size(); ++i)
    pixels[i] = static_cast<std::uint8_t>((i * 7919) % 251);
  const std::string png = encodeRGBPNG(w, h, pixels);
  ASSERT_EQ(png.substr(0, 8), std::string("\x89PNG\r\n\x1a\n", 8));
  // IHDR: width, height, depth 8, colour type 2.
  EXPECT_EQ(png.substr(12, 4), "IHDR");
  EXPECT_EQ(bigEndian(png, 16), static_cast<std::uint32_t>(w));
  EXPECT_EQ(bigEndian(png, 20), static_cast<std::uint32_t>(h));
  EXPECT_EQ(png[24], 8);
  EXPECT_EQ(png[25], 2);
  // IDAT follows IHDR (8 + 25 bytes in); inflate it and compare the scanlines.
  const std::size_t idat = 8 + 25;
  ASSERT_EQ(png.substr(idat + 4, 4), "IDAT");
  const std::uint32_t length = bigEndian(png, idat);
  std::vector<unsigned char> raw(static_cast<std::size_t>(h) * (3 * w + 1));
  uLongf raw_size = static_cast<uLongf>(raw.size());
  ASSERT_EQ(uncompress(raw.data(), &raw_size, reinterpret_cast<const Bytef*>(png.data() + idat + 8), length), Z_OK);
  ASSERT_EQ(raw_size, raw.size());
  for (int y = 0; y < h; ++y) {
    EXPECT_EQ(raw[static_cast<std::size_t>(y) * (3 * w + 1)], 0);  // filter: none
    for (int x = 0; x < 3 * w; ++x)
      EXPECT_EQ(raw[static_cast<std::size_t>(y) * (3 * w + 1) + 1 + x], pixels[static_cast<std::size_t>(y) * 3 * w + x]);
  }
  EXPECT_THROW(encodeRGBPNG(w, h, std::vector<std::uint8_t>(5)), Error);
}
